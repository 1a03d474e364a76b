//! The variational equations: Φ(t) = ∂(q, q̇)(t)/∂(q₀, q̇₀) from
//! `Simulation::sensitivity` against finite differences of runs, Liouville's formula for the
//! damped driven pendulum, and the sensitivity of an event's time against the pendulum's closed
//! form through K(k) and E(k).

use lagrange::prelude::*;
use lagrange::DMatrix;

use crate::support::systems::{HeavyTop, HeavyTopJets};
use crate::support::Rng;
use lagrange_examples::driven_pendulum_system::DrivenPendulum;
use lagrange_examples::pendulum_system::{period, Pendulum};

/// (q, q̇)(t_end) of a plain run from y0.
fn end_state<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    y0: &[f64],
    t_end: f64,
    method: Method,
) -> Vec<f64> {
    let q0: [f64; N] = core::array::from_fn(|i| y0[i]);
    let v0: [f64; N] = core::array::from_fn(|i| y0[N + i]);
    let tr = Simulation::new(sys, q0, v0)
        .method(method)
        .until(t_end)
        .run()
        .unwrap();
    let (q, v) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
    q.iter().chain(v.iter()).copied().collect()
}

/// Φ(t_end) by Richardson-extrapolated central differences of plain runs:
/// (4 D(h/2) − D(h))/3 with D(h) = (x(x₀ + h e_j) − x(x₀ − h e_j))/2h (truncation O(h⁴)).
fn phi_by_differences<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    y0: &[f64],
    t_end: f64,
    method: Method,
    h: f64,
) -> DMatrix<f64> {
    let n2 = 2 * N;
    let mut phi = DMatrix::zeros(n2, n2);
    for j in 0..n2 {
        let d = |h: f64| -> Vec<f64> {
            let mut p = y0.to_vec();
            let mut m = y0.to_vec();
            p[j] += h;
            m[j] -= h;
            let (xp, xm) = (
                end_state(sys, &p, t_end, method),
                end_state(sys, &m, t_end, method),
            );
            xp.iter()
                .zip(&xm)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect()
        };
        let (d1, d2) = (d(h), d(h / 2.0));
        for i in 0..n2 {
            phi[(i, j)] = (4.0 * d2[i] - d1[i]) / 3.0;
        }
    }
    phi
}

/// The largest |a − b| relative to max(1, max |b|).
fn rel_diff(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    (a - b).amax() / scale
}

