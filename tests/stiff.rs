//! Stiff mechanics: `Method::Radau5` against closed forms and against the explicit
//! methods on stiff systems (two masses joined by a stiff spring, the stiff spring pendulum, a
//! heavily damped driven oscillator), its accuracy on a non-stiff one (the heavy top), its dense
//! output under events and samples, its constrained runs (a stiff closed chain, a moving
//! constraint, velocity constraints), and the stiffness diagnosis that
//! points to it.
//!
//! The systems are those of the `stiff` example and benchmark (examples/support/stiff_system.rs).

use lagrange::prelude::*;
use lagrange_examples::stiff_system::{DampedDriven, RigidPendulumXy, SpringPendulum, TwoMasses};

use crate::support::{slope, TOP, TOP_Q0, TOP_V0};

/// Radau5 at rtol 1e-8 on the stiff problems.
const RADAU: Method = Method::Radau5 {
    rtol: 1e-8,
    atol: 1e-10,
};

/// The largest difference between two states.
fn max_diff(a: ([f64; 2], [f64; 2]), b: ([f64; 2], [f64; 2])) -> f64 {
    (0..2).fold(0.0_f64, |m, i| {
        m.max((a.0[i] - b.0[i]).abs()).max((a.1[i] - b.1[i]).abs())
    })
}

/// The two-mass run of `method` to t = 10 from the slow manifold: its steps and its error
/// against the modal solution at the end, or `None` past `max_steps`.
fn two_masses(method: Method, max_steps: usize) -> Option<(usize, f64)> {
    let sys = TwoMasses::STIFF;
    let (q0, v0) = sys.slow_start();
    let tr = Simulation::new(&sys, q0, v0)
        .method(method)
        .until(10.0)
        .max_steps(max_steps)
        .keep_samples(false)
        .run()
        .ok()?;
    let end = (*tr.q.last()?, *tr.qdot.last()?);
    Some((tr.stats.steps, max_diff(end, sys.exact(q0, v0, 10.0))))
}

/// Two masses, k₁ = 1 and k₂ = 10⁸, from the slow manifold: Radau5 reaches t = 10 within 1e-7
/// of the exact solution in at most 1,000 steps; DOP853 needs over 100 times as many (measured
/// 2026-11-27: Radau5 91 steps, error 2.4e-9; DOP853 ~49,000 steps).
#[test]
fn radau5_crosses_the_two_masses_in_few_steps() {
    let (steps, err) = two_masses(RADAU, 1_000_000).expect("Radau5 reaches t = 10");
    eprintln!("two masses: Radau5 {steps} steps, error {err:.2e}");
    assert!(err <= 1e-7, "error {err:e}");
    assert!(steps <= 1000, "{steps} steps");
    let (dop, dop_err) = two_masses(
        Method::Dop853 {
            rtol: 1e-8,
            atol: 1e-10,
        },
        1_000_000,
    )
    .expect("DOP853 reaches t = 10");
    eprintln!("two masses: DOP853 {dop} steps, error {dop_err:.2e}");
    assert!(dop > 100 * steps, "DOP853 {dop} vs Radau5 {steps}");
    assert!(dop > 10_000, "DOP853 {dop}");
}

