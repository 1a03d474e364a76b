//! A charged particle in uniform E and B, written with a vector potential A = B×r/2 and a
//! `Coord3` coordinate, against the textbook motion: gyration at ω_c = qB/m with the Larmor
//! radius, and the E×B drift v_d = E×B/B². A gauge term λ∇χ·ṙ (χ = x y z) added to L changes
//! the canonical momentum but not the trajectory.
//!
//! Run: `cargo run --release --example charged_particle [lambda]` (gauge strength, default 0.7).

use lagrange::prelude::*;
#[allow(dead_code)] // each example uses a part of the shared command-line helpers
use lagrange_examples::cli;

/// L = m|ṙ|²/2 + q ṙ·(B×r)/2 + q E·r + λ ∇(xyz)·ṙ.
pub struct ChargedParticle {
    pub m: f64,
    pub q: f64,
    pub b: Vector3<f64>,
    pub e: Vector3<f64>,
    pub lambda: f64,
}

#[lagrangian]
impl ChargedParticle {
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        let a = self.b.cross(&r) / 2.0;
        let grad_chi = Vector3::new(r.y * r.z, r.x * r.z, r.x * r.y);
        self.m / 2.0 * r_dot.norm_squared()
            + self.q * (r_dot.dot(&a) + self.e.dot(&r))
            + self.lambda * grad_chi.dot(&r_dot)
    }
}

fn usage() -> ! {
    eprintln!("usage: charged_particle [lambda]   (gauge-term strength, default 0.7)");
    std::process::exit(2)
}

fn run(
    p: &ChargedParticle,
    v0: Vector3<f64>,
    t_end: f64,
) -> Result<Trajectory<3>, SimulationError> {
    Simulation::new(p, [0.0, 0.0, 0.0], [v0.x, v0.y, v0.z])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(t_end)
        .sample_every(t_end / 400.0)
        .run()
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let lambda: f64 = match args.as_slice() {
        [] => 0.7,
        [a] => a.parse().unwrap_or_else(|_| usage()),
        _ => usage(),
    };
    let (m, q, b) = (2.0, 1.5, 3.0);
    let omega_c = q * b / m;
    let period = 2.0 * std::f64::consts::PI / omega_c;

    // 1. Pure B: a circle of radius m v⊥ / (|q| B) traversed in 2π/ω_c, plus uniform v∥.
    let v0 = Vector3::new(0.8, 0.0, 0.25);
    let pure = ChargedParticle {
        m,
        q,
        b: Vector3::new(0.0, 0.0, b),
        e: Vector3::zeros(),
        lambda: 0.0,
    };
    let traj = run(&pure, v0, 3.0 * period)?;
    let larmor = m * v0.x / (q * b);
    // The guiding centre for r(0) = 0, v(0) = (v⊥, 0, ·) with B along +z and q > 0 is (0, −r_L).
    let radius_err = traj
        .q
        .iter()
        .map(|r| ((r[0]).hypot(r[1] + larmor) - larmor).abs())
        .fold(0.0, f64::max);
    let last = traj.q.last().copied().unwrap_or([f64::NAN; 3]);
    println!("Uniform B = {b} ẑ, m = {m}, q = {q}: ω_c = qB/m = {omega_c}, T = {period:.9}");
    println!(
        "  Larmor radius theory {larmor:.9}; max |distance to guiding centre − r_L| = {radius_err:.2e}"
    );
    println!(
        "  after 3 T: (x, y) = ({:.2e}, {:.2e}) (theory 0, 0); z = {:.9} (theory v∥·3T = {:.9})",
        last[0],
        last[1],
        last[2],
        v0.z * 3.0 * period
    );

    // 2. Crossed E and B: after whole gyration periods the particle has drifted by v_d n T.
    let e = Vector3::new(0.6, 0.0, 0.0);
    let bvec = Vector3::new(0.0, 0.0, b);
    let crossed = ChargedParticle { e, ..pure };
    let v_drift = e.cross(&bvec) / bvec.norm_squared();
    let n = 4.0;
    let traj = run(&crossed, v0, n * period)?;
    let last = traj.q.last().copied().unwrap_or([f64::NAN; 3]);
    let want = v_drift * (n * period) + Vector3::new(0.0, 0.0, v0.z * n * period);
    println!();
    println!(
        "Add E = (0.6, 0, 0): E×B drift v_d = E×B/B² = ({:.6}, {:.6}, {:.6})",
        v_drift.x, v_drift.y, v_drift.z
    );
    println!(
        "  after {n} T: r = ({:.9}, {:.9}, {:.9}); theory r = v_d·nT + v∥·nT ẑ = ({:.9}, {:.9}, {:.9})",
        last[0], last[1], last[2], want.x, want.y, want.z
    );

    // 3. The gauge term: same trajectory, different canonical momentum.
    let gauged = ChargedParticle { lambda, ..crossed };
    let traj_g = run(&gauged, v0, n * period)?;
    let max_dev = traj
        .q
        .iter()
        .zip(&traj_g.q)
        .map(|(a, b)| (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    let p_at = |sys: &ChargedParticle| sys.momenta(&[1.0, 2.0, 3.0], &[v0.x, v0.y, v0.z], 0.0);
    println!();
    println!("Add the gauge term λ ∇(xyz)·ṙ with λ = {lambda}:");
    println!("  max |r_gauged − r| over the run = {max_dev:.2e} (theory 0)");
    println!(
        "  canonical p at r = (1, 2, 3): without {:?}\n                                  with    {:?} (shift λ∇χ = λ(6, 3, 2))",
        p_at(&crossed),
        p_at(&gauged)
    );
    Ok(())
}
