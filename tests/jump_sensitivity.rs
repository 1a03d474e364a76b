//! Sensitivities through resetting events: Φ carried across each jump by its saltation matrix
//! S = ∂R/∂y + (f⁺ − ∂R/∂y f⁻ − ∂R/∂t)(∂h/∂y)/ḣ, against a closed form derived here (a ball
//! bouncing on a floor) and against central differences of runs (a pendulum striking a wall
//! twice, an oblique bounce that couples the coordinates); a hybrid periodic orbit found by
//! shooting through its jumps (the rimless wheel's gait and its step-to-step multiplier
//! cos² 2α); the refusals of what is not covered.

use crate::support::gauss_legendre;
use lagrange::prelude::*;
use lagrange::sensitivity::Shooting;

const G: f64 = 9.81;

/// A ball of mass m in a vertical plane (x, y) under gravity.
pub struct Ball2 {
    pub m: f64,
}

#[lagrangian]
impl Ball2 {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * G * y
    }
}

/// A pendulum of length l in its angle from the downward vertical.
pub struct Swing {
    pub l: f64,
}

#[lagrangian]
impl Swing {
    fn lagrangian(&self, (th, th_dot): Coord) -> Scalar {
        0.5 * self.l * self.l * th_dot * th_dot + G * self.l * th.cos()
    }
}

fn tight() -> Method {
    Method::Dop853 {
        rtol: 1e-13,
        atol: 1e-13,
    }
}

/// The floor y = 0 with restitution e: ẏ⁺ = −e ẏ⁻.
fn floor(e: f64) -> Event<'static, 2> {
    Event::zero_crossing("floor", |_t, q: &[f64; 2], _v| q[1])
        .falling()
        .reset(move |_t, q, v| (*q, [v[0], -e * v[1]]))
}

/// The ball dropped from height y₀ with vertical speed v₀ strikes the floor at
/// t₁ = (v₀ + s)/g, s = √(v₀² + 2 g y₀), arriving at speed s, and leaves at e s; at T > t₁
/// (before the next bounce), with τ = T − t₁,
///
///   y(T) = e s τ − g τ²/2,   ẏ(T) = e s − g τ.
///
/// With ∂t₁/∂y₀ = 1/s, ∂t₁/∂v₀ = (1 + v₀/s)/g, ∂s/∂y₀ = g/s, ∂s/∂v₀ = v₀/s and ∂τ = −∂t₁:
///
///   ∂y(T) = e τ ∂s − ẏ(T) ∂t₁,   ∂ẏ(T) = e ∂s + g ∂t₁;
///
/// x moves on at its own speed: ∂x(T)/∂x₀ = 1, ∂x(T)/∂ẋ₀ = T, ∂ẋ(T)/∂ẋ₀ = 1, and nothing else
/// couples. Φ(T) from the run against these to 1e-10, with DOP853, the Taylor method and
/// Radau5 (whose Φ is the derivative of its discrete flow: exact here, the flight being a
/// polynomial its collocation reproduces).
#[test]
fn phi_through_a_bounce_is_the_closed_form() {
    let radau = Method::Radau5 {
        rtol: 1e-12,
        atol: 1e-12,
    };
    for method in [tight(), Method::Taylor { tol: 1e-15 }, radau] {
        bounce_against_closed_form(method);
    }
}

fn bounce_against_closed_form(method: Method) {
    let (e, y0, v0, vx) = (0.7, 1.3, 0.4, 0.6);
    let t_end = 1.2;
    let run = Simulation::new(&Ball2 { m: 0.8 }, [0.0, y0], [vx, v0])
        .method(method)
        .until(t_end)
        .event(floor(e))
        .sensitivity()
        .run()
        .unwrap();
    let s = (v0 * v0 + 2.0 * G * y0).sqrt();
    let t1 = (v0 + s) / G;
    assert_eq!(run.trajectory.jumps.len(), 1);
    assert!((run.trajectory.jumps[0].t - t1).abs() < 1e-12);
    let tau = t_end - t1;
    let ydot = e * s - G * tau;
    let (dt1, ds) = ([1.0 / s, (1.0 + v0 / s) / G], [G / s, v0 / s]);
    // Columns: ∂/∂y₀ (index 1) and ∂/∂ẏ₀ (index 3); rows: y (1) and ẏ (3).
    let phi = run.phi.last().unwrap();
    for (col, k) in [(1, 0), (3, 1)] {
        let dy = e * tau * ds[k] - ydot * dt1[k];
        let dydot = e * ds[k] + G * dt1[k];
        assert!(
            (phi[(1, col)] - dy).abs() < 1e-10 && (phi[(3, col)] - dydot).abs() < 1e-10,
            "column {col}: ({}, {}) vs ({dy}, {dydot})",
            phi[(1, col)],
            phi[(3, col)]
        );
        // The vertical motion does not reach x.
        assert!(phi[(0, col)].abs() < 1e-12 && phi[(2, col)].abs() < 1e-12);
    }
    let want_x = [[1.0, 0.0, t_end, 0.0], [0.0, 0.0, 1.0, 0.0]];
    for (row, want) in [(0, want_x[0]), (2, want_x[1])] {
        for c in 0..4 {
            assert!((phi[(row, c)] - want[c]).abs() < 1e-10, "Φ[{row}, {c}]");
        }
    }
    // Before the bounce Φ is the free flight's: ∂y(t)/∂ẏ₀ = t.
    let k = run.trajectory.t.iter().position(|&t| t > 0.1).unwrap();
    let t = run.trajectory.t[k];
    assert!((run.phi[k][(1, 3)] - t).abs() < 1e-12);
}

