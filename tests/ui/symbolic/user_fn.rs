use lagrange::prelude::*;

fn potential<S: Scalar>(x: S) -> S {
    x.powi(4)
}

pub struct Anharmonic {
    pub m: f64,
}

#[lagrangian]
impl Anharmonic {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * self.m * x_dot.powi(2) - potential(x)
    }
}

fn main() {}