/// The stiff spring pendulum (k = 1/ε², ε = 10⁻⁴, g = l = m = 1, θ₀ = 1, from the slow
/// manifold) follows the rigid pendulum (DOP853 on the constrained system at rtol 1e-12) to 1e-6
/// in θ up to t = 10, in at most 2,000 steps (measured 2026-11-27: 119 steps, θ within 1.2e-7).
#[test]
fn radau5_stiff_spring_pendulum_follows_the_rigid_one() {
    let sys = SpringPendulum::STIFF;
    let (q0, v0) = sys.slow_start(1.0, 0.0);
    let times: Vec<f64> = (1..=100).map(|k| 0.1 * k as f64).collect();
    let tr = Simulation::new(&sys, q0, v0)
        .method(RADAU)
        .until(10.0)
        .sample_at(times.iter().copied())
        .run()
        .expect("Radau5 runs the spring pendulum");
    let rigid = RigidPendulumXy {
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    let (p0, u0) = rigid.state(1.0, 0.0);
    let rt = Simulation::constrained(&rigid, p0, u0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(10.0)
        .sample_at(times.iter().copied())
        .run()
        .expect("DOP853 runs the rigid pendulum");
    assert_eq!(tr.t.len(), rt.t.len());
    let mut worst = 0.0_f64;
    for (k, (q, p)) in tr.q.iter().zip(&rt.q).enumerate() {
        assert_eq!(tr.t[k], rt.t[k]);
        worst = worst.max((q[1] - RigidPendulumXy::theta(p)).abs());
    }
    eprintln!(
        "spring pendulum: Radau5 {} steps ({} rejected), max |θ − θ_rigid| {worst:.2e}",
        tr.stats.steps, tr.stats.rejected
    );
    assert!(worst <= 1e-6, "θ off the rigid pendulum by {worst:e}");
    assert!(tr.stats.steps <= 2000, "{:?}", tr.stats);
}

/// On the (non-stiff) heavy top Radau5 is correct: its error at t = 10 against DOP853 at rtol
/// 1e-13 is proportional to rtol (slope of ln error against ln rtol measured 2026-11-27: about
/// 1, asserted in [0.8, 1.2]), and the energy drifts by at most 100 rtol.
#[test]
fn radau5_on_the_heavy_top_error_follows_the_tolerance() {
    let reference = Simulation::new(&TOP, TOP_Q0, TOP_V0)
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-13,
        })
        .until(10.0)
        .keep_samples(false)
        .run()
        .unwrap();
    let (qr, vr) = (reference.q[1], reference.qdot[1]);
    let mut points = Vec::new();
    for rtol in [1e-6, 1e-7, 1e-8, 1e-9, 1e-10] {
        let tr = Simulation::new(&TOP, TOP_Q0, TOP_V0)
            .method(Method::Radau5 { rtol, atol: rtol })
            .until(10.0)
            .sample_every(0.01)
            .run()
            .unwrap();
        let (q, v) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
        let err = (0..3).fold(0.0_f64, |m, i| {
            m.max((q[i] - qr[i]).abs()).max((v[i] - vr[i]).abs())
        });
        let energy = tr.invariants().energy.unwrap().max_rel;
        eprintln!(
            "heavy top: rtol {rtol:.0e}: {} steps, error {err:.2e}, energy drift {energy:.2e}",
            tr.stats.steps
        );
        assert!(
            energy <= 100.0 * rtol,
            "rtol {rtol:e}: energy drift {energy:e}"
        );
        points.push((rtol, err));
    }
    let p = slope(&points);
    eprintln!("heavy top: error ∝ rtol^{p:.3}");
    assert!((0.8..1.2).contains(&p), "slope {p}: {points:?}");
}

