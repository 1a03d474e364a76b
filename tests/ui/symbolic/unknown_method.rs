use lagrange::prelude::*;

pub struct Clamp {
    pub m: f64,
}

#[lagrangian]
impl Clamp {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * self.m * x_dot.powi(2) - x.fract()
    }
}

fn main() {}
