//! [`Lanes`]: W numbers side by side, one per ensemble member, so that one pass of straight-line
//! code (the generated accelerations, the stages of DOP853) advances W members at once.
//!
//! Every operation is the `f64` operation applied lane by lane, in the same order: a lane's
//! result is bit for bit what the scalar code computes for that member (the lane-vs-scalar tests
//! rely on it). Arithmetic is written as loops over a fixed-size array, which LLVM turns into
//! vector instructions (SSE2 on any x86-64; AVX2 or AVX-512 with `-C target-cpu=native`); the
//! elementary functions (`sin`, `exp`, …) call the scalar `f64` method per lane, so they round
//! exactly as the scalar run does.
//!
//! ```
//! use lagrange_runtime::lanes::Lanes;
//! let x = Lanes::from([1.0, 2.0, 3.0, 4.0]);
//! let y = 2.0 * x + x * x;
//! assert_eq!(y.0, [3.0, 8.0, 15.0, 24.0]);
//! assert_eq!(x.sqrt().0[3], 2.0);
//! ```

use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// W `f64`s operated on lane by lane (see the module docs).
///
/// ```
/// # use lagrange_runtime::lanes::Lanes;
/// assert_eq!(Lanes::<2>::splat(1.5).0, [1.5, 1.5]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes<const W: usize>(pub [f64; W]);

/// W booleans, one per lane: what a comparison of [`Lanes`] gives and [`Lanes::select`] takes.
///
/// ```
/// # use lagrange_runtime::lanes::{Lanes, Mask};
/// let m: Mask<2> = Lanes([1.0, -1.0]).ge(0.0);
/// assert_eq!(m.0, [true, false]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mask<const W: usize>(pub [bool; W]);

impl<const W: usize> Mask<W> {
    /// The mask with lane l = `f(l)`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Mask;
    /// assert_eq!(Mask::<3>::from_fn(|l| l == 1).0, [false, true, false]);
    /// ```
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> bool) -> Self {
        Mask(core::array::from_fn(f))
    }
}

impl<const W: usize> From<[f64; W]> for Lanes<W> {
    #[inline(always)]
    fn from(a: [f64; W]) -> Self {
        Lanes(a)
    }
}

impl<const W: usize> From<f64> for Lanes<W> {
    #[inline(always)]
    fn from(x: f64) -> Self {
        Lanes([x; W])
    }
}

impl<const W: usize> Default for Lanes<W> {
    #[inline(always)]
    fn default() -> Self {
        Lanes([0.0; W])
    }
}

impl<const W: usize> Lanes<W> {
    /// Not a number in every lane.
    pub const NAN: Self = Lanes([f64::NAN; W]);
    /// +∞ in every lane.
    pub const INFINITY: Self = Lanes([f64::INFINITY; W]);
    /// −∞ in every lane.
    pub const NEG_INFINITY: Self = Lanes([f64::NEG_INFINITY; W]);
    /// Zero in every lane.
    pub const ZERO: Self = Lanes([0.0; W]);

    /// `x` in every lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<3>::splat(2.0).0, [2.0; 3]);
    /// ```
    #[inline(always)]
    pub fn splat(x: f64) -> Self {
        Lanes([x; W])
    }

