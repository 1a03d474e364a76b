//! Linearization: a double pendulum's normal modes, and the sleeping top's eigenvalues swept
//! through its stability threshold Ω_c = 2ω₀ (Example 1 of the reference text).
//!
//! 1. The double pendulum (unequal masses and lengths) linearized about its rest position:
//!    ω² from K v = ω² M v against the roots of m₁l₁l₂ω⁴ − (m₁+m₂)g(l₁+l₂)ω² + (m₁+m₂)g² = 0, the
//!    mode shapes drawn as the pendulum displaced along each.
//! 2. The heavy symmetric top exactly upright in Tait–Bryan angles (regular there), spinning at
//!    s: with Ω = I∥s/I⊥ and ω₀² = mgl/I⊥ the tilt has λ = i(Ω ± √(Ω² − 4ω₀²))/2, a root locus
//!    whose complex pairs meet the imaginary axis at Ω = 2ω₀ (Re λ and Im λ against Ω/ω₀).
//!
//! Run: `cargo run --release --example modes -- [--from 0] [--to 4] [--points 161]
//!       [--modes-svg out/modes_double_pendulum.svg] [--locus-svg out/modes_sleeping_top.svg]`

use lagrange_examples::cli;

use lagrange::linearize::Stability;
use lagrange::prelude::*;
use plotters::prelude::*;

use double_pendulum_system::DoublePendulum;
use lagrange_examples::double_pendulum_system;

/// The heavy symmetric top in Tait–Bryan angles, R = Rx(α) Ry(β) Rz(γ), regular at the upright
/// (β = 0); body angular velocity ω = (α̇ cos β cos γ + β̇ sin γ, −α̇ cos β sin γ + β̇ cos γ,
/// α̇ sin β + γ̇), height of the centre of mass l cos α cos β.
pub struct UprightTop {
    pub i_perp: f64,
    pub i_par: f64,
    pub mgl: f64,
}

#[lagrangian]
impl UprightTop {
    fn lagrangian(&self, (a, a_dot): Coord, (b, b_dot): Coord, (c, c_dot): Coord) -> Scalar {
        let (w1, w2) = (
            a_dot * b.cos() * c.cos() + b_dot * c.sin(),
            -a_dot * b.cos() * c.sin() + b_dot * c.cos(),
        );
        let w3 = a_dot * b.sin() + c_dot;
        self.i_perp / 2.0 * (w1 * w1 + w2 * w2) + self.i_par / 2.0 * w3 * w3
            - self.mgl * a.cos() * b.cos()
    }
}

const USAGE: &str = "usage: modes [--from R (0)] [--to R (4)] [--points N (161)] \
[--modes-svg PATH (out/modes_double_pendulum.svg)] [--locus-svg PATH (out/modes_sleeping_top.svg)]
  --from, --to   range of Ω/ω0 for the sleeping top's root locus
  --points       number of spin rates in that range
";

struct Options {
    from: f64,
    to: f64,
    points: usize,
    modes_svg: String,
    locus_svg: String,
}

