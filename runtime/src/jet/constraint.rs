//! [`ConstraintJet`]: what the constraint rows of the equations of motion need from g(q, t).

use super::JetCalculus;

/// A jet for holonomic constraints g(q, t): the gradient in q (the constraint Jacobian row) and
/// the first and second derivatives along the motion, i.e. along the direction (q̇, 1) in (q, t).
///
/// Seeded at (q, q̇, t) by [`ConstraintJet::seed`], one evaluation of g yields
/// - `grad_q`: ∂g/∂q (a row of G),
/// - `rate`: ġ = G q̇ + ∂g/∂t,
/// - `curvature`: g̈ at q̈ = 0, i.e. q̇ᵀ (∂²g/∂q²) q̇ + 2 (∂²g/∂q∂t) q̇ + ∂²g/∂t²,
///
/// so that along any motion g̈ = G q̈ + `curvature`: the acceleration-level constraint is
/// G q̈ = −`curvature`.
///
/// ```
/// use lagrange_runtime::jet::ConstraintJet;
/// // g = x² + y² − 1 at (x, y) = (0.6, 0.8), velocity (−0.8, 0.6): ġ = 0, g̈ = 2|v|² = 2.
/// let (q, _t) = ConstraintJet::<2>::seed(&[0.6, 0.8], &[-0.8, 0.6], 0.0);
/// let g = q[0] * q[0] + q[1] * q[1] - 1.0;
/// assert_eq!(g.grad_q(), [1.2, 1.6]);
/// assert!(g.rate().abs() < 1e-15);
/// assert!((g.curvature() - 2.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct ConstraintJet<const N: usize> {
    v: f64,
    gq: [f64; N],
    d1: f64,
    d2: f64,
}

impl<const N: usize> ConstraintJet<N> {
    const ZERO: Self = ConstraintJet {
        v: 0.0,
        gq: [0.0; N],
        d1: 0.0,
        d2: 0.0,
    };

    /// Seeds q (each carrying ∂/∂q_j and the direction q̇_j) and t (the direction 1).
    ///
    /// ```
    /// use lagrange_runtime::jet::ConstraintJet;
    /// let (q, t) = ConstraintJet::<2>::seed(&[1.0, 2.0], &[3.0, 4.0], 5.0);
    /// assert_eq!((q[1].value(), q[1].rate(), t.rate()), (2.0, 4.0, 1.0));
    /// ```
    pub fn seed(q: &[f64; N], qdot: &[f64; N], t: f64) -> ([Self; N], Self) {
        let mut qj = [Self::ZERO; N];
        for i in 0..N {
            qj[i].v = q[i];
            qj[i].gq[i] = 1.0;
            qj[i].d1 = qdot[i];
        }
        let tj = ConstraintJet {
            v: t,
            d1: 1.0,
            ..Self::ZERO
        };
        (qj, tj)
    }

    /// A number moving at `rate` along the motion with no gradient: a coordinate of a velocity
    /// constraint, whose gradient is taken in the velocities.
    ///
    /// ```
    /// use lagrange_runtime::jet::ConstraintJet;
    /// let x = ConstraintJet::<2>::moving(1.0, 3.0);
    /// assert_eq!((x.value(), x.rate(), x.grad_q()), (1.0, 3.0, [0.0, 0.0]));
    /// ```
    pub fn moving(value: f64, rate: f64) -> Self {
        ConstraintJet {
            v: value,
            d1: rate,
            ..Self::ZERO
        }
    }

    /// The value g.
    ///
    /// ```
    /// use lagrange_runtime::jet::ConstraintJet;
    /// assert_eq!(ConstraintJet::<1>::from(2.0).value(), 2.0);
    /// ```
    pub fn value(&self) -> f64 {
        self.v
    }

    /// ∂g/∂q.
    ///
    /// ```
    /// use lagrange_runtime::jet::ConstraintJet;
    /// let (q, _) = ConstraintJet::<1>::seed(&[3.0], &[0.0], 0.0);
    /// assert_eq!((q[0] * q[0]).grad_q(), [6.0]);
    /// ```
    pub fn grad_q(&self) -> [f64; N] {
        self.gq
    }

    /// ġ = (∂g/∂q) q̇ + ∂g/∂t.
    ///
    /// ```
    /// use lagrange_runtime::jet::ConstraintJet;
    /// let (q, t) = ConstraintJet::<1>::seed(&[3.0], &[2.0], 1.0);
    /// assert_eq!((q[0] - t * 4.0).rate(), 2.0 - 4.0);
    /// ```
    pub fn rate(&self) -> f64 {
        self.d1
    }