/// The pendulum strikes a wall at θ_w twice (θ̇ → −e θ̇ at θ = θ_w): Φ(T) against central
/// differences of runs started at θ₀ ± h and θ̇₀ ± h (h = 1e-5: the differences' error
/// h² Φ‴ ≈ 1e-10, the runs' 1e-13 / h = 1e-8; tolerance 1e-7), and the event times'
/// sensitivities dt*/dy₀ against differences of the hit times.
#[test]
fn phi_through_two_impacts_matches_differences_of_runs() {
    let sys = Swing { l: 0.9 };
    let (e, thw) = (0.8, -0.3);
    let wall = move || {
        Event::zero_crossing("wall", move |_t, q: &[f64; 1], _v| q[0] - thw)
            .falling()
            .reset(move |_t, q, v| (*q, [-e * v[0]]))
    };
    let until = 2.5;
    let run_from = |th: f64, w: f64| {
        Simulation::new(&sys, [th], [w])
            .method(tight())
            .until(until)
            .event(wall())
            .run()
            .unwrap()
    };
    let (th0, w0) = (0.6, 0.2);
    let run = Simulation::new(&sys, [th0], [w0])
        .method(tight())
        .until(until)
        .event(wall())
        .sensitivity()
        .run()
        .unwrap();
    assert!(
        run.trajectory.jumps.len() >= 2,
        "{}",
        run.trajectory.jumps.len()
    );
    let phi = run.phi.last().unwrap();
    let h = 1e-5;
    let end = |tr: &Trajectory<1>| [*tr.q.last().unwrap(), *tr.qdot.last().unwrap()];
    for (col, plus, minus) in [
        (0, run_from(th0 + h, w0), run_from(th0 - h, w0)),
        (1, run_from(th0, w0 + h), run_from(th0, w0 - h)),
    ] {
        assert_eq!(plus.jumps.len(), run.trajectory.jumps.len());
        let (p, m) = (end(&plus), end(&minus));
        for row in 0..2 {
            let diff = (p[row][0] - m[row][0]) / (2.0 * h);
            assert!(
                (phi[(row, col)] - diff).abs() < 1e-7 * diff.abs().max(1.0),
                "Φ[{row}, {col}] = {} vs {diff}",
                phi[(row, col)]
            );
        }
        // Each impact's time: dt*/dy₀ against the differences of the hit times.
        for (k, ev) in run.events.iter().enumerate() {
            let dt = ev.dt_dx0.as_ref().unwrap();
            let diff = (plus.jumps[k].t - minus.jumps[k].t) / (2.0 * h);
            assert!(
                (dt[col] - diff).abs() < 1e-7 * diff.abs().max(1.0),
                "impact {k}: dt*/dy₀[{col}] = {} vs {diff}",
                dt[col]
            );
        }
    }
}

/// A bounce off an inclined floor y = x tan α (restitution e along its normal, no friction)
/// couples x and y (twice before T): Φ(T) against central differences of runs in all four
/// directions.
#[test]
fn phi_through_an_oblique_bounce_matches_differences_of_runs() {
    let (e, alpha) = (0.6_f64, 0.25_f64);
    let (c, s) = (alpha.cos(), alpha.sin());
    let slope = move || {
        Event::zero_crossing("slope", move |_t, q: &[f64; 2], _v| q[1] * c - q[0] * s)
            .falling()
            .reset(move |_t, q, v| {
                // The normal n = (−sin α, cos α): v⁺ = v − (1 + e)(v·n) n.
                let vn = -v[0] * s + v[1] * c;
                (*q, [v[0] + (1.0 + e) * vn * s, v[1] - (1.0 + e) * vn * c])
            })
    };
    let sys = Ball2 { m: 1.0 };
    let (q0, v0) = ([0.2, 1.0], [0.5, 0.3]);
    let until = 1.0;
    let run = Simulation::new(&sys, q0, v0)
        .method(tight())
        .until(until)
        .event(slope())
        .sensitivity()
        .run()
        .unwrap();
    let bounces = run.trajectory.jumps.len();
    assert!(bounces >= 1);
    let phi = run.phi.last().unwrap();
    let h = 1e-5;
    let end_from = |q: [f64; 2], v: [f64; 2]| {
        let tr = Simulation::new(&sys, q, v)
            .method(tight())
            .until(until)
            .event(slope())
            .run()
            .unwrap();
        assert_eq!(tr.jumps.len(), bounces);
        let (q, v) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
        [q[0], q[1], v[0], v[1]]
    };
    for col in 0..4 {
        let shifted = |d: f64| {
            let mut y = [q0[0], q0[1], v0[0], v0[1]];
            y[col] += d;
            end_from([y[0], y[1]], [y[2], y[3]])
        };
        let (p, m) = (shifted(h), shifted(-h));
        for row in 0..4 {
            let diff = (p[row] - m[row]) / (2.0 * h);
            assert!(
                (phi[(row, col)] - diff).abs() < 1e-7 * diff.abs().max(1.0),
                "Φ[{row}, {col}] = {} vs {diff}",
                phi[(row, col)]
            );
        }
    }
}

