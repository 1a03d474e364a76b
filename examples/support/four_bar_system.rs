//! The four-bar linkage as the example (`four_bar`) and the constraint tests declare it: three
//! uniform bars (crank, coupler, rocker) in a vertical plane, their absolute angles from the +x
//! axis as coordinates, and the loop closure as two holonomic constraints, written by hand.
//!
//! The crank turns about A = (0, 0), the rocker about D = (l0, 0); the crank's tip is
//! B = l1 (cos θ1, sin θ1), the coupler runs from B to C = B + l2 (cos θ2, sin θ2), and the loop
//! closes where the rocker's tip D + l3 (cos θ3, sin θ3) is C:
//!
//! ```text
//! g0 = l1 cos θ1 + l2 cos θ2 − l3 cos θ3 − l0 = 0,
//! g1 = l1 sin θ1 + l2 sin θ2 − l3 sin θ3      = 0.
//! ```
//!
//! A flywheel of inertia `flywheel` on the crank keeps it turning through the motion's
//! slow parts (no motor: the linkage runs on its own momentum).

use lagrange::prelude::*;

/// A four-bar linkage of uniform bars; gravity along −y.
pub struct FourBar {
    /// Ground link: the distance between the fixed pivots A and D.
    pub l0: f64,
    /// Crank (A to B).
    pub l1: f64,
    /// Coupler (B to C).
    pub l2: f64,
    /// Rocker (D to C).
    pub l3: f64,
    /// Crank mass.
    pub m1: f64,
    /// Coupler mass.
    pub m2: f64,
    /// Rocker mass.
    pub m3: f64,
    /// The flywheel's moment of inertia, added to the crank's about A.
    pub flywheel: f64,
    /// Gravity (along −y).
    pub g: f64,
}

impl FourBar {
    /// The Grashof crank–rocker of the example and the tests: l0 = 4, l1 = 1, l2 = 3.5, l3 = 3
    /// (shortest + longest = 5 ≤ 6.5 = the other two, the shortest link is the crank), unit
    /// masses, a flywheel of 10 kg m², g = 9.81.
    pub fn crank_rocker() -> Self {
        FourBar {
            l0: 4.0,
            l1: 1.0,
            l2: 3.5,
            l3: 3.0,
            m1: 1.0,
            m2: 1.0,
            m3: 1.0,
            flywheel: 10.0,
            g: 9.81,
        }
    }

    /// The closed configuration (θ1, θ2, θ3) at crank angle θ1 with C above the line B–D (the
    /// assembly the crank–rocker keeps), and the velocities with crank rate `omega1` in the null
    /// space of G (so ġ = 0): the cross product of G's two rows, scaled to θ̇1 = `omega1`.
    pub fn closed_state(&self, theta1: f64, omega1: f64) -> ([f64; 3], [f64; 3]) {
        let (bx, by) = (self.l1 * theta1.cos(), self.l1 * theta1.sin());
        let (ux, uy) = (self.l0 - bx, -by); // B → D
        let d = ux.hypot(uy);
        let (ux, uy) = (ux / d, uy / d);
        // C at distance l2 from B and l3 from D: a along B → D, h across it (to the left).
        let a = (self.l2 * self.l2 - self.l3 * self.l3 + d * d) / (2.0 * d);
        let h = (self.l2 * self.l2 - a * a).sqrt();
        let (cx, cy) = (bx + a * ux - h * uy, by + a * uy + h * ux);
        let theta2 = (cy - by).atan2(cx - bx);
        let theta3 = cy.atan2(cx - self.l0);
        let q = [theta1, theta2, theta3];
        let [r0, r1] = self.jacobian(&q);
        let n = [
            r0[1] * r1[2] - r0[2] * r1[1],
            r0[2] * r1[0] - r0[0] * r1[2],
            r0[0] * r1[1] - r0[1] * r1[0],
        ];
        let s = omega1 / n[0];
        (q, [omega1, n[1] * s, n[2] * s])
    }

    /// G = ∂g/∂θ, written out (the tests check the jets' G against it).
    pub fn jacobian(&self, q: &[f64; 3]) -> [[f64; 3]; 2] {
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let (s3, c3) = q[2].sin_cos();
        [
            [-self.l1 * s1, -self.l2 * s2, self.l3 * s3],
            [self.l1 * c1, self.l2 * c2, -self.l3 * c3],
        ]
    }

