//! Sensitivities through constraints: Φ(t) = ∂(q, q̇)(t)/∂(q₀, q̇₀) of a constrained run, the
//! variations integrated with the Jacobian of the constrained accelerations. Φ(t0) is the
//! derivative of the projection onto the constraints, so Φ maps a perturbation of the start to
//! that of the run started from its projection; tested against central differences of runs
//! started on the constraints (the pendulum in x, y), against differences of runs whose start is
//! projected (`project_initial_state`), and on the Chaplygin sleigh (velocity constraints)
//! against the derivative of its closed form.

use lagrange::prelude::*;
use lagrange_examples::stiff_system::RigidPendulumXy;

/// The pendulum of the tests: m = g = l = 1 from θ₀ = 0.8, θ̇₀ = 0.3, to t = 3.
const PENDULUM: RigidPendulumXy = RigidPendulumXy {
    m: 1.0,
    g: 1.0,
    l: 1.0,
};

/// DOP853 at this tolerance for the runs and their differences.
const TIGHT: Method = Method::Dop853 {
    rtol: 1e-13,
    atol: 1e-13,
};

/// The end state (q, q̇) of a run from (q0, q̇0), projected onto the rod first if asked.
fn end(q0: [f64; 2], v0: [f64; 2], project: bool) -> [f64; 4] {
    let mut sim = Simulation::new(&PENDULUM, q0, v0).method(TIGHT).until(3.0);
    if project {
        sim = sim.project_initial_state();
    }
    let tr = sim.keep_samples(false).run().unwrap();
    let (q, v) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
    [q[0], q[1], v[0], v[1]]
}

/// Φ(3) of the pendulum in x, y against central differences (h = 1e-4: the differences' error
/// is h² y‴ ≈ 1e-8 plus the runs' 1e-13 / h = 1e-9; tolerance 1e-6) of runs started on the rod
/// at θ₀ ± h and θ̇₀ ± h: Φ (∂y₀/∂θ₀) and Φ (∂y₀/∂θ̇₀). A perturbation off the rod (along x) is
/// projected first: Φ e_x against differences of runs started at y₀ ± h e_x with
/// `project_initial_state`. Every column of Φ stays tangent to the rod (2 q·δq = 0).
#[test]
fn phi_of_a_constrained_run_is_the_derivative_of_the_projected_flow() {
    let (theta0, rate0) = (0.8, 0.3);
    let (q0, v0) = PENDULUM.state(theta0, rate0);
    let run = Simulation::new(&PENDULUM, q0, v0)
        .method(TIGHT)
        .until(3.0)
        .sensitivity()
        .run()
        .unwrap();
    let phi = run.final_phi();
    let apply = |d: [f64; 4]| -> [f64; 4] {
        core::array::from_fn(|i| (0..4).map(|k| phi[(i, k)] * d[k]).sum())
    };
    let h = 1e-4;
    let diff = |plus: [f64; 4], minus: [f64; 4]| -> [f64; 4] {
        core::array::from_fn(|i| (plus[i] - minus[i]) / (2.0 * h))
    };
    let on_rod = |theta: f64, rate: f64| {
        let (q, v) = PENDULUM.state(theta, rate);
        end(q, v, false)
    };
    // ∂y₀/∂θ₀ and ∂y₀/∂θ̇₀ of (l sin θ, −l cos θ, l cos θ θ̇, l sin θ θ̇).
    let (s, c) = (theta0.sin(), theta0.cos());
    let d_theta = [c, s, -s * rate0, c * rate0];
    let d_rate = [0.0, 0.0, c, s];
    let cases = [
        (
            "θ₀",
            apply(d_theta),
            diff(on_rod(theta0 + h, rate0), on_rod(theta0 - h, rate0)),
        ),
        (
            "θ̇₀",
            apply(d_rate),
            diff(on_rod(theta0, rate0 + h), on_rod(theta0, rate0 - h)),
        ),
        (
            "x₀ (off the rod, projected)",
            apply([1.0, 0.0, 0.0, 0.0]),
            diff(
                end([q0[0] + h, q0[1]], v0, true),
                end([q0[0] - h, q0[1]], v0, true),
            ),
        ),
        (
            "ẏ₀ (off the rod, projected)",
            apply([0.0, 0.0, 0.0, 1.0]),
            diff(
                end(q0, [v0[0], v0[1] + h], true),
                end(q0, [v0[0], v0[1] - h], true),
            ),
        ),
    ];
    for (name, from_phi, from_runs) in cases {
        let worst = (0..4).fold(0.0_f64, |m, i| m.max((from_phi[i] - from_runs[i]).abs()));
        eprintln!("pendulum in x, y: Φ along {name} within {worst:.1e} of the differences");
        assert!(worst <= 1e-6, "{name}: {from_phi:?} against {from_runs:?}");
    }
    // The columns stay tangent: G δq = 2 q·δq = 0 at the end.
    let q = run.trajectory.q.last().unwrap();
    for k in 0..4 {
        let g = 2.0 * (q[0] * phi[(0, k)] + q[1] * phi[(1, k)]);
        assert!(g.abs() <= 1e-9, "column {k}: G δq = {g:e}");
    }
    // The same run through `Simulation::constrained`.
    let explicit = Simulation::constrained(&PENDULUM, q0, v0)
        .method(TIGHT)
        .until(3.0)
        .sensitivity()
        .run()
        .unwrap();
    assert_eq!(explicit.final_phi(), phi);
}

