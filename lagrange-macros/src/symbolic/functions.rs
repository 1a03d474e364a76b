//! The elementary functions of one argument, one row each: the method name the body calls (and
//! the generated code calls), its value (constant folding), its derivative rule, and its names
//! for people (Unicode and LaTeX). Lowering, differentiation, code generation, evaluation and
//! printing all read this table; adding a function is adding a row.

/// A node id of the expression graph.
pub type Id = u32;

/// The id of the constant 0 in every graph.
pub const ZERO: Id = 0;
/// The id of the constant 1 in every graph.
pub const ONE: Id = 1;

/// The graph operations a derivative rule builds its result with (the DAG provides them): the
/// table needs nothing else of the graph, so it does not depend on it.
pub trait Build {
    /// The constant c.
    fn constant(&mut self, c: f64) -> Id;
    /// a + b.
    fn add(&mut self, a: Id, b: Id) -> Id;
    /// a − b.
    fn sub(&mut self, a: Id, b: Id) -> Id;
    /// a · b.
    fn mul(&mut self, a: Id, b: Id) -> Id;
    /// a / b.
    fn div(&mut self, a: Id, b: Id) -> Id;
    /// −a.
    fn neg(&mut self, a: Id) -> Id;
    /// aⁿ.
    fn powi(&mut self, a: Id, n: i32) -> Id;
    /// f(a).
    fn un(&mut self, f: Fun, a: Id) -> Id;
}

/// One elementary function.
pub struct Row {
    /// The function.
    pub fun: Fun,
    /// The `f64` method (`x.sin()`): what lowering recognizes and code generation emits.
    pub method: &'static str,
    /// Its value on an `f64` (constant folding, and the tests' evaluation).
    pub eval: fn(f64) -> f64,
    /// d f(a) = `derivative(dag, f(a), a, da)`: the node of f(a), its argument and the
    /// argument's tangent.
    pub derivative: fn(&mut dyn Build, Id, Id, Id) -> Id,
    /// The name in the printed equations (Unicode).
    pub unicode: &'static str,
    /// The name in the printed equations (LaTeX).
    pub latex: &'static str,
}

macro_rules! functions {
    ($( $variant:ident: $method:literal, $unicode:literal, $latex:literal, $eval:expr,
        $derivative:expr; )*) => {
        /// A smooth elementary function of one argument (see [`TABLE`]).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Fun {
            $(
                #[doc = concat!("`", $method, "`")]
                $variant,
            )*
        }

        /// Every function, in the order of [`Fun`].
        pub const TABLE: &[Row] = &[$(Row {
            fun: Fun::$variant,
            method: $method,
            eval: $eval,
            derivative: $derivative,
            unicode: $unicode,
            latex: $latex,
        },)*];
    };
}

