//! The Bari IVP test set's mechanical problems (Mazzia & Magherini, *Test Set for Initial Value
//! Problem Solvers*, release 2.4, 2008) run by every method that takes constraints: per problem,
//! method and tolerance, the significant correct digits at the end against the test set's
//! reference (scd of the positions, of the velocities and of the multipliers, apart), the steps (and
//! rejected attempts), right-hand-side evaluations, Newton iterations, Jacobians, LU
//! decompositions and the time. The problems are written as a user writes them
//! (`examples/support/testset_system.rs`): a Lagrangian, its constraints, no index hints. The
//! problems: the car axis (t = 3), Andrews' squeezer (t = 0.03) and the flexible slider crank
//! (t = 0.1; its x₃ compared with the published start's offset added, see
//! [`SliderCrank::X3_OFFSET`]).
//!
//! Run: `cargo run --release --example testset`
//!
//! With `-- --work`: the test set's own columns instead (its `report.f`: mescd, scd, steps,
//! accept, #f, #Jac, #LU), for DOP853 and Radau5 on the three problems at the
//! published tolerances rtol = atol = 1e-4, 1e-7, 1e-10, to set beside the published tables of
//! BIMD, GAMD, MEBDFI, PSIDE, RADAU and RADAU5 (BENCHMARKS.md); with `-- --work-grid` the same
//! columns on the test set's work-precision grid rtol = atol = 10^−(4 + m/4), m = 0 … 24. See
//! [`work`] for which components enter scd and mescd.

use std::time::Instant;

use lagrange::Stats;
use lagrange_examples::cli;
use lagrange_examples::testset_system::{scd, Andrews, CarAxis, SliderCrank};

use lagrange::prelude::*;

fn main() {
    cli::run_or_exit(body);
}

fn body() -> Result<(), Box<dyn std::error::Error>> {
    match std::env::args().nth(1).as_deref() {
        None => digits(),
        Some("--work") => work(&[1e-4, 1e-7, 1e-10]),
        Some("--work-grid") => work(
            &(0..=24)
                .map(|m| 10f64.powf(-4.0 - f64::from(m) / 4.0))
                .collect::<Vec<_>>(),
        ),
        Some(other) => {
            Err(format!("unknown argument {other}; usage: testset [--work | --work-grid]").into())
        }
    }
}

/// The significant correct digits of q, q̇ and λ apart, and the work, for every method.
fn digits() -> Result<(), Box<dyn std::error::Error>> {
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
            (&CarAxis::REFERENCE, |_| {}),
            method,
        )?;
    }
    let andrews = Andrews::TESTSET;
    let (q0, v0) = andrews.start();
    // RATTLE's order 2 on 0.03 and 0.1 units of fast mechanisms: a finer step.
    let finer = |method| match method {
        Method::VariationalMidpoint { dt } => Method::VariationalMidpoint { dt: dt / 100.0 },
        m => m,
    };
    for &method in &methods {
        row(
            "andrews",
            &andrews,
            (q0, v0),
            Andrews::END,
            (&Andrews::REFERENCE, |_| {}),
            finer(method),
        )?;
    }
    let crank = SliderCrank::TESTSET;
    let (q0, v0) = crank.start();
    for &method in &methods {
        row(
            "crank",
            &crank,
            (q0, v0),
            SliderCrank::END,
            (&SliderCrank::REFERENCE, SliderCrank::to_testset),
            finer(method),
        )?;
    }
    Ok(())
}

/// The end of one run: the state (q, q̇, then λ, in one vector), the counters and the time in ms.
struct End {
    y: Vec<f64>,
    stats: Stats,
    ms: f64,
}

/// `sys` from `start` to `end` by `method`, no samples kept.
fn run<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    (q0, v0): ([f64; N], [f64; N]),
    end: f64,
    method: Method,
) -> Result<End, Box<dyn std::error::Error>> {
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
    Ok(End {
        y: q.iter().chain(v).chain(l).copied().collect(),
        stats: tr.stats,
        ms,
    })
}

/// One line of the table: `sys` from `start` to `end` by `method`, against `reference` (the
/// positions, the velocities, then the multipliers) after `to_reference` (the slider crank's
/// x₃ offset).
fn row<L: Lagrangian<N>, const N: usize>(
    problem: &str,
    sys: &L,
    start: ([f64; N], [f64; N]),
    end: f64,
    (reference, to_reference): (&[f64], fn(&mut [f64])),
    method: Method,
) -> Result<(), Box<dyn std::error::Error>> {
    let End {
        mut y,
        stats: s,
        ms,
    } = run(sys, start, end, method)?;
    to_reference(&mut y);
    let (q, v, l) = (&y[..N], &y[N..2 * N], &y[2 * N..]);
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

/// The test set's mixed error measure (its `report.f`): −log₁₀ of the largest
/// |yᵢ − refᵢ| / (atol/rtol + |refᵢ|) over the components given.
fn mescd(y: &[f64], reference: &[f64], rtol: f64, atol: f64) -> f64 {
    let worst = y
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b).abs() / (atol / rtol + b.abs()))
        .fold(0.0_f64, f64::max);
    -worst.log10()
}

