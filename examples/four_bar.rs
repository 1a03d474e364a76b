//! A four-bar linkage with its loop closed by holonomic constraints.
//!
//! The Grashof crank–rocker l0 = 4 (ground), l1 = 1 (crank), l2 = 3.5 (coupler), l3 = 3 (rocker)
//! of uniform unit-mass bars in a vertical plane, in its three bar angles θ1, θ2, θ3 with the two
//! loop-closure constraints (examples/support/four_bar_system.rs). No motor: a flywheel on the
//! crank keeps it turning. The example starts from a closed state (θ2, θ3 solved from the loop at
//! θ1 = 0, velocities in the null space of G), integrates several crank revolutions with DOP853,
//! and prints the constraint residual, the energy drift and the multipliers λ over one revolution
//! (the force, in N, that the rocker exerts on the coupler at their joint: the loop is cut
//! there), then draws the coupler curve, the path of
//! a point on the coupler, as SVG.
//!
//! Run: `cargo run --release --example four_bar -- [--turns 10] [--out out/four_bar.svg]`

#[allow(dead_code)] // each example uses a part of the shared command-line helpers
use lagrange_examples::cli;
use lagrange_examples::four_bar_system;

use std::f64::consts::TAU;

use four_bar_system::FourBar;
use lagrange::prelude::*;
use plotters::prelude::*;

const USAGE: &str = "usage: cargo run --release --example four_bar -- [--turns N] [--out PATH.svg]
  --turns N    crank revolutions to integrate (default 10)
  --out PATH   the coupler curve (default out/four_bar.svg)
";

/// The coupler point whose path is drawn: halfway along the coupler, 0.4 l2 to its left.
const ALONG: f64 = 0.5;
const ACROSS: f64 = 0.4;

struct Options {
    turns: f64,
    out: String,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        turns: 10.0,
        out: "out/four_bar.svg".into(),
    };
    for (key, val) in cli::pairs()? {
        match key.as_str() {
            "--turns" => o.turns = cli::number(&key, &val)?,
            "--out" => o.out = val,
            _ => return Err(format!("unknown option {key}")),
        }
    }
    if !(o.turns >= 2.0 && o.turns <= 1e5) {
        return Err("--turns must be between 2 and 100000".into());
    }
    Ok(o)
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = cli::or_exit(options(), USAGE);
    let fb = FourBar::crank_rocker();
    let (q0, v0) = fb.closed_state(0.0, TAU);
    println!(
        "Four-bar crank–rocker: l0 = {}, l1 = {}, l2 = {}, l3 = {}; flywheel {} kg m², g = {}",
        fb.l0, fb.l1, fb.l2, fb.l3, fb.flywheel, fb.g
    );
    println!(
        "start: θ = ({:.6}, {:.6}, {:.6}), θ̇ = ({:.6}, {:.6}, {:.6})",
        q0[0], q0[1], q0[2], v0[0], v0[1], v0[2]
    );

    // Events at twelve crank angles of the second revolution, for the table of λ; a terminal
    // event after `turns` revolutions.
    let table: Vec<f64> = (0..12).map(|k| TAU * (1.0 + k as f64 / 12.0)).collect();
    let mut sim = Simulation::new(&fb, q0, v0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(2.0 * o.turns + 10.0)
        .sample_every(0.01);
    for (k, &angle) in table.iter().enumerate() {
        sim = sim.event(
            Event::zero_crossing(format!("{}°", 30 * k), move |_t, q: &[f64; 3], _v| {
                q[0] - angle
            })
            .rising(),
        );
    }
    let end = o.turns * TAU;
    let tr = sim
        .event(Event::zero_crossing("turns", move |_t, q: &[f64; 3], _v| q[0] - end).terminal())
        .run()?;
    let inv = tr.invariants();
    let t_end = tr.t.last().copied().unwrap_or(f64::NAN);
    let c = inv.constraints.unwrap_or_default();
    println!(
        "\n{} crank revolutions in t = {t_end:.4} s: {} steps, {} right-hand sides",
        o.turns, tr.stats.steps, tr.stats.rhs_evals
    );
    println!(
        "constraint residual: max |g| = {:.2e}, max |ġ| = {:.2e} (largest projection {:.2e})",
        c.position, c.velocity, c.projection
    );
    if let Some(e) = inv.energy {
        println!(
            "energy h = {:.9} J, max relative drift {:.2e}",
            e.initial, e.max_rel
        );
    }

    // Gᵀλ = (r_B × λ, (C − B) × λ, −(C − D) × λ): λ = (λ0, λ1) is the force the rocker exerts
    // on the coupler at the joint C (the loop's cut), in N.
    println!(
        "\nλ over the second revolution (M θ̈ = f + Gᵀλ): (λ0, λ1) is the force of the rocker \
         on the coupler at C, in N"
    );
    println!(
        "{:>6} {:>9} {:>14} {:>14} {:>10}",
        "crank", "t", "λ0", "λ1", "θ̇1"
    );
    for hit in tr.events.iter().filter(|h| h.name != "turns") {
        let (_, lambda) = fb.constrained_accelerations(&hit.q, &hit.qdot, hit.t)?;
        println!(
            "{:>6} {:>9.5} {:>14.6} {:>14.6} {:>10.5}",
            hit.name, hit.t, lambda[0], lambda[1], hit.qdot[0]
        );
    }

    plot(&o.out, &fb, &tr)?;
    println!("\nwrote {}", o.out);
    cli::write_animation(&o.out, "four-bar crank–rocker", &tr, &fb)?;
    Ok(())
}

