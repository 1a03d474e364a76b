use lagrange::prelude::*;

pub struct Skate {
    pub m: f64,
}

#[lagrangian]
impl Skate {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord, (phi, phi_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot + phi_dot * phi_dot)
    }
    fn velocity_constraints(&self, (_, x_dot): Coord, (y, _): Coord, (phi, _): Coord) -> [Scalar; 2] {
        [x_dot * phi.sin(), y - phi]
    }
}

fn main() {}
