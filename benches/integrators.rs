//! Heavy top (I⊥ = 1, I∥ = 0.5, m g l = 4.905; θ0 = 0.7, φ̇0 = 2, ψ̇0 = 12) for 100 nutation
//! periods (t = 114.3) with DOP853 at rtol 1e-10, atol 1e-12.
//!
//! Measures in one run: the jet-derived dynamics (`HeavyTop`, only L written), the macro-declared
//! top in the default symbolic mode (`MacroTop`), and the same integrator on a hand-written
//! closed-form baseline (`HeavyTopClosedForm`: accelerations, momenta and energy overridden with
//! the hand-derived formulas). Prints steps, right-hand-side evaluations and the
//! invariant drift once; then, when python3 with SciPy is installed, compares the drift of ours
//! and SciPy's over 30 tops (one trajectory's drift is partly the luck of its step sequence), runs
//! the SciPy peer (`benches/peers/scipy_dop853.py`, best of 5) and ours (best of 20) side by side
//! and prints the ratios; then criterion's measurements (see BENCHMARKS.md).
//!
//! Run: `cargo bench --bench integrators`

mod timing;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;
use lagrange::Drift;
use std::hint::black_box;
use std::process::Command;
use timing::best_of;

/// The heavy top, eq. 92: only L is written, the dynamics come from the jets.
struct HeavyTop {
    i_perp: f64,
    i_par: f64,
    mgl: f64,
}
impl Lagrangian<3> for HeavyTop {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], qd: &[S; 3], _t: S) -> S {
        let (s, c) = q[0].sin_cos();
        let w3 = qd[2] + qd[1] * c;
        (qd[0] * qd[0] + qd[1] * qd[1] * s * s) * (self.i_perp / 2.0) + w3 * w3 * (self.i_par / 2.0)
            - c * self.mgl
    }
}

/// The same top with the hand-derived accelerations (the closed-form baseline).
struct HeavyTopClosedForm(HeavyTop);
impl Lagrangian<3> for HeavyTopClosedForm {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], qd: &[S; 3], t: S) -> S {
        self.0.lagrangian(q, qd, t)
    }
    fn accelerations(
        &self,
        q: &[f64; 3],
        qd: &[f64; 3],
        _t: f64,
    ) -> Result<[f64; 3], DynamicsError> {
        let top = &self.0;
        let (s, c) = q[0].sin_cos();
        let (th_d, ph_d, ps_d) = (qd[0], qd[1], qd[2]);
        let w3 = ps_d + ph_d * c;
        let th_dd =
            ph_d * ph_d * s * c - top.i_par / top.i_perp * w3 * ph_d * s + top.mgl / top.i_perp * s;
        let ph_dd = th_d * (top.i_par * w3 - 2.0 * top.i_perp * ph_d * c) / (top.i_perp * s);
        let ps_dd = ph_d * th_d * s - ph_dd * c;
        Ok([th_dd, ph_dd, ps_dd])
    }
    fn momenta(&self, q: &[f64; 3], qd: &[f64; 3], _t: f64) -> [f64; 3] {
        let top = &self.0;
        let (s, c) = q[0].sin_cos();
        let l_par = top.i_par * (qd[2] + qd[1] * c);
        [
            top.i_perp * qd[0],
            top.i_perp * qd[1] * s * s + l_par * c,
            l_par,
        ]
    }
    fn energy_and_momenta(&self, q: &[f64; 3], qd: &[f64; 3], t: f64) -> (f64, [f64; 3]) {
        (self.energy(q, qd, t), self.momenta(q, qd, t))
    }
    fn energy(&self, q: &[f64; 3], qd: &[f64; 3], _t: f64) -> f64 {
        let top = &self.0;
        let (s, c) = q[0].sin_cos();
        let w3 = qd[2] + qd[1] * c;
        top.i_perp / 2.0 * (qd[0] * qd[0] + qd[1] * qd[1] * s * s)
            + top.i_par / 2.0 * w3 * w3
            + top.mgl * c
    }
}

use lagrange_examples::bench_top::MacroTop;

const TOP: HeavyTop = HeavyTop {
    i_perp: 1.0,
    i_par: 0.5,
    mgl: 4.905,
};
const Q0: [f64; 3] = [0.7, 0.0, 0.0];
const V0: [f64; 3] = [0.0, 2.0, 12.0];
const T_END: f64 = 114.3;
const METHOD: Method = Method::Dop853 {
    rtol: 1e-10,
    atol: 1e-12,
};

fn run<L: Lagrangian<3>>(sys: &L) -> Trajectory<3> {
    Simulation::new(sys, Q0, V0)
        .method(METHOD)
        .until(T_END)
        .run()
        .expect("the heavy top integrates")
}