fn parse() -> Result<Options, String> {
    let mut o = Options {
        from: 0.0,
        to: 4.0,
        points: 161,
        modes_svg: "out/modes_double_pendulum.svg".into(),
        locus_svg: "out/modes_sleeping_top.svg".into(),
    };
    for (k, v) in cli::pairs()? {
        match k.as_str() {
            "--from" => o.from = cli::number(&k, &v)?,
            "--to" => o.to = cli::number(&k, &v)?,
            "--points" => o.points = cli::number(&k, &v)? as usize,
            "--modes-svg" => o.modes_svg = v,
            "--locus-svg" => o.locus_svg = v,
            _ => return Err(format!("unknown option {k}")),
        }
    }
    if !(o.from >= 0.0 && o.to > o.from && o.points >= 2) {
        return Err("need 0 ≤ from < to and points ≥ 2".into());
    }
    Ok(o)
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = cli::or_exit(parse(), USAGE);

    // 1. Double pendulum.
    let (m1, m2, l1, l2, g) = (1.3, 0.7, 0.9, 1.6, 9.81);
    let p = DoublePendulum { m1, m2, l1, l2, g };
    let bottom = lagrange::equilibrium(&p, &[0.3, -0.2], 0.0)?;
    let lin = p.linearize(&bottom, &[0.0, 0.0], 0.0)?;
    println!("double pendulum m1 = {m1}, m2 = {m2}, l1 = {l1}, l2 = {l2}, g = {g}");
    println!("  equilibrium from the guess (0.3, -0.2): {bottom:?}");
    println!("  M = {:.6}  K = {:.6}", lin.m, lin.k);
    let (a, b, c) = (m1 * l1 * l2, -(m1 + m2) * g * (l1 + l2), (m1 + m2) * g * g);
    let disc = (b * b - 4.0 * a * c).sqrt();
    let roots = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)];
    let modes = lin.modes()?;
    println!(
        "  {:<5} {:>22} {:>22} {:>9} {:>24}",
        "mode", "ω² (linearize)", "ω² (quartic)", "rel diff", "shape (M-normalized)"
    );
    for (k, (mode, w2)) in modes.iter().zip(roots).enumerate() {
        println!(
            "  {:<5} {:>22.15e} {:>22.15e} {:>9.1e}   ({:+.6}, {:+.6})",
            k + 1,
            mode.omega_squared,
            w2,
            ((mode.omega_squared - w2) / w2).abs(),
            mode.shape[0],
            mode.shape[1]
        );
    }
    println!("  stability: {:?}", lin.stability()?);
    draw_modes(&o.modes_svg, &p, &modes)?;
    println!("wrote {}\n", o.modes_svg);

    // 2. Sleeping top root locus (ω0 = 1).
    let top = UprightTop {
        i_perp: 1.0,
        i_par: 0.5,
        mgl: 1.0,
    };
    let w0 = (top.mgl / top.i_perp).sqrt();
    println!(
        "sleeping top upright, I⊥ = {}, I∥ = {}, mgl = {}: ω0 = {w0}, Ω_c = 2ω0",
        top.i_perp, top.i_par, top.mgl
    );
    println!("  Ω/ω0   max Re λ      stability          largest error vs i(Ω ± √(Ω² − 4ω0²))/2");
    let mut locus: Vec<(f64, Vec<Complex>)> = Vec::new();
    let every = (o.points / 16).max(1);
    for k in 0..o.points {
        let ratio = o.from + (o.to - o.from) * k as f64 / (o.points - 1) as f64;
        let spin = ratio * w0 * top.i_perp / top.i_par;
        let lin = top.linearize(&[0.0; 3], &[0.0, 0.0, spin], 0.0)?;
        let eig = lin.eigenvalues()?;
        let want = closed_form(ratio * w0, w0);
        let err = want
            .iter()
            .map(|w| {
                eig.iter()
                    .map(|l| ((l.re - w.0).powi(2) + (l.im - w.1).powi(2)).sqrt())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0_f64, f64::max);
        let stability = lin.stability()?;
        if k % every == 0 || k == o.points - 1 {
            let growth = eig.iter().map(|l| l.re).fold(f64::NEG_INFINITY, f64::max);
            let s = match stability {
                Stability::Unstable { .. } => "unstable",
                Stability::MarginallyStable => "marginal",
                Stability::AsymptoticallyStable => "asymptotic",
            };
            println!("  {ratio:5.3}  {growth:+.6e}  {s:<17}  {err:.1e}");
        }
        locus.push((ratio, eig.iter().map(|l| (l.re, l.im)).collect()));
    }
    draw_locus(&o.locus_svg, &locus, o.from, o.to)?;
    println!("wrote {}", o.locus_svg);
    Ok(())
}

type Complex = (f64, f64);

