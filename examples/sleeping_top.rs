//! The sleeping top (reference text, section D, Example 1 / eq. 98): a top spinning almost upright
//! stays up only if Ω = L∥/I⊥ ≥ 2ω0.
//!
//! ```text
//! cargo run --release --example sleeping_top
//! cargo run --release --example sleeping_top -- --nudge 1e-6 --points 161 --svg out/sleeping.svg
//! ```
//!
//! Sweeps Ω/ω0 on the ensemble API (threads, a progress bar, constrained members). Each top starts **exactly upright**,
//! spinning about its axis, with a tilt rate θ̇0 = ε (the nudge, default 1e-8 rad/s): the top is
//! written in unit quaternions with the constraint |q|² = 1 (`#[lagrangian]` with
//! `fn constraints`), a chart with no singularity, where the Euler angles of eq. 92 are singular
//! at θ = 0. It is integrated with DOP853 until its first turning point of θ, and the largest
//! nutation θ_max is recorded. Below 2ω0 the top falls to cos θ = Ω²/2ω0² − 1 (eq. 98); above it
//! stays within 2ε/√(Ω² − 4ω0²) (the linearized motion about upright, u = θe^{iφ}:
//! ü − iΩu̇ − ω0²u = 0, from u = 0, u̇ = ε). Plots θ_max against Ω/ω0 (log scale) with both
//! predictions.

use std::time::Instant;

use lagrange::prelude::*;
use lagrange_theory::heavy_top::sleeping_top_lowest_cos;
use plotters::prelude::*;

// The top of eq. 92 in unit quaternions, declared with `#[lagrangian]` and `fn constraints`;
// shared with the tests and the benches.
use lagrange_examples::cli;
use lagrange_examples::quaternion_top_system;
use quaternion_top_system::{axis_z_rate, tilt, QuaternionTop};

const USAGE: &str = "\
usage: cargo run --release --example sleeping_top -- [options]
  --nudge X      initial tilt rate in rad/s from exactly upright, > 0 (1e-8)
  --from X       smallest Ω/ω0 (1.0)       --to X   largest Ω/ω0 (3.0)
  --points N     number of Ω/ω0 values (81)
  --i-perp X (1) --i-par X (1) --mgl X (1)
  --svg PATH     figure (out/sleeping_top.svg)
";

struct Options {
    nudge: f64,
    from: f64,
    to: f64,
    points: usize,
    top: QuaternionTop,
    svg: String,
}

fn parse() -> Result<Options, String> {
    let mut o = Options {
        nudge: 1e-8,
        from: 1.0,
        to: 3.0,
        points: 81,
        top: QuaternionTop {
            i_perp: 1.0,
            i_par: 1.0,
            mgl: 1.0,
        },
        svg: "out/sleeping_top.svg".into(),
    };
    for (key, val) in cli::pairs()? {
        let num = || cli::number(&key, &val);
        match key.as_str() {
            "--nudge" => o.nudge = num()?,
            "--from" => o.from = num()?,
            "--to" => o.to = num()?,
            "--points" => o.points = num()? as usize,
            "--i-perp" => o.top.i_perp = num()?,
            "--i-par" => o.top.i_par = num()?,
            "--mgl" => o.top.mgl = num()?,
            "--svg" => o.svg = val,
            _ => return Err(format!("unknown option {key}")),
        }
    }
    if !(o.nudge > 0.0 && o.nudge < 0.1) {
        return Err(
            "--nudge must be in (0, 0.1): exactly upright with no nudge stays up at any Ω".into(),
        );
    }
    if !(o.from > 0.0 && o.to > o.from && o.points >= 2) {
        return Err("need 0 < --from < --to and --points ≥ 2".into());
    }
    Ok(o)
}

/// The initial state of one member: exactly upright, with the tilt rate `nudge` and the spin
/// of the given Ω/ω0. Body angular velocity (ε, 0, ω3) with Ω = L∥/I⊥ = I∥ ω3/I⊥;
/// q = (1, 0, 0, 0), q̇ = ½ q ⊗ (0, ω).
fn upright(top: &QuaternionTop, nudge: f64, ratio: f64) -> ([f64; 4], [f64; 4]) {
    let omega0 = (top.mgl / top.i_perp).sqrt();
    let spin = ratio * omega0 * top.i_perp / top.i_par;
    ([1.0, 0.0, 0.0, 0.0], [0.0, nudge / 2.0, 0.0, spin / 2.0])
}

