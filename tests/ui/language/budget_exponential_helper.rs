use lagrange::prelude::*;

pub struct Tree {
    pub m: f64,
}

#[lagrangian]
impl Tree {
    // 2⁴⁰ inlined calls: the macro would run for hours.
    fn grow(&self, x: Scalar, n: usize) -> Scalar {
        if n == 0 {
            x
        } else {
            self.grow(x, n - 1) + self.grow(x, n - 1)
        }
    }
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * self.m * x_dot * x_dot - self.grow(x, 40)
    }
}

fn main() {}
