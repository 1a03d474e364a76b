//! The [`Scalar`] trait: the number type a Lagrangian body computes in.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Sub, SubAssign};

use nalgebra::{RealField, Vector3};

/// The number type a Lagrangian is evaluated in: `f64`, or one of the jets that carry derivatives.
///
/// Every `Scalar` is a [`nalgebra::RealField`], so the elementary functions (`sin`, `cos`, `tan`,
/// `sin_cos`, `exp`, `ln`, `sqrt`, `powi`, `powf`, `abs`, `atan2`, `asin`, `acos`, `atan`, `sinh`,
/// `cosh`, `tanh`, ...) and nalgebra's generic code (`Vector3<S>` with `dot`, `cross`,
/// `norm_squared`, `norm`, rotations, matrices) work with it. On top of that a `Scalar` mixes with
/// `f64` on its right-hand side (`x * 2.0`, `x - 1.0`) and multiplies a `Vector3<Self>` from the
/// left (`x * v`).
///
/// ```
/// use lagrange_runtime::Scalar;
/// fn kinetic<S: Scalar>(m: f64, v: S) -> S { v * v * (m / 2.0) }
/// assert_eq!(kinetic(2.0, 3.0_f64), 9.0);
/// ```
pub trait Scalar:
    RealField
    + Copy
    + Debug
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + AddAssign<f64>
    + SubAssign<f64>
    + MulAssign<f64>
    + DivAssign<f64>
    + Mul<Vector3<Self>, Output = Vector3<Self>>
    + From<f64>
    + core::iter::Sum
    + for<'a> core::iter::Sum<&'a Self>
    + core::iter::Product
    + for<'a> core::iter::Product<&'a Self>
    + Velocity
{
    /// The constant `x` in this number type (all derivative parts zero).
    ///
    /// ```
    /// use lagrange_runtime::Scalar;
    /// assert_eq!(<f64 as Scalar>::constant(1.5), 1.5);
    /// ```
    fn constant(x: f64) -> Self;

    /// The value part (the number itself, without derivatives).
    ///
    /// ```
    /// use lagrange_runtime::Scalar;
    /// assert_eq!(Scalar::value(&2.5_f64), 2.5);
    /// ```
    fn value(&self) -> f64;

    /// The chain rule with f(x), f′(x), f″(x), f‴(x), f⁗(x) at the value of `self` (what
    /// [`Timed`](crate::jet::Timed) builds its rate from; the jets use up to f‴, `f64` only f).
    #[doc(hidden)]
    fn chain_rule(self, f: [f64; 5]) -> Self;

    /// Whether every derivative part is zero (a constant in this number type).
    #[doc(hidden)]
    fn is_constant_number(&self) -> bool;
}

/// The total time derivative d/dt x(q, t) = Σ ∂x/∂qᵢ q̇ᵢ + ∂x/∂t of a value computed from the
/// coordinates and time: what [`velocity`](crate::geometry::velocity) returns.
///
/// Inside a `#[lagrangian]` body that names `velocity` or an angular velocity, the macro
/// evaluates the body in numbers that carry their rate ([`Timed`](crate::jet::Timed)); elsewhere
/// (an `f64`, a jet) there is no rate to read and the result is NaN.
///
/// ```
/// use lagrange_runtime::{jet::Timed, Velocity};
/// let x = Timed::new(2.0_f64, 0.5); // x = 2 moving at 0.5
/// assert_eq!((x * x).velocity().value(), 2.0); // d(x²)/dt = 2 x ẋ
/// assert!(1.0_f64.velocity().is_nan());
/// ```
#[diagnostic::on_unimplemented(
    message = "`velocity` takes a `Scalar` or a `Vector3<Scalar>`, not `{Self}`",
    label = "for a `Rotation`, use `angular_velocity(&r)` or `body_angular_velocity(&r)`"
)]
pub trait Velocity: Sized {
    /// d/dt of `self` along the motion (NaN where the number carries no rate).
    fn velocity(&self) -> Self;
}

impl Velocity for f64 {
    #[inline(always)]
    fn velocity(&self) -> Self {
        note_unseen_rate();
        f64::NAN
    }
}

std::thread_local! {
    /// Whether a number without a rate was asked for its `velocity` since the last
    /// [`take_unseen_rate`] on this thread.
    static UNSEEN_RATE: core::cell::Cell<bool> = const { core::cell::Cell::new(false) };
}

/// Notes that `velocity()` was read from a number that carries no rate (it returns NaN): a
/// helper outside the `#[lagrangian]` impl reads a rate the macro did not see, so the body was
/// not evaluated in the jets that carry rates. [`Lagrangian::accelerations`](crate::Lagrangian::accelerations)
/// turns it into an error that names `velocity` (a NaN that `min` or `max` swallowed would
/// otherwise give a wrong q̈ silently).
#[inline(never)]
#[cold]
pub(crate) fn note_unseen_rate() {
    UNSEEN_RATE.with(|c| c.set(true));
}

/// Whether a rate was read unseen since the last call (and clears the note).
pub(crate) fn take_unseen_rate() -> bool {
    UNSEEN_RATE.with(|c| c.replace(false))
}

impl<S: Scalar> Velocity for Vector3<S> {
    #[inline(always)]
    fn velocity(&self) -> Self {
        self.map(|x| x.velocity())
    }
}

impl Scalar for f64 {
    #[inline(always)]
    fn constant(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn value(&self) -> f64 {
        *self
    }
    #[inline(always)]
    fn chain_rule(self, f: [f64; 5]) -> Self {
        f[0]
    }
    #[inline(always)]
    fn is_constant_number(&self) -> bool {
        true
    }
}
