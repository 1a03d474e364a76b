//! The fast top (reference text, section D, Example 2, eqs. 99–102).
//!
//! ```text
//! cargo run --release --example fast_top
//! cargo run --release --example fast_top -- --theta0 0.5 --ratios 5,10,20,50,100
//! ```
//!
//! A top released at rest (θ̇ = φ̇ = 0) from θ0 with Ω/ω0 ≫ 1. For each Ω/ω0 it prints the largest
//! error of eq. 101 over the first nutation period divided by the nutation width 2Δ (it shrinks
//! like (ω0/Ω)²), and the mean precession rate over a nutation period: measured, from the precise
//! quadrature, the corrected fast-top value mgl/L∥ and the text's printed mgl/(2L∥). Writes an
//! SVG with cos θ(t) against eq. 101 and φ̇(t) against the corrected and the printed eq. 102.

use std::f64::consts::PI;

use lagrange::prelude::*;
use lagrange_theory::heavy_top::{fast_top_cos_theta, fast_top_precession_rate, Constants, Top};
use plotters::prelude::*;

// The top of eq. 92, declared with `#[lagrangian]` exactly as the equation reads; shared by the
// heavy-top examples.
use heavy_top_system::HeavyTop;
use lagrange_examples::cli;
use lagrange_examples::heavy_top_system;

const USAGE: &str = "\
usage: cargo run --release --example fast_top -- [options]
  --theta0 X        release angle in rad (1.0)
  --ratios A,B,...  values of Ω/ω0 (5,10,20,50)
  --plot-ratio X    Ω/ω0 of the figure (10)
  --i-perp X (1.2) --i-par X (0.96) --mgl X (2.7)
  --svg PATH        figure (out/fast_top.svg)
";

struct Options {
    theta0: f64,
    ratios: Vec<f64>,
    plot_ratio: f64,
    top: HeavyTop,
    svg: String,
}

fn parse() -> Result<Options, String> {
    let mut o = Options {
        theta0: 1.0,
        ratios: vec![5.0, 10.0, 20.0, 50.0],
        plot_ratio: 10.0,
        top: HeavyTop {
            i_perp: 1.2,
            i_par: 0.96,
            mgl: 2.7,
        },
        svg: "out/fast_top.svg".into(),
    };
    for (key, val) in cli::pairs()? {
        let num = |s: &str| cli::number(&key, s);
        match key.as_str() {
            "--theta0" => o.theta0 = num(&val)?,
            "--ratios" => o.ratios = val.split(',').map(num).collect::<Result<_, _>>()?,
            "--plot-ratio" => o.plot_ratio = num(&val)?,
            "--i-perp" => o.top.i_perp = num(&val)?,
            "--i-par" => o.top.i_par = num(&val)?,
            "--mgl" => o.top.mgl = num(&val)?,
            "--svg" => o.svg = val,
            _ => return Err(format!("unknown option {key}")),
        }
    }
    Ok(o)
}

struct Run {
    constants: Constants,
    traj: Trajectory<3>,
}