/// Φ(2) of the heavy top at 4 random states, from its variational equations, against
/// differences of runs (h = 1e-3, Richardson: truncation O(h⁴) ≈ 1e-12): DOP853 and
/// Dormand–Prince at rtol = atol = 1e-13 and the Taylor method at tol = 1e-15, where the runs'
/// error (~1e-13) over h makes the differences good to ~1e-10 of max |Φ|; RK4 at dt = 1e-2, where
/// both sides differentiate the same discrete map. Asserted to 1e-9 of max(1, max |Φ|) for each
/// (measured, symbolic: 7.7e-12 DOP853, 1.3e-11 RK4, 1.9e-11 Dormand–Prince, 6.9e-12 Taylor;
/// jets, which have no Taylor series: 6.9e-12, 1.3e-11, 1.7e-11), and the motion equal to the
/// plain run's to 1e-9.
fn heavy_top_phi_matches_differences<L: Lagrangian<3>>(top: &L, label: &str, taylor: bool) {
    let mut rng = Rng(0x5eed_0038);
    let mut worst = [0.0_f64; 4];
    for _ in 0..4 {
        let y0 = [
            rng.uniform(0.6, 2.4),
            rng.uniform(-3.0, 3.0),
            rng.uniform(-3.0, 3.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-5.0, 5.0),
        ];
        let t_end = 2.0;
        for (k, (method, tol)) in [
            (
                Method::Dop853 {
                    rtol: 1e-13,
                    atol: 1e-13,
                },
                1e-9,
            ),
            (Method::Rk4 { dt: 1e-2 }, 1e-9),
            (
                Method::DormandPrince {
                    rtol: 1e-13,
                    atol: 1e-13,
                },
                1e-9,
            ),
            (Method::Taylor { tol: 1e-15 }, 1e-9),
        ]
        .into_iter()
        .enumerate()
        .take(if taylor { 4 } else { 3 })
        {
            let run = Simulation::new(top, [y0[0], y0[1], y0[2]], [y0[3], y0[4], y0[5]])
                .method(method)
                .until(t_end)
                .sensitivity()
                .run()
                .unwrap();
            let fd = phi_by_differences(top, &y0, t_end, method, 1e-3);
            let d = rel_diff(run.final_phi(), &fd);
            worst[k] = worst[k].max(d);
            assert!(
                d < tol,
                "{label} {method:?} at {y0:?}: Φ off differences by {d:e}"
            );
            // The motion is the plain run's to the tolerance.
            let plain = end_state(top, &y0, t_end, method);
            let tr = &run.trajectory;
            let x: Vec<f64> =
                tr.q.last()
                    .unwrap()
                    .iter()
                    .chain(tr.qdot.last().unwrap())
                    .copied()
                    .collect();
            let dx = x
                .iter()
                .zip(&plain)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                dx < 1e-9,
                "{label} {method:?}: motion off the plain run by {dx:e}"
            );
        }
    }
    eprintln!(
        "{label}: worst relative difference DOP853 {:.2e}, RK4 {:.2e}, Dormand–Prince {:.2e}{}",
        worst[0],
        worst[1],
        worst[2],
        if taylor {
            format!(", Taylor {:.2e}", worst[3])
        } else {
            String::new()
        }
    );
}

#[test]
fn heavy_top_phi_matches_differences_symbolic() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    heavy_top_phi_matches_differences(&top, "symbolic", true);
}

