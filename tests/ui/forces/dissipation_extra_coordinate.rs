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
    fn dissipation(&self, (_, theta_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.b * (theta_dot.powi(2) + y_dot.powi(2))
    }
}

fn main() {}
