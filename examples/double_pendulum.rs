//! Double pendulum declared with `#[lagrangian]`: small-amplitude normal modes against theory,
//! and energy conservation in the chaotic regime.
//!
//! For equal masses and lengths the linearized equations have normal modes
//! ω² = (2 ∓ √2) g/l with amplitude ratios θ₂/θ₁ = ±√2. Starting exactly in one mode, the
//! measured period (between successive downward crossings of θ₁ = 0) must be 2π/ω up to the
//! O(θ²) anharmonic correction.
//!
//! Run: `cargo run --release --example double_pendulum [amplitude_rad]` (default 0.01).

use lagrange::prelude::*;
#[allow(dead_code)] // each example uses a part of the shared command-line helpers
use lagrange_examples::cli;

use double_pendulum_system::DoublePendulum;
use lagrange_examples::double_pendulum_system;

fn usage() -> ! {
    eprintln!("usage: double_pendulum [amplitude_rad]   (a small angle, default 0.01)");
    std::process::exit(2)
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let amp: f64 = match args.as_slice() {
        [] => 0.01,
        [a] => a.parse().unwrap_or_else(|_| usage()),
        _ => usage(),
    };
    let (g, l) = (9.81, 1.0);
    let p = DoublePendulum {
        m1: 1.0,
        m2: 1.0,
        l1: l,
        l2: l,
        g,
    };

    println!("Double pendulum, m1 = m2 = 1, l1 = l2 = {l}, g = {g}; mode amplitude θ₁ = {amp} rad");
    println!(
        "{:<6} {:>12} {:>14} {:>14} {:>10}",
        "mode", "θ₂/θ₁", "T theory", "T measured", "rel. diff"
    );
    let sqrt2 = std::f64::consts::SQRT_2;
    for (name, ratio, omega2) in [
        ("slow", sqrt2, (2.0 - sqrt2) * g / l),
        ("fast", -sqrt2, (2.0 + sqrt2) * g / l),
    ] {
        let period = 2.0 * std::f64::consts::PI / omega2.sqrt();
        // Start at maximum displacement (θ̇ = 0) along the mode shape.
        let traj = Simulation::new(&p, [amp, ratio * amp], [0.0, 0.0])
            .method(Method::Dop853 {
                rtol: 1e-12,
                atol: 1e-14,
            })
            .until(3.5 * period)
            .event(Event::zero_crossing("θ₁ = 0 falling", |_t, q: &[f64; 2], _v| q[0]).falling())
            .run()?;
        let ts: Vec<f64> = traj.events.iter().map(|h| h.t).collect();
        if ts.len() < 2 {
            return Err(format!("only {} crossings found", ts.len()).into());
        }
        let measured = (ts[ts.len() - 1] - ts[0]) / (ts.len() - 1) as f64;
        println!(
            "{name:<6} {ratio:>12.6} {period:>14.9} {measured:>14.9} {:>10.2e}",
            (measured - period) / period
        );
    }
    println!("(the difference is the O(θ²) anharmonic shift: try a smaller amplitude)");

    // Large amplitude: chaotic, but the energy must be conserved by the integrator.
    let traj = Simulation::new(&p, [2.0, -1.0], [0.0, 3.0])
        .method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(60.0)
        .sample_every(0.05)
        .run()?;
    let inv = traj.invariants();
    let last = traj.q.last().copied().unwrap_or([f64::NAN; 2]);
    println!();
    println!(
        "chaotic run θ(0) = (2, −1), θ̇(0) = (0, 3), t = 60: {} steps, θ(60) = ({:.6}, {:.6})",
        traj.stats.steps, last[0], last[1]
    );
    if let Some(e) = inv.energy {
        println!(
            "energy E = {:.9}, max relative drift {:.2e}",
            e.initial, e.max_rel
        );
    }
    // The first 20 s of the chaotic run, to watch.
    let watch = Simulation::new(&p, [2.0, -1.0], [0.0, 3.0])
        .until(20.0)
        .sample_every(0.01)
        .run()?;
    cli::write_animation("out/double_pendulum.svg", "double pendulum", &watch, &p)?;
    Ok(())
}
