//! The Taylor method (`Method::Taylor`): its series against an independent power-series
//! evaluation of the heavy top's closed-form equations and against exact series; convergence on
//! the oscillator and Kepler; the heavy top's nutation period (eq. 97) at tight tolerance; dense
//! output and events against DOP853; forces with explicit time; what it refuses, and how.

use lagrange::prelude::*;
use lagrange::{taylor::TaylorBuf, SimulationError};
use lagrange_theory::heavy_top::Constants;

use crate::heavy_top::regimes;
use crate::support::systems::{Chain16, Chain8, HeavyTop, HeavyTopJets, Kepler};
use crate::support::{Kernels, Rng};

/// x'' = −w² x.
pub struct Oscillator {
    pub w: f64,
}

#[lagrangian]
impl Oscillator {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - 0.5 * self.w * self.w * x * x
    }
}

/// A plane pendulum in x, y with its rod as a constraint.
pub struct PendulumXy {
    pub l: f64,
}

#[lagrangian]
impl PendulumXy {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * (x_dot * x_dot + y_dot * y_dot) - 9.81 * y
    }
    fn constraints(&self, (x, _x_dot): Coord, (y, _y_dot): Coord) -> [Scalar; 1] {
        [x * x + y * y - self.l * self.l]
    }
}

/// The damped driven pendulum (forces with explicit time, dissipation).
pub struct Driven {
    pub b: f64,
    pub a: f64,
    pub w: f64,
}

#[lagrangian]
impl Driven {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * theta_dot.powi(2) + theta.cos()
    }
    fn dissipation(&self, (_theta, theta_dot): Coord) -> Scalar {
        0.5 * self.b * theta_dot.powi(2)
    }
    fn forces(&self, (_theta, _theta_dot): Coord, t: Time) -> [Scalar; 1] {
        [self.a * (self.w * t).cos()]
    }
}

/// The generated series through (q, q̇) at t, orders 0..=p.
fn series<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    q: [f64; N],
    qdot: [f64; N],
    t: f64,
    p: usize,
) -> Vec<[[f64; N]; 2]> {
    let mut out = vec![[[0.0; N]; 2]; p + 1];
    out[0] = [q, qdot];
    sys.taylor_series(t, &mut out, &mut TaylorBuf::new())
        .expect("a symbolic system provides its series")
        .expect("the series at a regular state");
    out
}

// A truncated power series arithmetic written here with direct sums (independent of the
// runtime's kernels), for the closed form of the heavy top's equations.
fn ps_mul(a: &[f64], b: &[f64]) -> Vec<f64> {
    (0..a.len())
        .map(|k| (0..=k).map(|j| a[j] * b[k - j]).sum())
        .collect()
}
fn ps_div(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut c = vec![0.0; a.len()];
    for k in 0..a.len() {
        let s: f64 = (1..=k).map(|j| b[j] * c[k - j]).sum();
        c[k] = (a[k] - s) / b[0];
    }
    c
}
fn ps_sin_cos(a: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = a.len();
    let (mut s, mut c) = (vec![0.0; n], vec![0.0; n]);
    (s[0], c[0]) = a[0].sin_cos();
    for k in 1..n {
        let ds: f64 = (1..=k).map(|j| j as f64 * a[j] * c[k - j]).sum();
        let dc: f64 = (1..=k).map(|j| j as f64 * a[j] * s[k - j]).sum();
        s[k] = ds / k as f64;
        c[k] = -dc / k as f64;
    }
    (s, c)
}
fn ps_lin(terms: &[(f64, &[f64])]) -> Vec<f64> {
    let n = terms[0].1.len();
    (0..n)
        .map(|k| terms.iter().map(|(w, x)| w * x[k]).sum())
        .collect()
}

