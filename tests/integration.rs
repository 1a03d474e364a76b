//! The integration tests, one test crate (one binary to build and link instead of one per file).
//! Each module is one of the other files of tests/ (crate-root modules resolve next to this
//! file); `support` holds what they share, the systems declared once among it. The compile-fail
//! and compile-pass cases are the other test target, tests/ui.rs.
//!
//! Run one module with `cargo test --test integration heavy_top::`.

// First: `twins!` (tests/support/systems.rs) is in scope for the modules declared after it.
#[macro_use]
mod support;

mod gallery;
mod hand_written;
mod heavy_top;
mod integrators;
mod lint_clean;
mod macro_contract;
mod non_inertial;
mod rigid_body;
mod symbolic;
