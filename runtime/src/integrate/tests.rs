//! Unit tests of the single steps and interpolants: convergence orders with fixed steps.

use super::dop853::Dop853;
use super::dopri5::Dopri5;
use super::explicit::{Counted, Tableau, attempt};
use super::problem::Plain;
use super::rk4::Rk4;
use super::state::Stats;
use super::state::Y;
use crate::lagrangian::Lagrangian;
use crate::scalar::Scalar;

/// x'' = −x: x = cos t from (1, 0) (also the dense output's tests' oscillator).
pub(super) struct Osc;
impl Lagrangian<1> for Osc {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        (v[0] * v[0] - q[0] * q[0]) * 0.5
    }
}

/// Kepler problem (GM = 1) in Cartesian coordinates.
struct Kepler;
impl Lagrangian<2> for Kepler {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [false, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 + S::constant(1.0) / (q[0] * q[0] + q[1] * q[1]).sqrt()
    }
}

/// Kepler ellipse with e = 0.5, a = 1 from perihelion: period 2π.
fn kepler_start() -> Y<2> {
    [[0.5, 0.0], [0.0, 3.0_f64.sqrt()]]
}

/// Least-squares slope of ln e against ln h (an order of convergence).
pub(super) fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for &(h, e) in points {
        let (x, y) = (h.ln(), e.ln());
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    (n * sxy - sx * sy) / (n * sxx - sx * sx)
}

fn dist<const N: usize>(a: &Y<N>, b: &Y<N>) -> f64 {
    let mut m = 0.0_f64;
    for c in 0..2 {
        for i in 0..N {
            m = m.max((a[c][i] - b[c][i]).abs());
        }
    }
    m
}

/// One step of the tableau T of size h from (t, y) with f = F(t, y): y₁, ln err for the
/// tolerances `tol`, and the stages.
#[allow(clippy::too_many_arguments)]
fn tab_step<T: Tableau, L: Lagrangian<N>, const N: usize>(
    sys: &L,
    t: f64,
    y: &Y<N>,
    f: &Y<N>,
    h: f64,
    tol: (f64, f64),
    stats: &mut Stats,
) -> (Y<N>, f64, [Y<N>; 16]) {
    let p = Plain { sys };
    let mut k = [*f; 16];
    let (mut arg, mut y1) = (*y, *y);
    let mut c = Counted { p: &p, stats };
    let ln_err =
        attempt::<T, _, _, N>(&mut c, L::CYCLIC, t, y, &mut k, h, tol, &mut arg, &mut y1).unwrap();
    (y1, ln_err, k)
}

/// One step of T on the oscillator and its dense output at θ: (y₁, the output).
fn tab_dense<T: Tableau>(
    t0: f64,
    y0: &Y<1>,
    f0: &Y<1>,
    h: f64,
    th: f64,
    stats: &mut Stats,
) -> (Y<1>, Y<1>) {
    let (y1, _, mut k) = tab_step::<T, _, 1>(&Osc, t0, y0, f0, h, (1e-6, 1e-6), stats);
    k[T::STAGES] = super::state::rhs(&Osc, t0 + h, &y1, stats).unwrap();
    let p = Plain { sys: &Osc };
    let mut rows = [*y0; 8];
    let step = super::explicit::Step {
        cyclic: [false],
        t: t0,
        h,
        x: y0,
        x1: &y1,
        k: &mut k,
    };
    T::dense(&mut Counted { p: &p, stats }, step, &mut rows).unwrap();
    let mut out = *y0;
    T::eval(&rows, h, th, &mut out);
    (y1, out)
}

/// Integrates over one Kepler period with n fixed steps of the given single-step method.
fn kepler_period<F>(n: usize, mut step: F) -> f64
where
    F: FnMut(f64, &Y<2>, &Y<2>, f64, &mut Stats) -> Y<2>,
{
    let mut stats = Stats::default();
    let h = 2.0 * core::f64::consts::PI / n as f64;
    let mut y = kepler_start();
    for k in 0..n {
        let t = k as f64 * h;
        let f = super::state::rhs(&Kepler, t, &y, &mut stats).unwrap();
        y = step(t, &y, &f, h, &mut stats);
    }
    dist(&y, &kepler_start())
}