fn report(name: &str, tr: &Trajectory<3>) {
    let inv = tr.invariants();
    let e = inv.energy.map_or(f64::NAN, |d| d.max_rel);
    let p_phi = inv.momenta[1].map_or(f64::NAN, |d| d.max_rel);
    let p_psi = inv.momenta[2].map_or(f64::NAN, |d| d.max_rel);
    eprintln!(
        "{name}: steps {}, rejected {}, rhs evals {}, max rel drift: energy {e:.2e}, p_phi {p_phi:.2e}, \
         p_psi {p_psi:.2e}, final theta {:.12}",
        tr.stats.steps,
        tr.stats.rejected,
        tr.stats.rhs_evals,
        tr.q.last().map_or(f64::NAN, |q| q[0]),
    );
}

/// The SciPy peer script.
const SCIPY_PEER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/peers/scipy_dop853.py");

/// The SciPy peer in the same run (`benches/peers/scipy_dop853.py`, best of 5), when python3 with
/// SciPy is installed: its best wall time in seconds, and its report line.
fn scipy_peer() -> Option<(f64, String)> {
    let out = Command::new("python3").arg(SCIPY_PEER).output().ok()?;
    let line = String::from_utf8_lossy(&out.stdout).trim().to_string();
    if !out.status.success() {
        eprintln!(
            "SciPy peer not run ({}): python3 -m pip install scipy",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("?")
        );
        return None;
    }
    let ms: f64 = line
        .split("best of 5 wall ")
        .nth(1)?
        .split(" ms")
        .next()?
        .parse()
        .ok()?;
    Some((ms * 1e-3, line))
}

/// The initial conditions (θ0, φ̇0, ψ̇0) of the drift comparison: 5 × 3 × 2 = 30 tops with the
/// benchmark's parameters, θ̇0 = φ0 = ψ0 = 0, each run to t = 114.3.
fn family() -> Vec<[f64; 3]> {
    let mut ics = Vec::new();
    for th in [0.3, 0.7, 1.1, 1.5, 2.0] {
        for ph_d in [0.5, 2.0, 4.0] {
            for ps_d in [6.0, 12.0] {
                ics.push([th, ph_d, ps_d]);
            }
        }
    }
    ics
}

/// SciPy's right-hand-side evaluations and drifts (energy, p_φ, p_ψ) for each initial condition,
/// when python3 with SciPy is installed.
fn scipy_family(ics: &[[f64; 3]]) -> Option<Vec<[f64; 4]>> {
    use std::io::Write;
    let mut child = Command::new("python3")
        .args([SCIPY_PEER, "--family"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .ok()?;
    let input: String = ics
        .iter()
        .map(|[a, b, c]| format!("{a} {b} {c}\n"))
        .collect();
    child.stdin.take()?.write_all(input.as_bytes()).ok()?;
    let out = child.wait_with_output().ok()?;
    let rows: Vec<[f64; 4]> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| {
            let v: Vec<f64> = l
                .split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect();
            v.try_into().ok()
        })
        .collect();
    (out.status.success() && rows.len() == ics.len()).then_some(rows)
}

/// The drift of one trajectory is partly the luck of its step sequence: compare ours with SciPy's
/// over the 30 tops of [`family`] (same tolerances), as ratios ours / SciPy.
fn drift_over_family(top: &MacroTop) {
    let ics = family();
    let Some(scipy) = scipy_family(&ics) else {
        eprintln!("SciPy family comparison not run (python3 with SciPy needed)");
        return;
    };
    // Per initial condition: ratios of RHS evaluations and of the three drifts.
    let ratios: Vec<[f64; 4]> = ics
        .iter()
        .zip(&scipy)
        .map(|(&[th, ph_d, ps_d], s)| {
            let tr = Simulation::new(top, [th, 0.0, 0.0], [0.0, ph_d, ps_d])
                .method(METHOD)
                .until(T_END)
                .run()
                .expect("the heavy top integrates");
            let inv = tr.invariants();
            let d = |x: Option<Drift>| x.map_or(f64::NAN, |d| d.max_rel);
            [
                tr.stats.rhs_evals as f64 / s[0],
                d(inv.energy) / s[1],
                d(inv.momenta[1]) / s[2],
                d(inv.momenta[2]) / s[3],
            ]
        })
        .collect();
    let n = ratios.len() as f64;
    let geo = |i: usize| (ratios.iter().map(|r| r[i].ln()).sum::<f64>() / n).exp();
    let at_most = |i: usize| ratios.iter().filter(|r| r[i] <= 1.0).count();
    eprintln!(
        "drift over {} tops (ours / SciPy, geometric mean): rhs evals {:.3}, energy {:.2}, p_phi {:.2}, \
         p_psi {:.2}; ours <= SciPy in {} / {} / {} of {}",
        ratios.len(),
        geo(0),
        geo(1),
        geo(2),
        geo(3),
        at_most(1),
        at_most(2),
        at_most(3),
        ratios.len()
    );
}

/// Three uncoupled oscillators with a right-hand side that costs almost nothing: what the DOP853
/// stepper itself (stage sums, error estimate, controller, recording) costs per evaluation.
struct FreeRhs;
impl Lagrangian<3> for FreeRhs {
    const COORDINATES: [&'static str; 3] = ["a", "b", "c"];
    const CYCLIC: [bool; 3] = [false; 3];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], qd: &[S; 3], _t: S) -> S {
        (qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2]
            - q[0] * q[0] * 4.0
            - q[1] * q[1] * 9.0
            - q[2] * q[2])
            * 0.5
    }
    fn accelerations(
        &self,
        q: &[f64; 3],
        _qd: &[f64; 3],
        _t: f64,
    ) -> Result<[f64; 3], DynamicsError> {
        Ok([-4.0 * q[0], -9.0 * q[1], -q[2]])
    }
    fn energy_and_momenta(&self, q: &[f64; 3], qd: &[f64; 3], _t: f64) -> (f64, [f64; 3]) {
        let e = (qd[0] * qd[0]
            + qd[1] * qd[1]
            + qd[2] * qd[2]
            + q[0] * q[0] * 4.0
            + q[1] * q[1] * 9.0
            + q[2] * q[2])
            * 0.5;
        (e, *qd)
    }
}

