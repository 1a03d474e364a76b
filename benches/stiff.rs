//! Stiff mechanics: two unit masses, k₁ = 1 to the wall and k₂ = 10⁸ between them, from the slow
//! manifold to t = 10 (the `stiff` example's problem, examples/support/stiff_system.rs).
//!
//! Prints, once, Radau5's steps, evaluations, error against the modal solution and best-of-20
//! wall time at rtol 1e-8 (atol 1e-10) and at rtol 1e-10 (atol 1e-12), and DOP853's at rtol 1e-8
//! (best of 3); then, when python3 with SciPy is installed, runs the SciPy peer
//! (`benches/peers/scipy_stiff.py`: `solve_ivp` Radau and BDF with the exact Jacobian, rtol 1e-8,
//! atol 1e-10, best of 5) and prints the time ratios; then criterion's measurement of Radau5 at
//! rtol 1e-8 (see BENCHMARKS.md).
//!
//! Run: `cargo bench --bench stiff`

mod timing;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;
use lagrange_examples::stiff_system::TwoMasses;
use std::hint::black_box;
use std::process::Command;
use timing::best_of;

const SYS: TwoMasses = TwoMasses::STIFF;
const T_END: f64 = 10.0;

/// The run of `method` to t = 10 from the slow manifold (final state only).
fn run(method: Method) -> Trajectory<2> {
    let (q0, v0) = SYS.slow_start();
    Simulation::new(&SYS, q0, v0)
        .method(method)
        .until(T_END)
        .keep_samples(false)
        .run()
        .expect("the two masses integrate")
}

/// The largest error in (q, q̇) at t = 10.
fn error(tr: &Trajectory<2>) -> f64 {
    let (q0, v0) = SYS.slow_start();
    let (qe, ve) = SYS.exact(q0, v0, T_END);
    let (q, v) = (tr.q[tr.q.len() - 1], tr.qdot[tr.qdot.len() - 1]);
    (0..2).fold(0.0_f64, |m, i| {
        m.max((q[i] - qe[i]).abs()).max((v[i] - ve[i]).abs())
    })
}

/// The SciPy peer script.
const SCIPY_PEER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/peers/scipy_stiff.py");

/// The SciPy peer's lines (`solve_ivp` Radau, then BDF), each with its best wall time in seconds,
/// when python3 with SciPy is installed.
fn scipy_peer() -> Option<Vec<(f64, String)>> {
    let out = Command::new("python3").arg(SCIPY_PEER).output().ok()?;
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
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|line| {
            let ms: f64 = line
                .split("best of 5 wall ")
                .nth(1)?
                .split(" ms")
                .next()?
                .parse()
                .ok()?;
            Some((ms * 1e-3, line.to_string()))
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let radau = |rtol: f64| Method::Radau5 {
        rtol,
        atol: rtol * 1e-2,
    };
    let mut ours = Vec::new();
    for rtol in [1e-8, 1e-10] {
        let tr = run(radau(rtol));
        let t = best_of(20, || drop(black_box(run(black_box(radau(rtol))))));
        eprintln!(
            "lagrange Radau5 rtol {rtol:.0e}: {} steps ({} rejected), {} evaluations, {} Newton \
             iterations, error {:.2e}, best of 20 {:.3} ms",
            tr.stats.steps,
            tr.stats.rejected,
            tr.stats.rhs_evals,
            tr.stats.newton_iterations,
            error(&tr),
            t * 1e3
        );
        ours.push((rtol, t));
    }
    let dop = Method::Dop853 {
        rtol: 1e-8,
        atol: 1e-10,
    };
    let tr = run(dop);
    let t_dop = best_of(3, || drop(black_box(run(black_box(dop)))));
    eprintln!(
        "lagrange DOP853 rtol 1e-8: {} steps, error {:.2e}, best of 3 {:.3} ms (DOP853 / Radau5 = \
         {:.0}x)",
        tr.stats.steps,
        error(&tr),
        t_dop * 1e3,
        t_dop / ours[0].1
    );
    if let Some(peers) = scipy_peer() {
        for (t, line) in peers {
            eprintln!("{line}");
            for &(rtol, ours) in &ours {
                eprintln!("  / lagrange Radau5 rtol {rtol:.0e} = {:.0}x", t / ours);
            }
        }
    }
    let mut g = c.benchmark_group("stiff_two_masses_t10");
    g.sample_size(50);
    g.bench_function("radau5_rtol1e-8", |b| {
        b.iter(|| run(black_box(radau(1e-8))))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
