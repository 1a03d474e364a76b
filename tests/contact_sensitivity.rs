//! Sensitivities through contacts (`fn contacts`, run by `Simulation::new` or
//! `Simulation::contacts`): Φ carried across every impact by the jump's saltation matrix, each
//! jump's pieces (the event's function, f⁻ and the impact map's differences) taken in the
//! contacts' mode before it and f⁺ in the mode after it; through a resting phase (the closed
//! contact a constraint: the view's Jacobian) and a lift-off. Against a closed form derived here
//! (a ball bouncing, elastic and plastic) and against central differences of runs started on the
//! constraints (a pendulum on a rod striking a wall; a particle sliding off a sphere).

use crate::contact_constraints::RodWall;
use crate::contacts::OnSphere;
use lagrange::prelude::*;
use lagrange_examples::contact_systems::Ball;

const G: f64 = 9.81;

fn tight() -> Method {
    Method::Dop853 {
        rtol: 1e-13,
        atol: 1e-13,
    }
}

/// The ball dropped from y₀ with vertical speed v₀ strikes the floor at t₁ = (v₀ + s)/g,
/// s = √(v₀² + 2 g y₀), and leaves at e s (`tests/jump_sensitivity.rs` derives Φ(T) for T
/// before the next bounce, τ = T − t₁: ∂y(T) = e τ ∂s − ẏ(T) ∂t₁, ∂ẏ(T) = e ∂s + g ∂t₁, with
/// ∂t₁/∂y₀ = 1/s, ∂t₁/∂v₀ = (1 + v₀/s)/g, ∂s/∂y₀ = g/s, ∂s/∂v₀ = v₀/s; x moves on alone). The
/// same ball with its floor a contact (the impact map derived from M and the gap, not a reset
/// written by hand): Φ(T) against that closed form to 1e-10, with DOP853, Dormand–Prince and
/// Radau5 (its Φ the derivative of its discrete flow: exact on the flights, polynomials its
/// collocation reproduces).
/// With e = 0 the contact closes at the landing and the ball rests: every start near this one
/// ends at rest on the floor, so ∂(y, ẏ)(T)/∂y₀ = 0 (the closed contact's saltation and the
/// resting phase's Jacobian), while x moves on (∂x(T)/∂ẋ₀ = T).
#[test]
fn phi_through_a_contact_bounce_is_the_closed_form() {
    let (y0, v0, vx, t_end) = (1.3, 0.4, 0.6, 1.2);
    let s = (v0 * v0 + 2.0 * G * y0).sqrt();
    let t1 = (v0 + s) / G;
    let (dt1, ds) = ([1.0 / s, (1.0 + v0 / s) / G], [G / s, v0 / s]);
    let tau = t_end - t1;
    for method in [
        tight(),
        Method::DormandPrince {
            rtol: 1e-12,
            atol: 1e-12,
        },
        Method::Radau5 {
            rtol: 1e-12,
            atol: 1e-12,
        },
    ] {
        for e in [0.7, 0.0] {
            let ball = Ball { m: 0.8, g: G, e };
            let run = Simulation::new(&ball, [0.0, y0], [vx, v0])
                .method(method)
                .until(t_end)
                .sensitivity()
                .run()
                .unwrap();
            assert_eq!(run.trajectory.jumps.len(), 1, "{method:?}, e = {e}");
            assert!((run.trajectory.jumps[0].t - t1).abs() < 1e-11);
            let phi = run.phi.last().unwrap();
            let ydot = e * s - G * tau;
            let mut worst = 0.0_f64;
            for (col, k) in [(1, 0), (3, 1)] {
                let dy = e * tau * ds[k] - ydot * dt1[k];
                let dydot = e * ds[k] + G * dt1[k];
                let (dy, dydot) = if e == 0.0 { (0.0, 0.0) } else { (dy, dydot) };
                worst = worst
                    .max((phi[(1, col)] - dy).abs())
                    .max((phi[(3, col)] - dydot).abs());
                assert!(phi[(0, col)].abs() < 1e-12 && phi[(2, col)].abs() < 1e-12);
            }
            let want_x = [[1.0, 0.0, t_end, 0.0], [0.0, 0.0, 1.0, 0.0]];
            for (row, want) in [(0, want_x[0]), (2, want_x[1])] {
                for c in 0..4 {
                    worst = worst.max((phi[(row, c)] - want[c]).abs());
                }
            }
            eprintln!("{method:?}, e = {e}: Φ(T) off the closed form by {worst:.1e}");
            assert!(worst < 1e-10, "{method:?}, e = {e}: {worst:e}\n{phi}");
        }
    }
}

