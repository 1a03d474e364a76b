use lagrange::prelude::*;

pub struct Pendulum<T> {
    pub g: T,
}

#[lagrangian]
impl<T> Pendulum<T> {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        theta_dot.powi(2) / 2.0 + theta.cos()
    }
}

fn main() {}
