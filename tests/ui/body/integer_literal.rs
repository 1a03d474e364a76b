use lagrange::prelude::*;

pub struct Spring {
    pub k: f64,
}

#[lagrangian(mode = "jets")]
impl Spring {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        x_dot * x_dot / 2 - 0.5 * self.k * x * x
    }
}

fn main() {}
