//! The systems with unilateral contacts of the `impacts` example and the contact tests: a
//! bouncing ball, a rocking block and a rimless wheel, each written as L and its contacts
//! (`fn contacts`), nothing more.

use lagrange::prelude::*;

/// A ball in a vertical plane above the floor y = 0 (x horizontal, y up), restitution e.
pub struct Ball {
    /// Mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
    /// Restitution coefficient.
    pub e: f64,
}

#[lagrangian]
impl Ball {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn contacts(&self, (_, _): Coord, (y, _): Coord) -> [Contact; 1] {
        [Contact::gap(y).restitution(self.e).named("floor")]
    }
}

/// A uniform rectangular block of half-width b and half-height h rocking on its bottom corners,
/// which stick where they land (plastic impacts): coordinates the centre (x, y) and the tilt θ.
pub struct Block {
    /// Mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
    /// Half-width.
    pub b: f64,
    /// Half-height.
    pub h: f64,
}

#[lagrangian]
impl Block {
    fn lagrangian(
        &self,
        (_x, x_dot): Coord,
        (y, y_dot): Coord,
        (_theta, theta_dot): Coord,
    ) -> Scalar {
        // A uniform rectangle: I = m (b² + h²)/3 about its centre.
        let inertia = self.m * (self.b * self.b + self.h * self.h) / 3.0;
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) + 0.5 * inertia * theta_dot * theta_dot
            - self.m * self.g * y
    }
    fn contacts(&self, (x, _): Coord, (y, _): Coord, (theta, _): Coord) -> [Contact; 2] {
        let (s, c) = (theta.sin(), theta.cos());
        // The bottom corners (±b, −h) of the body frame, in the world.
        let (xr, yr) = (x + self.b * c + self.h * s, y + self.b * s - self.h * c);
        let (xl, yl) = (x - self.b * c + self.h * s, y - self.b * s - self.h * c);
        [
            Contact::gap(yr).sticking(xr).named("right corner"),
            Contact::gap(yl).sticking(xl).named("left corner"),
        ]
    }
    /// What it looks like (x to the right, y up): the floor, the block, and the path of the
    /// middle of its top face.
    fn scene(&self, (x, _): Coord, (y, _): Coord, (theta, _): Coord) -> Scene {
        let body = Rotation::about_z(theta);
        let centre = Vector3::new(x, y, 0.0);
        Scene::new()
            .up(Vector3::y())
            .cuboid(
                "floor",
                Rotation::identity(),
                Vector3::new(0.0, -0.025 * self.h, 0.0),
                Vector3::new(8.0 * self.b, 0.05 * self.h, 4.0 * self.b),
                Rgb::GREY,
            )
            .cuboid(
                "block",
                body,
                centre,
                Vector3::new(2.0 * self.b, 2.0 * self.h, 2.0 * self.b),
                Rgb::STEEL,
            )
            .trace(
                "top",
                centre + body * Vector3::new(0.0, self.h, 0.0),
                Rgb::RED,
            )
    }
}

/// The number of spokes of [`RimlessWheel`]: 2α = 2π/8 apart.
pub const SPOKES: usize = 8;

/// A rimless wheel: a point mass m at the hub of [`SPOKES`] massless spokes of length l on a
/// slope γ; (x, y) in the slope's frame (x downhill, y normal to it), θ the wheel's angle (no
/// inertia of its own). The spokes' tips stick where they land (plastic impacts).
pub struct RimlessWheel {
    /// Mass at the hub.
    pub m: f64,
    /// Gravity.
    pub g: f64,
    /// Spoke length.
    pub l: f64,
    /// The slope γ.
    pub slope: f64,
}

#[lagrangian]
impl RimlessWheel {
    fn lagrangian(
        &self,
        (x, x_dot): Coord,
        (y, y_dot): Coord,
        (_theta, _theta_dot): Coord,
    ) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot)
            + self.m * self.g * (x * self.slope.sin() - y * self.slope.cos())
    }
    fn contacts(&self, (x, _): Coord, (y, _): Coord, (theta, _): Coord) -> [Contact; 8] {
        let spoke = |k: f64| {
            let phi = theta + k * std::f64::consts::PI / 4.0;
            let (tx, ty) = (x + self.l * phi.sin(), y - self.l * phi.cos());
            Contact::gap(ty).sticking(tx)
        };
        [
            spoke(0.0),
            spoke(1.0),
            spoke(2.0),
            spoke(3.0),
            spoke(4.0),
            spoke(5.0),
            spoke(6.0),
            spoke(7.0),
        ]
    }
    /// What it looks like, gravity down (the slope's frame turned by γ): the hub, the spokes,
    /// a stretch of the slope under the hub (it follows the hub: the run's length is not known
    /// here), and the hub's path.
    fn scene(&self, (x, _): Coord, (y, _): Coord, (theta, _): Coord) -> Scene {
        let hub = Vector3::new(x, y, 0.0);
        let up = Vector3::new(-self.slope.sin(), self.slope.cos(), 0.0);
        let mut scene = Scene::new()
            .up(up)
            .cuboid(
                "slope",
                Rotation::identity(),
                Vector3::new(x, -0.025 * self.l, 0.0),
                Vector3::new(6.0 * self.l, 0.05 * self.l, 1.5 * self.l),
                Rgb::GREY,
            )
            .sphere("hub", hub, 0.1 * self.l, Rgb::ORANGE);
        for k in 0..SPOKES {
            let phi = theta + k as f64 * std::f64::consts::PI / 4.0;
            let tip = hub + Vector3::new(self.l * phi.sin(), -self.l * phi.cos(), 0.0);
            scene = scene.rod(&format!("spoke {k}"), hub, tip, 0.025 * self.l, Rgb::STEEL);
        }
        scene.trace("hub's path", hub, Rgb::RED)
    }
}

/// ω* = cot 2α √(4 (g/l) sin α sin γ): the rimless wheel's post-impact rate on its limit cycle
/// (the stance phase gains ω⁻² − ω⁺² = 4 (g/l) sin α sin γ, each impact keeps cos 2α of ω).
///
/// ```
/// use lagrange_examples::contact_systems::{omega_star, RimlessWheel};
/// let w = RimlessWheel { m: 1.0, g: 1.0, l: 1.0, slope: 0.08 };
/// assert!((omega_star(&w) - 0.34977).abs() < 1e-4);
/// ```
pub fn omega_star(w: &RimlessWheel) -> f64 {
    let alpha = std::f64::consts::PI / SPOKES as f64;
    (4.0 * (w.g / w.l) * alpha.sin() * w.slope.sin()).sqrt() / (2.0 * alpha).tan()
}
