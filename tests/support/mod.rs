//! What the modules of the integration test crates (tests/equations.rs, tests/physics.rs,
//! tests/ensembles.rs) share: the systems declared once ([`systems`], also included by
//! benches/symbolic.rs), the hand-written heavy top ([`hand`]) and a small deterministic random
//! generator ([`Rng`]).
// Each test crate uses a subset.
#![allow(dead_code)]

#[macro_use]
pub mod systems;
#[path = "../../examples/support/double_pendulum_system.rs"]
pub mod double_pendulum;
#[path = "../../examples/support/four_bar_system.rs"]
pub mod four_bar;
pub mod hand;
#[path = "../../examples/support/quaternion_top_system.rs"]
pub mod quaternion_top;

use lagrange::prelude::*;

/// A small deterministic generator (xorshift) so the tests need no extra dependency.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }

    /// Three uniform components in [lo, hi), x first.
    pub fn vec3(&mut self, lo: f64, hi: f64) -> Vector3<f64> {
        Vector3::new(
            self.uniform(lo, hi),
            self.uniform(lo, hi),
            self.uniform(lo, hi),
        )
    }

    /// Three uniform values in [lo, hi), the first drawn first.
    pub fn arr3(&mut self, lo: f64, hi: f64) -> [f64; 3] {
        [
            self.uniform(lo, hi),
            self.uniform(lo, hi),
            self.uniform(lo, hi),
        ]
    }
}