#[test]
fn heavy_top_phi_matches_differences_jets() {
    let top = HeavyTopJets {
        i_perp: 1.0,
        i_par: 0.6,
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    heavy_top_phi_matches_differences(&top, "jets", false);
}

/// The damped driven pendulum of `examples/driven_pendulum.rs`: tr J = −b/(m l²), so by
/// Liouville's formula det Φ(t) = exp(−b t/(m l²)) along any motion. Asserted to 1e-10
/// relative at every quarter drive period over 5 periods (a = 0.9, DOP853 at 1e-12; measured
/// 1.4e-11).
#[test]
fn liouville_det_phi_of_the_damped_driven_pendulum() {
    let p = DrivenPendulum {
        m: 1.0,
        l: 1.0,
        g: 1.0,
        b: 0.5,
        a: 0.9,
        w: 2.0 / 3.0,
    };
    let period = 2.0 * std::f64::consts::PI / p.w;
    let run = Simulation::new(&p, [0.3], [-0.2])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(5.0 * period)
        .sample_every(period / 4.0)
        .sensitivity()
        .run()
        .unwrap();
    let rate = p.b / (p.m * p.l * p.l);
    let mut worst = 0.0_f64;
    for (t, phi) in run.trajectory.t.iter().zip(&run.phi) {
        let det = phi[(0, 0)] * phi[(1, 1)] - phi[(0, 1)] * phi[(1, 0)];
        let want = (-rate * t).exp();
        worst = worst.max((det / want - 1.0).abs());
    }
    eprintln!("Liouville: worst relative error of det Φ {worst:.2e}");
    assert!(worst < 1e-10, "det Φ off exp(−bt/ml²) by {worst:e}");
}

/// Released from rest at θ₀ = 1.3 (g = l = 1): the period T = 4 √(l/g) K(k), k = sin(θ₀/2),
/// from the time of the first θ-maximum (θ̇ = 0 falling), and dT/dθ₀ = 2 √(l/g) cos(θ₀/2)
/// (E/(k k′²) − K/k) from the event-time sensitivity, both to 1e-10 (the numbers
/// 7.019250311844546 and 1.2581654724013054 too); dT/dg = −T/(2g) through the parameter
/// sensitivity of the event time, to 1e-10. With DOP853 at 1e-13 and with the Taylor method
/// (the variational equations' series from the generated one) at 1e-15; with Radau5 at 1e-13,
/// T to 1e-10 and its sensitivities to 1e-8 (below). Measured: DOP853, T off by 2.2e-13, dT/dθ₀
/// by 9.6e-14, dT/dg by 7.3e-13; Taylor, 8.9e-16, 6.7e-16 and 2.1e-13; Radau5, 4.7e-12, 8.4e-10
/// and 2.4e-9.
#[test]
fn pendulum_period_and_its_sensitivities() {
    let (theta0, g, l) = (1.3_f64, 1.0_f64, 1.0_f64);
    let (t_closed, dt_closed) = period(theta0, g, l);
    assert!((t_closed - 7.019250311844546).abs() < 1e-12, "{t_closed}");
    assert!(
        (dt_closed - 1.2581654724013054).abs() < 1e-12,
        "{dt_closed}"
    );
    let p = Pendulum { g, l };
    // The tolerance of the sensitivities: 1e-10; Radau5's 1e-8, its Φ the derivative of its
    // discrete flow at radau5.f's internal tolerance 0.1·rtol^(2/3) = 4.6e-10 and read between
    // nodes from the collocation polynomial (order 3).
    for (method, sens_tol) in [
        (
            Method::Dop853 {
                rtol: 1e-13,
                atol: 1e-13,
            },
            1e-10,
        ),
        (Method::Taylor { tol: 1e-15 }, 1e-10),
        (
            Method::Radau5 {
                rtol: 1e-13,
                atol: 1e-13,
            },
            1e-8,
        ),
    ] {
        let run = Simulation::new(&p, [theta0], [0.0])
            .method(method)
            .until(10.0)
            .event(
                Event::zero_crossing("theta max", |_t, _q, v: &[f64; 1]| v[0])
                    .falling()
                    .terminal(),
            )
            .sensitivity()
            .parameter("g", g, |g| Pendulum { g, l })
            .run()
            .unwrap();
        let ev = &run.events[0];
        let dt = ev.dt_dx0.as_ref().unwrap();
        let dtdg = ev.dt_dp.as_ref().unwrap()[0];
        eprintln!(
            "{method:?}: T off by {:.1e}, dT/dθ₀ by {:.1e}, dT/dg by {:.1e}",
            ev.t - t_closed,
            dt[0] - dt_closed,
            dtdg + t_closed / (2.0 * g)
        );
        assert!((ev.t - t_closed).abs() < 1e-10, "{method:?}: T = {}", ev.t);
        assert!(
            (dt[0] - dt_closed).abs() < sens_tol,
            "{method:?}: dT/dθ₀ = {}",
            dt[0]
        );
        assert!(
            (dtdg + t_closed / (2.0 * g)).abs() < sens_tol,
            "{method:?}: dT/dg = {dtdg}"
        );
    }
}

/// What the sensitivity runs do not cover is refused before any step, saying what to use: a
/// field alone with the variational integrator (its Φ, its parameters given by their closure
/// and Radau5's are covered: tests/implicit_sensitivity.rs).
#[test]
fn unsupported_runs_are_refused() {
    let p = Pendulum { g: 1.0, l: 1.0 };
    let err = Simulation::new(&p, [1.0], [0.0])
        .method(Method::VariationalMidpoint { dt: 1e-2 })
        .until(1.0)
        .sensitivity()
        .field("g")
        .run()
        .unwrap_err();
    assert!(
        matches!(err, SimulationError::InvalidOptions { .. }),
        "{err}"
    );
    assert!(err.to_string().contains("Method::Dop853"), "{err}");
    // Resetting events are carried (the saltation matrix): tests/jump_sensitivity.rs.
}

/// The figure-eight choreography of three unit masses (G = 1) from the 8-digit initial data:
/// shooting (DOP853 at 1e-13, Newton with the monodromy and the phase condition, least-norm
/// steps across the family the integrals make) closes it to |x(T) − x₀| ≤ 1e-12 with
/// T = 6.32591398 to 1e-8. The masses are 1, so (q, q̇) are canonical (q, p) and the monodromy
/// is symplectic there: max |MᵀJM − J| ≤ 1e-10 (J = [[0, I], [−I, 0]]). The orbit is linearly
/// stable (Simó): every multiplier on the unit circle. Measured: one Newton iteration, closure
/// 8.4e-14, T = 6.325913980826 (8.3e-10 from 6.32591398), symplecticity 3.9e-12.
#[test]
fn figure_eight_by_shooting() {
    use lagrange::sensitivity::{OrbitStability, Shooting};
    use lagrange_examples::three_body_system::{
        FIGURE_EIGHT_PERIOD, FIGURE_EIGHT_Q0, FIGURE_EIGHT_V0, UNIT,
    };
    let orbit = Shooting::autonomous(&UNIT, FIGURE_EIGHT_Q0, FIGURE_EIGHT_V0, FIGURE_EIGHT_PERIOD)
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-13,
        })
        .tolerance(1e-12)
        .find()
        .unwrap();
    let m = &orbit.monodromy;
    let n = 6;
    let j = DMatrix::from_fn(12, 12, |r, c| {
        if c == r + n {
            1.0
        } else if r == c + n {
            -1.0
        } else {
            0.0
        }
    });
    let symplecticity = (m.transpose() * &j * m - &j).amax();
    eprintln!(
        "figure-eight: T = {:.12}, closure {:.2e}, symplecticity {:.2e}, {} iterations, |μ| = {:?}",
        orbit.period,
        orbit.closure,
        symplecticity,
        orbit.iterations,
        orbit
            .multipliers
            .iter()
            .map(|m| m.norm())
            .collect::<Vec<_>>()
    );
    assert!(orbit.closure <= 1e-12, "closure {:e}", orbit.closure);
    assert!(
        (orbit.period - FIGURE_EIGHT_PERIOD).abs() <= 1e-8,
        "T = {}",
        orbit.period
    );
    assert!(symplecticity <= 1e-10, "‖MᵀJM − J‖ = {symplecticity:e}");
    assert_eq!(orbit.stability, OrbitStability::Neutral);
}