/// The state on the rod at angle θ from the downward vertical with rate ω: x = l sin θ,
/// y = −l cos θ, ẋ = l ω cos θ, ẏ = l ω sin θ.
fn on_rod(l: f64, th: f64, w: f64) -> ([f64; 2], [f64; 2]) {
    (
        [l * th.sin(), -l * th.cos()],
        [l * w * th.cos(), l * w * th.sin()],
    )
}

/// The rod pendulum released at θ₀ = 0.9 swings through the bottom and strikes the wall at
/// x = −0.5 twice before T = 3 (the rod a constraint through each impact). Φ(T) applied to the
/// two directions along the constraints, ∂y₀/∂θ₀ and ∂y₀/∂ω₀, against central differences of
/// runs started on the rod at θ₀ ± h, ω₀ ± h (h = 1e-5: the differences' error h² y‴ ≈ 1e-10,
/// the runs' 1e-13 / h = 1e-8; tolerance 1e-6 of max(1, |Φ v|)).
#[test]
fn phi_of_a_rod_pendulum_through_its_wall_impacts_matches_differences() {
    let sys = RodWall {
        m: 0.8,
        l: 1.2,
        d: 0.5,
        e: 0.6,
    };
    let (th0, w0, t_end) = (0.9, 0.0, 3.0);
    let end = |th: f64, w: f64| -> (Vec<f64>, usize) {
        let (q, v) = on_rod(sys.l, th, w);
        let tr = Simulation::new(&sys, q, v)
            .method(tight())
            .until(t_end)
            .run()
            .unwrap();
        let (q, v) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
        (q.iter().chain(v).copied().collect(), tr.jumps.len())
    };
    let (q, v) = on_rod(sys.l, th0, w0);
    let run = Simulation::new(&sys, q, v)
        .method(tight())
        .until(t_end)
        .sensitivity()
        .run()
        .unwrap();
    assert_eq!(run.trajectory.jumps.len(), 2);
    let phi = run.phi.last().unwrap();
    let h = 1e-5;
    // The start's derivatives along θ₀ and ω₀ (on the rod).
    let dirs = [
        [
            sys.l * th0.cos(),
            sys.l * th0.sin(),
            -sys.l * w0 * th0.sin(),
            sys.l * w0 * th0.cos(),
        ],
        [0.0, 0.0, sys.l * th0.cos(), sys.l * th0.sin()],
    ];
    for (k, dir) in dirs.iter().enumerate() {
        let (up, n_up) = if k == 0 {
            end(th0 + h, w0)
        } else {
            end(th0, w0 + h)
        };
        let (down, n_down) = if k == 0 {
            end(th0 - h, w0)
        } else {
            end(th0, w0 - h)
        };
        assert_eq!((n_up, n_down), (2, 2));
        let mut worst = 0.0_f64;
        let mut size = 1.0_f64;
        for i in 0..4 {
            let phi_v: f64 = (0..4).map(|j| phi[(i, j)] * dir[j]).sum();
            let diff = (up[i] - down[i]) / (2.0 * h);
            worst = worst.max((phi_v - diff).abs());
            size = size.max(diff.abs());
        }
        eprintln!(
            "rod pendulum, direction {k}: Φ v off the differences by {worst:.1e} (of {size:.1})"
        );
        assert!(worst < 1e-6 * size, "direction {k}: {worst:e}");
    }
}

/// The particle starts on top of the sphere with speed v₀ along it: the contact is closed (a
/// constraint, the view's Jacobian by differences) until it leaves where the normal force
/// vanishes (cos θ = (2 + v₀²/(g r))/3), then flies free. Φ(T) on the direction ∂y₀/∂v₀ (along
/// the sphere) against central differences of runs from v₀ ± h (h = 1e-5, tolerance 1e-6 of
/// max(1, |Φ v|)): the closed phase's variations and the lift-off's (continuous: λ = 0 there,
/// the two flows agree).
#[test]
fn phi_through_a_resting_phase_and_its_lift_off_matches_differences() {
    let sys = OnSphere {
        m: 0.5,
        g: G,
        r: 1.0,
    };
    let (v0, t_end) = (0.8, 1.2);
    let end = |v: f64| -> (Vec<f64>, usize) {
        let tr = Simulation::new(&sys, [0.0, sys.r], [v, 0.0])
            .method(tight())
            .until(t_end)
            .run()
            .unwrap();
        let (q, qd) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
        (q.iter().chain(qd).copied().collect(), tr.jumps.len())
    };
    let run = Simulation::new(&sys, [0.0, sys.r], [v0, 0.0])
        .method(tight())
        .until(t_end)
        .sensitivity()
        .run()
        .unwrap();
    assert_eq!(run.trajectory.jumps.len(), 1, "one lift-off");
    let phi = run.phi.last().unwrap();
    let h = 1e-5;
    let ((up, _), (down, _)) = (end(v0 + h), end(v0 - h));
    let mut worst = 0.0_f64;
    let mut size = 1.0_f64;
    for i in 0..4 {
        let diff = (up[i] - down[i]) / (2.0 * h);
        worst = worst.max((phi[(i, 2)] - diff).abs());
        size = size.max(diff.abs());
    }
    eprintln!("sphere: Φ e_ẋ off the differences by {worst:.1e} (of {size:.1})");
    assert!(worst < 1e-6 * size, "{worst:e}\n{phi}");
}