/// The heavy top's series by Picard iteration of the hand-written closed form, order by order
/// (every order recomputes the whole expression: slow and plain).
fn closed_form_series(top: &HeavyTop, q0: [f64; 3], v0: [f64; 3], p: usize) -> Vec<[[f64; 3]; 2]> {
    let (ip, ia, mgl) = (top.i_perp, top.i_par, top.m * top.g * top.l);
    let mut q = vec![vec![0.0; p + 1]; 3];
    let mut v = vec![vec![0.0; p + 1]; 3];
    for i in 0..3 {
        q[i][0] = q0[i];
        v[i][0] = v0[i];
    }
    for k in 0..p {
        let cut = |x: &Vec<f64>| x[..=k].to_vec();
        let (th, thd, phd, psd) = (cut(&q[0]), cut(&v[0]), cut(&v[1]), cut(&v[2]));
        let (s, c) = ps_sin_cos(&th);
        let w3 = ps_lin(&[(1.0, &psd), (1.0, &ps_mul(&phd, &c))]);
        let th_dd = ps_lin(&[
            (1.0, &ps_mul(&ps_mul(&phd, &phd), &ps_mul(&s, &c))),
            (-ia / ip, &ps_mul(&ps_mul(&w3, &phd), &s)),
            (mgl / ip, &s),
        ]);
        let num = ps_lin(&[(ia, &w3), (-2.0 * ip, &ps_mul(&phd, &c))]);
        let ph_dd = ps_div(&ps_mul(&thd, &num), &ps_lin(&[(ip, &s)]));
        let ps_dd = ps_lin(&[
            (1.0, &ps_mul(&ps_mul(&phd, &thd), &s)),
            (-1.0, &ps_mul(&ph_dd, &c)),
        ]);
        for (i, a) in [th_dd, ph_dd, ps_dd].iter().enumerate() {
            q[i][k + 1] = v[i][k] / (k + 1) as f64;
            v[i][k + 1] = a[k] / (k + 1) as f64;
        }
    }
    (0..=p)
        .map(|k| [[q[0][k], q[1][k], q[2][k]], [v[0][k], v[1][k], v[2][k]]])
        .collect()
}

/// Every order of the generated series of the heavy top equals the power-series evaluation of
/// the closed-form equations to 1e-12 relative to that order's largest coefficient (M, f and the
/// order-by-order solve against the explicit accelerations), at orders 0..=20, at 20 states along
/// the motion of each of the six regimes of tests/heavy_top.rs and at random tops and states
/// whose series converge beyond τ = 0.3 (where the recurrences' round-off, amplified ~10⁴ when
/// coefficients grow tenfold per order, would make the two f64 evaluations disagree by more).
#[test]
fn heavy_top_series_equals_the_closed_form_power_series_order_by_order() {
    let p = 20;
    let check = |top: &HeavyTop, q: [f64; 3], v: [f64; 3], what: &str| {
        let ours = series(top, q, v, 0.0, p);
        let reference = closed_form_series(top, q, v, p);
        for k in 0..=p {
            let scale = reference[k]
                .iter()
                .flatten()
                .fold(0.0_f64, |m, x| m.max(x.abs()));
            for (a, b) in ours[k].iter().flatten().zip(reference[k].iter().flatten()) {
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "{what}, order {k}: {a:e} vs {b:e} (order scale {scale:e})"
                );
            }
        }
    };
    for r in regimes() {
        let tr = Simulation::new(&r.top, r.q0, r.qdot0)
            .method(Method::Dop853 {
                rtol: 1e-10,
                atol: 1e-12,
            })
            .until(10.0)
            .sample_every(0.5)
            .run()
            .unwrap();
        for (i, (q, v)) in tr.q.iter().zip(&tr.qdot).enumerate() {
            check(&r.top, *q, *v, &format!("{} sample {i}", r.name));
        }
    }
    let mut rng = Rng(0x7a71_0e5e);
    let mut checked = 0;
    while checked < 40 {
        let top = HeavyTop {
            i_perp: rng.uniform(0.2, 3.0),
            i_par: rng.uniform(0.1, 3.0),
            m: rng.uniform(0.1, 2.0),
            g: 9.81,
            l: rng.uniform(0.05, 1.0),
        };
        let q = [
            rng.uniform(0.2, 2.9),
            rng.uniform(-7.0, 7.0),
            rng.uniform(-7.0, 7.0),
        ];
        let v = [
            rng.uniform(-3.0, 3.0),
            rng.uniform(-3.0, 3.0),
            rng.uniform(-10.0, 10.0),
        ];
        // The radius of convergence from the last coefficients, as the step size control sees it.
        let s = closed_form_series(&top, q, v, p);
        let norm = |k: usize| s[k].iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
        if (norm(0).max(1.0) / norm(p)).powf(1.0 / p as f64) < 0.3 {
            continue;
        }
        check(
            &top,
            q,
            v,
            &format!("random top {checked}: {top:?} {q:?} {v:?}"),
        );
        checked += 1;
    }
}

