//! The elementary functions of one argument that a `#[lagrangian]` body may call, one row each,
//! in one table ([`with_functions!`]). Every consumer reads its rows, so a function is added by
//! adding a row here and nowhere else:
//! - the macro's symbolic mode: the method a body calls, the tangent rule d f(a) =
//!   [`tangent`]`(f, a, f(a), da)` (differentiation, the Taylor series), the value on an `f64`
//!   (constant folding) and the names in printed equations ([`Row`]);
//! - the runtime's jets: the first three derivatives at a point ([`jets`]), written for accuracy
//!   (sech² as 1/cosh², not 1 − tanh²), which the chain rule of every jet type takes;
//! - the runtime's kernel number trait `Real` (an `f64` and SIMD lanes): one method per row.
//!
//! A row reads: `Variant method "unicode" "latex" real = yes|no jets = yes|no`, then
//! `tangent(x, y, dx, k) = …;` (generic over [`Calc`]: x the argument, y = f(x), dx the argument's
//! tangent, `k(c)` the constant c) and `jets(x, y) = […];` (f′(x), f″(x), f‴(x) as `f64`).
//! `real = no` marks a function whose `Real` method is written by hand (sin and cos share one
//! vector computation in lanes), `jets = no` one whose jets method is not a smooth chain rule
//! (|x|, sgn x: `num_traits::Signed`). The unit step H is the switch of `max`, `min`, `clamp` and
//! of |x|'s slope: a row for the symbolic mode, not a method a body calls.
//!
//! ```
//! use lagrange_functions::{jets, tangent, Fun};
//! assert_eq!(Fun::from_method("tanh"), Some(Fun::Tanh));
//! // d tan = (1 + tan²) dx; its jets at 0: (1, 0, 2).
//! assert_eq!(tangent(Fun::Tan, 0.5_f64, 0.5_f64.tan(), 1.0, &|c| c), 1.0 + 0.5_f64.tan().powi(2));
//! assert_eq!(jets::tan(0.0, 0.0), [1.0, 0.0, 2.0]);
//! ```
#![forbid(unsafe_code)]

