use lagrange::prelude::*;

pub struct Beads {
    pub m: f64,
}

#[lagrangian]
impl Beads {
    fn lagrangian(&self, (q, q_dot): Coords<2>) -> Scalar {
        let mut t = 0.0 * q[0];
        let mut add = |v: Scalar| t += 0.5 * self.m * v * v;
        add(q_dot[0]);
        add(q_dot[1]);
        t - q[0].cos()
    }
}

fn main() {}
