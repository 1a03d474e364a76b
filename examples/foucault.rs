//! The Foucault pendulum: a spherical pendulum in Earth's rotating frame.
//!
//! Local axes x east, y north, z up; Earth's angular velocity Ω_E = Ω (0, cos λ, sin λ) at
//! latitude λ. Coordinates are the bob's horizontal position (x, y), z = −√(l² − x² − y²), so
//! nothing is singular where the bob swings through the bottom. The centrifugal effect of the
//! suspension point's motion is absorbed in g.
//!
//!     L = |ṙ + Ω_E×r|²/2 + g (−z)        (per unit mass)
//!
//! Theory: the swing plane turns clockwise (northern hemisphere, seen from above) at Ω sin λ;
//! the released-from-rest swing is slightly elliptic and its Airy precession (3/8)(a/l)²·Ω sin λ
//! turns the other way. Earth's rate can be scaled up for a short run.
//!
//! Run: `cargo run --release --example foucault -- [--lat DEG] [--scale S] [--length M]
//!       [--amplitude M] [--turns N] [--out PATH]`

#[allow(dead_code)] // each example uses a part of the shared command-line helpers
use lagrange_examples::cli;
use std::f64::consts::PI;

use lagrange::prelude::*;
use lagrange::{Event, Method, Simulation};
use plotters::prelude::*;

/// Earth's sidereal rotation rate, rad/s.
const OMEGA_EARTH: f64 = 7.292_115e-5;

/// A spherical pendulum of length `l` in a frame rotating at `omega` (local east–north–up axes).
pub struct Foucault {
    pub g: f64,
    pub l: f64,
    pub omega: Vector3<f64>,
}

#[lagrangian]
impl Foucault {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        let z = -(self.l * self.l - x * x - y * y).sqrt();
        let z_dot = -(x * x_dot + y * y_dot) / z;
        let r = Vector3::new(x, y, z);
        let v = Vector3::new(x_dot, y_dot, z_dot) + self.omega.cross(&r);
        0.5 * v.norm_squared() - self.g * z
    }
}

struct Options {
    lat_deg: f64,
    scale: f64,
    length: f64,
    amplitude: f64,
    turns: f64,
    out: String,
}

const USAGE: &str = "usage: foucault [--lat DEG (48.85)] [--scale S (100: Earth's rate × S)] \
[--length M (67)] [--amplitude M (1)] [--turns N (0.5: swing-plane turns to simulate)] \
[--out PATH (out/foucault.svg)]";

