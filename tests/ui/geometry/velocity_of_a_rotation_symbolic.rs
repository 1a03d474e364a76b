// `velocity` of a `Rotation` in symbolic mode: the error names the angular velocities.
use lagrange::prelude::*;

pub struct Spinner {
    pub i: f64,
}

#[lagrangian]
impl Spinner {
    fn lagrangian(&self, (a, a_dot): Coord) -> Scalar {
        let w = velocity(Rotation::about_z(a));
        0.5 * self.i * a_dot * a_dot
    }
}

fn main() {}
