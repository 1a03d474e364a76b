use lagrange::prelude::*;

pub struct Ball {
    pub m: f64,
    pub g: f64,
    pub e: f64,
}

#[lagrangian]
impl Ball {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn contacts(&self, (_, _): Coord, (y, y_dot): Coord) -> [Contact; 1] {
        [Contact::gap(y + y_dot).restitution(self.e)]
    }
}

fn main() {}
