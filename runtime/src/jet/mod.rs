//! Forward-mode jets: number types that carry the derivatives the Euler–Lagrange equations need.
//!
//! The calculus is written once, in the [`JetCalculus`] primitives each jet type provides (chain
//! rule through `chain`, product rule through `mul`); every operator, the elementary functions and
//! the `nalgebra::RealField` impl are generated from those by `impl_jet_scalar!`.
//!
//! - [`ElJet`]: from one evaluation of L, ∂L/∂q, ∂L/∂q̇, the mass matrix ∂²L/∂q̇∂q̇ and the
//!   directional derivative of ∂L/∂q̇ along (q̇, 0, 1) in (q, q̇, t).
//! - [`HessianJet`]: the gradient and the full Hessian in (q, q̇), for implicit integrators.
//! - [`ColumnJet`]: the gradient and one column of the Hessian, from which large systems
//!   assemble the Hessian (2N evaluations, each O(N) numbers: see [`HESSIAN_BY_COLUMNS_ABOVE`]).
//! - [`LinJet`]: the gradient and Hessian in (q, q̇) and their derivative along one direction in
//!   (q, q̇, t) (third derivatives contracted with that direction), for the linearization about a
//!   steady motion; [`LinColumnJet`], one column of it, for large systems.
//! - [`ConstraintJet`]: the gradient of a holonomic constraint g(q, t) and its first and second
//!   derivatives along the motion, for the constraint rows.

#[macro_use]
mod scalar_impl;
mod column;
mod constraint;
mod el;
mod hessian;
mod lin;
mod lin_column;
mod timed;

pub use column::{ColumnJet, HESSIAN_BY_COLUMNS_ABOVE};
pub use constraint::ConstraintJet;
pub use el::{EL_BY_COLUMNS_ABOVE, ElJet};
pub use hessian::HessianJet;
pub use lin::LinJet;
pub use lin_column::LinColumnJet;
pub use timed::{Timed, timed_state};

/// Runs `f`, an evaluation of L (or of the constraints) in jets of `jet_bytes` bytes each over
/// `n` coordinates, where the stack has room for it: on the caller's stack when enough of it is
/// left, else on a segment of twice the estimate (stacker's, on the same thread). The estimate is
/// 16 copies of the 2N seeded numbers (the seeds, the body's bindings of `Coords<N>` and the
/// temporaries a body keeps) plus 256 KiB: a 64-link chain's linearization by columns took a
/// 1.5 MB frame on a 2 MiB thread.
///
/// ```
/// use lagrange_runtime::jet::with_jet_stack;
/// assert_eq!(with_jet_stack(64, 4128, || [1.0_f64; 100_000].iter().sum::<f64>()), 1e5);
/// ```
pub fn with_jet_stack<R>(n: usize, jet_bytes: usize, f: impl FnOnce() -> R) -> R {
    let need = 16usize
        .saturating_mul(2 * n)
        .saturating_mul(jet_bytes)
        .saturating_add(256 << 10);
    // `f` in a frame of its own: inlined into this one, its jets would be reserved on the
    // caller's stack on entry, before the test of the room left (a 64-coordinate evaluation
    // overflowed a 2 MiB thread with the segment never entered).
    stacker::maybe_grow(need, need.saturating_mul(2), || own_frame(f))
}

/// Calls `f` in a frame that is not the caller's (see [`with_jet_stack`]).
#[inline(never)]
fn own_frame<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// The jets carry derivatives in (q, q̇), not a rate along the motion: their `velocity` is NaN
/// (a body that reads rates is evaluated in [`Timed`] jets).
macro_rules! no_rate {
    ($($T:ident),*) => {$(
        impl<const N: usize> crate::scalar::Velocity for $T<N> {
            #[inline(always)]
            fn velocity(&self) -> Self {
                crate::scalar::note_unseen_rate();
                JetCalculus::constant(f64::NAN)
            }
        }
    )*};
}
no_rate!(
    ColumnJet,
    ConstraintJet,
    ElJet,
    HessianJet,
    LinJet,
    LinColumnJet
);

