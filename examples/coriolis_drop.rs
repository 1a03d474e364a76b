//! A body dropped from a tower lands east of its foot.
//!
//! Earth's frame, local axes x east, y north, z up, Ω_E = Ω (0, cos λ, sin λ), uniform effective
//! gravity g (the centrifugal effect of the origin's motion absorbed in it):
//!
//!     L = |ṙ + Ω_E×r|²/2 − g z        (per unit mass)
//!
//! Theory (docs/ERRATA.md, section E notes), t = √(2h/g):
//!   east  = (1/3) Ω g t³ cos λ  +  Ω³ g t⁵ cos λ (3/8 cos²λ − 1/5)  + O(Ω⁵)
//!   north = −(3/2) (Ω² h²/g) sin λ cos λ + O(Ω⁴)
//! The example integrates the drop (DOP853, the ground located as a terminal event), compares
//! with the first-order result, and shows that the difference is the second-order (relative
//! (Ωt)²) term by scaling Earth's rate up.
//!
//! Run: `cargo run --release --example coriolis_drop -- [--height M] [--lat DEG] [--out PATH]`

use lagrange::prelude::*;
use lagrange::{Event, Method, Simulation};
#[allow(dead_code)] // each example uses a part of the shared command-line helpers
use lagrange_examples::cli;
use plotters::prelude::*;

/// Earth's sidereal rotation rate, rad/s.
const OMEGA_EARTH: f64 = 7.292_115e-5;

/// A body near the ground in a frame rotating at `omega`, under uniform gravity −g ẑ.
pub struct Drop {
    pub g: f64,
    pub omega: Vector3<f64>,
}

#[lagrangian]
impl Drop {
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        let v = r_dot + self.omega.cross(&r);
        0.5 * v.norm_squared() - self.g * r.z
    }
}

const USAGE: &str =
    "usage: coriolis_drop [--height M (100)] [--lat DEG (48.85)] [--out PATH (out/coriolis_drop.svg)]";

/// A theory curve of the figure: legend, colour, displacement as a function of Ω.
type Curve<'a> = (&'static str, RGBColor, Box<dyn Fn(f64) -> f64 + 'a>);

struct Landing {
    scale: f64,
    t: f64,
    east: f64,
    north: f64,
}