    /// A point of the coupler: `along` of the way from B to C and `across` to its left (in
    /// units of l2), the point whose path is the coupler curve.
    pub fn coupler_point(&self, q: &[f64; 3], along: f64, across: f64) -> (f64, f64) {
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let (a, h) = (along * self.l2, across * self.l2);
        (
            self.l1 * c1 + a * c2 - h * s2,
            self.l1 * s1 + a * s2 + h * c2,
        )
    }
}

impl Lagrangian<3> for FourBar {
    const COORDINATES: [&'static str; 3] = ["theta1", "theta2", "theta3"];
    const CYCLIC: [bool; 3] = [false; 3];
    const AUTONOMOUS: bool = true;

    /// T = ½(m1 l1²/3 + J) θ̇1² + ½ m2 |v_G2|² + ½ (m2 l2²/12) θ̇2² + ½ (m3 l3²/3) θ̇3², with the
    /// coupler's centre G2 = B + (l2/2)(cos θ2, sin θ2); V = g Σ m_i y_i of the bars' centres.
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        let (l1, l2, l3) = (self.l1, self.l2, self.l3);
        let (m1, m2, m3) = (self.m1, self.m2, self.m3);
        let (w1, w2, w3) = (v[0], v[1], v[2]);
        let i1 = m1 * l1 * l1 / 3.0 + self.flywheel;
        let v_g2_sq = w1 * w1 * (l1 * l1)
            + w2 * w2 * (l2 * l2 / 4.0)
            + w1 * w2 * (q[0] - q[1]).cos() * (l1 * l2);
        let kinetic = w1 * w1 * (i1 / 2.0)
            + v_g2_sq * (m2 / 2.0)
            + w2 * w2 * (m2 * l2 * l2 / 24.0)
            + w3 * w3 * (m3 * l3 * l3 / 6.0);
        let height = q[0].sin() * (m1 * l1 / 2.0 + m2 * l1)
            + q[1].sin() * (m2 * l2 / 2.0)
            + q[2].sin() * (m3 * l3 / 2.0);
        kinetic - height * self.g
    }

    /// Runs take the two loop-closure constraints (`Simulation::new` runs the linkage on them).
    fn declared<'s, V: lagrange::Declared<'s, Self, 3>>(&'s self, v: V) -> V::Output {
        v.constrained::<2>(self)
    }
}

impl Holonomic<3, 2> for FourBar {
    const SCLERONOMIC: bool = true;

    fn constraints<S: Scalar>(&self, q: &[S; 3], _t: S) -> [S; 2] {
        [
            q[0].cos() * self.l1 + q[1].cos() * self.l2 - q[2].cos() * self.l3 - self.l0,
            q[0].sin() * self.l1 + q[1].sin() * self.l2 - q[2].sin() * self.l3,
        ]
    }
}

/// What the linkage looks like (x to the right, y up), written by hand as `#[lagrangian]`'s
/// `fn scene` would be: the ground pivots, the three bars, the coupler point's curve.
impl Visual<3> for FourBar {
    fn scene(&self, q: &[f64; 3], _t: f64) -> Scene {
        let at = |x: f64, y: f64| Vector3::new(x, y, 0.0);
        let (a, d) = (at(0.0, 0.0), at(self.l0, 0.0));
        let b = at(self.l1 * q[0].cos(), self.l1 * q[0].sin());
        let c = b + at(self.l2 * q[1].cos(), self.l2 * q[1].sin());
        // The coupler point of the example's figure: halfway from B to C, 0.4 l2 to its left.
        let (px, py) = self.coupler_point(q, 0.5, 0.4);
        let r = 0.04 * self.l0;
        Scene::new()
            .up(Vector3::y())
            .sphere("pivot A", a, r, Rgb::BLACK)
            .sphere("pivot D", d, r, Rgb::BLACK)
            .rod("crank", a, b, 0.5 * r, Rgb::ORANGE)
            .rod("coupler", b, c, 0.5 * r, Rgb::STEEL)
            .rod("rocker", d, c, 0.5 * r, Rgb::GREEN)
            .sphere("coupler point", at(px, py), 0.7 * r, Rgb::RED)
            .trace("coupler curve", at(px, py), Rgb::RED)
    }
}
