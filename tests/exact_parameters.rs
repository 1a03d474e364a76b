//! Exact parameter derivatives: where a parameter is a field the compiled kernels read (the
//! symbolic mode), ∂q̈/∂p is the kernel's own derivative, its parameter slot seeded in the same
//! tangents as the state's directions, not a difference of neighbouring systems. Given by name
//! (`.field("g")`) or by a closure that sets the field affinely (`.parameter("g", g, |g| …)`,
//! detected), with every method that takes parameters. Against closed forms where the
//! difference's round-off (≈ 1.6e-13 relative at h = ε^(1/5) |g|) would show, and against the
//! difference where the closure is not affine.

use lagrange::prelude::*;
use lagrange::DMatrix;
use lagrange_examples::driven_pendulum_system::DrivenPendulum;
use lagrange_examples::pendulum_system::{period, Pendulum};

/// A body of mass m falling under gravity g: ẍ = −g, so ∂x(t)/∂g = −t²/2, ∂ẋ(t)/∂g = −t and
/// ∂/∂m = 0, exactly.
pub struct Fall {
    /// Mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
}

#[lagrangian]
impl Fall {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * self.m * x_dot * x_dot - self.m * self.g * x
    }
}

/// The same body in the jets mode: no compiled kernels, so no field to seed.
pub struct FallJets {
    /// Gravity.
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl FallJets {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - self.g * x
    }
}

/// Every method that takes parameters, at tolerances where the falling body is integrated
/// exactly (its solution is a quadratic in t: every method of order ≥ 2 is exact on it).
fn methods() -> [Method; 5] {
    [
        Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-10,
        },
        Method::DormandPrince {
            rtol: 1e-10,
            atol: 1e-10,
        },
        Method::Rk4 { dt: 0.01 },
        Method::Taylor { tol: 1e-12 },
        Method::Radau5 {
            rtol: 1e-10,
            atol: 1e-10,
        },
    ]
}

/// ∂(x, ẋ)(t)/∂(m, g) = (0, 0), (−t²/2, −t) at every sample to 1e-14 · max(1, t²): round-off of
/// the steps' sums. The difference of the accelerations −(g ± h), −(g ± 2h) would be off by
/// ≈ 1.6e-13 relative (the rounding of g ± h over 12h), 6.4e-13 in ∂x(2)/∂g: this fails
/// without the exact path. `.field` and the affine closure give the same numbers bit for bit.
#[test]
fn a_falling_body_differentiates_exactly_by_its_fields() {
    let fall = Fall { m: 2.5, g: 9.81 };
    for method in methods() {
        let base = || {
            Simulation::new(&fall, [0.0], [0.0])
                .method(method)
                .until(2.0)
                .sample_every(0.1)
                .sensitivity()
        };
        let by_name = base().field("m").field("g").run().unwrap();
        let by_closure = base()
            .parameter("m", fall.m, |m| Fall { m, ..fall })
            .parameter("g", fall.g, |g| Fall { g, ..fall })
            .run()
            .unwrap();
        assert_eq!(by_name.parameters, ["m", "g"]);
        let mut worst = 0.0_f64;
        for (t, d) in by_name.trajectory.t.iter().zip(&by_name.dparams) {
            let exact = DMatrix::from_row_slice(2, 2, &[0.0, -0.5 * t * t, 0.0, -t]);
            let err = (d - &exact).amax() / t.mul_add(*t, 1.0);
            worst = worst.max(err);
        }
        eprintln!("{method:?}: ∂(x, ẋ)/∂(m, g) off by {worst:.1e}");
        assert!(worst < 1e-14, "{method:?}: {worst:e}");
        assert_eq!(by_name.dparams, by_closure.dparams, "{method:?}");
    }
}

/// The pendulum's return to its largest angle: a period from rest (terminal).
fn theta_max() -> Event<'static, 1> {
    Event::zero_crossing("theta max", |_t, _q, v: &[f64; 1]| v[0])
        .falling()
        .terminal()
}

