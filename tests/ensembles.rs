//! Integration tests, part 3 of 3 (one test crate whose modules are files of tests/): ensembles —
//! sweeps on threads, shards and CSV (`ensemble`), and the SIMD lanes engines of DOP853 and the
//! Taylor method against single runs (`ensemble_lanes`). Apart from tests/physics.rs because the
//! lanes engines are large generic code instantiated per system: the three parts build in
//! parallel.
//!
//! Run one module with `cargo test --test ensembles ensemble_lanes::`.

mod support;

mod ensemble;
mod ensemble_lanes;