/// A heavily damped driven oscillator (k = 10⁶, c = 10⁴, written with `fn dissipation`,
/// `fn forces` and `t: Time`) follows its closed form, transient and steady state, to 1e-8 at
/// every step up to t = 10 (x absolutely, ẋ relative to max(|ẋ|, 1)), in far fewer steps than
/// DOP853 needs at the same tolerance (measured 2026-11-27 at rtol 1e-11: 1,628 steps, error
/// 1.3e-9, against DOP853's 120,154; at rtol 1e-10 ẋ was off by 1.3e-8, as the tolerance
/// transform 0.1 rtol^(2/3) allows).
#[test]
fn radau5_damped_driven_oscillator_follows_its_closed_form() {
    let sys = DampedDriven::STIFF;
    let run = |method: Method| {
        Simulation::new(&sys, [0.0], [0.0])
            .method(method)
            .until(10.0)
            .run()
            .unwrap()
    };
    let tr = run(Method::Radau5 {
        rtol: 1e-11,
        atol: 1e-13,
    });
    let (mut worst, mut worst_x, mut at) = (0.0_f64, 0.0_f64, 0.0);
    for (k, &t) in tr.t.iter().enumerate() {
        let (x, v) = sys.exact(0.0, 0.0, t);
        // x is O(1), ẋ too after the transient; ẋ peaks near 100 in it.
        let e = (tr.q[k][0] - x)
            .abs()
            .max((tr.qdot[k][0] - v).abs() / v.abs().max(1.0));
        worst_x = worst_x.max((tr.q[k][0] - x).abs());
        if e > worst {
            (worst, at) = (e, t);
        }
    }
    let dop = run(Method::Dop853 {
        rtol: 1e-11,
        atol: 1e-13,
    });
    eprintln!(
        "damped driven: Radau5 {} steps, error {worst:.2e} (at t = {at}; in x {worst_x:.2e}); \
         DOP853 {} steps",
        tr.stats.steps, dop.stats.steps
    );
    assert!(worst <= 1e-8, "error {worst:e}");
    assert!(
        10 * tr.stats.steps < dop.stats.steps,
        "Radau5 {} vs DOP853 {}",
        tr.stats.steps,
        dop.stats.steps
    );
}

/// The stiffness diagnosis of a DOP853 run out of steps (`.max_steps(1000)`) names Radau5 on the
/// stiff pair, and no diagnosis comes on the heavy top with the same budget.
#[test]
fn the_diagnosis_names_radau5_on_the_stiff_pair_only() {
    let dop = Method::Dop853 {
        rtol: 1e-8,
        atol: 1e-10,
    };
    let sys = TwoMasses::STIFF;
    let (q0, v0) = sys.slow_start();
    let err = Simulation::new(&sys, q0, v0)
        .method(dop)
        .until(10.0)
        .max_steps(1000)
        .run()
        .unwrap_err();
    assert!(err.stiffness().is_some(), "{err}");
    let m = err.to_string();
    assert!(
        m.contains("Method::Radau5 { rtol, atol }")
            && m.find("Method::Radau5") < m.find("Method::VariationalMidpoint"),
        "{m}"
    );
    let err = Simulation::new(&TOP, TOP_Q0, TOP_V0)
        .method(dop)
        .until(1e5)
        .max_steps(1000)
        .run()
        .unwrap_err();
    assert!(matches!(err, SimulationError::MaxSteps { .. }), "{err}");
    assert!(err.stiffness().is_none(), "{err}");
    assert!(!err.to_string().contains("Radau5"), "{err}");
}