/// The damped driven pendulum's period-1 orbit at a = 0.9 (forced: T = 2π/ω fixed), from a
/// state strobed after a transient: closes to 1e-11, is asymptotically stable, and its
/// monodromy obeys Liouville, det M = exp(−(b/(m l²)) T) to 1e-10 relative. Measured:
/// closure 2.0e-13, det M off by 8.5e-14 relative, μ = −0.0248 ± 0.0915i.
#[test]
fn driven_pendulum_period_one_orbit_and_liouville() {
    use lagrange::sensitivity::{OrbitStability, Shooting};
    let p = DrivenPendulum {
        m: 1.0,
        l: 1.0,
        g: 1.0,
        b: 0.5,
        a: 0.9,
        w: 2.0 / 3.0,
    };
    let period = 2.0 * std::f64::consts::PI / p.w;
    let tr = Simulation::new(&p, [0.0], [0.0])
        .until(30.0 * period)
        .run()
        .unwrap();
    let (q, v) = (*tr.q.last().unwrap(), *tr.qdot.last().unwrap());
    let orbit = Shooting::forced(&p, q, v, period)
        .start_time(30.0 * period)
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-13,
        })
        .tolerance(1e-11)
        .find()
        .unwrap();
    let m = &orbit.monodromy;
    let det = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
    let want = (-p.b / (p.m * p.l * p.l) * period).exp();
    let rel = (det / want - 1.0).abs();
    eprintln!(
        "driven pendulum a = 0.9: x₀ = ({}, {}), closure {:.2e}, det M relative error {rel:.2e}, μ = {:?}",
        orbit.q0[0], orbit.qdot0[0], orbit.closure, orbit.multipliers
    );
    assert!(orbit.closure <= 1e-11);
    assert!(rel <= 1e-10, "det M = {det}, exp(−bT/ml²) = {want}");
    assert_eq!(orbit.stability, OrbitStability::AsymptoticallyStable);
}

