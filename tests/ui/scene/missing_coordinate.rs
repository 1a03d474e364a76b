use lagrange::prelude::*;

pub struct Planar {
    pub m: f64,
}

#[lagrangian]
impl Planar {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - 9.81 * self.m * y
    }
    fn scene(&self, (x, _): Coord) -> Scene {
        Scene::new().sphere("ball", Vector3::new(x, 0.0, 0.0), 0.1, Rgb::RED)
    }
}

fn main() {}
