use lagrange::prelude::*;

pub struct Bumper {
    pub m: f64,
    pub k: f64,
}

// An `if` on the state (the coordinate `x`, and a local computed from it) cannot be derived
// once for every state: the symbolic mode points at the names and says to use the jets.
#[lagrangian]
impl Bumper {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let wall = if x > 0.0 { self.k * x * x } else { 0.0 * x };
        let e = 0.5 * self.m * x_dot * x_dot;
        let extra = if e > self.k { e } else { 0.0 * e };
        e - wall + extra
    }
}

fn main() {}
