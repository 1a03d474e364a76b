use lagrange::prelude::*;

pub struct Particle {
    pub c: f64,
}

#[lagrangian]
impl Particle {
    fn lagrangian(&self, (_r, r_dot): Coord3) -> Scalar {
        0.5 * r_dot.norm_squared()
    }
    fn dissipation(&self, (_, r_dot): Coord3) -> Vector3<Scalar> {
        r_dot * self.c
    }
}

fn main() {}