/// x = x₀ cos wτ + (v₀/w) sin wτ: the exact series, every order to 1e-15 relative.
#[test]
fn oscillator_series_is_the_exact_series() {
    let osc = Oscillator { w: 1.7 };
    let (x0, v0) = (0.8, -0.3);
    let s = series(&osc, [x0], [v0], 0.0, 25);
    let mut fact = 1.0;
    for (k, y) in s.iter().enumerate() {
        if k > 0 {
            fact *= k as f64;
        }
        let wk = osc.w.powi(k as i32);
        // d^k/dτ^k of cos and sin at 0.
        let (dc, ds) = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][k % 4];
        let exact = (x0 * dc + v0 / osc.w * ds) * wk / fact;
        assert!(
            (y[0][0] - exact).abs() <= 1e-15 * exact.abs().max(wk / fact),
            "order {k}: {} vs {exact}",
            y[0][0]
        );
    }
}

/// A series of order 1 is the state and its derivative; an output shorter than 2 is left alone.
#[test]
fn short_outputs() {
    let osc = Oscillator { w: 2.0 };
    let s = series(&osc, [1.0], [0.5], 0.0, 1);
    assert_eq!(s, vec![[[1.0], [0.5]], [[0.5], [-4.0]]]);
    let mut one = [[[1.0], [0.5]]];
    assert!(matches!(
        osc.taylor_series(0.0, &mut one, &mut TaylorBuf::new()),
        Some(Ok(()))
    ));
    assert_eq!(one, [[[1.0], [0.5]]]);
}

/// One buffer shared by two systems of different layouts gives each its own series.
#[test]
fn a_buffer_shared_between_systems() {
    let (osc, top) = (Oscillator { w: 1.3 }, regimes()[0].top);
    let mut buf = TaylorBuf::new();
    let mut a = vec![[[0.0; 3]; 2]; 12];
    a[0] = [[0.9, 0.1, 0.2], [0.3, 1.0, 5.0]];
    top.taylor_series(0.0, &mut a, &mut buf).unwrap().unwrap();
    let mut b = vec![[[0.0; 1]; 2]; 12];
    b[0] = [[1.0], [0.0]];
    osc.taylor_series(0.0, &mut b, &mut buf).unwrap().unwrap();
    assert_eq!(b, series(&osc, [1.0], [0.0], 0.0, 11));
    top.taylor_series(0.0, &mut a, &mut buf).unwrap().unwrap();
    assert_eq!(a, series(&top, [0.9, 0.1, 0.2], [0.3, 1.0, 5.0], 0.0, 11));
}

fn oscillator_error(tol: f64) -> (f64, usize) {
    let osc = Oscillator { w: 1.0 };
    let t_end = 50.0;
    let tr = Simulation::new(&osc, [1.0], [0.0])
        .method(Method::Taylor { tol })
        .until(t_end)
        .run()
        .unwrap();
    let q = tr.q.last().unwrap()[0];
    ((q - t_end.cos()).abs(), tr.stats.steps)
}

/// Kepler ellipse e = 0.5, a = 1 from perihelion; after one period 2π the state returns.
fn kepler_error(tol: f64) -> (f64, usize) {
    let k = Kepler { m: 1.0, k: 1.0 };
    let tr = Simulation::new(&k, [0.5, 0.0], [0.0, 2.0 * 3.0_f64.sqrt()])
        .method(Method::Taylor { tol })
        .until(2.0 * std::f64::consts::PI)
        .run()
        .unwrap();
    let (q, v) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
    let err = (q[0] - 0.5)
        .abs()
        .max((q[1] - 2.0 * std::f64::consts::PI).abs())
        .max(v[0].abs())
        .max((v[1] - 2.0 * 3.0_f64.sqrt()).abs());
    (err, tr.stats.steps)
}

