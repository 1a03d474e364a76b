// `velocity` of something that depends on the velocities: it takes positions.
use lagrange::prelude::*;

pub struct P {
    pub m: f64,
}

#[lagrangian]
impl P {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let a = velocity(x_dot * x);
        0.5 * self.m * a * a
    }
}

fn main() {}
