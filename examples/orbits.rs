//! Sensitivities and periodic orbits: the variational equations integrated with the
//! motion give the state transition matrix Φ = ∂(q, q̇)(t)/∂(q₀, q̇₀), the sensitivity of an
//! event's time and of the motion to a parameter, the monodromy matrix of a periodic orbit found
//! by shooting, its Floquet multipliers, and Lyapunov exponents.
//!
//! - a pendulum (g = l = 1) from rest at θ₀ = 1.3: its period from the turning-point event and
//!   dT/dθ₀, dT/dg from the event-time sensitivity, against the closed forms through K(k), E(k);
//! - the figure-eight choreography of three unit masses by shooting: period, closure,
//!   symplecticity of the monodromy, multipliers; and from rough initial data (2 digits) to a
//!   member of its family, recognized by the scale-invariant T |E|^{3/2};
//! - the damped driven pendulum of `driven_pendulum`: its period-1 orbit (Liouville's
//!   det M = e^{−bT}), the multipliers of its stable period-1 orbit as the drive a grows (the
//!   symmetric orbit gives way to an asymmetric one at a ≈ 1, a multiplier through +1; that one
//!   has a multiplier through −1 at a ≈ 1.066: it loses stability and the motion doubles its
//!   period), and the Lyapunov spectrum on the strange attractor (a = 1.5), whose sum is
//!   −b/(m l²).
//!
//! Run: `cargo run --release --example orbits -- [--out out/orbits.svg]`

use lagrange::prelude::*;
use lagrange::sensitivity::{Lyapunov, PeriodicOrbit, Shooting};
use lagrange::DMatrix;
use lagrange_examples::cli;
use lagrange_examples::driven_pendulum_system::DrivenPendulum;
use lagrange_examples::pendulum_system::{period, Pendulum};
use lagrange_examples::three_body_system::{
    FIGURE_EIGHT_PERIOD, FIGURE_EIGHT_Q0, FIGURE_EIGHT_V0, UNIT,
};
use plotters::prelude::*;
use std::f64::consts::PI;

const USAGE: &str = "usage: cargo run --release --example orbits -- [--out PATH.svg]
  --out PATH   the figure (default out/orbits.svg)
";

fn pendulum_period() -> Result<(), Box<dyn std::error::Error>> {
    let (theta0, g, l) = (1.3_f64, 1.0, 1.0);
    let p = Pendulum { g, l };
    let run = Simulation::new(&p, [theta0], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-13,
        })
        .until(10.0)
        .event(
            Event::zero_crossing("theta max", |_t, _q, v: &[f64; 1]| v[0])
                .falling()
                .terminal(),
        )
        .sensitivity()
        .parameter("g", g, |g| Pendulum { g, l })
        .run()?;
    let ev = run.events.first().ok_or("the pendulum did not come back")?;
    let dt = ev.dt_dx0.as_ref().ok_or("grazing turning point")?;
    let dtdg = ev.dt_dp.as_ref().ok_or("grazing turning point")?[0];
    let (t_closed, dt_closed) = period(theta0, g, l);
    println!("Pendulum g = l = 1 from rest at θ₀ = 1.3 (event θ̇ = 0, θ max; DOP853 at 1e-13):");
    println!("pendulum T = {:.15}", ev.t);
    println!("pendulum dT/dtheta0 = {:.15}", dt[0]);
    println!("pendulum dT/dg = {:.15}", dtdg);
    println!(
        "  closed forms 4√(l/g) K(k) = {t_closed:.15}, dT/dθ₀ = {dt_closed:.15}, −T/2g = {:.15}",
        -t_closed / (2.0 * g)
    );
    println!(
        "  errors {:.1e}, {:.1e}, {:.1e}\n",
        (ev.t - t_closed).abs(),
        (dt[0] - dt_closed).abs(),
        (dtdg + t_closed / (2.0 * g)).abs()
    );
    Ok(())
}

/// The energy of the three bodies at (q, q̇).
fn energy(q: &[f64; 6], v: &[f64; 6]) -> f64 {
    UNIT.energy(q, v, 0.0)
}

/// ‖MᵀJM − J‖ (largest entry): the masses are 1, so (q, q̇) are canonical.
fn symplecticity(m: &DMatrix<f64>) -> f64 {
    let n = m.nrows() / 2;
    let j = DMatrix::from_fn(2 * n, 2 * n, |r, c| {
        if c == r + n {
            1.0
        } else if r == c + n {
            -1.0
        } else {
            0.0
        }
    });
    (m.transpose() * &j * m - &j).amax()
}

