use lagrange::prelude::*;

pub struct Grid {
    pub m: f64,
}

#[lagrangian]
impl Grid {
    // 10⁶ unrolled iterations: 94 s and 4.9 GB of macro expansion before the budget.
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let mut v = 0.0 * x;
        for i in 0..1000 {
            for j in 0..1000 {
                v += ((i + j) as f64) * x;
            }
        }
        0.5 * self.m * x_dot * x_dot - v
    }
}

fn main() {}
