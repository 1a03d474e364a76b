//! [`HessianJet`]: gradient and full Hessian of L in (q, q̇), for implicit (Newton) integrators.

use super::JetCalculus;

/// A dense second-order forward-mode jet in the 2N variables (q, q̇); time is held constant.
///
/// ```
/// use lagrange_runtime::jet::HessianJet;
/// // L = q q̇² at q = 2, q̇ = 3
/// let (q, v) = HessianJet::<1>::seed(&[2.0], &[3.0]);
/// let l = q[0] * v[0] * v[0];
/// assert_eq!((l.grad_q()[0], l.grad_qdot()[0]), (9.0, 12.0));
/// assert_eq!((l.hess_qq()[0][0], l.hess_qqdot()[0][0], l.hess_qdotqdot()[0][0]), (0.0, 6.0, 4.0));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct HessianJet<const N: usize> {
    pub(super) v: f64,
    pub(super) gq: [f64; N],
    pub(super) gv: [f64; N],
    pub(super) hqq: [[f64; N]; N],
    pub(super) hqv: [[f64; N]; N],
    pub(super) hvv: [[f64; N]; N],
}

impl<const N: usize> HessianJet<N> {
    pub(super) const ZERO: Self = HessianJet {
        v: 0.0,
        gq: [0.0; N],
        gv: [0.0; N],
        hqq: [[0.0; N]; N],
        hqv: [[0.0; N]; N],
        hvv: [[0.0; N]; N],
    };

    /// Seeds q and q̇ as the 2N independent variables.
    ///
    /// ```
    /// use lagrange_runtime::jet::HessianJet;
    /// let (q, v) = HessianJet::<2>::seed(&[1.0, 2.0], &[3.0, 4.0]);
    /// assert_eq!((q[1].value(), v[1].grad_qdot()), (2.0, [0.0, 1.0]));
    /// ```
    pub fn seed(q: &[f64; N], qdot: &[f64; N]) -> ([Self; N], [Self; N]) {
        seed_variables!(q, qdot)
    }
    value_and_gradient!(HessianJet, "");
    /// ∂²/∂q_i∂q_k.
    ///
    /// ```
    /// use lagrange_runtime::jet::HessianJet;
    /// let (q, _) = HessianJet::<1>::seed(&[3.0], &[0.0]);
    /// assert_eq!((q[0] * q[0]).hess_qq(), [[2.0]]);
    /// ```
    pub fn hess_qq(&self) -> [[f64; N]; N] {
        self.hqq
    }
    /// ∂²/∂q_i∂q̇_k (row: q, column: q̇).
    ///
    /// ```
    /// use lagrange_runtime::jet::HessianJet;
    /// let (q, v) = HessianJet::<2>::seed(&[1.0, 1.0], &[1.0, 1.0]);
    /// assert_eq!((q[0] * v[1]).hess_qqdot(), [[0.0, 1.0], [0.0, 0.0]]);
    /// ```
    pub fn hess_qqdot(&self) -> [[f64; N]; N] {
        self.hqv
    }
    /// ∂²/∂q̇_i∂q̇_k.
    ///
    /// ```
    /// use lagrange_runtime::jet::HessianJet;
    /// let (_, v) = HessianJet::<1>::seed(&[0.0], &[3.0]);
    /// assert_eq!((v[0] * v[0]).hess_qdotqdot(), [[2.0]]);
    /// ```
    pub fn hess_qdotqdot(&self) -> [[f64; N]; N] {
        self.hvv
    }

    /// The gradient and the Hessian, one number after another (what `is_constant` and
    /// `all_finite` read besides the value).
    fn parts(&self) -> impl Iterator<Item = &f64> {
        let hessian = self.hqq.iter().chain(&self.hqv).chain(&self.hvv).flatten();
        self.gq.iter().chain(&self.gv).chain(hessian)
    }
}

impl<const N: usize> JetCalculus for HessianJet<N> {
    #[inline(always)]
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let a = &self;
        let mut r = Self::constant(f0);
        for i in 0..N {
            r.gq[i] = f1 * a.gq[i];
            r.gv[i] = f1 * a.gv[i];
        }
        for i in 0..N {
            for k in 0..N {
                r.hqq[i][k] = f1 * a.hqq[i][k] + f2 * a.gq[i] * a.gq[k];
                r.hqv[i][k] = f1 * a.hqv[i][k] + f2 * a.gq[i] * a.gv[k];
                r.hvv[i][k] = f1 * a.hvv[i][k] + f2 * a.gv[i] * a.gv[k];
            }
        }
        r
    }
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let a = &self;
        let mut r = Self::ZERO;
        r.v = a.v + b.v;
        for i in 0..N {
            r.gq[i] = a.gq[i] + b.gq[i];
            r.gv[i] = a.gv[i] + b.gv[i];
            for k in 0..N {
                r.hqq[i][k] = a.hqq[i][k] + b.hqq[i][k];
                r.hqv[i][k] = a.hqv[i][k] + b.hqv[i][k];
                r.hvv[i][k] = a.hvv[i][k] + b.hvv[i][k];
            }
        }
        r
    }
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = &self;
        let mut r = Self::ZERO;
        r.v = a.v * b.v;
        for i in 0..N {
            r.gq[i] = a.v * b.gq[i] + b.v * a.gq[i];
            r.gv[i] = a.v * b.gv[i] + b.v * a.gv[i];
        }
        for i in 0..N {
            for k in 0..N {
                r.hqq[i][k] =
                    a.v * b.hqq[i][k] + b.v * a.hqq[i][k] + a.gq[i] * b.gq[k] + a.gq[k] * b.gq[i];
                r.hqv[i][k] =
                    a.v * b.hqv[i][k] + b.v * a.hqv[i][k] + a.gq[i] * b.gv[k] + b.gq[i] * a.gv[k];
                r.hvv[i][k] =
                    a.v * b.hvv[i][k] + b.v * a.hvv[i][k] + a.gv[i] * b.gv[k] + a.gv[k] * b.gv[i];
            }
        }
        r
    }
    #[inline(always)]
    fn scale(mut self, c: f64) -> Self {
        self.v *= c;
        for i in 0..N {
            self.gq[i] *= c;
            self.gv[i] *= c;
            for k in 0..N {
                self.hqq[i][k] *= c;
                self.hqv[i][k] *= c;
                self.hvv[i][k] *= c;
            }
        }
        self
    }
    fn is_constant(&self) -> bool {
        self.parts().all(|x| *x == 0.0)
    }
    fn all_finite(&self) -> bool {
        self.v.is_finite() && self.parts().all(|x| x.is_finite())
    }
    jet_value_members!(v);
    sub_by_scale!();
}

impl_jet_scalar!([const N: usize] HessianJet<N>);