fn figure_eight() -> Result<PeriodicOrbit<6>, Box<dyn std::error::Error>> {
    let method = Method::Dop853 {
        rtol: 1e-13,
        atol: 1e-13,
    };
    let orbit = Shooting::autonomous(&UNIT, FIGURE_EIGHT_Q0, FIGURE_EIGHT_V0, FIGURE_EIGHT_PERIOD)
        .method(method)
        .tolerance(1e-12)
        .find()?;
    println!(
        "Figure-eight, three unit masses, G = 1 (shooting from the 8-digit data, DOP853 at 1e-13):"
    );
    println!("figure-eight T = {:.12}", orbit.period);
    println!("figure-eight closure = {:.2e}", orbit.closure);
    println!(
        "figure-eight symplecticity = {:.2e}",
        symplecticity(&orbit.monodromy)
    );
    println!(
        "  {} Newton iteration(s); multipliers |μ| − 1: {}; {}",
        orbit.iterations,
        orbit
            .multipliers
            .iter()
            .map(|m| format!("{:+.1e}", m.norm() - 1.0))
            .collect::<Vec<_>>()
            .join(" "),
        orbit.stability
    );
    let invariant = |o: &PeriodicOrbit<6>| o.period * energy(&o.q0, &o.qdot0).abs().powf(1.5);
    // Rough data: every number to 2 digits.
    let round = |x: &[f64; 6]| x.map(|v| (v * 100.0).round() / 100.0);
    let rough = Shooting::autonomous(&UNIT, round(&FIGURE_EIGHT_Q0), round(&FIGURE_EIGHT_V0), 6.3)
        .method(method)
        .tolerance(1e-11)
        .max_iterations(50)
        .find()?;
    let (ir, io) = (invariant(&rough), invariant(&orbit));
    println!(
        "  from 2-digit data: T = {:.9}, closure {:.1e} after {} iterations; the scale-invariant \
         T|E|^(3/2) = {ir:.9} against the 8-digit orbit's {io:.9} (relative difference {:.1e}): \
         the figure-eight at another scale\n",
        rough.period,
        rough.closure,
        rough.iterations,
        (ir / io - 1.0).abs()
    );
    Ok(orbit)
}