/// Released at rest from θ0 with Ω/ω0 = ratio, for `periods` nutation periods.
fn run(
    top: &HeavyTop,
    theta0: f64,
    ratio: f64,
    periods: f64,
) -> Result<Run, Box<dyn std::error::Error>> {
    let omega0 = (top.mgl / top.i_perp).sqrt();
    let spin = ratio * omega0 * top.i_perp / top.i_par; // Ω = I∥ψ̇/I⊥ at rest
    let (q0, qd0) = ([theta0, 0.0, 0.0], [0.0, 0.0, spin]);
    let theory = Top {
        i_perp: top.i_perp,
        i_par: top.i_par,
        mgl: top.mgl,
    };
    let constants = Constants::from_state(&theory, &q0, &qd0)?;
    let period = constants.nutation.period()?;
    let traj = Simulation::new(top, q0, qd0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(periods * period)
        .sample_every(period / 400.0)
        .event(Event::zero_crossing("theta max", |_t, _q, v: &[f64; 3]| v[0]).falling())
        .run()?;
    Ok(Run { constants, traj })
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = cli::or_exit(parse(), USAGE);
    let top = o.top;
    println!(
        "fast top released at rest from θ0 = {} (I⊥ = {}, I∥ = {}, mgl = {})\n",
        o.theta0, top.i_perp, top.i_par, top.mgl
    );
    println!(
        "eq. 101: cos θ(t) ≈ p0 + (ω0/Ω)²(1 − p0²)(cos Ωt − 1); error over the first period / 2Δ"
    );
    println!("eq. 102 (corrected): ⟨φ̇⟩ ≈ mgl/L∥; the text prints mgl/(2L∥)\n");
    println!(
        "  Ω/ω0   eq.101 err/2Δ  ×(Ω/ω0)²   ⟨φ̇⟩ measured      quadrature        mgl/L∥ (rel. err ×(Ω/ω0)²)   text mgl/2L∥"
    );
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    for &ratio in &o.ratios {
        let r = run(&top, o.theta0, ratio, 2.2)?;
        let n = r.constants.nutation;
        let first = 2.0 * PI / n.omega.abs();
        let delta = (n.omega0 / n.omega).powi(2) * (1.0 - n.p0 * n.p0);
        let err = r
            .traj
            .t
            .iter()
            .zip(&r.traj.q)
            .filter(|(t, _)| **t <= first)
            .map(|(t, q)| (q[0].cos() - fast_top_cos_theta(n.p0, n.omega0, n.omega, *t)).abs())
            .fold(0.0, f64::max)
            / (2.0 * delta);
        let lows = &r.traj.events;
        let measured = if lows.len() >= 2 {
            (lows[1].q[1] - lows[0].q[1]) / (lows[1].t - lows[0].t)
        } else {
            f64::NAN
        };
        let quad = n.mean_precession_rate()?;
        let fast = top.mgl / r.constants.l_par;
        println!(
            "  {ratio:5.1}  {err:.4e}  {:8.4}   {measured:.12}  {quad:.12}  {fast:.9} ({:.3e} ×{:.3})  {:.9}",
            err * ratio * ratio,
            rel(measured, fast),
            rel(measured, fast) * ratio * ratio,
            fast / 2.0
        );
    }
    let r = run(&top, o.theta0, o.plot_ratio, 3.0)?;
    plot(&o.svg, &r, &top, o.plot_ratio)?;
    println!("\nwrote {}", o.svg);
    Ok(())
}

fn plot(path: &str, r: &Run, top: &HeavyTop, ratio: f64) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let n = r.constants.nutation;
    let t = &r.traj.t;
    let t_end = t.last().copied().unwrap_or(1.0);
    let root = SVGBackend::new(path, (1000, 760)).into_drawing_area();
    root.fill(&WHITE)?;
    let (upper, lower) = root.split_vertically(380);

    let p: Vec<(f64, f64)> = t
        .iter()
        .zip(&r.traj.q)
        .map(|(t, q)| (*t, q[0].cos()))
        .collect();
    let (lo, hi) = p.iter().fold((f64::MAX, f64::MIN), |(a, b), (_, y)| {
        (a.min(*y), b.max(*y))
    });
    let pad = 0.1 * (hi - lo).max(1e-12);
    let mut ch = ChartBuilder::on(&upper)
        .caption(
            format!("cos θ(t), Ω/ω0 = {ratio}: simulation vs eq. 101"),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(90)
        .build_cartesian_2d(0.0..t_end, (lo - pad)..(hi + pad))?;
    ch.configure_mesh()
        .x_desc("t")
        .y_desc("cos θ")
        .y_label_formatter(&|v| format!("{v:.5}"))
        .draw()?;
    ch.draw_series(LineSeries::new(p, BLUE.stroke_width(2)))?
        .label("simulation (DOP853)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
    ch.draw_series(LineSeries::new(
        t.iter()
            .map(|t| (*t, fast_top_cos_theta(n.p0, n.omega0, n.omega, *t))),
        RED.stroke_width(1),
    ))?
    .label("eq. 101")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    ch.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()?;

    let scale = top.mgl / r.constants.l_par;
    let mut ch = ChartBuilder::on(&lower)
        .caption(
            "φ̇(t): corrected eq. 102 (mgl/L∥)(1 − cos Ωt) vs the printed (mgl/L∥)(cos Ωt − 1)",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(90)
        .build_cartesian_2d(0.0..t_end, (-2.3 * scale)..(2.3 * scale))?;
    ch.configure_mesh()
        .x_desc("t")
        .y_desc("φ̇")
        .y_label_formatter(&|v| format!("{:.3}", if v.abs() < 1e-12 { 0.0 } else { *v }))
        .draw()?;
    ch.draw_series(LineSeries::new(
        t.iter().zip(&r.traj.qdot).map(|(t, v)| (*t, v[1])),
        BLUE.stroke_width(2),
    ))?
    .label("simulation")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
    ch.draw_series(LineSeries::new(
        t.iter()
            .map(|t| (*t, fast_top_precession_rate(n.omega0, n.omega, *t))),
        RED.stroke_width(1),
    ))?
    .label("corrected eq. 102")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    ch.draw_series(LineSeries::new(
        t.iter()
            .map(|t| (*t, -fast_top_precession_rate(n.omega0, n.omega, *t))),
        BLACK.mix(0.6).stroke_width(1),
    ))?
    .label("as printed in the text")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.6)));
    for (level, color, name) in [
        (scale, GREEN, "⟨φ̇⟩ = mgl/L∥"),
        (scale / 2.0, MAGENTA, "text: mgl/2L∥"),
    ] {
        ch.draw_series(LineSeries::new(
            vec![(0.0, level), (t_end, level)],
            color.stroke_width(1),
        ))?
        .label(name)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
    }
    ch.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()?;
    root.present()?;
    Ok(())
}