/// The damped driven pendulum on its strange attractor (a = 1.5): the sum of the Lyapunov
/// spectrum (QR every drive period over 300 periods after 100 of transient) is the mean of
/// tr J = −b/(m l²) = −0.5, to 1e-6; the largest exponent is positive (chaos). Measured:
/// λ = (0.1006, −0.6006), the sum −0.5 to 1e-12 (a finite-time spectrum on a chaotic motion:
/// its split moves with the step sequence, 0.1146 with per-component error weights).
#[test]
fn driven_pendulum_lyapunov_sum_on_the_strange_attractor() {
    use lagrange::sensitivity::Lyapunov;
    let p = DrivenPendulum {
        m: 1.0,
        l: 1.0,
        g: 1.0,
        b: 0.5,
        a: 1.5,
        w: 2.0 / 3.0,
    };
    let period = 2.0 * std::f64::consts::PI / p.w;
    let s = Lyapunov::new(&p, [0.0], [0.0])
        .transient(100.0 * period)
        .duration(300.0 * period)
        .renormalize_every(period)
        .tolerances(1e-11, 1e-11)
        .compute()
        .unwrap();
    let expected = -p.b / (p.m * p.l * p.l);
    eprintln!(
        "driven pendulum a = 1.5: λ = {:?}, sum {:.12} (expected {expected}), {} re-orthonormalizations",
        s.exponents,
        s.sum(),
        s.renormalizations
    );
    assert!((s.sum() - expected).abs() <= 1e-6, "sum {}", s.sum());
    assert!(s.exponents[0] > 0.05, "λ₁ = {}", s.exponents[0]);
    assert_eq!(
        s.history.last().map(|h| h.1.clone()),
        Some(s.exponents.clone())
    );
}

/// Near the pitchfork of the symmetric period-1 orbit (a = 1.0167), from the state where the
/// orbits example's shooting stopped (2e-3 off the orbit): the forced shooting converges (to the
/// symmetric orbit, unstable past the pitchfork: μ ≈ 1.19) and its monodromy obeys Liouville.
/// Regression: shooting cut singular values below the relative residual for forced systems too
/// (meant for autonomous families), which near the bifurcation dropped the direction Newton
/// needs, and the example stopped there with "no step along Newton's direction reduces
/// |x(T) − x₀|". Measured: 14 iterations, closure 3.1e-13.
#[test]
fn driven_pendulum_orbit_near_the_pitchfork() {
    use lagrange::sensitivity::{OrbitStability, Shooting};
    let p = DrivenPendulum {
        m: 1.0,
        l: 1.0,
        g: 1.0,
        b: 0.5,
        a: 0.9 + 0.2 * 7.0 / 12.0,
        w: 2.0 / 3.0,
    };
    let period = 2.0 * std::f64::consts::PI / p.w;
    let orbit = Shooting::forced(&p, [-0.8680008254129434], [1.9489105877596977], period)
        .start_time(30.0 * period)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .tolerance(1e-10)
        .find()
        .unwrap();
    eprintln!(
        "a = {}: θ₀ = {}, closure {:.1e}, μ = {:?}, {} iterations",
        p.a, orbit.q0[0], orbit.closure, orbit.multipliers, orbit.iterations
    );
    let m = &orbit.monodromy;
    let det = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
    let want = (-p.b / (p.m * p.l * p.l) * period).exp();
    assert!(orbit.closure <= 1e-10);
    assert!(
        (det / want - 1.0).abs() <= 1e-9,
        "det M = {det}, want {want}"
    );
    assert!(matches!(orbit.stability, OrbitStability::Unstable { .. }));
}

