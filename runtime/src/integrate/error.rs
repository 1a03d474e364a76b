//! [`SimulationError`]: what stopped a run, where (t and the state), what to try, and the
//! trajectory up to that point.

use core::any::Any;
use core::fmt;

use crate::error::{DynamicsError, Short};

use super::stiffness::Stiffness;
use super::trajectory::Trajectory;

/// The trajectory computed before a run failed (type-erased so that [`SimulationError`] does not
/// depend on the number of coordinates). Get it back with
/// [`SimulationError::partial_trajectory`].
///
/// ```
/// use lagrange_runtime::PartialTrajectory;
/// let p = PartialTrajectory::none();
/// assert!(p.get::<2>().is_none());
/// ```
pub struct PartialTrajectory {
    traj: Option<Box<dyn Any + Send + Sync>>,
    /// What the run learned about its fastest motion where that is why it stopped (boxed: the
    /// error stays small).
    stiffness: Option<Box<Stiffness>>,
}

impl PartialTrajectory {
    pub(crate) fn new<const N: usize>(t: Trajectory<N>) -> Self {
        PartialTrajectory {
            traj: Some(Box::new(t)),
            stiffness: None,
        }
    }
    pub(crate) fn with_stiffness(mut self, s: Option<Stiffness>) -> Self {
        self.stiffness = s.map(Box::new);
        self
    }
    /// No trajectory (the run was rejected before the first step).
    ///
    /// ```
    /// assert!(lagrange_runtime::PartialTrajectory::none().get::<1>().is_none());
    /// ```
    pub fn none() -> Self {
        PartialTrajectory {
            traj: None,
            stiffness: None,
        }
    }
    /// The trajectory, if there is one and it has `N` coordinates.
    ///
    /// ```
    /// assert!(lagrange_runtime::PartialTrajectory::none().get::<3>().is_none());
    /// ```
    pub fn get<const N: usize>(&self) -> Option<&Trajectory<N>> {
        self.traj.as_ref()?.downcast_ref::<Trajectory<N>>()
    }
    fn take<const N: usize>(self) -> Option<Trajectory<N>> {
        self.traj?.downcast::<Trajectory<N>>().ok().map(|b| *b)
    }
}

impl fmt::Debug for PartialTrajectory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.traj {
            Some(_) => f.write_str("PartialTrajectory(..)"),
            None => f.write_str("PartialTrajectory(none)"),
        }
    }
}

