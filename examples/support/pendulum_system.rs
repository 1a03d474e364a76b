//! The plane pendulum of the `orbits` example and the sensitivity tests, and its period in
//! closed form through the complete elliptic integrals K(k), E(k).

use lagrange::prelude::*;

/// A plane pendulum, θ̈ = −(g/l) sin θ.
pub struct Pendulum {
    /// Gravity.
    pub g: f64,
    /// Length.
    pub l: f64,
}

#[lagrangian]
impl Pendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.l * self.l * theta_dot * theta_dot + self.g * self.l * theta.cos()
    }
}

/// K(k) and E(k) by the arithmetic–geometric mean: K = π/(2 AGM(1, k′)),
/// E = K (1 − Σₙ 2ⁿ⁻¹ cₙ²) with c₀ = k, cₙ₊₁ = (aₙ − bₙ)/2.
///
/// ```
/// use lagrange_examples::pendulum_system::elliptic_ke;
/// let (k, e) = elliptic_ke(0.0);
/// assert!((k - std::f64::consts::FRAC_PI_2).abs() < 1e-15 && (e - k).abs() < 1e-15);
/// ```
pub fn elliptic_ke(k: f64) -> (f64, f64) {
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    let (mut sum, mut pow) = (0.5 * k * k, 0.5);
    for _ in 0..40 {
        let c = 0.5 * (a - b);
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
        pow *= 2.0;
        sum += pow * c * c;
        if c.abs() < 1e-17 {
            break;
        }
    }
    let kk = std::f64::consts::PI / (2.0 * a);
    (kk, kk * (1.0 - sum))
}

/// The period T = 4 √(l/g) K(k) of the pendulum released from rest at θ₀ (k = sin(θ₀/2)), and
/// dT/dθ₀ = 2 √(l/g) cos(θ₀/2) (E/(k k′²) − K/k).
///
/// ```
/// use lagrange_examples::pendulum_system::period;
/// let (t, dt) = period(1.3, 1.0, 1.0);
/// assert!((t - 7.019250311844546).abs() < 1e-12 && (dt - 1.2581654724013054).abs() < 1e-12);
/// ```
pub fn period(theta0: f64, g: f64, l: f64) -> (f64, f64) {
    let k = (theta0 / 2.0).sin();
    let (kk, ee) = elliptic_ke(k);
    let s = (l / g).sqrt();
    (
        4.0 * s * kk,
        2.0 * s * (theta0 / 2.0).cos() * (ee / (k * (1.0 - k * k)) - kk / k),
    )
}
