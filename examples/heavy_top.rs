//! The heavy symmetric top (reference text, section D, eqs. 92–102), end to end.
//!
//! ```text
//! cargo run --release --example heavy_top
//! cargo run --release --example heavy_top -- --theta0 0.8 --phi-dot0 0 --psi-dot0 6   # cusps
//! cargo run --release --example heavy_top -- --help
//! ```
//!
//! Declares the top with `#[lagrangian]` exactly as eq. 92 reads, integrates it, and prints the
//! derived constants (Ω, p0, ω0, p_E, the roots of eq. 96), the nutation period measured from the
//! located turning points against eq. 97, the mean precession rate measured against the precise
//! quadrature of `lagrange_theory::heavy_top`, and the drift of the invariants. Writes an SVG
//! figure (θ(t), the trace of the symmetry axis seen from above, the drift) and, on request, CSV.

use std::f64::consts::PI;
use std::time::Instant;

use lagrange::prelude::*;
use lagrange_theory::heavy_top::{Constants, Motion, Top};
use plotters::prelude::*;

// The top of eq. 92, declared with `#[lagrangian]` exactly as the equation reads; shared by the
// heavy-top examples.
use heavy_top_system::HeavyTop;
use lagrange_examples::cli;
use lagrange_examples::heavy_top_system;

const USAGE: &str = "\
usage: cargo run --release --example heavy_top -- [options]

parameters   --i-perp X (1)  --i-par X (0.6)  --mgl X (1)
state        --theta0 X (1)  --phi0 X (0)  --psi0 X (0)
             --theta-dot0 X (0)  --phi-dot0 X (-0.5)  --psi-dot0 X (8)
method       --method dop853|dopri5|taylor|rk4|variational (dop853)
             --rtol X (1e-12) --atol X (1e-14)   adaptive methods
             --tol X (1e-14)                      the Taylor method
             --dt X (period/400)                  fixed-step methods
duration     --periods N  or  --until T   (default: one precession revolution,
             2π/|⟨φ̇⟩|, clamped to 5…200 nutation periods)
outputs      --svg PATH (out/heavy_top.svg)  --csv PATH (none)  --samples N (4000)
";

struct Options {
    top: HeavyTop,
    q0: [f64; 3],
    qdot0: [f64; 3],
    method: String,
    rtol: f64,
    atol: f64,
    tol: f64,
    dt: Option<f64>,
    periods: Option<f64>,
    until: Option<f64>,
    svg: String,
    csv: Option<String>,
    samples: usize,
}

