//! The double pendulum as the examples (`double_pendulum`, `modes`) and the linearization tests
//! declare it: two point masses on massless rods, angles from the downward vertical.

use lagrange::prelude::*;

/// Two point masses on massless rods; angles from the downward vertical.
pub struct DoublePendulum {
    /// Upper mass.
    pub m1: f64,
    /// Lower mass.
    pub m2: f64,
    /// Upper rod.
    pub l1: f64,
    /// Lower rod.
    pub l2: f64,
    /// Gravity.
    pub g: f64,
}

#[lagrangian]
impl DoublePendulum {
    fn lagrangian(&self, (th1, th1_dot): Coord, (th2, th2_dot): Coord) -> Scalar {
        let (m1, m2, l1, l2, g) = (self.m1, self.m2, self.l1, self.l2, self.g);
        (m1 + m2) / 2.0 * (l1 * th1_dot).powi(2)
            + m2 / 2.0 * (l2 * th2_dot).powi(2)
            + m2 * l1 * l2 * th1_dot * th2_dot * (th1 - th2).cos()
            + (m1 + m2) * g * l1 * th1.cos()
            + m2 * g * l2 * th2.cos()
    }

    /// What it looks like (x to the right, y up): the rods, the bobs, and the lower bob's path.
    fn scene(&self, (th1, _): Coord, (th2, _): Coord) -> Scene {
        let p1 = Vector3::new(self.l1 * th1.sin(), -self.l1 * th1.cos(), 0.0);
        let p2 = p1 + Vector3::new(self.l2 * th2.sin(), -self.l2 * th2.cos(), 0.0);
        let r = 0.06 * (self.l1 + self.l2);
        Scene::new()
            .up(Vector3::y())
            .sphere("pivot", Vector3::zeros(), 0.4 * r, Rgb::BLACK)
            .rod("upper rod", Vector3::zeros(), p1, 0.15 * r, Rgb::GREY)
            .rod("lower rod", p1, p2, 0.15 * r, Rgb::GREY)
            .sphere("upper bob", p1, r, Rgb::STEEL)
            .sphere("lower bob", p2, r, Rgb::ORANGE)
            .trace("lower bob's path", p2, Rgb::RED)
    }
}
