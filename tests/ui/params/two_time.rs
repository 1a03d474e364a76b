use lagrange::prelude::*;

pub struct Driven {
    pub w: f64,
}

#[lagrangian]
impl Driven {
    fn lagrangian(&self, (x, x_dot): Coord, t: Time, s: Time) -> Scalar {
        x_dot.powi(2) / 2.0 - x * (self.w * t).cos() * s
    }
}

fn main() {}
