//! [`Real`]: the numbers the compiled kernels compute with — `f64` for a single run and
//! [`Lanes`] for W ensemble members at once (each lane the scalar computation bit for bit, to
//! round-off where the vector sin and cos enter). `#[lagrangian]` emits every body (q̈, the
//! Taylor series) once, generic over this; the Taylor kernels, the factorization of the series
//! solve and the integrators' vector arithmetic are written once over it too. The elementary
//! functions come from the one table of `lagrange_functions` (see `functions!` below): a function is a
//! row there.

use core::ops::{Add, AddAssign, BitAnd, Div, Mul, Neg, Sub, SubAssign};

use crate::lanes::{Lanes, Mask};

/// `f64 ∘ R` for the four operators: what generated code needs where a constant stands on the
/// left (`2.0 * x`). Implemented for every [`Real`]; a generic kernel states `f64: LeftOps<R>`.
///
/// ```
/// use lagrange_runtime::{lanes::Lanes, real::LeftOps};
/// fn twice<R: Copy>(x: R) -> R where f64: LeftOps<R> { 2.0 * x }
/// assert_eq!(twice(Lanes::<2>([1.0, 2.0])).0, [2.0, 4.0]);
/// ```
pub trait LeftOps<R>:
    Add<R, Output = R> + Sub<R, Output = R> + Mul<R, Output = R> + Div<R, Output = R>
{
}

impl<R> LeftOps<R> for f64 where
    f64: Add<R, Output = R> + Sub<R, Output = R> + Mul<R, Output = R> + Div<R, Output = R>
{
}

/// The elementary functions of one argument, from the one table
/// ([`lagrange_functions::with_functions!`]): each row marked `real = yes` is a trait method of
/// [`Real`] (`functions!(decl)`), its `f64` instance (`functions!(f64)`) and its lanes instance
/// (`functions!(lanes)`: the `f64` method lane by lane; `ln` of the fused lanes from the vector
/// code, [`Lanes::ln_vector`]). A new row needs nothing here.
macro_rules! functions {
    ($part:ident) => {
        lagrange_functions::with_functions!(functions @rows $part);
    };
    (@rows $part:ident $($variant:ident $method:ident $unicode:literal $latex:literal
        real = $real:ident jets = $jets:ident
        tangent $targs:tt = $tangent:expr; jets $jargs:tt = $jet:expr;)*) => {
        $(functions!(@one $part $real $method);)*
    };
    (@one $part:ident no $f:ident) => {};
    (@one decl yes $f:ident) => {
        #[doc = concat!("`f64::", stringify!($f), "` (lane by lane).")]
        fn $f(self) -> Self;
    };
    (@one f64 yes $f:ident) => {
        #[inline(always)]
        fn $f(self) -> Self {
            f64::$f(self)
        }
    };
    // The fused lanes take ln from the vector code (within 1 ulp of `f64::ln`): DOP853's error
    // norm takes two per member and step.
    (@one lanes yes ln) => {
        #[inline(always)]
        fn ln(self) -> Self {
            if F { Lanes::ln_vector(self) } else { self.map(f64::ln) }
        }
    };
    (@one lanes yes $f:ident) => {
        #[inline(always)]
        fn $f(self) -> Self {
            self.map(f64::$f)
        }
    };
}

