//! The damped driven pendulum as the `driven_pendulum` example and the forces bench declare it
//! (the contract's text): m l² θ̈ + b θ̇ + m g l sin θ = a cos(w t).

use lagrange::prelude::*;

/// A pendulum with viscous friction b at the pivot and a periodic torque a cos(w t).
pub struct DrivenPendulum {
    /// Mass of the bob.
    pub m: f64,
    /// Length of the rod.
    pub l: f64,
    /// Gravity.
    pub g: f64,
    /// Friction coefficient at the pivot.
    pub b: f64,
    /// Drive amplitude (a torque).
    pub a: f64,
    /// Drive angular frequency.
    pub w: f64,
}

#[lagrangian]
impl DrivenPendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.m * self.l * self.l * theta_dot.powi(2) + self.m * self.g * self.l * theta.cos()
    }
    /// Rayleigh dissipation function D(q, q̇, t) ≥ 0; its −∂D/∂q̇ joins the generalized forces.
    fn dissipation(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.b * theta_dot.powi(2)
    }
    /// Generalized forces Q(q, q̇, t), one per coordinate in declaration order.
    fn forces(&self, (theta, theta_dot): Coord, t: Time) -> [Scalar; 1] {
        [self.a * (self.w * t).cos()]
    }
}
