//! The damped driven pendulum's bifurcation diagram over the drive amplitude, on the ensemble API:
//! one member per amplitude a, run in parallel with a progress bar, each reduced to its Poincaré
//! section (θ̇ strobed once per drive period after the transient), drawn as SVG and written as CSV.
//!
//! θ̈ + b θ̇ + sin θ = a cos(ω t) with b = ½, ω = ⅔ (Baker and Gollub's pendulum, declared once in
//! examples/support/driven_pendulum_system.rs). As a grows from 1.0 the period-1 orbit doubles
//! (near a ≈ 1.07), doubles again, and the cascade ends in chaos (a ≈ 1.15), with windows of
//! periodic motion inside it.
//!
//! Run: `cargo run --release --example bifurcation -- [--members 1000] [--from 1.0] [--to 1.5]
//! [--transient 300] [--strobes 60] [--out out/bifurcation.svg] [--csv out/bifurcation.csv]
//! [--shard k/n]` (`--shard` runs block k of n of the members and writes only the CSV: a job
//! array's task; see the README's "Ensembles").

use lagrange_examples::cli;

use lagrange::prelude::*;
use plotters::prelude::*;
use std::f64::consts::PI;
use std::time::Instant;

use driven_pendulum_system::DrivenPendulum;
use lagrange_examples::driven_pendulum_system;

const USAGE: &str = "usage: cargo run --release --example bifurcation -- [options]
  --members N    drive amplitudes (members), at least 2 (1000)
  --from X       smallest amplitude (1.0)     --to X   largest amplitude (1.5)
  --transient N  drive periods left out before strobing (300)
  --strobes N    drive periods strobed per member (60)
  --out PATH     the figure (out/bifurcation.svg)
  --csv PATH     the strobed θ̇ per member (out/bifurcation.csv)
  --shard K/N    run block K of N of the members (0 ≤ K < N), write the CSV only
";

