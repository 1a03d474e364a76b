//! Operator and trait boilerplate for jet types, generated from [`super::JetCalculus`].
//!
//! Nothing here does calculus of its own: every derivative comes from `chain4` (with the
//! elementary function's first, second and third derivative, from its row of the one function
//! table, `lagrange_functions`; the second-order jets ignore the third) or from `mul`/`add`.

/// The `ComplexField` methods of a jet type for the rows of the function table marked `jets = yes`:
/// the value and the row's f′, f″, f‴ into the chain rule. A new row needs nothing here.
macro_rules! jet_functions {
    ($($variant:ident $method:ident $unicode:literal $latex:literal real = $real:ident
        jets = $jets:ident tangent $targs:tt = $tangent:expr; jets $jargs:tt = $jet:expr;)*) => {
        $(jet_functions!(@one $jets $variant $method);)*
    };
    (@one no $variant:ident $f:ident) => {};
    (@one yes $variant:ident $f:ident) => {
        #[inline(always)]
        fn $f(self) -> Self {
            let x = $crate::jet::JetCalculus::value(&self);
            let y = f64::$f(x);
            let d = lagrange_functions::jets::$f(x, y);
            $crate::jet::JetCalculus::function(self, lagrange_functions::Fun::$variant, y, d)
        }
    };
}

/// The [`JetCalculus`](super::JetCalculus) members that every jet writes the same way, given the
/// field that holds its value (`v`, or `a.v` for a jet that carries a derivative along a
/// direction): a constant is `Self::ZERO` with that value, and `with_value` and `add_f64` touch
/// the value alone. Invoked inside the jet's `impl JetCalculus`.
macro_rules! jet_value_members {
    ($($v:ident).+) => {
        #[inline(always)]
        fn constant(x: f64) -> Self {
            let mut r = Self::ZERO;
            r.$($v).+ = x;
            r
        }
        #[inline(always)]
        fn value(&self) -> f64 {
            self.$($v).+
        }
        #[inline(always)]
        fn with_value(mut self, v: f64) -> Self {
            self.$($v).+ = v;
            self
        }
        #[inline(always)]
        fn add_f64(mut self, c: f64) -> Self {
            self.$($v).+ += c;
            self
        }
    };
}

/// `a − b` as `a + (−1)·b`: the difference of the jets whose `add` and `scale` skip structural
/// zeros (invoked inside the jet's `impl JetCalculus`).
macro_rules! sub_by_scale {
    () => {
        #[inline(always)]
        fn sub(self, b: Self) -> Self {
            self.add(b.scale(-1.0))
        }
    };
}

/// The inherent `value`, `grad_q` and `grad_qdot` of a jet with fields `v`, `gq`, `gv` whose
/// `seed(q, q̇` + `$more` + `)` returns `(qj, vj)` (its doc examples seed one coordinate).
macro_rules! value_and_gradient {
    ($Jet:ident, $more:literal) => {
        /// The value.
        ///
        /// ```
        #[doc = concat!("use lagrange_runtime::jet::", stringify!($Jet), ";")]
        #[doc = concat!("assert_eq!(", stringify!($Jet), "::<1>::from(2.0).value(), 2.0);")]
        /// ```
        pub fn value(&self) -> f64 {
            self.v
        }

        /// ∂/∂q.
        ///
        /// ```
        #[doc = concat!("use lagrange_runtime::jet::", stringify!($Jet), ";")]
        #[doc = concat!("let (q, _) = ", stringify!($Jet), "::<1>::seed(&[3.0], &[0.0]", $more, ");")]
        /// assert_eq!((q[0] * q[0]).grad_q(), [6.0]);
        /// ```
        pub fn grad_q(&self) -> [f64; N] {
            self.gq
        }

        /// ∂/∂q̇.
        ///
        /// ```
        #[doc = concat!("use lagrange_runtime::jet::", stringify!($Jet), ";")]
        #[doc = concat!("let (_, v) = ", stringify!($Jet), "::<1>::seed(&[0.0], &[3.0]", $more, ");")]
        /// assert_eq!((v[0] * v[0]).grad_qdot(), [6.0]);
        /// ```
        pub fn grad_qdot(&self) -> [f64; N] {
            self.gv
        }
    };
}

