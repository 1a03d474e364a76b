use lagrange::prelude::*;

pub struct Spring {
    pub k: f64,
}

#[lagrangian]
impl Spring {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - 0.5 * self.k * (x ^ 2)
    }
}

fn main() {}
