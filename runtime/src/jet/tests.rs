//! Verification of the jets against independent values.
//!
//! 1. **Analytic.** Every elementary function and operator, applied to composite seeds
//!    u = α(q₀q̇₁ + q̇₀² + q₁t) + β and w = γ(q₁q̇₀ + q̇₁² + q̇₀t) + δ, against the chain rule written
//!    out densely in the five variables (q₀, q₁, q̇₀, q̇₁, t) with f, f′, f″ (and the partials of
//!    binary functions) typed in from calculus tables. The states and the seed coefficients are
//!    dyadic rationals, so u and w and their derivatives are exact in both computations and the only
//!    rounding is in f and the chain rule. Tolerance: 1e-14 relative to the sum of the absolute
//!    values of the terms of each reference entry (so cancellation cannot hide or fake an error).
//! 2. **Property tests.** Random expression trees in q, q̇, t and constants against central finite
//!    differences of the `f64` evaluation, and `ElJet` against `HessianJet` (time made a coordinate
//!    with velocity 1 so that ∂²/∂q̇∂t is available to the dense jet); random Lagrangians
//!    L = ½q̇ᵀA(q)q̇ + b(q,t)·q̇ − V(q,t) whose `accelerations` must solve the dense-jet equations.
//! 3. **Structural flags.** `ElJet` skips blocks by three flags; its results must be bitwise equal
//!    to the flag-free `HessianJet` for the blocks both compute with the same formulas.
#![allow(clippy::needless_range_loop)]

use nalgebra::{ComplexField, RealField};
use proptest::prelude::*;

use super::{ElJet, HessianJet};
use crate::{Lagrangian, Scalar};

// ---------------------------------------------------------------------------------------------
// 1. Analytic checks
// ---------------------------------------------------------------------------------------------

/// Number of variables of the dense reference: q₀, q₁, q̇₀, q̇₁, t.
const NV: usize = 5;
const IT: usize = 4;

/// A value with the magnitude of the terms that produced it (for a cancellation-aware tolerance).
#[derive(Clone, Copy, Debug, Default)]
struct Mg {
    x: f64,
    m: f64,
}
impl Mg {
    fn leaf(x: f64) -> Self {
        Mg { x, m: x.abs() }
    }
}
impl core::ops::Add for Mg {
    type Output = Mg;
    fn add(self, o: Mg) -> Mg {
        Mg {
            x: self.x + o.x,
            m: self.m + o.m,
        }
    }
}
impl core::ops::Mul for Mg {
    type Output = Mg;
    fn mul(self, o: Mg) -> Mg {
        Mg {
            x: self.x * o.x,
            m: self.m * o.m,
        }
    }
}

/// Dense second-order Taylor data in (q₀, q₁, q̇₀, q̇₁, t).
#[derive(Clone, Copy, Debug)]
struct Dense {
    v: f64,
    g: [Mg; NV],
    h: [[Mg; NV]; NV],
}

/// A state with dyadic coordinates (exact products).
#[derive(Clone, Copy, Debug)]
struct State {
    q: [f64; 2],
    v: [f64; 2],
    t: f64,
}

const STATES: [State; 2] = [
    State {
        q: [0.75, -0.375],
        v: [0.625, -1.25],
        t: 0.5,
    },
    State {
        q: [-1.5, 0.25],
        v: [-0.875, 0.5],
        t: -1.25,
    },
];

/// base_u = q₀q̇₁ + q̇₀² + q₁t, generic.
fn base_u<S: Scalar>(q: &[S], v: &[S], t: S) -> S {
    q[0] * v[1] + v[0] * v[0] + q[1] * t
}
/// base_w = q₁q̇₀ + q̇₁² + q̇₀t, generic.
fn base_w<S: Scalar>(q: &[S], v: &[S], t: S) -> S {
    q[1] * v[0] + v[1] * v[1] + v[0] * t
}

