//! [`Tangent`]: a number with K directional derivatives (first-order forward mode), a [`Real`]
//! of width 1. The compiled kernels are written once over [`Real`], so evaluating them in
//! tangents differentiates the generated code itself: q̈ with its derivatives along K directions
//! of (q, q̇, parameters) in one pass, and the Taylor series of the motion with the series of its
//! variations (the variational equations' Taylor method, [`Simulation::sensitivity`]).
//!
//! The calculus is written once: the four operations and the functions of the one table
//! (`lagrange_functions`, their first derivatives `jets::f(x, y)[0]`), each a value and the chain
//! rule on the K slopes. Comparisons (pivot tests, `max`, the step) look at the value only.
//!
//! [`Simulation::sensitivity`]: crate::Simulation::sensitivity
//!
//! ```
//! use lagrange_runtime::{real::Real, tangent::Tangent};
//! // f(x, y) = x sin y at (2, 0.5) along x and along y.
//! let (x, y) = (Tangent::<2>::seed(2.0, 0), Tangent::<2>::seed(0.5, 1));
//! let f = x * y.sin();
//! assert_eq!(f.value(), 2.0 * 0.5_f64.sin());
//! assert_eq!(f.slopes(), [0.5_f64.sin(), 2.0 * 0.5_f64.cos()]);
//! ```

use core::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

use crate::real::Real;

/// A value and its derivatives along K directions.
///
/// ```
/// use lagrange_runtime::tangent::Tangent;
/// let x = Tangent::new(3.0, [1.0, 0.0]);
/// assert_eq!((x * x).slopes(), [6.0, 0.0]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangent<const K: usize> {
    v: f64,
    d: [f64; K],
}

impl<const K: usize> Tangent<K> {
    /// The number with value `v` and slopes `d`.
    ///
    /// ```
    /// use lagrange_runtime::tangent::Tangent;
    /// assert_eq!(Tangent::new(1.0, [2.0]).slopes(), [2.0]);
    /// ```
    #[inline(always)]
    pub const fn new(v: f64, d: [f64; K]) -> Self {
        Tangent { v, d }
    }

    /// A constant: value `v`, every slope 0.
    ///
    /// ```
    /// use lagrange_runtime::tangent::Tangent;
    /// assert_eq!(Tangent::<3>::constant(5.0).slopes(), [0.0; 3]);
    /// ```
    #[inline(always)]
    pub const fn constant(v: f64) -> Self {
        Tangent { v, d: [0.0; K] }
    }

    /// The variable of direction `i`: value `v`, slope 1 along `i` and 0 along the others.
    ///
    /// ```
    /// use lagrange_runtime::tangent::Tangent;
    /// assert_eq!(Tangent::<2>::seed(4.0, 1).slopes(), [0.0, 1.0]);
    /// ```
    #[inline(always)]
    pub fn seed(v: f64, i: usize) -> Self {
        let mut d = [0.0; K];
        d[i] = 1.0;
        Tangent { v, d }
    }

    /// The value.
    ///
    /// ```
    /// use lagrange_runtime::tangent::Tangent;
    /// assert_eq!(Tangent::<1>::seed(4.0, 0).value(), 4.0);
    /// ```
    #[inline(always)]
    pub const fn value(self) -> f64 {
        self.v
    }

    /// The derivatives along the K directions.
    ///
    /// ```
    /// use lagrange_runtime::tangent::Tangent;
    /// assert_eq!((Tangent::<1>::seed(4.0, 0) * 3.0).slopes(), [3.0]);
    /// ```
    #[inline(always)]
    pub const fn slopes(self) -> [f64; K] {
        self.d
    }

    /// f(self) for f with value `y` = f(v) and derivative `dy` = f′(v): the chain rule.
    #[inline(always)]
    fn chain(self, y: f64, dy: f64) -> Self {
        Tangent {
            v: y,
            d: self.d.map(|x| dy * x),
        }
    }
}

impl<const K: usize> From<f64> for Tangent<K> {
    #[inline(always)]
    fn from(v: f64) -> Self {
        Tangent::constant(v)
    }
}

impl<const K: usize> Neg for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Tangent {
            v: -self.v,
            d: self.d.map(|x| -x),
        }
    }
}

impl<const K: usize> Add for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, b: Self) -> Self {
        self.v += b.v;
        for (x, y) in self.d.iter_mut().zip(b.d) {
            *x += y;
        }
        self
    }
}

