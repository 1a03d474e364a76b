use lagrange::prelude::*;

pub struct Clock {
    pub w: f64,
}

#[lagrangian]
impl Clock {
    fn lagrangian(&self, t: Time) -> Scalar {
        (self.w * t).sin()
    }
}

fn main() {}
