//! The heavy symmetric top (reference text eq. 92) as a hand-written `impl Lagrangian<3>`: the
//! runtime alone, without the macro. Used by tests/hand_written.rs and tests/integrators.rs.

use lagrange::prelude::*;

/// The symmetric heavy top with I⊥, I∥ and m g l; coordinates θ, φ, ψ (φ and ψ cyclic).
pub struct HeavyTop {
    /// Transverse moment of inertia I⊥.
    pub i_perp: f64,
    /// Axial moment of inertia I∥.
    pub i_par: f64,
    /// m g l.
    pub mgl: f64,
}

impl Lagrangian<3> for HeavyTop {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], qd: &[S; 3], _t: S) -> S {
        let (s, c) = q[0].sin_cos();
        let w3 = qd[2] + qd[1] * c;
        (qd[0] * qd[0] + qd[1] * qd[1] * s * s) * (self.i_perp / 2.0) + w3 * w3 * (self.i_par / 2.0)
            - c * self.mgl
    }
}