    /// The lanes l ↦ `f(l)`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<3>::from_fn(|l| l as f64).0, [0.0, 1.0, 2.0]);
    /// ```
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        Lanes(core::array::from_fn(f))
    }

    /// `f` applied to every lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes([1.0, 4.0]).map(|x| x + 1.0).0, [2.0, 5.0]);
    /// ```
    #[inline(always)]
    pub fn map(self, mut f: impl FnMut(f64) -> f64) -> Self {
        let mut out = self.0;
        for x in &mut out {
            *x = f(*x);
        }
        Lanes(out)
    }

    /// `f` applied lane by lane to `self` and `other`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes([1.0, 4.0]).zip(Lanes([2.0, 3.0]), f64::max).0, [2.0, 4.0]);
    /// ```
    #[inline(always)]
    pub fn zip(self, other: Self, mut f: impl FnMut(f64, f64) -> f64) -> Self {
        let mut out = self.0;
        for l in 0..W {
            out[l] = f(out[l], other.0[l]);
        }
        Lanes(out)
    }

    /// Lane l of `a` where `mask` is set, else lane l of `b`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::{Lanes, Mask};
    /// let s = Lanes::select(Mask([true, false]), 1.0, Lanes([5.0, 6.0]));
    /// assert_eq!(s.0, [1.0, 6.0]);
    /// ```
    #[inline(always)]
    pub fn select(mask: Mask<W>, a: impl Into<Self>, b: impl Into<Self>) -> Self {
        let (a, b) = (a.into(), b.into());
        Lanes(core::array::from_fn(|l| {
            if mask.0[l] {
                a.0[l]
            } else {
                b.0[l]
            }
        }))
    }

    /// The lanes where `self ≥ x`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes([0.0, -0.5]).ge(0.0).0, [true, false]);
    /// ```
    #[inline(always)]
    pub fn ge(self, x: impl Into<Self>) -> Mask<W> {
        let x = x.into();
        Mask(core::array::from_fn(|l| self.0[l] >= x.0[l]))
    }

    /// Whether `self > x` in every lane (false if any lane is NaN): the generated solve's pivot
    /// test, which sends the whole vector to the per-lane scalar path when it fails anywhere.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert!(Lanes([1.0, 2.0]).all_gt(0.5));
    /// assert!(!Lanes([1.0, f64::NAN]).all_gt(0.5));
    /// ```
    #[inline(always)]
    pub fn all_gt(self, x: impl Into<Self>) -> bool {
        let x = x.into();
        // Non-short-circuit `&`: one vector compare, no branch per lane.
        (0..W).fold(true, |ok, l| ok & (self.0[l] > x.0[l]))
    }

    /// Whether every lane is finite.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert!(Lanes([1.0, 2.0]).all_finite());
    /// assert!(!Lanes([1.0, f64::INFINITY]).all_finite());
    /// ```
    #[inline(always)]
    pub fn all_finite(self) -> bool {
        // x − x is 0 for a finite x and NaN otherwise; the sum of the lanes' is 0 only if all are.
        let mut s = 0.0;
        for l in 0..W {
            s += self.0[l] - self.0[l];
        }
        s == 0.0
    }

    /// The Heaviside step lane by lane: 1 where `self ≥ 0`, else 0.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes([0.0, -1.0]).step().0, [1.0, 0.0]);
    /// ```
    #[inline(always)]
    pub fn step(self) -> Self {
        self.map(|x| if x >= 0.0 { 1.0 } else { 0.0 })
    }

    /// (sin, cos) lane by lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// let (s, c) = Lanes([0.0, 1.0]).sin_cos();
    /// assert_eq!((s.0[1], c.0[1]), 1.0_f64.sin_cos());
    /// ```
    #[inline(always)]
    pub fn sin_cos(self) -> (Self, Self) {
        let mut s = [0.0; W];
        let mut c = [0.0; W];
        for l in 0..W {
            (s[l], c[l]) = self.0[l].sin_cos();
        }
        (Lanes(s), Lanes(c))
    }

    /// `powi(n)` lane by lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes([2.0, 3.0]).powi(3).0, [8.0, 27.0]);
    /// ```
    #[inline(always)]
    pub fn powi(self, n: i32) -> Self {
        self.map(|x| x.powi(n))
    }

    /// `powf` lane by lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes([4.0, 9.0]).powf(0.5).0, [2.0, 3.0]);
    /// ```
    #[inline(always)]
    pub fn powf(self, e: impl Into<Self>) -> Self {
        self.zip(e.into(), f64::powf)
    }

    /// `atan2(self, x)` lane by lane (self is y).
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes([1.0]).atan2(1.0).0[0], 1.0_f64.atan2(1.0));
    /// ```
    #[inline(always)]
    pub fn atan2(self, x: impl Into<Self>) -> Self {
        self.zip(x.into(), f64::atan2)
    }
}

