//! [`Real`]: the numbers the compiled kernels compute with — `f64` for a single run and
//! [`Lanes`] for W ensemble members at once (each lane the scalar computation bit for bit). The
//! Taylor kernels, the factorizations and the integrators' vector arithmetic are written once,
//! over this.

use core::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

use crate::lanes::Lanes;

/// The numbers of the compiled kernels: `f64`, and [`Lanes`] for ensembles (W members at once,
/// each lane the scalar computation bit for bit: every kernel is written once, over this).
///
/// ```
/// use lagrange_runtime::{lanes::Lanes, {real::Real, taylor::mul}};
/// let (mut a, mut b) = ([Lanes::<2>::ZERO; 32], [<Lanes<2> as Real>::ZERO; 32]);
/// // a = 1 + c τ with c = 1 in lane 0 and 2 in lane 1, b = 3 + τ: (ab)₁ = 3c + 1.
/// (a[0], a[1], b[0], b[1]) = (Lanes([1.0; 2]), Lanes([1.0, 2.0]), Lanes([3.0; 2]), Lanes([1.0; 2]));
/// assert_eq!(mul(&a, &b, 1).0, [4.0, 7.0]);
/// ```
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + From<f64>
{
    /// 0 (in every lane).
    const ZERO: Self;
}

impl Real for f64 {
    const ZERO: Self = 0.0;
}

impl<const W: usize> Real for Lanes<W> {
    const ZERO: Self = Lanes([0.0; W]);
}
