//! [`Timed`]: a number together with its total time derivative along the motion, over any
//! [`Scalar`] (an `f64` or a jet): what a `#[lagrangian]` body that names `velocity` (or an
//! angular velocity) is evaluated in.
//!
//! The macro lifts the state as q with rate q̇, t with rate 1, and q̇ with rate NaN (a velocity
//! has no rate the state determines), runs the body, and keeps the value part. Arithmetic is the
//! product and chain rules on the pair; an elementary function's rate is the function table's
//! exact tangent rule evaluated in the underlying number (so a jet of the rate carries every
//! derivative the jet carries, to any order).

use core::ops::{Add, Div, Mul, Neg, Sub};

use lagrange_functions::{Calc, Fun, tangent};

use super::JetCalculus;
use crate::scalar::{Scalar, Velocity};

/// A value `x` and its rate `ẋ` = d/dt x along the motion.
///
/// ```
/// use lagrange_runtime::jet::Timed;
/// use nalgebra::ComplexField;
/// let theta = Timed::new(0.5_f64, 2.0); // θ = 0.5, θ̇ = 2
/// let x = theta.sin();
/// assert_eq!(x.value(), 0.5_f64.sin());
/// assert_eq!(x.rate(), 0.5_f64.cos() * 2.0);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Timed<S> {
    x: S,
    dx: S,
}

impl<S: Scalar> Timed<S> {
    /// The value `x` moving at rate `dx`.
    ///
    /// ```
    /// let t = lagrange_runtime::jet::Timed::new(1.0_f64, 0.0);
    /// assert_eq!(t.untimed(), 1.0);
    /// ```
    #[inline(always)]
    pub fn new(x: S, dx: S) -> Self {
        Timed { x, dx }
    }

    /// The value, in the underlying number type.
    ///
    /// ```
    /// assert_eq!(lagrange_runtime::jet::Timed::new(3.0_f64, 1.0).untimed(), 3.0);
    /// ```
    #[inline(always)]
    pub fn untimed(self) -> S {
        self.x
    }

    /// The value as an `f64`.
    ///
    /// ```
    /// assert_eq!(lagrange_runtime::jet::Timed::new(3.0_f64, 1.0).value(), 3.0);
    /// ```
    #[inline(always)]
    pub fn value(&self) -> f64 {
        self.x.value()
    }

    /// The rate as an `f64`.
    ///
    /// ```
    /// assert_eq!(lagrange_runtime::jet::Timed::new(3.0_f64, 1.5).rate(), 1.5);
    /// ```
    #[inline(always)]
    pub fn rate(&self) -> f64 {
        self.dx.value()
    }
}

/// Lifts a state for a body that reads rates: each qᵢ moving at q̇ᵢ, each q̇ᵢ with an unknown
/// (NaN) rate, and t at rate 1.
///
/// ```
/// let (q, v, t) = lagrange_runtime::jet::timed_state(&[1.0_f64], &[2.0], 0.0);
/// assert_eq!((q[0].rate(), t.rate()), (2.0, 1.0));
/// assert!(v[0].rate().is_nan());
/// ```
#[allow(clippy::type_complexity)]
#[inline(always)]
pub fn timed_state<S: Scalar, const N: usize>(
    q: &[S; N],
    q_dot: &[S; N],
    t: S,
) -> ([Timed<S>; N], [Timed<S>; N], Timed<S>) {
    let nan = S::constant(f64::NAN);
    (
        core::array::from_fn(|i| Timed::new(q[i], q_dot[i])),
        core::array::from_fn(|i| Timed::new(q_dot[i], nan)),
        Timed::new(t, S::constant(1.0)),
    )
}

/// The underlying number as a [`Calc`] (what the function table's tangent rules compute with).
#[derive(Clone, Copy)]
struct C<S>(S);

macro_rules! calc_ops {
    ($($Op:ident $op:ident),*) => {$(
        impl<S: Scalar> $Op for C<S> {
            type Output = Self;
            #[inline(always)]
            fn $op(self, o: Self) -> Self {
                C(self.0.$op(o.0))
            }
        }
    )*};
}
calc_ops!(Add add, Sub sub, Mul mul, Div div);

impl<S: Scalar> Neg for C<S> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        C(-self.0)
    }
}

impl<S: Scalar> Calc for C<S> {
    fn sqrt(self) -> Self {
        C(nalgebra::ComplexField::sqrt(self.0))
    }
    fn sin(self) -> Self {
        C(nalgebra::ComplexField::sin(self.0))
    }
    fn cos(self) -> Self {
        C(nalgebra::ComplexField::cos(self.0))
    }
    fn sinh(self) -> Self {
        C(nalgebra::ComplexField::sinh(self.0))
    }
    fn cosh(self) -> Self {
        C(nalgebra::ComplexField::cosh(self.0))
    }
    fn exp(self) -> Self {
        C(nalgebra::ComplexField::exp(self.0))
    }
    fn powi(self, n: i32) -> Self {
        C(nalgebra::ComplexField::powi(self.0, n))
    }
    fn step(self) -> Self {
        C(S::constant(lagrange_functions::step(self.0.value())))
    }
}

