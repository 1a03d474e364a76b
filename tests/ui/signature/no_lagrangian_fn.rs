use lagrange::prelude::*;

pub struct Pendulum {
    pub g: f64,
}

#[lagrangian]
impl Pendulum {
    pub fn length(&self) -> f64 {
        self.g / 9.81
    }
}

fn main() {}
