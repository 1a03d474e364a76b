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

/// scale·f + shift as dense data, from f's value, gradient and the non-zero entries (i, k, ∂²f)
/// of its Hessian's upper triangle (mirrored below).
fn dense_scaled(
    scale: f64,
    shift: f64,
    value: f64,
    grad: [f64; NV],
    hess: &[(usize, usize, f64)],
) -> Dense {
    let mut h = [[Mg::default(); NV]; NV];
    for &(i, k, x) in hess {
        h[i][k] = Mg::leaf(scale * x);
        h[k][i] = Mg::leaf(scale * x);
    }
    Dense {
        v: scale * value + shift,
        g: grad.map(|x| Mg::leaf(scale * x)),
        h,
    }
}

/// α·base_u + β as dense data, its derivatives typed in by hand.
fn dense_u(s: &State, alpha: f64, beta: f64) -> Dense {
    let ([q0, q1], [v0, v1], t) = (s.q, s.v, s.t);
    let grad = [v1, t, 2.0 * v0, q0, q1];
    let hess = [(0, 3, 1.0), (2, 2, 2.0), (1, IT, 1.0)];
    dense_scaled(alpha, beta, q0 * v1 + v0 * v0 + q1 * t, grad, &hess)
}
/// γ·base_w + δ as dense data, its derivatives typed in by hand.
fn dense_w(s: &State, gamma: f64, delta: f64) -> Dense {
    let ([_q0, q1], [v0, v1], t) = (s.q, s.v, s.t);
    let grad = [0.0, v0, q1 + t, 2.0 * v1, v0];
    let hess = [(1, 2, 1.0), (3, 3, 2.0), (2, IT, 1.0)];
    dense_scaled(gamma, delta, q1 * v0 + v1 * v1 + v0 * t, grad, &hess)
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

/// Checks a jet's value and gradient in (q, q̇) against the dense reference.
#[track_caller]
fn check_gradient(tag: &str, (value, gq, gv): (f64, [f64; 2], [f64; 2]), r: &Dense, rel: f64) {
    close(&format!("{tag} value"), value, Mg::leaf(r.v), rel);
    for i in 0..2 {
        close(&format!("{tag} grad_q[{i}]"), gq[i], r.g[i], rel);
        close(&format!("{tag} grad_qdot[{i}]"), gv[i], r.g[2 + i], rel);
    }
}

/// Checks every ElJet block against the dense reference.
fn check_el(tag: &str, s: &State, j: &ElJet<2>, r: &Dense, rel: f64) {
    check_gradient(tag, (j.value(), j.grad_q(), j.grad_qdot()), r, rel);
    for i in 0..2 {
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
    check_gradient(tag, (j.value(), j.grad_q(), j.grad_qdot()), r, rel);
    for i in 0..2 {
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
            // exponents as f64 (exact): n − 1 and n − 2 overflow i32 at i32::MIN
            let d1 = if n == 0 { 0.0 } else { nf * u.powf(nf - 1.0) };
            let d2 = if n == 0 || n == 1 {
                0.0
            } else {
                nf * (nf - 1.0) * u.powf(nf - 2.0)
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
fn powi_at_the_ends_of_i32_does_not_overflow() {
    // ±1 keep every derivative finite: (−1)^n, n (−1)^(n−1), n (n−1) (−1)^(n−2)
    for n in [i32::MIN, i32::MIN + 1, i32::MAX, i32::MAX - 1] {
        run_unary(Op::Powi(n), &[-1.0, 1.0]);
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
            Op::JetPlusF,
            Op::FPlusJet,
            Op::JetMinusF,
            Op::FMinusJet,
            Op::JetTimesF,
            Op::FTimesJet,
            Op::JetOverF,
            Op::FOverJet,
            Op::AddAssignF,
            Op::SubAssignF,
            Op::MulAssignF,
            Op::DivAssignF,
        ] {
            run_unary(op(c), &us);
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

// ---------------------------------------------------------------------------------------------
// 2. Property tests: random expressions against finite differences and against each other
// ---------------------------------------------------------------------------------------------

/// A random expression in q₀, q₁, q̇₀, q̇₁, t and constants. The forms that have singularities are
/// guarded (`Div`: a/(b² + ½), `SqrtPos`: √(a² + ¼), negative `Powi` and `PowfPos` on a² + ½) so
/// that random trees stay where the function is smooth; `Atan2` is unguarded and cases too close to
/// its singularity are discarded by the scale filter.
#[derive(Clone, Debug)]
enum Expr {
    Q(usize),
    V(usize),
    T,
    C(f64),
    Add(Box<Expr>, Box<Expr>),
    Sub(Box<Expr>, Box<Expr>),
    Mul(Box<Expr>, Box<Expr>),
    Div(Box<Expr>, Box<Expr>),
    Sin(Box<Expr>),
    Cos(Box<Expr>),
    Exp(Box<Expr>),
    SqrtPos(Box<Expr>),
    Powi(Box<Expr>, i32),
    Atan(Box<Expr>),
    Tanh(Box<Expr>),
    Atan2(Box<Expr>, Box<Expr>),
    PowfPos(Box<Expr>, Box<Expr>),
    MulF(Box<Expr>, f64),
}

fn eval<S: Scalar>(e: &Expr, q: &[S], v: &[S], t: S) -> S {
    let ev = |x: &Expr| eval(x, q, v, t);
    match e {
        Expr::Q(i) => q[*i],
        Expr::V(i) => v[*i],
        Expr::T => t,
        Expr::C(c) => S::constant(*c),
        Expr::Add(a, b) => ev(a) + ev(b),
        Expr::Sub(a, b) => ev(a) - ev(b),
        Expr::Mul(a, b) => ev(a) * ev(b),
        Expr::Div(a, b) => {
            let d = ev(b);
            ev(a) / (d * d + 0.5)
        }
        Expr::Sin(a) => ev(a).sin(),
        Expr::Cos(a) => ev(a).cos(),
        Expr::Exp(a) => ev(a).exp(),
        Expr::SqrtPos(a) => {
            let x = ev(a);
            (x * x + 0.25).sqrt()
        }
        Expr::Powi(a, n) => {
            let x = ev(a);
            if *n < 0 {
                (x * x + 0.5).powi(*n)
            } else {
                x.powi(*n)
            }
        }
        Expr::Atan(a) => ev(a).atan(),
        Expr::Tanh(a) => ev(a).tanh(),
        Expr::Atan2(a, b) => ev(a).atan2(ev(b)),
        Expr::PowfPos(a, b) => {
            let x = ev(a);
            (x * x + 0.5).powf(ev(b))
        }
        Expr::MulF(a, c) => ev(a) * *c,
    }
}

fn expr_strategy() -> impl Strategy<Value = Expr> {
    let leaf = prop_oneof![
        (0..2usize).prop_map(Expr::Q),
        (0..2usize).prop_map(Expr::V),
        Just(Expr::T),
        (-2.0..2.0f64).prop_map(Expr::C),
    ];
    leaf.prop_recursive(4, 32, 2, |inner| {
        let b = |x: Expr| Box::new(x);
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Expr::Add(b(x), b(y))),
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Expr::Sub(b(x), b(y))),
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Expr::Mul(b(x), b(y))),
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Expr::Div(b(x), b(y))),
            inner.clone().prop_map(move |x| Expr::Sin(b(x))),
            inner.clone().prop_map(move |x| Expr::Cos(b(x))),
            inner.clone().prop_map(move |x| Expr::Exp(b(x))),
            inner.clone().prop_map(move |x| Expr::SqrtPos(b(x))),
            (inner.clone(), -2..5i32).prop_map(move |(x, n)| Expr::Powi(b(x), n)),
            inner.clone().prop_map(move |x| Expr::Atan(b(x))),
            inner.clone().prop_map(move |x| Expr::Tanh(b(x))),
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Expr::Atan2(b(x), b(y))),
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Expr::PowfPos(b(x), b(y))),
            (inner, -3.0..3.0f64).prop_map(move |(x, c)| Expr::MulF(b(x), c)),
        ]
    })
}

