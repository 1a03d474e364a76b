//! The passive compass-gait walker (Goswami, Thuilot & Espiau 1996): two legs and a hip mass
//! walking down a slope with no motor, written as its stance-phase Lagrangian and its heel
//! strike (`examples/support/walker_system.rs`). The library finds its period-one gaits as
//! fixed points of the step-to-step map, shot through the heel strike, and the map's
//! multipliers from the monodromy carried across the strike (its saltation matrix):
//!
//! - the *simplest walker* (the feet's masses → 0; Garcia, Chatterjee, Ruina & Coleman 1998) at
//!   γ = 0.009: its long-step gait as published to 14 digits, and its multipliers;
//! - Goswami's walker (m_H = 10, m = 5, a = b = 0.5, g = 9.8) at 3°: its gait as published to 4
//!   digits, its multipliers, and, following the gait up the slope, where a multiplier passes
//!   −1: the first period doubling, after which the walker takes long and short steps in turn;
//! - the bifurcation diagram, drawn (SVG): the inter-leg angle at the steps of the settled
//!   walk against the slope, from period one through period doubling towards chaos.
//!
//! Run: `cargo run --release --example walker -- [--out out/walker.svg]`

use lagrange::prelude::*;
use lagrange::sensitivity::PeriodicOrbit;
use lagrange_examples::cli;
use lagrange_examples::walker_system::CompassGait;
use plotters::prelude::*;

const USAGE: &str = "usage: cargo run --release --example walker -- [--out PATH.svg]
  --out PATH   the bifurcation diagram (default out/walker.svg)
";

fn options() -> Result<String, String> {
    let mut out = "out/walker.svg".to_string();
    for (key, val) in cli::pairs()? {
        match key.as_str() {
            "--out" => out = val,
            _ => return Err(format!("unknown option {key}")),
        }
    }
    Ok(out)
}

fn tight() -> Method {
    Method::Dop853 {
        rtol: 1e-13,
        atol: 1e-15,
    }
}