/// Events and samples on Radau5's dense output: on the two masses from the slow manifold,
/// x₁ = cos(ω t) crosses zero at t = (k + ½)π/ω, located against that closed form, and the samples
/// every 0.25 match the modal solution (measured 2026-11-27 at rtol 1e-10: 188 steps, events
/// within 6.6e-11, samples within 2.0e-9, `Trajectory::at` within 3.3e-9).
#[test]
fn radau5_events_and_samples_on_its_dense_output() {
    let sys = TwoMasses::STIFF;
    let (q0, v0) = sys.slow_start();
    let w = sys.modes()[0].0.sqrt();
    let tr = Simulation::new(&sys, q0, v0)
        .method(Method::Radau5 {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(10.0)
        .sample_every(0.25)
        .keep_dense_output(true)
        .event(Event::zero_crossing("x1 = 0", |_t, q: &[f64; 2], _v| q[0]))
        .run()
        .unwrap();
    let zeros: Vec<f64> = (0..)
        .map(|k| (k as f64 + 0.5) * core::f64::consts::PI / w)
        .take_while(|&t| t < 10.0)
        .collect();
    assert_eq!(tr.events.len(), zeros.len(), "{:?}", tr.events);
    let mut worst_event = 0.0_f64;
    for (hit, t) in tr.events.iter().zip(&zeros) {
        worst_event = worst_event.max((hit.t - t).abs());
    }
    let mut worst_sample = 0.0_f64;
    assert_eq!(tr.t.len(), 41);
    for (k, &t) in tr.t.iter().enumerate() {
        let s = (tr.q[k], tr.qdot[k]);
        worst_sample = worst_sample.max(max_diff(s, sys.exact(q0, v0, t)));
    }
    // The kept dense output between the samples too.
    let mut worst_dense = 0.0_f64;
    for k in 0..200 {
        let t = 0.0498 * k as f64 + 0.013;
        let (q, v) = tr.at(t).unwrap();
        worst_dense = worst_dense.max(max_diff((q, v), sys.exact(q0, v0, t)));
    }
    eprintln!(
        "two masses, Radau5 1e-10: {} steps, events within {worst_event:.2e}, samples within \
         {worst_sample:.2e}, dense output within {worst_dense:.2e}",
        tr.stats.steps
    );
    assert!(worst_event <= 1e-7, "{worst_event:e}");
    assert!(worst_sample <= 1e-7, "{worst_sample:e}");
    assert!(worst_dense <= 1e-7, "{worst_dense:e}");
}

/// A slider crank whose connecting rod is a stiff, damped spring, written as a user writes it:
/// the crank pin (x₁, y₁) of mass m₁ on a rigid crank of length l about the origin, the slider
/// (x₂, y₂) of mass m₂ on the rail y = −h, the rod between them a spring of rest length d and
/// stiffness k with a dashpot c along it, gravity along −y: a closed chain with a stiff element
/// (for k = 10⁸, c = 10⁴ the rod's axial mode at ≈ √(k/μ) ≈ 1.7·10⁴ rad/s, damping ratio
/// c/2√(kμ) ≈ 0.9, μ ≈ 1/3 the reduced mass), two holonomic constraints.
#[derive(Clone, Copy)]
pub struct ElasticCrank {
    pub m1: f64,
    pub m2: f64,
    pub l: f64,
    pub h: f64,
    pub d: f64,
    pub k: f64,
    pub c: f64,
    pub g: f64,
}

#[lagrangian]
impl ElasticCrank {
    fn lagrangian(
        &self,
        (x1, x1_dot): Coord,
        (y1, y1_dot): Coord,
        (x2, x2_dot): Coord,
        (y2, y2_dot): Coord,
    ) -> Scalar {
        let stretch = ((x2 - x1).powi(2) + (y2 - y1).powi(2)).sqrt() - self.d;
        0.5 * self.m1 * (x1_dot.powi(2) + y1_dot.powi(2))
            + 0.5 * self.m2 * (x2_dot.powi(2) + y2_dot.powi(2))
            - self.g * (self.m1 * y1 + self.m2 * y2)
            - 0.5 * self.k * stretch.powi(2)
    }
    /// A dashpot along the rod: D = ½ c ṡ², ṡ = Δr·Δṙ/|Δr| the rate of the rod's length.
    fn dissipation(
        &self,
        (x1, x1_dot): Coord,
        (y1, y1_dot): Coord,
        (x2, x2_dot): Coord,
        (y2, y2_dot): Coord,
    ) -> Scalar {
        let (dx, dy) = (x2 - x1, y2 - y1);
        let rate = (dx * (x2_dot - x1_dot) + dy * (y2_dot - y1_dot)) / (dx * dx + dy * dy).sqrt();
        0.5 * self.c * rate.powi(2)
    }
    fn constraints(
        &self,
        (x1, _): Coord,
        (y1, _): Coord,
        (_, _): Coord,
        (y2, _): Coord,
    ) -> [Scalar; 2] {
        [x1.powi(2) + y1.powi(2) - self.l * self.l, y2 + self.h]
    }
}

/// The same mechanism in its minimal coordinates, derived apart: the crank angle θ from the
/// downward vertical (x₁ = l sin θ, y₁ = −l cos θ) and the slider's x₂ (y₂ = −h); no constraint.
pub struct ElasticCrankMinimal {
    pub m1: f64,
    pub m2: f64,
    pub l: f64,
    pub h: f64,
    pub d: f64,
    pub k: f64,
    pub c: f64,
    pub g: f64,
}

#[lagrangian]
impl ElasticCrankMinimal {
    fn lagrangian(&self, (theta, theta_dot): Coord, (x2, x2_dot): Coord) -> Scalar {
        let (x1, y1) = (self.l * theta.sin(), -self.l * theta.cos());
        let stretch = ((x2 - x1).powi(2) + (-self.h - y1).powi(2)).sqrt() - self.d;
        0.5 * self.m1 * self.l * self.l * theta_dot.powi(2)
            + 0.5 * self.m2 * x2_dot.powi(2)
            + self.g * self.m1 * self.l * theta.cos()
            - 0.5 * self.k * stretch.powi(2)
    }
    fn dissipation(&self, (theta, theta_dot): Coord, (x2, x2_dot): Coord) -> Scalar {
        // Δr = (x₂ − l sin θ, −h + l cos θ), Δṙ = (ẋ₂ − l θ̇ cos θ, −l θ̇ sin θ).
        let (dx, dy) = (x2 - self.l * theta.sin(), -self.h + self.l * theta.cos());
        let (du, dw) = (
            x2_dot - self.l * theta_dot * theta.cos(),
            -self.l * theta_dot * theta.sin(),
        );
        let rate = (dx * du + dy * dw) / (dx * dx + dy * dy).sqrt();
        0.5 * self.c * rate.powi(2)
    }
}

/// (q, q̇) of a system of N coordinates.
type State<const N: usize> = ([f64; N], [f64; N]);

/// The elastic crank of the tests: the rod at rest length at θ₀ = 0.5 (the slider where the
/// rod's length is d), everything at rest; returns the Cartesian state and the minimal one.
fn elastic_crank() -> (ElasticCrank, State<4>, State<2>) {
    let p = ElasticCrank {
        m1: 1.0,
        m2: 0.5,
        l: 1.0,
        h: 1.5,
        d: 2.0,
        k: 1e8,
        c: 1e4,
        g: 9.81,
    };
    let theta0: f64 = 0.5;
    let (x1, y1) = (p.l * theta0.sin(), -p.l * theta0.cos());
    let x2 = x1 + (p.d * p.d - (p.h + y1).powi(2)).sqrt();
    (p, ([x1, y1, x2, -p.h], [0.0; 4]), ([theta0, x2], [0.0; 2]))
}

/// Radau5 runs a stiff mechanism with holonomic constraints (the elastic crank: a closed chain
/// whose rod is a stiff damped spring) to the accuracy asked, against the same mechanism in its
/// minimal coordinates (derived apart, run by Radau5 at rtol 1e-12), in a small fraction of
/// DOP853's steps. Measured 2026-12-07 at rtol 1e-8: Radau5 1 005 steps (411 rejected, 10 135
/// evaluations, 1 271 LUs; before the bound on the step after a Newton failure 878 steps, 1 043
/// rejected, 13 451 evaluations, 1 820 LUs), worst difference 9.9e-9; DOP853 11 976 steps (at its
/// stability limit), 4.0e-9; Radau5 on the minimal model 486 steps (190 rejected; before, 498 and
/// 418).
#[test]
fn radau5_runs_a_stiff_closed_chain_on_its_constraints() {
    let (p, (q0, v0), (qm, vm)) = elastic_crank();
    let until = 2.0;
    let minimal = ElasticCrankMinimal {
        m1: p.m1,
        m2: p.m2,
        l: p.l,
        h: p.h,
        d: p.d,
        k: p.k,
        c: p.c,
        g: p.g,
    };
    let reference = Simulation::new(&minimal, qm, vm)
        .method(Method::Radau5 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(until)
        .sample_every(0.25)
        .run()
        .unwrap();
    let run = |method: Method| {
        Simulation::new(&p, q0, v0)
            .method(method)
            .until(until)
            .sample_every(0.25)
            .max_steps(2_000_000)
            .run()
            .unwrap()
    };
    let minimal_radau = Simulation::new(&minimal, qm, vm)
        .method(Method::Radau5 {
            rtol: 1e-8,
            atol: 1e-10,
        })
        .until(until)
        .sample_every(0.25)
        .run()
        .unwrap();
    eprintln!(
        "elastic crank in minimal coordinates, Radau5: {:?}",
        minimal_radau.stats
    );
    let radau = run(Method::Radau5 {
        rtol: 1e-8,
        atol: 1e-10,
    });
    let dop = run(Method::Dop853 {
        rtol: 1e-8,
        atol: 1e-10,
    });
    assert_eq!(radau.t.len(), reference.t.len());
    for (name, tr, tol) in [("Radau5", &radau, 1e-6), ("DOP853", &dop, 1e-6)] {
        let mut worst = 0.0_f64;
        for (k, q) in tr.q.iter().enumerate() {
            let theta = q[0].atan2(-q[1]);
            let (theta_ref, x2_ref) = (reference.q[k][0], reference.q[k][1]);
            worst = worst
                .max((theta - theta_ref).abs())
                .max((q[2] - x2_ref).abs());
            // The slider's speed, the rate the reference carries too.
            worst = worst.max((tr.qdot[k][2] - reference.qdot[k][1]).abs());
        }
        let inv = tr.invariants();
        let c = inv.constraints.unwrap();
        eprintln!(
            "elastic crank, {name}: {:?}, {} steps, {} evaluations, worst difference {worst:.2e}, \
             residuals {:.1e} / {:.1e}",
            tr.stats, tr.stats.steps, tr.stats.rhs_evals, c.position, c.velocity
        );
        assert!(worst <= tol, "{name}: {worst:e}");
        assert!(c.position <= 1e-12 && c.velocity <= 1e-10, "{name}: {c:?}");
        assert_eq!(tr.lambda.len(), tr.t.len());
    }
    // The crank moves a lot: this is not a run that stays near its start.
    assert!((radau.q.last().unwrap()[0] - q0[0]).abs() > 0.1);
    assert!(
        10 * radau.stats.steps <= dop.stats.steps,
        "Radau5 {} steps against DOP853's {}",
        radau.stats.steps,
        dop.stats.steps
    );
}

/// A pendulum whose pivot is driven along x (x_p = a sin ωt), written in x, y with the moving
/// rod (x − x_p(t))² + y² = l²: Radau5 with a constraint that depends on time.
#[derive(Clone, Copy)]
pub struct DrivenPivot {
    pub l: f64,
    pub g: f64,
    pub a: f64,
    pub w: f64,
}

#[lagrangian]
impl DrivenPivot {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * (x_dot.powi(2) + y_dot.powi(2)) - self.g * y
    }
    fn constraints(&self, (x, _): Coord, (y, _): Coord, t: Time) -> [Scalar; 1] {
        [(x - self.a * (self.w * t).sin()).powi(2) + y.powi(2) - self.l * self.l]
    }
}

/// The same pendulum in its angle θ from the downward vertical, derived apart: the bob at
/// (x_p + l sin θ, −l cos θ), L = ½[(a ω cos ωt + l θ̇ cos θ)² + (l θ̇ sin θ)²] + g l cos θ.
pub struct DrivenPivotAngle {
    pub l: f64,
    pub g: f64,
    pub a: f64,
    pub w: f64,
}

#[lagrangian]
impl DrivenPivotAngle {
    fn lagrangian(&self, (theta, theta_dot): Coord, t: Time) -> Scalar {
        let u = self.a * self.w * (self.w * t).cos() + self.l * theta_dot * theta.cos();
        let w = self.l * theta_dot * theta.sin();
        0.5 * (u * u + w * w) + self.g * self.l * theta.cos()
    }
}

/// Radau5 with a rheonomic constraint (its Newton matrix from differences of the constrained
/// accelerations, the linearization leaving out the rows' terms in t) keeps the driven pendulum
/// on its moving rod and follows the angle model to the accuracy asked.
#[test]
fn radau5_follows_a_moving_constraint() {
    let p = DrivenPivot {
        l: 1.0,
        g: 9.81,
        a: 0.2,
        w: 5.0,
    };
    let (theta0, rate0) = (0.4_f64, 0.0);
    // ẋ = a ω + l θ̇ cos θ at t = 0, ẏ = l θ̇ sin θ.
    let q0 = [p.l * theta0.sin(), -p.l * theta0.cos()];
    let v0 = [
        p.a * p.w + p.l * rate0 * theta0.cos(),
        p.l * rate0 * theta0.sin(),
    ];
    let until = 5.0;
    let angle = DrivenPivotAngle {
        l: p.l,
        g: p.g,
        a: p.a,
        w: p.w,
    };
    let reference = Simulation::new(&angle, [theta0], [rate0])
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-13,
        })
        .until(until)
        .sample_every(0.5)
        .run()
        .unwrap();
    let tr = Simulation::new(&p, q0, v0)
        .method(Method::Radau5 {
            rtol: 1e-9,
            atol: 1e-11,
        })
        .until(until)
        .sample_every(0.5)
        .run()
        .unwrap();
    let mut worst = 0.0_f64;
    for ((t, q), r) in tr.t.iter().zip(&tr.q).zip(&reference.q) {
        let theta = (q[0] - p.a * (p.w * t).sin()).atan2(-q[1]);
        worst = worst.max((theta - r[0]).abs());
    }
    let c = tr.invariants().constraints.unwrap();
    eprintln!(
        "driven pivot, Radau5: {} steps, worst θ difference {worst:.2e}, residuals {:.1e} / {:.1e}",
        tr.stats.steps, c.position, c.velocity
    );
    assert!(worst <= 1e-7, "{worst:e}");
    assert!(c.position <= 1e-12 && c.velocity <= 1e-10, "{c:?}");
}