#[test]
fn rk4_fixed_step_is_order_4_on_kepler() {
    let pts: Vec<_> = [400, 800, 1600]
        .iter()
        .map(|&n| {
            let e = kepler_period(n, |t, y, f, h, s| {
                tab_step::<Rk4, _, 2>(&Kepler, t, y, f, h, (0.0, 0.0), s).0
            });
            (1.0 / n as f64, e)
        })
        .collect();
    let p = slope(&pts);
    assert!((p - 4.0).abs() < 0.2, "order {p}, points {pts:?}");
}

#[test]
fn dopri5_fixed_step_is_order_5_on_kepler() {
    let pts: Vec<_> = [200, 400, 800]
        .iter()
        .map(|&n| {
            let e = kepler_period(n, |t, y, f, h, s| {
                tab_step::<Dopri5, _, 2>(&Kepler, t, y, f, h, (1e-6, 1e-6), s).0
            });
            (1.0 / n as f64, e)
        })
        .collect();
    let p = slope(&pts);
    assert!((p - 5.0).abs() < 0.25, "order {p}, points {pts:?}");
}

#[test]
fn dop853_fixed_step_is_order_8_on_kepler() {
    let pts: Vec<_> = [160, 200, 250]
        .iter()
        .map(|&n| {
            let e = kepler_period(n, |t, y, f, h, s| {
                tab_step::<Dop853, _, 2>(&Kepler, t, y, f, h, (1e-6, 1e-6), s).0
            });
            (1.0 / n as f64, e)
        })
        .collect();
    let p = slope(&pts);
    assert!((p - 8.0).abs() < 0.4, "order {p}, points {pts:?}");
}

/// Local error of the interpolant at θ = 0.37 on the oscillator: O(h^(p+1)) for dense order p.
fn dense_local_error(h: f64, which: &str) -> f64 {
    let mut stats = Stats::default();
    let (t0, y0) = (0.3, [[0.3_f64.cos()], [-(0.3_f64.sin())]]);
    let f0 = super::state::rhs(&Osc, t0, &y0, &mut stats).unwrap();
    let th = 0.37;
    let got = match which {
        "dopri5" => tab_dense::<Dopri5>(t0, &y0, &f0, h, th, &mut stats).1,
        _ => tab_dense::<Dop853>(t0, &y0, &f0, h, th, &mut stats).1,
    };
    let t = t0 + th * h;
    dist(&got, &[[t.cos()], [-t.sin()]])
}

#[test]
fn dopri5_dense_output_is_order_4() {
    let pts: Vec<_> = [0.4, 0.2, 0.1]
        .iter()
        .map(|&h| (h, dense_local_error(h, "dopri5")))
        .collect();
    let p = slope(&pts) - 1.0;
    assert!((p - 4.0).abs() < 0.3, "order {p}, points {pts:?}");
}

#[test]
fn dop853_dense_output_is_order_7() {
    let pts: Vec<_> = [0.8, 0.4, 0.2]
        .iter()
        .map(|&h| (h, dense_local_error(h, "dop853")))
        .collect();
    let p = slope(&pts) - 1.0;
    assert!((p - 7.0).abs() < 0.4, "order {p}, points {pts:?}");
}

#[test]
fn dense_outputs_hit_both_ends_exactly() {
    let mut stats = Stats::default();
    let y0 = [[1.0], [0.2]];
    let f0 = super::state::rhs(&Osc, 0.0, &y0, &mut stats).unwrap();
    let (y1, at0) = tab_dense::<Dopri5>(0.0, &y0, &f0, 0.3, 0.0, &mut stats);
    let (_, at1) = tab_dense::<Dopri5>(0.0, &y0, &f0, 0.3, 1.0, &mut stats);
    assert!(dist(&at0, &y0) < 1e-15);
    assert!(dist(&at1, &y1) < 1e-15);
}