struct Options {
    members: usize,
    from: f64,
    to: f64,
    transient: usize,
    strobes: usize,
    out: String,
    csv: String,
    shard: Option<(usize, usize)>,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        members: 1000,
        from: 1.0,
        to: 1.5,
        transient: 300,
        strobes: 60,
        out: "out/bifurcation.svg".into(),
        csv: "out/bifurcation.csv".into(),
        shard: None,
    };
    let whole = |key: &str, val: &str, lo: f64| -> Result<usize, String> {
        let n = cli::number(key, val)?;
        if n < lo || n > 1e7 || n.fract() != 0.0 {
            return Err(format!("{key}: a whole number from {lo} to 10⁷, not {val}"));
        }
        Ok(n as usize)
    };
    for (key, val) in cli::pairs()? {
        match key.as_str() {
            "--members" => o.members = whole(&key, &val, 2.0)?,
            "--from" => o.from = cli::number(&key, &val)?,
            "--to" => o.to = cli::number(&key, &val)?,
            "--transient" => o.transient = whole(&key, &val, 0.0)?,
            "--strobes" => o.strobes = whole(&key, &val, 1.0)?,
            "--out" => o.out = val,
            "--csv" => o.csv = val,
            "--shard" => {
                let (k, n) = val
                    .split_once('/')
                    .ok_or_else(|| format!("--shard: K/N, not {val}"))?;
                let (k, n) = (whole(&key, k, 0.0)?, whole(&key, n, 1.0)?);
                if k >= n {
                    return Err(format!("--shard: K must be below N, not {val}"));
                }
                o.shard = Some((k, n));
            }
            _ => return Err(format!("unknown option {key}")),
        }
    }
    if !(o.from.is_finite() && o.to.is_finite() && o.from < o.to) {
        return Err("need finite --from < --to".into());
    }
    Ok(o)
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = cli::or_exit(options(), USAGE);
    let w = 2.0 / 3.0;
    let period = 2.0 * PI / w;
    let amplitude = |i: usize| o.from + (o.to - o.from) * i as f64 / (o.members - 1) as f64;
    let strobes: Vec<f64> = (o.transient..o.transient + o.strobes)
        .map(|k| (k + 1) as f64 * period)
        .collect();
    let t_end = strobes[strobes.len() - 1];
    let columns: Vec<String> = (0..o.strobes).map(|k| format!("thetadot_{k}")).collect();
    let column_refs: Vec<&str> = columns.iter().map(String::as_str).collect();
    let mut ensemble = Ensemble::new(o.members, |i| {
        let a = amplitude(i);
        let p = DrivenPendulum {
            m: 1.0,
            l: 1.0,
            g: 1.0,
            b: 0.5,
            a,
            w,
        };
        Member::new(p, [0.2], [0.0]).param("a", a)
    })
    .configure(|sim| {
        sim.method(Method::Dop853 {
            rtol: 1e-9,
            atol: 1e-11,
        })
        .until(t_end)
        .sample_at(strobes.iter().copied())
    })
    .progress(true);
    if let Some((k, n)) = o.shard {
        ensemble = ensemble.shard(k, n);
    }
    let members = ensemble.members();
    println!(
        "damped driven pendulum, b = 0.5, ω = 2/3: {} amplitudes from {} to {} (members {}..{}), {} transient + {} strobed periods each",
        o.members, o.from, o.to, members.start, members.end, o.transient, o.strobes
    );
    let start = Instant::now();
    let results = ensemble.reduce(&column_refs, |tr| {
        // The samples at the strobe times (the start sample t0 = 0 is not one of them).
        tr.t.iter()
            .zip(&tr.qdot)
            .filter(|(t, _)| **t > 0.0)
            .map(|(_, v)| v[0])
            .collect::<Vec<f64>>()
    });
    println!(
        "{} members in {:.2} s, {} failed",
        results.results.len(),
        start.elapsed().as_secs_f64(),
        results.failures()
    );
    for (i, r) in results.index.iter().zip(&results.results) {
        if let Err(e) = r {
            println!("  member {i} (a = {}): {e}", amplitude(*i));
        }
    }
    if let Some(dir) = std::path::Path::new(&o.csv).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    results.write_csv(&o.csv, o.shard.is_none_or(|(k, _)| k == 0))?;
    println!("CSV: {}", o.csv);
    if o.shard.is_some() {
        return Ok(());
    }

    // How many distinct strobed values (to 1e-4) each amplitude has: 1 for period 1, 2 after the
    // first doubling, 4, …, many in chaos.
    let distinct = |v: &[f64]| {
        let mut s: Vec<f64> = v.to_vec();
        s.sort_by(f64::total_cmp);
        s.dedup_by(|a, b| (*a - *b).abs() < 1e-4);
        s.len()
    };
    // Runs of equal counts over at least three neighbouring amplitudes (a lone member near a
    // bifurcation may not have settled within the transient).
    let counts: Vec<(f64, usize)> = results
        .index
        .iter()
        .zip(&results.results)
        .filter_map(|(i, r)| r.as_ref().ok().map(|v| (amplitude(*i), distinct(v).min(9))))
        .collect();
    let mut k = 0;
    while k < counts.len() {
        let mut e = k;
        while e + 1 < counts.len() && counts[e + 1].1 == counts[k].1 {
            e += 1;
        }
        if e - k >= 2 {
            let d = counts[k].1;
            let label = if d >= 9 {
                "≥ 9 (chaos or a long period)".to_string()
            } else {
                d.to_string()
            };
            println!(
                "  a = {:.4} … {:.4}: {label} strobed values",
                counts[k].0, counts[e].0
            );
        }
        k = e + 1;
    }

    if let Some(dir) = std::path::Path::new(&o.out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let root = SVGBackend::new(&o.out, (1200, 700)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Damped driven pendulum θ̈ + ½θ̇ + sin θ = a cos(⅔t): θ̇ strobed once per drive period",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(o.from..o.to, -3.0..3.0)?;
    chart
        .configure_mesh()
        .x_desc("drive amplitude a")
        .y_desc("θ̇ at t = k·2π/ω (rad/s)")
        .draw()?;
    for (i, r) in results.index.iter().zip(&results.results) {
        if let Ok(v) = r {
            let a = amplitude(*i);
            chart.draw_series(
                v.iter()
                    .map(|&y| Circle::new((a, y), 1, BLUE.mix(0.5).filled())),
            )?;
        }
    }
    root.present()?;
    println!("figure: {}", o.out);
    Ok(())
}