/// α·base_u + β as dense data, its derivatives typed in by hand.
fn dense_u(s: &State, alpha: f64, beta: f64) -> Dense {
    let [q0, q1] = s.q;
    let [v0, v1] = s.v;
    let t = s.t;
    let mut h = [[Mg::default(); NV]; NV];
    h[0][3] = Mg::leaf(alpha);
    h[3][0] = Mg::leaf(alpha);
    h[2][2] = Mg::leaf(2.0 * alpha);
    h[1][IT] = Mg::leaf(alpha);
    h[IT][1] = Mg::leaf(alpha);
    Dense {
        v: alpha * (q0 * v1 + v0 * v0 + q1 * t) + beta,
        g: [v1, t, 2.0 * v0, q0, q1].map(|x| Mg::leaf(alpha * x)),
        h,
    }
}
/// γ·base_w + δ as dense data, its derivatives typed in by hand.
fn dense_w(s: &State, gamma: f64, delta: f64) -> Dense {
    let [_q0, q1] = s.q;
    let [v0, v1] = s.v;
    let t = s.t;
    let mut h = [[Mg::default(); NV]; NV];
    h[1][2] = Mg::leaf(gamma);
    h[2][1] = Mg::leaf(gamma);
    h[3][3] = Mg::leaf(2.0 * gamma);
    h[2][IT] = Mg::leaf(gamma);
    h[IT][2] = Mg::leaf(gamma);
    Dense {
        v: gamma * (q1 * v0 + v1 * v1 + v0 * t) + delta,
        g: [0.0, v0, q1 + t, 2.0 * v1, v0].map(|x| Mg::leaf(gamma * x)),
        h,
    }
}

/// Partial derivatives of g(u, w) at a point: g, g_u, g_w, g_uu, g_uw, g_ww.
type Partials = (f64, f64, f64, f64, f64, f64);

/// The dense chain rule for g(u, w).
fn dense_apply(u: &Dense, w: &Dense, p: Partials) -> Dense {
    let (g, gu, gw, guu, guw, gww) = p;
    let (gu, gw, guu, guw, gww) = (
        Mg::leaf(gu),
        Mg::leaf(gw),
        Mg::leaf(guu),
        Mg::leaf(guw),
        Mg::leaf(gww),
    );
    let mut r = Dense {
        v: g,
        g: [Mg::default(); NV],
        h: [[Mg::default(); NV]; NV],
    };
    for x in 0..NV {
        r.g[x] = gu * u.g[x] + gw * w.g[x];
        for y in 0..NV {
            r.h[x][y] = guu * u.g[x] * u.g[y]
                + guw * (u.g[x] * w.g[y] + u.g[y] * w.g[x])
                + gww * w.g[x] * w.g[y]
                + gu * u.h[x][y]
                + gw * w.h[x][y];
        }
    }
    r
}

#[track_caller]
fn close(what: &str, got: f64, want: Mg, rel: f64) {
    let ok = if want.m == 0.0 {
        got == 0.0
    } else {
        (got - want.x).abs() <= rel * want.m
    };
    assert!(
        ok,
        "{what}: got {got:e}, want {:e} (terms {:e}), error {:e} relative to the terms",
        want.x,
        want.m,
        (got - want.x).abs() / want.m
    );
}

/// Checks every ElJet block against the dense reference.
fn check_el(tag: &str, s: &State, j: &ElJet<2>, r: &Dense, rel: f64) {
    close(&format!("{tag} value"), j.value(), Mg::leaf(r.v), rel);
    for i in 0..2 {
        close(&format!("{tag} grad_q[{i}]"), j.grad_q()[i], r.g[i], rel);
        close(
            &format!("{tag} grad_qdot[{i}]"),
            j.grad_qdot()[i],
            r.g[2 + i],
            rel,
        );
        for k in 0..2 {
            close(
                &format!("{tag} hess_qdot({i},{k})"),
                j.hess_qdot(i, k),
                r.h[2 + i][2 + k],
                rel,
            );
        }
        // mixed_i = Σ_j ∂²/∂q̇_i∂q_j q̇_j + ∂²/∂q̇_i∂t
        let mixed =
            r.h[2 + i][0] * Mg::leaf(s.v[0]) + r.h[2 + i][1] * Mg::leaf(s.v[1]) + r.h[2 + i][IT];
        close(&format!("{tag} mixed[{i}]"), j.mixed()[i], mixed, rel);
    }
    let dir = r.g[0] * Mg::leaf(s.v[0]) + r.g[1] * Mg::leaf(s.v[1]) + r.g[IT];
    close(&format!("{tag} directional"), j.directional(), dir, rel);
}

