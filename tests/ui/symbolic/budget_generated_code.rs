use lagrange::prelude::*;

pub struct Twisted {
    pub i: f64,
}

#[lagrangian]
impl Twisted {
    // 60 pairs of elementary rotations differentiated by `body_angular_velocity`: 130 000
    // generated operations, 41 s and 4 GB of rustc in the symbolic mode.
    fn lagrangian(
        &self,
        (a, a_dot): Coord,
        (b, b_dot): Coord,
        (c, c_dot): Coord,
    ) -> Scalar {
        let mut r = Rotation::about_z(a);
        for _k in 0..60 {
            r = r * Rotation::about_x(b) * Rotation::about_z(c);
        }
        let w = body_angular_velocity(&r);
        0.5 * self.i * (w.x * w.x + w.y * w.y + 2.0 * w.z * w.z) - (r * Vector3::z()).z
    }
}

fn main() {}