/// θ_max (rad) of one run: where the axis stops tipping (the terminal event), or the largest
/// tilt sampled if it never does.
fn largest_nutation(traj: &Trajectory<4>) -> f64 {
    traj.events
        .first()
        .map(|e| tilt(&e.q))
        .unwrap_or_else(|| traj.q.iter().map(tilt).fold(0.0, f64::max))
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = cli::or_exit(parse(), USAGE);
    let ratios: Vec<f64> = (0..o.points)
        .map(|k| o.from + (o.to - o.from) * k as f64 / (o.points - 1) as f64)
        .collect();
    println!(
        "sleeping top: exactly upright, nudged at θ̇0 = {:e} rad/s, Ω/ω0 from {} to {} ({} runs on {} threads)",
        o.nudge,
        o.from,
        o.to,
        o.points,
        rayon::current_num_threads()
    );
    // The constrained run of each member (the system declares its constraint; the quaternion
    // chart has no singularity upright), on the ensemble API: threads, a progress bar, results
    // in member order.
    let top = o.top;
    let omega0 = (top.mgl / top.i_perp).sqrt();
    let start = Instant::now();
    let sweep = Ensemble::new(ratios.len(), |k| {
        let (q0, qd0) = upright(&top, o.nudge, ratios[k]);
        Member::new(top, q0, qd0).param("ratio", ratios[k])
    })
    .configure(|sim| {
        sim.method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-15,
        })
        .until(1e4 / omega0)
        .max_steps(2_000_000)
        .event(
            Event::zero_crossing("theta max", |_t, q: &[f64; 4], v: &[f64; 4]| {
                axis_z_rate(q, v)
            })
            .rising()
            .terminal(),
        )
    })
    .progress(true)
    .reduce(&["theta_max"], largest_nutation);
    let results: Vec<(f64, Result<f64, String>)> = ratios
        .iter()
        .zip(sweep.results)
        .map(|(&r, out)| (r, out.map_err(|e| e.to_string())))
        .collect();
    println!(
        "{} runs in {:.2} s\n",
        results.len(),
        start.elapsed().as_secs_f64()
    );

    println!("  Ω/ω0    θ_max (sim)      prediction       rel. diff");
    let mut points = Vec::new();
    for (r, out) in &results {
        let omega0 = (o.top.mgl / o.top.i_perp).sqrt();
        let predicted = predicted_max(*r, o.nudge / omega0);
        match out {
            Ok(th) => {
                points.push((*r, *th));
                let diff = predicted.map(|p| ((th - p) / p).abs());
                let every = (results.len() / 20).max(1);
                let k = ((r - o.from) / (o.to - o.from) * (o.points - 1) as f64).round() as usize;
                if k.is_multiple_of(every) || (r - 2.0).abs() < 1e-9 {
                    println!(
                        "  {r:5.3}   {th:.9e}  {}  {}",
                        predicted.map_or("      —        ".to_string(), |p| format!("{p:.9e}")),
                        diff.map_or("—".to_string(), |d| format!("{d:.1e}"))
                    );
                }
            }
            Err(e) => println!("  {r:5.3}   failed: {e}"),
        }
    }
    println!(
        "\nbelow 2ω0 the top falls to cos θ = Ω²/2ω0² − 1 (eq. 98); above it, θ_max ≈ 2θ̇0/√(Ω² − 4ω0²)"
    );
    let omega0 = (o.top.mgl / o.top.i_perp).sqrt();
    plot(&o.svg, &points, o.nudge / omega0, o.from, o.to)?;
    println!("wrote {}", o.svg);
    Ok(())
}

/// Eq. 98 below the threshold, the linearized bound 2ε/√(r² − 4) above it (ε = θ̇0/ω0, r = Ω/ω0);
/// none at the threshold (secular growth until the nonlinear terms stop it).
fn predicted_max(ratio: f64, eps: f64) -> Option<f64> {
    if ratio > 2.0 {
        return Some(above(eps, ratio));
    }
    sleeping_top_lowest_cos(ratio, 1.0).map(f64::acos)
}

/// The linearized largest tilt above the threshold, 2ε/√(r² − 4).
fn above(eps: f64, ratio: f64) -> f64 {
    2.0 * eps / (ratio * ratio - 4.0).sqrt()
}

fn plot(
    path: &str,
    points: &[(f64, f64)],
    eps: f64,
    from: f64,
    to: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let root = SVGBackend::new(path, (1000, 620)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut ch = ChartBuilder::on(&root)
        .caption(
            format!("sleeping top from exactly upright, θ̇0/ω0 = {eps:e}: largest nutation vs Ω/ω0"),
            ("sans-serif", 22),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(from..to, (eps * 0.5..4.0).log_scale())?;
    ch.configure_mesh()
        .x_desc("Ω/ω0")
        .y_desc("θ_max (rad)")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    let n = 400;
    let below: Vec<(f64, f64)> = (0..=n)
        .map(|k| from + (2.0_f64.min(to) - from) * k as f64 / n as f64)
        .filter_map(|r| sleeping_top_lowest_cos(r, 1.0).map(|p| (r, p.acos())))
        .collect();
    ch.draw_series(LineSeries::new(below, RED.stroke_width(2)))?
        .label("eq. 98: cos θ_max = Ω²/2ω0² − 1")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(2)));
    let above: Vec<(f64, f64)> = (1..=n)
        .map(|k| 2.0_f64.max(from) + (to - 2.0_f64.max(from)) * k as f64 / n as f64)
        .map(|r| (r, above(eps, r)))
        .filter(|(_, t)| *t < 4.0)
        .collect();
    ch.draw_series(LineSeries::new(above, GREEN.stroke_width(2)))?
        .label("2θ̇0/√(Ω² − 4ω0²) (linearized about upright)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], GREEN.stroke_width(2)));
    ch.draw_series(LineSeries::new(
        vec![(2.0, eps * 0.5), (2.0, 4.0)],
        BLACK.mix(0.5).stroke_width(1),
    ))?
    .label("threshold Ω = 2ω0")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.5)));
    ch.draw_series(
        points
            .iter()
            .map(|&(r, t)| Circle::new((r, t), 3, BLUE.filled())),
    )?
    .label("simulation (DOP853, first turning point)")
    .legend(|(x, y)| Circle::new((x + 10, y), 3, BLUE.filled()));
    ch.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    root.present()?;
    Ok(())
}
