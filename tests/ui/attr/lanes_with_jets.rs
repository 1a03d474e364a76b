use lagrange::prelude::*;

pub struct Pendulum {
    pub g: f64,
}

#[lagrangian(mode = "jets", lanes)]
impl Pendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        theta_dot.powi(2) / 2.0 + self.g * theta.cos()
    }
}

fn main() {}
