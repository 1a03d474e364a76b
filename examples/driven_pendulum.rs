//! The damped driven pendulum: a Rayleigh dissipation function and a generalized force declared
//! next to the Lagrangian, a Poincaré section strobed at the drive period, and the energy balance.
//!
//! m l² θ̈ + b θ̇ + m g l sin θ = a cos(ω t), written as
//! L = ½ m l² θ̇² + m g l cos θ, D = ½ b θ̇², Q = a cos(ω t). With m = l = g = 1, b = ½ and
//! ω = ⅔ (Baker and Gollub's pendulum), a drive a = 0.9 settles on a period-1 orbit (the section
//! is one point) while a = 1.5 is chaotic (the section fills a strange attractor). The
//! energy is not conserved: the trajectory records the work W(t) done by the drive and the
//! friction, and h(t) − h(t0) − W(t) stays at the integrator's error.
//!
//! Run: `cargo run --release --example driven_pendulum -- [--periods 3000] [--out out/driven_pendulum.svg]`

use lagrange_examples::cli;

use lagrange::prelude::*;
use plotters::prelude::*;
use std::f64::consts::PI;

use driven_pendulum_system::DrivenPendulum;
use lagrange_examples::driven_pendulum_system;

const USAGE: &str =
    "usage: cargo run --release --example driven_pendulum -- [--periods N] [--out PATH.svg]
  --periods N  drive periods strobed after the transient (default 3000, at least 10)
  --out PATH   the figure (default out/driven_pendulum.svg)
";

struct Options {
    periods: usize,
    out: String,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        periods: 3000,
        out: "out/driven_pendulum.svg".into(),
    };
    for (key, val) in cli::pairs()? {
        match key.as_str() {
            "--periods" => {
                let n = cli::number(&key, &val)?;
                if !(10.0..=1e6).contains(&n) || n.fract() != 0.0 {
                    return Err(format!(
                        "--periods: a whole number from 10 to 10⁶, not {val}"
                    ));
                }
                o.periods = n as usize;
            }
            "--out" => o.out = val,
            _ => return Err(format!("unknown option {key}")),
        }
    }
    Ok(o)
}

/// θ wrapped into (−π, π].
fn wrap(theta: f64) -> f64 {
    let x = (theta + PI).rem_euclid(2.0 * PI) - PI;
    if x == -PI {
        PI
    } else {
        x
    }
}

/// The strobed points (θ wrapped, θ̇) after `transient` drive periods, and the run's largest
/// energy-balance residual.
fn section(
    p: &DrivenPendulum,
    transient: usize,
    periods: usize,
) -> Result<(Vec<(f64, f64)>, f64), SimulationError> {
    let period = 2.0 * PI / p.w;
    let traj = Simulation::new(p, [0.2], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-11,
            atol: 1e-11,
        })
        .until((transient + periods) as f64 * period)
        .sample_every(period)
        .run()?;
    let points = traj
        .q
        .iter()
        .zip(&traj.qdot)
        .skip(transient + 1)
        .map(|(q, v)| (wrap(q[0]), v[0]))
        .collect();
    let balance = traj
        .invariants()
        .energy_balance
        .map_or(f64::NAN, |d| d.max_abs);
    Ok((points, balance))
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = cli::or_exit(options(), USAGE);
    let pendulum = |a: f64| DrivenPendulum {
        m: 1.0,
        l: 1.0,
        g: 1.0,
        b: 0.5,
        a,
        w: 2.0 / 3.0,
    };
    println!(
        "Damped driven pendulum, m = l = g = 1, b = 0.5, ω = 2/3 (drive period {:.4})",
        3.0 * PI
    );
    println!(
        "Equations of motion derived by #[lagrangian]:\n{}\n",
        DrivenPendulum::EQUATIONS
    );
    println!(
        "flags: ENERGY_CONSERVED = {}, MOMENTUM_CONSERVED = {:?}",
        <DrivenPendulum as Lagrangian<1>>::ENERGY_CONSERVED,
        <DrivenPendulum as Lagrangian<1>>::MOMENTUM_CONSERVED
    );

    let transient = 200;
    let mut panels = Vec::new();
    for (name, a) in [("regular", 0.9), ("chaotic", 1.5)] {
        let (points, balance) = match section(&pendulum(a), transient, o.periods) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("error: the {name} run (a = {a}) failed: {e}");
                std::process::exit(1);
            }
        };
        let spread = |f: fn(&(f64, f64)) -> f64| {
            let (lo, hi) = points
                .iter()
                .map(f)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                });
            hi - lo
        };
        println!(
            "a = {a} ({name}): {} strobed points after {transient} periods; spread of θ {:.2e} rad, of θ̇ {:.2e} rad/s",
            points.len(),
            spread(|p| p.0),
            spread(|p| p.1),
        );
        println!("  energy balance: max |h(t) − h(t0) − W(t)| = {balance:.2e}");
        panels.push((name, a, points));
    }
    println!("(a period-1 orbit strobes to one point; the chaotic attractor spreads over the whole circle)");

    if let Some(dir) = std::path::Path::new(&o.out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let root = SVGBackend::new(&o.out, (1200, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let areas = root.split_evenly((1, 2));
    for (area, (name, a, points)) in areas.iter().zip(&panels) {
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!("Poincaré section, a = {a} ({name}), strobed at t = k·2π/ω"),
                ("sans-serif", 17),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(-PI..PI, -3.0..3.0)?;
        chart
            .configure_mesh()
            .x_desc("θ (rad)")
            .y_desc("θ̇ (rad/s)")
            .draw()?;
        let radius = if points.len() < 50 { 4 } else { 1 };
        chart.draw_series(
            points
                .iter()
                .map(|&(x, y)| Circle::new((x, y), radius, BLUE.mix(0.7).filled())),
        )?;
    }
    root.present()?;
    println!("figure: {}", o.out);
    Ok(())
}
