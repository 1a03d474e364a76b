use lagrange::prelude::*;

pub struct Chain {
    pub m: f64,
    pub n: usize,
}

#[lagrangian]
impl Chain {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let mut l = 0.5 * self.m * x_dot.powi(2);
        for k in 1..self.n {
            l -= x.powi(k as i32);
        }
        l
    }
}

fn main() {}
