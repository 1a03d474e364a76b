//! Impacts and unilateral contact, each system written as its Lagrangian and its contact gaps
//! (`fn contacts`), the impact law derived from M and the gaps' gradients
//! (`Simulation::new` runs them with their contacts): a bouncing ball whose impacts accumulate (Zeno) into resting
//! contact, a rocking block losing Housner's ratio 1 − (3/2) sin²α of its angular velocity at
//! each plastic impact, and a rimless wheel walking down a slope to its limit cycle
//! ω* = cot 2α √(4 (g/l) sin α sin γ), whose gait the shooting finds with its step-to-step
//! multiplier cos² 2α. Each against its closed form; the work column against the
//! kinetic energy each jump removes. Figures as SVG.
//!
//! Run: `cargo run --release --example impacts -- [--out out/impacts.svg]`

use lagrange::prelude::*;
use lagrange_examples::cli;
use lagrange_examples::contact_systems::{omega_star, Ball, Block, RimlessWheel, SPOKES};
use plotters::prelude::*;

const USAGE: &str = "usage: cargo run --release --example impacts -- [--out PATH.svg]
  --out PATH   the figure (default out/impacts.svg)
";

fn options() -> Result<String, String> {
    let mut out = "out/impacts.svg".to_string();
    for (key, val) in cli::pairs()? {
        match key.as_str() {
            "--out" => out = val,
            _ => return Err(format!("unknown option {key}")),
        }
    }
    Ok(out)
}

/// The kinetic energy each jump changes, ½ q̇ᵀ M q̇ after minus before (the positions do not
/// jump), from the mass matrix: an account of the impacts apart from the work column.
fn jumps_kinetic<L: Lagrangian<N>, const N: usize>(sys: &L, tr: &Trajectory<N>) -> f64 {
    let kinetic = |q: &[f64; N], v: &[f64; N], t: f64| {
        let m = sys.mass_matrix(q, v, t);
        let mut s = 0.0;
        for i in 0..N {
            for k in 0..N {
                s += 0.5 * v[i] * m[(i, k)] * v[k];
            }
        }
        s
    };
    tr.jumps
        .iter()
        .map(|j| kinetic(&j.after.0, &j.after.1, j.t) - kinetic(&j.before.0, &j.before.1, j.t))
        .sum()
}