/// The multipliers of a gait, largest first, as "a ± bi" or "a".
fn show_multipliers(orbit: &PeriodicOrbit<2>) -> String {
    let mut m = orbit.multipliers.clone();
    m.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    m.iter()
        .filter(|z| z.im >= 0.0)
        .map(|z| {
            if z.im.abs() < 1e-12 {
                format!("{:.12}", z.re)
            } else {
                format!("{:.12} ± {:.12}i", z.re, z.im)
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The smallest real part among the multipliers (a period doubling: it passes −1).
fn most_negative(orbit: &PeriodicOrbit<2>) -> f64 {
    orbit
        .multipliers
        .iter()
        .map(|z| z.re)
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let out = cli::or_exit(options(), USAGE);

    // The simplest walker, from Garcia et al.'s published state just after a heel strike.
    let simplest = CompassGait::simplest(0.009);
    let (th, thd) = (0.20031090049483, -0.19983247291764);
    let (q, v) = simplest.from_garcia_state(&[th, thd, 2.0 * th, (1.0 - (2.0 * th).cos()) * thd]);
    let (qm, vm) = simplest.to_mid_stance(q, v, tight())?;
    let orbit = simplest.gait(qm, vm, 4.0, tight())?;
    let (qs, vs) = simplest.after_strike(orbit.q0, orbit.qdot0, tight())?;
    let x = simplest.garcia_state(&qs, &vs);
    println!("simplest walker (Garcia et al. 1998), γ = 0.009, long-step gait:");
    println!(
        "  after the heel strike θ = {:.14}, θ̇ = {:.14}   (published {th}, {thd})",
        x[0], x[1]
    );
    println!(
        "  step time {:.12}, {} Newton iterations",
        orbit.period, orbit.iterations
    );
    println!("  multipliers {}", show_multipliers(&orbit));
    println!("  (published −0.19120868949940 ± 0.55633363687106i: see docs/ERRATA.md)");
    // Its short-step gait, unstable: Newton finds it all the same.
    let (th, thd) = (0.19393736960624, -0.20386692731962);
    let (q, v) = simplest.from_garcia_state(&[th, thd, 2.0 * th, (1.0 - (2.0 * th).cos()) * thd]);
    let (qm, vm) = simplest.to_mid_stance(q, v, tight())?;
    let orbit = simplest.gait(qm, vm, 4.0, tight())?;
    let (qs, vs) = simplest.after_strike(orbit.q0, orbit.qdot0, tight())?;
    let x = simplest.garcia_state(&qs, &vs);
    println!(
        "  short-step gait: θ = {:.14}, θ̇ = {:.14}   (published {th}, {thd})",
        x[0], x[1]
    );
    println!(
        "  multipliers {}   (published 4.000, 0.459), {}",
        show_multipliers(&orbit),
        orbit.stability
    );

    // Goswami's walker at 3°: walk it from a rough start until it settles, then shoot.
    let w = CompassGait::goswami(3.0);
    let (q0, v0) = w.to_mid_stance([-0.27, 0.27], [1.1, 0.4], tight())?;
    let settled = Simulation::new(&w, q0, v0)
        .method(tight())
        .event(w.heel_strike_event())
        .until(20.0)
        .keep_samples(false)
        .run()?;
    let (q1, v1) = settled
        .jumps
        .last()
        .map(|j| j.after)
        .ok_or("the walker took no step")?;
    let (qm, vm) = w.to_mid_stance(q1, v1, tight())?;
    let orbit = w.gait(qm, vm, 1.0, tight())?;
    let (qs, vs) = w.after_strike(orbit.q0, orbit.qdot0, tight())?;
    // Goswami's angles: from the vertical, the leg that just landed first.
    let gos = [-qs[0] - w.slope, -qs[1] - w.slope, -vs[0], -vs[1]];
    println!("\nGoswami's walker (m_H = 10, m = 5, a = b = 0.5, g = 9.8) at 3°:");
    println!(
        "  after the heel strike ({:.4}, {:.4}, {:.4}, {:.4})   (published 0.2187, −0.3234, \
         −1.0918, −0.3772)",
        gos[0], gos[1], gos[2], gos[3]
    );
    println!(
        "  step time {:.12}, step length {:.12}",
        orbit.period,
        2.0 * w.leg() * qs[1].sin()
    );
    println!("  multipliers {}", show_multipliers(&orbit));

    // Follow the gait up the slope until a multiplier passes −1.
    let (mut deg, mut prev) = (3.0, orbit);
    let doubling = loop {
        let next_deg = deg + 0.2;
        let wn = CompassGait::goswami(next_deg);
        let (qg, vg) = wn.to_mid_stance(prev.q0, prev.qdot0, tight())?;
        let next = wn.gait(qg, vg, prev.period, tight())?;
        if most_negative(&next) < -1.0 {
            // The secant on the multiplier's real part + 1, refined twice.
            let (mut lo, mut hi) = (
                (deg, most_negative(&prev)),
                (next_deg, most_negative(&next)),
            );
            let mut start = (prev.q0, prev.qdot0, prev.period);
            for _ in 0..6 {
                let d = lo.0 + (hi.0 - lo.0) * (-1.0 - lo.1) / (hi.1 - lo.1);
                let wd = CompassGait::goswami(d);
                let (qg, vg) = wd.to_mid_stance(start.0, start.1, tight())?;
                let o = wd.gait(qg, vg, start.2, tight())?;
                let r = most_negative(&o);
                if r < -1.0 {
                    hi = (d, r);
                } else {
                    lo = (d, r);
                    start = (o.q0, o.qdot0, o.period);
                }
                if (r + 1.0).abs() < 1e-10 {
                    break;
                }
            }
            break if (lo.1 + 1.0).abs() < (hi.1 + 1.0).abs() {
                lo.0
            } else {
                hi.0
            };
        }
        deg = next_deg;
        prev = next;
    };
    println!("  the period-one gait's multiplier passes −1 at γ = {doubling:.6}°: period doubling");

    // The bifurcation diagram: walk 120 steps at each slope, keep the last 24 inter-leg angles.
    let slopes: Vec<f64> = (0..=90).map(|k| 2.0 + 0.04 * k as f64).collect();
    let mut points = Vec::new();
    let (mut qa, mut va) = (q1, v1);
    for &d in &slopes {
        let wd = CompassGait::goswami(d);
        let fallen = Event::zero_crossing("fallen", |_t, q: &[f64; 2], _v| 1.2 - q[0].abs())
            .falling()
            .terminal();
        let run = Simulation::new(&wd, qa, va)
            .method(Method::Dop853 {
                rtol: 1e-10,
                atol: 1e-12,
            })
            .event(wd.heel_strike_event())
            .event(fallen)
            .until(120.0 * 0.75)
            .keep_samples(false)
            .run()?;
        if run.terminated_by.is_some() || run.jumps.len() < 60 {
            println!("  at γ = {d:.2}° the walker falls");
            break;
        }
        for j in run.jumps.iter().rev().take(24) {
            points.push((d, 2.0 * j.after.0[1].to_degrees()));
        }
        if let Some(j) = run.jumps.last() {
            (qa, va) = j.after;
        }
    }
    // The inter-leg angles the settled walk takes at the grid's slope nearest d.
    let distinct = |d: f64| {
        let near = slopes
            .iter()
            .copied()
            .min_by(|a, b| (a - d).abs().total_cmp(&(b - d).abs()))
            .unwrap_or(d);
        let mut a: Vec<f64> = points.iter().filter(|p| p.0 == near).map(|p| p.1).collect();
        a.sort_by(f64::total_cmp);
        a.dedup_by(|x, y| (*x - *y).abs() < 1e-6);
        a.len()
    };
    let last = points.last().map(|p| p.0).unwrap_or(2.0);
    println!(
        "  the settled walk takes {} inter-leg angle(s) at 3°, {} at {:.2}°, {} at {last:.2}°",
        distinct(3.0),
        distinct(doubling + 0.2),
        doubling + 0.2,
        distinct(last)
    );

    if let Some(dir) = std::path::Path::new(&out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let root = SVGBackend::new(&out, (900, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let (ymin, ymax) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("compass-gait walker (Goswami): period doubling at γ = {doubling:.4}°"),
            ("sans-serif", 20),
        )
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(2.0..last + 0.1, ymin - 0.5..ymax + 0.5)?;
    chart
        .configure_mesh()
        .x_desc("slope γ (degrees)")
        .y_desc("inter-leg angle at heel strike (degrees)")
        .draw()?;
    chart.draw_series(
        points
            .iter()
            .map(|&(x, y)| Circle::new((x, y), 2, BLUE.filled())),
    )?;
    chart.draw_series(LineSeries::new(
        [(doubling, ymin - 0.5), (doubling, ymax + 0.5)],
        RED.stroke_width(1),
    ))?;
    root.present()?;
    println!("\nwrote {out}");
    Ok(())
}
