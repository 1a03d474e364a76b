//! [`ElJet`]: the second-order jet that gives everything the Euler–Lagrange solve needs in one pass.

use super::JetCalculus;

const DQ: u8 = 1; // depends on q or t: gq, gd may be non-zero
const DV: u8 = 2; // depends on q̇: gv may be non-zero
const NL: u8 = 4; // non-linear in q̇: hvv may be non-zero

/// Above this many coordinates the jets' defaults of [`Lagrangian`](crate::Lagrangian) (the
/// pieces, hence `accelerations` and `mass_matrix`; the momenta, the energy, the power and the
/// applied forces) evaluate L in [`ColumnJet`](super::ColumnJet)s (4N + 2 numbers each: N + 1
/// evaluations for the pieces, one for the rest) instead of once in an [`ElJet`]
/// (N² + 3N + 3 numbers: 8.8 KB at N = 32, 33 KB at 64, and the seeds alone are 2N of them).
/// At or below it the defaults are what they always were, bit for bit.
///
/// Measured (`accelerations` of a hand-written chain in `ElJet`s, the least thread stack it ran
/// on; opt-level 2 / opt-level 0): N = 16 191 / 511 KiB, 20 343 / 871 KiB, 24 567 / 1383 KiB,
/// 32 1255 / 2935 KiB, 48 3951 / 8829 KiB, 64 9061 / 19739 KiB. The stack grows as N³ (2N
/// seeds of N² numbers), and at 16 a debug build keeps three quarters of a 2 MiB thread for
/// its caller and for a body's own bindings. By columns the same evaluations need 63 / 183 KiB
/// at 17 and 607 / 2359 KiB at 64, and they run in
/// [`with_jet_stack`](super::with_jet_stack), on a segment of their own when the stack is
/// short: `accelerations` at 64 then ran on a thread of 143 / 535 KiB. By columns costs
/// N + 1 evaluations in numbers of 4N + 2 values: 3 to 8 times the time of the `ElJet`
/// (95 µs against 28 µs at 17, 7 to 11 ms against 1.5 ms at 64, opt-level 2).
///
/// ```
/// assert_eq!(lagrange_runtime::jet::EL_BY_COLUMNS_ABOVE, 16);
/// ```
pub const EL_BY_COLUMNS_ABOVE: usize = 16;

/// A packed second-order forward-mode jet for the Euler–Lagrange equations of an `N`-coordinate
/// system.
///
/// Seeded at a state (q, q̇, t) by [`ElJet::seed`], one evaluation of L yields
/// - `grad_q`: ∂L/∂q,
/// - `grad_qdot`: ∂L/∂q̇ (the momenta),
/// - `hess_qdot`: ∂²L/∂q̇∂q̇ (the mass matrix; upper triangle stored),
/// - `mixed`: (∂²L/∂q̇∂q)·q̇ + ∂²L/∂q̇∂t, taken as one directional derivative along (q̇, 0, 1).
///
/// Three structural flags (depends on q or t / depends on q̇ / non-linear in q̇) let every
/// operation skip the blocks that are structurally zero: `sin θ` never touches the q̇ blocks.
///
/// ```
/// use lagrange_runtime::jet::ElJet;
/// // L = q̇²/2 · q  at q = 2, q̇ = 3
/// let (q, v, _t) = ElJet::<1>::seed(&[2.0], &[3.0], 0.0);
/// let l = v[0] * v[0] * q[0] * 0.5;
/// assert_eq!(l.grad_q()[0], 4.5);      // ∂L/∂q = q̇²/2
/// assert_eq!(l.grad_qdot()[0], 6.0);   // ∂L/∂q̇ = q̇ q
/// assert_eq!(l.hess_qdot(0, 0), 2.0);  // ∂²L/∂q̇² = q
/// assert_eq!(l.mixed()[0], 9.0);       // ∂²L/∂q̇∂q · q̇ = q̇ · q̇
/// ```
#[derive(Clone, Copy, Debug)]
pub struct ElJet<const N: usize> {
    v: f64,
    gq: [f64; N],
    gv: [f64; N],
    gd: f64,
    hvv: [[f64; N]; N],
    hvd: [f64; N],
    flags: u8,
}

impl<const N: usize> ElJet<N> {
    const ZERO: Self = ElJet {
        v: 0.0,
        gq: [0.0; N],
        gv: [0.0; N],
        gd: 0.0,
        hvv: [[0.0; N]; N],
        hvd: [0.0; N],
        flags: 0,
    };

