use lagrange::prelude::*;

pub struct Driven {
    pub w: f64,
}

#[lagrangian]
impl Driven {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - x * (self.w * t).cos()
    }
}

fn main() {}
