//! The sleeping top (reference text, section D, Example 1 / eq. 98): a top spinning almost upright
//! stays up only if Ω = L∥/I⊥ ≥ 2ω0.
//!
//! ```text
//! cargo run --release --example sleeping_top
//! cargo run --release --example sleeping_top -- --theta0 1e-4 --points 161 --svg out/sleeping.svg
//! ```
//!
//! Sweeps Ω/ω0 in parallel (rayon, with a progress bar): each top is released at rest (θ̇ = φ̇ = 0)
//! from θ0 (default 1e-3; the Euler-angle chart is singular at θ = 0 exactly, so the top does not
//! start there), integrated with DOP853 until its first turning point of θ, and the largest
//! nutation θ_max is recorded. Below 2ω0 the top falls to cos θ = Ω²/2ω0² − 1 (eq. 98); above it
//! stays within θ0 Ω/√(Ω² − 4ω0²) (small-oscillation bound); at the threshold θ_max ≈ √(2θ0).
//! Plots θ_max against Ω/ω0 (log scale) with both predictions.

use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use lagrange::prelude::*;
use lagrange::theory::heavy_top::{
    sleeping_top_lowest_cos, sleeping_top_max_angle, Constants, Top,
};
use plotters::prelude::*;
use rayon::prelude::*;

// The top of eq. 92, declared with `#[lagrangian]` exactly as the equation reads; shared by the
// heavy-top examples.
#[path = "support/cli.rs"]
mod cli;
#[path = "support/heavy_top_system.rs"]
mod heavy_top_system;
use heavy_top_system::HeavyTop;

const USAGE: &str = "\
usage: cargo run --release --example sleeping_top -- [options]
  --theta0 X     initial tilt in rad, > 0 (1e-3)
  --from X       smallest Ω/ω0 (1.0)       --to X   largest Ω/ω0 (3.0)
  --points N     number of Ω/ω0 values (81)
  --i-perp X (1) --i-par X (1) --mgl X (1)
  --svg PATH     figure (out/sleeping_top.svg)
";

struct Options {
    theta0: f64,
    from: f64,
    to: f64,
    points: usize,
    top: HeavyTop,
    svg: String,
}

fn parse() -> Result<Options, String> {
    let mut o = Options {
        theta0: 1e-3,
        from: 1.0,
        to: 3.0,
        points: 81,
        top: HeavyTop {
            i_perp: 1.0,
            i_par: 1.0,
            mgl: 1.0,
        },
        svg: "out/sleeping_top.svg".into(),
    };
    for (key, val) in cli::pairs()? {
        let num = || cli::number(&key, &val);
        match key.as_str() {
            "--theta0" => o.theta0 = num()?,
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
    if !(o.theta0 > 0.0 && o.theta0 < 0.5) {
        return Err("--theta0 must be in (0, 0.5): θ = 0 is the chart's singular point".into());
    }
    if !(o.from > 0.0 && o.to > o.from && o.points >= 2) {
        return Err("need 0 < --from < --to and --points ≥ 2".into());
    }
    Ok(o)
}

/// One run: θ_max (rad) reached after release at rest from θ0 with the given Ω/ω0.
fn largest_nutation(top: &HeavyTop, theta0: f64, ratio: f64) -> Result<f64, String> {
    let omega0 = (top.mgl / top.i_perp).sqrt();
    // At rest: L∥ = I∥ ψ̇ and Ω = L∥/I⊥.
    let spin = ratio * omega0 * top.i_perp / top.i_par;
    let (q0, qd0) = ([theta0, 0.0, 0.0], [0.0, 0.0, spin]);
    let theory = Top {
        i_perp: top.i_perp,
        i_par: top.i_par,
        mgl: top.mgl,
    };
    // Only to bound the run: stop at the first θ maximum or after 1.5 predicted periods.
    let period = Constants::from_state(&theory, &q0, &qd0)
        .and_then(|c| c.nutation.period())
        .map_err(|e| e.to_string())?;
    let until = if period.is_finite() {
        1.5 * period
    } else {
        1e4
    };
    let traj = Simulation::new(top, q0, qd0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-15,
        })
        .until(until)
        .max_steps(2_000_000)
        .event(
            Event::zero_crossing("theta max", |_t, _q, v: &[f64; 3]| v[0])
                .falling()
                .terminal(),
        )
        .run()
        .map_err(|e| e.to_string())?;
    Ok(traj
        .events
        .first()
        .map(|e| e.q[0])
        .unwrap_or_else(|| traj.q.iter().map(|q| q[0]).fold(0.0, f64::max)))
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
        "sleeping top: released at rest from θ0 = {:e}, Ω/ω0 from {} to {} ({} runs on {} threads)",
        o.theta0,
        o.from,
        o.to,
        o.points,
        rayon::current_num_threads()
    );
    let bar = ProgressBar::new(ratios.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs  {elapsed_precise}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let results: Vec<(f64, Result<f64, String>)> = ratios
        .par_iter()
        .map(|&r| {
            let out = largest_nutation(&o.top, o.theta0, r);
            bar.inc(1);
            (r, out)
        })
        .collect();
    bar.finish();
    println!(
        "{} runs in {:.2} s\n",
        results.len(),
        start.elapsed().as_secs_f64()
    );

    println!("  Ω/ω0    θ_max (sim)      prediction       rel. diff");
    let mut points = Vec::new();
    for (r, out) in &results {
        let predicted = predicted_max(*r, o.theta0);
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
        "\nbelow 2ω0 the top falls to cos θ = Ω²/2ω0² − 1 (eq. 98); above it, θ_max ≈ θ0 Ω/√(Ω² − 4ω0²)"
    );
    plot(&o.svg, &points, o.theta0, o.from, o.to)?;
    println!("wrote {}", o.svg);
    Ok(())
}

/// Eq. 98 below the threshold, the small-oscillation bound above it, √(2θ0) at it (ω0 = 1 units).
fn predicted_max(ratio: f64, theta0: f64) -> Option<f64> {
    if (ratio - 2.0).abs() < 1e-12 {
        return Some((1.0 - 2.0 * (theta0 / 2.0).sin()).acos());
    }
    sleeping_top_lowest_cos(ratio, 1.0)
        .map(f64::acos)
        .or_else(|| sleeping_top_max_angle(theta0, ratio, 1.0))
}

fn plot(
    path: &str,
    points: &[(f64, f64)],
    theta0: f64,
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
            format!("sleeping top released at θ0 = {theta0:e}: largest nutation vs Ω/ω0"),
            ("sans-serif", 22),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(from..to, (theta0 * 0.5..4.0).log_scale())?;
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
        .filter_map(|r| sleeping_top_max_angle(theta0, r, 1.0).map(|t| (r, t)))
        .filter(|(_, t)| *t < 4.0)
        .collect();
    ch.draw_series(LineSeries::new(above, GREEN.stroke_width(2)))?
        .label("θ0 Ω/√(Ω² − 4ω0²) (small oscillations)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], GREEN.stroke_width(2)));
    ch.draw_series(LineSeries::new(
        vec![(2.0, theta0 * 0.5), (2.0, 4.0)],
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