/// Least-squares slope of log y against log x.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for &(x, y) in points {
        let (x, y) = (x.ln(), y.ln());
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    (n * sxy - sx * sy) / (n * sxx - sx * sx)
}

/// The global error follows the tolerance (error ∝ tol: the log-log slope over tol = 1e-6 …
/// 1e-12 is about one, every error within 1000 tol), while the number of steps barely grows (the
/// order does); at tol 1e-16 the error is at round-off.
#[test]
fn error_is_proportional_to_the_tolerance() {
    for (name, run) in [
        ("oscillator", oscillator_error as fn(f64) -> (f64, usize)),
        ("kepler", kepler_error),
    ] {
        let tols = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12];
        let runs: Vec<(f64, usize)> = tols.iter().map(|&t| run(t)).collect();
        for (tol, (err, _)) in tols.iter().zip(&runs) {
            assert!(*err < 1e3 * tol, "{name}: tol {tol:e}: error {err:e}");
        }
        let points: Vec<(f64, f64)> = tols.iter().zip(&runs).map(|(&t, &(e, _))| (t, e)).collect();
        let p = slope(&points);
        assert!((0.8..=1.5).contains(&p), "{name}: slope {p} ({runs:?})");
        let (s0, s1) = (runs[0].1, runs[6].1);
        assert!(s1 < 2 * s0, "{name}: steps {s0} → {s1}");
        let (err, _) = run(1e-16);
        assert!(err < 1e-12, "{name}: error {err:e} at tol 1e-16");
    }
}

/// Eq. 97: the measured nutation period of the six regimes of tests/heavy_top.rs, Taylor at
/// tol 1e-15, equals the theory to 1e-12 (relative).
#[test]
fn heavy_top_nutation_period_against_eq_97() {
    for r in regimes() {
        let c = Constants::from_state(&r.top.theory(), &r.q0, &r.qdot0).unwrap();
        let t = c.nutation.period().unwrap();
        let tr = Simulation::new(&r.top, r.q0, r.qdot0)
            .method(Method::Taylor { tol: 1e-15 })
            .until(10.3 * t)
            .keep_samples(false)
            .event(Event::zero_crossing("low", |_t, _q, v: &[f64; 3]| v[0]).falling())
            .run()
            .unwrap();
        let lows: Vec<f64> = tr.events.iter().map(|e| e.t).collect();
        assert!(lows.len() >= 10, "{}: {} lows", r.name, lows.len());
        let measured = (lows[lows.len() - 1] - lows[0]) / (lows.len() - 1) as f64;
        assert!(
            ((measured - t) / t).abs() < 1e-12,
            "{}: period {measured} vs eq. 97 {t}",
            r.name
        );
        let inv = tr.invariants();
        let energy = inv.energy.expect("the top conserves its energy");
        assert!(energy.max_rel < 1e-13, "{}: {energy:?}", r.name);
    }
}

/// Samples (the Taylor polynomial as dense output) and located events equal DOP853's at tight
/// tolerances.
#[test]
fn dense_output_and_events_against_dop853() {
    let r = regimes()[1];
    let run = |m: Method| {
        Simulation::new(&r.top, r.q0, r.qdot0)
            .method(m)
            .until(20.0)
            .sample_every(0.01)
            .event(Event::zero_crossing("theta max", |_t, _q, v: &[f64; 3]| v[0]).falling())
            .event(Event::zero_crossing(
                "phi dot = 0",
                |_t, _q, v: &[f64; 3]| v[1],
            ))
            .run()
            .unwrap()
    };
    let a = run(Method::Taylor { tol: 1e-15 });
    let b = run(Method::Dop853 {
        rtol: 1e-14,
        atol: 1e-16,
    });
    assert_eq!(a.t, b.t);
    for (x, y) in a.q.iter().zip(&b.q).chain(a.qdot.iter().zip(&b.qdot)) {
        for i in 0..3 {
            assert!(
                (x[i] - y[i]).abs() < 1e-10 * (1.0 + y[i].abs()),
                "{x:?} vs {y:?}"
            );
        }
    }
    assert_eq!(a.events.len(), b.events.len());
    assert!(a.events.len() > 5);
    for (x, y) in a.events.iter().zip(&b.events) {
        assert_eq!(x.name, y.name);
        assert!((x.t - y.t).abs() < 1e-10, "{}: {} vs {}", x.name, x.t, y.t);
    }
}