#[test]
fn dop853_error_estimate_scales_like_h8() {
    // The blended estimate err ~ |h|·err5²/sqrt(err5² + 0.01 err3²) behaves like h^8 for small h.
    let mut stats = Stats::default();
    let y0 = kepler_start();
    let f0 = super::state::rhs(&Kepler, 0.0, &y0, &mut stats).unwrap();
    let pts: Vec<_> = [0.08, 0.04, 0.02]
        .iter()
        .map(|&h| {
            let (_, ln_err, _) =
                tab_step::<Dop853, _, 2>(&Kepler, 0.0, &y0, &f0, h, (0.0, 1e-6), &mut stats);
            (h, ln_err.exp())
        })
        .collect();
    let p = slope(&pts);
    assert!(p > 6.5 && p < 9.5, "estimate order {p}, {pts:?}");
}

/// The default `max_samples` is a memory budget (256 MiB at (3N + 3) · 8 bytes per sample), not
/// 10⁸ (919 MB for every step of a 10⁷-step top): a grid of 10⁷ samples of x'' = −x is refused
/// before any step, and the message says the bound is the default and what a sample takes.
#[test]
fn default_max_samples_is_a_memory_budget() {
    use crate::integrate::{Simulation, SimulationError};
    assert_eq!(super::trajectory::sample_bytes(1, 0), 48);
    assert_eq!(super::trajectory::sample_bytes(32, 0), 99 * 8);
    assert_eq!(super::trajectory::sample_bytes(2, 1), 72 + 32);
    let sim = Simulation::new(&Osc, [1.0], [0.0]).until(1.0);
    assert_eq!(sim.o.max_samples_bound(), (256 << 20) / 48);
    let err = sim.sample_every(1e-7).run().unwrap_err();
    assert!(
        matches!(err, SimulationError::InvalidOptions { .. }),
        "{err}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("the default: a 256 MiB budget") && msg.contains("48 bytes per sample"),
        "{msg}"
    );
}

/// Both `max_samples` messages, before the run (a sample grid) and during it (every step), give
/// the same bytes per sample, computed by one function.
#[test]
fn max_samples_messages_agree_on_bytes_per_sample() {
    use crate::integrate::{Method, Simulation, SimulationError};
    let before = Simulation::new(&Kepler, kepler_start()[0], kepler_start()[1])
        .until(1.0)
        .sample_every(0.01)
        .max_samples(5)
        .run()
        .unwrap_err();
    let during = Simulation::new(&Kepler, kepler_start()[0], kepler_start()[1])
        .method(Method::Rk4 { dt: 0.01 })
        .until(1.0)
        .max_samples(5)
        .run()
        .unwrap_err();
    assert!(
        matches!(
            during,
            SimulationError::MaxSamples {
                sample_bytes: 72,
                default_limit: false,
                ..
            }
        ),
        "{during}"
    );
    for e in [before.to_string(), during.to_string()] {
        assert!(
            e.contains("max_samples = 5 (at 72 bytes per sample)"),
            "{e}"
        );
    }
}

/// `max_samples(1).keep_samples(false)` runs: streaming keeps two samples, so the bound on
/// stored samples does not apply (it failed at the second sample, and a grid of 101 samples was
/// refused before the run).
#[test]
fn max_samples_does_not_bound_a_run_that_keeps_no_samples() {
    use crate::integrate::{Method, Simulation};
    let mut seen = 0;
    let tr = Simulation::new(&Osc, [1.0], [0.0])
        .method(Method::Rk4 { dt: 0.1 })
        .until(1.0)
        .max_samples(1)
        .keep_samples(false)
        .observe(|_| seen += 1)
        .run()
        .unwrap();
    assert_eq!((tr.t.len(), seen), (2, 11));
    let tr = Simulation::new(&Osc, [1.0], [0.0])
        .until(1.0)
        .sample_every(0.01)
        .max_samples(1)
        .keep_samples(false)
        .run()
        .unwrap();
    assert_eq!(tr.t, vec![0.0, 1.0]);
}

/// A full disk (ENOSPC, /dev/full) while writing the samples gives an error that names the path
/// (the writes and the flush returned the bare OS error).
#[cfg(target_os = "linux")]
#[test]
fn write_csv_names_the_path_on_a_full_disk() {
    use crate::integrate::{Method, Simulation};
    let tr = Simulation::new(&Osc, [1.0], [0.0])
        .method(Method::Rk4 { dt: 0.1 })
        .until(1.0)
        .run()
        .unwrap();
    let e = tr.write_csv("/dev/full").unwrap_err();
    assert!(e.to_string().contains("/dev/full"), "{e}");
}