impl<const K: usize> Sub for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, b: Self) -> Self {
        self.v -= b.v;
        for (x, y) in self.d.iter_mut().zip(b.d) {
            *x -= y;
        }
        self
    }
}

impl<const K: usize> Mul for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let mut d = [0.0; K];
        for ((z, x), y) in d.iter_mut().zip(self.d).zip(b.d) {
            *z = x * b.v + self.v * y;
        }
        Tangent { v: self.v * b.v, d }
    }
}

impl<const K: usize> Div for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn div(self, b: Self) -> Self {
        let r = self.v / b.v;
        let mut d = [0.0; K];
        for ((z, x), y) in d.iter_mut().zip(self.d).zip(b.d) {
            *z = (x - r * y) / b.v;
        }
        Tangent { v: r, d }
    }
}

impl<const K: usize> Add<f64> for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, b: f64) -> Self {
        self.v += b;
        self
    }
}

impl<const K: usize> Sub<f64> for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, b: f64) -> Self {
        self.v -= b;
        self
    }
}

impl<const K: usize> Mul<f64> for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, b: f64) -> Self {
        Tangent {
            v: self.v * b,
            d: self.d.map(|x| x * b),
        }
    }
}

impl<const K: usize> Div<f64> for Tangent<K> {
    type Output = Self;
    #[inline(always)]
    fn div(self, b: f64) -> Self {
        Tangent {
            v: self.v / b,
            d: self.d.map(|x| x / b),
        }
    }
}

impl<const K: usize> Add<Tangent<K>> for f64 {
    type Output = Tangent<K>;
    #[inline(always)]
    fn add(self, b: Tangent<K>) -> Tangent<K> {
        b + self
    }
}

impl<const K: usize> Sub<Tangent<K>> for f64 {
    type Output = Tangent<K>;
    #[inline(always)]
    fn sub(self, b: Tangent<K>) -> Tangent<K> {
        -b + self
    }
}

impl<const K: usize> Mul<Tangent<K>> for f64 {
    type Output = Tangent<K>;
    #[inline(always)]
    fn mul(self, b: Tangent<K>) -> Tangent<K> {
        b * self
    }
}

impl<const K: usize> Div<Tangent<K>> for f64 {
    type Output = Tangent<K>;
    #[inline(always)]
    fn div(self, b: Tangent<K>) -> Tangent<K> {
        Tangent::constant(self) / b
    }
}

impl<const K: usize> AddAssign for Tangent<K> {
    #[inline(always)]
    fn add_assign(&mut self, b: Self) {
        *self = *self + b;
    }
}

impl<const K: usize> SubAssign for Tangent<K> {
    #[inline(always)]
    fn sub_assign(&mut self, b: Self) {
        *self = *self - b;
    }
}

/// The functions of the table: value `f64::f(v)`, slope `jets::f(v, y)[0]` times the slopes.
macro_rules! functions {
    () => {
        lagrange_functions::with_functions!(functions @rows);
    };
    (@rows $($variant:ident $method:ident $unicode:literal $latex:literal
        real = $real:ident jets = $jets:ident
        tangent $targs:tt = $tangent:expr; jets $jargs:tt = $jet:expr;)*) => {
        $(functions!(@one $real $method);)*
    };
    (@one no $f:ident) => {};
    (@one yes $f:ident) => {
        #[inline(always)]
        fn $f(self) -> Self {
            let y = f64::$f(self.v);
            self.chain(y, lagrange_functions::jets::$f(self.v, y)[0])
        }
    };
}

impl<const K: usize> Real for Tangent<K> {
    const ZERO: Self = Tangent::constant(0.0);
    const NAN: Self = Tangent::constant(f64::NAN);
    crate::real::single_run!();