/// The expression in f64 as a function of x = (q₀, q₁, q̇₀, q̇₁, t).
fn eval_f64(e: &Expr, x: &[f64; NV]) -> f64 {
    eval(e, &x[0..2], &x[2..4], x[IT])
}

/// Finite-difference step and tolerance of the property tests: central differences with steps
/// h = 1e-3 and h/2 combined by one Richardson extrapolation, (4D(h/2) − D(h))/3, which is
/// fourth-order (truncation ~h⁴f⁽⁶⁾/360 ≈ 3e-15 f⁽⁶⁾, rounding ~ε|f|/(h/2)² ≈ 1e-9|f|). Plain
/// second-order differences with h = 1e-4 were not accurate enough for random trees with
/// fast-oscillating parts such as sin(exp(q̇²)) (their truncation error h²f⁗/12 reached 1.5e-6 of
/// the scale). Tolerance: 1e-6 times the scale max(1, |f|, max|∇f|, max|∇²f|).
const FD_H: f64 = 1e-3;
const FD_TOL: f64 = 1e-6;

/// Value, gradient and Hessian of the f64 evaluation by central finite differences.
fn finite_differences(e: &Expr, x: &[f64; NV]) -> (f64, [f64; NV], [[f64; NV]; NV]) {
    let (f0, g1, h1) = central_differences(e, x, FD_H);
    let (_, g2, h2) = central_differences(e, x, FD_H / 2.0);
    let richardson = |a: f64, b: f64| (4.0 * b - a) / 3.0;
    let mut g = [0.0; NV];
    let mut hs = [[0.0; NV]; NV];
    for i in 0..NV {
        g[i] = richardson(g1[i], g2[i]);
        for j in 0..NV {
            hs[i][j] = richardson(h1[i][j], h2[i][j]);
        }
    }
    (f0, g, hs)
}