/// A free particle pushed by a force of 1e150 (and 1e153): the initial step estimate squared
/// (1e150 / 1e-10)² = ∞ and started at h = 0, a StepSizeUnderflow at t = 0. Now x(1) = F/2.
#[test]
fn a_huge_force_does_not_underflow_the_initial_step() {
    use crate::integrate::Simulation;
    struct Pushed(f64);
    impl Lagrangian<1> for Pushed {
        const COORDINATES: [&'static str; 1] = ["x"];
        const CYCLIC: [bool; 1] = [true];
        const AUTONOMOUS: bool = true;
        const MOMENTUM_CONSERVED: [bool; 1] = [false];
        const ENERGY_CONSERVED: bool = false;
        fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
            v[0] * v[0] * 0.5
        }
        fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], _t: S) -> [S; 1] {
            [S::constant(self.0)]
        }
    }
    for f in [1e150, 1e153] {
        let tr = Simulation::new(&Pushed(f), [0.0], [0.0])
            .until(1.0)
            .run()
            .unwrap_or_else(|e| panic!("F = {f:e}: {e}"));
        let x = tr.q[tr.q.len() - 1][0];
        assert!((x / (0.5 * f) - 1.0).abs() < 1e-12, "F = {f:e}: x = {x:e}");
    }
}

/// A failed projection onto the constraints (a blown-up projected DOP853 run) names the
/// projection, not "the variational integrator's Newton solve"; the variational one still does.
#[test]
fn a_failed_projection_names_the_projection() {
    use crate::integrate::SimulationError;
    let err = |reason| SimulationError::NewtonFailed {
        t: 1.0,
        q: vec![0.0],
        qdot: vec![0.0],
        iterations: 8,
        residual: 1.0,
        reason,
        partial: super::error::PartialTrajectory::none(),
    };
    let m = err("projecting the state back onto the constraints g(q, t) = 0 did not converge")
        .to_string();
    assert!(
        m.starts_with("the projection onto the constraints failed"),
        "{m}"
    );
    assert!(!m.contains("variational"), "{m}");
    let m = err("projecting onto the constraints: their gradients are dependent").to_string();
    assert!(
        m.starts_with("the projection onto the constraints failed"),
        "{m}"
    );
    let m = err("the midpoint equations did not converge").to_string();
    assert!(
        m.starts_with("the variational integrator's Newton solve"),
        "{m}"
    );
}

/// x'' = −x with a force (or a damping) that turns NaN after t = 0.5.
struct Poisoned {
    in_forces: bool,
}
impl Lagrangian<1> for Poisoned {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    const ENERGY_CONSERVED: bool = false;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        (v[0] * v[0] - q[0] * q[0]) * 0.5
    }
    fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], t: S) -> [S; 1] {
        let bad = self.in_forces && t.value() > 0.5;
        [S::constant(if bad { f64::NAN } else { 0.0 })]
    }
    fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], t: S) -> S {
        let bad = !self.in_forces && t.value() > 0.5;
        v[0] * v[0] * if bad { f64::NAN } else { 0.1 }
    }
}

/// A NaN generalized force is reported as coming from `fn forces`, a NaN dissipation from
/// `fn dissipation` (both were "the derivatives of L are not finite").
#[test]
fn a_non_finite_force_names_where_it_comes_from() {
    use crate::integrate::{Method, Simulation, SimulationError};
    for (in_forces, name) in [(true, "`fn forces`"), (false, "`fn dissipation`")] {
        for method in [
            Method::Rk4 { dt: 0.1 },
            Method::Dop853 {
                rtol: 1e-10,
                atol: 1e-12,
            },
        ] {
            let sys = Poisoned { in_forces };
            let err = Simulation::new(&sys, [1.0], [0.0])
                .method(method)
                .until(1.0)
                .run()
                .unwrap_err();
            assert!(matches!(err, SimulationError::Dynamics { .. }), "{err}");
            let m = err.to_string();
            assert!(m.contains(name) && !m.contains("derivatives of L"), "{m}");
        }
    }
}