/// The coupler curve over the run (one closed loop, traced once per revolution), the paths of
/// the crank's and the rocker's tips, and the linkage at t = 0.
fn plot(path: &str, fb: &FourBar, tr: &Trajectory<3>) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let curve: Vec<(f64, f64)> =
        tr.q.iter()
            .map(|q| fb.coupler_point(q, ALONG, ACROSS))
            .collect();
    let tip_b: Vec<(f64, f64)> = tr.q.iter().map(|q| fb.coupler_point(q, 0.0, 0.0)).collect();
    let tip_c: Vec<(f64, f64)> = tr.q.iter().map(|q| fb.coupler_point(q, 1.0, 0.0)).collect();
    let all = curve.iter().chain(&tip_b).chain(&tip_c);
    let (mut x0, mut x1, mut y0, mut y1) = (0.0_f64, fb.l0, 0.0_f64, 0.0_f64);
    for &(x, y) in all {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    // Equal scales on both axes: a square window around the drawing.
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let half = 0.55 * (x1 - x0).max(y1 - y0);

    let root = SVGBackend::new(path, (720, 720)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "Four-bar crank–rocker (l0, l1, l2, l3) = ({}, {}, {}, {}): coupler curve",
                fb.l0, fb.l1, fb.l2, fb.l3
            ),
            ("sans-serif", 18),
        )
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(cx - half..cx + half, cy - half..cy + half)?;
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .draw()?;
    chart
        .draw_series(LineSeries::new(curve, RED.stroke_width(2)))?
        .label(format!(
            "coupler point ({ALONG} l2 along B→C, {ACROSS} l2 to its left)"
        ))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(2)));
    let grey = RGBColor(150, 150, 150);
    chart
        .draw_series(LineSeries::new(tip_b, grey.stroke_width(1)))?
        .label("crank tip B, rocker tip C")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(1)));
    chart.draw_series(LineSeries::new(tip_c, grey.stroke_width(1)))?;

    // The linkage at t = 0: ground, crank, coupler (with the traced point), rocker.
    let q = tr.q[0];
    let a = (0.0, 0.0);
    let d = (fb.l0, 0.0);
    let b = fb.coupler_point(&q, 0.0, 0.0);
    let c = fb.coupler_point(&q, 1.0, 0.0);
    let p = fb.coupler_point(&q, ALONG, ACROSS);
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![a, d],
            BLACK.stroke_width(1),
        )))?
        .label("linkage at t = 0")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(3)));
    chart.draw_series(std::iter::once(PathElement::new(
        vec![a, b, c, d],
        BLUE.stroke_width(3),
    )))?;
    chart.draw_series(std::iter::once(Polygon::new(
        vec![b, p, c],
        BLUE.mix(0.2).filled(),
    )))?;
    chart.draw_series(
        [a, b, c, d]
            .into_iter()
            .map(|pt| Circle::new(pt, 4, BLACK.filled())),
    )?;
    chart.draw_series(std::iter::once(Circle::new(p, 4, RED.filled())))?;
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()?;
    root.present()?;
    Ok(())
}