/// The pendulum θ̈ = −(g/l) sin θ from rest at θ₀ = 1.3: its period's derivative
/// dT/dg = −T/(2g) (T = 4 √(l/g) K(sin(θ₀/2)) scales as g^(−1/2)), by an event's time
/// sensitivity. With the exact ∂q̈/∂g the parameter's column has the accuracy of Φ's: the Taylor
/// method at 1e-16 within 2e-15 of the closed form (measured 4.4e-16, one ulp of 3.5), DOP853 at
/// 1e-13 within 2e-13 (measured 7.2e-14); the difference's path is off by ≈ 3e-13 with either
/// (measured through a closure that is not affine in its parameter, g = s², s = √g, which takes
/// the difference: dT/ds = 2s dT/dg to 1e-10). A closure p ↦ g = p/2 at p = 2g is detected
/// affine with ∂g/∂p = 1/2: its column is half the field's, bit for bit (the same steps: the
/// motion's).
#[test]
fn the_pendulum_period_derivative_in_gravity() {
    let (theta0, g, l) = (1.3_f64, 1.0_f64, 1.0_f64);
    let (t_closed, _) = period(theta0, g, l);
    let dtdg_closed = -t_closed / (2.0 * g);
    let p = Pendulum { g, l };
    for (method, tol) in [
        (
            Method::Dop853 {
                rtol: 1e-13,
                atol: 1e-13,
            },
            2e-13,
        ),
        (Method::Taylor { tol: 1e-16 }, 2e-15),
    ] {
        let base = || {
            Simulation::new(&p, [theta0], [0.0])
                .method(method)
                .until(10.0)
                .event(theta_max())
                .sensitivity()
        };
        let dt_dp = |run: &Sensitivities<1>| run.events[0].dt_dp.as_ref().unwrap()[0];
        let run = base().field("g").run().unwrap();
        let dtdg = dt_dp(&run);
        let root = base()
            .parameter("sqrt g", g.sqrt(), |s| Pendulum { g: s * s, l })
            .run()
            .unwrap();
        let dtds = dt_dp(&root);
        eprintln!(
            "{method:?}: dT/dg off by {:.1e} (T by {:.1e}); by the difference of s = √g {:.1e}",
            dtdg - dtdg_closed,
            run.events[0].t - t_closed,
            dtds / (2.0 * g.sqrt()) - dtdg_closed
        );
        assert!((dtdg - dtdg_closed).abs() < tol, "{method:?}: {dtdg}");
        assert!(
            (dtds - 2.0 * g.sqrt() * dtdg).abs() < 1e-10,
            "{method:?}: {dtds}"
        );
        // On the motion's steps, p ↦ g = p/2 at p = 2g: the column is half the field's.
        let field = base().motion_steps().field("g").run().unwrap();
        let half = base()
            .motion_steps()
            .parameter("2g", 2.0 * g, |p| Pendulum { g: p / 2.0, l })
            .run()
            .unwrap();
        let halved: Vec<DMatrix<f64>> = field.dparams.iter().map(|d| d * 0.5).collect();
        assert_eq!(half.dparams, halved, "{method:?}");
    }
}

/// Radau5's parameter columns take the exact ∂f/∂p at its stages: the falling body (above) and
/// the pendulum's dT/dg within its own tolerance of the Φ comparisons (1e-8,
/// `tests/variational_equations.rs`).
#[test]
fn radau5_takes_the_exact_parameter_derivative() {
    let (theta0, g, l) = (1.3_f64, 1.0_f64, 1.0_f64);
    let (t_closed, _) = period(theta0, g, l);
    let run = Simulation::new(&Pendulum { g, l }, [theta0], [0.0])
        .method(Method::Radau5 {
            rtol: 1e-13,
            atol: 1e-13,
        })
        .until(10.0)
        .event(theta_max())
        .sensitivity()
        .field("g")
        .run()
        .unwrap();
    let dtdg = run.events[0].dt_dp.as_ref().unwrap()[0];
    eprintln!("Radau5: dT/dg off by {:.1e}", dtdg + t_closed / (2.0 * g));
    assert!((dtdg + t_closed / (2.0 * g)).abs() < 1e-8, "{dtdg}");
}

