use lagrange::prelude::*;

pub struct Pendulum {
    pub g: f64,
}

// Every mistake is reported, each at its own token.
#[lagrangian(mode = "fast")]
impl Pendulum {
    fn lagrangian(self, theta: Coord, (x, x_dot): Vector3<f64>) -> f64 {
        self.g * theta.cos()
    }
}

fn main() {}
