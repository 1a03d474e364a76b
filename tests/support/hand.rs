//! Hand-written `impl Lagrangian` systems, the runtime alone without the macro: the heavy
//! symmetric top (reference text eq. 92) and the damped, driven oscillator (with dissipation and a
//! generalized force). Used by the integrator, forces, linearization and hand-written tests.

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

/// m ẍ + b ẋ + k x = F cos(ω t), declared by hand: L = m ẋ²/2 − k x²/2, D = b ẋ²/2, Q = F cos ωt.
#[derive(Clone, Copy)]
pub struct Oscillator {
    /// Mass.
    pub m: f64,
    /// Spring constant.
    pub k: f64,
    /// Friction coefficient.
    pub b: f64,
    /// Drive amplitude.
    pub f: f64,
    /// Drive frequency.
    pub w: f64,
}

impl Lagrangian<1> for Oscillator {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    const ENERGY_CONSERVED: bool = false;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * (self.m / 2.0) - q[0] * q[0] * (self.k / 2.0)
    }
    fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * (self.b / 2.0)
    }
    fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], t: S) -> [S; 1] {
        [(t * self.w).cos() * self.f]
    }
}
