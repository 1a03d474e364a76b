//! Time integration of any [`Lagrangian`](crate::Lagrangian): RK4, Dormand–Prince 5(4), DOP853,
//! Radau IIA (stiff systems), the Taylor method and a variational midpoint integrator, with dense output, events and invariant reports.
//!
//! Build a run with [`Simulation`], pick a [`Method`], add [`Event`]s, and [`Simulation::run`] it to
//! get a [`Trajectory`] (or a [`SimulationError`] that still holds the trajectory up to the
//! failure).
//!
//! ```
//! use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method, Event};
//! /// x'' = -x.
//! struct Osc;
//! impl Lagrangian<1> for Osc {
//!     const COORDINATES: [&'static str; 1] = ["x"];
//!     const CYCLIC: [bool; 1] = [false];
//!     const AUTONOMOUS: bool = true;
//!     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
//!         (v[0] * v[0] - q[0] * q[0]) * 0.5
//!     }
//! }
//! let traj = Simulation::new(&Osc, [1.0], [0.0])
//!     .method(Method::Dop853 { rtol: 1e-10, atol: 1e-12 })
//!     .until(4.0)
//!     .sample_every(0.5)
//!     .event(Event::zero_crossing("x = 0", |_t, q: &[f64; 1], _v| q[0]))
//!     .run()
//!     .unwrap();
//! assert!((traj.events[0].t - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
//! assert_eq!(traj.t.len(), 9);
//! assert!((traj.q[8][0] - 4.0_f64.cos()).abs() < 1e-8);
//! ```

// The layers, each importing only those above it: what every method shares (`state`: the state
// y, faults, the right-hand side and stage combination; `stepper`: the `Stepper` trait and the
// fixed step grid; `control`: error norms and step-size control; `newton`: the Newton solver of
// the implicit methods), the methods (`rk4`, `dopri5`, `dop853`, `radau5`, `taylor`, `variational`), the dense
// output a run keeps of them (`dense`), the `driver` loop that runs any of them, and the public
// builder (`method`, `simulation`, `validate`).
mod contacts;
mod control;
mod dense;
mod dop853;
/// DOP853's tableau (Hairer's published coefficients): benches/ensemble.rs measures the floor of
/// DOP853-shaped steps with it.
#[doc(hidden)]
pub mod dop853_coefficients;
mod dopri5;
mod driver;
mod error;
mod events;
mod explicit;
mod factory;
mod jacobian;
pub(crate) mod lanes;
mod manifold;
mod method;
mod newton;
mod problem;
mod radau5;
mod rattle;
mod report;
mod rk4;
pub mod sensitivity;
mod simulation;
mod state;
mod stepper;
mod stiffness;
mod system;
mod taylor;
mod trajectory;
mod validate;
mod variational;

pub use contacts::ContactView;
pub use dense::DenseOutputError;
pub use error::{PartialTrajectory, SimulationError};
pub use events::{Direction, Event, EventHit, Jump, Zeno};
pub use method::{Method, MethodSpec};
pub use report::NamedInvariants;
pub use sensitivity::{EventSensitivity, Sensitivities, Sensitivity};
pub(crate) use sensitivity::{central, difference_step};
pub use simulation::Simulation;
pub use state::Stats;
pub use stiffness::Stiffness;
pub use trajectory::{ConstraintResidual, Drift, INVARIANT_FLOOR, Invariants, Sample, Trajectory};

#[cfg(test)]
mod tests;