/// A name the kernels do not read, and a system without compiled kernels: refused at `run`
/// with what to do instead.
#[test]
fn fields_the_kernels_do_not_read_are_refused() {
    let fall = Fall { m: 1.0, g: 9.81 };
    let err = Simulation::new(&fall, [0.0], [0.0])
        .until(1.0)
        .sensitivity()
        .field("k")
        .run()
        .unwrap_err();
    let text = err.to_string();
    assert!(
        matches!(err, SimulationError::InvalidOptions { .. }),
        "{text}"
    );
    assert!(
        text.contains("field `k`") && text.contains("m, g"),
        "{text}"
    );
    let jets = FallJets { g: 9.81 };
    let err = Simulation::new(&jets, [0.0], [0.0])
        .until(1.0)
        .sensitivity()
        .field("g")
        .run()
        .unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("no compiled kernels") && text.contains(".parameter(\"g\""),
        "{text}"
    );
    // The closure form still differentiates the jets-mode body (by differences).
    let run = Simulation::new(&jets, [0.0], [0.0])
        .until(2.0)
        .sensitivity()
        .parameter("g", jets.g, |g| FallJets { g })
        .run()
        .unwrap();
    assert!((run.dparams.last().unwrap()[(0, 0)] + 2.0).abs() < 1e-10);
}

/// A nonlinear, forced, damped case: the driven pendulum m l² θ̈ = −m g l sin θ − b θ̇ + a cos ωt,
/// differentiated by its fields l (in M and in the gravity term), b (in D) and ω (inside the
/// drive's cosine, a force depending on time and on the field nonlinearly), exactly, against
/// central differences of runs at each field ± h (h = 1e-5 of its size: the differences' error
/// h² ∂³y/∂p³ ≈ 1e-10, the runs' 1e-13 / h = 1e-8), tolerance 1e-7 of max(1, |∂y/∂p|), with
/// DOP853 and Radau5.
#[test]
fn field_derivatives_of_a_driven_pendulum_match_differences_of_runs() {
    let p = DrivenPendulum {
        m: 1.0,
        l: 1.2,
        g: 9.81,
        b: 0.3,
        a: 1.5,
        w: 2.0,
    };
    let t_end = 4.0;
    let (q0, v0) = ([0.4], [0.0]);
    for method in [
        Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-13,
        },
        Method::Radau5 {
            rtol: 1e-13,
            atol: 1e-13,
        },
    ] {
        let run = Simulation::new(&p, q0, v0)
            .method(method)
            .until(t_end)
            .sensitivity()
            .field("l")
            .field("b")
            .field("w")
            .run()
            .unwrap();
        let d = run.dparams.last().unwrap();
        let end = |sys: DrivenPendulum| {
            let tr = Simulation::new(&sys, q0, v0)
                .method(method)
                .until(t_end)
                .run()
                .unwrap();
            [tr.q.last().unwrap()[0], tr.qdot.last().unwrap()[0]]
        };
        // The system with field k (l, b, ω) at x.
        let set = |k: usize, x: f64| DrivenPendulum {
            l: if k == 0 { x } else { p.l },
            b: if k == 1 { x } else { p.b },
            w: if k == 2 { x } else { p.w },
            ..p
        };
        for (k, value) in [p.l, p.b, p.w].into_iter().enumerate() {
            let h = 1e-5 * value.abs();
            let (up, down) = (end(set(k, value + h)), end(set(k, value - h)));
            for i in 0..2 {
                let diff = (up[i] - down[i]) / (2.0 * h);
                let err = (d[(i, k)] - diff).abs() / diff.abs().max(1.0);
                eprintln!(
                    "{method:?} field {k} row {i}: exact {:.12e}, differences off {err:.1e}",
                    d[(i, k)]
                );
                assert!(
                    err < 1e-7,
                    "{method:?}, field {k}, row {i}: {} vs {diff}",
                    d[(i, k)]
                );
            }
        }
    }
}
