//! The stiff systems of the `stiff` example, the stiff-mechanics tests (tests/stiff.rs) and the
//! stiff benchmark (benches/stiff.rs), each with its closed form or its start on the slow
//! manifold: two masses joined by a stiff spring, the stiff spring pendulum (and the rigid
//! pendulum it approaches, as a constrained system), and a heavily damped driven oscillator.

use lagrange::prelude::*;

/// Two unit masses on a line: a soft spring k₁ from the wall to the first, a stiff spring k₂
/// between the two. Linear, M = I and K = [[k₁ + k₂, −k₂], [−k₂, k₂]].
#[derive(Debug, Clone, Copy)]
pub struct TwoMasses {
    /// The soft spring (wall to mass 1).
    pub k1: f64,
    /// The stiff spring (mass 1 to mass 2).
    pub k2: f64,
}

#[lagrangian]
impl TwoMasses {
    fn lagrangian(&self, (x1, x1_dot): Coord, (x2, x2_dot): Coord) -> Scalar {
        0.5 * (x1_dot.powi(2) + x2_dot.powi(2))
            - 0.5 * self.k1 * x1.powi(2)
            - 0.5 * self.k2 * (x2 - x1).powi(2)
    }
}

impl TwoMasses {
    /// The problem of the tests, the example and the benchmark: k₁ = 1, k₂ = 10⁸ (ω ≈ 0.71
    /// and 1.4·10⁴).
    pub const STIFF: TwoMasses = TwoMasses { k1: 1.0, k2: 1e8 };

    /// The normal modes: (ω², shape) for the slow mode, then the fast one, shapes of unit length.
    pub fn modes(&self) -> [(f64, [f64; 2]); 2] {
        let (k1, k2) = (self.k1, self.k2);
        // λ² − (k₁ + 2k₂) λ + k₁k₂ = 0: the larger root by the formula, the smaller from the
        // product (no cancellation).
        let b = k1 + 2.0 * k2;
        let fast = 0.5 * (b + (b * b - 4.0 * k1 * k2).sqrt());
        let slow = k1 * k2 / fast;
        let shape = |w2: f64| {
            // (K − ω² I) v = 0, from the row with the larger entries: k₂ v₂ = (k₁ + k₂ − ω²) v₁
            // for the slow mode; −k₂ v₁ + (k₂ − ω²) v₂ = 0 for the fast one.
            let v = if w2 < k2 {
                [1.0, (k1 + k2 - w2) / k2]
            } else {
                [(k2 - w2) / k2, 1.0]
            };
            let n = (v[0] * v[0] + v[1] * v[1]).sqrt();
            [v[0] / n, v[1] / n]
        };
        [(slow, shape(slow)), (fast, shape(fast))]
    }

    /// The start on the slow manifold: the slow mode's shape with x₁ = 1, at rest (the fast mode
    /// not excited).
    pub fn slow_start(&self) -> ([f64; 2], [f64; 2]) {
        let v = self.modes()[0].1;
        ([1.0, v[1] / v[0]], [0.0, 0.0])
    }

    /// The exact (q, q̇) at t from (q0, q̇0) at 0, by modal decomposition.
    pub fn exact(&self, q0: [f64; 2], v0: [f64; 2], t: f64) -> ([f64; 2], [f64; 2]) {
        let (mut q, mut v) = ([0.0; 2], [0.0; 2]);
        for (w2, s) in self.modes() {
            let w = w2.sqrt();
            let a = s[0] * q0[0] + s[1] * q0[1];
            let b = (s[0] * v0[0] + s[1] * v0[1]) / w;
            let (sin, cos) = (w * t).sin_cos();
            for i in 0..2 {
                q[i] += s[i] * (a * cos + b * sin);
                v[i] += s[i] * w * (b * cos - a * sin);
            }
        }
        (q, v)
    }
}

/// The elastic (spring) pendulum in polar coordinates: a bob of mass m on a spring of stiffness k
/// and rest length l, swinging in a vertical plane; θ from the downward vertical.
#[derive(Debug, Clone, Copy)]
pub struct SpringPendulum {
    /// The bob's mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
    /// The spring's rest length.
    pub l: f64,
    /// The spring's stiffness.
    pub k: f64,
}

#[lagrangian]
impl SpringPendulum {
    fn lagrangian(&self, (r, r_dot): Coord, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.m * (r_dot.powi(2) + r.powi(2) * theta_dot.powi(2))
            + self.m * self.g * r * theta.cos()
            - 0.5 * self.k * (r - self.l).powi(2)
    }
}

impl SpringPendulum {
    /// The stiff spring pendulum of the tests: g = l = m = 1 and k = 1/ε², ε = 10⁻⁴.
    pub const STIFF: SpringPendulum = SpringPendulum {
        m: 1.0,
        g: 1.0,
        l: 1.0,
        k: 1e8,
    };

