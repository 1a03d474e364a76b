//! [`ColumnJet`]: the gradient of L in (q, q̇) and one column of its Hessian, for systems too
//! large for a [`HessianJet`](super::HessianJet) on the stack.

use super::JetCalculus;

/// Above this many coordinates the Hessian of L (and of D) is assembled column by column from
/// 2N evaluations in [`ColumnJet`]s (4N + 2 numbers each) instead of one evaluation in a
/// [`HessianJet`](super::HessianJet) (3N² + 2N + 1 numbers: 25 KB at N = 32, 100 KB at 64,
/// and a body holds dozens of them: a 32-link chain overflowed a 2 MiB thread stack).
///
/// ```
/// assert_eq!(lagrange_runtime::jet::HESSIAN_BY_COLUMNS_ABOVE, 16);
/// ```
pub const HESSIAN_BY_COLUMNS_ABOVE: usize = 16;

/// A second-order forward-mode jet in the 2N variables (q, q̇) that carries the gradient and the
/// derivative of the gradient along one of the variables (one column of the Hessian); time is
/// held constant.
///
/// ```
/// use lagrange_runtime::jet::ColumnJet;
/// // L = q q̇² at q = 2, q̇ = 3, the column of q̇ (variable 1 = N + 0).
/// let (q, v) = ColumnJet::<1>::seed(&[2.0], &[3.0], Some(1));
/// let l = q[0] * v[0] * v[0];
/// assert_eq!((l.grad_q()[0], l.grad_qdot()[0]), (9.0, 12.0));
/// assert_eq!((l.column_q()[0], l.column_qdot()[0]), (6.0, 4.0)); // ∂²L/∂q∂q̇, ∂²L/∂q̇²
/// ```
#[derive(Clone, Copy, Debug)]
pub struct ColumnJet<const N: usize> {
    pub(super) v: f64,
    pub(super) gq: [f64; N],
    pub(super) gv: [f64; N],
    /// The derivative along the chosen variable.
    pub(super) s: f64,
    /// The derivative of the gradient along the chosen variable.
    pub(super) cq: [f64; N],
    pub(super) cv: [f64; N],
}

impl<const N: usize> ColumnJet<N> {
    pub(super) const ZERO: Self = ColumnJet {
        v: 0.0,
        gq: [0.0; N],
        gv: [0.0; N],
        s: 0.0,
        cq: [0.0; N],
        cv: [0.0; N],
    };

    /// Seeds q and q̇ as the 2N independent variables, with the column of variable `column`
    /// (q_j for j < N, q̇_{j−N} above; `None`: no column).
    ///
    /// ```
    /// use lagrange_runtime::jet::ColumnJet;
    /// let (q, v) = ColumnJet::<2>::seed(&[1.0, 2.0], &[3.0, 4.0], Some(3));
    /// assert_eq!((q[1].value(), v[1].grad_qdot()), (2.0, [0.0, 1.0]));
    /// ```
    pub fn seed(q: &[f64; N], qdot: &[f64; N], column: Option<usize>) -> ([Self; N], [Self; N]) {
        let (mut qj, mut vj) = seed_variables!(q, qdot);
        match column {
            Some(j) if j < N => qj[j].s = 1.0,
            Some(j) if j < 2 * N => vj[j - N].s = 1.0,
            _ => {}
        }
        (qj, vj)
    }

    /// Seeds q, q̇ and t with the direction (`dq`, 0, `dt`) in (q, q̇, t) instead of one
    /// variable: the "column" is then the derivative of the gradient along that direction, and
    /// [`slope`](Self::slope) the derivative of the value. Along (q̇, 0, 1) the column's q̇ part
    /// is (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t, what [`ElJet::mixed`](super::ElJet::mixed) gives; along
    /// (0, 0, 1) the slope is ∂L/∂t.
    ///
    /// ```
    /// use lagrange_runtime::jet::ColumnJet;
    /// // L = q q̇ t at q = 2, q̇ = 3, t = 5 along (q̇, 0, 1):
    /// let (q, v, t) = ColumnJet::<1>::seed_along(&[2.0], &[3.0], 5.0, &[3.0], 1.0);
    /// let l = q[0] * v[0] * t;
    /// assert_eq!(l.column_qdot(), [3.0 * 5.0 + 2.0]); // ∂²L/∂q̇∂q q̇ + ∂²L/∂q̇∂t = t q̇ + q
    /// assert_eq!(l.slope(), 3.0 * 3.0 * 5.0 + 2.0 * 3.0); // (∂L/∂q) q̇ + ∂L/∂t
    /// ```
    pub fn seed_along(
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
        dq: &[f64; N],
        dt: f64,
    ) -> ([Self; N], [Self; N], Self) {
        let (mut qj, vj) = Self::seed(q, qdot, None);
        for (x, d) in qj.iter_mut().zip(dq) {
            x.s = *d;
        }
        let mut tj = Self::ZERO;
        tj.v = t;
        tj.s = dt;
        (qj, vj, tj)
    }

    /// The derivative of the value along the seeded variable or direction.
    ///
    /// ```
    /// use lagrange_runtime::jet::ColumnJet;
    /// let (q, _) = ColumnJet::<1>::seed(&[3.0], &[0.0], Some(0));
    /// assert_eq!((q[0] * q[0]).slope(), 6.0);
    /// ```
    pub fn slope(&self) -> f64 {
        self.s
    }

    value_and_gradient!(ColumnJet, ", None");

