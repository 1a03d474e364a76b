//! The IVP test set's car axis (examples/support/testset_system.rs) against a compiled DAE
//! solver: SUNDIALS IDAS through CasADi (`benches/peers/casadi_caraxis.py`, the car axis in its
//! index-1 form), timed in the same run.
//!
//! Prints, once, our DOP853 and Radau5 at rtol 1e-6 … 1e-12 (atol = rtol): the significant
//! correct digits of q, q̇ and λ at t = 3 against the quad-precision reference, steps and the best
//! of 20 wall times; then, when python3 with CasADi is installed, the peer's lines and for each
//! the ratio of its time to that of our fastest run with at least its digits in q; then
//! criterion's measurement of DOP853 at rtol 1e-10 (see BENCHMARKS.md).
//!
//! Run: `cargo bench --bench testset` (the peer: `python3 -m pip install casadi`)

mod timing;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;
use lagrange_examples::testset_system::{scd, CarAxis};
use std::hint::black_box;
use std::process::Command;
use timing::best_of;

/// The car axis run of `method` to t = 3 (final state only).
fn run(method: Method) -> Trajectory<4> {
    let p = CarAxis::TESTSET;
    let (q0, v0) = p.start();
    Simulation::new(&p, q0, v0)
        .method(method)
        .until(CarAxis::END)
        .keep_samples(false)
        .run()
        .expect("the car axis integrates")
}

/// The digits of q, q̇ and λ at t = 3.
fn digits(tr: &Trajectory<4>) -> (f64, f64, f64) {
    let r = &CarAxis::REFERENCE;
    let last = tr.t.len() - 1;
    (
        scd(&tr.q[last], &r[..4]),
        scd(&tr.qdot[last], &r[4..8]),
        scd(&tr.lambda[last], &r[8..]),
    )
}

/// The CasADi peer script.
const PEER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/peers/casadi_caraxis.py");

/// The peer's lines with their best wall time (seconds) and digits in q, when python3 with
/// CasADi is installed.
fn peer() -> Option<Vec<(f64, f64, String)>> {
    let out = Command::new("python3").arg(PEER).output().ok()?;
    if !out.status.success() {
        eprintln!(
            "CasADi peer not run ({}): python3 -m pip install casadi",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("?")
        );
        return None;
    }
    let field = |line: &str, key: &str, end: &str| -> Option<f64> {
        line.split(key)
            .nth(1)?
            .split(end)
            .next()?
            .trim()
            .parse()
            .ok()
    };
    Some(
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|line| {
                let ms = field(line, "best of 5 wall ", " ms")?;
                let q = field(line, "scd q ", " q'")?;
                Some((ms * 1e-3, q, line.to_string()))
            })
            .collect(),
    )
}

fn bench(c: &mut Criterion) {
    let mut ours = Vec::new();
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        for method in [
            Method::Dop853 {
                rtol: tol,
                atol: tol,
            },
            Method::Radau5 {
                rtol: tol,
                atol: tol,
            },
        ] {
            let tr = run(method);
            let d = digits(&tr);
            let t = best_of(20, || drop(black_box(run(black_box(method)))));
            eprintln!(
                "lagrange {method:?}: scd q {:.2} q̇ {:.2} λ {:.2}, {} steps, best of 20 {:.3} ms",
                d.0,
                d.1,
                d.2,
                tr.stats.steps,
                t * 1e3
            );
            ours.push((t, d.0, format!("{method:?}")));
        }
    }
    if let Some(lines) = peer() {
        for (t, q, line) in lines {
            eprintln!("{line}");
            let best = ours
                .iter()
                .filter(|(_, d, _)| *d >= q)
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((ours_t, d, name)) = best {
                eprintln!("  / lagrange {name} (scd q {d:.2}) = {:.1}x", t / ours_t);
            }
        }
    }
    let dop = Method::Dop853 {
        rtol: 1e-10,
        atol: 1e-10,
    };
    let mut g = c.benchmark_group("caraxis_t3");
    g.sample_size(50);
    g.bench_function("dop853_rtol1e-10", |b| b.iter(|| run(black_box(dop))));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
