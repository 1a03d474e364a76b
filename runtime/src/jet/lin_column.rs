//! [`LinColumnJet`]: a [`ColumnJet`] together with its derivative along one direction in
//! (q, q̇, t): one column of what a [`LinJet`](super::LinJet) carries whole, for systems too
//! large for a `LinJet` on the stack.

use super::lin::along_members;
use super::{ColumnJet, JetCalculus};

/// A [`ColumnJet`] (gradient in (q, q̇) and one column of the Hessian) whose every part also
/// carries its derivative along one seeded direction z = (δq, δq̇, δt).
///
/// A [`LinJet`](super::LinJet) carries the whole Hessian and its derivative: 2(3N² + 2N + 1)
/// numbers, 200 KB per number at N = 64, and a body holds dozens of them (a 24-link chain
/// overflowed a 2 MiB thread stack). This jet carries 2(4N + 2): the linearization of a large
/// system is assembled from 2N evaluations of L in it, one per column (see
/// [`HESSIAN_BY_COLUMNS_ABOVE`](super::HESSIAN_BY_COLUMNS_ABOVE)).
///
/// ```
/// use lagrange_runtime::jet::LinColumnJet;
/// // L = q³ q̇ at q = 2, q̇ = 5, the column of q (variable 0), along z = (δq, δq̇) = (1, 0).
/// let (q, v, _t) = LinColumnJet::<1>::seed(&[2.0], &[5.0], 0.0, &[1.0], &[0.0], 0.0, 0);
/// let l = q[0] * q[0] * q[0] * v[0];
/// assert_eq!(l.base().column_q(), [6.0 * 2.0 * 5.0]); // ∂²L/∂q² = 6 q q̇
/// assert_eq!(l.along().column_q(), [6.0 * 5.0]); // its derivative along δq
/// assert_eq!(l.along().column_qdot(), [6.0 * 2.0]); // ∂/∂q of ∂²L/∂q∂q̇ = 3 q²
/// ```
#[derive(Clone, Copy, Debug)]
pub struct LinColumnJet<const N: usize> {
    a: ColumnJet<N>,
    d: ColumnJet<N>,
}

impl<const N: usize> LinColumnJet<N> {
    /// Seeds q and q̇ as the 2N variables with the column of variable `column` (q_j for j < N,
    /// q̇_{j−N} above), at time t, and the direction z = (`dq`, `dqdot`, `dt`) along which every
    /// part is differentiated.
    ///
    /// ```
    /// use lagrange_runtime::jet::LinColumnJet;
    /// let (q, v, t) = LinColumnJet::<1>::seed(&[1.0], &[2.0], 3.0, &[0.5], &[0.25], 1.0, 1);
    /// assert_eq!((q[0].along().value(), v[0].along().value(), t.along().value()), (0.5, 0.25, 1.0));
    /// ```
    pub fn seed(
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
        dq: &[f64; N],
        dqdot: &[f64; N],
        dt: f64,
        column: usize,
    ) -> ([Self; N], [Self; N], Self) {
        let base = ColumnJet::seed(q, qdot, Some(column));
        Self::along_direction(base, dq, dqdot, Self::time(t, dt))
    }

    /// [`LinColumnJet::seed`] with the 2N seeded numbers on the heap (2N (8N + 4) · 8 bytes:
    /// 530 KB at N = 64), built there one by one.
    ///
    /// ```
    /// use lagrange_runtime::jet::LinColumnJet;
    /// let (q, v, _t) = LinColumnJet::<2>::seed_boxed(&[1.0, 2.0], &[3.0, 4.0], 0.0, &[0.0; 2], &[0.0; 2], 0.0, 3);
    /// assert_eq!((q[1].base().value(), v[1].base().grad_qdot()), (2.0, [0.0, 1.0]));
    /// ```
    #[allow(clippy::type_complexity)]
    pub fn seed_boxed(
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
        dq: &[f64; N],
        dqdot: &[f64; N],
        dt: f64,
        column: usize,
    ) -> (Box<[Self; N]>, Box<[Self; N]>, Self) {
        let one = |x: f64, d: f64, var: usize| {
            let mut j = Self::constant(x);
            if var < N {
                j.a.gq[var] = 1.0;
            } else {
                j.a.gv[var - N] = 1.0;
            }
            if var == column {
                j.a.s = 1.0;
            }
            j.d.v = d;
            j
        };
        let boxed = |v: Vec<Self>| -> Box<[Self; N]> {
            match v.into_boxed_slice().try_into() {
                Ok(b) => b,
                // The vectors are built with exactly N entries.
                Err(_) => unreachable!("N seeded numbers"),
            }
        };
        let qj = boxed((0..N).map(|i| one(q[i], dq[i], i)).collect());
        let vj = boxed((0..N).map(|i| one(qdot[i], dqdot[i], N + i)).collect());
        (qj, vj, Self::time(t, dt))
    }

    along_members!(@seed ColumnJet);

    /// The value, the gradient in (q, q̇) and the seeded column of the Hessian.
    ///
    /// ```
    /// use lagrange_runtime::jet::LinColumnJet;
    /// let (q, _, _) = LinColumnJet::<1>::seed(&[3.0], &[0.0], 0.0, &[1.0], &[0.0], 0.0, 0);
    /// assert_eq!((q[0] * q[0]).base().column_q(), [2.0]);
    /// ```
    pub fn base(&self) -> &ColumnJet<N> {
        &self.a
    }

    /// The derivative along the seeded direction of the value, the gradient and the column, in
    /// the layout of [`LinColumnJet::base`].
    ///
    /// ```
    /// use lagrange_runtime::jet::LinColumnJet;
    /// let (q, _, _) = LinColumnJet::<1>::seed(&[3.0], &[0.0], 0.0, &[2.0], &[0.0], 0.0, 0);
    /// assert_eq!((q[0] * q[0] * q[0]).along().column_q(), [6.0 * 2.0]); // (q³)‴ δq
    /// ```
    pub fn along(&self) -> &ColumnJet<N> {
        &self.d
    }
}

impl<const N: usize> JetCalculus for LinColumnJet<N> {
    along_members!(@calculus ColumnJet, #[inline(never)]);

    #[inline(never)]
    fn chain3(self, f0: f64, f1: f64, f2: f64, f3: f64) -> Self {
        let (x, dx) = (&self.a, &self.d);
        let sz = dx.v; // D_z of the argument's value
        let mut d = ColumnJet::ZERO;
        d.v = f1 * sz;
        d.s = f2 * sz * x.s + f1 * dx.s;
        // The column part of f(x) is f′ c + f″ s g; its derivative along z:
        // f″ σ c + f′ D_z c + f‴ σ s g + f″ (D_z s g + s D_z g).
        for i in 0..N {
            d.gq[i] = f2 * sz * x.gq[i] + f1 * dx.gq[i];
            d.gv[i] = f2 * sz * x.gv[i] + f1 * dx.gv[i];
            d.cq[i] = f2 * sz * x.cq[i]
                + f1 * dx.cq[i]
                + f3 * sz * x.s * x.gq[i]
                + f2 * (dx.s * x.gq[i] + x.s * dx.gq[i]);
            d.cv[i] = f2 * sz * x.cv[i]
                + f1 * dx.cv[i]
                + f3 * sz * x.s * x.gv[i]
                + f2 * (dx.s * x.gv[i] + x.s * dx.gv[i]);
        }
        LinColumnJet {
            a: self.a.chain(f0, f1, f2),
            d,
        }
    }
}

impl_jet_scalar!([const N: usize] LinColumnJet<N>);