/// Checks every HessianJet block (q, q̇ only; t is a constant there) against the dense reference.
fn check_hess(tag: &str, j: &HessianJet<2>, r: &Dense, rel: f64) {
    close(&format!("{tag} value"), j.value(), Mg::leaf(r.v), rel);
    for i in 0..2 {
        close(&format!("{tag} grad_q[{i}]"), j.grad_q()[i], r.g[i], rel);
        close(
            &format!("{tag} grad_qdot[{i}]"),
            j.grad_qdot()[i],
            r.g[2 + i],
            rel,
        );
        for k in 0..2 {
            close(
                &format!("{tag} hess_qq[{i}][{k}]"),
                j.hess_qq()[i][k],
                r.h[i][k],
                rel,
            );
            close(
                &format!("{tag} hess_qqdot[{i}][{k}]"),
                j.hess_qqdot()[i][k],
                r.h[i][2 + k],
                rel,
            );
            close(
                &format!("{tag} hess_qdotqdot[{i}][{k}]"),
                j.hess_qdotqdot()[i][k],
                r.h[2 + i][2 + k],
                rel,
            );
        }
    }
}

/// The operation under test, applied to u (and w for binary ones).
#[derive(Clone, Copy, Debug)]
enum Op {
    Sin,
    Cos,
    Tan,
    SinCosSin,
    SinCosCos,
    Exp,
    Ln,
    Sqrt,
    Powi(i32),
    PowfConst(f64),
    PowfVar,
    Abs,
    Atan2,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Asinh,
    Acosh,
    Atanh,
    Recip,
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    AddAssign,
    SubAssign,
    MulAssign,
    DivAssign,
    JetPlusF(f64),
    FPlusJet(f64),
    JetMinusF(f64),
    FMinusJet(f64),
    JetTimesF(f64),
    FTimesJet(f64),
    JetOverF(f64),
    FOverJet(f64),
    AddAssignF(f64),
    SubAssignF(f64),
    MulAssignF(f64),
    DivAssignF(f64),
}

macro_rules! apply_for {
    ($name:ident, $T:ty) => {
        fn $name(op: Op, u: $T, w: $T) -> $T {
            match op {
                Op::Sin => u.sin(),
                Op::Cos => u.cos(),
                Op::Tan => u.tan(),
                Op::SinCosSin => u.sin_cos().0,
                Op::SinCosCos => u.sin_cos().1,
                Op::Exp => u.exp(),
                Op::Ln => u.ln(),
                Op::Sqrt => u.sqrt(),
                Op::Powi(n) => u.powi(n),
                Op::PowfConst(p) => u.powf(<$T>::from(p)),
                Op::PowfVar => u.powf(w),
                Op::Abs => ComplexField::abs(u),
                Op::Atan2 => u.atan2(w),
                Op::Asin => u.asin(),
                Op::Acos => u.acos(),
                Op::Atan => u.atan(),
                Op::Sinh => u.sinh(),
                Op::Cosh => u.cosh(),
                Op::Tanh => u.tanh(),
                Op::Asinh => u.asinh(),
                Op::Acosh => u.acosh(),
                Op::Atanh => u.atanh(),
                Op::Recip => u.recip(),
                Op::Neg => -u,
                Op::Add => u + w,
                Op::Sub => u - w,
                Op::Mul => u * w,
                Op::Div => u / w,
                Op::AddAssign => {
                    let mut x = u;
                    x += w;
                    x
                }
                Op::SubAssign => {
                    let mut x = u;
                    x -= w;
                    x
                }
                Op::MulAssign => {
                    let mut x = u;
                    x *= w;
                    x
                }
                Op::DivAssign => {
                    let mut x = u;
                    x /= w;
                    x
                }
                Op::JetPlusF(c) => u + c,
                Op::FPlusJet(c) => c + u,
                Op::JetMinusF(c) => u - c,
                Op::FMinusJet(c) => c - u,
                Op::JetTimesF(c) => u * c,
                Op::FTimesJet(c) => c * u,
                Op::JetOverF(c) => u / c,
                Op::FOverJet(c) => c / u,
                Op::AddAssignF(c) => {
                    let mut x = u;
                    x += c;
                    x
                }
                Op::SubAssignF(c) => {
                    let mut x = u;
                    x -= c;
                    x
                }
                Op::MulAssignF(c) => {
                    let mut x = u;
                    x *= c;
                    x
                }
                Op::DivAssignF(c) => {
                    let mut x = u;
                    x /= c;
                    x
                }
            }
        }
    };
}
apply_for!(apply_el, ElJet<2>);
apply_for!(apply_hess, HessianJet<2>);