/// `(qj, vj)`: the 2N independent variables of a jet with value `v` and gradient parts `gq`,
/// `gv` (in an `impl` over `const N`): q_i and q̇_i at their values with a unit derivative along
/// themselves, every other part `Self::ZERO`'s.
macro_rules! seed_variables {
    ($q:expr, $qdot:expr) => {{
        let mut qj = [Self::ZERO; N];
        let mut vj = [Self::ZERO; N];
        for i in 0..N {
            qj[i].v = $q[i];
            qj[i].gq[i] = 1.0;
            vj[i].v = $qdot[i];
            vj[i].gv[i] = 1.0;
        }
        (qj, vj)
    }};
}

/// Implements the operators, `num_traits`, `approx`, `simba` (`RealField`) and `Scalar` traits for
/// a jet type that implements `JetCalculus`: `impl_jet_scalar!([<generics>] Type<..>)`, e.g.
/// `impl_jet_scalar!([const N: usize] ElJet<N>)`.
macro_rules! impl_jet_scalar {
    ([$($g:tt)*] $T:ty) => {
        const _: () = {
            use core::ops::{
                Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
            };
            use $crate::jet::JetCalculus as J;

            impl<$($g)*> From<f64> for $T {
                #[inline(always)]
                fn from(x: f64) -> Self {
                    J::constant(x)
                }
            }
            impl<$($g)*> PartialEq for $T {
                fn eq(&self, o: &Self) -> bool {
                    J::value(self) == J::value(o)
                }
            }
            impl<$($g)*> PartialOrd for $T {
                fn partial_cmp(&self, o: &Self) -> Option<core::cmp::Ordering> {
                    J::value(self).partial_cmp(&J::value(o))
                }
            }
            impl<$($g)*> core::fmt::Display for $T {
                fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                    write!(f, "{} + ε", J::value(self))
                }
            }

            // ---- arithmetic with Self ----
            impl<$($g)*> Add for $T {
                type Output = Self;
                #[inline(always)]
                fn add(self, o: Self) -> Self {
                    J::add(self, o)
                }
            }
            impl<$($g)*> Sub for $T {
                type Output = Self;
                #[inline(always)]
                fn sub(self, o: Self) -> Self {
                    J::sub(self, o)
                }
            }
            impl<$($g)*> Mul for $T {
                type Output = Self;
                #[inline(always)]
                fn mul(self, o: Self) -> Self {
                    J::mul(self, o)
                }
            }
            impl<$($g)*> Div for $T {
                type Output = Self;
                #[inline(always)]
                fn div(self, o: Self) -> Self {
                    J::div(self, o)
                }
            }
            #[allow(clippy::suspicious_arithmetic_impl)]
            impl<$($g)*> Rem for $T {
                type Output = Self;
                #[allow(clippy::suspicious_arithmetic_impl)] // the quotient picks the branch
                fn rem(self, o: Self) -> Self {
                    // a % b = a - trunc(a/b) b, with trunc(a/b) locally constant
                    let k = (J::value(&self) / J::value(&o)).trunc();
                    J::sub(self, J::scale(o, k))
                }
            }
            impl<$($g)*> Neg for $T {
                type Output = Self;
                #[inline(always)]
                fn neg(self) -> Self {
                    J::scale(self, -1.0)
                }
            }
            impl<$($g)*> AddAssign for $T {
                #[inline(always)]
                fn add_assign(&mut self, o: Self) {
                    *self = J::add(*self, o)
                }
            }
            impl<$($g)*> SubAssign for $T {
                #[inline(always)]
                fn sub_assign(&mut self, o: Self) {
                    *self = J::sub(*self, o)
                }
            }
            impl<$($g)*> MulAssign for $T {
                #[inline(always)]
                fn mul_assign(&mut self, o: Self) {
                    *self = J::mul(*self, o)
                }
            }
            impl<$($g)*> DivAssign for $T {
                #[inline(always)]
                fn div_assign(&mut self, o: Self) {
                    *self = J::div(*self, o)
                }
            }
            impl<$($g)*> RemAssign for $T {
                fn rem_assign(&mut self, o: Self) {
                    *self = *self % o
                }
            }

            // ---- arithmetic with f64, either side ----
            impl<$($g)*> Add<f64> for $T {
                type Output = Self;
                #[inline(always)]
                fn add(self, c: f64) -> Self {
                    J::add_f64(self, c)
                }
            }
            impl<$($g)*> Sub<f64> for $T {
                type Output = Self;
                #[inline(always)]
                fn sub(self, c: f64) -> Self {
                    J::add_f64(self, -c)
                }
            }
            impl<$($g)*> Mul<f64> for $T {
                type Output = Self;
                #[inline(always)]
                fn mul(self, c: f64) -> Self {
                    J::scale(self, c)
                }
            }
            impl<$($g)*> Div<f64> for $T {
                type Output = Self;
                #[inline(always)]
                fn div(self, c: f64) -> Self {
                    J::scale(self, 1.0 / c)
                }
            }
            impl<$($g)*> AddAssign<f64> for $T {
                #[inline(always)]
                fn add_assign(&mut self, c: f64) {
                    *self = J::add_f64(*self, c)
                }
            }
            impl<$($g)*> SubAssign<f64> for $T {
                #[inline(always)]
                fn sub_assign(&mut self, c: f64) {
                    *self = J::add_f64(*self, -c)
                }
            }
            impl<$($g)*> MulAssign<f64> for $T {
                #[inline(always)]
                fn mul_assign(&mut self, c: f64) {
                    *self = J::scale(*self, c)
                }
            }
            impl<$($g)*> DivAssign<f64> for $T {
                #[inline(always)]
                fn div_assign(&mut self, c: f64) {
                    *self = J::scale(*self, 1.0 / c)
                }
            }
            impl<$($g)*> Add<$T> for f64 {
                type Output = $T;
                #[inline(always)]
                fn add(self, x: $T) -> $T {
                    J::add_f64(x, self)
                }
            }
            impl<$($g)*> Sub<$T> for f64 {
                type Output = $T;
                #[inline(always)]
                fn sub(self, x: $T) -> $T {
                    J::add_f64(J::scale(x, -1.0), self)
                }
            }
            impl<$($g)*> Mul<$T> for f64 {
                type Output = $T;
                #[inline(always)]
                fn mul(self, x: $T) -> $T {
                    J::scale(x, self)
                }
            }
            impl<$($g)*> Div<$T> for f64 {
                type Output = $T;
                #[inline(always)]
                fn div(self, x: $T) -> $T {
                    J::scale(J::recip_jet(x), self)
                }
            }
            impl<$($g)*> Mul<nalgebra::Vector3<$T>> for $T {
                type Output = nalgebra::Vector3<$T>;
                #[inline(always)]
                fn mul(self, v: nalgebra::Vector3<$T>) -> nalgebra::Vector3<$T> {
                    v * self
                }
            }
            impl<$($g)*> core::iter::Sum for $T {
                fn sum<I: Iterator<Item = Self>>(it: I) -> Self {
                    it.fold(J::constant(0.0), J::add)
                }
            }
            impl<$($g)*> core::iter::Product for $T {
                fn product<I: Iterator<Item = Self>>(it: I) -> Self {
                    it.fold(J::constant(1.0), J::mul)
                }
            }
            impl<'a, $($g)*> core::iter::Sum<&'a $T> for $T {
                fn sum<I: Iterator<Item = &'a Self>>(it: I) -> Self {
                    it.fold(J::constant(0.0), |a, b| J::add(a, *b))
                }
            }
            impl<'a, $($g)*> core::iter::Product<&'a $T> for $T {
                fn product<I: Iterator<Item = &'a Self>>(it: I) -> Self {
                    it.fold(J::constant(1.0), |a, b| J::mul(a, *b))
                }
            }

            // ---- num-traits ----
            impl<$($g)*> num_traits::Zero for $T {
                fn zero() -> Self {
                    J::constant(0.0)
                }
                fn is_zero(&self) -> bool {
                    J::value(self) == 0.0
                }
            }
            impl<$($g)*> num_traits::One for $T {
                fn one() -> Self {
                    J::constant(1.0)
                }
            }
            impl<$($g)*> num_traits::Num for $T {
                type FromStrRadixErr = num_traits::ParseFloatError;
                fn from_str_radix(s: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
                    <f64 as num_traits::Num>::from_str_radix(s, radix).map(J::constant)
                }
            }
            impl<$($g)*> num_traits::Signed for $T {
                fn abs(&self) -> Self {
                    let x = J::value(self);
                    J::chain4(*self, x.abs(), if x < 0.0 { -1.0 } else { 1.0 }, 0.0, 0.0, 0.0)
                }
                fn abs_sub(&self, o: &Self) -> Self {
                    if J::value(self) <= J::value(o) {
                        J::constant(0.0)
                    } else {
                        J::sub(*self, *o)
                    }
                }
                fn signum(&self) -> Self {
                    J::constant(num_traits::Signed::signum(&J::value(self)))
                }
                fn is_positive(&self) -> bool {
                    J::value(self) > 0.0
                }
                fn is_negative(&self) -> bool {
                    J::value(self) < 0.0
                }
            }
            impl<$($g)*> num_traits::Bounded for $T {
                fn min_value() -> Self {
                    J::constant(f64::MIN)
                }
                fn max_value() -> Self {
                    J::constant(f64::MAX)
                }
            }
            impl<$($g)*> num_traits::FromPrimitive for $T {
                fn from_i64(n: i64) -> Option<Self> {
                    Some(J::constant(n as f64))
                }
                fn from_u64(n: u64) -> Option<Self> {
                    Some(J::constant(n as f64))
                }
                fn from_f64(n: f64) -> Option<Self> {
                    Some(J::constant(n))
                }
            }

            // ---- approx (compares values) ----
            impl<$($g)*> approx::AbsDiffEq for $T {
                type Epsilon = Self;
                fn default_epsilon() -> Self {
                    J::constant(f64::EPSILON)
                }
                fn abs_diff_eq(&self, o: &Self, eps: Self) -> bool {
                    J::value(self).abs_diff_eq(&J::value(o), J::value(&eps))
                }
            }
            impl<$($g)*> approx::RelativeEq for $T {
                fn default_max_relative() -> Self {
                    J::constant(f64::EPSILON)
                }
                fn relative_eq(&self, o: &Self, eps: Self, rel: Self) -> bool {
                    J::value(self).relative_eq(&J::value(o), J::value(&eps), J::value(&rel))
                }
            }
            impl<$($g)*> approx::UlpsEq for $T {
                fn default_max_ulps() -> u32 {
                    4
                }
                fn ulps_eq(&self, o: &Self, eps: Self, ulps: u32) -> bool {
                    J::value(self).ulps_eq(&J::value(o), J::value(&eps), ulps)
                }
            }

            // ---- simba ----
            // SimdValue declares two `unsafe fn`s without default bodies; a one-lane type
            // implements them with safe code, but the declaration itself needs the allow.
            #[allow(unsafe_code)]
            impl<$($g)*> simba::simd::SimdValue for $T {
                const LANES: usize = 1;
                type Element = Self;
                type SimdBool = bool;
                #[inline(always)]
                fn splat(v: Self) -> Self {
                    v
                }
                #[inline(always)]
                fn extract(&self, _: usize) -> Self {
                    *self
                }
                #[inline(always)]
                unsafe fn extract_unchecked(&self, _: usize) -> Self {
                    *self
                }
                #[inline(always)]
                fn replace(&mut self, _: usize, v: Self) {
                    *self = v
                }
                #[inline(always)]
                unsafe fn replace_unchecked(&mut self, _: usize, v: Self) {
                    *self = v
                }
                #[inline(always)]
                fn select(self, cond: bool, other: Self) -> Self {
                    if cond {
                        self
                    } else {
                        other
                    }
                }
            }
            impl<$($g)*> simba::scalar::Field for $T {}
            impl<$($g)*> simba::scalar::SubsetOf<$T> for $T {
                fn to_superset(&self) -> Self {
                    *self
                }
                fn from_superset_unchecked(e: &Self) -> Self {
                    *e
                }
                fn is_in_subset(_: &Self) -> bool {
                    true
                }
            }
            impl<$($g)*> simba::scalar::SubsetOf<$T> for f64 {
                fn to_superset(&self) -> $T {
                    J::constant(*self)
                }
                fn from_superset_unchecked(e: &$T) -> f64 {
                    J::value(e)
                }
                fn is_in_subset(_: &$T) -> bool {
                    true
                }
            }
            impl<$($g)*> simba::scalar::SubsetOf<$T> for f32 {
                fn to_superset(&self) -> $T {
                    J::constant(f64::from(*self))
                }
                fn from_superset_unchecked(e: &$T) -> f32 {
                    J::value(e) as f32
                }
                fn is_in_subset(_: &$T) -> bool {
                    true
                }
            }

            impl<$($g)*> simba::scalar::ComplexField for $T {
                type RealField = Self;
                fn from_real(re: Self) -> Self {
                    re
                }
                fn real(self) -> Self {
                    self
                }
                fn imaginary(self) -> Self {
                    J::constant(0.0)
                }
                fn modulus(self) -> Self {
                    num_traits::Signed::abs(&self)
                }
                fn modulus_squared(self) -> Self {
                    J::mul(self, self)
                }
                fn argument(self) -> Self {
                    J::constant(if J::value(&self) >= 0.0 {
                        0.0
                    } else {
                        core::f64::consts::PI
                    })
                }
                fn norm1(self) -> Self {
                    num_traits::Signed::abs(&self)
                }
                fn scale(self, f: Self) -> Self {
                    J::mul(self, f)
                }
                fn unscale(self, f: Self) -> Self {
                    J::div(self, f)
                }
                fn floor(self) -> Self {
                    J::constant(J::value(&self).floor())
                }
                fn ceil(self) -> Self {
                    J::constant(J::value(&self).ceil())
                }
                fn round(self) -> Self {
                    J::constant(J::value(&self).round())
                }
                fn trunc(self) -> Self {
                    J::constant(J::value(&self).trunc())
                }
                fn fract(self) -> Self {
                    J::chain4(self, J::value(&self).fract(), 1.0, 0.0, 0.0, 0.0)
                }
                fn mul_add(self, a: Self, b: Self) -> Self {
                    J::add(J::mul(self, a), b)
                }
                fn abs(self) -> Self {
                    num_traits::Signed::abs(&self)
                }
                fn hypot(self, o: Self) -> Self {
                    simba::scalar::ComplexField::sqrt(J::add(J::mul(self, self), J::mul(o, o)))
                }
                fn recip(self) -> Self {
                    J::recip_jet(self)
                }
                fn conjugate(self) -> Self {
                    self
                }
                // The smooth functions of the table (`lagrange_functions`), one chain rule each.
                lagrange_functions::with_functions!(jet_functions);
                #[inline(always)]
                fn sin_cos(self) -> (Self, Self) {
                    let (s, c) = J::value(&self).sin_cos();
                    (J::chain4(self, s, c, -s, -c, s), J::chain4(self, c, -s, -c, s, c))
                }
                fn log(self, base: Self) -> Self {
                    J::div(
                        simba::scalar::ComplexField::ln(self),
                        simba::scalar::ComplexField::ln(base),
                    )
                }
                #[inline(always)]
                fn powi(self, n: i32) -> Self {
                    let x = J::value(&self);
                    match n {
                        0 => J::constant(1.0),
                        1 => self,
                        2 => J::chain4(self, x * x, 2.0 * x, 2.0, 0.0, 0.0),
                        _ => {
                            let nf = f64::from(n);
                            // x^(n−2), x^(n−3); near i32::MIN the exponent is an f64 (exact),
                            // never an overflowing i32
                            let pow = |k: i32| match n.checked_sub(k) {
                                Some(m) => x.powi(m),
                                None => x.powf(nf - f64::from(k)),
                            };
                            let p2 = pow(2);
                            let f3 = nf * (nf - 1.0) * (nf - 2.0) * pow(3);
                            let f4 = nf * (nf - 1.0) * (nf - 2.0) * (nf - 3.0) * pow(4);
                            J::chain4(self, p2 * x * x, nf * p2 * x, nf * (nf - 1.0) * p2, f3, f4)
                        }
                    }
                }
                fn powf(self, n: Self) -> Self {
                    if J::is_constant(&n) {
                        let (x, nf) = (J::value(&self), J::value(&n));
                        if nf == 0.0 {
                            return J::constant(1.0);
                        }
                        // zero (not 0·∞ at x = 0) where the cubic coefficient vanishes
                        let f3 = if nf == 1.0 || nf == 2.0 {
                            0.0
                        } else {
                            nf * (nf - 1.0) * (nf - 2.0) * x.powf(nf - 3.0)
                        };
                        let f4 = if nf == 1.0 || nf == 2.0 || nf == 3.0 {
                            0.0
                        } else {
                            nf * (nf - 1.0) * (nf - 2.0) * (nf - 3.0) * x.powf(nf - 4.0)
                        };
                        if x == 0.0 {
                            // x^n, n x^(n−1), n(n−1) x^(n−2) one by one: the shared x^(n−2)·x·x
                            // below is ∞·0 = NaN here for 0 < n < 2 (|x|^1.5 at 0 is 0, with
                            // slope 0).
                            let f2 = if nf == 1.0 {
                                0.0
                            } else {
                                nf * (nf - 1.0) * x.powf(nf - 2.0)
                            };
                            return J::chain4(self, x.powf(nf), nf * x.powf(nf - 1.0), f2, f3, f4);
                        }
                        let p2 = x.powf(nf - 2.0);
                        J::chain4(self, p2 * x * x, nf * p2 * x, nf * (nf - 1.0) * p2, f3, f4)
                    } else {
                        let v = J::value(&self).powf(J::value(&n));
                        simba::scalar::ComplexField::exp(J::mul(
                            n,
                            simba::scalar::ComplexField::ln(self),
                        ))
                        .with_value(v)
                    }
                }
                fn powc(self, n: Self) -> Self {
                    simba::scalar::ComplexField::powf(self, n)
                }
                fn is_finite(&self) -> bool {
                    J::all_finite(self)
                }
                fn try_sqrt(self) -> Option<Self> {
                    if J::value(&self) >= 0.0 {
                        Some(simba::scalar::ComplexField::sqrt(self))
                    } else {
                        None
                    }
                }
            }

            impl<$($g)*> simba::scalar::RealField for $T {
                fn is_sign_positive(&self) -> bool {
                    J::value(self).is_sign_positive()
                }
                fn is_sign_negative(&self) -> bool {
                    J::value(self).is_sign_negative()
                }
                fn copysign(self, sign: Self) -> Self {
                    if J::value(&self).is_sign_negative() == J::value(&sign).is_sign_negative() {
                        self
                    } else {
                        -self
                    }
                }
                fn max(self, o: Self) -> Self {
                    if J::value(&self) >= J::value(&o) {
                        self
                    } else {
                        o
                    }
                }
                fn min(self, o: Self) -> Self {
                    if J::value(&self) <= J::value(&o) {
                        self
                    } else {
                        o
                    }
                }
                fn clamp(self, lo: Self, hi: Self) -> Self {
                    simba::scalar::RealField::min(simba::scalar::RealField::max(self, lo), hi)
                }
                fn atan2(self, x: Self) -> Self {
                    // atan2(y, x) equals atan(y/x) or π/2·sign − atan(x/y) up to a locally
                    // constant branch; take the well-conditioned one for the derivatives.
                    let (yv, xv) = (J::value(&self), J::value(&x));
                    let local = if xv.abs() >= yv.abs() {
                        simba::scalar::ComplexField::atan(J::div(self, x))
                    } else {
                        -simba::scalar::ComplexField::atan(J::div(x, self))
                    };
                    local.with_value(yv.atan2(xv))
                }
                fn min_value() -> Option<Self> {
                    Some(J::constant(f64::MIN))
                }
                fn max_value() -> Option<Self> {
                    Some(J::constant(f64::MAX))
                }
                fn pi() -> Self {
                    J::constant(core::f64::consts::PI)
                }
                fn two_pi() -> Self {
                    J::constant(core::f64::consts::TAU)
                }
                fn frac_pi_2() -> Self {
                    J::constant(core::f64::consts::FRAC_PI_2)
                }
                fn frac_pi_3() -> Self {
                    J::constant(core::f64::consts::FRAC_PI_3)
                }
                fn frac_pi_4() -> Self {
                    J::constant(core::f64::consts::FRAC_PI_4)
                }
                fn frac_pi_6() -> Self {
                    J::constant(core::f64::consts::FRAC_PI_6)
                }
                fn frac_pi_8() -> Self {
                    J::constant(core::f64::consts::FRAC_PI_8)
                }
                fn frac_1_pi() -> Self {
                    J::constant(core::f64::consts::FRAC_1_PI)
                }
                fn frac_2_pi() -> Self {
                    J::constant(core::f64::consts::FRAC_2_PI)
                }
                fn frac_2_sqrt_pi() -> Self {
                    J::constant(core::f64::consts::FRAC_2_SQRT_PI)
                }
                fn e() -> Self {
                    J::constant(core::f64::consts::E)
                }
                fn log2_e() -> Self {
                    J::constant(core::f64::consts::LOG2_E)
                }
                fn log10_e() -> Self {
                    J::constant(core::f64::consts::LOG10_E)
                }
                fn ln_2() -> Self {
                    J::constant(core::f64::consts::LN_2)
                }
                fn ln_10() -> Self {
                    J::constant(core::f64::consts::LN_10)
                }
            }

            impl<$($g)*> $crate::Scalar for $T {
                #[inline(always)]
                fn constant(x: f64) -> Self {
                    J::constant(x)
                }
                #[inline(always)]
                fn value(&self) -> f64 {
                    J::value(self)
                }
                #[inline(always)]
                fn chain_rule(self, f: [f64; 5]) -> Self {
                    J::chain4(self, f[0], f[1], f[2], f[3], f[4])
                }
                #[inline(always)]
                fn is_constant_number(&self) -> bool {
                    J::is_constant(self)
                }
            }
        };
    };
}