fn parse() -> Result<Options, String> {
    let mut o = Options {
        lat_deg: 48.85,
        scale: 100.0,
        length: 67.0,
        amplitude: 1.0,
        turns: 0.5,
        out: "out/foucault.svg".into(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut val = || args.next().ok_or(format!("{a} needs a value"));
        let num = |s: String| s.parse::<f64>().map_err(|e| format!("{a}: {e}"));
        match a.as_str() {
            "--lat" => o.lat_deg = num(val()?)?,
            "--scale" => o.scale = num(val()?)?,
            "--length" => o.length = num(val()?)?,
            "--amplitude" => o.amplitude = num(val()?)?,
            "--turns" => o.turns = num(val()?)?,
            "--out" => o.out = val()?,
            "-h" | "--help" => return Err(String::new()),
            _ => return Err(format!("unknown option {a}")),
        }
    }
    if !(o.length > 0.0 && o.amplitude > 0.0 && o.amplitude < 0.5 * o.length) {
        return Err("need 0 < amplitude < length/2".into());
    }
    if !(o.scale > 0.0 && o.turns > 0.0 && o.lat_deg.abs() <= 90.0 && o.lat_deg != 0.0) {
        return Err("need scale > 0, turns > 0, 0 < |lat| ≤ 90".into());
    }
    Ok(o)
}

/// Least-squares slope of the unwrapped swing-plane azimuth (modulo π) at the turning points.
fn swing_plane_rate(hits: &[(f64, f64, f64)]) -> (f64, Vec<(f64, f64)>) {
    let mut prev: Option<f64> = None;
    let mut pts = Vec::with_capacity(hits.len());
    // The chord joining successive turning points (the two ends of one swing) gives the swing
    // line's direction without reference to the centre, which the centrifugal force shifts.
    for w in hits.windows(2) {
        let (t, x, y) = ((w[0].0 + w[1].0) / 2.0, w[1].1 - w[0].1, w[1].2 - w[0].2);
        let mut psi = y.atan2(x);
        if let Some(p) = prev {
            while psi - p > PI / 2.0 {
                psi -= PI;
            }
            while psi - p < -PI / 2.0 {
                psi += PI;
            }
        }
        prev = Some(psi);
        pts.push((t, psi));
    }
    let n = pts.len() as f64;
    let mt = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let mp = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let num: f64 = pts.iter().map(|(t, p)| (t - mt) * (p - mp)).sum();
    let den: f64 = pts.iter().map(|(t, _)| (t - mt).powi(2)).sum();
    (num / den, pts)
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = match parse() {
        Ok(o) => o,
        Err(e) => {
            if !e.is_empty() {
                eprintln!("error: {e}");
            }
            eprintln!("{USAGE}");
            std::process::exit(2);
        }
    };
    let g = 9.81;
    let lat = o.lat_deg.to_radians();
    let om = OMEGA_EARTH * o.scale;
    let pend = Foucault {
        g,
        l: o.length,
        omega: Vector3::new(0.0, om * lat.cos(), om * lat.sin()),
    };
    let w0 = (g / o.length).sqrt();
    let period = 2.0 * PI / w0;
    let theory = -om * lat.sin();
    let until = o.turns * 2.0 * PI / theory.abs();

    let traj = Simulation::new(&pend, [o.amplitude, 0.0], [0.0, 0.0])
        .method(Method::Dop853 {
            rtol: 1e-11,
            atol: 1e-12,
        })
        .until(until)
        .sample_every(period / 200.0)
        .event(
            Event::zero_crossing("turning point", |_t, q: &[f64; 2], v: &[f64; 2]| {
                q[0] * v[0] + q[1] * v[1]
            })
            .falling(),
        )
        .run()?;
    let hits: Vec<(f64, f64, f64)> = traj.events.iter().map(|e| (e.t, e.q[0], e.q[1])).collect();
    let (rate, psi) = swing_plane_rate(&hits);
    let airy = 3.0 / 8.0 * (o.amplitude / o.length).powi(2);
    let theory_airy = theory * (1.0 - airy);

    println!("Foucault pendulum at latitude {:.2}°", o.lat_deg);
    println!(
        "  l = {} m, amplitude {} m, swing period {:.3} s, Earth's rate × {}",
        o.length, o.amplitude, period, o.scale
    );
    println!(
        "  simulated {:.1} s ({} turning points, {} DOP853 steps, {} rhs evaluations)",
        until,
        hits.len(),
        traj.stats.steps,
        traj.stats.rhs_evals
    );
    println!("  swing-plane rate, measured        {rate:+.9e} rad/s");
    println!(
        "  theory −Ω sin λ                    {theory:+.9e} rad/s   (rel. diff {:+.2e})",
        rate / theory - 1.0
    );
    println!(
        "  with Airy −(3/8)(a/l)² correction  {theory_airy:+.9e} rad/s   (rel. diff {:+.2e})",
        rate / theory_airy - 1.0
    );
    println!(
        "  (Ω/ω0)² = {:.1e}: the size of the remaining, higher-order corrections",
        (om / w0).powi(2)
    );
    println!(
        "  unscaled, the plane would turn once in {:.2} h here (half-turn, when the pattern repeats: {:.2} h)",
        2.0 * PI / (OMEGA_EARTH * lat.sin().abs()) / 3600.0,
        PI / (OMEGA_EARTH * lat.sin().abs()) / 3600.0
    );

    // The centrifugal force on the bob relative to the pivot (the pivot's own is in g) shifts the
    // centre of the swing north by Ω² sin λ cos λ · l²/g (to leading order).
    let n_mid = (hits.len() - 1) as f64;
    let (cx, cy) = hits.windows(2).fold((0.0, 0.0), |(sx, sy), w| {
        (
            sx + (w[0].1 + w[1].1) / (2.0 * n_mid),
            sy + (w[0].2 + w[1].2) / (2.0 * n_mid),
        )
    });
    println!(
        "  centre of the swing ({cx:+.3e}, {cy:+.3e}) m; static equilibrium (0, {:+.3e}) m",
        om * om * lat.sin() * lat.cos() * o.length * o.length / g
    );

    // Figure: the rosette (bob's horizontal track in Earth's frame), the turning points, and the
    // swing-plane direction predicted at the end.
    if let Some(dir) = std::path::Path::new(&o.out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let a = o.amplitude * 1.1;
    let root = SVGBackend::new(&o.out, (720, 900)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "Foucault pendulum, λ = {:.2}°, Ω = {}·Ω_E: swing plane turns at Ω sin λ",
                o.lat_deg, o.scale
            ),
            ("sans-serif", 18),
        )
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(-a..a, -1.45 * a..a)?;
    chart
        .configure_mesh()
        .x_desc("east (m)")
        .y_desc("north (m)")
        .draw()?;
    chart
        .draw_series(LineSeries::new(
            traj.q.iter().map(|q| (q[0], q[1])),
            BLUE.mix(0.6).stroke_width(1),
        ))?
        .label("bob track (Earth's frame)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    chart
        .draw_series(
            hits.iter()
                .map(|&(_, x, y)| Circle::new((x, y), 2, RED.filled())),
        )?
        .label("turning points")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, RED.filled()));
    // Theory: at each turning point the bob is at ±a along the azimuth −Ω sin λ · t.
    let ra = o.amplitude;
    chart
        .draw_series(hits.iter().map(|&(t, x, y)| {
            let (s, c) = (theory * t).sin_cos();
            let end = if x * c + y * s >= 0.0 { ra } else { -ra };
            Circle::new((end * c, end * s), 5, BLACK.stroke_width(1))
        }))?
        .label("theory: ±a along azimuth −Ω sin λ · t")
        .legend(|(x, y)| Circle::new((x + 10, y), 5, BLACK.stroke_width(1)));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()?;
    root.present()?;
    let last = psi.last().map_or(0.0, |p| p.1);
    println!(
        "  swing-plane azimuth turned {:.4} rad (theory {:.4} rad); figure: {}",
        last - psi[0].1,
        theory * (psi.last().map_or(0.0, |p| p.0) - psi[0].0),
        o.out
    );
    Ok(())
}
