//! Sensitivities of a run: the variational equations integrated with the motion.
//!
//! [`Simulation::sensitivity`](crate::Simulation::sensitivity) turns a run into one that also
//! carries the state transition matrix Φ(t) = ∂(q, q̇)(t)/∂(q₀, q̇₀) and, for parameters named
//! with [`Sensitivity::parameter`], S(t) = ∂(q, q̇)(t)/∂p. They obey
//!
//! ```text
//! Φ̇ = J Φ,  Φ(t₀) = I          Ṡ = J S + ∂f/∂p,  S(t₀) = 0
//! J = [[0, I], [∂q̈/∂q, ∂q̈/∂q̇]] = [[0, I], [−M⁻¹K, −M⁻¹C]]
//! ```
//!
//! with J exact: where the system has a compiled q̈ (the symbolic mode) the generated kernel
//! evaluated in [`Tangent`](crate::tangent::Tangent)s — the derivative of the generated code,
//! two passes (along q, along q̇) — and otherwise, or where that kernel's pivot test declines,
//! M, C, K of the linearization about the motion through the current state
//! ([`jet_linearize`](crate::linearize::jet_linearize): third derivatives of L from the jets).
//! Forces, dissipation and explicit time are included either way. ∂f/∂p = (0, ∂q̈/∂p) is exact
//! where the parameter is a field the compiled kernels read ([`Sensitivity::field`], or a
//! closure that sets fields affinely): the kernel's parameter slots seeded in the same tangents
//! as the state; otherwise a fourth-order central difference in p of the accelerations of the
//! systems the parameter's closure builds.
//!
//! **How it is integrated.** A sensitivity run is a problem, not a method: the motion and its
//! 2N + P columns of variations form one state (`augmented::Aug`) with the variational
//! equations as its right-hand side, and the same explicit Runge–Kutta stepper that runs a plain
//! run (`explicit::ExplicitRk`, any tableau: DOP853, Dormand–Prince, RK4) steps it, with its
//! dense output for samples and events; the driver tells the problem through two hooks when it
//! records a sample or locates an event, so Φ is recorded exactly there. The error control is
//! the motion's (as CVODES does by default): the steps, and so the motion, are the plain run's
//! bit for bit, and the variations are the method applied to the variational equations with
//! those steps — the exact derivative of the discrete flow, of the motion's order.
//!
//! **The Taylor method** (`Method::Taylor`, systems with a compiled series) steps the motion as in
//! a plain run, carrying the columns (`taylor`'s `VarSeries`): it takes the generated
//! series of the motion in tangents whose order-0 slopes are the columns at the node: the slopes
//! of the k-th coefficients are the k-th Taylor coefficients of the variations, so the
//! variational equations get their Taylor series from the same generated code (N columns per
//! evaluation), summed at the motion's Jorba–Zou step; a parameter's explicit part comes from the
//! same evaluation where it is a field (its slots seeded), else from the central difference of
//! the neighbouring systems' series.
//!
//! **Events.** At each located event t* (g(t*, q, q̇) = 0) the run also gives the sensitivity of
//! the event's time, dt*/dx₀ = −(∂g/∂x · Φ(t*)) / ġ with ġ = ∂g/∂t + ∂g/∂x · f, and
//! dt*/dp the same way with S. ∂g/∂(t, q, q̇) is a fourth-order central difference of the event
//! function (it is a closure of numbers); at a grazing hit (ġ = 0) the event time is not
//! differentiable and the sensitivity is `None`.
//!
//! **Periodic orbits and Lyapunov exponents.** [`Shooting`] finds a periodic orbit by Newton on
//! x(t₀ + T) − x₀ with the monodromy Φ(t₀ + T) (its [`PeriodicOrbit`] has the Floquet
//! multipliers and an [`OrbitStability`] verdict); [`Lyapunov`] computes the exponents of a
//! motion by QR re-orthonormalization of the carried directions.
//!
//! **Constrained runs** (holonomic and velocity constraints) integrate the variations with the
//! Jacobian of the constrained accelerations (the first-order Jacobian of the
//! constrained view); Φ(t0) is the derivative of the projection onto the constraints, so Φ maps
//! a perturbation of the start to that of the run started from its projection, and its columns
//! stay tangent to the constraints.
//!
//! **Resetting events** (the explicit methods and the Taylor method): at a jump y⁺ = R(t*, y⁻) of an event whose
//! function h crosses zero, Φ jumps to S Φ with the saltation matrix
//! S = ∂R/∂y + (f⁺ − ∂R/∂y f⁻ − ∂R/∂t)(∂h/∂y)/ḣ (f∓ the flow on either side, ḣ the rate h
//! crosses zero at; ∂R, ∂h by fourth-order differences): the derivative of the flow that jumps.
//!
//! **Radau5:** Φ is the derivative of the method's discrete flow, exact for the steps the
//! motion takes: after a step from y₀ with stages Z = h (A ⊗ I) F(y₀ + Z), the implicit
//! function theorem gives D = (∂Z/∂y₀) Φ₀ from (I − h (A ⊗ I) diag(J₁, J₂, J₃)) D =
//! h (A ⊗ I) (J₁ Φ₀, J₂ Φ₀, J₃ Φ₀) with the stages' exact Jacobians Jᵢ (three per step and
//! one LU of dimension 6N), and Φ₁ = Φ₀ + D₃; between nodes Φ follows the collocation
//! polynomial. Its error is the method's (order 5), not controlled on its own. A parameter's
//! column moves likewise, its stage slopes J S + ∂f/∂p.
//!
//! **The variational integrator:** Φ is the derivative of its discrete map
//! (q_k, p_k) ↦ (q_{k+1}, p_{k+1}), by the implicit function theorem on its discrete
//! Euler–Lagrange equation R(q_k, q_{k+1}, p_k) = 0 (the Hessian jet and the applied forces'
//! Jacobians at the midpoint, which its Newton solve has already), carried in (q, p) and read in
//! (q, q̇) through the Legendre map's derivative at the nodes and the interpolant's between them.
//! A parameter's column: R and p_{k+1} − p_k = h (∂L/∂q + F) at the midpoint move with p (their
//! ∂/∂p by fourth-order differences over the systems the parameter's closure builds), so does
//! the start's momentum (the start is given in (q, q̇)), and q̇ at a node through the Legendre
//! map's ∂/∂p.
//!
//! **Not covered (refused with [`SimulationError::InvalidOptions`](crate::SimulationError)):**
//! constraints (RATTLE) or a field alone (`.field`) with the variational integrator, parameters of a run
//! with resetting events (the reset and the event's function are closures the parameters do
//! not reach) or contacts, and of a run built on a view given directly
//! (`Simulation::constrained`: no closure can build it).
//!
//! **Parameters of a constrained run** (the system's own constraints, `Simulation::new`): each
//! parameter's closure builds the system at its neighbouring values, and ∂q̈/∂p is the
//! fourth-order difference of those systems' *constrained* accelerations (the constraints may
//! read the parameter: a rod's length); the parameter's column starts at ∂/∂p of the start's
//! projection onto the constraints of the system at p (the start moves with such a
//! constraint). A field given alone (`.field`) has no neighbouring systems and is refused
//! there, naming the closure form.
//!
//! ```
//! use lagrange_runtime::{Lagrangian, Scalar, Simulation};
//! /// ẍ = −x: Φ(t) = [[cos t, sin t], [−sin t, cos t]].
//! struct Osc;
//! impl Lagrangian<1> for Osc {
//!     const COORDINATES: [&'static str; 1] = ["x"];
//!     const CYCLIC: [bool; 1] = [false];
//!     const AUTONOMOUS: bool = true;
//!     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
//! }
//! let run = Simulation::new(&Osc, [1.0], [0.0]).until(2.0).sensitivity().run().unwrap();
//! let phi = run.phi.last().unwrap();
//! assert!((phi[(0, 0)] - 2.0_f64.cos()).abs() < 1e-9 && (phi[(0, 1)] - 2.0_f64.sin()).abs() < 1e-9);
//! ```

