use lagrange::prelude::*;

const N: usize = 3;

pub struct Chain {
    pub m: f64,
}

#[lagrangian]
impl Chain {
    fn lagrangian(&self, (q, q_dot): Coords<N>) -> Scalar {
        0.5 * self.m * q_dot[0] * q_dot[0] - q[0].cos()
    }
}

fn main() {}