/// Second-order central differences with step h.
fn central_differences(e: &Expr, x: &[f64; NV], h: f64) -> (f64, [f64; NV], [[f64; NV]; NV]) {
    let f = |dx: &[(usize, f64)]| {
        let mut y = *x;
        for &(i, d) in dx {
            y[i] += d;
        }
        eval_f64(e, &y)
    };
    let f0 = f(&[]);
    let mut g = [0.0; NV];
    let mut hs = [[0.0; NV]; NV];
    for i in 0..NV {
        let (fp, fm) = (f(&[(i, h)]), f(&[(i, -h)]));
        g[i] = (fp - fm) / (2.0 * h);
        hs[i][i] = (fp - 2.0 * f0 + fm) / (h * h);
        for j in 0..i {
            let d = (f(&[(i, h), (j, h)]) - f(&[(i, h), (j, -h)]) - f(&[(i, -h), (j, h)])
                + f(&[(i, -h), (j, -h)]))
                / (4.0 * h * h);
            hs[i][j] = d;
            hs[j][i] = d;
        }
    }
    (f0, g, hs)
}

/// The expression in the dense jet with time as a third coordinate of velocity 1, which makes
/// ∂²/∂q̇∂t (row 2 of `hess_qqdot`) and ∂/∂t (`grad_q()[2]`) available.
fn hessian_with_time(e: &Expr, x: &[f64; NV]) -> HessianJet<3> {
    let (q, v) = HessianJet::<3>::seed(&[x[0], x[1], x[IT]], &[x[2], x[3], 1.0]);
    eval(e, &q[0..2], &v[0..2], q[2])
}

/// The reference (q, q̇, t)-Hessian of the augmented dense jet in the 5-variable layout.
fn dense_of(h: &HessianJet<3>) -> (f64, [f64; NV], [[f64; NV]; NV]) {
    // layout: augmented q = (q₀, q₁, t) → 0, 1, 4; augmented q̇ = (q̇₀, q̇₁, ·) → 2, 3
    let qi = [0, 1, IT];
    let (gq, gv, hqq, hqv, hvv) = (
        h.grad_q(),
        h.grad_qdot(),
        h.hess_qq(),
        h.hess_qqdot(),
        h.hess_qdotqdot(),
    );
    let mut g = [0.0; NV];
    let mut hs = [[0.0; NV]; NV];
    for a in 0..3 {
        g[qi[a]] = gq[a];
        for b in 0..3 {
            hs[qi[a]][qi[b]] = hqq[a][b];
        }
        for k in 0..2 {
            hs[qi[a]][2 + k] = hqv[a][k];
            hs[2 + k][qi[a]] = hqv[a][k];
        }
    }
    for i in 0..2 {
        g[2 + i] = gv[i];
        for k in 0..2 {
            hs[2 + i][2 + k] = hvv[i][k];
        }
    }
    (h.value(), g, hs)
}

/// The ElJet blocks derived from dense (f, ∇f, ∇²f) data: value, grad_q, grad_qdot, hess_qdot,
/// mixed, directional, flattened for comparison.
fn el_blocks_from_dense(x: &[f64; NV], d: &(f64, [f64; NV], [[f64; NV]; NV])) -> Vec<f64> {
    let (f, g, h) = d;
    let mut out = vec![*f, g[0], g[1], g[2], g[3]];
    // ElJet stores the upper triangle of M; the dense jet's lower triangle is the same value
    // summed in another order, so read the upper one for a bitwise comparison.
    for i in 0..2 {
        for k in 0..2 {
            out.push(h[2 + i.min(k)][2 + i.max(k)]);
        }
    }
    for i in 0..2 {
        out.push(h[2 + i][0] * x[2] + h[2 + i][1] * x[3] + h[2 + i][IT]);
    }
    out.push(g[0] * x[2] + g[1] * x[3] + g[IT]);
    out
}

fn el_blocks(j: &ElJet<2>) -> Vec<f64> {
    let mut out = vec![j.value()];
    out.extend(j.grad_q());
    out.extend(j.grad_qdot());
    for i in 0..2 {
        for k in 0..2 {
            out.push(j.hess_qdot(i, k));
        }
    }
    out.extend(j.mixed());
    out.push(j.directional());
    out
}

const EL_BLOCK_NAMES: [&str; 12] = [
    "value",
    "grad_q[0]",
    "grad_q[1]",
    "grad_qdot[0]",
    "grad_qdot[1]",
    "hess_qdot(0,0)",
    "hess_qdot(0,1)",
    "hess_qdot(1,0)",
    "hess_qdot(1,1)",
    "mixed[0]",
    "mixed[1]",
    "directional",
];

fn el_at(e: &Expr, x: &[f64; NV]) -> ElJet<2> {
    let (q, v, t) = ElJet::<2>::seed(&[x[0], x[1]], &[x[2], x[3]], x[IT]);
    eval(e, &q, &v, t)
}
fn hess_at(e: &Expr, x: &[f64; NV]) -> HessianJet<2> {
    let (q, v) = HessianJet::<2>::seed(&[x[0], x[1]], &[x[2], x[3]]);
    eval(e, &q, &v, HessianJet::from(x[IT]))
}