/// The slider crank's scd and mescd as `report.f` computes them from our end state `y` (q, q̇, λ,
/// x₃ with the offset) at rtol = atol = `tol`: scd over y₁..y₇ and y₂₂..y₂₄, mescd over all 24,
/// the accelerations y₁₅..y₂₁ those of the end state (M q̈ = f + Gᵀλ, G q̈ = −g̈), as the test
/// set's run has them as unknowns.
fn crank_digits(
    crank: &SliderCrank,
    y: &[f64],
    tol: f64,
) -> Result<(f64, f64), Box<dyn std::error::Error>> {
    let r = &SliderCrank::REFERENCE;
    let (mut q, v): ([f64; 7], [f64; 7]) = (y[..7].try_into()?, y[7..14].try_into()?);
    q[2] -= SliderCrank::X3_OFFSET;
    let (a, _) = crank.constrained_accelerations(&q, &v, SliderCrank::END)?;
    let positions_and_multipliers =
        |y: &[f64]| -> Vec<f64> { y[..7].iter().chain(&y[14..]).copied().collect() };
    let s = scd(&positions_and_multipliers(y), &positions_and_multipliers(r));
    let all = |y: &[f64], a: &[f64]| -> Vec<f64> {
        y[..14].iter().chain(a).chain(&y[14..]).copied().collect()
    };
    let m = mescd(
        &all(y, &a),
        &all(r, &SliderCrank::REFERENCE_ACCELERATIONS),
        tol,
        tol,
    );
    Ok((s, m))
}

/// The test set's tables' columns for DOP853 and Radau5 on the car axis (t = 3), Andrews'
/// squeezer (t = 0.03) and the slider crank (t = 0.1) at rtol = atol = each of `tols`, scd and
/// mescd as the test set's `report.f` computes them, over the components our runs give:
///
/// - car axis: the test set's y = (p, q, λ) ∈ R¹⁰ is our (q, q̇, λ) in the same order and sign;
///   scd and mescd over all 10, as `report.f` (λ computed from the end state, not integrated).
/// - Andrews: the test set's y = (q, q̇, q̈, λ) ∈ R²⁷. scd over y₁..y₇, the angles, as
///   `report.f`; mescd over the 20 we have, q, q̇ and λ (the test set's λ negated: its
///   M q̈ = f − Gᵀλ), without the accelerations y₁₅..y₂₁, which our state does not hold
///   (`report.f` takes all 27).
/// - slider crank: the test set's y = (p, q, v_p, v_q, a_p, a_q, λ) ∈ R²⁴ (index 2); scd over
///   y₁..y₇ and y₂₂..y₂₄ as `report.f`, mescd over all 24 ([`crank_digits`]). The published
///   runs start at h0 = 1e-2 rtol and have their rows at rtol = 1e-4, 1e-6, 1e-8.
///
/// steps = accepted + rejected, accept = accepted, #f = evaluations of the (constrained)
/// accelerations (DOP853's with the 3 per step of the dense output the work integral needs,
/// Radau5's with the one per step after the projection), #Jac = Jacobians (Andrews: exact, from
/// the jets; car axis, whose constraint moves: central differences of the constrained
/// accelerations, 4N evaluations each that #f leaves out, as `radau5.f`'s #f leaves out those of
/// a numerical Jacobian), #LU = decompositions (Radau5's I − hA⊗J and I − γhJ of one step size
/// counted as one, as `radau5.f`'s NDEC counts its real and complex pair). The first step size is our own (the
/// published runs start at h0 = rtol). The test set's grid for Andrews is finer,
/// 10^−(4 + m/8); `--work-grid` uses the car axis's for both.
fn work(tols: &[f64]) -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "{:<8} {:<7} {:>8} {:>8} {:>6} {:>6} {:>6} {:>6} {:>7} {:>5} {:>5} {:>7} {:>8}",
        "problem",
        "solver",
        "rtol",
        "atol",
        "mescd",
        "scd",
        "steps",
        "accept",
        "#f",
        "#Jac",
        "#LU",
        "newton",
        "time ms"
    );
    let car = CarAxis::TESTSET;
    let andrews = Andrews::TESTSET;
    let crank = SliderCrank::TESTSET;
    for problem in ["caraxis", "andrews", "crank"] {
        for &tol in tols {
            for (solver, method) in [
                (
                    "DOP853",
                    Method::Dop853 {
                        rtol: tol,
                        atol: tol,
                    },
                ),
                (
                    "Radau5",
                    Method::Radau5 {
                        rtol: tol,
                        atol: tol,
                    },
                ),
            ] {
                let (end, scd_of, mescd_of) = if problem == "caraxis" {
                    let e = run(&car, car.start(), CarAxis::END, method)?;
                    let r = &CarAxis::REFERENCE;
                    let (s, m) = (scd(&e.y, r), mescd(&e.y, r, tol, tol));
                    (e, s, m)
                } else if problem == "andrews" {
                    let e = run(&andrews, andrews.start(), Andrews::END, method)?;
                    let r = &Andrews::REFERENCE;
                    let (s, m) = (scd(&e.y[..7], &r[..7]), mescd(&e.y, r, tol, tol));
                    (e, s, m)
                } else {
                    let mut e = run(&crank, crank.start(), SliderCrank::END, method)?;
                    SliderCrank::to_testset(&mut e.y);
                    let (s, m) = crank_digits(&crank, &e.y, tol)?;
                    (e, s, m)
                };
                let s = end.stats;
                println!(
                    "{:<8} {:<7} {:>8.2e} {:>8.2e} {:>6.2} {:>6.2} {:>6} {:>6} {:>7} {:>5} {:>5} {:>7} {:>8.2}",
                    problem,
                    solver,
                    tol,
                    tol,
                    mescd_of,
                    scd_of,
                    s.steps + s.rejected,
                    s.steps,
                    s.rhs_evals,
                    s.jacobians,
                    s.decompositions,
                    s.newton_iterations,
                    end.ms
                );
            }
        }
    }
    Ok(())
}
