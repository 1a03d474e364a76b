//! The models of lagrange's examples, tests and benchmarks, each declared once: the examples'
//! command-line handling ([`cli`]) and the systems several of them run (the heavy top of eq. 92,
//! the quaternion top, the double pendulum, the driven pendulum, the four-bar linkage, the stiff
//! systems of the `stiff` example, the IVP test set's mechanical problems of the `testset`
//! example, the contact systems of the `impacts` example, three bodies in a plane with the
//! figure-eight's data, the compass-gait walker). With the
//! feature `test-models` (turned on by the root package's dev-dependency, so the tests and
//! benchmarks have it and `cargo run --example` does not build it) also the twin systems the
//! tests compare mode against mode ([`systems`]: the heavy top, Kepler, the pendulum chains) and
//! the heavy top the benchmarks time ([`bench_top`]). Nothing includes these files by path.

#[cfg(feature = "test-models")]
pub mod animations;
#[cfg(feature = "test-models")]
pub mod bench_top;
pub mod bicycle_system;
pub mod cli;
pub mod contact_systems;
pub mod double_pendulum_system;
pub mod driven_pendulum_system;
pub mod four_bar_system;
pub mod heavy_top_system;
pub mod pendulum_system;
pub mod quaternion_top_system;
pub mod stiff_system;
pub mod testset_system;
pub mod three_body_system;
pub mod walker_system;
#[cfg(feature = "test-models")]
#[macro_use]
pub mod systems;