functions! {
    Sqrt: "sqrt", "√", "\\sqrt", f64::sqrt, |d, y, _, da| {
        let two = d.constant(2.0);
        let den = d.mul(two, y);
        d.div(da, den)
    };
    Sin: "sin", "sin", "\\sin", f64::sin, |d, _, a, da| {
        let c = d.un(Fun::Cos, a);
        d.mul(c, da)
    };
    Cos: "cos", "cos", "\\cos", f64::cos, |d, _, a, da| {
        let s = d.un(Fun::Sin, a);
        let m = d.mul(s, da);
        d.neg(m)
    };
    Tan: "tan", "tan", "\\tan", f64::tan, |d, y, _, da| {
        let r2 = d.powi(y, 2);
        let k = d.add(ONE, r2);
        d.mul(k, da)
    };
    Exp: "exp", "exp", "\\exp", f64::exp, |d, y, _, da| d.mul(y, da);
    Ln: "ln", "ln", "\\ln", f64::ln, |d, _, a, da| d.div(da, a);
    Abs: "abs", "abs", "abs", f64::abs, |d, _, a, da| {
        // The jets' one-sided rule: slope +1 at ±0 (2 H(a) − 1, with H(−0) = 1).
        let h = d.un(Fun::Step, a);
        let two = d.constant(2.0);
        let h2 = d.mul(two, h);
        let s = d.sub(h2, ONE);
        d.mul(s, da)
    };
    Asinh: "asinh", "asinh", "\\operatorname{arsinh}", f64::asinh, |d, _, a, da| {
        let a2 = d.powi(a, 2);
        let w = d.add(ONE, a2);
        let r = d.un(Fun::Sqrt, w);
        d.div(da, r)
    };
    Acosh: "acosh", "acosh", "\\operatorname{arcosh}", f64::acosh, |d, _, a, da| {
        let a2 = d.powi(a, 2);
        let w = d.sub(a2, ONE);
        let r = d.un(Fun::Sqrt, w);
        d.div(da, r)
    };
    Atanh: "atanh", "atanh", "\\operatorname{artanh}", f64::atanh, |d, _, a, da| {
        let a2 = d.powi(a, 2);
        let w = d.sub(ONE, a2);
        d.div(da, w)
    };
    Exp2: "exp2", "exp2", "2^", f64::exp2, |d, y, _, da| {
        let k = d.constant(std::f64::consts::LN_2);
        let ky = d.mul(k, y);
        d.mul(ky, da)
    };
    // H(u) = 1 for u ≥ 0 (also −0), else 0: the switch of `max`, `min`, `clamp` and of |u|'s slope.
    // Not a method a body can call (the empty name matches no identifier); emitted as an `if`.
    Step: "", "H", "H", step, |_, _, _, _| ZERO;
    Cbrt: "cbrt", "∛", "\\sqrt[3]", f64::cbrt, |d, y, a, da| {
        let three = d.constant(3.0);
        let den = d.mul(three, a);
        let k = d.div(y, den);
        d.mul(k, da)
    };
    Ln1p: "ln_1p", "ln1p", "\\operatorname{ln1p}", f64::ln_1p, |d, _, a, da| {
        let w = d.add(ONE, a);
        d.div(da, w)
    };
    ExpM1: "exp_m1", "expm1", "\\operatorname{expm1}", f64::exp_m1, |d, _, a, da| {
        let e = d.un(Fun::Exp, a);
        d.mul(e, da)
    };
    Log10: "log10", "log₁₀", "\\log_{10}", f64::log10, |d, _, a, da| {
        let k = d.constant(std::f64::consts::LOG10_E);
        let r = d.div(da, a);
        d.mul(k, r)
    };
    Log2: "log2", "log₂", "\\log_2", f64::log2, |d, _, a, da| {
        let k = d.constant(std::f64::consts::LOG2_E);
        let r = d.div(da, a);
        d.mul(k, r)
    };
    Signum: "signum", "sgn", "\\operatorname{sgn}", f64::signum, |_, _, _, _| ZERO;
    Asin: "asin", "asin", "\\arcsin", f64::asin, |d, _, a, da| {
        let a2 = d.powi(a, 2);
        let w = d.sub(ONE, a2);
        let r = d.un(Fun::Sqrt, w);
        d.div(da, r)
    };
    Acos: "acos", "acos", "\\arccos", f64::acos, |d, _, a, da| {
        let a2 = d.powi(a, 2);
        let w = d.sub(ONE, a2);
        let r = d.un(Fun::Sqrt, w);
        let k = d.div(da, r);
        d.neg(k)
    };
    Atan: "atan", "atan", "\\arctan", f64::atan, |d, _, a, da| {
        let a2 = d.powi(a, 2);
        let w = d.add(ONE, a2);
        d.div(da, w)
    };
    Sinh: "sinh", "sinh", "\\sinh", f64::sinh, |d, _, a, da| {
        let c = d.un(Fun::Cosh, a);
        d.mul(c, da)
    };
    Cosh: "cosh", "cosh", "\\cosh", f64::cosh, |d, _, a, da| {
        let s = d.un(Fun::Sinh, a);
        d.mul(s, da)
    };
    Tanh: "tanh", "tanh", "\\tanh", f64::tanh, |d, y, _, da| {
        let r2 = d.powi(y, 2);
        let k = d.sub(ONE, r2);
        d.mul(k, da)
    };
}

/// The unit step H(u): 1 for u ≥ 0 (−0 included), 0 below (and for NaN).
fn step(u: f64) -> f64 {
    if u >= 0.0 {
        1.0
    } else {
        0.0
    }
}

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

    /// The Rust method name.
    pub fn method(self) -> &'static str {
        self.row().method
    }

    /// Evaluates the function on an `f64`.
    pub fn eval(self, x: f64) -> f64 {
        (self.row().eval)(x)
    }

    /// The tangent of `y = f(a)` given the tangent `da` of `a`.
    pub fn derivative(self, dag: &mut dyn Build, y: Id, a: Id, da: Id) -> Id {
        (self.row().derivative)(dag, y, a, da)
    }
}
