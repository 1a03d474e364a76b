//! The symmetric heavy top of eq. 92 in unit-quaternion coordinates: four coordinates
//! q = (w, x, y, z) with the constraint |q|² = 1, no chart singularity (the top can start exactly
//! upright, where the Euler angles of eq. 92 are singular). Shared by the `sleeping_top` example,
//! the tests and the benches.
//!
//! The body angular velocity is ω = 2 E(q) q̇ with
//! E = [[−x, w, z, −y], [−y, −z, w, x], [−z, y, −x, w]] (from q̇ = ½ q ⊗ (0, ω)), so
//! L = I⊥ (ω₁² + ω₂²)/2 + I∥ ω₃²/2 − m g l R₃₃(q), R₃₃ = w² − x² − y² + z² the vertical
//! component of the symmetry axis (cos θ in eq. 92). E q = 0, so the mass matrix 4EᵀIE has rank 3:
//! the constraint makes the system regular.

#![allow(dead_code)]

use lagrange::prelude::*;

/// The symmetric heavy top in unit-quaternion coordinates (m g l given as one parameter).
#[derive(Debug, Clone, Copy)]
pub struct QuaternionTop {
    /// Moment of inertia about a transverse axis through the fixed point.
    pub i_perp: f64,
    /// Moment of inertia about the symmetry axis.
    pub i_par: f64,
    /// Mass × gravity × distance from the fixed point to the centre of mass.
    pub mgl: f64,
}

#[lagrangian]
impl QuaternionTop {
    fn lagrangian(
        &self,
        (w, w_dot): Coord,
        (x, x_dot): Coord,
        (y, y_dot): Coord,
        (z, z_dot): Coord,
    ) -> Scalar {
        let o1 = 2.0 * (-x * w_dot + w * x_dot + z * y_dot - y * z_dot);
        let o2 = 2.0 * (-y * w_dot - z * x_dot + w * y_dot + x * z_dot);
        let o3 = 2.0 * (-z * w_dot + y * x_dot - x * y_dot + w * z_dot);
        self.i_perp / 2.0 * (o1 * o1 + o2 * o2) + self.i_par / 2.0 * o3 * o3
            - self.mgl * (w * w - x * x - y * y + z * z)
    }

    /// The unit norm of the quaternion.
    fn constraints(
        &self,
        (w, _): Coord,
        (x, _): Coord,
        (y, _): Coord,
        (z, _): Coord,
    ) -> [Scalar; 1] {
        [w * w + x * x + y * y + z * z - 1.0]
    }
}

/// The Hamilton product a ⊗ b of quaternions (w, x, y, z).
pub fn qmul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The state (q, q̇) of the z-x-z Euler angles (θ, φ, ψ) and their rates: q = q_z(φ) ⊗ q_x(θ) ⊗
/// q_z(ψ), q̇ = ½ q ⊗ (0, ω) with the body angular velocity ω of the Euler rates.
pub fn from_euler(angles: [f64; 3], rates: [f64; 3]) -> ([f64; 4], [f64; 4]) {
    let [theta, phi, psi] = angles;
    let [td, pd, sd] = rates;
    let qz = |a: f64| [(a / 2.0).cos(), 0.0, 0.0, (a / 2.0).sin()];
    let qx = |a: f64| [(a / 2.0).cos(), (a / 2.0).sin(), 0.0, 0.0];
    let q = qmul(qmul(qz(phi), qx(theta)), qz(psi));
    let omega = [
        pd * theta.sin() * psi.sin() + td * psi.cos(),
        pd * theta.sin() * psi.cos() - td * psi.sin(),
        pd * theta.cos() + sd,
    ];
    let d = qmul(q, [0.0, omega[0], omega[1], omega[2]]);
    (q, [d[0] / 2.0, d[1] / 2.0, d[2] / 2.0, d[3] / 2.0])
}

/// The symmetry axis R e₃ in space: (sin φ sin θ, −cos φ sin θ, cos θ) in Euler angles.
pub fn axis(q: &[f64; 4]) -> [f64; 3] {
    let [w, x, y, z] = *q;
    [
        2.0 * (x * z + w * y),
        2.0 * (y * z - w * x),
        w * w - x * x - y * y + z * z,
    ]
}

/// d/dt of the axis' vertical component R₃₃ = cos θ: zero at the turning points of the nutation.
/// Written as −4(x ẋ + y ẏ), which equals 2(w ẇ − x ẋ − y ẏ + z ż) on |q| = 1 (where
/// w ẇ + z ż = −(x ẋ + y ẏ)) without its cancellation near upright: its sign stays right there.
pub fn axis_z_rate(q: &[f64; 4], qdot: &[f64; 4]) -> f64 {
    -4.0 * (q[1] * qdot[1] + q[2] * qdot[2])
}

/// The angle of the axis from the upward vertical, accurate near upright:
/// 1 − cos θ = 2(x² + y²) (on |q| = 1), so θ = 2 asin √(x² + y²).
pub fn tilt(q: &[f64; 4]) -> f64 {
    2.0 * (q[1] * q[1] + q[2] * q[2]).sqrt().min(1.0).asin()
}
