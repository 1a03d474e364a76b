//! Stiff mechanics: two unit masses, a soft spring k₁ = 1 to the wall and a stiff one k₂ = 10⁸
//! between them (ω ≈ 0.71 and 1.4·10⁴), started on the slow manifold (the fast mode not
//! excited), run to t = 10 by every method, each against the exact solution (modal
//! decomposition). The explicit methods take steps bounded by the fast mode; Radau5 (implicit,
//! L-stable) takes steps that follow the slow one.
//!
//! One line per method: `method = NAME steps = N error = X` (X the largest error in q and q̇ at
//! t = 10), or `error = - (hit the step limit)` for a run that used up its steps.
//!
//! Run: `cargo run --release --example stiff -- [--max-steps 200000]`

use lagrange_examples::cli;
use lagrange_examples::stiff_system::TwoMasses;

use lagrange::prelude::*;

const USAGE: &str = "usage: cargo run --release --example stiff -- [--max-steps N]
  --max-steps N  the step limit of every run (default 200000, at least 1)
";

/// The step limit from the command line.
fn options() -> Result<usize, String> {
    let mut max_steps = 200_000;
    for (key, val) in cli::pairs()? {
        match key.as_str() {
            "--max-steps" => {
                let n = cli::number(&key, &val)?;
                if !(1.0..=1e12).contains(&n) || n.fract() != 0.0 {
                    return Err(format!(
                        "--max-steps: a whole number from 1 to 10¹², not {val}"
                    ));
                }
                max_steps = n as usize;
            }
            _ => return Err(format!("unknown option {key}")),
        }
    }
    Ok(max_steps)
}

fn main() {
    cli::run_or_exit(body);
}

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let max_steps = cli::or_exit(options(), USAGE);
    let sys = TwoMasses::STIFF;
    let (q0, v0) = sys.slow_start();
    let until = 10.0;
    let (qe, ve) = sys.exact(q0, v0, until);
    let methods = [
        ("rk4", Method::Rk4 { dt: 1e-4 }),
        (
            "dopri5",
            Method::DormandPrince {
                rtol: 1e-8,
                atol: 1e-10,
            },
        ),
        (
            "dop853",
            Method::Dop853 {
                rtol: 1e-8,
                atol: 1e-10,
            },
        ),
        ("taylor", Method::Taylor { tol: 1e-8 }),
        ("variational", Method::VariationalMidpoint { dt: 1e-3 }),
        (
            "radau5",
            Method::Radau5 {
                rtol: 1e-8,
                atol: 1e-10,
            },
        ),
    ];
    for (name, method) in methods {
        let run = Simulation::new(&sys, q0, v0)
            .method(method)
            .until(until)
            .max_steps(max_steps)
            .keep_samples(false)
            .run();
        match run {
            Ok(tr) => {
                let (q, v) = (tr.q[tr.q.len() - 1], tr.qdot[tr.qdot.len() - 1]);
                let err = (0..2).fold(0.0_f64, |m, i| {
                    m.max((q[i] - qe[i]).abs()).max((v[i] - ve[i]).abs())
                });
                println!(
                    "method = {name} steps = {} error = {err:.2e}",
                    tr.stats.steps
                );
            }
            Err(SimulationError::MaxSteps { partial, .. }) => println!(
                "method = {name} steps = {} error = - (hit the step limit)",
                partial.get::<2>().map_or(max_steps, |t| t.stats.steps)
            ),
            Err(e) => return Err(e.into()),
        }
    }
    Ok(())
}