fn three_body_paths(orbit: &PeriodicOrbit<6>) -> Result<Vec<Vec<(f64, f64)>>, SimulationError> {
    let tr = Simulation::new(&UNIT, orbit.q0, orbit.qdot0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(orbit.period)
        .sample_every(orbit.period / 400.0)
        .run()?;
    Ok((0..3)
        .map(|b| tr.q.iter().map(|q| (q[2 * b], q[2 * b + 1])).collect())
        .collect())
}

/// The driven pendulum of the `driven_pendulum` example at drive a.
fn driven(a: f64) -> DrivenPendulum {
    DrivenPendulum {
        m: 1.0,
        l: 1.0,
        g: 1.0,
        b: 0.5,
        a,
        w: 2.0 / 3.0,
    }
}

/// (a, the two multipliers as (Re, Im)) along the drive sweep.
type Sweep = Vec<(f64, [(f64, f64); 2])>;
/// The Lyapunov run's convergence: (elapsed time, the running exponents).
type History = Vec<(f64, Vec<f64>)>;

fn driven_pendulum() -> Result<(Sweep, History), Box<dyn std::error::Error>> {
    let period = 3.0 * PI;
    let method = Method::Dop853 {
        rtol: 1e-12,
        atol: 1e-12,
    };
    // The period-1 orbit at a = 0.9, from a state strobed after a transient.
    let p = driven(0.9);
    let t0 = 30.0 * period;
    let tr = Simulation::new(&p, [0.0], [0.0])
        .method(method)
        .until(t0)
        .run()?;
    let (mut q, mut v) = match (tr.q.last(), tr.qdot.last()) {
        (Some(q), Some(v)) => (*q, *v),
        _ => return Err("no state after the transient".into()),
    };
    println!("Damped driven pendulum m = l = g = 1, b = 0.5, ω = 2/3 (T = 3π), period-1 orbits:");
    let mut sweep = Vec::new();
    let mut reported = false;
    let n = 60;
    for i in 0..=n {
        let a = 0.9 + 0.2 * i as f64 / n as f64;
        if a > 1.09 {
            // Past the period doubling the motion settles on the period-2 orbit.
            break;
        }
        // The motion settles on the stable period-1 orbit (after the symmetric orbit's
        // pitchfork, on one of the two asymmetric ones): 40 drive periods from the last orbit,
        // nudged off the symmetric one, then shooting (the system is 3π-periodic in t, so the
        // state at t₀ + 40T is a guess at t₀).
        let settle = Simulation::new(&driven(a), q, [v[0] + 1e-3])
            .method(method)
            .start_time(t0)
            .until(t0 + 40.0 * period)
            .keep_samples(false)
            .run()?;
        if let (Some(qs), Some(vs)) = (settle.q.last(), settle.qdot.last()) {
            (q, v) = (*qs, *vs);
        }
        let orbit = Shooting::forced(&driven(a), q, v, period)
            .start_time(t0)
            .method(method)
            .tolerance(1e-10)
            .find()?;
        (q, v) = (orbit.q0, orbit.qdot0);
        let mu = &orbit.multipliers;
        if i == 0 {
            let m = &orbit.monodromy;
            let det = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
            let want = (-p.b / (p.m * p.l * p.l) * period).exp();
            println!(
                "driven pendulum liouville = {:.2e}",
                (det / want - 1.0).abs()
            );
            println!(
                "  a = 0.9: θ₀ = {:.6}, θ̇₀ = {:.6} at t₀ = 30T; det M = {det:.12e} against e^(−bT) = {want:.12e}",
                orbit.q0[0], orbit.qdot0[0]
            );
        }
        let through = mu.iter().any(|m| m.im == 0.0 && m.re < -1.0);
        if i % 5 == 0 || (through && !reported) {
            println!(
                "  a = {a:.4}: θ₀ = {:+.4}, μ = {:+.4}{:+.4}i, {:+.4}{:+.4}i  ({})",
                orbit.q0[0], mu[0].re, mu[0].im, mu[1].re, mu[1].im, orbit.stability
            );
        }
        if through && !reported {
            println!(
                "  a multiplier has gone through −1: the period-1 orbit is unstable, the motion \
                 doubles its period"
            );
            reported = true;
        }
        sweep.push((a, [(mu[0].re, mu[0].im), (mu[1].re, mu[1].im)]));
    }
    let p = driven(1.5);
    let s = Lyapunov::new(&p, [0.0], [0.0])
        .transient(100.0 * period)
        .duration(1000.0 * period)
        .renormalize_every(period)
        .tolerances(1e-11, 1e-11)
        .compute()?;
    println!(
        "Lyapunov spectrum at a = 1.5 (strange attractor; QR every drive period over 1000 periods):"
    );
    println!(
        "  λ₁ = {:.6}, λ₂ = {:.6} (per unit time)",
        s.exponents[0], s.exponents[1]
    );
    println!("driven pendulum lyapunov sum = {:.12}", s.sum());
    println!(
        "driven pendulum lyapunov expected = {:.12}",
        -p.b / (p.m * p.l * p.l)
    );
    Ok((sweep, s.history))
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let out = cli::or_exit(
        cli::pairs().and_then(|pairs| {
            let mut out = "out/orbits.svg".to_string();
            for (key, val) in pairs {
                match key.as_str() {
                    "--out" => out = val,
                    _ => return Err(format!("unknown option {key}")),
                }
            }
            Ok(out)
        }),
        USAGE,
    );
    pendulum_period()?;
    let orbit = figure_eight()?;
    let paths = three_body_paths(&orbit)?;
    let (sweep, history) = driven_pendulum()?;

    if let Some(dir) = std::path::Path::new(&out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let root = SVGBackend::new(&out, (1500, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let areas = root.split_evenly((1, 3));
    let colors = [RED, BLUE, GREEN];
    {
        let mut chart = ChartBuilder::on(&areas[0])
            .caption(
                format!("figure-eight, T = {:.8}", orbit.period),
                ("sans-serif", 17),
            )
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(44)
            .build_cartesian_2d(-1.2..1.2, -0.6..0.6)?;
        chart.configure_mesh().x_desc("x").y_desc("y").draw()?;
        for (b, path) in paths.iter().enumerate() {
            chart.draw_series(LineSeries::new(
                path.iter().copied(),
                colors[b].stroke_width(2),
            ))?;
            if let Some(&(x, y)) = path.first() {
                chart.draw_series(std::iter::once(Circle::new((x, y), 5, colors[b].filled())))?;
            }
        }
    }
    {
        let a_max = sweep.last().map_or(1.1, |s| s.0);
        let mut chart = ChartBuilder::on(&areas[1])
            .caption(
                "driven pendulum, stable period-1 orbit: Floquet multipliers (Re μ)",
                ("sans-serif", 17),
            )
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(44)
            .build_cartesian_2d(0.9..a_max, -2.5..0.5)?;
        chart
            .configure_mesh()
            .x_desc("drive a")
            .y_desc("Re μ")
            .draw()?;
        chart.draw_series(LineSeries::new(
            [(0.9, -1.0), (a_max, -1.0)],
            BLACK.mix(0.5),
        ))?;
        for k in 0..2 {
            chart.draw_series(
                sweep
                    .iter()
                    .map(|(a, mu)| Circle::new((*a, mu[k].0), 3, colors[k].filled())),
            )?;
        }
    }
    {
        let t_max = history.last().map_or(1.0, |h| h.0);
        let mut chart = ChartBuilder::on(&areas[2])
            .caption(
                "Lyapunov exponents at a = 1.5 as the run goes",
                ("sans-serif", 17),
            )
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(44)
            .build_cartesian_2d(0.0..t_max, -1.0..0.5)?;
        chart.configure_mesh().x_desc("t").y_desc("λ").draw()?;
        for k in 0..2 {
            chart.draw_series(LineSeries::new(
                history.iter().map(|(t, l)| (*t, l[k])),
                colors[k].stroke_width(2),
            ))?;
        }
        chart.draw_series(LineSeries::new(
            history.iter().map(|(t, l)| (*t, l[0] + l[1])),
            BLACK.stroke_width(1),
        ))?;
    }
    root.present()?;
    println!("figure: {out}");
    Ok(())
}

fn main() {
    cli::run_or_exit(report);
}