/// A column dy = ∂(x, y, φ, ẋ, ẏ, φ̇) of the sleigh at (q, q̇) and t read as (δu, δω) —
/// δu = cos φ δẋ + sin φ δẏ + (ẏ cos φ − ẋ sin φ) δφ, δω = δφ̇ — against the central
/// difference (step h) of the closed form's (u, ω) at the two ends `exact`, to 1e-7.
fn assert_sleigh_column(
    t: f64,
    name: &str,
    (q, v): (&[f64; 3], &[f64; 3]),
    dy: [f64; 6],
    exact: [(f64, f64); 2],
    h: f64,
) {
    let (sn, cs) = q[2].sin_cos();
    let du = cs * dy[3] + sn * dy[4] + (v[1] * cs - v[0] * sn) * dy[2];
    let dw = dy[5];
    let (du_exact, dw_exact) = (
        (exact[0].0 - exact[1].0) / (2.0 * h),
        (exact[0].1 - exact[1].1) / (2.0 * h),
    );
    eprintln!(
        "sleigh t = {t}: ∂u/∂{name} {du:.10} (closed form {du_exact:.10}), ∂ω/∂{name} \
         {dw:.10} ({dw_exact:.10})"
    );
    assert!(
        (du - du_exact).abs() <= 1e-7 && (dw - dw_exact).abs() <= 1e-7,
        "t = {t}, {name}: ({du}, {dw}) against ({du_exact}, {dw_exact})"
    );
}