use core::f64::consts::{LN_2, LOG10_E, LOG2_E};
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Calls `$callback! { $($args)* rows… }` with every row of the table (the grammar is in the
/// crate's docs): the runtime generates its `Real` methods and its jets' methods from it.
#[macro_export]
macro_rules! with_functions {
    ($callback:ident $($args:tt)*) => {
        $callback! { $($args)*
            Sqrt sqrt "√" "\\sqrt" real = yes jets = yes
                tangent(x, y, dx, k) = dx / (k(2.0) * y);
                jets(x, y) = {
                    let d = 0.5 / y;
                    [d, -0.5 * d / x, 0.75 * d / (x * x)]
                };
            Sin sin "sin" "\\sin" real = no jets = yes
                tangent(x, y, dx, k) = x.cos() * dx;
                jets(x, y) = {
                    let c = x.cos();
                    [c, -y, -c]
                };
            Cos cos "cos" "\\cos" real = no jets = yes
                tangent(x, y, dx, k) = -(x.sin() * dx);
                jets(x, y) = {
                    let s = x.sin();
                    [-s, -y, s]
                };
            Tan tan "tan" "\\tan" real = yes jets = yes
                tangent(x, y, dx, k) = (k(1.0) + y.powi(2)) * dx;
                jets(x, y) = {
                    let d = 1.0 + y * y;
                    [d, 2.0 * y * d, 2.0 * d * d + 4.0 * y * y * d]
                };
            Exp exp "exp" "\\exp" real = yes jets = yes
                tangent(x, y, dx, k) = y * dx;
                jets(x, y) = [y, y, y];
            Ln ln "ln" "\\ln" real = yes jets = yes
                tangent(x, y, dx, k) = dx / x;
                jets(x, y) = {
                    let r = 1.0 / x;
                    [r, -r * r, 2.0 * r * r * r]
                };
            // The jets' one-sided rule: slope +1 at ±0 (2 H(x) − 1, with H(−0) = 1).
            Abs abs "abs" "abs" real = yes jets = no
                tangent(x, y, dx, k) = (k(2.0) * x.step() - k(1.0)) * dx;
                jets(x, y) = [if x < 0.0 { -1.0 } else { 1.0 }, 0.0, 0.0];
            Asinh asinh "asinh" "\\operatorname{arsinh}" real = yes jets = yes
                tangent(x, y, dx, k) = dx / (k(1.0) + x.powi(2)).sqrt();
                jets(x, y) = {
                    let w = x * x + 1.0;
                    let d = 1.0 / w.sqrt();
                    [d, -x * d / w, d * (2.0 * x * x - 1.0) / (w * w)]
                };
            Acosh acosh "acosh" "\\operatorname{arcosh}" real = yes jets = yes
                tangent(x, y, dx, k) = dx / (x.powi(2) - k(1.0)).sqrt();
                jets(x, y) = {
                    let w = (x - 1.0) * (x + 1.0);
                    let d = 1.0 / w.sqrt();
                    [d, -x * d / w, d * (2.0 * x * x + 1.0) / (w * w)]
                };
            Atanh atanh "atanh" "\\operatorname{artanh}" real = yes jets = yes
                tangent(x, y, dx, k) = dx / (k(1.0) - x.powi(2));
                jets(x, y) = {
                    let d = 1.0 / ((1.0 - x) * (1.0 + x));
                    [d, 2.0 * x * d * d, (2.0 + 6.0 * x * x) * d * d * d]
                };
            Exp2 exp2 "exp2" "2^" real = yes jets = yes
                tangent(x, y, dx, k) = k(LN_2) * y * dx;
                jets(x, y) = [LN_2 * y, LN_2 * LN_2 * y, LN_2 * LN_2 * LN_2 * y];
            // H(u) = 1 for u ≥ 0 (also −0), else 0: piecewise constant.
            Step step "H" "H" real = no jets = no
                tangent(x, y, dx, k) = k(0.0);
                jets(x, y) = [0.0, 0.0, 0.0];
            Cbrt cbrt "∛" "\\sqrt[3]" real = yes jets = yes
                tangent(x, y, dx, k) = y / (k(3.0) * x) * dx;
                jets(x, y) = {
                    let d = y / (3.0 * x);
                    [d, -2.0 * d / (3.0 * x), 10.0 * d / (9.0 * x * x)]
                };
            Ln1p ln_1p "ln1p" "\\operatorname{ln1p}" real = yes jets = yes
                tangent(x, y, dx, k) = dx / (k(1.0) + x);
                jets(x, y) = {
                    let r = 1.0 / (1.0 + x);
                    [r, -r * r, 2.0 * r * r * r]
                };
            ExpM1 exp_m1 "expm1" "\\operatorname{expm1}" real = yes jets = yes
                tangent(x, y, dx, k) = x.exp() * dx;
                jets(x, y) = {
                    let e = x.exp();
                    [e, e, e]
                };
            Log10 log10 "log₁₀" "\\log_{10}" real = yes jets = yes
                tangent(x, y, dx, k) = k(LOG10_E) * (dx / x);
                jets(x, y) = {
                    let r = 1.0 / x;
                    [LOG10_E * r, -LOG10_E * r * r, 2.0 * LOG10_E * r * r * r]
                };
            Log2 log2 "log₂" "\\log_2" real = yes jets = yes
                tangent(x, y, dx, k) = k(LOG2_E) * (dx / x);
                jets(x, y) = {
                    let r = 1.0 / x;
                    [LOG2_E * r, -LOG2_E * r * r, 2.0 * LOG2_E * r * r * r]
                };
            Signum signum "sgn" "\\operatorname{sgn}" real = yes jets = no
                tangent(x, y, dx, k) = k(0.0);
                jets(x, y) = [0.0, 0.0, 0.0];
            Asin asin "asin" "\\arcsin" real = yes jets = yes
                tangent(x, y, dx, k) = dx / (k(1.0) - x.powi(2)).sqrt();
                jets(x, y) = {
                    let w = (1.0 - x) * (1.0 + x);
                    let d = 1.0 / w.sqrt();
                    [d, x * d / w, d * (1.0 + 2.0 * x * x) / (w * w)]
                };
            Acos acos "acos" "\\arccos" real = yes jets = yes
                tangent(x, y, dx, k) = -(dx / (k(1.0) - x.powi(2)).sqrt());
                jets(x, y) = {
                    let w = (1.0 - x) * (1.0 + x);
                    let d = 1.0 / w.sqrt();
                    [-d, -x * d / w, -d * (1.0 + 2.0 * x * x) / (w * w)]
                };
            Atan atan "atan" "\\arctan" real = yes jets = yes
                tangent(x, y, dx, k) = dx / (k(1.0) + x.powi(2));
                jets(x, y) = {
                    let d = 1.0 / (1.0 + x * x);
                    [d, -2.0 * x * d * d, (6.0 * x * x - 2.0) * d * d * d]
                };
            Sinh sinh "sinh" "\\sinh" real = yes jets = yes
                tangent(x, y, dx, k) = x.cosh() * dx;
                jets(x, y) = {
                    let c = x.cosh();
                    [c, y, c]
                };
            Cosh cosh "cosh" "\\cosh" real = yes jets = yes
                tangent(x, y, dx, k) = x.sinh() * dx;
                jets(x, y) = {
                    let s = x.sinh();
                    [s, y, s]
                };
            // sech² = 1/cosh² in the jets, not 1 − tanh² (which cancels for large |x|).
            Tanh tanh "tanh" "\\tanh" real = yes jets = yes
                tangent(x, y, dx, k) = (k(1.0) - y.powi(2)) * dx;
                jets(x, y) = {
                    let c = x.cosh();
                    let d = 1.0 / (c * c);
                    [d, -2.0 * y * d, 4.0 * y * y * d - 2.0 * d * d]
                };
        }
    };
}

/// What a tangent rule computes with: an `f64`, or a node of the macro's expression graph.
pub trait Calc:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// √x.
    fn sqrt(self) -> Self;
    /// sin x.
    fn sin(self) -> Self;
    /// cos x.
    fn cos(self) -> Self;
    /// sinh x.
    fn sinh(self) -> Self;
    /// cosh x.
    fn cosh(self) -> Self;
    /// eˣ.
    fn exp(self) -> Self;
    /// xⁿ.
    fn powi(self, n: i32) -> Self;
    /// The unit step H(x): 1 for x ≥ 0 (−0 included), 0 below and for NaN.
    fn step(self) -> Self;
}