/// Why a [`Simulation`](crate::Simulation) stopped before reaching its end time.
///
/// Every variant after [`SimulationError::InvalidOptions`] carries the time and the last accepted
/// state, and the trajectory computed up to it ([`SimulationError::partial_trajectory`]).
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar, Simulation, SimulationError, Method};
/// struct Osc;
/// impl Lagrangian<1> for Osc {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
/// }
/// let err = Simulation::new(&Osc, [1.0], [0.0]).method(Method::Rk4 { dt: 0.1 }).until(10.0).max_steps(5).run().unwrap_err();
/// assert!(matches!(err, SimulationError::MaxSteps { .. }));
/// assert_eq!(err.partial_trajectory::<1>().unwrap().t.len(), 6);
/// ```
#[non_exhaustive]
pub enum SimulationError {
    /// The options were rejected by `run()` before any step.
    InvalidOptions {
        /// What is wrong and what to do.
        message: String,
    },
    /// The adaptive step size fell below the round-off limit at t.
    StepSizeUnderflow {
        /// Time of the last accepted state.
        t: f64,
        /// Last accepted coordinates.
        q: Vec<f64>,
        /// Last accepted velocities.
        qdot: Vec<f64>,
        /// The step that was too small.
        h: f64,
        /// The trajectory up to t.
        partial: PartialTrajectory,
    },
    /// The run needed more steps than `max_steps`.
    MaxSteps {
        /// Time reached.
        t: f64,
        /// Coordinates there.
        q: Vec<f64>,
        /// Velocities there.
        qdot: Vec<f64>,
        /// The limit.
        max_steps: usize,
        /// The trajectory up to t.
        partial: PartialTrajectory,
    },
    /// The trajectory reached `max_samples` stored samples at t (recording every step of a long
    /// run): memory is bounded by that option.
    MaxSamples {
        /// Time of the last stored sample.
        t: f64,
        /// Coordinates there.
        q: Vec<f64>,
        /// Velocities there.
        qdot: Vec<f64>,
        /// The limit.
        max_samples: usize,
        /// The bytes one stored sample takes (t, q, q̇, the energy, the momenta, the work and λ).
        sample_bytes: usize,
        /// Whether the limit was the default (a memory budget), not set with `.max_samples(n)`.
        default_limit: bool,
        /// The trajectory up to t.
        partial: PartialTrajectory,
    },
    /// The state became NaN or infinite in the step after t.
    NonFinite {
        /// Time of the last finite state.
        t: f64,
        /// Last finite coordinates.
        q: Vec<f64>,
        /// Last finite velocities.
        qdot: Vec<f64>,
        /// The trajectory up to t.
        partial: PartialTrajectory,
    },
    /// The equations of motion could not be solved (singular mass matrix, non-finite derivatives);
    /// the inner error carries the state where it happened.
    Dynamics {
        /// The dynamics' error (its t, q, q̇ are where it happened).
        source: Box<DynamicsError>,
        /// Time of the last accepted state.
        t: f64,
        /// Last accepted coordinates.
        q: Vec<f64>,
        /// Last accepted velocities.
        qdot: Vec<f64>,
        /// The trajectory up to t.
        partial: PartialTrajectory,
    },
    /// Newton's method of an implicit step (the variational integrator's, Radau5's stage
    /// equations) or of the projection onto the constraints did not converge in the step after t.
    NewtonFailed {
        /// Time of the last accepted state.
        t: f64,
        /// Last accepted coordinates.
        q: Vec<f64>,
        /// Last accepted velocities.
        qdot: Vec<f64>,
        /// Newton iterations made.
        iterations: usize,
        /// The residual when it gave up: the ∞-norm in momentum units (variational integrator),
        /// the weighted RMS of the last Newton increment (Radau5).
        residual: f64,
        /// Which solve failed and why.
        reason: &'static str,
        /// The trajectory up to t.
        partial: PartialTrajectory,
    },
    /// The initial state of a constrained run is not on the constraints g(q, t) = 0 (or its
    /// velocity is not tangent to them, ġ ≠ 0); rejected before any step. Ask for
    /// `.project_initial_state()` to start from the nearest state that is.
    OffConstraints {
        /// The start time.
        t: f64,
        /// The initial coordinates.
        q: Vec<f64>,
        /// The initial velocities.
        qdot: Vec<f64>,
        /// max |g_j(q0, t0)|.
        position_residual: f64,
        /// max |ġ_j(q0, q̇0, t0)| = max |G q̇0 + ∂g/∂t|.
        velocity_residual: f64,
        /// The constraint (index in the order `constraints` returns them) furthest off, relative
        /// to its own scale.
        worst: usize,
    },
    /// A member of an [`Ensemble`](crate::ensemble::Ensemble) panicked (in its member, configure
    /// or reduce closure, or in the system's code): its slot holds this, the other members'
    /// results are kept.
    MemberPanicked {
        /// The member's index.
        member: usize,
        /// The panic's message (or a note that it was not a string).
        message: String,
    },
}

impl SimulationError {
    /// The time of the last accepted state (`None` for invalid options).
    ///
    /// ```
    /// use lagrange_runtime::SimulationError;
    /// assert_eq!(SimulationError::InvalidOptions { message: String::new() }.t(), None);
    /// ```
    pub fn t(&self) -> Option<f64> {
        match self {
            SimulationError::InvalidOptions { .. } | SimulationError::MemberPanicked { .. } => None,
            SimulationError::OffConstraints { t, .. }
            | SimulationError::StepSizeUnderflow { t, .. }
            | SimulationError::MaxSteps { t, .. }
            | SimulationError::MaxSamples { t, .. }
            | SimulationError::NonFinite { t, .. }
            | SimulationError::Dynamics { t, .. }
            | SimulationError::NewtonFailed { t, .. } => Some(*t),
        }
    }

    fn partial(&self) -> Option<&PartialTrajectory> {
        match self {
            SimulationError::InvalidOptions { .. }
            | SimulationError::OffConstraints { .. }
            | SimulationError::MemberPanicked { .. } => None,
            SimulationError::StepSizeUnderflow { partial, .. }
            | SimulationError::MaxSteps { partial, .. }
            | SimulationError::MaxSamples { partial, .. }
            | SimulationError::NonFinite { partial, .. }
            | SimulationError::Dynamics { partial, .. }
            | SimulationError::NewtonFailed { partial, .. } => Some(partial),
        }
    }

    /// The trajectory computed up to the failure (samples, events, counters), if the run started
    /// and it has `N` coordinates. Its last sample is the last accepted state.
    ///
    /// ```
    /// use lagrange_runtime::SimulationError;
    /// let e = SimulationError::InvalidOptions { message: "dt ≤ 0".into() };
    /// assert!(e.partial_trajectory::<1>().is_none());
    /// ```
    pub fn partial_trajectory<const N: usize>(&self) -> Option<&Trajectory<N>> {
        self.partial()?.get::<N>()
    }