fn parse() -> Result<Options, String> {
    let mut o = Options {
        top: HeavyTop {
            i_perp: 1.0,
            i_par: 0.6,
            mgl: 1.0,
        },
        q0: [1.0, 0.0, 0.0],
        qdot0: [0.0, -0.5, 8.0],
        method: "dop853".into(),
        rtol: 1e-12,
        atol: 1e-14,
        tol: 1e-14,
        dt: None,
        periods: None,
        until: None,
        svg: "out/heavy_top.svg".into(),
        csv: None,
        samples: 4000,
    };
    for (key, val) in cli::pairs()? {
        let num = || cli::number(&key, &val);
        match key.as_str() {
            "--i-perp" => o.top.i_perp = num()?,
            "--i-par" => o.top.i_par = num()?,
            "--mgl" => o.top.mgl = num()?,
            "--theta0" => o.q0[0] = num()?,
            "--phi0" => o.q0[1] = num()?,
            "--psi0" => o.q0[2] = num()?,
            "--theta-dot0" => o.qdot0[0] = num()?,
            "--phi-dot0" => o.qdot0[1] = num()?,
            "--psi-dot0" => o.qdot0[2] = num()?,
            "--method" => o.method = val.to_lowercase(),
            "--rtol" => o.rtol = num()?,
            "--atol" => o.atol = num()?,
            "--tol" => o.tol = num()?,
            "--dt" => o.dt = Some(num()?),
            "--periods" => o.periods = Some(num()?),
            "--until" => o.until = Some(num()?),
            "--svg" => o.svg = val,
            "--csv" => o.csv = Some(val),
            "--samples" => o.samples = num()? as usize,
            _ => return Err(format!("unknown option {key}")),
        }
    }
    Ok(o)
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = cli::or_exit(parse(), USAGE);
    let top = o.top;
    let theory = Top {
        i_perp: top.i_perp,
        i_par: top.i_par,
        mgl: top.mgl,
    };
    if o.q0[0].sin().abs() < 1e-9 {
        return Err(format!(
            "θ0 = {}: the Euler-angle chart is singular there (sin θ = 0, the top's axis on the \
             vertical, where φ and ψ turn about the same axis), so the equations of eq. 92 cannot be \
             solved for the accelerations. For the sleeping top of Example 1 start slightly tilted \
             (--theta0 1e-3) or run `cargo run --release --example sleeping_top`, which sweeps Ω/ω0 \
             through the stability threshold.",
            o.q0[0]
        )
        .into());
    }
    let c = Constants::from_state(&theory, &o.q0, &o.qdot0)?;
    let n = c.nutation;
    let roots = n.roots()?;
    let period = n.period()?;
    let mean_rate = n.mean_precession_rate()?;
    let motion = n.motion()?;

    println!(
        "Heavy symmetric top, eq. 92: I⊥ = {}, I∥ = {}, m g l = {}",
        top.i_perp, top.i_par, top.mgl
    );
    println!(
        "initial state: θ = {}, φ = {}, ψ = {};  θ̇ = {}, φ̇ = {}, ψ̇ = {}",
        o.q0[0], o.q0[1], o.q0[2], o.qdot0[0], o.qdot0[1], o.qdot0[2]
    );
    println!("\nEuler–Lagrange equations of eq. 92, derived at compile time by #[lagrangian]:");
    for line in HeavyTop::EQUATIONS.lines() {
        println!("  {line}");
    }
    println!("\nconstants of the motion (eqs. 93–96)");
    println!(
        "  L∥  = {:.12}   L_φ = {:.12}   E = {:.12}",
        c.l_par, c.l_phi, c.energy
    );
    println!(
        "  Ω   = L∥/I⊥ = {:.12}   ω0 = √(mgl/I⊥) = {:.12}   Ω/ω0 = {:.6}",
        n.omega,
        n.omega0,
        n.omega / n.omega0
    );
    println!("  p0  = L_φ/L∥ = {:.12}   p_E = {:.12}", n.p0, n.p_e);
    let (th_min, th_max) = roots.theta_range();
    println!(
        "  roots of eq. 96: p1 = {:.12}, p2 = {:.12}, p3 = {:.12}",
        roots.p1, roots.p2, roots.p3
    );
    println!(
        "  nutation between θ = {:.9} and {:.9} rad; motion: {}",
        th_min,
        th_max,
        match motion {
            Motion::RegularPrecession => "regular precession",
            Motion::Wavy => "waves (φ̇ keeps its sign)",
            Motion::Cusps => "cusps (φ̇ = 0 at the top turning point)",
            Motion::Loops => "loops (φ̇ changes sign at p = p0)",
        }
    );

    let revolution = (2.0 * PI / mean_rate.abs()).clamp(5.0 * period, 200.0 * period);
    let until = o
        .until
        .unwrap_or_else(|| o.periods.map_or(revolution, |k| k * period));
    let dt = o.dt.unwrap_or(period / 400.0);
    let method = match o.method.as_str() {
        "dop853" => Method::Dop853 {
            rtol: o.rtol,
            atol: o.atol,
        },
        "dopri5" | "dormandprince" => Method::DormandPrince {
            rtol: o.rtol,
            atol: o.atol,
        },
        "taylor" => Method::Taylor { tol: o.tol },
        "rk4" => Method::Rk4 { dt },
        "variational" | "vi" => Method::VariationalMidpoint { dt },
        m => {
            eprintln!("error: unknown method {m}\n\n{USAGE}");
            std::process::exit(2);
        }
    };
    let mut sim = Simulation::new(&top, o.q0, o.qdot0)
        .method(method)
        .until(until)
        .event(Event::zero_crossing("theta max", |_t, _q, v: &[f64; 3]| v[0]).falling());
    if !method.is_fixed_step() {
        sim = sim.sample_every(until / o.samples.max(10) as f64);
    }
    let start = Instant::now();
    let traj = sim.run()?;
    let wall = start.elapsed();
    println!(
        "\nrun: {method:?}, t = 0 … {until:.6} ({:.2} nutation periods), {}, {:.1} ms",
        until / period,
        traj.stats,
        wall.as_secs_f64() * 1e3
    );

    // Nutation period (eq. 97) and mean precession rate, from successive turning points.
    let lows: Vec<_> = traj.events.iter().collect();
    println!("\nnutation period, eq. 97 (AGM closed form): T = {period:.12}");
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    if lows.len() >= 2 {
        let periods: Vec<f64> = lows.windows(2).map(|w| w[1].t - w[0].t).collect();
        let mean_t = periods.iter().sum::<f64>() / periods.len() as f64;
        let worst = periods.iter().map(|t| rel(*t, period)).fold(0.0, f64::max);
        println!(
            "  measured from {} turning points (θ̇ = 0, θ max): mean {mean_t:.12}, worst relative deviation {worst:.2e}",
            lows.len()
        );
        let rates: Vec<f64> = lows
            .windows(2)
            .map(|w| (w[1].q[1] - w[0].q[1]) / (w[1].t - w[0].t))
            .collect();
        let mean_r = rates.iter().sum::<f64>() / rates.len() as f64;
        let worst_r = rates.iter().map(|r| rel(*r, mean_rate)).fold(0.0, f64::max);
        println!("\nmean precession rate ⟨φ̇⟩ over a nutation period");
        println!("  quadrature (Gauss–Kronrod) = {mean_rate:.12}");
        println!(
            "  measured Δφ/Δt per period  = {mean_r:.12} (worst relative deviation {worst_r:.2e})"
        );
        println!(
            "  fast-top limit mgl/L∥      = {:.12} (corrected eq. 102; off by {:.2e}, O((ω0/Ω)²) = {:.2e})",
            top.mgl / c.l_par,
            rel(mean_r, top.mgl / c.l_par),
            (n.omega0 / n.omega).powi(2)
        );
        println!(
            "  text's eq. 102 mgl/(2L∥)   = {:.12} (wrong: off by {:.1} %)",
            top.mgl / (2.0 * c.l_par),
            100.0 * rel(mean_r, top.mgl / (2.0 * c.l_par))
        );
    } else {
        println!("  (fewer than two turning points in the run: use a longer --periods)");
    }

    let inv = traj.invariants();
    println!("\ninvariants, largest relative drift over the run");
    if let Some(e) = inv.energy {
        println!("  E   {:.2e}", e.max_rel);
    }
    for (k, name) in [(1, "L_φ"), (2, "L∥")] {
        if let Some(d) = inv.momenta[k] {
            println!("  {name} {:.2e}", d.max_rel);
        }
    }

    if let Some(path) = &o.csv {
        if let Some(dir) = std::path::Path::new(path).parent() {
            std::fs::create_dir_all(dir)?;
        }
        traj.write_csv(path)?;
        println!("\nwrote {path}");
    }
    plot(&o.svg, &traj, th_min, th_max, &c, motion, period)?;
    println!("wrote {}", o.svg);
    cli::write_animation(&o.svg, "heavy top (eq. 92)", &traj, &top)?;
    Ok(())
}

