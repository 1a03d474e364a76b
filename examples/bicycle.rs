//! The Whipple bicycle benchmark (Meijaard, Papadopoulos, Ruina, Schwab, Proc. R. Soc. A 463
//! (2007)) from its nonlinear geometry: four rigid bodies, two knife-edge wheels rolling
//! without slip (four velocity constraints), the front wheel on the ground (a holonomic one).
//! Linearized on the constraint manifold about upright straight running and reduced to lean and
//! steer, it gives the paper's M, C₁, K₀, K₂, its eigenvalues against speed (the paper's
//! Figure 3: weave, capsize, caster), the stable speed band; and the nonlinear bicycle, run from
//! a small lean rate at 3, 5 and 7 m/s, against the linear growth rates.
//!
//! Run: `cargo run --release --example bicycle -- [--csv PATH] [--out out/bicycle.svg]`

use lagrange::prelude::*;
use lagrange_examples::bicycle_system::{published, Bicycle};
use lagrange_examples::cli;
use plotters::prelude::*;

const USAGE: &str = "usage: cargo run --release --example bicycle -- [--csv PATH] [--out PATH.svg]
  --csv PATH   one row per speed v = 0, 0.1, …, 10 m/s: v, then re and im of the four
               lean/steer eigenvalues (sorted by decreasing real part), nine numbers
  --out PATH   the figure (default out/bicycle.svg)
";

struct Options {
    csv: Option<String>,
    out: String,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        csv: None,
        out: "out/bicycle.svg".into(),
    };
    for (key, val) in cli::pairs()? {
        match key.as_str() {
            "--csv" => o.csv = Some(val),
            "--out" => o.out = val,
            _ => return Err(format!("unknown option {key}")),
        }
    }
    Ok(o)
}

fn main() {
    cli::run_or_exit(report);
}

/// The largest relative difference of two 2 × 2 matrices (against the larger entry of b).
fn rel(a: &SMatrix<f64, 2, 2>, b: [[f64; 2]; 2]) -> f64 {
    let scale = b.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    (0..2)
        .flat_map(|i| (0..2).map(move |j| (i, j)))
        .map(|(i, j)| (a[(i, j)] - b[i][j]).abs() / scale)
        .fold(0.0, f64::max)
}

fn print_matrix(name: &str, a: &SMatrix<f64, 2, 2>) {
    println!(
        "  {name} = [[{:.14}, {:.14}], [{:.14}, {:.14}]]",
        a[(0, 0)],
        a[(0, 1)],
        a[(1, 0)],
        a[(1, 1)]
    );
}