/// `Trajectory::at` on a Taylor run is the step's series: the exact motion to the tolerance at
/// random times (the error follows the tolerance), the recorded samples bit for bit at the
/// nodes and between them, and the same in an ensemble's lanes as in a single run.
#[test]
fn dense_output_kept_is_the_series_of_each_step() {
    let osc = Oscillator { w: 1.0 };
    let run = |tol: f64| {
        Simulation::new(&osc, [1.0], [0.0])
            .method(Method::Taylor { tol })
            .until(20.0)
            .keep_dense_output(true)
    };
    let mut rng = Rng(11);
    let times: Vec<f64> = (0..1000).map(|_| rng.uniform(0.0, 20.0)).collect();
    let worst = |tr: &Trajectory<1>| {
        times.iter().fold(0.0_f64, |m, &t| {
            let (q, v) = tr.at(t).unwrap();
            m.max((q[0] - t.cos()).abs()).max((v[0] + t.sin()).abs())
        })
    };
    let (loose, tight) = (run(1e-8).run().unwrap(), run(1e-14).run().unwrap());
    let (e8, e14) = (worst(&loose), worst(&tight));
    assert!(
        e8 < 1e-6 && e14 < 1e-11 && e14 < 1e-4 * e8,
        "{e8:e} {e14:e}"
    );
    for k in 0..tight.len() {
        assert_eq!(tight.at(tight.t[k]).unwrap(), (tight.q[k], tight.qdot[k]));
    }
    let mut inside: Vec<f64> = times.iter().copied().filter(|&t| t > 0.0).collect();
    inside.sort_by(f64::total_cmp);
    let sampled = run(1e-14).sample_at(inside).run().unwrap();
    for k in 0..sampled.len() {
        assert_eq!(
            sampled.at(sampled.t[k]).unwrap(),
            (sampled.q[k], sampled.qdot[k])
        );
    }
    // Members in lanes keep the single run's dense output.
    let members = Ensemble::new(5, |i| {
        Member::new(
            Oscillator {
                w: 1.0 + 0.2 * i as f64,
            },
            [1.0],
            [0.0],
        )
    })
    .configure(|sim| {
        sim.method(Method::Taylor { tol: 1e-14 })
            .until(20.0)
            .keep_dense_output(true)
    })
    .lanes(4)
    .progress(false)
    .run();
    for (i, tr) in members.results.iter().enumerate() {
        let o = Oscillator {
            w: 1.0 + 0.2 * i as f64,
        };
        let single = Simulation::new(&o, [1.0], [0.0])
            .method(Method::Taylor { tol: 1e-14 })
            .until(20.0)
            .keep_dense_output(true)
            .run()
            .unwrap();
        let tr = tr.as_ref().unwrap();
        assert_eq!(tr, &single, "member {i}");
        for &t in &times[..50] {
            assert_eq!(tr.at(t).unwrap(), single.at(t).unwrap());
        }
    }
}