/// f, f′, f″ (and the partials in w) from calculus tables, written independently of the jets.
fn partials(op: Op, u: f64, w: f64) -> Partials {
    let unary = |f: f64, f1: f64, f2: f64| (f, f1, 0.0, f2, 0.0, 0.0);
    match op {
        Op::Sin | Op::SinCosSin => unary(u.sin(), u.cos(), -u.sin()),
        Op::Cos | Op::SinCosCos => unary(u.cos(), -u.sin(), -u.cos()),
        Op::Tan => {
            let c = u.cos();
            unary(u.tan(), 1.0 / (c * c), 2.0 * u.sin() / (c * c * c))
        }
        Op::Exp => unary(u.exp(), u.exp(), u.exp()),
        Op::Ln => unary(u.ln(), 1.0 / u, -1.0 / (u * u)),
        Op::Sqrt => unary(u.sqrt(), 0.5 / u.sqrt(), -0.25 / (u * u.sqrt())),
        Op::Powi(n) => {
            let nf = f64::from(n);
            let d1 = if n == 0 { 0.0 } else { nf * u.powi(n - 1) };
            let d2 = if n == 0 || n == 1 {
                0.0
            } else {
                nf * (nf - 1.0) * u.powi(n - 2)
            };
            unary(u.powi(n), d1, d2)
        }
        Op::PowfConst(p) => unary(
            u.powf(p),
            p * u.powf(p - 1.0),
            p * (p - 1.0) * u.powf(p - 2.0),
        ),
        Op::PowfVar => {
            let (l, g) = (u.ln(), u.powf(w));
            (
                g,
                w * u.powf(w - 1.0),
                g * l,
                w * (w - 1.0) * u.powf(w - 2.0),
                u.powf(w - 1.0) * (1.0 + w * l),
                g * l * l,
            )
        }
        Op::Abs => unary(u.abs(), u.signum(), 0.0),
        Op::Atan2 => {
            let r2 = u * u + w * w;
            let r4 = r2 * r2;
            (
                u.atan2(w),
                w / r2,
                -u / r2,
                -2.0 * u * w / r4,
                (u * u - w * w) / r4,
                2.0 * u * w / r4,
            )
        }
        Op::Asin => {
            let s = (1.0 - u) * (1.0 + u);
            unary(u.asin(), 1.0 / s.sqrt(), u / (s * s.sqrt()))
        }
        Op::Acos => {
            let s = (1.0 - u) * (1.0 + u);
            unary(u.acos(), -1.0 / s.sqrt(), -u / (s * s.sqrt()))
        }
        Op::Atan => {
            let s = 1.0 + u * u;
            unary(u.atan(), 1.0 / s, -2.0 * u / (s * s))
        }
        Op::Sinh => unary(u.sinh(), u.cosh(), u.sinh()),
        Op::Cosh => unary(u.cosh(), u.sinh(), u.cosh()),
        Op::Tanh => {
            let c = u.cosh();
            unary(u.tanh(), 1.0 / (c * c), -2.0 * u.sinh() / (c * c * c))
        }
        Op::Asinh => {
            let s = 1.0 + u * u;
            unary(u.asinh(), 1.0 / s.sqrt(), -u / (s * s.sqrt()))
        }
        Op::Acosh => {
            let s = (u - 1.0) * (u + 1.0);
            unary(u.acosh(), 1.0 / s.sqrt(), -u / (s * s.sqrt()))
        }
        Op::Atanh => {
            let s = (1.0 - u) * (1.0 + u);
            unary(u.atanh(), 1.0 / s, 2.0 * u / (s * s))
        }
        Op::Recip => unary(1.0 / u, -1.0 / (u * u), 2.0 / (u * u * u)),
        Op::Neg => unary(-u, -1.0, 0.0),
        Op::Add | Op::AddAssign => (u + w, 1.0, 1.0, 0.0, 0.0, 0.0),
        Op::Sub | Op::SubAssign => (u - w, 1.0, -1.0, 0.0, 0.0, 0.0),
        Op::Mul | Op::MulAssign => (u * w, w, u, 0.0, 1.0, 0.0),
        Op::Div | Op::DivAssign => (
            u / w,
            1.0 / w,
            -u / (w * w),
            0.0,
            -1.0 / (w * w),
            2.0 * u / (w * w * w),
        ),
        Op::JetPlusF(c) | Op::FPlusJet(c) | Op::AddAssignF(c) => unary(u + c, 1.0, 0.0),
        Op::JetMinusF(c) | Op::SubAssignF(c) => unary(u - c, 1.0, 0.0),
        Op::FMinusJet(c) => unary(c - u, -1.0, 0.0),
        Op::JetTimesF(c) | Op::FTimesJet(c) | Op::MulAssignF(c) => unary(u * c, c, 0.0),
        Op::JetOverF(c) | Op::DivAssignF(c) => unary(u / c, 1.0 / c, 0.0),
        Op::FOverJet(c) => unary(c / u, -c / (u * u), 2.0 * c / (u * u * u)),
    }
}