/// The numbers of the compiled kernels: `f64`, and [`Lanes`] for ensembles (W members at once,
/// each lane the scalar computation: every kernel is written once, over this). A comparison gives
/// a [`Mask`](Real::Mask) (`bool` for `f64`), so a pivot test that fails in one lane clears that
/// lane alone.
///
/// ```
/// use lagrange_runtime::{lanes::Lanes, {real::Real, taylor::mul}};
/// let (mut a, mut b) = ([Lanes::<2>::ZERO; 33], [<Lanes<2> as Real>::ZERO; 33]);
/// // a = 1 + c τ with c = 1 in lane 0 and 2 in lane 1, b = 3 + τ: (ab)₁ = 3c + 1.
/// (a[0], a[1], b[0], b[1]) = (Lanes::<2>([1.0; 2]), Lanes::<2>([1.0, 2.0]), Lanes::<2>([3.0; 2]), Lanes::<2>([1.0; 2]));
/// assert_eq!(mul(&a, &b, 1).0, [4.0, 7.0]);
/// // One body for both widths:
/// fn pivot_ok<R: Real>(d: R, m: R) -> R::Mask { d.greater(m * 1e-8) & d.finite() }
/// assert!(pivot_ok(1.0, 2.0));
/// assert_eq!(pivot_ok(Lanes::<2>([1.0, -1.0]), Lanes::<2>([2.0; 2])).0, [true, false]);
/// ```
pub trait Real:
    Copy
    + core::fmt::Debug
    + PartialEq
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + AddAssign
    + SubAssign
    + From<f64>
{
    /// 0 (in every lane).
    const ZERO: Self;
    /// Not a number (in every lane).
    const NAN: Self;
    /// How many members one value carries (1 for `f64`).
    const WIDTH: usize;
    /// One flag per lane: `bool` for `f64`, [`Mask`] for [`Lanes`].
    type Mask: Copy + core::fmt::Debug + BitAnd<Output = Self::Mask>;
    /// The mask with every lane set.
    const EVERY_LANE: Self::Mask;

    /// The value with lane l = `f(l)`.
    fn from_lanes(f: impl FnMut(usize) -> f64) -> Self;
    /// The lanes where `self > x` (not where either is NaN).
    fn greater(self, x: Self) -> Self::Mask;
    /// The lanes where `self ≤ x` (not where either is NaN).
    fn at_most(self, x: Self) -> Self::Mask;
    /// The larger of `self` and `x` in every lane (`f64::max`: a NaN loses).
    fn max(self, x: Self) -> Self;
    /// The finite lanes.
    fn finite(self) -> Self::Mask;
    /// The lanes that are not zero (a condition carried as 0 or 1).
    fn nonzero(self) -> Self::Mask;
    /// Whether every lane of `m` is set.
    fn all(m: Self::Mask) -> bool;

    /// Lane by lane, `a` where `m` is set, else `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// `self · a + b`: rounded twice for `f64` (a single run computes as written) and for
    /// [`Lanes`] of the exact paths, once for fused [`Lanes`] (the engines' FMA paths). What the
    /// integrators' sums and the Taylor convolutions are written with.
    fn madd(self, a: Self, b: Self) -> Self;
    /// The Heaviside step: 1 where `self ≥ 0`, else 0.
    fn step(self) -> Self;
    /// (sin, cos); for lanes one vector computation within 1 ulp of the `f64` methods.
    fn sin_cos(self) -> (Self, Self);
    /// sin (see [`sin_cos`](Real::sin_cos)).
    fn sin(self) -> Self;
    /// cos (see [`sin_cos`](Real::sin_cos)).
    fn cos(self) -> Self;
    /// `powi(n)`.
    fn powi(self, n: i32) -> Self;
    /// `powf(e)`.
    fn powf(self, e: Self) -> Self;
    /// `atan2(self, x)` (self is y).
    fn atan2(self, x: Self) -> Self;
    functions!(decl);
}

/// The members of [`Real`] that are the same for every single-run number (`f64`,
/// [`Tangent`](crate::tangent::Tangent)): width 1, a `bool` for a mask, `select` by that `bool`
/// and `madd` as written (rounded twice).
macro_rules! single_run {
    () => {
        const WIDTH: usize = 1;
        type Mask = bool;
        const EVERY_LANE: bool = true;

        #[inline(always)]
        fn all(m: bool) -> bool {
            m
        }
        #[inline(always)]
        fn select(m: bool, a: Self, b: Self) -> Self {
            if m { a } else { b }
        }
        #[inline(always)]
        fn madd(self, a: Self, b: Self) -> Self {
            self * a + b
        }
    };
}
pub(crate) use single_run;

impl Real for f64 {
    const ZERO: Self = 0.0;
    const NAN: Self = f64::NAN;
    single_run!();