    /// The start on the slow manifold at angle θ₀ and rate θ̇₀: the spring stretched by the
    /// static load, k (r − l) = m g cos θ₀ + m r θ̇₀² (gravity along the spring and the
    /// centripetal force), ṙ = 0. Returns (q, q̇) in the order (r, θ).
    pub fn slow_start(&self, theta0: f64, theta_dot0: f64) -> ([f64; 2], [f64; 2]) {
        let w2 = theta_dot0 * theta_dot0;
        // k (r − l) = m g cos θ₀ + m r ω²  ⇒  r = (k l + m g cos θ₀) / (k − m ω²).
        let r = (self.k * self.l + self.m * self.g * theta0.cos()) / (self.k - self.m * w2);
        ([r, theta0], [0.0, theta_dot0])
    }
}

/// The rigid pendulum the stiff spring pendulum approaches, in Cartesian coordinates with the rod
/// as a holonomic constraint x² + y² = l² (y up).
#[derive(Debug, Clone, Copy)]
pub struct RigidPendulumXy {
    /// The bob's mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
    /// The rod's length.
    pub l: f64,
}

#[lagrangian]
impl RigidPendulumXy {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot.powi(2) + y_dot.powi(2)) - self.m * self.g * y
    }
    /// Holonomic constraints g(q, t) = 0, one entry per constraint.
    fn constraints(&self, (x, _): Coord, (y, _): Coord) -> [Scalar; 1] {
        [x.powi(2) + y.powi(2) - self.l * self.l]
    }
}

impl RigidPendulumXy {
    /// (q, q̇) at angle θ from the downward vertical and rate θ̇.
    pub fn state(&self, theta: f64, theta_dot: f64) -> ([f64; 2], [f64; 2]) {
        let (s, c) = theta.sin_cos();
        let l = self.l;
        ([l * s, -l * c], [l * c * theta_dot, l * s * theta_dot])
    }

    /// The angle from the downward vertical at position q.
    pub fn theta(q: &[f64; 2]) -> f64 {
        q[0].atan2(-q[1])
    }
}

/// A heavily damped driven oscillator: m ẍ + c ẋ + k x = a cos(w t), written with a Rayleigh
/// dissipation ½ c ẋ² and a generalized force that depends on time.
#[derive(Debug, Clone, Copy)]
pub struct DampedDriven {
    /// Mass.
    pub m: f64,
    /// Spring stiffness.
    pub k: f64,
    /// Damping coefficient.
    pub c: f64,
    /// Drive amplitude (a force).
    pub a: f64,
    /// Drive angular frequency.
    pub w: f64,
}

#[lagrangian]
impl DampedDriven {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * self.m * x_dot.powi(2) - 0.5 * self.k * x.powi(2)
    }
    /// Rayleigh dissipation function D(q, q̇, t) ≥ 0; its −∂D/∂q̇ joins the generalized forces.
    fn dissipation(&self, (_x, x_dot): Coord) -> Scalar {
        0.5 * self.c * x_dot.powi(2)
    }
    /// Generalized forces Q(q, q̇, t), one per coordinate in declaration order.
    fn forces(&self, (_x, _x_dot): Coord, t: Time) -> [Scalar; 1] {
        [self.a * (self.w * t).cos()]
    }
}

impl DampedDriven {
    /// The problem of the tests: k = 10⁶, c = 10⁴ (overdamped: rates ≈ 101 and 9899 per unit
    /// time), m = 1, driven by a = k at w = 1 (a steady motion of amplitude ≈ 1).
    pub const STIFF: DampedDriven = DampedDriven {
        m: 1.0,
        k: 1e6,
        c: 1e4,
        a: 1e6,
        w: 1.0,
    };

    /// The exact (x, ẋ) at t from (x0, ẋ0) at 0: the steady state A cos wt + B sin wt plus the
    /// two decaying exponentials of the transient.
    pub fn exact(&self, x0: f64, v0: f64, t: f64) -> (f64, f64) {
        let (m, k, c, a, w) = (self.m, self.k, self.c, self.a, self.w);
        let re = k - m * w * w;
        let d = re * re + (c * w) * (c * w);
        let (pa, pb) = (a * re / d, a * c * w / d);
        // m λ² + c λ + k = 0 (overdamped): the root of larger magnitude by the formula, the other
        // from the product.
        let disc = (c * c - 4.0 * m * k).sqrt();
        let l2 = (-c - disc) / (2.0 * m);
        let l1 = k / (m * l2);
        // x − x_p = C₁ e^{λ₁t} + C₂ e^{λ₂t}.
        let (dx, dv) = (x0 - pa, v0 - pb * w);
        let c2 = (dv - l1 * dx) / (l2 - l1);
        let c1 = dx - c2;
        let (s, co) = (w * t).sin_cos();
        let (e1, e2) = ((l1 * t).exp(), (l2 * t).exp());
        (
            pa * co + pb * s + c1 * e1 + c2 * e2,
            w * (pb * co - pa * s) + c1 * l1 * e1 + c2 * l2 * e2,
        )
    }
}