    /// Seeds the jets of q, q̇ and t at a state: q_j carries ∂/∂q_j and the direction q̇_j, q̇_i
    /// carries ∂/∂q̇_i, t carries the direction 1.
    ///
    /// ```
    /// use lagrange_runtime::jet::ElJet;
    /// let (q, v, t) = ElJet::<2>::seed(&[1.0, 2.0], &[3.0, 4.0], 5.0);
    /// assert_eq!((q[1].value(), v[0].value(), t.value()), (2.0, 3.0, 5.0));
    /// ```
    #[inline(always)]
    pub fn seed(q: &[f64; N], qdot: &[f64; N], t: f64) -> ([Self; N], [Self; N], Self) {
        let (mut qj, mut vj) = seed_variables!(q, qdot);
        for i in 0..N {
            qj[i].gd = qdot[i];
            qj[i].flags = DQ;
            vj[i].flags = DV;
        }
        let mut tj = Self::ZERO;
        tj.v = t;
        tj.gd = 1.0;
        tj.flags = DQ;
        (qj, vj, tj)
    }

    /// Seeds like [`seed`](Self::seed), but with the direction (0, 0, 1): only t moves, so
    /// [`directional`](Self::directional) is ∂/∂t exactly (no cancellation against (∂/∂q)·q̇).
    ///
    /// ```
    /// use lagrange_runtime::jet::ElJet;
    /// let (q, v, t) = ElJet::<1>::seed_time(&[2.0], &[3.0], 5.0);
    /// assert_eq!((q[0] * v[0] * t).directional(), 6.0);
    /// ```
    #[inline(always)]
    pub fn seed_time(q: &[f64; N], qdot: &[f64; N], t: f64) -> ([Self; N], [Self; N], Self) {
        let (mut qj, vj, tj) = Self::seed(q, qdot, t);
        for x in &mut qj {
            x.gd = 0.0;
        }
        (qj, vj, tj)
    }

    /// The value.
    ///
    /// ```
    /// use lagrange_runtime::jet::ElJet;
    /// assert_eq!(ElJet::<2>::from(1.5).value(), 1.5);
    /// ```
    #[inline(always)]
    pub fn value(&self) -> f64 {
        self.v
    }
    /// ∂/∂q.
    ///
    /// ```
    /// use lagrange_runtime::jet::ElJet;
    /// let (q, _, _) = ElJet::<1>::seed(&[3.0], &[0.0], 0.0);
    /// assert_eq!((q[0] * q[0]).grad_q(), [6.0]);
    /// ```
    #[inline(always)]
    pub fn grad_q(&self) -> [f64; N] {
        self.gq
    }
    /// ∂/∂q̇.
    ///
    /// ```
    /// use lagrange_runtime::jet::ElJet;
    /// let (_, v, _) = ElJet::<1>::seed(&[0.0], &[3.0], 0.0);
    /// assert_eq!((v[0] * v[0]).grad_qdot(), [6.0]);
    /// ```
    #[inline(always)]
    pub fn grad_qdot(&self) -> [f64; N] {
        self.gv
    }
    /// ∂²/∂q̇_i∂q̇_k (symmetric; either order).
    ///
    /// ```
    /// use lagrange_runtime::jet::ElJet;
    /// let (_, v, _) = ElJet::<2>::seed(&[0.0; 2], &[1.0, 2.0], 0.0);
    /// let l = v[0] * v[1];
    /// assert_eq!((l.hess_qdot(0, 1), l.hess_qdot(1, 0), l.hess_qdot(0, 0)), (1.0, 1.0, 0.0));
    /// ```
    #[inline(always)]
    pub fn hess_qdot(&self, i: usize, k: usize) -> f64 {
        if i <= k {
            self.hvv[i][k]
        } else {
            self.hvv[k][i]
        }
    }
    /// (∂²/∂q̇∂q)·q̇ + ∂²/∂q̇∂t: the derivative of ∂/∂q̇ along (q̇, 0, 1).
    ///
    /// ```
    /// use lagrange_runtime::jet::ElJet;
    /// // L = q̇ t: ∂²L/∂q̇∂t = 1
    /// let (_, v, t) = ElJet::<1>::seed(&[0.0], &[2.0], 7.0);
    /// assert_eq!((v[0] * t).mixed(), [1.0]);
    /// ```
    #[inline(always)]
    pub fn mixed(&self) -> [f64; N] {
        self.hvd
    }
    /// The derivative along (q̇, 0, 1): (∂/∂q)·q̇ + ∂/∂t.
    ///
    /// ```
    /// use lagrange_runtime::jet::ElJet;
    /// let (q, _, t) = ElJet::<1>::seed(&[2.0], &[3.0], 1.0);
    /// assert_eq!((q[0] * t).directional(), 3.0 * 1.0 + 2.0);
    /// ```
    #[inline(always)]
    pub fn directional(&self) -> f64 {
        self.gd
    }

