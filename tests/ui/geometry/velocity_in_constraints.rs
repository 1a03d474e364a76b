// A velocity in `fn constraints` is a velocity (nonholonomic) constraint.
use lagrange::prelude::*;

pub struct Skate {
    pub m: f64,
}

#[lagrangian]
impl Skate {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot)
    }

    fn constraints(&self, (x, _): Coord, (y, _): Coord) -> [Scalar; 1] {
        [velocity(x * y)]
    }
}

fn main() {}
