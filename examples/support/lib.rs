//! What the examples share: their command-line handling ([`cli`]) and the systems several of
//! them run (the heavy top of eq. 92, the quaternion top, the double pendulum, the driven
//! pendulum, the four-bar linkage), each declared once with `#[lagrangian]`. The integration tests
//! include the same system files.

pub mod cli;
pub mod double_pendulum_system;
pub mod driven_pendulum_system;
pub mod four_bar_system;
pub mod heavy_top_system;
pub mod quaternion_top_system;