/// Velocity constraints: the Chaplygin sleigh of tests/one_run.rs. Its forward speed u and
/// turning rate ω at t follow in closed form from u₀, ω₀ (derived there); their derivatives by
/// u₀ and ω₀ (central differences of the closed form, h = 1e-5: error ~1e-10) against Φ(t)
/// applied to the start's tangent directions ∂y₀/∂u₀ = (0, 0, 0, 1, 0, 0) and
/// ∂y₀/∂ω₀ = (0, 0, 0, 0, a, 1), with δu = cos φ δẋ + sin φ δẏ + (ẏ cos φ − ẋ sin φ) δφ,
/// δω = δφ̇; tolerance 1e-7.
#[test]
fn phi_through_velocity_constraints_matches_the_sleighs_closed_form() {
    use crate::one_run::{sleigh_closed_form, sleigh_start, Sleigh};
    let s = Sleigh {
        m: 2.0,
        i: 0.3,
        a: 0.4,
    };
    let (u0, w0) = (0.2, 1.5);
    let (q0, v0) = sleigh_start(&s, u0, w0);
    let run = Simulation::new(&s, q0, v0)
        .method(TIGHT)
        .until(4.0)
        .sample_every(1.0)
        .sensitivity()
        .run()
        .unwrap();
    let h = 1e-5;
    for (k, &t) in run.trajectory.t.iter().enumerate().skip(1) {
        let (q, v, phi) = (run.trajectory.q[k], run.trajectory.qdot[k], &run.phi[k]);
        for (name, d0, exact) in [
            (
                "u₀",
                [0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
                [
                    sleigh_closed_form(&s, u0 + h, w0, t),
                    sleigh_closed_form(&s, u0 - h, w0, t),
                ],
            ),
            (
                "ω₀",
                [0.0, 0.0, 0.0, 0.0, s.a, 1.0],
                [
                    sleigh_closed_form(&s, u0, w0 + h, t),
                    sleigh_closed_form(&s, u0, w0 - h, t),
                ],
            ),
        ] {
            let dy: [f64; 6] = core::array::from_fn(|i| (0..6).map(|j| phi[(i, j)] * d0[j]).sum());
            assert_sleigh_column(t, name, (&q, &v), dy, exact, h);
        }
    }
}

/// Parameter sensitivities of a constrained run: the pendulum in x, y (m = 0.7, g = 9.81, rod
/// l = 1.3, from θ₀ = 0.8, θ̇₀ = 0.3, to t = 3, DOP853 and Radau5) differentiated by g (in L)
/// and by l (in the constraint x² + y² − l² alone: the start moves with it), against the
/// same pendulum in its angle (θ̈ = −(g/l) sin θ), whose ∂θ/∂g and ∂θ/∂l are the compiled
/// kernel's exact field derivatives — a different formulation, sharing only the physics.
///
/// Derivation: x = l sin θ, y = −l cos θ, so ∂x/∂g = l cos θ ∂θ/∂g, ∂y/∂g = l sin θ ∂θ/∂g, and
/// ∂ẋ/∂g = l (cos θ ∂θ̇/∂g − sin θ θ̇ ∂θ/∂g), ∂ẏ/∂g = l (sin θ ∂θ̇/∂g + cos θ θ̇ ∂θ/∂g). For l
/// the start (q₀, q̇₀) given at l is projected onto the circle of radius l + δl: along the rod
/// (θ₀ kept), the velocity kept (it is tangent), so θ̇₀ becomes l θ̇₀/(l + δl): dθ̇₀/dl =
/// −θ̇₀/l. Hence dθ/dl = ∂θ/∂l + Φ_θθ̇₀ (−θ̇₀/l) (and the same for θ̇), and ∂x/∂l = sin θ +
/// l cos θ dθ/dl, ∂y/∂l = −cos θ + l sin θ dθ/dl, ∂ẋ/∂l = cos θ θ̇ + l (cos θ dθ̇/dl − sin θ θ̇
/// dθ/dl), ∂ẏ/∂l = sin θ θ̇ + l (sin θ dθ̇/dl + cos θ θ̇ dθ/dl). Tolerance 1e-8 of the columns'
/// size (the constrained columns take ∂q̈/∂p as fourth-order differences of the constrained
/// accelerations, error ≈ 1e-11; the runs' 1e-13). A field alone (`.field`) is refused there,
/// naming the closure form.
#[test]
fn parameters_of_a_constrained_run_against_the_pendulum_in_its_angle() {
    use lagrange_examples::pendulum_system::Pendulum;
    let (m, g, l) = (0.7, 9.81, 1.3);
    let xy = RigidPendulumXy { m, g, l };
    let (th0, thd0) = (0.8, 0.3);
    let (q0, v0) = xy.state(th0, thd0);
    for method in [
        TIGHT,
        Method::Radau5 {
            rtol: 1e-13,
            atol: 1e-13,
        },
    ] {
        let angle = Simulation::new(&Pendulum { g, l }, [th0], [thd0])
            .method(TIGHT)
            .until(3.0)
            .sensitivity()
            .field("g")
            .field("l")
            .run()
            .unwrap();
        let run = Simulation::new(&xy, q0, v0)
            .method(method)
            .until(3.0)
            .sensitivity()
            .parameter("g", g, |p| RigidPendulumXy { m, g: p, l })
            .parameter("l", l, |p| RigidPendulumXy { m, g, l: p })
            .run()
            .unwrap();
        let (th, thd) = (
            angle.trajectory.q.last().unwrap()[0],
            angle.trajectory.qdot.last().unwrap()[0],
        );
        let (s, c) = th.sin_cos();
        let phi = angle.final_phi();
        let dp = angle.dparams.last().unwrap();
        // d(θ, θ̇)/dg, and d(θ, θ̇)/dl with the start's move.
        let (dth_g, dthd_g) = (dp[(0, 0)], dp[(1, 0)]);
        let (dth_l, dthd_l) = (
            dp[(0, 1)] + phi[(0, 1)] * (-thd0 / l),
            dp[(1, 1)] + phi[(1, 1)] * (-thd0 / l),
        );
        let want_g = [
            l * c * dth_g,
            l * s * dth_g,
            l * (c * dthd_g - s * thd * dth_g),
            l * (s * dthd_g + c * thd * dth_g),
        ];
        let want_l = [
            s + l * c * dth_l,
            -c + l * s * dth_l,
            c * thd + l * (c * dthd_l - s * thd * dth_l),
            s * thd + l * (s * dthd_l + c * thd * dth_l),
        ];
        let got = run.dparams.last().unwrap();
        for (col, want) in [(0, want_g), (1, want_l)] {
            let size = want.iter().fold(0.0_f64, |a, w| a.max(w.abs()));
            let worst = (0..4).fold(0.0_f64, |a, i| a.max((got[(i, col)] - want[i]).abs()));
            eprintln!(
                "{method:?}: ∂(x, y, ẋ, ẏ)/∂{} = {:?} against {want:?}: {:.1e} of {size:.2}",
                ["g", "l"][col],
                (0..4).map(|i| got[(i, col)]).collect::<Vec<_>>(),
                worst / size
            );
            assert!(worst < 1e-8 * size, "{worst:e} of {size}");
        }
    }
    // A field alone has no neighbouring systems to take the constrained accelerations of.
    let err = Simulation::new(&xy, q0, v0)
        .until(1.0)
        .sensitivity()
        .field("g")
        .run()
        .unwrap_err();
    assert!(
        matches!(err, SimulationError::InvalidOptions { .. }),
        "{err}"
    );
    assert!(err.to_string().contains(".parameter(\"g\""), "{err}");
}

/// Parameter sensitivities through velocity constraints: the Chaplygin sleigh (m = 2, i = 0.3,
/// a = 0.4, from u₀ = 0.2, ω₀ = 1.5) differentiated by its mass m and its moment of inertia i
/// (both in L; the blade's constraint and the start do not read them), against central
/// differences (h = 1e-5: error ~1e-10) of its closed form's (u, ω)(t) in m and i, read from
/// the columns as in the Φ test above: δu = cos φ δẋ + sin φ δẏ + (ẏ cos φ − ẋ sin φ) δφ,
/// δω = δφ̇; tolerance 1e-7.
#[test]
fn parameters_through_velocity_constraints_match_the_sleighs_closed_form() {
    use crate::one_run::{sleigh_closed_form, sleigh_start, Sleigh};
    let s = Sleigh {
        m: 2.0,
        i: 0.3,
        a: 0.4,
    };
    let (u0, w0) = (0.2, 1.5);
    let (q0, v0) = sleigh_start(&s, u0, w0);
    let run = Simulation::new(&s, q0, v0)
        .method(TIGHT)
        .until(4.0)
        .sample_every(1.0)
        .sensitivity()
        .parameter("m", s.m, |m| Sleigh { m, ..s })
        .parameter("i", s.i, |i| Sleigh { i, ..s })
        .run()
        .unwrap();
    let h = 1e-5;
    for (k, &t) in run.trajectory.t.iter().enumerate().skip(1) {
        let (q, v, dp) = (run.trajectory.q[k], run.trajectory.qdot[k], &run.dparams[k]);
        for (col, name, up, down) in [
            (
                0,
                "m",
                Sleigh { m: s.m + h, ..s },
                Sleigh { m: s.m - h, ..s },
            ),
            (
                1,
                "i",
                Sleigh { i: s.i + h, ..s },
                Sleigh { i: s.i - h, ..s },
            ),
        ] {
            let dy: [f64; 6] = core::array::from_fn(|r| dp[(r, col)]);
            let exact = [
                sleigh_closed_form(&up, u0, w0, t),
                sleigh_closed_form(&down, u0, w0, t),
            ];
            assert_sleigh_column(t, name, (&q, &v), dy, exact, h);
        }
    }
}

/// How the period of a constrained mechanism depends on a length: the pendulum in x, y on its
/// rod released from rest at θ₀ = 1 reaches its other turning point (ẋ = 0) at half its
/// period, T/2 = 2 √(l/g) K(sin ½); released from the same angle on a longer rod (the start's
/// projection keeps θ₀ and rest), dT/dl = T/(2l), dT/dg = −T/(2g). The event's time
/// sensitivities dt*/dp through the constrained run against those to 1e-9 relative.
#[test]
fn the_half_period_of_a_constrained_pendulum_by_its_length() {
    use lagrange_examples::pendulum_system::elliptic_ke;
    let (m, g, l) = (0.7, 9.81, 1.3);
    let xy = RigidPendulumXy { m, g, l };
    let (q0, v0) = xy.state(1.0, 0.0);
    let run = Simulation::new(&xy, q0, v0)
        .method(TIGHT)
        .until(2.0)
        .event(Event::zero_crossing("turning point", |_t, _q, v: &[f64; 2]| v[0]).terminal())
        .sensitivity()
        .parameter("l", l, |p| RigidPendulumXy { m, g, l: p })
        .parameter("g", g, |p| RigidPendulumXy { m, g: p, l })
        .run()
        .unwrap();
    let (kk, _) = elliptic_ke(0.5_f64.sin());
    let half = 2.0 * (l / g).sqrt() * kk;
    let hit = run.events.last().unwrap();
    let dt = hit.dt_dp.as_ref().unwrap();
    eprintln!(
        "half period {} (closed form {half}), dt/dl {} ({}), dt/dg {} ({})",
        hit.t,
        dt[0],
        half / (2.0 * l),
        dt[1],
        -half / (2.0 * g)
    );
    assert!((hit.t - half).abs() < 1e-11 * half);
    assert!((dt[0] - half / (2.0 * l)).abs() < 1e-9 * half / l);
    assert!((dt[1] + half / (2.0 * g)).abs() < 1e-9 * half / g);
}