/// The Taylor method checks the time resolution as the fixed steps do: at t0 = 1e9 a run of
/// 1e-5 cannot be cut into steps, and tol = 1e-12 is far below the rounding of each step's end
/// time (1.2e-7 apart); both are InvalidOptions that say to shift the time origin. t0 = 0.7 to
/// 40 with tol 1e-15 (the driven pendulum's test) and t0 = 1e9 with tol 1e-6 still run.
#[test]
fn taylor_checks_the_time_resolution() {
    use crate::integrate::{Method, Simulation, SimulationError};
    let check = |t0: f64, until: f64, tol: f64| {
        let sim = Simulation::new(&Osc, [1.0], [0.0])
            .method(Method::Taylor { tol })
            .start_time(t0)
            .until(until);
        sim.o.validate(&Osc)
    };
    // A long run from t = 0 (10⁵ periods of a top at tol 1e-16) is told to cut itself into
    // segments short enough for its tol, not to shift an origin that is already 0.
    let m = check(0.0, 1.143e5, 1e-16).unwrap_err();
    assert!(
        m.contains("time resolution") && m.contains("Cut the run into segments of at most 9.0e2"),
        "{m}"
    );
    for (t0, until, tol) in [(1e9, 1e9 + 1e-5, 1e-6), (1e9, 1e9 + 10.0, 1e-12)] {
        let m = check(t0, until, tol).unwrap_err();
        assert!(
            m.contains("time resolution") && m.contains("Shift the time origin"),
            "{m}"
        );
        let e = Simulation::new(&Osc, [1.0], [0.0])
            .method(Method::Taylor { tol })
            .start_time(t0)
            .until(until)
            .run()
            .unwrap_err();
        assert!(matches!(e, SimulationError::InvalidOptions { .. }), "{e}");
    }
    for (t0, until, tol) in [
        (0.7, 40.0, 1e-15),
        (1e9, 1e9 + 10.0, 1e-6),
        (0.0, 1e3, 1e-15),
    ] {
        if let Err(m) = check(t0, until, tol) {
            assert!(
                !m.contains("time resolution"),
                "[{t0}, {until}] tol {tol:e}: {m}"
            );
        }
    }
}

/// Two unit masses on a line: a soft spring k₁ = 1 to the wall and a stiff one k₂ = 1e8 between
/// them (ω² ≈ 2·10⁸ and ≈ 1/2: a stiffness ratio of 2·10⁴).
struct StiffPair;