fn state_strategy() -> impl Strategy<Value = [f64; NV]> {
    proptest::array::uniform5(-1.5..1.5f64)
}

/// max(1, |f|, max|∇f|, max|∇²f|) of dense data; infinite if any entry is not finite.
fn scale_of(d: &(f64, [f64; NV], [[f64; NV]; NV])) -> f64 {
    let (f, g, h) = d;
    max_abs_of(core::iter::once(f).chain(g).chain(h.iter().flatten()))
}

/// max(1, max|x|) over `xs`; infinite if any is not finite.
fn max_abs_of<'a>(xs: impl IntoIterator<Item = &'a f64>) -> f64 {
    xs.into_iter().fold(1.0_f64, |m, x| {
        if x.is_finite() {
            m.max(x.abs())
        } else {
            f64::INFINITY
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 384, max_global_rejects: 100_000, ..ProptestConfig::default() })]

    /// Both jets against central finite differences of the f64 evaluation.
    #[test]
    fn random_expressions_match_finite_differences(e in expr_strategy(), x in state_strategy()) {
        let reference = dense_of(&hessian_with_time(&e, &x));
        let scale = scale_of(&reference);
        // keep to functions whose derivatives are moderate, where the FD reference is meaningful
        prop_assume!(reference.0.is_finite() && scale < 1e3);
        let fd = finite_differences(&e, &x);
        // and to points where f is resolved by the stencil (not astride atan2's branch cut, not
        // within a few h of its singularity): there the two step sizes agree to 1e-4 of the
        // scale, and the extrapolated error is far smaller still
        let (_, g1, h1) = central_differences(&e, &x, FD_H);
        let (_, g2, h2) = central_differences(&e, &x, FD_H / 2.0);
        let spread = g1.iter().zip(&g2).chain(h1.iter().flatten().zip(h2.iter().flatten()))
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        prop_assume!(spread <= 1e-4 * scale);
        let tol = FD_TOL * scale;

        let el = el_blocks(&el_at(&e, &x));
        let want = el_blocks_from_dense(&x, &fd);
        // mixed and directional sum three FD entries weighted by |q̇| ≤ 1.5
        for (n, (a, b)) in el.iter().zip(&want).enumerate() {
            let tol = if n >= 9 { 4.0 * tol } else { tol };
            prop_assert!((a - b).abs() <= tol,
                "ElJet {}: jet {a:e}, FD {b:e}, scale {scale:e}, expr {e:?}", EL_BLOCK_NAMES[n]);
        }

        let hj = hess_at(&e, &x);
        let (_, g, h) = &fd;
        for i in 0..2 {
            prop_assert!((hj.grad_q()[i] - g[i]).abs() <= tol, "grad_q {i}: {e:?}");
            prop_assert!((hj.grad_qdot()[i] - g[2 + i]).abs() <= tol, "grad_qdot {i}: {e:?}");
            for k in 0..2 {
                prop_assert!((hj.hess_qq()[i][k] - h[i][k]).abs() <= tol, "hess_qq {i}{k}: {e:?}");
                prop_assert!((hj.hess_qqdot()[i][k] - h[i][2 + k]).abs() <= tol, "hess_qqdot {i}{k}: jet {:e} FD {:e} scale {scale:e} at {x:?}: {e:?}", hj.hess_qqdot()[i][k], h[i][2 + k]);
                prop_assert!((hj.hess_qdotqdot()[i][k] - h[2 + i][2 + k]).abs() <= tol, "hess_qdotqdot {i}{k}: {e:?}");
            }
        }
    }

    /// ElJet against HessianJet (time as a coordinate) on every shared block, to 1e-12 of the scale.
    #[test]
    fn eljet_agrees_with_hessianjet(e in expr_strategy(), x in state_strategy()) {
        let reference = dense_of(&hessian_with_time(&e, &x));
        let scale = scale_of(&reference);
        prop_assume!(scale.is_finite() && reference.0.is_finite());
        let el = el_blocks(&el_at(&e, &x));
        let want = el_blocks_from_dense(&x, &reference);
        for (n, (a, b)) in el.iter().zip(&want).enumerate() {
            prop_assert!((a - b).abs() <= 1e-12 * scale,
                "{}: ElJet {a:e}, HessianJet {b:e}, scale {scale:e}, expr {e:?}", EL_BLOCK_NAMES[n]);
        }
        // HessianJet with t as a constant agrees with the augmented one on its blocks
        let hj = hess_at(&e, &x);
        let (_, g, h) = &reference;
        for i in 0..2 {
            for k in 0..2 {
                prop_assert!((hj.hess_qq()[i][k] - h[i][k]).abs() <= 1e-12 * scale);
                prop_assert!((hj.hess_qqdot()[i][k] - h[i][2 + k]).abs() <= 1e-12 * scale);
            }
            prop_assert!((hj.grad_q()[i] - g[i]).abs() <= 1e-12 * scale);
        }
    }
}

