//! Three bodies in a plane under Newtonian gravity, as the `orbits` example and the
//! variational-equation tests declare them, with the figure-eight choreography's initial data
//! (Chenciner & Montgomery 2000; the numbers of Simó's search).

use lagrange::prelude::*;

/// Three point masses in the plane, attracting each other with G m_i m_j / r_ij.
pub struct ThreeBody {
    /// Masses.
    pub m1: f64,
    /// Masses.
    pub m2: f64,
    /// Masses.
    pub m3: f64,
    /// The gravitational constant.
    pub g: f64,
}

#[lagrangian]
impl ThreeBody {
    fn lagrangian(
        &self,
        (x1, x1_dot): Coord,
        (y1, y1_dot): Coord,
        (x2, x2_dot): Coord,
        (y2, y2_dot): Coord,
        (x3, x3_dot): Coord,
        (y3, y3_dot): Coord,
    ) -> Scalar {
        let r12 = ((x1 - x2).powi(2) + (y1 - y2).powi(2)).sqrt();
        let r13 = ((x1 - x3).powi(2) + (y1 - y3).powi(2)).sqrt();
        let r23 = ((x2 - x3).powi(2) + (y2 - y3).powi(2)).sqrt();
        0.5 * self.m1 * (x1_dot.powi(2) + y1_dot.powi(2))
            + 0.5 * self.m2 * (x2_dot.powi(2) + y2_dot.powi(2))
            + 0.5 * self.m3 * (x3_dot.powi(2) + y3_dot.powi(2))
            + self.g * (self.m1 * self.m2 / r12 + self.m1 * self.m3 / r13 + self.m2 * self.m3 / r23)
    }
}

/// Unit masses and G = 1 (the figure-eight's units).
pub const UNIT: ThreeBody = ThreeBody {
    m1: 1.0,
    m2: 1.0,
    m3: 1.0,
    g: 1.0,
};

/// The figure-eight's positions (x₁, y₁, x₂, y₂, x₃, y₃): x₁ = −x₂ = (0.97000436, −0.24308753),
/// x₃ = 0.
pub const FIGURE_EIGHT_Q0: [f64; 6] = [0.97000436, -0.24308753, -0.97000436, 0.24308753, 0.0, 0.0];

/// The figure-eight's velocities: v₃ = (−0.93240737, −0.86473146), v₁ = v₂ = −v₃/2.
pub const FIGURE_EIGHT_V0: [f64; 6] = [
    0.466203685,
    0.43236573,
    0.466203685,
    0.43236573,
    -0.93240737,
    -0.86473146,
];

/// The figure-eight's period, to the digits the initial data carry.
pub const FIGURE_EIGHT_PERIOD: f64 = 6.32591398;