/// The `f64` instance (the tests evaluate rules with it).
impl Calc for f64 {
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn sin(self) -> Self {
        f64::sin(self)
    }
    fn cos(self) -> Self {
        f64::cos(self)
    }
    fn sinh(self) -> Self {
        f64::sinh(self)
    }
    fn cosh(self) -> Self {
        f64::cosh(self)
    }
    fn exp(self) -> Self {
        f64::exp(self)
    }
    fn powi(self, n: i32) -> Self {
        f64::powi(self, n)
    }
    fn step(self) -> Self {
        step(self)
    }
}

/// The unit step H(u): 1 for u ≥ 0 (−0 included), 0 below (and for NaN).
pub fn step(u: f64) -> f64 {
    if u >= 0.0 {
        1.0
    } else {
        0.0
    }
}

/// One elementary function's row (what the symbolic mode reads besides the rule).
#[derive(Debug)]
pub struct Row {
    /// The function.
    pub fun: Fun,
    /// The `f64` method a body calls and generated code emits (`"sin"`); empty for the step,
    /// which no body calls.
    pub method: &'static str,
    /// Its value on an `f64` (constant folding, and the tests' evaluation).
    pub eval: fn(f64) -> f64,
    /// The name in the printed equations (Unicode).
    pub unicode: &'static str,
    /// The name in the printed equations (LaTeX).
    pub latex: &'static str,
}

macro_rules! define {
    ($( $(#[$meta:meta])* $variant:ident $method:ident $unicode:literal $latex:literal
        real = $real:ident jets = $jets:ident
        tangent($x:ident, $y:ident, $dx:ident, $k:ident) = $tangent:expr;
        jets($jx:ident, $jy:ident) = $jet:expr; )*) => {
        /// A smooth (or piecewise constant) elementary function of one argument.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Fun {
            $(
                #[doc = concat!("`", stringify!($method), "`")]
                $variant,
            )*
        }

        /// Every function's row, in the order of [`Fun`].
        pub const TABLE: &[Row] = &[$(Row {
            fun: Fun::$variant,
            method: method_name(stringify!($method)),
            eval: f64_value::$method,
            unicode: $unicode,
            latex: $latex,
        },)*];

        /// The tangent of y = f(x) given x's tangent `dx`: f′(x) dx, built from `Calc`'s operations
        /// (`k(c)` makes the constant c). The symbolic mode builds its graph with it.
        #[allow(unused_variables)]
        pub fn tangent<T: Calc>(f: Fun, x: T, y: T, dx: T, k: &dyn Fn(f64) -> T) -> T {
            match f {
                $(Fun::$variant => {
                    let ($x, $y, $dx, $k) = (x, y, dx, k);
                    $tangent
                })*
            }
        }

        /// f′(x), f″(x), f‴(x) of each function at x, given y = f(x): what the jets' chain rule
        /// takes.
        pub mod jets {
            #[allow(unused_imports)]
            use core::f64::consts::{LN_2, LOG10_E, LOG2_E};
            $(
                #[doc = concat!("The derivatives of `", stringify!($method), "`.")]
                #[inline(always)]
                #[allow(unused_variables)]
                pub fn $method($jx: f64, $jy: f64) -> [f64; 3] {
                    $jet
                }
            )*
        }

        /// Each function's value on an `f64`.
        mod f64_value {
            $(
                pub fn $method(x: f64) -> f64 {
                    value!($method, x)
                }
            )*
        }
    };
}

/// The value of a row's function on an `f64`: its method (the step has no `f64` method).
macro_rules! value {
    (step, $x:ident) => {
        crate::step($x)
    };
    ($method:ident, $x:ident) => {
        f64::$method($x)
    };
}

/// The method a body calls: none for the step.
const fn method_name(name: &'static str) -> &'static str {
    if matches!(name.as_bytes(), b"step") {
        ""
    } else {
        name
    }
}

with_functions!(define);

impl Fun {
    /// This function's row of [`TABLE`].
    pub fn row(self) -> &'static Row {
        &TABLE[self as usize]
    }

    /// The function a method name calls (`"sin"` → `Sin`), if it is in the table.
    pub fn from_method(name: &str) -> Option<Fun> {
        TABLE
            .iter()
            .find(|r| !r.method.is_empty() && r.method == name)
            .map(|r| r.fun)
    }

    /// The Rust method name (empty for the step).
    pub fn method(self) -> &'static str {
        self.row().method
    }

    /// Evaluates the function on an `f64`.
    pub fn eval(self, x: f64) -> f64 {
        (self.row().eval)(x)
    }
}

#[cfg(test)]
mod tests;
