//! What a sensitivity run returns: the trajectory, Φ and ∂(q, q̇)/∂p at its samples, and the
//! sensitivities of its events' times.

use nalgebra::DMatrix;

use super::super::trajectory::Trajectory;

/// A run with its sensitivities ([`Sensitivity::run`](crate::Sensitivity::run)).
///
/// Φ and the parameter sensitivities are matrices whose rows are (q, q̇) at the sample time
/// (coordinates first, then velocities, in declaration order) and whose columns are
/// (q₀, q̇₀) in the same order, then the parameters.
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
/// /// A free particle: q(t) = q₀ + q̇₀ t, so Φ = [[1, t], [0, 1]].
/// struct Free;
/// impl Lagrangian<1> for Free {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
/// }
/// let run = Simulation::new(&Free, [0.0], [1.0]).until(3.0).sample_every(1.0).sensitivity().run().unwrap();
/// assert_eq!(run.phi.len(), run.trajectory.t.len());
/// assert!((run.phi[2][(0, 1)] - 2.0).abs() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct Sensitivities<const N: usize> {
    /// The run itself (as [`Simulation::run`](crate::Simulation::run) records it).
    pub trajectory: Trajectory<N>,
    /// Φ(t) = ∂(q, q̇)(t)/∂(q₀, q̇₀) at each sample of the trajectory (2N × 2N).
    pub phi: Vec<DMatrix<f64>>,
    /// The names of the parameters, in the order of the columns of `dparams`.
    pub parameters: Vec<String>,
    /// ∂(q, q̇)(t)/∂p at each sample (2N × P, one column per parameter; 2N × 0 without any).
    pub dparams: Vec<DMatrix<f64>>,
    /// The sensitivity of each located event, in the order of `trajectory.events`.
    pub events: Vec<EventSensitivity>,
}

/// The sensitivities at one located event g(t*, q, q̇) = 0.
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Event};
/// /// A free particle from x₀ with speed v₀ reaches x = 1 at t* = (1 − x₀)/v₀:
/// /// dt*/dx₀ = −1/v₀, dt*/dv₀ = −(1 − x₀)/v₀².
/// struct Free;
/// impl Lagrangian<1> for Free {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
/// }
/// let run = Simulation::new(&Free, [0.0], [2.0])
///     .until(1.0)
///     .event(Event::zero_crossing("x = 1", |_t, q: &[f64; 1], _v| q[0] - 1.0))
///     .sensitivity()
///     .run()
///     .unwrap();
/// let dt = run.events[0].dt_dx0.as_ref().unwrap();
/// assert!((dt[0] + 0.5).abs() < 1e-10 && (dt[1] + 0.25).abs() < 1e-10);
/// ```
#[derive(Clone, Debug)]
pub struct EventSensitivity {
    /// The event's name.
    pub name: String,
    /// Its time t*.
    pub t: f64,
    /// Φ(t*).
    pub phi: DMatrix<f64>,
    /// ∂(q, q̇)(t*)/∂p at the fixed time t* (2N × P).
    pub dparams: DMatrix<f64>,
    /// ∂g/∂(q, q̇) at the hit (a fourth-order central difference of the event function).
    pub gradient: Vec<f64>,
    /// ġ = ∂g/∂t + ∂g/∂(q, q̇) · (q̇, q̈) at the hit: the rate g crosses zero at (with the
    /// variational integrator, along its interpolant, on which the hit was located: (q̇, q̈)
    /// there is the interpolant's rate).
    pub rate: f64,
    /// dt*/d(q₀, q̇₀) = −(∂g/∂x · Φ(t*))/ġ; `None` at a grazing hit (ġ = 0 to round-off), where
    /// the event's time is not differentiable.
    pub dt_dx0: Option<Vec<f64>>,
    /// dt*/dp = −(∂g/∂x · S(t*))/ġ per parameter; `None` at a grazing hit.
    pub dt_dp: Option<Vec<f64>>,
    /// The derivative of the state at the event, x(t*(x₀), x₀), with respect to x₀:
    /// Φ(t*) + f(t*) dt*/dx₀ (2N × 2N; a Poincaré map's Jacobian when the event is the
    /// section); `None` at a grazing hit.
    pub dstate_dx0: Option<DMatrix<f64>>,
}

impl<const N: usize> Sensitivities<N> {
    /// Φ at the last sample (the end of the run, or its terminal event).
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let run = Simulation::new(&Free, [0.0], [1.0]).until(2.0).sensitivity().run().unwrap();
    /// assert!((run.final_phi()[(0, 1)] - 2.0).abs() < 1e-12);
    /// ```
    pub fn final_phi(&self) -> &DMatrix<f64> {
        // A run records at least its initial sample, so `phi` is never empty.
        &self.phi[self.phi.len() - 1]
    }
}