    #[inline(always)]
    fn from_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        f(0)
    }
    #[inline(always)]
    fn greater(self, x: Self) -> bool {
        self > x
    }
    #[inline(always)]
    fn at_most(self, x: Self) -> bool {
        self <= x
    }
    #[inline(always)]
    fn max(self, x: Self) -> Self {
        f64::max(self, x)
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline(always)]
    fn nonzero(self) -> bool {
        self != 0.0
    }
    #[inline(always)]
    fn step(self) -> Self {
        if self >= 0.0 { 1.0 } else { 0.0 }
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        f64::sin_cos(self)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        f64::powi(self, n)
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        f64::powf(self, e)
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    functions!(f64);
}

impl<const W: usize, const F: bool> Real for Lanes<W, F> {
    const ZERO: Self = Lanes([0.0; W]);
    const NAN: Self = Lanes([f64::NAN; W]);
    const WIDTH: usize = W;
    type Mask = Mask<W>;
    const EVERY_LANE: Mask<W> = Mask([true; W]);

    #[inline(always)]
    fn from_lanes(f: impl FnMut(usize) -> f64) -> Self {
        Lanes::from_fn(f)
    }
    #[inline(always)]
    fn greater(self, x: Self) -> Mask<W> {
        self.gt(x)
    }
    #[inline(always)]
    fn at_most(self, x: Self) -> Mask<W> {
        Mask::from_fn(|l| self.0[l] <= x.0[l])
    }
    #[inline(always)]
    fn max(self, x: Self) -> Self {
        self.zip(x, f64::max)
    }
    #[inline(always)]
    fn finite(self) -> Mask<W> {
        Lanes::finite(self)
    }
    #[inline(always)]
    fn nonzero(self) -> Mask<W> {
        Mask::from_fn(|l| self.0[l] != 0.0)
    }
    #[inline(always)]
    fn all(m: Mask<W>) -> bool {
        m.all()
    }

    #[inline(always)]
    fn select(m: Mask<W>, a: Self, b: Self) -> Self {
        Lanes::select(m, a, b)
    }
    #[inline(always)]
    fn madd(self, a: Self, b: Self) -> Self {
        Lanes::madd(self, a, b)
    }
    #[inline(always)]
    fn step(self) -> Self {
        Lanes::step(self)
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        Lanes::sin_cos(self)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        Lanes::sin_cos(self).0
    }
    #[inline(always)]
    fn cos(self) -> Self {
        Lanes::sin_cos(self).1
    }
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        self.map(|x| x.powi(n))
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        self.zip(e, f64::powf)
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        self.zip(x, f64::atan2)
    }
    functions!(lanes);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every function of the table is the `f64` method in every lane, bit for bit.
    #[test]
    fn lanes_functions_are_the_f64_methods() {
        let x = Lanes::<4>([0.3, 0.7, 0.05, 0.9]);
        macro_rules! check {
            ($($variant:ident $f:ident $unicode:literal $latex:literal real = $real:ident
                jets = $jets:ident tangent $targs:tt = $tangent:expr; jets $jargs:tt = $jet:expr;)*) => {
                $(check!(@one $real $f);)*
            };
            (@one no $f:ident) => {};
            (@one yes $f:ident) => {
                let v = Real::$f(x);
                for l in 0..4 {
                    let want = f64::$f(x.0[l]);
                    assert!(v.0[l].to_bits() == want.to_bits() || (want.is_nan() && v.0[l].is_nan()), stringify!($f));
                    assert_eq!(Real::$f(x.0[l]).to_bits(), want.to_bits());
                }
            };
        }
        lagrange_functions::with_functions!(check);
        assert_eq!(Real::powf(x, Lanes([2.0; 4])).0[1], 0.7_f64.powf(2.0));
        assert_eq!(Real::atan2(x, Lanes([1.0; 4])).0[2], 0.05_f64.atan2(1.0));
        assert_eq!(Real::powi(x, 3).0[3], 0.9_f64.powi(3));
        assert_eq!(<f64 as Real>::select(false, 1.0, 2.0), 2.0);
        assert_eq!(Real::step(Lanes::<2>([0.0, -1.0])).0, [1.0, 0.0]);
        assert_eq!(Real::nonzero(Lanes::<2>([0.0, 2.0])).0, [false, true]);
    }
}