/// One analytic case: `op` at u = `u_at`, w = `w_at` (both set through dyadic offsets), seeds
/// scaled by `alpha` and `gamma`.
fn run_case(op: Op, u_at: f64, w_at: f64, alpha: f64, gamma: f64) {
    for (si, s) in STATES.iter().enumerate() {
        let beta = u_at - alpha * base_u(&s.q, &s.v, s.t);
        let delta = w_at - gamma * base_w(&s.q, &s.v, s.t);
        let du = dense_u(s, alpha, beta);
        let dw = dense_w(s, gamma, delta);
        assert_eq!((du.v, dw.v), (u_at, w_at), "seeds must be exact");
        let want = dense_apply(&du, &dw, partials(op, u_at, w_at));
        let tag = format!("{op:?} at u={u_at}, w={w_at}, state {si}");

        let (q, v, t) = ElJet::<2>::seed(&s.q, &s.v, s.t);
        let u = base_u(&q, &v, t) * alpha + beta;
        let w = base_w(&q, &v, t) * gamma + delta;
        assert_eq!((u.value(), w.value()), (u_at, w_at));
        check_el(
            &format!("ElJet {tag}"),
            s,
            &apply_el(op, u, w),
            &want,
            1e-14,
        );

        let (q, v) = HessianJet::<2>::seed(&s.q, &s.v);
        let t = HessianJet::from(s.t);
        let u = base_u(&q, &v, t) * alpha + beta;
        let w = base_w(&q, &v, t) * gamma + delta;
        check_hess(
            &format!("HessianJet {tag}"),
            &apply_hess(op, u, w),
            &want,
            1e-14,
        );
    }
}

/// Unary case at several values of u, w irrelevant.
fn run_unary(op: Op, us: &[f64]) {
    for &u in us {
        for alpha in [0.5, -1.25] {
            run_case(op, u, 0.75, alpha, 0.5);
        }
    }
}

#[test]
fn trigonometric_functions_match_calculus_tables() {
    let us = [-1.125, -0.25, 0.4375, 1.3125];
    for op in [Op::Sin, Op::Cos, Op::Tan, Op::SinCosSin, Op::SinCosCos] {
        run_unary(op, &us);
    }
}

#[test]
fn exp_ln_sqrt_match_calculus_tables() {
    run_unary(Op::Exp, &[-2.5, 0.0, 0.875, 3.25]);
    run_unary(Op::Ln, &[0.0625, 0.875, 1.0, 7.5]);
    run_unary(Op::Sqrt, &[0.0625, 0.875, 1.0, 7.5]);
}

#[test]
fn powi_matches_calculus_tables_for_every_exponent_class() {
    let us = [-1.625, -0.375, 0.5, 2.25];
    for n in [0, 1, 2, 3, -1, -2, 5] {
        run_unary(Op::Powi(n), &us);
    }
}

#[test]
fn powf_with_constant_exponent_matches_calculus_tables() {
    for p in [2.5, -0.75, 1.0, 3.0, 0.5, 0.0] {
        run_unary(Op::PowfConst(p), &[0.375, 1.0, 2.75]);
    }
    // integer-valued constant exponents on a negative base
    for p in [2.0, 3.0, -1.0] {
        run_unary(Op::PowfConst(p), &[-1.5, -0.625]);
    }
}

#[test]
fn powf_with_variable_exponent_matches_calculus_tables() {
    for (u, w) in [(0.375, 1.5), (2.75, -0.625), (1.25, 2.0), (0.875, 0.0)] {
        for (alpha, gamma) in [(0.5, 0.25), (-0.25, 1.0)] {
            run_case(Op::PowfVar, u, w, alpha, gamma);
        }
    }
}