    /// The second derivative of g along the motion with q̈ = 0:
    /// q̇ᵀ(∂²g/∂q²)q̇ + 2(∂²g/∂q∂t)q̇ + ∂²g/∂t².
    ///
    /// ```
    /// use lagrange_runtime::jet::ConstraintJet;
    /// // g = q t at q = 1, q̇ = 3, t = 2: g̈ = 2 q̇ ṫ = 6.
    /// let (q, t) = ConstraintJet::<1>::seed(&[1.0], &[3.0], 2.0);
    /// assert_eq!((q[0] * t).curvature(), 6.0);
    /// ```
    pub fn curvature(&self) -> f64 {
        self.d2
    }
}

impl<const N: usize> JetCalculus for ConstraintJet<N> {
    #[inline(always)]
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let mut r = Self::ZERO;
        r.v = f0;
        for i in 0..N {
            r.gq[i] = f1 * self.gq[i];
        }
        r.d1 = f1 * self.d1;
        r.d2 = f1 * self.d2 + f2 * self.d1 * self.d1;
        r
    }
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let mut r = self;
        r.v += b.v;
        for i in 0..N {
            r.gq[i] += b.gq[i];
        }
        r.d1 += b.d1;
        r.d2 += b.d2;
        r
    }
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        let mut r = self;
        r.v -= b.v;
        for i in 0..N {
            r.gq[i] -= b.gq[i];
        }
        r.d1 -= b.d1;
        r.d2 -= b.d2;
        r
    }
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = &self;
        let mut r = ConstraintJet {
            v: a.v * b.v,
            d1: a.v * b.d1 + b.v * a.d1,
            d2: a.v * b.d2 + b.v * a.d2 + 2.0 * a.d1 * b.d1,
            ..Self::ZERO
        };
        for i in 0..N {
            r.gq[i] = a.v * b.gq[i] + b.v * a.gq[i];
        }
        r
    }
    #[inline(always)]
    fn scale(mut self, c: f64) -> Self {
        self.v *= c;
        for i in 0..N {
            self.gq[i] *= c;
        }
        self.d1 *= c;
        self.d2 *= c;
        self
    }
    fn is_constant(&self) -> bool {
        self.gq.iter().all(|x| *x == 0.0) && self.d1 == 0.0 && self.d2 == 0.0
    }
    fn all_finite(&self) -> bool {
        self.v.is_finite()
            && self.gq.iter().all(|x| x.is_finite())
            && self.d1.is_finite()
            && self.d2.is_finite()
    }
    jet_value_members!(v);
}

impl_jet_scalar!([const N: usize] ConstraintJet<N>);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scalar;

    /// g(q, t) for the tests: every kind of operation, with t.
    fn g<S: Scalar>(q: &[S; 3], t: S) -> S {
        (q[0] * q[1]).sin() + q[2].exp() * t - (q[0] / (q[2] + 3.0)).sqrt() * q[1].powi(3)
            + (t * q[0]).cos()
    }

    /// Gradient, rate and curvature against central finite differences along a path
    /// q(s) = q + s q̇, t + s (step 1e-4 for the second difference: truncation 1e-8 · |g⁗|,
    /// round-off 1e-16 / 1e-8: agreement to 1e-6 relative is what the differences can show).
    #[test]
    fn derivatives_match_finite_differences() {
        let q = [0.3, -0.7, 0.5];
        let v = [1.1, 0.4, -0.9];
        let t = 0.8;
        let (qj, tj) = ConstraintJet::seed(&q, &v, t);
        let jet = g(&qj, tj);
        let along = |s: f64| {
            let qs = [q[0] + s * v[0], q[1] + s * v[1], q[2] + s * v[2]];
            g(&qs, t + s)
        };
        let h = 1e-4;
        let d1 = (along(h) - along(-h)) / (2.0 * h);
        let d2 = (along(h) - 2.0 * along(0.0) + along(-h)) / (h * h);
        assert_eq!(jet.value(), g(&q, t));
        assert!((jet.rate() - d1).abs() < 1e-7, "{} {d1}", jet.rate());
        assert!((jet.curvature() - d2).abs() < 1e-6 * d2.abs().max(1.0));
        for k in 0..3 {
            let mut qp = q;
            let mut qm = q;
            qp[k] += 1e-6;
            qm[k] -= 1e-6;
            let fd = (g(&qp, t) - g(&qm, t)) / 2e-6;
            assert!((jet.grad_q()[k] - fd).abs() < 1e-8, "∂g/∂q{k}");
        }
    }
}