impl<S: Scalar> JetCalculus for Timed<S> {
    #[inline(always)]
    fn constant(x: f64) -> Self {
        Timed::new(S::constant(x), S::constant(0.0))
    }
    #[inline(always)]
    fn value(&self) -> f64 {
        self.x.value()
    }
    #[inline(always)]
    fn with_value(self, v: f64) -> Self {
        Timed::new(self.x + (v - self.x.value()), self.dx)
    }
    /// Without f‴ and f⁗ the rate's jet is unknown: NaN there, never a silently wrong value
    /// (every caller in this crate passes all five through [`chain4`](Self::chain4)).
    #[inline(always)]
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        self.chain4(f0, f1, f2, f64::NAN, f64::NAN)
    }
    #[inline(always)]
    fn chain3(self, f0: f64, f1: f64, f2: f64, f3: f64) -> Self {
        self.chain4(f0, f1, f2, f3, f64::NAN)
    }
    #[inline(always)]
    fn chain4(self, f0: f64, f1: f64, f2: f64, f3: f64, f4: f64) -> Self {
        // d/dt f(x) = f′(x) ẋ, with the jet of f′(x) from f′…f⁗.
        let y = self.x.chain_rule([f0, f1, f2, f3, f4]);
        let slope = self.x.chain_rule([f1, f2, f3, f4, f64::NAN]);
        Timed::new(y, slope * self.dx)
    }
    #[inline(always)]
    fn function(self, f: Fun, y: f64, d: [f64; 3]) -> Self {
        let y = self.x.chain_rule([y, d[0], d[1], d[2], f64::NAN]);
        let k = |c: f64| C(S::constant(c));
        let dy = tangent(f, C(self.x), C(y), C(self.dx), &k).0;
        Timed::new(y, dy)
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Timed::new(self.x + o.x, self.dx + o.dx)
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Timed::new(self.x - o.x, self.dx - o.dx)
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Timed::new(self.x * o.x, self.dx * o.x + self.x * o.dx)
    }
    #[inline(always)]
    fn scale(self, c: f64) -> Self {
        Timed::new(self.x * c, self.dx * c)
    }
    #[inline(always)]
    fn add_f64(self, c: f64) -> Self {
        Timed::new(self.x + c, self.dx)
    }
    fn all_finite(&self) -> bool {
        self.x.value().is_finite()
    }
    fn is_constant(&self) -> bool {
        self.x.is_constant_number() && self.dx.value() == 0.0 && self.dx.is_constant_number()
    }
    #[inline(always)]
    fn recip_jet(self) -> Self {
        let r = nalgebra::ComplexField::recip(self.x);
        Timed::new(r, -(self.dx * r * r))
    }
}

impl_jet_scalar!([S: Scalar] Timed<S>);

impl<S: Scalar> Velocity for Timed<S> {
    /// The rate, itself with an unknown (NaN) rate: a velocity of a velocity is not taken.
    #[inline(always)]
    fn velocity(&self) -> Self {
        Timed::new(self.dx, S::constant(f64::NAN))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jet::HessianJet;
    use nalgebra::{ComplexField, RealField};

    /// An expression through every kind of rule: the table's functions (tangent rules), powi,
    /// powf, sin_cos, recip, division, atan2, abs.
    fn f<S: Scalar>(a: S, b: S) -> S {
        let (s, c) = (a * b).sin_cos();
        let e = (a * 0.3).exp() + b.powi(3) * 0.1;
        let r = (a * a + b * b + 1.0).sqrt().ln() + (b * 0.4).tanh();
        let p = (a * a + 2.0).powf(S::constant(1.7)) / (b * b + 3.0);
        s * c
            + e * r
            + p
            + ComplexField::recip(a * a + 1.5)
            + RealField::atan2(a, b + 5.0)
            + (a - b * 0.2).abs()
    }

    /// The rate of `f` along the motion (q, q̇) equals the central difference of f along (q̇)
    /// in time, at random points (tolerance 1e-8 relative: the difference's own error).
    #[test]
    fn rate_is_the_time_derivative() {
        let mut seed = 7_u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
        };
        for _ in 0..200 {
            let (a, b, va, vb) = (rnd(), rnd(), rnd(), rnd());
            let y = f(Timed::new(a, va), Timed::new(b, vb));
            let h = 1e-5;
            let fd = (f(a + h * va, b + h * vb) - f(a - h * va, b - h * vb)) / (2.0 * h);
            assert!(
                (y.rate() - fd).abs() <= 1e-8 * (1.0 + fd.abs()),
                "{} vs {fd}",
                y.rate()
            );
            // powf's value is x^(n−2)·x·x in the chain rule: within an ulp or two of f64's.
            assert!((y.value() - f(a, b)).abs() <= 1e-15 * (1.0 + f(a, b).abs()));
        }
    }

    /// Over a jet, the rate carries its own derivatives: the Hessian in (q, q̇) of the rate of
    /// `f` equals central differences of the rate's gradient (tolerance 1e-6 relative).
    #[test]
    fn rate_of_a_jet_carries_its_hessian() {
        let rate_jet = |q: [f64; 2], v: [f64; 2]| {
            let (qj, vj) = HessianJet::<2>::seed(&q, &v);
            let y = f(Timed::new(qj[0], vj[0]), Timed::new(qj[1], vj[1]));
            y.dx
        };
        let (q, v) = ([0.4, -0.9], [1.3, 0.6]);
        let r = rate_jet(q, v);
        let h = 1e-6;
        for k in 0..2 {
            let (mut qp, mut qm) = (q, q);
            qp[k] += h;
            qm[k] -= h;
            let (gp, gm) = (rate_jet(qp, v), rate_jet(qm, v));
            for i in 0..2 {
                let fd_qq = (gp.grad_q()[i] - gm.grad_q()[i]) / (2.0 * h);
                let fd_vq = (gp.grad_qdot()[i] - gm.grad_qdot()[i]) / (2.0 * h);
                assert!((r.hess_qq()[k][i] - fd_qq).abs() <= 1e-6 * (1.0 + fd_qq.abs()));
                assert!((r.hess_qqdot()[k][i] - fd_vq).abs() <= 1e-6 * (1.0 + fd_vq.abs()));
            }
        }
    }
}
