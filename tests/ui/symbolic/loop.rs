use lagrange::prelude::*;

pub struct Chain {
    pub m: f64,
}

#[lagrangian]
impl Chain {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let mut l = 0.5 * self.m * x_dot.powi(2);
        for k in 1..3 {
            l = l - x.powi(k);
        }
        l
    }
}

fn main() {}