mod augmented;
mod builder;
mod event_time;
mod lyapunov;
mod periodic;
mod result;
mod saltation;
mod taylor;
mod variation;

pub use builder::Sensitivity;
pub use lyapunov::{Lyapunov, Spectrum};
pub use periodic::{
    MULTIPLIER_TOL, OrbitError, OrbitStability, PeriodicOrbit, Shooting, TRIVIAL_RADIUS,
    multipliers,
};
pub use result::{EventSensitivity, Sensitivities};
pub(crate) use variation::{central, difference_step};

pub(crate) use super::jacobian::CHUNK;

/// What the driver's hooks record while a sensitivity run goes: the variations (the columns
/// after y, flattened) at each recorded sample, with its time as recorded, and at each event hit
/// with the event's index.
#[derive(Default)]
pub(crate) struct Log {
    pub(crate) samples: Vec<(f64, Vec<f64>)>,
    pub(crate) events: Vec<(f64, usize, Vec<f64>)>,
    /// The state (q, q̇) at each event hit, flattened (a jump's saltation matrix needs the
    /// state before it).
    pub(crate) states: Vec<Vec<f64>>,
    /// The rate ẏ at each hit of the curve the hit was located on, where the method's
    /// interpolant does not follow f to its order (the variational integrator's linear q̇);
    /// `None`: f.
    pub(crate) rates: Vec<Option<Vec<f64>>>,
}

impl Log {
    /// Records a hit of event `event` at t with the columns there, the state y there and the
    /// located curve's rate where it is not f (see [`rates`](Self::rates)).
    pub(crate) fn event<const N: usize>(
        &mut self,
        t: f64,
        event: usize,
        cols: Vec<f64>,
        y: &super::state::Y<N>,
        rate: Option<Vec<f64>>,
    ) {
        self.events.push((t, event, cols));
        self.states.push(y.iter().flatten().copied().collect());
        self.rates.push(rate);
    }
}