#[test]
fn abs_matches_calculus_tables_on_both_sides() {
    run_unary(Op::Abs, &[-2.5, -0.125, 0.375, 4.0]);
}

#[test]
fn atan2_matches_calculus_tables_in_all_quadrants_and_both_branches() {
    // (y, x): four quadrants, each with |x| > |y| and |x| < |y|, plus the axes.
    let points = [
        (0.5, 1.5),
        (1.5, 0.5),
        (0.5, -1.5),
        (1.5, -0.5),
        (-0.5, -1.5),
        (-1.5, -0.5),
        (-0.5, 1.5),
        (-1.5, 0.5),
        (1.0, 1.0),
        (0.0, 2.0),
        (2.0, 0.0),
        (0.0, -2.0),
        (-2.0, 0.0),
    ];
    for (y, x) in points {
        for (alpha, gamma) in [(0.5, 0.25), (-1.0, 0.75)] {
            run_case(Op::Atan2, y, x, alpha, gamma);
        }
    }
}

#[test]
fn inverse_trigonometric_functions_match_calculus_tables() {
    // includes 255/256, where 1 − u² computed as such would lose digits
    let inside = [-0.875, -0.25, 0.0, 0.4375, 0.9375, 0.99609375];
    run_unary(Op::Asin, &inside);
    run_unary(Op::Acos, &inside);
    run_unary(Op::Atanh, &inside);
    run_unary(Op::Asinh, &[-3.5, -0.25, 0.0, 0.4375, 6.0]);
    run_unary(Op::Acosh, &[1.00390625, 1.5, 6.0]);
    run_unary(Op::Atan, &[-3.5, -0.25, 0.0, 0.4375, 6.0]);
}

#[test]
fn hyperbolic_functions_match_calculus_tables() {
    // |u| up to 12: tanh′ must be sech², not 1 − tanh² (which cancels)
    let us = [-12.0, -2.25, -0.125, 0.0, 0.625, 3.5, 8.0];
    for op in [Op::Sinh, Op::Cosh, Op::Tanh] {
        run_unary(op, &us);
    }
}

#[test]
fn recip_neg_and_jet_jet_arithmetic_match_calculus_tables() {
    run_unary(Op::Recip, &[-2.5, -0.375, 0.625, 3.0]);
    run_unary(Op::Neg, &[-2.5, 0.625]);
    for op in [
        Op::Add,
        Op::Sub,
        Op::Mul,
        Op::Div,
        Op::AddAssign,
        Op::SubAssign,
        Op::MulAssign,
        Op::DivAssign,
    ] {
        for (u, w) in [(0.75, 1.5), (-2.25, 0.375), (3.0, -0.625)] {
            for (alpha, gamma) in [(0.5, 0.25), (-1.0, 1.5)] {
                run_case(op, u, w, alpha, gamma);
            }
        }
    }
}

#[test]
fn arithmetic_with_f64_on_either_side_matches_calculus_tables() {
    let us = [-2.5, 0.625, 3.0];
    for c in [-1.75, 0.3, 4.0] {
        for op in [
            Op::JetPlusF(c),
            Op::FPlusJet(c),
            Op::JetMinusF(c),
            Op::FMinusJet(c),
            Op::JetTimesF(c),
            Op::FTimesJet(c),
            Op::JetOverF(c),
            Op::FOverJet(c),
            Op::AddAssignF(c),
            Op::SubAssignF(c),
            Op::MulAssignF(c),
            Op::DivAssignF(c),
        ] {
            run_unary(op, &us);
        }
    }
}

#[test]
fn the_analytic_harness_detects_a_wrong_second_derivative() {
    // The checker must be able to fail: sin with the sign of f″ flipped is rejected.
    let s = &STATES[0];
    let beta = 0.4375 - 0.5 * base_u(&s.q, &s.v, s.t);
    let du = dense_u(s, 0.5, beta);
    let dw = dense_w(s, 0.5, 0.0);
    let u = 0.4375_f64;
    let wrong = dense_apply(&du, &dw, (u.sin(), u.cos(), 0.0, u.sin(), 0.0, 0.0));
    let (q, v, t) = ElJet::<2>::seed(&s.q, &s.v, s.t);
    let j = (base_u(&q, &v, t) * 0.5 + beta).sin();
    let caught = std::panic::catch_unwind(|| check_el("wrong", s, &j, &wrong, 1e-14));
    assert!(caught.is_err());
}