    /// ∂²/∂q ∂x along the seeded variable x.
    ///
    /// ```
    /// use lagrange_runtime::jet::ColumnJet;
    /// let (q, _) = ColumnJet::<1>::seed(&[3.0], &[0.0], Some(0));
    /// assert_eq!((q[0] * q[0]).column_q(), [2.0]);
    /// ```
    pub fn column_q(&self) -> [f64; N] {
        self.cq
    }

    /// ∂²/∂q̇ ∂x along the seeded variable x.
    ///
    /// ```
    /// use lagrange_runtime::jet::ColumnJet;
    /// let (_, v) = ColumnJet::<1>::seed(&[0.0], &[3.0], Some(1));
    /// assert_eq!((v[0] * v[0] * v[0]).column_qdot(), [18.0]);
    /// ```
    pub fn column_qdot(&self) -> [f64; N] {
        self.cv
    }

    /// The gradient and the column, one number after another (what `is_constant` and
    /// `all_finite` read besides the value and the slope).
    fn parts(&self) -> impl Iterator<Item = &f64> {
        self.gq
            .iter()
            .chain(&self.gv)
            .chain(&self.cq)
            .chain(&self.cv)
    }
}

impl<const N: usize> JetCalculus for ColumnJet<N> {
    #[inline(always)]
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let a = &self;
        let mut r = Self::constant(f0);
        r.s = f1 * a.s;
        let k = f2 * a.s;
        for i in 0..N {
            r.gq[i] = f1 * a.gq[i];
            r.gv[i] = f1 * a.gv[i];
            r.cq[i] = f1 * a.cq[i] + k * a.gq[i];
            r.cv[i] = f1 * a.cv[i] + k * a.gv[i];
        }
        r
    }
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let a = &self;
        let mut r = Self::ZERO;
        r.v = a.v + b.v;
        r.s = a.s + b.s;
        for i in 0..N {
            r.gq[i] = a.gq[i] + b.gq[i];
            r.gv[i] = a.gv[i] + b.gv[i];
            r.cq[i] = a.cq[i] + b.cq[i];
            r.cv[i] = a.cv[i] + b.cv[i];
        }
        r
    }
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = &self;
        let mut r = Self::ZERO;
        r.v = a.v * b.v;
        r.s = a.v * b.s + b.v * a.s;
        for i in 0..N {
            r.gq[i] = a.v * b.gq[i] + b.v * a.gq[i];
            r.gv[i] = a.v * b.gv[i] + b.v * a.gv[i];
            r.cq[i] = a.v * b.cq[i] + b.v * a.cq[i] + a.s * b.gq[i] + b.s * a.gq[i];
            r.cv[i] = a.v * b.cv[i] + b.v * a.cv[i] + a.s * b.gv[i] + b.s * a.gv[i];
        }
        r
    }
    #[inline(always)]
    fn scale(mut self, c: f64) -> Self {
        self.v *= c;
        self.s *= c;
        for i in 0..N {
            self.gq[i] *= c;
            self.gv[i] *= c;
            self.cq[i] *= c;
            self.cv[i] *= c;
        }
        self
    }
    fn is_constant(&self) -> bool {
        self.s == 0.0 && self.parts().all(|x| *x == 0.0)
    }
    fn all_finite(&self) -> bool {
        self.v.is_finite() && self.s.is_finite() && self.parts().all(|x| x.is_finite())
    }
    jet_value_members!(v);
    sub_by_scale!();
}

impl_jet_scalar!([const N: usize] ColumnJet<N>);

impl<const N: usize> super::HessianJet<N> {
    /// The gradient and Hessian of `f(q, q̇)` assembled column by column from 2N evaluations in
    /// [`ColumnJet`]s: what one evaluation in a `HessianJet` gives, in a stack of O(N) per
    /// number instead of O(N²).
    ///
    /// ```
    /// use lagrange_runtime::jet::HessianJet;
    /// // L = q₀ q̇₁² at q = (2, 0), q̇ = (0, 3)
    /// let h = HessianJet::<2>::by_columns(&[2.0, 0.0], &[0.0, 3.0], |q, v| q[0] * v[1] * v[1]);
    /// let (d, e) = HessianJet::<2>::seed(&[2.0, 0.0], &[0.0, 3.0]);
    /// let whole = d[0] * e[1] * e[1];
    /// assert_eq!((h.value(), h.grad_q(), h.grad_qdot()), (whole.value(), whole.grad_q(), whole.grad_qdot()));
    /// assert_eq!((h.hess_qq(), h.hess_qqdot(), h.hess_qdotqdot()), (whole.hess_qq(), whole.hess_qqdot(), whole.hess_qdotqdot()));
    /// ```
    pub fn by_columns(
        q: &[f64; N],
        qdot: &[f64; N],
        mut f: impl FnMut(&[ColumnJet<N>; N], &[ColumnJet<N>; N]) -> ColumnJet<N>,
    ) -> Self {
        let mut out = Self::ZERO;
        for j in 0..2 * N {
            let (qj, vj) = ColumnJet::seed(q, qdot, Some(j));
            let c = f(&qj, &vj);
            if j == 0 {
                out.v = c.v;
                out.gq = c.gq;
                out.gv = c.gv;
            }
            for i in 0..N {
                if j < N {
                    out.hqq[i][j] = c.cq[i];
                } else {
                    out.hqv[i][j - N] = c.cq[i];
                    out.hvv[i][j - N] = c.cv[i];
                }
            }
        }
        out
    }
}
