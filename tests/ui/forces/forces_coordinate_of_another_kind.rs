use lagrange::prelude::*;

pub struct Pendulum {
    pub a: f64,
}

#[lagrangian]
impl Pendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * theta_dot.powi(2) + theta.cos()
    }
    fn forces(&self, (_, _): Coord3) -> [Scalar; 1] {
        [self.a]
    }
}

fn main() {}