impl Lagrangian<2> for StiffPair {
    const COORDINATES: [&'static str; 2] = ["x1", "x2"];
    const CYCLIC: [bool; 2] = [false, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        let d = q[1] - q[0];
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[0] * q[0] * 0.5 - d * d * 0.5e8
    }
}

#[test]
fn stiffness_is_diagnosed_where_it_stops_a_run() {
    use crate::integrate::{Method, Simulation, SimulationError, Stiffness};
    let fast = (2e8_f64 + 0.5).sqrt();
    // DOP853 out of steps on the stiff pair: the error names the fast mode and the implicit
    // method, and does not advise looser tolerances.
    let err = Simulation::new(&StiffPair, [1.0, 1.0], [0.0, 0.0])
        .method(Method::Dop853 {
            rtol: 1e-8,
            atol: 1e-10,
        })
        .until(10.0)
        .max_steps(2000)
        .run()
        .unwrap_err();
    assert!(matches!(err, SimulationError::MaxSteps { .. }));
    let s: &Stiffness = err
        .stiffness()
        .expect("a stiff run out of steps is diagnosed");
    assert!((s.omega_max - fast).abs() < 1e-3 * fast, "{s:?}");
    assert!(
        s.omega_min
            .is_some_and(|m| (m - 0.5_f64.sqrt()).abs() < 1e-3),
        "{s:?}"
    );
    assert_eq!(s.limit, None);
    let m = err.to_string();
    assert!(
        m.contains("The system is stiff")
            && m.contains("Method::Radau5 { rtol, atol }")
            && m.contains("VariationalMidpoint")
            && m.find("Method::Radau5") < m.find("VariationalMidpoint")
            && !m.contains("loosen the tolerances or"),
        "{m}"
    );
    // The same budget on a non-stiff oscillator: no diagnosis, the old advice.
    let err = Simulation::new(&Osc, [1.0], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(100.0)
        .max_steps(5)
        .run()
        .unwrap_err();
    assert!(err.stiffness().is_none());
    assert!(err.to_string().contains("loosen the tolerances"));
    // RK4 with dt·ω_max = 14 > 2√2 blows the fast mode up: the error states the limit.
    let err = Simulation::new(&StiffPair, [1.0, 1.0], [0.0, 1e-3])
        .method(Method::Rk4 { dt: 1e-3 })
        .until(10.0)
        .run()
        .unwrap_err();
    // (It grows to ~1e300 and the dynamics report the overflow first: non-finite derivatives.)
    assert!(
        matches!(
            err,
            SimulationError::NonFinite { .. } | SimulationError::Dynamics { .. }
        ),
        "{err}"
    );
    let s = err
        .stiffness()
        .expect("a fixed step above the limit is diagnosed");
    assert_eq!(s.limit, Some(super::method::RK4_LIMIT));
    let m = err.to_string();
    assert!(
        m.contains("dt < 2.000e-4")
            && m.contains("Method::Radau5 { rtol, atol }")
            && m.find("Method::Radau5") < m.find("VariationalMidpoint"),
        "{m}"
    );
    // …and a step below the limit runs.
    assert!(
        Simulation::new(&StiffPair, [1.0, 1.0], [0.0, 1e-3])
            .method(Method::Rk4 { dt: 1.5e-4 })
            .until(0.1)
            .run()
            .is_ok()
    );
}

/// The stiff pair's slow mode (K v = ω² v, K = [[1 + k₂, −k₂], [−k₂, k₂]]): ω² and the shape
/// scaled to v₀ = 1.
fn stiff_pair_slow_mode() -> (f64, [f64; 2]) {
    let k2 = 1e8_f64;
    // The smaller root of λ² − (1 + 2k₂) λ + k₂ = 0, without cancellation.
    let b = 1.0 + 2.0 * k2;
    let big = 0.5 * (b + (b * b - 4.0 * k2).sqrt());
    let w2 = k2 / big;
    // Row 1: (1 + k₂ − ω²) v₀ = k₂ v₁.
    (w2, [1.0, (1.0 + k2 - w2) / k2])
}

/// Radau5 on the stiff pair started on its slow manifold (the fast mode not excited): the
/// steps follow the slow mode, whose closed form it matches; the Newton matrix is kept (J is
/// constant) and the step counts are far below DOP853's.
#[test]
fn radau5_follows_the_slow_mode_of_the_stiff_pair() {
    use crate::integrate::{Method, Simulation};
    let (w2, v) = stiff_pair_slow_mode();
    let w = w2.sqrt();
    let tr = Simulation::new(&StiffPair, v, [0.0, 0.0])
        .method(Method::Radau5 {
            rtol: 1e-8,
            atol: 1e-10,
        })
        .until(10.0)
        .run()
        .unwrap();
    let (q, qd) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
    let mut err = 0.0_f64;
    for i in 0..2 {
        err = err
            .max((q[i] - v[i] * (w * 10.0).cos()).abs())
            .max((qd[i] + v[i] * w * (w * 10.0).sin()).abs());
    }
    assert!(
        err <= 1e-7 && tr.stats.steps <= 1000,
        "{err:e} {:?}",
        tr.stats
    );
}

/// On the (non-stiff) oscillator the error follows the tolerance: proportional to it (slope of
/// ln error against ln rtol near 1; measured 0.97) and within 10 rtol.
#[test]
fn radau5_error_follows_the_tolerance() {
    use crate::integrate::{Method, Simulation};
    let mut points = Vec::new();
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        let tr = Simulation::new(&Osc, [1.0], [0.0])
            .method(Method::Radau5 { rtol, atol: rtol })
            .until(10.0)
            .run()
            .unwrap();
        let err = (tr.q.last().unwrap()[0] - 10.0_f64.cos()).abs();
        assert!(err <= 10.0 * rtol, "rtol {rtol:e}: error {err:e}");
        points.push((rtol, err));
    }
    let p = slope(&points);
    assert!((0.8..1.2).contains(&p), "slope {p}");
}
