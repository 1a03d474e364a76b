//! [`LinJet`]: gradient and Hessian in (q, q̇) together with their derivative along one direction
//! in (q, q̇, t): the third derivatives of L a linearization about a steady motion needs.

use super::{HessianJet, JetCalculus};

/// What [`LinJet`] and [`LinColumnJet`](super::LinColumnJet) do alike: each is a base jet `a`
/// (a [`HessianJet`], a [`ColumnJet`](super::ColumnJet)) with its derivative `d` along a seeded
/// direction, and only its `chain3` depends on what the base carries.
///
/// - `along_members!(@seed Base)`, in the inherent impl: `along_direction`, the seeded base
///   variables with the direction's components as the values of their derivatives, and `time`.
/// - `along_members!(@calculus Base, #[attributes of mul])`, in the `JetCalculus` impl: every
///   member but `chain3`, part by part on (a, d); the base's product is bilinear, so the product's
///   derivative is the product of each factor's derivative with the other factor.
macro_rules! along_members {
    (@seed $Base:ident) => {
        /// q and q̇ from the seeded base variables `(qa, va)`, moving along (`dq`, `dqdot`), and
        /// t (see [`time`](Self::time)).
        #[inline(always)]
        fn along_direction(
            (qa, va): ([$Base<N>; N], [$Base<N>; N]),
            dq: &[f64; N],
            dqdot: &[f64; N],
            t: Self,
        ) -> ([Self; N], [Self; N], Self) {
            let mut qj = [Self::constant(0.0); N];
            let mut vj = [Self::constant(0.0); N];
            for i in 0..N {
                qj[i].a = qa[i];
                qj[i].d.v = dq[i];
                vj[i].a = va[i];
                vj[i].d.v = dqdot[i];
            }
            (qj, vj, t)
        }

        /// t at `t`, moving at `dt` along the direction.
        #[inline(always)]
        fn time(t: f64, dt: f64) -> Self {
            let mut tj = Self::constant(t);
            tj.d.v = dt;
            tj
        }
    };
    (@calculus $Base:ident, $(#[$mul:meta])*) => {
        #[inline(always)]
        fn constant(x: f64) -> Self {
            Self {
                a: $Base::constant(x),
                d: $Base::ZERO,
            }
        }
        #[inline(always)]
        fn value(&self) -> f64 {
            self.a.v
        }
        #[inline(always)]
        fn with_value(mut self, v: f64) -> Self {
            self.a.v = v;
            self
        }
        #[inline(always)]
        fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
            // Exact only where f‴ = 0: every operator and elementary function of this crate
            // calls `chain3` instead.
            self.chain3(f0, f1, f2, 0.0)
        }
        #[inline(always)]
        fn add(self, b: Self) -> Self {
            Self {
                a: self.a.add(b.a),
                d: self.d.add(b.d),
            }
        }
        #[inline(always)]
        fn sub(self, b: Self) -> Self {
            Self {
                a: self.a.sub(b.a),
                d: self.d.sub(b.d),
            }
        }
        $(#[$mul])*
        fn mul(self, b: Self) -> Self {
            Self {
                a: self.a.mul(b.a),
                d: self.d.mul(b.a).add(self.a.mul(b.d)),
            }
        }
        #[inline(always)]
        fn scale(self, c: f64) -> Self {
            Self {
                a: self.a.scale(c),
                d: self.d.scale(c),
            }
        }
        #[inline(always)]
        fn add_f64(mut self, c: f64) -> Self {
            self.a.v += c;
            self
        }
        fn all_finite(&self) -> bool {
            self.a.all_finite() && self.d.all_finite()
        }
        fn is_constant(&self) -> bool {
            self.a.is_constant() && self.d.v == 0.0 && self.d.is_constant()
        }
    };
}
pub(super) use along_members;

/// A second-order jet in (q, q̇) whose every part also carries its derivative along one seeded
/// direction z = (δq, δq̇, δt) in (q, q̇, t).
///
/// Evaluating L in it gives L, ∇L, ∇²L (as a [`HessianJet`], [`LinJet::base`]) and
/// D_z L, D_z ∇L, D_z ∇²L (laid out the same way, [`LinJet::along`]): the third derivatives of L
/// contracted once with z, from one evaluation. The chain rule uses f, f′, f″ and f‴ of every
/// elementary function ([`JetCalculus::chain3`]).
///
/// ```
/// use lagrange_runtime::jet::LinJet;
/// // L = q³ q̇ at q = 2, q̇ = 5, along z = (δq, δq̇) = (1, 0)
/// let (q, v, _t) = LinJet::<1>::seed(&[2.0], &[5.0], 0.0, &[1.0], &[0.0], 0.0);
/// let l = q[0] * q[0] * q[0] * v[0];
/// assert_eq!(l.base().hess_qq(), [[6.0 * 2.0 * 5.0]]); // 6 q q̇
/// assert_eq!(l.along().hess_qq(), [[6.0 * 5.0]]);      // ∂/∂q of 6 q q̇
/// assert_eq!(l.along().hess_qqdot(), [[6.0 * 2.0]]); // ∂/∂q of 3 q²
/// ```
#[derive(Clone, Copy, Debug)]
pub struct LinJet<const N: usize> {
    a: HessianJet<N>,
    d: HessianJet<N>,
}

impl<const N: usize> LinJet<N> {
    /// Seeds q and q̇ as the 2N variables of the Hessian, at time t, and the direction
    /// z = (`dq`, `dqdot`, `dt`) along which every part is differentiated.
    ///
    /// ```
    /// use lagrange_runtime::jet::LinJet;
    /// let (q, v, t) = LinJet::<1>::seed(&[1.0], &[2.0], 3.0, &[0.5], &[0.25], 1.0);
    /// assert_eq!((q[0].along().value(), v[0].along().value(), t.along().value()), (0.5, 0.25, 1.0));
    /// ```
    pub fn seed(
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
        dq: &[f64; N],
        dqdot: &[f64; N],
        dt: f64,
    ) -> ([Self; N], [Self; N], Self) {
        Self::along_direction(HessianJet::seed(q, qdot), dq, dqdot, Self::time(t, dt))
    }

    along_members!(@seed HessianJet);

    /// The value, gradient and Hessian in (q, q̇).
    ///
    /// ```
    /// use lagrange_runtime::jet::LinJet;
    /// let (q, _, _) = LinJet::<1>::seed(&[3.0], &[0.0], 0.0, &[1.0], &[0.0], 0.0);
    /// assert_eq!((q[0] * q[0]).base().grad_q(), [6.0]);
    /// ```
    pub fn base(&self) -> &HessianJet<N> {
        &self.a
    }

    /// The derivative along the seeded direction of the value, the gradient and the Hessian, in
    /// the layout of [`LinJet::base`] (`along().hess_qqdot()[i][k]` is D_z ∂²L/∂qᵢ∂q̇ₖ).
    ///
    /// ```
    /// use lagrange_runtime::jet::LinJet;
    /// let (q, _, _) = LinJet::<1>::seed(&[3.0], &[0.0], 0.0, &[2.0], &[0.0], 0.0);
    /// let cube = q[0] * q[0] * q[0];
    /// assert_eq!(cube.along().hess_qq(), [[6.0 * 2.0]]); // (q³)‴ δq
    /// ```
    pub fn along(&self) -> &HessianJet<N> {
        &self.d
    }
}

impl<const N: usize> JetCalculus for LinJet<N> {
    along_members!(@calculus HessianJet,);

    fn chain3(self, f0: f64, f1: f64, f2: f64, f3: f64) -> Self {
        let (x, dx) = (&self.a, &self.d);
        let s = dx.v; // D_z of the argument's value
        let mut d = HessianJet::ZERO;
        d.v = f1 * s;
        for i in 0..N {
            d.gq[i] = f2 * s * x.gq[i] + f1 * dx.gq[i];
            d.gv[i] = f2 * s * x.gv[i] + f1 * dx.gv[i];
        }
        // D_z (f′ H + f″ g gᵀ) = f″ s H + f′ D_z H + f‴ s g gᵀ + f″ (D_z g gᵀ + g D_z gᵀ)
        let block = |h: f64, dh: f64, gi: f64, gk: f64, dgi: f64, dgk: f64| {
            f2 * s * h + f1 * dh + f3 * s * gi * gk + f2 * (dgi * gk + gi * dgk)
        };
        for i in 0..N {
            for k in 0..N {
                let (qi, qk, vi, vk) = (x.gq[i], x.gq[k], x.gv[i], x.gv[k]);
                let (dqi, dqk, dvi, dvk) = (dx.gq[i], dx.gq[k], dx.gv[i], dx.gv[k]);
                d.hqq[i][k] = block(x.hqq[i][k], dx.hqq[i][k], qi, qk, dqi, dqk);
                d.hqv[i][k] = block(x.hqv[i][k], dx.hqv[i][k], qi, vk, dqi, dvk);
                d.hvv[i][k] = block(x.hvv[i][k], dx.hvv[i][k], vi, vk, dvi, dvk);
            }
        }
        LinJet {
            a: self.a.chain(f0, f1, f2),
            d,
        }
    }
}

impl_jet_scalar!([const N: usize] LinJet<N>);
