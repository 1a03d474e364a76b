use lagrange::prelude::*;

pub struct Beads {
    pub m: [f64; 3],
}

#[lagrangian]
impl Beads {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let mut t = 0.0;
        for m in self.m.iter() {
            t += 0.5 * m * x_dot * x_dot;
        }
        t - x.cos()
    }
}

fn main() {}
