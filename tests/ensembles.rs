//! Integration tests, part 3 of 3 (one test crate whose modules are files of tests/): ensembles —
//! sweeps on threads, shards and CSV (`ensemble`), and the SIMD lanes engines of DOP853 and the
//! Taylor method against single runs (`ensemble_lanes`); and the implicit method on stiff systems
//! (`stiff`), redundant constraints (`redundant`), the IVP test set's mechanical problems
//! (`testset`), sensitivities through constraints (`constrained_sensitivity`) and jumps
//! (`jump_sensitivity`), the resetting
//! events (`impacts`), contacts (`contacts`) and contacts with constraints (`contact_constraints`),
//! and the Whipple bicycle (`bicycle`). Apart from
//! tests/physics.rs because the lanes engines and Radau5 are large generic code instantiated per
//! system: the three parts build in parallel, and the physics part alone had become the build's
//! critical path (340 s of a 6 min 43 s test build, 2026-11-27).
//!
//! Run one module with `cargo test --test ensembles ensemble_lanes::`.

mod support;

mod animation;
mod bicycle;
mod constrained_sensitivity;
mod contact_constraints;
mod contact_sensitivity;
mod contacts;
mod ensemble;
mod ensemble_lanes;
mod exact_parameters;
mod impacts;
mod implicit_sensitivity;
mod jump_sensitivity;
mod limits;
mod one_run;
mod redundant;
mod sections;
mod stiff;
mod testset;