    #[inline(always)]
    fn from_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        Tangent::constant(f(0))
    }
    #[inline(always)]
    fn greater(self, x: Self) -> bool {
        self.v > x.v
    }
    #[inline(always)]
    fn at_most(self, x: Self) -> bool {
        self.v <= x.v
    }
    #[inline(always)]
    fn max(self, x: Self) -> Self {
        // `f64::max`: a NaN loses; the slopes of the one taken.
        if self.v.is_nan() || x.v > self.v {
            x
        } else {
            self
        }
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.v.is_finite() && self.d.iter().all(|x| x.is_finite())
    }
    #[inline(always)]
    fn nonzero(self) -> bool {
        self.v != 0.0
    }
    #[inline(always)]
    fn step(self) -> Self {
        Tangent::constant(self.v.step())
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.v.sin_cos();
        (self.chain(s, c), self.chain(c, -s))
    }
    #[inline(always)]
    fn sin(self) -> Self {
        self.sin_cos().0
    }
    #[inline(always)]
    fn cos(self) -> Self {
        self.sin_cos().1
    }
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        let y = self.v.powi(n);
        let dy = if n == 0 {
            0.0
        } else {
            f64::from(n) * self.v.powi(n - 1)
        };
        self.chain(y, dy)
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        let y = self.v.powf(e.v);
        // d(x^e) = e x^(e−1) dx + x^e ln x de; the second term only where e varies (so a
        // constant exponent at x = 0 does not make 0 · ln 0 = NaN).
        let mut out = self.chain(y, e.v * self.v.powf(e.v - 1.0));
        if e.d.iter().any(|&x| x != 0.0) {
            let l = y * self.v.ln();
            for (z, x) in out.d.iter_mut().zip(e.d) {
                *z += l * x;
            }
        }
        out
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        // d atan2(y, x) = (x dy − y dx)/(x² + y²).
        let r2 = self.v * self.v + x.v * x.v;
        let mut d = [0.0; K];
        for ((z, dy), dx) in d.iter_mut().zip(self.d).zip(x.d) {
            *z = (x.v * dy - self.v * dx) / r2;
        }
        Tangent {
            v: self.v.atan2(x.v),
            d,
        }
    }
    functions!();
}

/// The Taylor series in tangents: one LDLᵀ of M₀ per step (a failed pivot test clears the mask).
impl<const K: usize> crate::eom::SeriesReal for Tangent<K> {
    type Factor<const N: usize> = crate::eom::LdlOf<Self, N>;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every function's slope against a central difference of its value (h = 1e-6: error
    /// ~1e-10 relative for these smooth functions at these points).
    #[test]
    fn slopes_of_every_function_match_central_differences() {
        macro_rules! check {
            ($($f:ident @ $x:expr),* $(,)?) => {$({
                let x: f64 = $x;
                let t = Tangent::<1>::seed(x, 0).$f();
                let h = 1e-6;
                let fd = (f64::$f(x + h) - f64::$f(x - h)) / (2.0 * h);
                assert!((t.value() - f64::$f(x)).abs() == 0.0, stringify!($f));
                assert!((t.slopes()[0] - fd).abs() <= 1e-8 * fd.abs().max(1.0),
                    "{}: {} vs {}", stringify!($f), t.slopes()[0], fd);
            })*};
        }
        check!(sqrt @ 1.7, sin @ 0.4, cos @ 0.4, tan @ 0.4, exp @ 0.3, ln @ 1.3,
            asinh @ 0.6, acosh @ 1.6, atanh @ 0.3, exp2 @ 0.7, cbrt @ 2.5, ln_1p @ 0.4,
            exp_m1 @ 0.2, log10 @ 3.0, log2 @ 3.0, asin @ 0.3, acos @ 0.3, atan @ 0.8,
            sinh @ 0.5, cosh @ 0.5, tanh @ 0.5, abs @ -0.7);
    }

    /// The operations and the two-argument functions against closed forms.
    #[test]
    fn products_quotients_powers_and_atan2() {
        let (x, y) = (Tangent::<2>::seed(1.5, 0), Tangent::<2>::seed(-0.5, 1));
        let q = x / y;
        assert_eq!(q.value(), -3.0);
        assert_eq!(q.slopes(), [1.0 / -0.5, -1.5 / 0.25]);
        let p = x.powf(y);
        assert!((p.slopes()[0] - (-0.5) * 1.5_f64.powf(-1.5)).abs() < 1e-15);
        assert!((p.slopes()[1] - 1.5_f64.powf(-0.5) * 1.5_f64.ln()).abs() < 1e-15);
        assert_eq!(x.powi(3).slopes(), [3.0 * 2.25, 0.0]);
        assert_eq!(Tangent::<1>::seed(0.0, 0).powf(2.0.into()).slopes(), [0.0]);
        let a = y.atan2(x);
        let r2 = 1.5 * 1.5 + 0.25;
        assert_eq!(a.value(), (-0.5_f64).atan2(1.5));
        assert_eq!(a.slopes(), [0.5 / r2, 1.5 / r2]);
        assert_eq!((2.0 - x).slopes(), [-1.0, 0.0]);
        assert_eq!((2.0 / x).slopes(), [-2.0 / 2.25, 0.0]);
        assert_eq!(x.max(y), x);
        assert_eq!(Tangent::<1>::NAN.max(1.0.into()).value(), 1.0);
    }
}
