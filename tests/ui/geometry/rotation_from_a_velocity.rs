// An angular velocity of a rotation built from a velocity.
use lagrange::prelude::*;

pub struct P {
    pub i: f64,
}

#[lagrangian]
impl P {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let r = Rotation::about_z(x + x_dot);
        let w = angular_velocity(&r);
        0.5 * self.i * w.z * w.z
    }
}

fn main() {}
