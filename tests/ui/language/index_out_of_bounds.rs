use lagrange::prelude::*;

pub struct Chain {
    pub m: f64,
}

#[lagrangian]
impl Chain {
    fn lagrangian(&self, (q, q_dot): Coords<3>) -> Scalar {
        let mut t = 0.0;
        for i in 0..=3 {
            t += 0.5 * self.m * q_dot[i] * q_dot[i];
        }
        t - q[0].cos()
    }
}

fn main() {}