/// The growth rate of |φ| in a run: the slope of ln |φ| at its peaks after the first 0.3 s
/// when the dominant linear eigenvalue is complex (a weave), over the run's second half when it
/// is real (a capsize, or the slowest decay).
pub fn measured_rate(t: &[f64], lean: &[f64], oscillates: bool) -> f64 {
    let points: Vec<(f64, f64)> = if oscillates {
        (1..lean.len() - 1)
            .filter(|&k| t[k] > 0.3)
            .filter(|&k| lean[k].abs() >= lean[k - 1].abs() && lean[k].abs() > lean[k + 1].abs())
            .map(|k| (t[k], lean[k].abs().ln()))
            .collect()
    } else {
        (t.len() / 2..t.len())
            .filter(|&k| lean[k] != 0.0)
            .map(|k| (t[k], lean[k].abs().ln()))
            .collect()
    };
    let n = points.len() as f64;
    let (st, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (t, y)| (a + t, b + y));
    let (mt, my) = (st / n, sy / n);
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), (t, y)| {
        (a + (t - mt) * (y - my), b + (t - mt) * (t - mt))
    });
    num / den
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let o = cli::or_exit(options(), USAGE);
    let bike = Bicycle::benchmark();
    println!(
        "Whipple bicycle, the benchmark's parameters: w = {}, c = {}, λ = π/10, g = {}; rear wheel \
         r = {}, m = {}; frame m = {}; fork m = {}; front wheel r = {}, m = {}",
        bike.w, bike.c, bike.g, bike.r_r, bike.m_r, bike.m_b, bike.m_h, bike.r_f, bike.m_f
    );

    // The matrices: M and K at v = 0 give M and g K₀; C and K at v = 1 give C₁ and K₂.
    let (l0, l1) = (bike.lean_and_steer(0.0)?, bike.lean_and_steer(1.0)?);
    let k0 = l0.k / bike.g;
    let (c1, k2) = (l1.c, l1.k - l0.k);
    println!("lean and steer, linearized on the constraints (q = (φ, δ)):");
    print_matrix("M ", &l0.m);
    print_matrix("C1", &c1);
    print_matrix("K0", &k0);
    print_matrix("K2", &k2);
    println!(
        "  largest relative difference from the paper's: M {:.1e}, C1 {:.1e}, K0 {:.1e}, K2 {:.1e}",
        rel(&l0.m, published::M),
        rel(&c1, published::C1),
        rel(&k0, published::K0),
        rel(&k2, published::K2)
    );
    let standstill = l0.eigenvalues()?;
    println!(
        "eigenvalues at v = 0: {} (paper: ±{}, ±{})",
        standstill
            .iter()
            .map(|l| format!("{:.14}", l.re))
            .collect::<Vec<_>>()
            .join(", "),
        published::STANDSTILL[0],
        published::STANDSTILL[1]
    );
    let (weave, capsize) = bike.stable_band();
    println!(
        "weave speed {weave:.14} m/s (paper {}), capsize speed {capsize:.14} m/s (paper {})",
        published::WEAVE,
        published::CAPSIZE
    );

    // Eigenvalues against speed.
    let mut rows = Vec::new();
    for k in 0..=100 {
        let v = k as f64 * 0.1;
        let eig = bike.lean_and_steer(v)?.eigenvalues()?;
        rows.push((v, eig));
    }
    if let Some(path) = &o.csv {
        let mut text = String::from("v,re1,im1,re2,im2,re3,im3,re4,im4\n");
        for (v, eig) in &rows {
            text.push_str(&format!("{v:.1}"));
            for l in eig {
                text.push_str(&format!(",{:e},{:e}", l.re, l.im));
            }
            text.push('\n');
        }
        if let Some(dir) = std::path::Path::new(path).parent() {
            if !dir.as_os_str().is_empty() {
                std::fs::create_dir_all(dir)?;
            }
        }
        std::fs::write(path, text)?;
        println!("eigenvalues against speed: {path}");
    }

    // The nonlinear bicycle from upright straight running with a lean rate of 0.02 rad/s.
    println!("nonlinear runs from a lean rate of 0.001 rad/s:");
    let mut runs = Vec::new();
    for v in [3.0, 5.0, 7.0] {
        let (q0, mut v0) = bike.upright(v);
        v0[3] = 1e-3;
        let until = if v < 4.0 { 3.0 } else { 8.0 };
        let tr = Simulation::new(&bike, q0, v0)
            .project_initial_state()
            .method(Method::Dop853 {
                rtol: 1e-10,
                atol: 1e-12,
            })
            .until(until)
            .sample_every(0.01)
            .run()?;
        let lean: Vec<f64> = tr.q.iter().map(|q| q[3]).collect();
        let eig = bike.lean_and_steer(v)?.eigenvalues()?;
        let (linear, oscillates) = (eig[0].re, eig[0].im != 0.0);
        let measured = measured_rate(&tr.t, &lean, oscillates);
        let inv = tr.invariants();
        println!(
            "  v = {v} m/s: {}, lean {:+.2e} at t = {until} s; growth rate {measured:+.4} /s \
             (linear {linear:+.4} /s); constraints held to {:.1e}, energy to {:.1e} relative",
            if linear > 0.0 { "grows" } else { "decays" },
            lean[lean.len() - 1],
            inv.constraints
                .map_or(f64::NAN, |c| c.position.max(c.velocity)),
            inv.energy.map_or(f64::NAN, |e| e.max_rel)
        );
        runs.push((v, tr.t.clone(), lean));
    }

    if let Some(dir) = std::path::Path::new(&o.out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    let root = SVGBackend::new(&o.out, (1400, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let areas = root.split_evenly((1, 2));
    let mut chart = ChartBuilder::on(&areas[0])
        .caption(
            format!("eigenvalues against speed: stable for {weave:.3} < v < {capsize:.3} m/s"),
            ("sans-serif", 17),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..10.0, -10.0..10.0)?;
    chart
        .configure_mesh()
        .x_desc("v (m/s)")
        .y_desc("Re λ (solid), |Im λ| (dots)  (1/s)")
        .draw()?;
    chart.draw_series(rows.iter().flat_map(|(v, eig)| {
        eig.iter()
            .filter(|l| l.re.abs() <= 10.0)
            .map(move |l| Circle::new((*v, l.re), 2, BLUE.filled()))
    }))?;
    chart.draw_series(rows.iter().flat_map(|(v, eig)| {
        eig.iter()
            .filter(|l| l.im > 0.0)
            .map(move |l| Circle::new((*v, l.im), 1, RED.filled()))
    }))?;
    chart.draw_series(LineSeries::new([(0.0, 0.0), (10.0, 0.0)], &BLACK))?;
    let mut chart = ChartBuilder::on(&areas[1])
        .caption("the nonlinear bicycle's lean φ(t)", ("sans-serif", 17))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..8.0, -0.002..0.002)?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc("φ (rad)")
        .draw()?;
    for ((v, t, lean), color) in runs.iter().zip([RED, BLUE, GREEN]) {
        chart
            .draw_series(LineSeries::new(
                t.iter()
                    .zip(lean)
                    .filter(|(_, l)| l.abs() < 0.002)
                    .map(|(&t, &l)| (t, l)),
                &color,
            ))?
            .label(format!("v = {v} m/s"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .draw()?;
    root.present()?;
    println!("figure: {}", o.out);

    // To watch, next to the figure: from a lean rate of 0.3 rad/s, the weave growing at 3 m/s
    // and decaying at 5 m/s.
    let stem = o.out.strip_suffix(".svg").unwrap_or(&o.out).to_owned();
    for (v, until, what) in [(3.0, 4.5, "weave"), (5.0, 8.0, "decay")] {
        let tr = bike.watch(v, until)?;
        let title = format!("Whipple bicycle at {v} m/s ({what})");
        cli::write_animation(&format!("{stem}_{v}ms.svg"), &title, &tr, &bike)?;
    }
    Ok(())
}