    /// Where a run ran out of steps or blew up because of a fast mode of the system (a stiff
    /// spring, a stiff joint): what that mode is and the step it forced (see [`Stiffness`]);
    /// `None` otherwise.
    ///
    /// ```
    /// use lagrange_runtime::SimulationError;
    /// assert!(SimulationError::InvalidOptions { message: String::new() }.stiffness().is_none());
    /// ```
    pub fn stiffness(&self) -> Option<&Stiffness> {
        match self {
            SimulationError::MaxSteps { partial, .. }
            | SimulationError::NonFinite { partial, .. }
            | SimulationError::Dynamics { partial, .. } => partial.stiffness.as_deref(),
            _ => None,
        }
    }

    /// Takes the partial trajectory out of the error.
    ///
    /// ```
    /// use lagrange_runtime::SimulationError;
    /// assert!(SimulationError::InvalidOptions { message: String::new() }.into_partial_trajectory::<1>().is_none());
    /// ```
    pub fn into_partial_trajectory<const N: usize>(self) -> Option<Trajectory<N>> {
        match self {
            SimulationError::InvalidOptions { .. }
            | SimulationError::OffConstraints { .. }
            | SimulationError::MemberPanicked { .. } => None,
            SimulationError::StepSizeUnderflow { partial, .. }
            | SimulationError::MaxSteps { partial, .. }
            | SimulationError::MaxSamples { partial, .. }
            | SimulationError::NonFinite { partial, .. }
            | SimulationError::Dynamics { partial, .. }
            | SimulationError::NewtonFailed { partial, .. } => partial.take::<N>(),
        }
    }
}

/// How the reasons of a failed projection onto the constraints (after an explicit method's step,
/// `manifold::project`) begin, so that the message names the projection rather than the
/// variational integrator's Newton solve.
pub(crate) const PROJECTION: &str = "projecting";

/// The start of every `NewtonFailed` reason that comes from Radau5's stage equations (or its
/// Jacobian), not from the variational integrator: the message then names Radau5.
pub(crate) const RADAU: &str = "Radau5";

impl fmt::Display for SimulationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimulationError::InvalidOptions { message } => {
                write!(f, "invalid simulation options: {message}")
            }
            SimulationError::MemberPanicked { member, message } => write!(
                f,
                "ensemble member {member} panicked: {message}. Its result is lost; the other \
                 members' results are kept. Try: run that member alone (Simulation::new with its \
                 system and state) to see where, and check the member, configure and reduce \
                 closures for indexing or unwrap on its values."
            ),
            SimulationError::OffConstraints {
                t,
                q,
                qdot,
                position_residual,
                velocity_residual,
                worst,
            } => {
                let (t, q, qdot) = shorts(t, q, qdot);
                write!(
                    f,
                    "the initial state is off the constraints at t = {t}, q = {q}, q̇ = {qdot}: \
                     max |g| = {position_residual:.3e}, max |ġ| = {velocity_residual:.3e} (constraint \
                     {worst}, counting from 0, is the furthest off). A constrained run starts on g = 0 \
                     with a velocity tangent to it (G q̇ + ∂g/∂t = 0). Try: compute q0 and q̇0 from \
                     the constraints, or call .project_initial_state() to start from the nearest \
                     state that satisfies them."
                )
            }
            SimulationError::StepSizeUnderflow { t, q, qdot, h, .. } => {
                let (t, q, qdot) = shorts(t, q, qdot);
                write!(
                    f,
                    "step size underflow at t = {t}, q = {q}, q̇ = {qdot}: the adaptive step shrank to \
                     h = {h:e}, below what round-off in t allows. The solution is probably singular or \
                     extremely stiff here (a collision, a blow-up, a chart singularity). Try: check the state \
                     and parameters near this time, loosen rtol/atol, or use other coordinates. The \
                     trajectory up to t is kept (partial_trajectory())."
                )
            }
            SimulationError::MaxSteps {
                t,
                q,
                qdot,
                max_steps,
                partial,
            } => match &partial.stiffness {
                Some(stiff) => {
                    let (t, q, qdot) = shorts(t, q, qdot);
                    write!(
                        f,
                        "maximum number of steps ({max_steps}) reached at t = {t}, q = {q}, q̇ = \
                         {qdot}. {stiff} The trajectory up to t is kept (partial_trajectory())."
                    )
                }
                None => {
                    let (t, q, qdot) = shorts(t, q, qdot);
                    write!(
                        f,
                        "maximum number of steps ({max_steps}) reached at t = {t}, q = {q}, q̇ = \
                         {qdot}. Try: raise .max_steps(), loosen the tolerances or enlarge dt, or \
                         shorten the run. The trajectory up to t is kept (partial_trajectory())."
                    )
                }
            },
            SimulationError::MaxSamples {
                t,
                q,
                qdot,
                max_samples,
                sample_bytes,
                default_limit,
                ..
            } => {
                let (t, q, qdot) = shorts(t, q, qdot);
                write!(
                    f,
                    "the trajectory reached {limit} stored samples at t = {t}, q = {q}, q̇ = {qdot}: \
                     memory is bounded by that option. Try: record less often (.sample_every(Δ) instead of every step), pass the \
                     samples to an observer without storing them (.observe(f).keep_samples(false)), or \
                     raise .max_samples(n). The trajectory up to t is kept (partial_trajectory()).",
                    limit = super::trajectory::max_samples_phrase(
                        *max_samples,
                        *sample_bytes,
                        *default_limit
                    )
                )
            }
            SimulationError::NonFinite {
                t,
                q,
                qdot,
                partial,
            } => match &partial.stiffness {
                Some(stiff) => {
                    let (t, q, qdot) = shorts(t, q, qdot);
                    write!(
                        f,
                        "the state became NaN or infinite in the step after t = {t} (last finite state \
                         q = {q}, q̇ = {qdot}). {stiff} The trajectory up to t is kept \
                         (partial_trajectory())."
                    )
                }
                None => {
                    let (t, q, qdot) = shorts(t, q, qdot);
                    write!(
                        f,
                        "the state became NaN or infinite in the step after t = {t} (last finite state \
                         q = {q}, q̇ = {qdot}). Try: a smaller dt or tighter tolerances, and check that \
                         L is defined along the motion. The trajectory up to t is kept \
                         (partial_trajectory())."
                    )
                }
            },
            SimulationError::Dynamics {
                source,
                t,
                q,
                qdot,
                partial,
            } => {
                let (t, q, qdot) = shorts(t, q, qdot);
                write!(
                    f,
                    "the equations of motion failed in the step after t = {t} (last accepted q = \
                     {q}, q̇ = {qdot}): {source}"
                )?;
                if let Some(stiff) = &partial.stiffness {
                    write!(f, " Why: {stiff}")?;
                }
                f.write_str(" The trajectory up to t is kept (partial_trajectory()).")
            }
            SimulationError::NewtonFailed {
                t,
                q,
                qdot,
                iterations,
                residual,
                reason,
                ..
            } => newton_failed(f, *t, q, qdot, (*iterations, *residual, reason)),
        }
    }
}

