//! The heavy top of the benchmarks as a user writes it: `#[lagrangian]` in the default (symbolic)
//! mode, m g l as one parameter. Shared by benches/integrators.rs, benches/taylor.rs and
//! benches/ensemble.rs.

use lagrange::prelude::*;

/// The symmetric heavy top, eq. 92.
#[derive(Debug, Clone, Copy)]
pub struct MacroTop {
    /// Moment of inertia about a transverse axis through the fixed point.
    pub i_perp: f64,
    /// Moment of inertia about the symmetry axis.
    pub i_par: f64,
    /// Mass × gravity × distance from the fixed point to the centre of mass.
    pub mgl: f64,
}

#[lagrangian]
impl MacroTop {
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let (s, c) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
            - self.mgl * c
    }
}
