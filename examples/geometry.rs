//! Geometry in, equations out: systems written from positions and rotations, with `velocity`
//! and the angular velocities derived by the macro.
//!
//! - the heavy top from its rotation R = R_z(φ) R_x(θ) R_z(ψ): its printed equations (eq. 92's)
//!   and a run against the top whose L was simplified by hand;
//! - the double pendulum from the positions of its bobs, against the hand-written L;
//! - a five-link chain from positions in a loop: the energy drift of a long run.
//!
//! Run: `cargo run --release --example geometry`.

use lagrange::prelude::*;
#[allow(dead_code)] // each example uses a part of the shared command-line helpers
use lagrange_examples::cli;
use lagrange_examples::double_pendulum_system::DoublePendulum;
use lagrange_examples::heavy_top_system::HeavyTop;

/// The symmetric heavy top from its orientation.
pub struct GeometryTop {
    /// Moment of inertia about a transverse axis through the fixed point.
    pub i_perp: f64,
    /// Moment of inertia about the symmetry axis.
    pub i_par: f64,
    /// Mass × gravity × distance from the fixed point to the centre of mass.
    pub mgl: f64,
}

#[lagrangian]
impl GeometryTop {
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let r = Rotation::about_z(phi) * Rotation::about_x(theta) * Rotation::about_z(psi);
        let w = body_angular_velocity(&r);
        0.5 * (self.i_perp * (w.x * w.x + w.y * w.y) + self.i_par * w.z * w.z)
            - self.mgl * (r * Vector3::z()).z
    }
}

/// Two point masses on massless rods, from the positions of the bobs.
pub struct PositionsDouble {
    /// Upper mass.
    pub m1: f64,
    /// Lower mass.
    pub m2: f64,
    /// Upper rod.
    pub l1: f64,
    /// Lower rod.
    pub l2: f64,
    /// Gravity.
    pub g: f64,
}

#[lagrangian]
impl PositionsDouble {
    fn lagrangian(&self, (th1, th1_dot): Coord, (th2, th2_dot): Coord) -> Scalar {
        let (m1, m2, l1, l2, g) = (self.m1, self.m2, self.l1, self.l2, self.g);
        let p1 = Vector3::new(l1 * th1.sin(), -l1 * th1.cos(), 0.0 * th1);
        let p2 = p1 + Vector3::new(l2 * th2.sin(), -l2 * th2.cos(), 0.0 * th2);
        let (v1, v2) = (velocity(p1), velocity(p2));
        0.5 * m1 * v1.norm_squared() + 0.5 * m2 * v2.norm_squared() - g * (m1 * p1.y + m2 * p2.y)
    }
}

/// A chain of five equal links, each bob's position the previous one's plus a rod.
pub struct Chain5 {
    /// Each bob's mass.
    pub m: f64,
    /// Each rod's length.
    pub l: f64,
    /// Gravity.
    pub g: f64,
}

#[lagrangian]
impl Chain5 {
    fn lagrangian(&self, (q, q_dot): Coords<5>) -> Scalar {
        let mut p = Vector3::new(0.0 * q[0], 0.0 * q[0], 0.0 * q[0]);
        let mut l = 0.0 * q[0];
        for k in 0..5 {
            p += Vector3::new(self.l * q[k].sin(), -self.l * q[k].cos(), 0.0 * q[k]);
            let v = velocity(p);
            l += 0.5 * self.m * v.norm_squared() - self.m * self.g * p.y;
        }
        l
    }
}

fn main() {
    cli::run_or_exit(report);
}

fn report() -> Result<(), Box<dyn std::error::Error>> {
    let dop = Method::Dop853 {
        rtol: 1e-12,
        atol: 1e-14,
    };

    println!("The heavy top from R = R_z(φ) R_x(θ) R_z(ψ) and body_angular_velocity(&r):");
    println!("{}", GeometryTop::EQUATIONS);
    println!("CYCLIC = {:?}", <GeometryTop as Lagrangian<3>>::CYCLIC);
    let (i_perp, i_par, mgl) = (1.0, 0.6, 1.2);
    let geo = GeometryTop { i_perp, i_par, mgl };
    let hand = HeavyTop { i_perp, i_par, mgl };
    let (q0, v0) = ([0.6, 0.0, 0.0], [0.0, 0.8, 12.0]);
    let a = Simulation::new(&geo, q0, v0)
        .method(dop)
        .until(20.0)
        .run()?;
    let b = Simulation::new(&hand, q0, v0)
        .method(dop)
        .until(20.0)
        .run()?;
    let (qa, qb) = (
        a.q.last().ok_or("empty run")?,
        b.q.last().ok_or("empty run")?,
    );
    println!(
        "t = 20: θ = {:.12} (from the rotation), {:.12} (eq. 92 by hand), difference {:.1e}",
        qa[0],
        qb[0],
        (qa[0] - qb[0]).abs()
    );
    println!("{}\n", a.invariants().named(&GeometryTop::COORDINATES));

    println!("The double pendulum from the positions of its bobs:");
    println!("{}", PositionsDouble::EQUATIONS);
    let (m1, m2, l1, l2, g) = (1.0, 1.0, 1.0, 1.0, 9.81);
    let pos = PositionsDouble { m1, m2, l1, l2, g };
    let hand = DoublePendulum { m1, m2, l1, l2, g };
    let (q0, v0) = ([1.2, -0.4], [0.0, 0.5]);
    let qa = Simulation::new(&pos, q0, v0).method(dop).until(5.0).run()?;
    let qb = Simulation::new(&hand, q0, v0)
        .method(dop)
        .until(5.0)
        .run()?;
    let (qa, qb) = (
        qa.q.last().ok_or("empty run")?,
        qb.q.last().ok_or("empty run")?,
    );
    println!(
        "t = 5: θ₁ = {:.12} (positions), {:.12} (hand-written), difference {:.1e}\n",
        qa[0],
        qb[0],
        (qa[0] - qb[0]).abs()
    );

    println!("A five-link chain from positions in a loop, 50 time units:");
    let chain = Chain5 {
        m: 1.0,
        l: 0.5,
        g: 9.81,
    };
    let tr = Simulation::new(&chain, [0.9, 0.5, 0.1, -0.3, -0.8], [0.0; 5])
        .method(dop)
        .until(50.0)
        .run()?;
    let drift = tr.invariants().energy.ok_or("energy is conserved")?;
    println!("energy drift {drift}");
    Ok(())
}