/// Where the time of a run goes, per right-hand-side evaluation (best of 20 each, same run): the
/// stepper alone ([`FreeRhs`]), glibc's `sin_cos` alone (one per evaluation), and the whole run
/// for the macro top and the closed form.
fn time_per_evaluation(macro_top: &MacroTop, closed: &HeavyTopClosedForm) {
    let per_eval = |f: &dyn Fn() -> Trajectory<3>| {
        let evals = f().stats.rhs_evals as f64;
        best_of(20, || drop(black_box(f()))) / evals * 1e9
    };
    let free = per_eval(&|| {
        Simulation::new(&FreeRhs, [1.0, 0.5, 0.2], [0.0, 1.0, 0.3])
            .method(METHOD)
            .until(60.0)
            .run()
            .expect("the oscillators integrate")
    });
    let thetas: Vec<f64> = (0..40_000).map(|i| 0.6 + 0.7 * (i as f64 / 4e4)).collect();
    let sincos = best_of(20, || {
        let mut acc = 0.0;
        for &x in black_box(&thetas) {
            let (s, c) = x.sin_cos();
            acc += s * c;
        }
        black_box(acc);
    }) / thetas.len() as f64
        * 1e9;
    let top = per_eval(&|| run(black_box(macro_top)));
    let closed = per_eval(&|| run(black_box(closed)));
    eprintln!(
        "per right-hand-side evaluation: stepper alone (free RHS) {free:.1} ns, sin_cos alone \
         {sincos:.1} ns; whole run: #[lagrangian] top {top:.1} ns, closed form {closed:.1} ns"
    );
}

fn bench(c: &mut Criterion) {
    let closed = HeavyTopClosedForm(HeavyTop { ..TOP });
    report("lagrange DOP853 (jets)", &run(&TOP));
    report("closed-form baseline DOP853", &run(&closed));
    let macro_top = MacroTop {
        i_perp: TOP.i_perp,
        i_par: TOP.i_par,
        mgl: TOP.mgl,
    };
    report(
        "lagrange DOP853 (#[lagrangian], symbolic)",
        &run(&macro_top),
    );
    drift_over_family(&macro_top);
    time_per_evaluation(&macro_top, &closed);
    // Side by side in one run: SciPy (best of 5) and ours (best of 20), as ratios.
    if let Some((scipy, line)) = scipy_peer() {
        eprintln!("{line}");
        for (name, t) in [
            (
                "lagrange #[lagrangian] (symbolic)",
                best_of(20, || drop(black_box(run(black_box(&macro_top))))),
            ),
            (
                "lagrange run-time jets",
                best_of(20, || drop(black_box(run(black_box(&TOP))))),
            ),
            (
                "hand-written closed form",
                best_of(20, || drop(black_box(run(black_box(&closed))))),
            ),
        ] {
            eprintln!(
                "{name}: best of 20 {:.3} ms, SciPy / this = {:.0}x",
                t * 1e3,
                scipy / t
            );
        }
    }
    let mut g = c.benchmark_group("heavy_top_dop853_t114.3");
    g.sample_size(20);
    g.bench_function("lagrange_jets", |b| b.iter(|| run(black_box(&TOP))));
    g.bench_function("lagrange_macro_symbolic", |b| {
        b.iter(|| run(black_box(&macro_top)))
    });
    g.bench_function("closed_form_baseline", |b| {
        b.iter(|| run(black_box(&closed)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