/// Forces with explicit time and dissipation are part of the series: the driven pendulum agrees
/// with DOP853, and its work balance closes.
#[test]
fn forces_and_time_against_dop853() {
    let p = Driven {
        b: 0.3,
        a: 1.2,
        w: 2.0 / 3.0,
    };
    let run = |m: Method| {
        Simulation::new(&p, [0.2], [0.0])
            .method(m)
            .start_time(0.7)
            .until(40.0)
            .run()
            .unwrap()
    };
    let a = run(Method::Taylor { tol: 1e-15 });
    let b = run(Method::Dop853 {
        rtol: 1e-14,
        atol: 1e-16,
    });
    let (x, y) = (a.q.last().unwrap()[0], b.q.last().unwrap()[0]);
    assert!((x - y).abs() < 1e-9, "{x} vs {y}");
    let (x, y) = (a.qdot.last().unwrap()[0], b.qdot.last().unwrap()[0]);
    assert!((x - y).abs() < 1e-9, "{x} vs {y}");
    // A random state's series against the one-step definition: q̈ of order 0 is the accelerations.
    let mut rng = Rng(5);
    for _ in 0..20 {
        let (q, v, t) = (
            rng.uniform(-3.0, 3.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-9.0, 9.0),
        );
        let s = series(&p, [q], [v], t, 3);
        let acc = p.accelerations(&[q], &[v], t).unwrap()[0];
        assert!((2.0 * s[2][0][0] - acc).abs() < 1e-14 * (1.0 + acc.abs()));
        // d/dt of the acceleration: −cos θ θ̇ − b θ̈ − a w sin(w t).
        let jerk = -q.cos() * v - p.b * acc - p.a * p.w * (p.w * t).sin();
        assert!((6.0 * s[3][0][0] - jerk).abs() < 1e-13 * (1.0 + jerk.abs()));
    }
}

/// `err` is `InvalidOptions` whose message says `what`.
fn assert_invalid_options(err: &SimulationError, what: &str) {
    match err {
        SimulationError::InvalidOptions { message } => {
            assert!(message.contains(what), "{message}");
        }
        e => panic!("{e:?}"),
    }
}

/// What the method refuses: a jets-mode system (no series), a tolerance out of range, a
/// constrained run; a singular mass matrix is the usual typed error.
#[test]
fn refusals_are_typed_errors() {
    let r = regimes()[0];
    let jets: HeavyTopJets = r.top.jets();
    let err = Simulation::new(&jets, r.q0, r.qdot0)
        .method(Method::Taylor { tol: 1e-10 })
        .until(1.0)
        .run()
        .unwrap_err();
    assert_invalid_options(&err, "symbolic");
    // Past 1024 series (a 16-link chain) the series are not generated (build time); 8 links are.
    let c16 = Chain16 {
        m: 1.0,
        l: 1.0,
        g: 9.81,
    };
    let err = Simulation::new(&c16, [0.1; 16], [0.0; 16])
        .method(Method::Taylor { tol: 1e-10 })
        .until(1.0)
        .run()
        .unwrap_err();
    assert_invalid_options(&err, "1024");
    let c8 = Chain8 {
        m: 1.0,
        l: 1.0,
        g: 9.81,
    };
    let a = Simulation::new(&c8, [0.1; 8], [0.0; 8])
        .method(Method::Taylor { tol: 1e-12 })
        .until(1.0)
        .run()
        .unwrap();
    let b = Simulation::new(&c8, [0.1; 8], [0.0; 8])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(1.0)
        .run()
        .unwrap();
    let (x, y) = (a.q.last().unwrap(), b.q.last().unwrap());
    assert!(
        x.iter().zip(y).all(|(p, q)| (p - q).abs() < 1e-9),
        "{x:?} vs {y:?}"
    );
    for tol in [0.0, 1e-27, 1.0, f64::NAN, -1e-8] {
        let err = Simulation::new(&r.top, r.q0, r.qdot0)
            .method(Method::Taylor { tol })
            .until(1.0)
            .run()
            .unwrap_err();
        assert!(
            matches!(err, SimulationError::InvalidOptions { .. }),
            "{tol}: {err:?}"
        );
    }
    let err = Simulation::constrained(&PendulumXy { l: 1.0 }, [1.0, 0.0], [0.0, 0.5])
        .method(Method::Taylor { tol: 1e-10 })
        .until(1.0)
        .run()
        .unwrap_err();
    assert_invalid_options(&err, "constraints");
    let err = Simulation::new(&r.top, [0.0, 0.0, 0.0], [0.0, 1.0, 2.0])
        .method(Method::Taylor { tol: 1e-10 })
        .until(1.0)
        .run()
        .unwrap_err();
    match &err {
        SimulationError::Dynamics { source, .. } => assert!(
            matches!(**source, DynamicsError::SingularMassMatrix { .. }),
            "{source:?}"
        ),
        e => panic!("{e:?}"),
    }
}
