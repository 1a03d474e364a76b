//! What the run machinery asks of a system, as a trait object: the driver (sampling, events, the
//! work integral, the failure and its stiffness diagnosis), the option checks and the trajectory
//! are compiled once per N, not once per system. The steppers' arithmetic stays specialized per
//! system, where the generated kernels inline (DOP853's stages with the cyclic positions known
//! when it compiles).

use crate::error::{DynamicsError, DynamicsResult};
use crate::jet::HessianJet;
use crate::lagrangian::{AppliedJacobian, Lagrangian, applied_jacobian, hessian_jet};
use crate::linearize::jet_linearize;

/// A system seen by the run machinery (every [`Lagrangian`] is one).
pub(crate) trait System<const N: usize> {
    /// q̈ at (q, q̇, t) ([`Lagrangian::accelerations`]).
    fn accelerations(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> DynamicsResult<[f64; N]>;
    /// p = ∂L/∂q̇ at (q, q̇, t) ([`Lagrangian::momenta`]).
    fn momenta(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> [f64; N];
    /// L with its gradient and Hessian at (q, q̇, t) ([`hessian_jet`]).
    fn hessian_jet(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> HessianJet<N>;
    /// The applied forces Q − ∂D/∂q̇ and their Jacobians at (q, q̇, t) ([`applied_jacobian`]).
    fn applied_jacobian(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> AppliedJacobian<N>;
    /// E at (q, q̇, t) ([`Lagrangian::energy`]).
    fn energy(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64;
    /// E and p at (q, q̇, t) ([`Lagrangian::energy_and_momenta`]).
    fn energy_and_momenta(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> (f64, [f64; N]);
    /// dE/dt ([`Lagrangian::power`]).
    fn power(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64;
    /// A non-finite dynamics error traced to the applied forces where it starts there.
    fn blame(&self, e: DynamicsError) -> DynamicsError;
    /// The sizes |λ| of the eigenvalues of the linearized motion at (q, q̇, t), from the jets
    /// (`None` where the linearization fails).
    fn mode_sizes(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Option<Vec<f64>>;
    /// The system's declarations.
    fn flags(&self) -> Flags<N>;
    /// The construct of the body that is not analytic along the motion, if any
    /// ([`Compiled::not_analytic`](crate::lagrangian::Compiled::not_analytic)).
    fn not_analytic(&self) -> Option<&'static str>;
    /// Whether the system has its Taylor series (compiled by the symbolic mode): tried at y.
    fn has_series(&self, y: &[[f64; N]; 2], t: f64) -> bool;
}

/// A system's declarations ([`Lagrangian::COORDINATES`], `CYCLIC`, …), as values.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Flags<const N: usize> {
    pub(crate) coordinates: [&'static str; N],
    pub(crate) cyclic: [bool; N],
    pub(crate) autonomous: bool,
    pub(crate) momentum_conserved: [bool; N],
    pub(crate) energy_conserved: bool,
    /// Whether the system declares holonomic or velocity constraints ([`Compiled::constrained`](crate::lagrangian::Compiled::constrained)).
    pub(crate) constrained: bool,
    /// Whether the system declares contacts ([`Lagrangian::DECLARES_CONTACTS`]).
    pub(crate) contacts: bool,
}

impl<L: Lagrangian<N>, const N: usize> System<N> for L {
    fn accelerations(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> DynamicsResult<[f64; N]> {
        Lagrangian::accelerations(self, q, qdot, t)
    }
    fn momenta(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> [f64; N] {
        Lagrangian::momenta(self, q, qdot, t)
    }
    fn hessian_jet(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> HessianJet<N> {
        hessian_jet(self, q, qdot, t)
    }
    fn applied_jacobian(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> AppliedJacobian<N> {
        applied_jacobian(self, q, qdot, t)
    }
    fn energy(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64 {
        Lagrangian::energy(self, q, qdot, t)
    }
    fn energy_and_momenta(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> (f64, [f64; N]) {
        Lagrangian::energy_and_momenta(self, q, qdot, t)
    }
    fn power(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64 {
        Lagrangian::power(self, q, qdot, t)
    }
    fn blame(&self, e: DynamicsError) -> DynamicsError {
        crate::lagrangian::blame_applied(self, e)
    }
    fn mode_sizes(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Option<Vec<f64>> {
        if let Some(j) = self.first_order_jacobian(q, qdot, t) {
            let eig = j.ok()?.complex_eigenvalues();
            return Some(eig.iter().map(|l| l.norm()).collect());
        }
        let eig = jet_linearize(self, q, qdot, t).ok()?.eigenvalues().ok()?;
        Some(eig.iter().map(|l| l.norm()).collect())
    }
    fn flags(&self) -> Flags<N> {
        Flags {
            coordinates: L::COORDINATES,
            cyclic: L::CYCLIC,
            autonomous: L::AUTONOMOUS,
            momentum_conserved: L::MOMENTUM_CONSERVED,
            energy_conserved: L::ENERGY_CONSERVED,
            constrained: L::COMPILED.constrained,
            contacts: L::DECLARES_CONTACTS,
        }
    }
    fn not_analytic(&self) -> Option<&'static str> {
        L::COMPILED.not_analytic
    }
    fn has_series(&self, y: &[[f64; N]; 2], t: f64) -> bool {
        let mut out = [*y, [[0.0; N]; 2]];
        let mut buf = crate::taylor::TaylorBuf::new();
        L::series_in(&[self], &mut Vec::new(), t, &mut out, &mut buf).is_some()
    }
}