/// A random three-coordinate Lagrangian L = ½q̇ᵀA(q)q̇ + b(q,t)·q̇ − V(q,t) with
/// A = B(q)ᵀB(q) + ½I (positive definite), B_ij = c_ij + d_ij sin(q_{(i+j) mod 3} + e_ij),
/// b_i = β_i cos(ωt + q_i) q_{i+1}, V = Σ k_i(1 − cos q_i) + κ q₀q₁q₂ + ε sin(t) q₀.
#[derive(Clone, Debug)]
struct RandomSystem {
    b: [[(f64, f64, f64); 3]; 3],
    beta: [f64; 3],
    omega: f64,
    k: [f64; 3],
    kappa: f64,
    eps: f64,
}

impl RandomSystem {
    fn l<S: Scalar>(&self, q: &[S], v: &[S], t: S) -> S {
        let mut kin = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * 0.25;
        for i in 0..3 {
            let mut w = S::constant(0.0);
            for j in 0..3 {
                let (c, d, e) = self.b[i][j];
                w += ((q[(i + j) % 3] + e).sin() * d + c) * v[j];
            }
            kin += w * w * 0.5;
        }
        let mut gyro = S::constant(0.0);
        let mut pot = q[0] * q[1] * q[2] * self.kappa + t.sin() * q[0] * self.eps;
        for i in 0..3 {
            gyro += (t * self.omega + q[i]).cos() * q[(i + 1) % 3] * v[i] * self.beta[i];
            pot += (S::constant(1.0) - q[i].cos()) * self.k[i];
        }
        kin + gyro - pot
    }
}

impl Lagrangian<3> for RandomSystem {
    const COORDINATES: [&'static str; 3] = ["a", "b", "c"];
    const CYCLIC: [bool; 3] = [false; 3];
    const AUTONOMOUS: bool = false;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], qdot: &[S; 3], t: S) -> S {
        self.l(q, qdot, t)
    }
}