/// The elementary functions of one argument, lane by lane with the `f64` method.
macro_rules! unary {
    ($($(#[$doc:meta])* $name:ident)*) => {
        impl<const W: usize> Lanes<W> {
            $(
                $(#[$doc])*
                #[inline(always)]
                pub fn $name(self) -> Self {
                    self.map(f64::$name)
                }
            )*
        }
    };
}

unary! {
    /// √x lane by lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes([4.0, 9.0]).sqrt().0, [2.0, 3.0]);
    /// ```
    sqrt
    /// sin lane by lane.
    sin
    /// cos lane by lane.
    cos
    /// tan lane by lane.
    tan
    /// exp lane by lane.
    exp
    /// ln lane by lane.
    ln
    /// |x| lane by lane.
    abs
    /// asinh lane by lane.
    asinh
    /// acosh lane by lane.
    acosh
    /// atanh lane by lane.
    atanh
    /// ∛x lane by lane.
    cbrt
    /// signum lane by lane.
    signum
    /// asin lane by lane.
    asin
    /// acos lane by lane.
    acos
    /// atan lane by lane.
    atan
    /// sinh lane by lane.
    sinh
    /// cosh lane by lane.
    cosh
    /// tanh lane by lane.
    tanh
}

/// `Lanes ∘ Lanes`, `Lanes ∘ f64` and `f64 ∘ Lanes` for one binary operator, lane by lane.
macro_rules! binary {
    ($($trait:ident $method:ident $assign:ident $assign_method:ident $op:tt;)*) => {$(
        impl<const W: usize> $trait for Lanes<W> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                let mut out = self.0;
                for l in 0..W {
                    out[l] = out[l] $op rhs.0[l];
                }
                Lanes(out)
            }
        }
        impl<const W: usize> $trait<f64> for Lanes<W> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: f64) -> Self {
                self $op Lanes::splat(rhs)
            }
        }
        impl<const W: usize> $trait<Lanes<W>> for f64 {
            type Output = Lanes<W>;
            #[inline(always)]
            fn $method(self, rhs: Lanes<W>) -> Lanes<W> {
                Lanes::splat(self) $op rhs
            }
        }
        impl<const W: usize> $assign for Lanes<W> {
            #[inline(always)]
            fn $assign_method(&mut self, rhs: Self) {
                *self = *self $op rhs;
            }
        }
    )*};
}

binary! {
    Add add AddAssign add_assign +;
    Sub sub SubAssign sub_assign -;
    Mul mul MulAssign mul_assign *;
    Div div DivAssign div_assign /;
}

impl<const W: usize> Neg for Lanes<W> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|x| -x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every operation is the f64 operation per lane, bit for bit.
    #[test]
    fn lanes_are_the_scalar_operations() {
        let a = Lanes([0.3, -1.7, 2.5, 1e-300]);
        let b = Lanes([1.1, 0.2, -3.0, 7.0]);
        for l in 0..4 {
            let (x, y) = (a.0[l], b.0[l]);
            assert_eq!((a + b).0[l].to_bits(), (x + y).to_bits());
            assert_eq!((a - b).0[l].to_bits(), (x - y).to_bits());
            assert_eq!((a * b).0[l].to_bits(), (x * y).to_bits());
            assert_eq!((a / b).0[l].to_bits(), (x / y).to_bits());
            assert_eq!((2.5 * a).0[l].to_bits(), (2.5 * x).to_bits());
            assert_eq!((a / 3.0).0[l].to_bits(), (x / 3.0).to_bits());
            assert_eq!((1.0 / b).0[l].to_bits(), (1.0 / y).to_bits());
            assert_eq!((-a).0[l].to_bits(), (-x).to_bits());
            assert_eq!(a.sin().0[l].to_bits(), x.sin().to_bits());
            assert_eq!(a.sin_cos().1 .0[l].to_bits(), x.cos().to_bits());
            assert_eq!(b.powi(3).0[l].to_bits(), y.powi(3).to_bits());
            assert_eq!(a.atan2(b).0[l].to_bits(), x.atan2(y).to_bits());
            assert_eq!(b.abs().sqrt().0[l].to_bits(), y.abs().sqrt().to_bits());
        }
        let mut c = a;
        c += b;
        c *= b;
        c -= a;
        c /= b;
        assert_eq!(c.0[1], ((-1.7 + 0.2) * 0.2 - -1.7) / 0.2);
        assert!(!Lanes([1.0, f64::NAN]).all_finite());
        assert!(!Lanes([1.0, 1.0]).all_gt(Lanes([0.5, 1.0])));
    }
}