/// A sensitivity run's motion is the plain run's: with the same steps (the fixed-step RK4) to
/// round-off (1e-12 over 2000 steps: the augmented right-hand side evaluates q̈ through the
/// tangent kernel, whose operations are ordered differently from the plain kernel's, so the
/// last bits differ); the adaptive methods hold the variations to the tolerance too, so their
/// steps may be shorter, and their motion agrees within the tolerance.
#[test]
fn a_sensitivity_run_moves_as_the_plain_run() {
    let top = crate::support::systems::HeavyTop {
        i_perp: 1.0,
        i_par: 0.5,
        m: 1.0,
        g: 9.81,
        l: 0.5,
    };
    let (q0, v0) = ([0.6, 0.0, 0.0], [0.0, 1.0, 20.0]);
    for (method, same_steps) in [
        (Method::Rk4 { dt: 1e-3 }, true),
        (
            Method::Dop853 {
                rtol: 1e-10,
                atol: 1e-12,
            },
            false,
        ),
        (
            Method::DormandPrince {
                rtol: 1e-10,
                atol: 1e-12,
            },
            false,
        ),
        (Method::Taylor { tol: 1e-14 }, false),
    ] {
        let sim = || {
            Simulation::new(&top, q0, v0)
                .method(method)
                .until(2.0)
                .sample_every(0.5)
        };
        let plain = sim().run().unwrap();
        let sens = sim().sensitivity().run().unwrap();
        let tr = &sens.trajectory;
        assert_eq!(tr.t, plain.t, "{method:?}");
        let tol = if same_steps { 1e-12 } else { 1e-8 };
        for (a, b) in tr.q.iter().zip(&plain.q) {
            for i in 0..3 {
                assert!((a[i] - b[i]).abs() < tol, "{method:?}: {a:?} against {b:?}");
            }
        }
    }
}

/// With `motion_steps` a sensitivity run is the plain run plus its variations: the same stepper
/// over a problem that carries the columns, the steps chosen on the motion alone, q̈ from the
/// plain kernel. Its motion, samples, events and counters of accepted and rejected steps are the
/// plain run's bit for bit, for every explicit method; and Φ is still the derivative of the flow
/// (against the default run's, which also controls Φ's error).
#[test]
fn a_sensitivity_run_on_the_motions_steps_is_the_plain_run_bit_for_bit() {
    let top = crate::support::systems::HeavyTop {
        i_perp: 1.0,
        i_par: 0.5,
        m: 1.0,
        g: 9.81,
        l: 0.5,
    };
    let (q0, v0) = ([0.6, 0.0, 0.0], [0.0, 1.0, 20.0]);
    for method in [
        Method::Rk4 { dt: 1e-3 },
        Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        },
        Method::DormandPrince {
            rtol: 1e-10,
            atol: 1e-12,
        },
    ] {
        let sim = || {
            Simulation::new(&top, q0, v0)
                .method(method)
                .until(2.0)
                .sample_every(0.25)
                .event(Event::zero_crossing("θ̇ = 0", |_t, _q, v: &[f64; 3]| {
                    v[0]
                }))
        };
        let plain = sim().run().unwrap();
        let same = sim().sensitivity().motion_steps().run().unwrap();
        let tr = &same.trajectory;
        assert_eq!(tr.t, plain.t, "{method:?}");
        assert_eq!(tr.q, plain.q, "{method:?}");
        assert_eq!(tr.qdot, plain.qdot, "{method:?}");
        assert_eq!(
            (tr.stats.steps, tr.stats.rejected, tr.stats.rhs_evals),
            (
                plain.stats.steps,
                plain.stats.rejected,
                plain.stats.rhs_evals
            ),
            "{method:?}"
        );
        let times = |t: &Trajectory<3>| t.events.iter().map(|e| e.t).collect::<Vec<_>>();
        assert!(!plain.events.is_empty());
        assert_eq!(times(tr), times(&plain), "{method:?}");
        // Φ of the fixed steps against Φ with its own error controlled: the same to the
        // tolerance's order (1e-6 relative to Φ's size, which grows to about 60 here).
        let controlled = sim().sensitivity().run().unwrap();
        let (a, b) = (same.final_phi(), controlled.final_phi());
        let scale = b.amax();
        assert!(
            (a - b).amax() < 1e-6 * scale,
            "{method:?}: {}",
            (a - b).amax() / scale
        );
    }
}
