//! The IVP test set's mechanical problems (examples/support/testset_system.rs: the car axis,
//! Andrews' squeezer and the flexible slider crank) against a compiled DAE solver: SUNDIALS IDAS
//! through CasADi (`benches/peers/casadi_testset.py`, each problem in its index-1 form), timed in
//! the same run.
//!
//! Prints, once, per problem: our DOP853 and Radau5 at rtol 1e-6 … 1e-12 (atol = rtol; the
//! crank also at 1e-13, where its digits reach the reference's double-precision ceiling): the
//! significant correct digits of q, q̇ and λ at the end against the test set's reference (the
//! crank's x₃ with the published start's offset, as `tests/testset.rs`), steps and the best of 20
//! wall times; then, when python3 with CasADi is installed, the peer's lines (IDAS with its
//! defaults and with the algebraic variables out of its error test, each at every tolerance)
//! and for each the ratio of its time to that of our fastest run with at least its digits in q;
//! then criterion's measurement of DOP853 on the car axis at rtol 1e-10 (see BENCHMARKS.md).
//!
//! Run: `cargo bench --bench testset` (the peer: `python3 -m pip install casadi`)

mod timing;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;
use lagrange_examples::testset_system::{scd, Andrews, CarAxis, SliderCrank};
use std::hint::black_box;
use std::process::Command;
use timing::best_of;

/// The car axis run of `method` to t = 3 (final state only).
fn run_car_axis(method: Method) -> Trajectory<4> {
    let p = CarAxis::TESTSET;
    let (q0, v0) = p.start();
    Simulation::new(&p, q0, v0)
        .method(method)
        .until(CarAxis::END)
        .keep_samples(false)
        .run()
        .expect("the car axis integrates")
}

/// One problem of the test set as this bench runs it.
struct Problem<'a, L> {
    /// The peer's name for it.
    name: &'static str,
    sys: &'a L,
    end: f64,
    /// The reference at `end`: q, q̇, then λ.
    reference: &'a [f64],
    /// Our end state as the reference's (the crank's x₃ offset).
    to_reference: fn(&mut [f64]),
    /// Our tolerances (rtol = atol).
    tolerances: &'a [f64],
}

/// `p` run by `method` to its end (final state only).
fn run<L: Lagrangian<N>, const N: usize>(
    p: &Problem<'_, L>,
    start: ([f64; N], [f64; N]),
    method: Method,
) -> Trajectory<N> {
    Simulation::new(p.sys, start.0, start.1)
        .method(method)
        .until(p.end)
        .keep_samples(false)
        .max_steps(10_000_000)
        .run()
        .unwrap_or_else(|e| panic!("{} by {method:?}: {e}", p.name))
}

/// The digits of q, q̇ and λ at the end of `tr` against `p`'s reference.
fn digits<L, const N: usize>(p: &Problem<'_, L>, tr: &Trajectory<N>) -> (f64, f64, f64) {
    let r = p.reference;
    let last = tr.t.len() - 1;
    let mut y: Vec<f64> = tr.q[last]
        .iter()
        .chain(&tr.qdot[last])
        .chain(&tr.lambda[last])
        .copied()
        .collect();
    (p.to_reference)(&mut y);
    (
        scd(&y[..N], &r[..N]),
        scd(&y[N..2 * N], &r[N..2 * N]),
        scd(&y[2 * N..], &r[2 * N..]),
    )
}

/// Our DOP853 and Radau5 runs of `p` at its tolerances: printed, and returned as (best wall time
/// in seconds, digits in q, method).
fn ours<L: Lagrangian<N>, const N: usize>(
    p: &Problem<'_, L>,
    start: ([f64; N], [f64; N]),
) -> Vec<(f64, f64, String)> {
    let mut runs = Vec::new();
    for &tol in p.tolerances {
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
            let tr = run(p, start, method);
            let d = digits(p, &tr);
            let t = best_of(20, || drop(black_box(run(p, start, black_box(method)))));
            eprintln!(
                "{} lagrange {method:?}: scd q {:.2} q̇ {:.2} λ {:.2}, {} steps, best of 20 {:.3} ms",
                p.name,
                d.0,
                d.1,
                d.2,
                tr.stats.steps,
                t * 1e3
            );
            runs.push((t, d.0, format!("{method:?}")));
        }
    }
    runs
}

/// The CasADi peer script.
const PEER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/peers/casadi_testset.py");

/// One line of the peer's: its best wall time (seconds) and digits in q when it timed a run (None
/// for a failed run), and the line.
type PeerLine = (Option<(f64, f64)>, String);

/// The peer's lines for `problem`, when python3 with CasADi is installed.
fn peer(problem: &str) -> Option<Vec<PeerLine>> {
    let out = Command::new("python3")
        .arg(PEER)
        .arg(problem)
        .output()
        .ok()?;
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
            .filter(|line| line.starts_with("casadi"))
            .map(|line| {
                let timed = field(line, "best of 5 wall ", " ms")
                    .zip(field(line, "scd q ", " q'"))
                    .map(|(ms, q)| (ms * 1e-3, q));
                (timed, line.to_string())
            })
            .collect(),
    )
}

/// The peer's lines for `problem`, each timed one followed by its ratio to our fastest run of
/// `ours` with at least its digits in q.
fn compare(problem: &str, ours: &[(f64, f64, String)]) {
    let Some(lines) = peer(problem) else {
        return;
    };
    for (timed, line) in lines {
        eprintln!("{problem} {line}");
        let Some((t, q)) = timed else {
            continue;
        };
        let best = ours
            .iter()
            .filter(|(_, d, _)| *d >= q)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((ours_t, d, name)) => {
                eprintln!("  / lagrange {name} (scd q {d:.2}) = {:.1}x", t / ours_t)
            }
            None => eprintln!("  no run of ours has {q:.2} digits in q"),
        }
    }
}

fn bench(c: &mut Criterion) {
    let grid = [1e-6, 1e-8, 1e-10, 1e-12];
    let car = CarAxis::TESTSET;
    let p = Problem {
        name: "caraxis",
        sys: &car,
        end: CarAxis::END,
        reference: &CarAxis::REFERENCE,
        to_reference: |_| {},
        tolerances: &grid,
    };
    let runs = ours(&p, car.start());
    compare(p.name, &runs);

    let andrews = Andrews::TESTSET;
    let p = Problem {
        name: "andrews",
        sys: &andrews,
        end: Andrews::END,
        reference: &Andrews::REFERENCE,
        to_reference: |_| {},
        tolerances: &grid,
    };
    let runs = ours(&p, andrews.start());
    compare(p.name, &runs);

    let crank = SliderCrank::TESTSET;
    let p = Problem {
        name: "crank",
        sys: &crank,
        end: SliderCrank::END,
        reference: &SliderCrank::REFERENCE,
        to_reference: SliderCrank::to_testset,
        tolerances: &[1e-6, 1e-8, 1e-10, 1e-12, 1e-13],
    };
    let runs = ours(&p, crank.start());
    compare(p.name, &runs);

    let dop = Method::Dop853 {
        rtol: 1e-10,
        atol: 1e-10,
    };
    let mut g = c.benchmark_group("caraxis_t3");
    g.sample_size(50);
    g.bench_function("dop853_rtol1e-10", |b| {
        b.iter(|| run_car_axis(black_box(dop)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