/// The calculus primitives a jet type provides; everything else is generated from them.
///
/// ```
/// use lagrange_runtime::jet::{ElJet, JetCalculus};
/// let x = <ElJet<1> as JetCalculus>::constant(2.0);
/// assert_eq!(x.mul(x).value(), 4.0);
/// ```
pub trait JetCalculus: Copy {
    /// A constant: value `x`, every derivative zero.
    fn constant(x: f64) -> Self;
    /// The value part.
    fn value(&self) -> f64;
    /// Replaces the value part, keeping the derivatives (used where a function's value and its
    /// local derivative formula differ by a constant branch, as in `atan2`).
    fn with_value(self, v: f64) -> Self;
    /// Chain rule: `f(self)` from `f`, `f'` and `f''` at the value of `self`.
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self;
    /// Chain rule with the third derivative `f'''` as well, for jets that carry a derivative of
    /// their Hessian ([`LinJet`]); the default ignores `f3` and is [`chain`](Self::chain), so the
    /// second-order jets compute exactly what they computed before.
    ///
    /// ```
    /// use lagrange_runtime::jet::{JetCalculus, LinJet};
    /// // sin at q = 0 along δq = 1: (sin)‴(0) = −1
    /// let (q, _, _) = LinJet::<1>::seed(&[0.0], &[0.0], 0.0, &[1.0], &[0.0], 0.0);
    /// assert_eq!(q[0].chain3(0.0, 1.0, 0.0, -1.0).along().hess_qq(), [[-1.0]]);
    /// ```
    #[inline(always)]
    fn chain3(self, f0: f64, f1: f64, f2: f64, f3: f64) -> Self {
        let _ = f3;
        self.chain(f0, f1, f2)
    }
    /// Chain rule with the fourth derivative `f⁗` as well: a number that carries a time
    /// derivative ([`Timed`]) needs the jet of f′(x), which takes f′…f⁗; the jets themselves
    /// ignore `f4` (the default is [`chain3`](Self::chain3)).
    ///
    /// ```
    /// use lagrange_runtime::jet::{JetCalculus, Timed};
    /// // sin along a rate: d/dt sin(x) = cos(x) ẋ
    /// let x = Timed::new(0.0_f64, 2.0);
    /// let y = x.chain4(0.0, 1.0, 0.0, -1.0, 0.0);
    /// assert_eq!((y.value(), y.rate()), (0.0, 2.0));
    /// ```
    #[inline(always)]
    fn chain4(self, f0: f64, f1: f64, f2: f64, f3: f64, f4: f64) -> Self {
        let _ = f4;
        self.chain3(f0, f1, f2, f3)
    }
    /// The elementary function `f` of the function table at `self`, given its value `y` and
    /// f′, f″, f‴ there (the table's `jets` row): the chain rule for the jets (the default);
    /// [`Timed`] takes the rate from the table's exact tangent rule instead.
    #[inline(always)]
    fn function(self, f: lagrange_functions::Fun, y: f64, d: [f64; 3]) -> Self {
        let _ = f;
        self.chain3(y, d[0], d[1], d[2])
    }
    /// Sum rule.
    fn add(self, other: Self) -> Self;
    /// Difference.
    fn sub(self, other: Self) -> Self;
    /// Product rule.
    fn mul(self, other: Self) -> Self;
    /// Multiplication by a constant.
    fn scale(self, c: f64) -> Self;
    /// Addition of a constant.
    fn add_f64(self, c: f64) -> Self;
    /// Whether the value and every derivative part are finite.
    fn all_finite(&self) -> bool;
    /// Whether every derivative part is zero.
    fn is_constant(&self) -> bool;

    /// Reciprocal, through the chain rule.
    #[inline(always)]
    fn recip_jet(self) -> Self {
        let x = self.value();
        let r = 1.0 / x;
        let r2 = r * r;
        self.chain4(r, -r2, 2.0 * r2 * r, -6.0 * r2 * r2, 24.0 * r2 * r2 * r)
    }
    /// Quotient, as product with the reciprocal.
    #[inline(always)]
    fn div(self, other: Self) -> Self {
        self.mul(other.recip_jet())
    }
}

#[cfg(test)]
mod tests;
