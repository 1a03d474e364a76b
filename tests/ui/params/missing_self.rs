use lagrange::prelude::*;

pub struct Free;

#[lagrangian]
impl Free {
    fn lagrangian((x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - 0.0 * x
    }
}

fn main() {}