/// What is not covered is refused, naming it: a reset with parameters.
#[test]
fn what_a_jump_sensitivity_cannot_take_is_refused() {
    let err = Simulation::new(&Ball2 { m: 1.0 }, [0.0, 1.0], [0.0, 0.0])
        .until(1.0)
        .event(floor(0.5))
        .sensitivity()
        .parameter("m", 1.0, |m| Ball2 { m })
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("parameters"), "{err}");
}

/// A rimless wheel (a hub of mass m on spokes of length l, 2α apart) rolling down a slope γ,
/// in the angle θ of its stance spoke from the slope's normal: L = ½ m l² θ̇² − m g l cos(θ + γ)
/// from θ = −α to α, where the next spoke lands (θ⁺ = −α, θ̇⁺ = cos 2α θ̇⁻: the angular
/// momentum about the new contact kept).
pub struct Wheel {
    pub l: f64,
    pub slope: f64,
}

#[lagrangian]
impl Wheel {
    fn lagrangian(&self, (th, th_dot): Coord) -> Scalar {
        0.5 * self.l * self.l * th_dot * th_dot - G * self.l * (th + self.slope).cos()
    }
}

/// Its gait found by shooting through the spoke's landing: over a step the energy gains
/// 2 g l sin α sin γ (per unit mass), and the landing keeps cos 2α of θ̇, so the post-impact
/// rate ω satisfies ω² = cos² 2α (ω² + k), k = 4 (g/l) sin α sin γ: ω* = cot 2α √k, and the
/// step-to-step map ω ↦ cos 2α √(ω² + k) has the slope cos 2α ω/√(ω² + k) = cos² 2α at ω*
/// (where √(ω*² + k) = ω*/cos 2α). The orbit found: on the energy of
/// the gait through ω*, its period the step time T = ∫ dθ/θ̇ from −α to α, and its monodromy's
/// multipliers {1, cos² 2α} (8 spokes: 1/2), against these closed forms.
#[test]
fn rimless_wheel_gait_and_its_multiplier_by_shooting_through_its_impacts() {
    let (l, slope) = (1.0, 0.2);
    let alpha = std::f64::consts::PI / 8.0;
    let sys = Wheel { l, slope };
    let k = 4.0 * (G / l) * alpha.sin() * slope.sin();
    let omega = k.sqrt() / (2.0 * alpha).tan();
    // θ̇ on the gait at θ: ½ θ̇² = ½ ω*² + (g/l)(cos(−α + γ) − cos(θ + γ)).
    let rate = |th: f64| {
        (omega * omega + 2.0 * (G / l) * ((slope - alpha).cos() - (th + slope).cos())).sqrt()
    };
    // T by composite Gauss–Legendre of 1/θ̇, smooth on [−α, α].
    let period = gauss_legendre(-alpha, alpha, |th| 1.0 / rate(th));
    let orbit = Shooting::autonomous(&sys, [0.0], [1.05 * rate(0.0)], 1.05 * period)
        .event(move || {
            Event::zero_crossing("next spoke", move |_t, q: &[f64; 1], _v| q[0] - alpha)
                .rising()
                .reset(move |_t, q, v| ([q[0] - 2.0 * alpha], [(2.0 * alpha).cos() * v[0]]))
        })
        .find()
        .unwrap();
    let (th0, w0) = (orbit.q0[0], orbit.qdot0[0]);
    eprintln!(
        "rimless wheel: T = {} (closed form {period}), start ({th0}, {w0}), multipliers {:?}",
        orbit.period, orbit.multipliers
    );
    assert!(
        (orbit.period - period).abs() < 1e-9 * period,
        "T = {}",
        orbit.period
    );
    assert!(
        (w0 - rate(th0)).abs() < 1e-9,
        "θ̇ = {w0} at θ = {th0}, gait {}",
        rate(th0)
    );
    let mut mods: Vec<f64> = orbit.multipliers.iter().map(|m| m.norm()).collect();
    mods.sort_by(f64::total_cmp);
    let mu = (2.0 * alpha).cos().powi(2);
    assert!((mods[0] - mu).abs() < 1e-8, "{mods:?} vs {mu}");
    assert!((mods[1] - 1.0).abs() < 1e-8, "{mods:?}");
    assert!(orbit.stability.is_stable(), "{:?}", orbit.stability);
}