/// A named, coloured polyline.
type Curve = (&'static str, RGBColor, Vec<(f64, f64)>);

fn plot(
    path: &str,
    traj: &Trajectory<3>,
    th_min: f64,
    th_max: f64,
    c: &Constants,
    motion: Motion,
    period: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let root = SVGBackend::new(path, (1200, 900)).into_drawing_area();
    root.fill(&WHITE)?;
    let (upper, lower) = root.split_vertically(560);
    let (left, right) = upper.split_horizontally(640);
    let t_end = traj.t.last().copied().unwrap_or(1.0);

    // θ(t) over the first few periods, with the turning points of eq. 96.
    let t_theta = t_end.min(6.0 * period);
    let pad = 0.08 * (th_max - th_min).max(1e-6);
    let mut ch = ChartBuilder::on(&left)
        .caption(
            "θ(t): nutation between the roots of eq. 96",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..t_theta, (th_min - pad)..(th_max + pad))?;
    ch.configure_mesh().x_desc("t").y_desc("θ (rad)").draw()?;
    ch.draw_series(LineSeries::new(
        traj.t
            .iter()
            .zip(&traj.q)
            .take_while(|(t, _)| **t <= t_theta)
            .map(|(t, q)| (*t, q[0])),
        BLUE.stroke_width(2),
    ))?
    .label("simulation (DOP853)")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
    for th in [th_min, th_max] {
        ch.draw_series(LineSeries::new(
            vec![(0.0, th), (t_theta, th)],
            RED.stroke_width(1),
        ))?;
    }
    ch.draw_series(std::iter::once(PathElement::new(
        vec![(0.0, th_min), (0.0, th_min)],
        RED,
    )))?
    .label("acos p2, acos p1 (eq. 96)")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    ch.configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()?;

    // The symmetry axis seen from above: (sin θ cos φ, sin θ sin φ).
    let r = th_max.sin().max(th_min.sin()).min(1.0) * 1.08;
    let kind = match motion {
        Motion::RegularPrecession => "regular precession",
        Motion::Wavy => "waves",
        Motion::Cusps => "cusps",
        Motion::Loops => "loops",
    };
    let mut ch = ChartBuilder::on(&right)
        .caption(format!("axis seen from above ({kind})"), ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(-r..r, -r..r)?;
    ch.configure_mesh().x_desc("x").y_desc("y").draw()?;
    ch.draw_series(LineSeries::new(
        traj.q
            .iter()
            .map(|q| (q[0].sin() * q[1].cos(), q[0].sin() * q[1].sin())),
        BLUE.stroke_width(1),
    ))?;
    for th in [th_min, th_max] {
        ch.draw_series(LineSeries::new(
            (0..=360).map(|k| {
                let a = k as f64 * PI / 180.0;
                (th.sin() * a.cos(), th.sin() * a.sin())
            }),
            RED.mix(0.5),
        ))?;
    }

    // Drift of the invariants.
    let e0 = traj.energy.first().copied().unwrap_or(0.0);
    let m0 = traj.momenta.first().copied().unwrap_or([0.0; 3]);
    let drift = |x: f64, x0: f64| (x - x0) / x0.abs().max(f64::MIN_POSITIVE);
    let series: [Curve; 3] = [
        (
            "E",
            BLACK,
            traj.t
                .iter()
                .zip(&traj.energy)
                .map(|(t, e)| (*t, drift(*e, e0)))
                .collect(),
        ),
        (
            "L_φ",
            GREEN,
            traj.t
                .iter()
                .zip(&traj.momenta)
                .map(|(t, p)| (*t, drift(p[1], m0[1])))
                .collect(),
        ),
        (
            "L∥",
            MAGENTA,
            traj.t
                .iter()
                .zip(&traj.momenta)
                .map(|(t, p)| (*t, drift(p[2], m0[2])))
                .collect(),
        ),
    ];
    let ymax = series
        .iter()
        .flat_map(|s| s.2.iter().map(|p| p.1.abs()))
        .fold(1e-16, f64::max)
        * 1.1;
    let mut ch = ChartBuilder::on(&lower)
        .caption(
            format!(
                "relative drift of the invariants (E = {:.6}, L_φ = {:.6}, L∥ = {:.6})",
                c.energy, c.l_phi, c.l_par
            ),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(90)
        .build_cartesian_2d(0.0..t_end, -ymax..ymax)?;
    ch.configure_mesh()
        .x_desc("t")
        .y_desc("(X − X₀)/|X₀|")
        .y_label_formatter(&|v| {
            if v.abs() < 1e-6 * ymax {
                "0".to_string()
            } else {
                format!("{v:.1e}")
            }
        })
        .draw()?;
    for (name, color, pts) in series {
        ch.draw_series(LineSeries::new(pts, color.stroke_width(1)))?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
    }
    ch.configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()?;
    root.present()?;
    Ok(())
}
