//! `Trajectory::at`: accuracy against the exact motion, agreement with the recorded samples bit
//! for bit, the interpolants' orders, the memory bound, terminal events, failed and constrained
//! runs, ensembles' lanes, and the errors.

use crate::constraints::Holonomic;
use crate::ensemble::{Ensemble, Member};
use crate::integrate::tests::{Osc, slope};
use crate::integrate::{DenseOutputError, Event, Method, Simulation, SimulationError, Trajectory};
use crate::lagrangian::Lagrangian;
use crate::scalar::Scalar;

/// x'' = −w² x (ensemble members).
struct Spring {
    w: f64,
}
impl Lagrangian<1> for Spring {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        (v[0] * v[0] - q[0] * q[0] * (self.w * self.w)) * 0.5
    }
}

/// A free particle on the unit circle: from (1, 0) with velocity (0, 1), (cos t, sin t).
struct Ring;
impl Lagrangian<2> for Ring {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [true, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * 0.5
    }
}
impl Holonomic<2, 1> for Ring {
    const SCLERONOMIC: bool = true;
    fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
        [q[0] * q[0] + q[1] * q[1] - 1.0]
    }
}

const DOP853: Method = Method::Dop853 {
    rtol: 1e-10,
    atol: 1e-12,
};

/// The explicit, Radau and variational methods, the adaptive ones first (the Taylor method
/// needs a generated series: it is tested in tests/taylor.rs).
fn methods() -> [Method; 5] {
    [
        DOP853,
        Method::DormandPrince {
            rtol: 1e-9,
            atol: 1e-12,
        },
        Method::Radau5 {
            rtol: 1e-9,
            atol: 1e-12,
        },
        Method::Rk4 { dt: 0.01 },
        Method::VariationalMidpoint { dt: 0.01 },
    ]
}

/// Uniform numbers in [0, 1) from a fixed seed (a 64-bit LCG's top 53 bits).
fn uniform(n: usize) -> Vec<f64> {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

fn osc(method: Method, until: f64) -> Simulation<'static, Osc, 1> {
    Simulation::new(&Osc, [1.0], [0.0])
        .method(method)
        .until(until)
        .keep_dense_output(true)
}

#[test]
fn at_agrees_with_the_exact_motion_at_1000_random_times() {
    let tr = osc(DOP853, 20.0).run().unwrap();
    assert_eq!(tr.dense_span(), Some((0.0, 20.0)));
    let mut worst = 0.0_f64;
    for u in uniform(1000) {
        let t = 20.0 * u;
        let (q, v) = tr.at(t).unwrap();
        worst = worst
            .max((q[0] - t.cos()).abs())
            .max((v[0] + t.sin()).abs());
    }
    assert!(worst <= 1e-8, "largest error {worst:e}");
    // Both ends are the run's first and last states.
    assert_eq!(tr.at(0.0).unwrap(), ([1.0], [0.0]));
    assert_eq!(
        tr.at(20.0).unwrap(),
        (tr.q[tr.len() - 1], tr.qdot[tr.len() - 1])
    );
}

/// (q, q̇) of sample k, for comparison with `at`.
fn sample(tr: &Trajectory<1>, k: usize) -> ([f64; 1], [f64; 1]) {
    (tr.q[k], tr.qdot[k])
}

#[test]
fn at_the_nodes_and_at_interpolated_samples_is_the_recorded_sample_bit_for_bit() {
    for method in methods() {
        // Every step recorded: the samples are the nodes.
        let tr = osc(method, 3.0).run().unwrap();
        assert!(tr.len() > 10, "{method:?}");
        for k in 0..tr.len() {
            assert_eq!(
                tr.at(tr.t[k]).unwrap(),
                sample(&tr, k),
                "{method:?} node {k}"
            );
        }
    }
    // Samples between the nodes come from the same interpolant.
    let times: Vec<f64> = uniform(200).iter().map(|u| 0.01 + 2.98 * u).collect();
    let mut times = times;
    times.sort_by(f64::total_cmp);
    for method in &methods()[..3] {
        let tr = osc(*method, 3.0).sample_at(times.clone()).run().unwrap();
        for k in 0..tr.len() {
            assert_eq!(
                tr.at(tr.t[k]).unwrap(),
                sample(&tr, k),
                "{method:?} t = {}",
                tr.t[k]
            );
        }
    }
}

#[test]
fn keeping_the_dense_output_changes_no_sample() {
    for method in methods() {
        let run = |keep| {
            Simulation::new(&Osc, [1.0], [0.0])
                .method(method)
                .until(3.0)
                .sample_every(0.25)
                .event(Event::zero_crossing("x = 0", |_t, q: &[f64; 1], _v| q[0]))
                .keep_dense_output(keep)
                .run()
                .unwrap()
        };
        let (with, without) = (run(true), run(false));
        assert_eq!(
            (&with.t, &with.q, &with.qdot),
            (&without.t, &without.q, &without.qdot)
        );
        assert_eq!(with.events, without.events, "{method:?}");
    }
}