/// |W − Σ ΔT| / |Σ ΔT| at the end of a run.
fn balance<L: Lagrangian<N>, const N: usize>(sys: &L, tr: &Trajectory<N>) -> f64 {
    let dt = jumps_kinetic(sys, tr);
    let w = tr.work.last().copied().unwrap_or(f64::NAN);
    (w - dt).abs() / dt.abs()
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let out = cli::or_exit(options(), USAGE);
    let tight = Method::Dop853 {
        rtol: 1e-12,
        atol: 1e-14,
    };

    // The ball: dropped from h with a horizontal speed.
    let (m, g, e, h, vx) = (0.7, 9.81, 0.8, 1.0, 0.3);
    let ball = Ball { m, g, e };
    println!(
        "bouncing ball: m = {m} kg, g = {g} m/s², e = {e}, dropped from h = {h} m at {vx} m/s"
    );
    let t1 = (2.0 * h / g).sqrt();
    let t_inf = t1 * (1.0 + e) / (1.0 - e);
    let ball_run = Simulation::new(&ball, [0.0, h], [vx, 0.0])
        .method(tight)
        .until(t_inf + 1.0)
        .sample_every(0.002)
        .run()?;
    let zeno = ball_run
        .zeno
        .as_ref()
        .ok_or("the ball's impacts did not accumulate")?;
    println!(
        "  {} impacts integrated, then resting contact with λ = {:.12} N (m g = {:.12} N)",
        zeno.hits,
        ball_run.lambda.last().map_or(f64::NAN, |l| l[0]),
        m * g
    );

    // The block: released from rest on its left corner, tilted by θ₀.
    let (b, hb, th0): (f64, f64, f64) = (0.2, 0.6, 0.2);
    let block = Block {
        m: 3.0,
        g,
        b,
        h: hb,
    };
    let alpha_b = (b / hb).atan();
    println!(
        "rocking block: half-width {b} m, half-height {hb} m (α = {alpha_b:.6} rad), released \
         from rest at θ = {th0} on a corner; sticking plastic corners"
    );
    let (x0, y0) = (
        b * th0.cos() - hb * th0.sin(),
        b * th0.sin() + hb * th0.cos(),
    );
    let block_run = Simulation::new(&block, [x0, y0, th0], [0.0; 3])
        .method(tight)
        .until(2.5)
        .sample_every(0.002)
        .run()?;
    let ratios: Vec<f64> = block_run
        .jumps
        .iter()
        .map(|j| j.after.1[2] / j.before.1[2])
        .collect();

    // The wheel: started just after an impact, 20 % faster than its limit cycle.
    let (l, gamma) = (1.0, 0.08);
    let wheel = RimlessWheel {
        m: 2.0,
        g,
        l,
        slope: gamma,
    };
    let alpha_w = std::f64::consts::PI / SPOKES as f64;
    let w_star = omega_star(&wheel);
    println!(
        "rimless wheel: {SPOKES} spokes (2α = {:.6} rad) of l = {l} m, slope γ = {gamma} rad, \
         started at 1.2 ω*",
        2.0 * alpha_w
    );
    let w0 = 1.2 * w_star;
    let q0 = [-l * alpha_w.sin(), l * alpha_w.cos(), alpha_w];
    let v0 = [l * w0 * alpha_w.cos(), l * w0 * alpha_w.sin(), -w0];
    let wheel_run = Simulation::new(&wheel, q0, v0)
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-15,
        })
        .until(130.0)
        .keep_samples(false)
        .run()?;
    let omegas: Vec<f64> = wheel_run.jumps.iter().map(|j| -j.after.1[2]).collect();
    println!("  {} steps", omegas.len());
    // Its gait by shooting (periodic up to one step on: x + 2l sin α, θ − 2α), from mid-stance
    // 3 % faster than the gait's |θ̇| there, ½ θ̇² + (g/l) cos(θ − γ) being the stance's
    // invariant: the step-to-step map's multipliers through the landing's saltation matrix.
    let mid_rate =
        (w_star * w_star + 2.0 * (g / l) * ((alpha_w - gamma).cos() - gamma.cos())).sqrt();
    let r0 = 1.03 * mid_rate;
    let gait = lagrange::sensitivity::Shooting::autonomous(
        &wheel,
        [0.0, l, 0.0],
        [l * r0, 0.0, -r0],
        2.0 * alpha_w / r0,
    )
    .method(tight)
    .shift([2.0 * l * alpha_w.sin(), 0.0, -2.0 * alpha_w])
    .find()?;
    let mut mods: Vec<f64> = gait.multipliers.iter().map(|z| z.norm()).collect();
    mods.sort_by(|a, b| b.total_cmp(a));
    println!(
        "  its gait by shooting: step time {:.12} s, multipliers {:?} (1, cos² 2α = {:.12}, and 0 \
         for the directions off the closed spoke)",
        gait.period,
        mods.iter().map(|m| format!("{m:.12}")).collect::<Vec<_>>(),
        (2.0 * alpha_w).cos().powi(2)
    );

    println!(
        "bouncing ball t_inf = {:.15} closed form = {t_inf:.15}",
        zeno.t_accumulation
    );
    println!(
        "rocking ratio = {:.15} closed form = {:.15}",
        ratios.first().copied().unwrap_or(f64::NAN),
        1.0 - 1.5 * alpha_b.sin().powi(2)
    );
    println!(
        "rimless wheel omega = {:.15} closed form = {w_star:.15}",
        omegas.last().copied().unwrap_or(f64::NAN)
    );
    let worst = [
        balance(&ball, &ball_run),
        balance(&block, &block_run),
        balance(&wheel, &wheel_run),
    ]
    .into_iter()
    .fold(0.0_f64, f64::max);
    println!("impact energy balance = {worst:.3e}");
    println!(
        "  (|W − Σ ΔT| / |Σ ΔT|: the work column against the kinetic energy the jumps change)"
    );

    if let Some(dir) = std::path::Path::new(&out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let root = SVGBackend::new(&out, (1500, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let areas = root.split_evenly((1, 3));

    let mut chart = ChartBuilder::on(&areas[0])
        .caption(
            format!("bouncing ball, e = {e}: resting from t∞ = {t_inf:.4} s"),
            ("sans-serif", 17),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..t_inf + 1.0, 0.0..h * 1.05)?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc("y (m)")
        .draw()?;
    chart.draw_series(LineSeries::new(
        ball_run.t.iter().zip(&ball_run.q).map(|(&t, q)| (t, q[1])),
        &BLUE,
    ))?;

    let mut chart = ChartBuilder::on(&areas[1])
        .caption(
            format!("rocking block: θ̇⁺/θ̇⁻ = 1 − (3/2) sin²α = {:.4}", ratios[0]),
            ("sans-serif", 17),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..2.5, -th0 * 1.05..th0 * 1.05)?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc("θ (rad)")
        .draw()?;
    chart.draw_series(LineSeries::new(
        block_run
            .t
            .iter()
            .zip(&block_run.q)
            .map(|(&t, q)| (t, q[2])),
        &RED,
    ))?;

    let errors: Vec<(f64, f64)> = omegas
        .iter()
        .enumerate()
        .map(|(k, w)| (k as f64, ((w - w_star).abs() / w_star).max(1e-16).log10()))
        .collect();
    let mut chart = ChartBuilder::on(&areas[2])
        .caption(
            format!("rimless wheel: ω⁺ → ω* = {w_star:.6} rad/s"),
            ("sans-serif", 17),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..omegas.len() as f64, -16.0..0.0)?;
    chart
        .configure_mesh()
        .x_desc("step")
        .y_desc("log₁₀ |ω⁺ − ω*| / ω*")
        .draw()?;
    chart.draw_series(
        errors
            .iter()
            .map(|&p| Circle::new(p, 3, BLUE.mix(0.8).filled())),
    )?;
    root.present()?;
    println!("figure: {out}");

    // To watch, next to the figure: the rocking block's run, and the wheel's first 12 s.
    let stem = out.strip_suffix(".svg").unwrap_or(&out);
    cli::write_animation(
        &format!("{stem}_block.svg"),
        "rocking block",
        &block_run,
        &block,
    )?;
    let wheel_watch = Simulation::new(&wheel, q0, v0)
        .until(12.0)
        .sample_every(0.01)
        .run()?;
    cli::write_animation(
        &format!("{stem}_rimless_wheel.svg"),
        "rimless wheel",
        &wheel_watch,
        &wheel,
    )?;
    Ok(())
}