/// What contacts do not take yet is refused, naming it: parameters, and Φ through a Zeno
/// accumulation (a ball bouncing ever lower comes to rest after infinitely many impacts).
#[test]
fn contact_sensitivities_refuse_what_they_do_not_cover() {
    let ball = Ball {
        m: 0.8,
        g: G,
        e: 0.5,
    };
    let err = Simulation::new(&ball, [0.0, 1.0], [0.0, 0.0])
        .until(1.0)
        .sensitivity()
        .parameter("e", 0.5, |e| Ball { e, ..ball })
        .run()
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("parameter sensitivities of a run with contacts"),
        "{err}"
    );
    let err = Simulation::new(&ball, [0.0, 1.0], [0.0, 0.0])
        .until(3.0)
        .sensitivity()
        .run()
        .unwrap_err()
        .to_string();
    assert!(err.contains("Zeno"), "{err}");
}

/// The rimless wheel of `examples/impacts.rs` written with contacts (the hub (x, y) in the
/// slope's frame and the wheel's angle θ; each spoke's tip sticks where it lands, plastic):
/// its gait is periodic up to a shift, one step on (x + 2l sin α, y, θ − 2α). Shot from
/// mid-stance (θ = 0, the hub over its tip) with `.shift` (each shot starts with the stance
/// spoke closed, Newton's iterate put on it): the monodromy carries the landing's saltation
/// matrix (the next spoke closing, the last one lifting off), so the multipliers are the
/// step-to-step map's: the trivial 1, cos² 2α = 1/2, and 0 four times (the directions off the
/// closed contact, which each start projects away). The period against the closed form
/// T = ∫ dφ/|φ̇| over the stance (the hub's potential m g l cos(φ − γ), φ the stance spoke's
/// angle; ω* from the step's energy balance), to 1e-9; the multiplier to 1e-7.
#[test]
fn rimless_wheel_gait_and_multiplier_through_its_contacts() {
    use crate::support::gauss_legendre;
    use lagrange::sensitivity::Shooting;
    use lagrange_examples::contact_systems::{omega_star, RimlessWheel, SPOKES};
    let w = RimlessWheel {
        m: 1.0,
        g: 1.0,
        l: 1.0,
        slope: 0.08,
    };
    let alpha = std::f64::consts::PI / SPOKES as f64;
    let omega = omega_star(&w);
    // |φ̇| at φ on the gait: ½ φ̇² + (g/l) cos(φ − γ) = ½ ω*² + (g/l) cos(α − γ).
    let rate = |phi: f64| {
        (omega * omega + 2.0 * (w.g / w.l) * ((alpha - w.slope).cos() - (phi - w.slope).cos()))
            .sqrt()
    };
    let period = gauss_legendre(-alpha, alpha, |phi| 1.0 / rate(phi));
    let r0 = 1.03 * rate(0.0);
    let orbit = Shooting::autonomous(&w, [0.0, w.l, 0.0], [w.l * r0, 0.0, -r0], 1.03 * period)
        .method(tight())
        .shift([2.0 * w.l * alpha.sin(), 0.0, -2.0 * alpha])
        .find()
        .unwrap();
    let mut mods: Vec<f64> = orbit.multipliers.iter().map(|m| m.norm()).collect();
    mods.sort_by(f64::total_cmp);
    eprintln!(
        "contact wheel: T = {} (closed form {period}), start {:?} {:?}, {} iterations, \
         multipliers {mods:?}",
        orbit.period, orbit.q0, orbit.qdot0, orbit.iterations
    );
    assert!(
        (orbit.period - period).abs() < 1e-9 * period,
        "{}",
        orbit.period
    );
    let mu = (2.0 * alpha).cos().powi(2);
    assert!(mods[..4].iter().all(|m| *m < 1e-7), "{mods:?}");
    assert!((mods[4] - mu).abs() < 1e-7, "{mods:?} vs {mu}");
    assert!((mods[5] - 1.0).abs() < 1e-7, "{mods:?}");
    assert!(orbit.stability.is_stable(), "{:?}", orbit.stability);
}