/// The four non-zero eigenvalues of the upright top's tilt (the spin angle adds λ = 0 twice).
fn closed_form(big_omega: f64, w0: f64) -> Vec<Complex> {
    let d = big_omega * big_omega - 4.0 * w0 * w0;
    if d >= 0.0 {
        let (hi, lo) = ((big_omega + d.sqrt()) / 2.0, (big_omega - d.sqrt()) / 2.0);
        vec![(0.0, hi), (0.0, -hi), (0.0, lo), (0.0, -lo)]
    } else {
        let (re, im) = ((-d).sqrt() / 2.0, big_omega / 2.0);
        vec![(re, im), (re, -im), (-re, im), (-re, -im)]
    }
}

fn draw_modes(
    path: &str,
    p: &DoublePendulum,
    modes: &[lagrange::linearize::Mode<2>],
) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let root = SVGBackend::new(path, (1000, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, modes.len()));
    let reach = p.l1 + p.l2;
    for (k, (area, mode)) in panels.iter().zip(modes).enumerate() {
        let w = mode.omega().unwrap_or(f64::NAN);
        let mut ch = ChartBuilder::on(area)
            .caption(
                format!(
                    "mode {}: ω = {w:.4} rad/s, θ₂/θ₁ = {:+.3}",
                    k + 1,
                    mode.shape[1] / mode.shape[0]
                ),
                ("sans-serif", 18),
            )
            .margin(15)
            .x_label_area_size(30)
            .y_label_area_size(40)
            .build_cartesian_2d(-reach..reach, -reach * 1.1..reach * 0.2)?;
        ch.configure_mesh().x_desc("x (m)").y_desc("y (m)").draw()?;
        // displaced along ±v, the largest angle 0.35 rad
        let scale = 0.35 / mode.shape.amax();
        for (sign, color) in [
            (1.0, BLUE.mix(1.0)),
            (-1.0, RED.mix(1.0)),
            (0.0, BLACK.mix(0.3)),
        ] {
            let th = [sign * scale * mode.shape[0], sign * scale * mode.shape[1]];
            let b1 = (p.l1 * th[0].sin(), -p.l1 * th[0].cos());
            let b2 = (b1.0 + p.l2 * th[1].sin(), b1.1 - p.l2 * th[1].cos());
            let style = color.stroke_width(2);
            ch.draw_series(LineSeries::new(vec![(0.0, 0.0), b1, b2], style))?;
            ch.draw_series(
                [b1, b2]
                    .into_iter()
                    .map(|c| Circle::new(c, 6, color.filled())),
            )?;
        }
    }
    root.present()?;
    Ok(())
}

fn draw_locus(
    path: &str,
    locus: &[(f64, Vec<Complex>)],
    from: f64,
    to: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let root = SVGBackend::new(path, (1000, 700)).into_drawing_area();
    root.fill(&WHITE)?;
    let (upper, lower) = root.split_vertically(350);
    let bound = |f: fn(&Complex) -> f64| {
        locus
            .iter()
            .flat_map(|(_, e)| e.iter().map(f))
            .fold(0.1_f64, |m, x| m.max(x.abs()))
            * 1.1
    };
    for (area, title, part, lim) in [
        (
            &upper,
            "Re λ",
            (|c: &Complex| c.0) as fn(&Complex) -> f64,
            bound(|c| c.0),
        ),
        (
            &lower,
            "Im λ",
            (|c: &Complex| c.1) as fn(&Complex) -> f64,
            bound(|c| c.1),
        ),
    ] {
        let mut ch = ChartBuilder::on(area)
            .caption(
                format!("sleeping top upright: {title} against Ω/ω0 (threshold Ω = 2ω0)"),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(from..to, -lim..lim)?;
        ch.configure_mesh().x_desc("Ω/ω0").y_desc(title).draw()?;
        ch.draw_series(locus.iter().flat_map(|(r, eig)| {
            eig.iter()
                .map(move |c| Circle::new((*r, part(c)), 2, BLUE.filled()))
        }))?;
        if (from..=to).contains(&2.0) {
            ch.draw_series(LineSeries::new(
                vec![(2.0, -lim), (2.0, lim)],
                BLACK.mix(0.5).stroke_width(1),
            ))?;
        }
    }
    root.present()?;
    Ok(())
}
