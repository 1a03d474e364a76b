//! The symmetric heavy top of eq. 92, as the heavy-top examples (`heavy_top`, `sleeping_top`,
//! `fast_top`) declare it: the Lagrangian written the way the equation reads.

use lagrange::prelude::*;

/// The symmetric heavy top, eq. 92 of the reference text (m g l given as one parameter).
#[derive(Debug, Clone, Copy)]
pub struct HeavyTop {
    /// Moment of inertia about a transverse axis through the fixed point.
    pub i_perp: f64,
    /// Moment of inertia about the symmetry axis.
    pub i_par: f64,
    /// Mass × gravity × distance from the fixed point to the centre of mass.
    pub mgl: f64,
}

#[lagrangian]
impl HeavyTop {
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        self.i_perp / 2.0 * (theta_dot.powi(2) + phi_dot.powi(2) * theta.sin().powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * theta.cos()).powi(2)
            - self.mgl * theta.cos()
    }

    /// What the top looks like: its axis from the fixed point, a disc across it with a mark on
    /// its rim (the spin), and the trace of the axis's tip (the nutation's waves or loops).
    fn scene(&self, (theta, _): Coord, (phi, _): Coord, (psi, _): Coord) -> Scene {
        let body = Rotation::about_z(phi) * Rotation::about_x(theta) * Rotation::about_z(psi);
        let along = |s: f64, x: f64| body * Vector3::new(x, 0.0, s);
        Scene::new()
            .sphere("pivot", Vector3::zeros(), 0.05, Rgb::BLACK)
            .rod("axis", Vector3::zeros(), along(1.2, 0.0), 0.025, Rgb::GREY)
            .disc("body", body, along(0.8, 0.0), 0.4, 0.1, Rgb::ORANGE)
            .sphere("mark", along(0.8, 0.4), 0.05, Rgb::STEEL)
            .trace("axis tip", along(1.2, 0.0), Rgb::RED)
    }
}