/// Radau5's constrained runs locate events and keep dense output and λ like its plain runs, and
/// run as ensemble members: the pendulum in x, y from θ = 1 at rest, its passages through the
/// bottom (x = 0), against DOP853 at rtol 1e-13 (Radau5 at rtol 1e-10 is ≈ 25× that: 2.5e-9).
#[test]
fn radau5_constrained_events_dense_output_and_ensembles() {
    let p = RigidPendulumXy {
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    let (q0, v0) = p.state(1.0, 0.0);
    let run = |method: Method| {
        Simulation::new(&p, q0, v0)
            .method(method)
            .until(10.0)
            .sample_every(0.5)
            .keep_dense_output(true)
            .event(Event::zero_crossing("bottom", |_t, q: &[f64; 2], _v| q[0]))
            .run()
            .unwrap()
    };
    let radau5 = Method::Radau5 {
        rtol: 1e-10,
        atol: 1e-12,
    };
    let radau = run(radau5);
    let reference = run(Method::Dop853 {
        rtol: 1e-13,
        atol: 1e-13,
    });
    // Bottom passages at T/4, 3T/4, 5T/4 (T ≈ 6.7 at 1 rad).
    assert_eq!(radau.events.len(), 3);
    assert_eq!(radau.events.len(), reference.events.len());
    let worst_event = radau
        .events
        .iter()
        .zip(&reference.events)
        .fold(0.0_f64, |m, (a, b)| m.max((a.t - b.t).abs()));
    let (mut worst_dense, mut off_rod) = (0.0_f64, 0.0_f64);
    for k in 0..97 {
        let t = 0.1031 * k as f64;
        let ((q, v), (qr, vr)) = (radau.at(t).unwrap(), reference.at(t).unwrap());
        for i in 0..2 {
            worst_dense = worst_dense
                .max((q[i] - qr[i]).abs())
                .max((v[i] - vr[i]).abs());
        }
        off_rod = off_rod.max((q[0] * q[0] + q[1] * q[1] - 1.0).abs());
    }
    let worst_lambda = radau
        .lambda
        .iter()
        .zip(&reference.lambda)
        .fold(0.0_f64, |m, (a, b)| m.max((a[0] - b[0]).abs()));
    eprintln!(
        "pendulum in x, y, Radau5 1e-10: {} steps, events within {worst_event:.1e}, dense \
         output within {worst_dense:.1e} (off the rod by {off_rod:.1e}), λ within \
         {worst_lambda:.1e}",
        radau.stats.steps
    );
    assert!(worst_event <= 1e-8, "{worst_event:e}");
    assert!(worst_dense <= 1e-8, "{worst_dense:e}");
    assert!(off_rod <= 1e-8, "{off_rod:e}");
    assert!(worst_lambda <= 1e-8, "{worst_lambda:e}");
    // Three members from θ = 0.5, 1, 1.5: each the single run of its start.
    let start = |i: usize| p.state(0.5 * (i + 1) as f64, 0.0);
    let r = Ensemble::new(3, |i| {
        let (q, v) = start(i);
        Member::new(p, q, v)
    })
    .configure(|sim| sim.method(radau5).until(10.0))
    .run();
    for (i, res) in r.results.iter().enumerate() {
        let tr = res.as_ref().unwrap();
        let (q, v) = start(i);
        let single = Simulation::new(&p, q, v)
            .method(radau5)
            .until(10.0)
            .run()
            .unwrap();
        assert_eq!(tr.q.last(), single.q.last(), "member {i}");
    }
}

/// Radau5 runs velocity constraints: the Chaplygin sleigh of tests/one_run.rs against its
/// closed form.
#[test]
fn radau5_runs_the_sleigh() {
    use crate::one_run::{sleigh_closed_form, sleigh_rates, sleigh_start, Sleigh};
    let s = Sleigh {
        m: 2.0,
        i: 0.3,
        a: 0.4,
    };
    let (u0, w0) = (0.2, 1.5);
    let (q0, v0) = sleigh_start(&s, u0, w0);
    let tr = Simulation::new(&s, q0, v0)
        .method(Method::Radau5 {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(6.0)
        .sample_every(1.0)
        .run()
        .unwrap();
    for ((t, q), v) in tr.t.iter().zip(&tr.q).zip(&tr.qdot) {
        let (u, w) = sleigh_rates(q, v);
        let (u_exact, w_exact) = sleigh_closed_form(&s, u0, w0, *t);
        assert!(
            (u - u_exact).abs() < 1e-8,
            "t = {t}: u {u} against {u_exact}"
        );
        assert!(
            (w - w_exact).abs() < 1e-8,
            "t = {t}: ω {w} against {w_exact}"
        );
    }
    assert!(tr.invariants().constraints.unwrap().velocity < 1e-12);
}

/// Bad tolerances are refused before any step, as for the other adaptive methods.
#[test]
fn radau5_checks_its_tolerances() {
    let sys = TwoMasses::STIFF;
    for (rtol, atol) in [(0.0, 1e-10), (-1e-8, 1e-10), (1e-8, -1.0), (1e-17, 0.0)] {
        let err = Simulation::new(&sys, [1.0, 1.0], [0.0, 0.0])
            .method(Method::Radau5 { rtol, atol })
            .until(1.0)
            .run()
            .unwrap_err();
        assert!(
            matches!(err, SimulationError::InvalidOptions { .. }),
            "{rtol} {atol}: {err}"
        );
    }
}
