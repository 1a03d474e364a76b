use lagrange::prelude::*;

pub struct Pendulum {
    pub m: f64,
    pub g: f64,
    pub l: f64,
}

#[lagrangian]
impl Pendulum {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn constraints(&self, (x, _): Coord, (y, _): Coord) -> [Scalar; Self::K] {
        [x * x + y * y - self.l * self.l]
    }
}

fn main() {}