    /// The gradients, the mixed term and M, one number after another (what `is_constant` and
    /// `all_finite` read besides the value and the directional derivative).
    fn parts(&self) -> impl Iterator<Item = &f64> {
        let gradients = self.gq.iter().chain(&self.gv).chain(&self.hvd);
        gradients.chain(self.hvv.iter().flatten())
    }
}

impl<const N: usize> JetCalculus for ElJet<N> {
    #[inline(always)]
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let a = &self;
        let flags = a.flags | if a.flags & DV != 0 { NL } else { 0 };
        let mut r = Self::constant(f0);
        r.flags = flags;
        if flags & DQ != 0 {
            for j in 0..N {
                r.gq[j] = f1 * a.gq[j];
            }
            r.gd = f1 * a.gd;
        }
        if flags & DV != 0 {
            for i in 0..N {
                r.gv[i] = f1 * a.gv[i];
            }
            for i in 0..N {
                for k in i..N {
                    r.hvv[i][k] = f1 * a.hvv[i][k] + f2 * a.gv[i] * a.gv[k];
                }
            }
            if flags & DQ != 0 {
                for i in 0..N {
                    r.hvd[i] = f1 * a.hvd[i] + f2 * a.gv[i] * a.gd;
                }
            }
        }
        r
    }

    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let a = &self;
        let flags = a.flags | b.flags;
        let mut r = Self::ZERO;
        r.v = a.v + b.v;
        r.flags = flags;
        if flags & DQ != 0 {
            for j in 0..N {
                r.gq[j] = a.gq[j] + b.gq[j];
            }
            r.gd = a.gd + b.gd;
        }
        if flags & DV != 0 {
            for i in 0..N {
                r.gv[i] = a.gv[i] + b.gv[i];
            }
            if flags & NL != 0 {
                for i in 0..N {
                    for k in i..N {
                        r.hvv[i][k] = a.hvv[i][k] + b.hvv[i][k];
                    }
                }
            }
            if flags & DQ != 0 {
                for i in 0..N {
                    r.hvd[i] = a.hvd[i] + b.hvd[i];
                }
            }
        }
        r
    }

    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = &self;
        let both_v = a.flags & b.flags & DV != 0;
        let flags = a.flags | b.flags | if both_v { NL } else { 0 };
        let mut r = Self::ZERO;
        r.v = a.v * b.v;
        r.flags = flags;
        if flags & DQ != 0 {
            for j in 0..N {
                r.gq[j] = a.v * b.gq[j] + b.v * a.gq[j];
            }
            r.gd = a.v * b.gd + b.v * a.gd;
        }
        if flags & DV != 0 {
            for i in 0..N {
                r.gv[i] = a.v * b.gv[i] + b.v * a.gv[i];
            }
            if flags & NL != 0 {
                for i in 0..N {
                    for k in i..N {
                        r.hvv[i][k] = a.v * b.hvv[i][k]
                            + b.v * a.hvv[i][k]
                            + a.gv[i] * b.gv[k]
                            + a.gv[k] * b.gv[i];
                    }
                }
            }
            if flags & DQ != 0 {
                for i in 0..N {
                    r.hvd[i] = a.v * b.hvd[i] + b.v * a.hvd[i] + a.gv[i] * b.gd + b.gv[i] * a.gd;
                }
            }
        }
        r
    }

    #[inline(always)]
    fn scale(mut self, c: f64) -> Self {
        self.v *= c;
        if self.flags & DQ != 0 {
            for j in 0..N {
                self.gq[j] *= c;
            }
            self.gd *= c;
        }
        if self.flags & DV != 0 {
            for i in 0..N {
                self.gv[i] *= c;
                self.hvd[i] *= c;
            }
            if self.flags & NL != 0 {
                for i in 0..N {
                    for k in i..N {
                        self.hvv[i][k] *= c;
                    }
                }
            }
        }
        self
    }

    fn is_constant(&self) -> bool {
        // A flagged jet can still have all-zero parts (`t - t`, `q * 0.0`); report it as constant
        // too, so `powf` takes the same (constant-exponent) path as the flag-free HessianJet.
        self.flags == 0 || (self.gd == 0.0 && self.parts().all(|x| *x == 0.0))
    }

    fn all_finite(&self) -> bool {
        self.v.is_finite() && self.gd.is_finite() && self.parts().all(|x| x.is_finite())
    }
    jet_value_members!(v);
    sub_by_scale!();
}

impl_jet_scalar!([const N: usize] ElJet<N>);
