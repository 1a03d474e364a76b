use lagrange::prelude::*;

pub struct Pendulum {
    pub l: f64,
}

#[lagrangian]
impl Pendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.l * self.l * theta_dot * theta_dot + 9.81 * self.l * theta.cos()
    }
    fn scene(&self, (theta, _): Coord) -> Scene {
        let bob = Vector3::new(self.l * theta.sin(), -self.l * theta.cos(), 0.0);
        Scene::new().rod("speed", bob, bob + velocity(bob), 0.01, Rgb::RED)
    }
}

fn main() {}
