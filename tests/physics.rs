//! Integration tests, part 2 of 3 (one test crate whose modules are files of tests/): the
//! reference text's physics simulated end to end (the heavy top, rigid bodies, a particle in a
//! non-inertial frame) and the integrators. Part 1 is tests/equations.rs, part 3 (ensembles, stiff
//! mechanics with Radau5, resetting events) tests/ensembles.rs; the parts build in parallel, which
//! on two cores is faster than one crate.
//!
//! Run one module with `cargo test --test physics heavy_top::`.

mod support;

mod constraints;
mod forces;
mod forces_macro;
mod hardening;
mod heavy_top;
mod integrators;
mod large_systems;
mod linearize;
mod non_inertial;
mod quaternion_top;
mod readable;
mod rigid_body;
mod taylor;
mod taylor_attack;
mod variational_equations;