fn drop(g: f64, h: f64, lat: f64, scale: f64) -> Result<Landing, Box<dyn std::error::Error>> {
    let om = OMEGA_EARTH * scale;
    let body = Drop {
        g,
        omega: Vector3::new(0.0, om * lat.cos(), om * lat.sin()),
    };
    let traj = Simulation::new(&body, [0.0, 0.0, h], [0.0; 3])
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-15,
        })
        .until(10.0 * (2.0 * h / g).sqrt())
        .event(Event::zero_crossing("ground", |_t, q: &[f64; 3], _v| q[2]).terminal())
        .run()?;
    let hit = traj
        .events
        .last()
        .ok_or("the body never reached the ground")?;
    Ok(Landing {
        scale,
        t: hit.t,
        east: hit.q[0],
        north: hit.q[1],
    })
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let (mut h, mut lat_deg, mut out) =
        (100.0_f64, 48.85_f64, String::from("out/coriolis_drop.svg"));
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let v = args.next();
        let parsed = match (a.as_str(), v) {
            ("--height", Some(v)) => v.parse().map(|x| h = x).is_ok(),
            ("--lat", Some(v)) => v.parse().map(|x| lat_deg = x).is_ok(),
            ("--out", Some(v)) => {
                out = v;
                true
            }
            _ => false,
        };
        if !parsed {
            eprintln!("error: bad option {a}\n{USAGE}");
            std::process::exit(2);
        }
    }
    if !(h > 0.0 && lat_deg.abs() < 90.0) {
        eprintln!("error: need height > 0 and |lat| < 90\n{USAGE}");
        std::process::exit(2);
    }
    let g = 9.81;
    let lat = lat_deg.to_radians();
    let t0 = (2.0 * h / g).sqrt();
    let (s, c) = lat.sin_cos();
    let first = |om: f64| om * g * t0.powi(3) * c / 3.0;
    let second_east = |om: f64| om.powi(3) * g * t0.powi(5) * c * (0.375 * c * c - 0.2);
    let second_north = |om: f64| -1.5 * om * om * h * h / g * s * c;

    let earth = drop(g, h, lat, 1.0)?;
    println!("Drop from h = {h} m at latitude {lat_deg:.2}°, g = {g} m/s², fall time {t0:.6} s");
    println!("Earth's rate Ω = {OMEGA_EARTH:.6e} rad/s:");
    println!("  east  (integrated)              {:.12e} m", earth.east);
    println!(
        "  east  first order (1/3)Ωg t³cosλ {:.12e} m   (rel. diff {:+.3e})",
        first(OMEGA_EARTH),
        earth.east / first(OMEGA_EARTH) - 1.0
    );
    println!(
        "  east − first order               {:+.4e} m   theory Ω³g t⁵ cosλ(3/8 cos²λ − 1/5) = {:+.4e} m",
        earth.east - first(OMEGA_EARTH),
        second_east(OMEGA_EARTH)
    );
    println!(
        "  north (integrated)              {:+.4e} m   theory −(3/2)(Ω²h²/g) sinλ cosλ = {:+.4e} m",
        earth.north,
        second_north(OMEGA_EARTH)
    );
    println!("  landing time {:.9} s (free fall {t0:.9} s)", earth.t);

    println!("\nEarth's rate scaled by k: the difference from first order is the (Ωt)² term");
    println!(
        "{:>7} {:>12} {:>14} {:>14} {:>10} {:>14} {:>14} {:>10}",
        "k", "(Ωt)²", "east−1st (m)", "theory (m)", "ratio", "north (m)", "theory (m)", "ratio"
    );
    let scales = [1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0];
    let mut rows = Vec::new();
    for &k in &scales {
        let l = drop(g, h, lat, k)?;
        let om = OMEGA_EARTH * k;
        let de = l.east - first(om);
        println!(
            "{:>7} {:>12.3e} {:>14.6e} {:>14.6e} {:>10.6} {:>14.6e} {:>14.6e} {:>10.6}",
            k,
            (om * t0).powi(2),
            de,
            second_east(om),
            de / second_east(om),
            l.north,
            second_north(om),
            l.north / second_north(om)
        );
        rows.push((l, de));
    }

    // Figure: |east − first order| and |north| against Ω, integrated vs theory, log–log.
    if let Some(dir) = std::path::Path::new(&out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let root = SVGBackend::new(&out, (760, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let xs: Vec<f64> = rows.iter().map(|(l, _)| OMEGA_EARTH * l.scale).collect();
    let ys: Vec<f64> = rows
        .iter()
        .flat_map(|(l, de)| [de.abs(), l.north.abs(), first(OMEGA_EARTH * l.scale)])
        .filter(|y| *y > 0.0)
        .collect();
    let (ymin, ymax) = ys
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(a, b), &y| (a.min(y), b.max(y)));
    let (xmin, xmax) = (xs[0] / 1.5, xs[xs.len() - 1] * 1.5);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("Dropped body, h = {h} m, λ = {lat_deg:.2}°: landing point vs Earth's rate"),
            ("sans-serif", 18),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (xmin..xmax).log_scale(),
            (ymin / 3.0..ymax * 3.0).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("Ω (rad/s)")
        .y_desc("displacement (m)")
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .draw()?;
    let fine: Vec<f64> = (0..=100)
        .map(|i| xmin * (xmax / xmin).powf(i as f64 / 100.0))
        .collect();
    let curves: [Curve; 3] = [
        ("east, first order (1/3)Ωg t³ cos λ", BLUE, Box::new(first)),
        (
            "|east − first order|, theory ∝ Ω³",
            RED,
            Box::new(move |om| second_east(om).abs()),
        ),
        (
            "|north| (south), theory ∝ Ω²",
            GREEN,
            Box::new(move |om| second_north(om).abs()),
        ),
    ];
    for (name, color, f) in curves.iter() {
        let color = *color;
        chart
            .draw_series(LineSeries::new(
                fine.iter().map(|&x| (x, f(x))),
                color.stroke_width(2),
            ))?
            .label(*name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
    }
    let marks: [(RGBColor, Vec<(f64, f64)>); 3] = [
        (
            BLUE,
            rows.iter()
                .map(|(l, _)| (OMEGA_EARTH * l.scale, l.east))
                .collect(),
        ),
        (
            RED,
            rows.iter()
                .map(|(l, de)| (OMEGA_EARTH * l.scale, de.abs()))
                .collect(),
        ),
        (
            GREEN,
            rows.iter()
                .map(|(l, _)| (OMEGA_EARTH * l.scale, l.north.abs()))
                .collect(),
        ),
    ];
    for (color, pts) in marks {
        chart.draw_series(
            pts.into_iter()
                .map(move |p| Circle::new(p, 4, color.filled())),
        )?;
    }
    chart
        .draw_series(std::iter::once(Circle::new(
            (xmin, ymin),
            0,
            BLACK.filled(),
        )))?
        .label("dots: integrated (DOP853, ground as a terminal event)")
        .legend(|(x, y)| Circle::new((x + 10, y), 4, BLACK.filled()));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()?;
    root.present()?;
    println!("\nfigure: {out}");
    Ok(())
}
