//! The Bari IVP test set's mechanical problems (Mazzia & Magherini, *Test Set for Initial Value
//! Problem Solvers*, release 2.4, 2008) run by every method that takes constraints: per problem,
//! method and tolerance, the significant correct digits at the end against the test set's
//! reference (scd of the positions, of the velocities and of the multipliers, apart), the steps (and
//! rejected attempts), right-hand-side evaluations, Newton iterations, Jacobians, LU
//! decompositions and the time. The problems are written as a user writes them
//! (`examples/support/testset_system.rs`): a Lagrangian, its constraints, no index hints.
//!
//! Run: `cargo run --release --example testset`

use std::time::Instant;

use lagrange_examples::cli;
use lagrange_examples::testset_system::{scd, Andrews, CarAxis};

use lagrange::prelude::*;

fn main() {
    cli::run_or_exit(body);
}

fn body() -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "{:<9} {:<40} {:>6} {:>6} {:>6} {:>9} {:>8} {:>10} {:>8} {:>6} {:>6} {:>9}",
        "problem",
        "method",
        "scd q",
        "scd q̇",
        "scd λ",
        "steps",
        "rejected",
        "evals",
        "newton",
        "jac",
        "LU",
        "time ms"
    );
    let mut methods = Vec::new();
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        methods.push(Method::Dop853 {
            rtol: tol,
            atol: tol,
        });
        methods.push(Method::Radau5 {
            rtol: tol,
            atol: tol,
        });
    }
    for dt in [1e-3, 1e-4] {
        methods.push(Method::VariationalMidpoint { dt });
    }
    let car = CarAxis::TESTSET;
    let (q0, v0) = car.start();
    for &method in &methods {
        row(
            "caraxis",
            &car,
            (q0, v0),
            CarAxis::END,
            &CarAxis::REFERENCE,
            method,
        )?;
    }
    let andrews = Andrews::TESTSET;
    let (q0, v0) = andrews.start();
    for method in methods {
        // RATTLE's order 2 on 0.03 units of a fast mechanism: a finer step.
        let method = match method {
            Method::VariationalMidpoint { dt } => Method::VariationalMidpoint { dt: dt * 1e-2 },
            m => m,
        };
        row(
            "andrews",
            &andrews,
            (q0, v0),
            Andrews::END,
            &Andrews::REFERENCE,
            method,
        )?;
    }
    Ok(())
}

/// One line of the table: `sys` from `start` to `end` by `method`, against `reference` (the
/// positions, the velocities, then the multipliers).
fn row<L: Lagrangian<N>, const N: usize>(
    problem: &str,
    sys: &L,
    (q0, v0): ([f64; N], [f64; N]),
    end: f64,
    reference: &[f64],
    method: Method,
) -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let tr = Simulation::new(sys, q0, v0)
        .method(method)
        .until(end)
        .keep_samples(false)
        .max_steps(10_000_000)
        .run()?;
    let ms = start.elapsed().as_secs_f64() * 1e3;
    let (q, v, l) = (
        tr.q.last().ok_or("no sample")?,
        tr.qdot.last().ok_or("no sample")?,
        tr.lambda.last().ok_or("no multipliers")?,
    );
    let s = tr.stats;
    println!(
        "{:<9} {:<40} {:>6.2} {:>6.2} {:>6.2} {:>9} {:>8} {:>10} {:>8} {:>6} {:>6} {:>9.2}",
        problem,
        format!("{method:?}"),
        scd(q, &reference[..N]),
        scd(v, &reference[N..2 * N]),
        scd(l, &reference[2 * N..]),
        s.steps,
        s.rejected,
        s.rhs_evals,
        s.newton_iterations,
        s.jacobians,
        s.decompositions,
        ms
    );
    Ok(())
}
