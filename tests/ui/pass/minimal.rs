//! The smallest declaration: one coordinate, a harmonic oscillator.
use lagrange::prelude::*;

pub struct Oscillator {
    pub k: f64,
}

#[lagrangian]
impl Oscillator {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - 0.5 * self.k * x * x
    }
}

fn main() {}
