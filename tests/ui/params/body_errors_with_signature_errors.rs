use lagrange::prelude::*;

pub struct Spring {
    pub k: f64,
}

// A mistyped coordinate type and a mistake in the body: both reported in one build (and no
// "needs at least one coordinate" for the coordinate that is there, only mistyped).
#[lagrangian]
impl Spring {
    fn lagrangian(&self, (x, x_dot): Cord) -> Scalar {
        0.5 * x_dot * x_dot - 0.5 * self.k * (x ^ 2)
    }
}

fn main() {}
