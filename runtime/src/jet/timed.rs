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

use lagrange_functions::{tangent, Calc, Fun};

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