fn system_strategy() -> impl Strategy<Value = RandomSystem> {
    let entry = (-1.5..1.5f64, -1.0..1.0f64, -3.0..3.0f64);
    (
        proptest::array::uniform3(proptest::array::uniform3(entry)),
        proptest::array::uniform3(-1.0..1.0f64),
        -2.0..2.0f64,
        proptest::array::uniform3(-3.0..3.0f64),
        -1.0..1.0f64,
        -1.0..1.0f64,
    )
        .prop_map(|(b, beta, omega, k, kappa, eps)| RandomSystem {
            b,
            beta,
            omega,
            k,
            kappa,
            eps,
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// `accelerations` solves M q̈ = ∂L/∂q − (∂²L/∂q̇∂q)q̇ − ∂²L/∂q̇∂t with M and the right-hand
    /// side assembled independently from the dense HessianJet (t as a fourth coordinate of velocity
    /// 1) and solved by nalgebra's LU.
    #[test]
    fn accelerations_solve_the_dense_jet_equations(
        sys in system_strategy(),
        q in proptest::array::uniform3(-3.0..3.0f64),
        v in proptest::array::uniform3(-2.0..2.0f64),
        t in -5.0..5.0f64,
    ) {
        let a = sys.accelerations(&q, &v, t).unwrap();
        let (qa, va) = HessianJet::<4>::seed(&[q[0], q[1], q[2], t], &[v[0], v[1], v[2], 1.0]);
        let l = sys.l(&qa[0..3], &va[0..3], qa[3]);
        let (gq, hqv, hvv) = (l.grad_q(), l.hess_qqdot(), l.hess_qdotqdot());
        let m = nalgebra::Matrix3::from_fn(|i, k| hvv[i][k]);
        let vaug = [v[0], v[1], v[2], 1.0];
        let f = nalgebra::Vector3::from_fn(|i, _| {
            gq[i] - (0..4).map(|j| hqv[j][i] * vaug[j]).sum::<f64>()
        });
        let want = m.lu().solve(&f).unwrap();
        let got = nalgebra::Vector3::from(a);
        // backward error: the residual of the dense equations
        let residual = (m * got - f).amax();
        let size = m.amax() * got.amax() + f.amax();
        prop_assert!(residual <= 1e-12 * size, "residual {residual:e} of {size:e}");
        // forward error, allowing for the conditioning of M
        let cond = m.norm() * m.try_inverse().unwrap().norm();
        prop_assert!((got - want).amax() <= 1e-13 * cond * want.amax().max(1e-300) + 1e-300,
            "got {got:?}, want {want:?}, cond {cond:e}");
    }
}

fn contains_powf(e: &Expr) -> bool {
    match e {
        Expr::Q(_) | Expr::V(_) | Expr::T | Expr::C(_) => false,
        Expr::PowfPos(..) => true,
        Expr::Add(a, b)
        | Expr::Sub(a, b)
        | Expr::Mul(a, b)
        | Expr::Div(a, b)
        | Expr::Atan2(a, b) => contains_powf(a) || contains_powf(b),
        Expr::Sin(a)
        | Expr::Cos(a)
        | Expr::Exp(a)
        | Expr::SqrtPos(a)
        | Expr::Powi(a, _)
        | Expr::Atan(a)
        | Expr::Tanh(a)
        | Expr::MulF(a, _) => contains_powf(a),
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Structural flags change nothing
// ---------------------------------------------------------------------------------------------

/// Expressions mixing q-only, q̇-only (linear and non-linear), t-only and constant parts, each
/// exercising one way a flag is set, propagated or used to skip a block.
#[allow(clippy::eq_op)] // `q - q` and `t - t` are the point: flagged jets with zero parts
fn flag_cases<S: Scalar>(q: &[S], v: &[S], t: S) -> Vec<S> {
    let c = S::constant;
    vec![
        q[0].sin() * q[1] + 3.0,                // q only, plus a constant
        v[0] * 2.0 + v[1] - 1.0,                // linear in q̇: M block skipped
        v[0] * v[1],                            // q̇ × q̇ sets "non-linear"
        (v[0] + 1.0).powi(3),                   // chain rule of a linear jet sets "non-linear"
        c(2.0).sin() * v[0],                    // constant chain × linear
        q[0].cos() * v[1],                      // q-only × linear: M = 0, mixed ≠ 0
        q[0].cos() * v[1] + v[0] * v[0] * q[1], // sum of linear and non-linear
        t * v[0],                               // ∂²/∂q̇∂t
        t.sin() * v[0] * v[0] + t,              // t-only parts
        v[0] / (q[1] * q[1] + 1.0),             // divide by a q-only jet
        q[0] / (v[1] * v[1] + 1.0),             // divide by a q̇-only jet
        (v[0] * 3.0 - v[1]).exp() * q[0],       // exp of a linear jet
        (v[0] + v[1]) * (v[0] - v[1]),          // linear × linear
        (q[0] - q[0]) * v[0] + v[1] * 0.0,      // flagged, numerically zero
        v[0].powi(0) * q[0],                    // powi(0) is a constant
        -(v[1] * q[1]) + c(0.5),                // negation
        (q[0] * v[0] + t).atan2(v[1] + 2.0),    // atan2 of mixed jets
        (v[0] * v[0] + 1.0).sqrt() * q[1] + (q[0] + t).exp(),
        (q[0].sin() + q[1].cos()) * (v[0] * v[1]),
        (v[0] * v[0] + q[0] * q[0] + 1.0).powf(v[1]), // variable exponent
        (v[0] * v[0] + 1.0).powf(c(2.5)),             // constant exponent
        (q[0] - 3.0).powf(t - t + 3.0), // negative base, flagged but constant exponent
        (t * 2.0).cos(),                // t only
        c(4.0),                         // constant only
        {
            let mut x = v[0];
            x *= q[1];
            x += t;
            x -= v[1] * v[1];
            x /= q[0] + 2.0;
            x
        },
    ]
}

#[test]
fn structural_flags_give_the_flag_free_results() {
    let states = [
        [0.3, -1.1, 0.7, -0.4, 2.0],
        [-0.9, 0.2, -1.3, 1.7, -0.5],
        [1.4, 0.6, 0.0, 0.9, 0.0],
    ];
    for x in states {
        let (q, v, t) = ElJet::<2>::seed(&[x[0], x[1]], &[x[2], x[3]], x[IT]);
        let el = flag_cases(&q, &v, t);
        let (qa, va) = HessianJet::<3>::seed(&[x[0], x[1], x[IT]], &[x[2], x[3], 1.0]);
        let dense = flag_cases(&qa[0..2], &va[0..2], qa[2]);
        let (q2, v2) = HessianJet::<2>::seed(&[x[0], x[1]], &[x[2], x[3]]);
        let dense_const_t = flag_cases(&q2, &v2, HessianJet::from(x[IT]));
        for (n, ((e, d), d2)) in el.iter().zip(&dense).zip(&dense_const_t).enumerate() {
            let want = el_blocks_from_dense(&x, &dense_of(d));
            let got = el_blocks(e);
            // value, gradients and M: same formulas with and without the flags → bitwise equal
            for b in 0..9 {
                assert!(
                    got[b] == want[b],
                    "case {n} at {x:?}: {} ElJet {:e} vs flag-free {:e}",
                    EL_BLOCK_NAMES[b],
                    got[b],
                    want[b]
                );
            }
            // mixed and directional: the flag-free value is a sum over the dense Hessian, so
            // compare to 1e-15 of the magnitude of its terms
            let (_, g, h) = dense_of(d);
            let mags = [
                h[2][0].abs() * x[2].abs() + h[2][1].abs() * x[3].abs() + h[2][IT].abs(),
                h[3][0].abs() * x[2].abs() + h[3][1].abs() * x[3].abs() + h[3][IT].abs(),
                g[0].abs() * x[2].abs() + g[1].abs() * x[3].abs() + g[IT].abs(),
            ];
            for (b, m) in (9..12).zip(mags) {
                assert!(
                    (got[b] - want[b]).abs() <= 1e-15 * m,
                    "case {n} at {x:?}: {} ElJet {:e} vs flag-free {:e}",
                    EL_BLOCK_NAMES[b],
                    got[b],
                    want[b]
                );
            }
            // the constant-time HessianJet gives the same q/q̇ blocks
            let m = d2.hess_qdotqdot();
            assert_eq!(
                [m[0][0], m[0][1], m[1][1]],
                [want[5], want[6], want[8]],
                "case {n}"
            );
            assert_eq!(d2.grad_q(), [want[1], want[2]], "case {n}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 384, max_global_rejects: 100_000, ..ProptestConfig::default() })]

    /// On random expressions, the blocks the flags may skip (value, ∂/∂q, ∂/∂q̇, M) are bitwise
    /// equal to the flag-free dense jet.
    #[test]
    fn structural_flags_are_bitwise_neutral_on_random_expressions(
        e in expr_strategy(), x in state_strategy()
    ) {
        let d = hessian_with_time(&e, &x);
        // Where a derivative is NaN (atan2 at the origin, say) the flag-free jet spreads it into
        // blocks that are structurally zero (0·NaN = NaN) while ElJet skips them; compare only
        // where everything is finite.
        prop_assume!(scale_of(&dense_of(&d)).is_finite());
        let dense = dense_of(&d);
        let want = el_blocks_from_dense(&x, &dense);
        let got = el_blocks(&el_at(&e, &x));
        // `powf` takes its constant-exponent shortcut when every derivative part of the exponent
        // is exactly zero; an exponent like atan2(q₀, q₀) has rounding-level parts that may be
        // zero in one layout and 1 ulp off in the other, so the two jets can take different
        // (both correct) paths there: allow 1e-15 of the scale in trees with `PowfPos`.
        let tol = if contains_powf(&e) { 1e-15 * scale_of(&dense) } else { 0.0 };
        for b in 0..9 {
            prop_assert!((got[b] - want[b]).abs() <= tol,
                "{}: ElJet {:e} vs flag-free {:e}, expr {e:?}", EL_BLOCK_NAMES[b], got[b], want[b]);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 4. LinJet: the derivative of the Hessian along a direction
// ---------------------------------------------------------------------------------------------
//
// The third derivatives are checked against central differences of the (independently verified)
// HessianJet: D_z ∇²f ≈ (∇²f(x + hz) − ∇²f(x − hz))/2h, with steps 1e-3 and 5e-4 combined by one
// Richardson extrapolation (error ~h⁴ f⁽⁷⁾), to 1e-6 of the scale. The differences check the
// jet here; they compute nothing in the library.

use super::LinJet;

/// Value, gradient and Hessian blocks of a 2-coordinate dense jet, flattened.
fn hess_blocks(h: &HessianJet<2>) -> Vec<f64> {
    let mut out = vec![h.value()];
    out.extend(h.grad_q());
    out.extend(h.grad_qdot());
    for m in [h.hess_qq(), h.hess_qqdot(), h.hess_qdotqdot()] {
        out.extend(m.iter().flatten());
    }
    out
}

fn lin_at(e: &Expr, x: &[f64; NV], z: &[f64; NV]) -> LinJet<2> {
    let (q, v, t) = LinJet::<2>::seed(
        &[x[0], x[1]],
        &[x[2], x[3]],
        x[IT],
        &[z[0], z[1]],
        &[z[2], z[3]],
        z[IT],
    );
    eval(e, &q, &v, t)
}

/// The central difference of the dense-jet blocks along z with step h.
fn hess_difference(e: &Expr, x: &[f64; NV], z: &[f64; NV], h: f64) -> Vec<f64> {
    let shifted = |s: f64| {
        let mut y = *x;
        for i in 0..NV {
            y[i] += s * z[i];
        }
        hess_blocks(&hess_at(e, &y))
    };
    let (p, m) = (shifted(h), shifted(-h));
    p.iter().zip(&m).map(|(a, b)| (a - b) / (2.0 * h)).collect()
}

fn max_abs(v: &[f64]) -> f64 {
    max_abs_of(v)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 384, max_global_rejects: 100_000, ..ProptestConfig::default() })]

    /// LinJet's base part is the HessianJet, and its derivative part is the derivative of the
    /// HessianJet along the seeded direction (time included).
    #[test]
    fn linjet_is_the_directional_derivative_of_the_hessian_jet(
        e in expr_strategy(), x in state_strategy(), z in proptest::array::uniform5(-1.0..1.0f64)
    ) {
        let lin = lin_at(&e, &x, &z);
        let base = hess_blocks(lin.base());
        let want_base = hess_blocks(&hess_at(&e, &x));
        let scale_base = max_abs(&want_base);
        prop_assume!(scale_base < 1e3);
        for (n, (a, b)) in base.iter().zip(&want_base).enumerate() {
            prop_assert!((a - b).abs() <= 1e-13 * scale_base, "base block {n}: {a:e} vs {b:e}, {e:?}");
        }
        let along = hess_blocks(lin.along());
        let d1 = hess_difference(&e, &x, &z, FD_H);
        let d2 = hess_difference(&e, &x, &z, FD_H / 2.0);
        let scale = max_abs(&along).max(max_abs(&d2)).max(scale_base);
        prop_assume!(scale < 1e3);
        let spread = d1.iter().zip(&d2).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        prop_assume!(spread <= 1e-4 * scale);
        for (n, ((a, h1), h2)) in along.iter().zip(&d1).zip(&d2).enumerate() {
            let fd = (4.0 * h2 - h1) / 3.0;
            prop_assert!((a - fd).abs() <= FD_TOL * scale,
                "along block {n}: jet {a:e}, FD {fd:e}, scale {scale:e}, at {x:?} along {z:?}: {e:?}");
        }
    }
}

/// The elementary functions of the jets, by index (for the f‴ checks).
fn elementary<S: Scalar + RealField>(k: usize, x: S) -> S {
    match k {
        0 => x.sin(),
        1 => x.cos(),
        2 => x.tan(),
        3 => x.asin(),
        4 => x.acos(),
        5 => x.atan(),
        6 => x.sinh(),
        7 => x.cosh(),
        8 => x.tanh(),
        9 => x.asinh(),
        10 => (x + 2.0).acosh(),
        11 => x.atanh(),
        12 => (x + 2.0).ln(),
        13 => x.ln_1p(),
        14 => (x + 2.0).sqrt(),
        15 => x.exp(),
        16 => x.exp2(),
        17 => x.exp_m1(),
        18 => x.powi(5),
        19 => (x + 2.0).powi(-2),
        20 => x.powi(2),
        21 => (x + 2.0).powf(S::constant(2.5)),
        22 => (x + 2.0).powf(S::constant(2.0)),
        23 => (x + 2.0).cbrt(),
        24 => (x + 2.0).recip(),
        25 => num_traits::Signed::abs(&x),
        26 => x.atan2(S::constant(0.7)),
        27 => x.log2(),
        _ => x.sin_cos().1,
    }
}
const ELEMENTARY: usize = 29;

/// f‴ of every elementary function, from the LinJet (one variable, direction 1), against the
/// Richardson-extrapolated central difference of f″ from the verified HessianJet, to 1e-7
/// relative to max(1, |f‴|).
#[test]
fn linjet_third_derivatives_of_every_elementary_function() {
    let f2 = |k: usize, x: f64| {
        let (q, _) = HessianJet::<1>::seed(&[x], &[0.0]);
        elementary(k, q[0]).hess_qq()[0][0]
    };
    for k in 0..ELEMENTARY {
        for x in [-0.6, -0.15, 0.35, 0.8] {
            let x = if k == 27 { x + 1.5 } else { x };
            let (q, _, _) = LinJet::<1>::seed(&[x], &[0.0], 0.0, &[1.0], &[0.0], 0.0);
            let j = elementary(k, q[0]);
            let got = j.along().hess_qq()[0][0];
            let d = |h: f64| (f2(k, x + h) - f2(k, x - h)) / (2.0 * h);
            let fd = (4.0 * d(5e-4) - d(1e-3)) / 3.0;
            assert!(
                (got - fd).abs() <= 1e-7 * got.abs().max(1.0),
                "function {k} at {x}: jet f‴ = {got:e}, FD = {fd:e}"
            );
            // the lower parts are those of the HessianJet, and D(f′) = f″
            assert!((j.along().grad_q()[0] - f2(k, x)).abs() <= 1e-14 * f2(k, x).abs().max(1.0));
        }
    }
}

/// The three directions of a LinJet add: D_(z₁+z₂) = D_z₁ + D_z₂ (linearity in the seed), and
/// the product rule across q̇ and t on a hand-checked case.
#[test]
fn linjet_is_linear_in_the_direction_and_hand_checked() {
    // L = q̇² t sin q: ∂²L/∂q̇² = 2 t sin q; along (δq, δq̇, δt) = (a, b, c): 2 c sin q + 2 t a cos q
    let (q0, v0, t0) = (0.4, -1.3, 2.5);
    let l = |dq: f64, dv: f64, dt: f64| {
        let (q, v, t) = LinJet::<1>::seed(&[q0], &[v0], t0, &[dq], &[dv], dt);
        v[0] * v[0] * t * q[0].sin()
    };
    let j = l(0.3, 0.7, -0.9);
    let want = 2.0 * -0.9 * q0.sin() + 2.0 * t0 * 0.3 * q0.cos();
    assert!((j.along().hess_qdotqdot()[0][0] - want).abs() < 1e-15);
    let sum = hess_blocks_1(l(0.3, 0.0, 0.0).along())
        .iter()
        .zip(hess_blocks_1(l(0.0, 0.7, 0.0).along()))
        .zip(hess_blocks_1(l(0.0, 0.0, -0.9).along()))
        .map(|((a, b), c)| a + b + c)
        .collect::<Vec<_>>();
    for (a, b) in hess_blocks_1(j.along()).iter().zip(sum) {
        assert!((a - b).abs() < 1e-14, "{a} vs {b}");
    }
}

fn hess_blocks_1(h: &HessianJet<1>) -> Vec<f64> {
    vec![
        h.value(),
        h.grad_q()[0],
        h.grad_qdot()[0],
        h.hess_qq()[0][0],
        h.hess_qqdot()[0][0],
        h.hess_qdotqdot()[0][0],
    ]
}
