use lagrange::prelude::*;

pub struct Chain {
    pub m: f64,
}

#[lagrangian]
impl Chain {
    fn energy(&self, v: Scalar) -> Scalar {
        if self.m > 0.0 {
            v
        } else {
            self.energy(v * v)
        }
    }
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        self.energy(x_dot) - x.cos()
    }
}

fn main() {}
