use lagrange::prelude::*;

pub struct Pendulum {
    pub g: f64,
    pub b: f64,
}

#[lagrangian]
impl Pendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        theta_dot.powi(2) / 2.0 + self.g * theta.cos()
    }
    fn forces(&self, (theta, _): Coord) -> [Scalar; 2] {
        [-self.b * theta, 0.0]
    }
}

fn main() {}