/// The largest error of `at` at the middle of every step of a run to t = 2 in steps of h
/// (the adaptive methods with tolerances so loose that the step saturates at its cap h).
fn midpoint_error(method: fn(f64) -> Method, h: f64) -> f64 {
    let tr = osc(method(h), 2.0).max_step(h).run().unwrap();
    let mut worst = 0.0_f64;
    for w in tr.t.windows(2) {
        let t = 0.5 * (w[0] + w[1]);
        let (q, v) = tr.at(t).unwrap();
        worst = worst
            .max((q[0] - t.cos()).abs())
            .max((v[0] + t.sin()).abs());
    }
    worst
}

/// A method's name, the method at step h, three steps h, the expected order.
type Case = (&'static str, fn(f64) -> Method, [f64; 3], f64);

#[test]
fn each_methods_interpolant_shows_its_order() {
    // (method at step h, steps, the order of the error between the nodes): the method's global
    // order where its interpolant's local error is of that order too (DOP853: 7th-order dense
    // output, local error h⁸; Dormand–Prince: 4th order, h⁵; RK4: cubic Hermite, h⁴; the
    // variational method: 2, its q̇ linear between the nodes).
    let cases: [Case; 4] = [
        (
            "DOP853",
            |_| Method::Dop853 {
                rtol: 1.0,
                atol: 1.0,
            },
            [0.4, 0.3, 0.2],
            8.0,
        ),
        (
            "Dormand–Prince",
            |_| Method::DormandPrince {
                rtol: 1.0,
                atol: 1.0,
            },
            [0.1, 0.05, 0.025],
            5.0,
        ),
        ("RK4", |h| Method::Rk4 { dt: h }, [0.1, 0.05, 0.025], 4.0),
        (
            "variational",
            |h| Method::VariationalMidpoint { dt: h },
            [0.1, 0.05, 0.025],
            2.0,
        ),
    ];
    for (name, method, hs, order) in cases {
        let pts: Vec<(f64, f64)> = hs.iter().map(|&h| (h, midpoint_error(method, h))).collect();
        let p = slope(&pts);
        assert!(
            (p - order).abs() < 0.6,
            "{name}: error between nodes ∝ h^{p:.2}, expected {order}: {pts:?}"
        );
    }
}

#[test]
fn the_memory_bound_keeps_the_first_steps_and_at_says_where_it_stopped() {
    // max_samples(20) of a 1-coordinate run: 20 · 48 bytes. An RK4 step takes 24 + 4 · 16 = 88
    // bytes: 10 steps are kept, up to t = 0.1; the run goes on to its end.
    let tr = osc(Method::Rk4 { dt: 0.01 }, 10.0)
        .sample_every(1.0)
        .max_samples(20)
        .run()
        .unwrap();
    assert_eq!(tr.len(), 11);
    let (start, kept) = tr.dense_span().unwrap();
    assert_eq!(start, 0.0);
    assert!((kept - 0.1).abs() < 1e-15, "kept until {kept}");
    assert!((tr.at(0.05).unwrap().0[0] - 0.05_f64.cos()).abs() < 1e-9);
    let err = tr.at(5.0).unwrap_err();
    assert!(
        matches!(
            err,
            DenseOutputError::Truncated {
                t: 5.0,
                reached: 10.0,
                budget_bytes: 960,
                ..
            }
        ),
        "{err}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains(".max_samples(n)") && msg.contains("t = 10"),
        "{msg}"
    );
    // Beyond the run it is out of range, not truncated.
    assert!(matches!(
        tr.at(10.5),
        Err(DenseOutputError::OutOfRange { .. })
    ));
}

#[test]
fn the_errors_say_what_happened_and_what_to_try() {
    let plain = Simulation::new(&Osc, [1.0], [0.0])
        .until(1.0)
        .run()
        .unwrap();
    let err = plain.at(0.5).unwrap_err();
    assert_eq!(err, DenseOutputError::NotKept);
    assert!(
        err.to_string().contains(".keep_dense_output(true)"),
        "{err}"
    );
    assert_eq!(plain.dense_span(), None);

    let tr = osc(DOP853, 2.0).start_time(1.0).run().unwrap();
    let err = tr.at(f64::NAN).unwrap_err();
    assert_eq!(
        err,
        DenseOutputError::NotANumber {
            start: 1.0,
            end: 2.0
        }
    );
    assert!(
        err.to_string().contains("NaN") && err.to_string().contains("[1, 2]"),
        "{err}"
    );
    for t in [0.5, 2.5, f64::INFINITY, f64::NEG_INFINITY] {
        let err = tr.at(t).unwrap_err();
        assert_eq!(
            err,
            DenseOutputError::OutOfRange {
                t,
                start: 1.0,
                end: 2.0
            }
        );
        assert!(
            err.to_string()
                .contains("outside the run's dense output [1, 2]"),
            "{err}"
        );
    }
    // Debug is the sentence.
    assert_eq!(format!("{err:?}"), err.to_string());
}

#[test]
fn a_terminal_event_ends_the_dense_output_at_the_event() {
    let tr = osc(DOP853, 10.0)
        .event(Event::zero_crossing("x = 0", |_t, q: &[f64; 1], _v| q[0]).terminal())
        .run()
        .unwrap();
    let tz = tr.events[0].t;
    assert!((tz - core::f64::consts::FRAC_PI_2).abs() < 1e-9);
    assert_eq!(tr.dense_span(), Some((0.0, tz)));
    assert_eq!(tr.at(tz).unwrap(), sample(&tr, tr.len() - 1));
    assert!(matches!(
        tr.at(tz + 1e-3),
        Err(DenseOutputError::OutOfRange { .. })
    ));
    assert!((tr.at(1.0).unwrap().0[0] - 1.0_f64.cos()).abs() < 1e-9);
}

#[test]
fn a_failed_runs_partial_trajectory_serves_up_to_its_last_accepted_step() {
    let err = osc(Method::Rk4 { dt: 0.1 }, 10.0)
        .max_steps(5)
        .run()
        .unwrap_err();
    assert!(matches!(err, SimulationError::MaxSteps { .. }));
    let tr = err.partial_trajectory::<1>().unwrap();
    let (start, end) = tr.dense_span().unwrap();
    assert_eq!(start, 0.0);
    assert!((end - 0.5).abs() < 1e-15, "{end}");
    assert_eq!(tr.at(end).unwrap(), sample(tr, tr.len() - 1));
    assert!((tr.at(0.25).unwrap().0[0] - 0.25_f64.cos()).abs() < 1e-6);
}

#[test]
fn constrained_runs_keep_their_dense_output_on_the_projected_nodes() {
    for method in [DOP853, Method::VariationalMidpoint { dt: 1e-3 }] {
        let tr = Simulation::constrained(&Ring, [1.0, 0.0], [0.0, 1.0])
            .method(method)
            .until(3.0)
            .keep_dense_output(true)
            .run()
            .unwrap();
        let tol = if method == DOP853 { 1e-8 } else { 1e-5 };
        for u in uniform(300) {
            let t = 3.0 * u;
            let (q, v) = tr.at(t).unwrap();
            let e = (q[0] - t.cos()).abs().max((q[1] - t.sin()).abs());
            let e = e.max((v[0] + t.sin()).abs()).max((v[1] - t.cos()).abs());
            assert!(e < tol, "{method:?}: error {e:e} at t = {t}");
        }
        // At the nodes, the recorded samples (projected once more, a round-off move).
        for k in 0..tr.len() {
            let (q, v) = tr.at(tr.t[k]).unwrap();
            let d = (0..2)
                .map(|i| (q[i] - tr.q[k][i]).abs().max((v[i] - tr.qdot[k][i]).abs()))
                .fold(0.0_f64, f64::max);
            assert!(d < 1e-14, "{method:?}: node {k} differs by {d:e}");
        }
    }
}

#[test]
fn ensemble_members_in_lanes_keep_the_single_runs_dense_output() {
    let ensemble = |lanes, simd| {
        Ensemble::new(6, |i| {
            Member::new(
                Spring {
                    w: 1.0 + 0.3 * i as f64,
                },
                [1.0],
                [0.0],
            )
        })
        .configure(|sim| {
            sim.method(DOP853)
                .until(4.0)
                .sample_every(1.0)
                .keep_dense_output(true)
        })
        .lanes(lanes)
        .simd(simd)
        .progress(false)
        .run()
    };
    // The exact lanes: every member's single run bit for bit.
    let simd = crate::ensemble::Simd::Exact;
    for lanes in [1, 4] {
        let r = ensemble(lanes, simd);
        for (i, tr) in r.results.iter().enumerate() {
            let tr = tr.as_ref().unwrap();
            let w = 1.0 + 0.3 * i as f64;
            let single = Simulation::new(&Spring { w }, [1.0], [0.0])
                .method(DOP853)
                .until(4.0)
                .sample_every(1.0)
                .keep_dense_output(true)
                .run()
                .unwrap();
            assert_eq!(tr, &single, "member {i}, {lanes} lanes");
            for u in uniform(50) {
                let t = 4.0 * u;
                assert_eq!(tr.at(t).unwrap(), single.at(t).unwrap());
                assert!((tr.at(t).unwrap().0[0] - (w * t).cos()).abs() < 1e-8);
            }
        }
    }
    // The fastest path this CPU has (fused multiply-adds where it has FMA): to round-off.
    let r = ensemble(4, crate::ensemble::Simd::Native);
    for (i, tr) in r.results.iter().enumerate() {
        let tr = tr.as_ref().unwrap();
        let w = 1.0 + 0.3 * i as f64;
        for u in uniform(50) {
            let t = 4.0 * u;
            let (q, _) = tr.at(t).unwrap();
            assert!((q[0] - (w * t).cos()).abs() < 1e-8, "member {i} at {t}");
        }
    }
}
