// `velocity` of a `Rotation`: the angular velocities are what a rotation has (jets mode: the
// trait bound says so).
use lagrange::prelude::*;

pub struct Spinner {
    pub i: f64,
}

#[lagrangian(mode = "jets")]
impl Spinner {
    fn lagrangian(&self, (a, a_dot): Coord) -> Scalar {
        let w = velocity(Rotation::about_z(a));
        0.5 * self.i * a_dot * a_dot
    }
}

fn main() {}
