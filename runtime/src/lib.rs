//! Run-time support for [lagrange](https://docs.rs/lagrange): the [`Scalar`] number trait, the
//! forward-mode jets that derive the Euler–Lagrange equations of any Lagrangian written generically
//! over it, the small dense solves for the mass matrix, and the [`Lagrangian`] trait.
//!
//! Users normally depend on the facade crate `lagrange`, which re-exports all of this.
#![deny(unsafe_code)]
#![warn(missing_docs)]
// Numeric kernels over fixed-size arrays index several arrays at once and read as the math.
#![allow(clippy::needless_range_loop)]

pub mod animation;
pub mod constraints;
pub mod contact;
pub mod ensemble;
pub mod eom;
pub mod error;
pub mod geometry;
pub mod impact;
pub mod integrate;
pub mod jet;
pub mod lagrangian;
pub mod lanes;
pub mod linalg;
pub mod linearize;
#[doc(hidden)]
pub mod mix;
pub mod real;
pub mod rigid;
mod scalar;
pub mod scene;
pub mod tangent;
pub mod taylor;

pub use constraints::{Holonomic, Nonholonomic};
pub use contact::{Contact, Unilateral};
pub use ensemble::{Ensemble, Member};
pub use eom::solve_mass_matrix;
pub use error::{DynamicsError, DynamicsResult};
pub use integrate::sensitivity;
pub use integrate::{
    ConstraintResidual, DenseOutputError, Direction, Drift, Event, EventHit, EventSensitivity,
    INVARIANT_FLOOR, Invariants, Jump, Method, MethodSpec, NamedInvariants, PartialTrajectory,
    Sample, Sensitivities, Sensitivity, Simulation, SimulationError, Stats, Stiffness, Trajectory,
    Zeno,
};
pub use lagrangian::{Lagrangian, el_jet, hessian_jet};
pub use linearize::{
    ConstrainedLinearization, Linearization, LinearizationError, Linearize, LinearizeConstrained,
    Mode, Stability, equilibrium,
};
pub use nalgebra::{DMatrix, SMatrix, Vector3};
pub use scalar::{Scalar, Velocity};