/// The place of a failure as its messages print it: t, q and q̇ shortened.
fn shorts<'a>(
    t: &f64,
    q: &'a [f64],
    qdot: &'a [f64],
) -> (Short<f64>, Short<&'a [f64]>, Short<&'a [f64]>) {
    (Short(*t), Short(q), Short(qdot))
}

/// The message of [`SimulationError::NewtonFailed`]: which solve failed (a constrained run's
/// projection, Radau5's stage equations, the variational integrator's step), where, and what
/// to try.
fn newton_failed(
    f: &mut fmt::Formatter<'_>,
    t: f64,
    q: &[f64],
    qdot: &[f64],
    (iterations, residual, reason): (usize, f64, &str),
) -> fmt::Result {
    let (t, q, qdot) = (Short(t), Short(q), Short(qdot));
    if reason.starts_with(PROJECTION) {
        write!(
            f,
            "the projection onto the constraints failed after the step from t = {t} (q = {q}, \
             q̇ = {qdot}): {reason}; {iterations} iterations, residual {residual:e}. Try: a \
             tighter tolerance or a smaller max_step (the step left the constraints too far), \
             or Method::VariationalMidpoint (RATTLE). The trajectory up to t is kept \
             (partial_trajectory())."
        )
    } else if reason.starts_with(RADAU) {
        write!(
            f,
            "the implicit step after t = {t} (q = {q}, q̇ = {qdot}) failed: {reason}; \
             {iterations} iterations, last scaled Newton increment {residual:e}, after the \
             step was halved down to the round-off limit. Try: Method::Dop853 to see whether \
             the motion itself is singular here (a state where the mass matrix degenerates, \
             a force that blows up), or a smaller max_step. The trajectory up to t is kept \
             (partial_trajectory())."
        )
    } else {
        write!(
            f,
            "the variational integrator's Newton solve failed in the step after t = {t} (q = \
             {q}, q̇ = {qdot}): {reason}; {iterations} iterations, residual {residual:e}. Try: a \
             smaller dt, or an explicit method (Dop853) to see whether the motion itself is \
             singular here. The trajectory up to t is kept (partial_trajectory())."
        )
    }
}

impl std::error::Error for SimulationError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SimulationError::Dynamics { source, .. } => Some(source.as_ref()),
            _ => None,
        }
    }
}

impl core::fmt::Debug for SimulationError {
    /// The sentence of `Display` (what happened, where, what to try), without the escapes a
    /// derived `Debug` puts on every combining dot of q̇: what `fn main() -> Result<..>` prints.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(self, f)
    }
}
