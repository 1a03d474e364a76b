//! Integration tests, part 1 of 2 (each part is one test crate whose modules are files of
//! tests/; crate-root modules resolve next to this file): the equations of motion of declared
//! and hand-written systems against closed forms and against the run-time jets, the macro
//! contract and its lint cleanliness; and the compass-gait walker's gaits (`walker`, its
//! own crate's weight kept off the larger parts). Part 2, tests/physics.rs, simulates the reference text's
//! physics. `support` holds what both share, the systems declared once among it. The
//! compile-fail cases are tests/ui.rs, the package tests/Cargo.toml.
//!
//! Run one module with `cargo test --test equations symbolic::`.

// First: `twins!` (tests/support/systems.rs) is in scope for the modules declared after it.
mod support;

mod constraints_macro;
mod deep_bodies;
mod gallery;
mod geometry;
mod hand_written;
mod hygiene;
mod language;
mod lint_clean;
mod macro_contract;
mod pieces;
mod rolling;
mod symbolic;
mod walker;
