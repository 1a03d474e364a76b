use lagrange::prelude::*;

pub struct Pendulum {
    pub g: f64,
}

#[lagrangian]
impl Pendulum {
    fn lagrangian(&self, theta: Coord) -> Scalar {
        self.g * theta.cos()
    }
}

fn main() {}
