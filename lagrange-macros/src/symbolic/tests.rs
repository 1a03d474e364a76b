//! Unit tests of the symbolic path: DAG folding, derivative rules against finite differences of
//! the numerically evaluated DAG, the whole derivation against closed forms, equation printing
//! and the "use mode = jets" errors.
// Index loops mirror the formulas they check.
#![allow(clippy::needless_range_loop)]

use proc_macro2::Span;
use quote::format_ident;

use super::dag::{Dag, Fun, Id, Node, VarSet};
use super::derive::Derivation;
use super::{SymbolicOutput, MAX_GENERATED_LETS};
use crate::errors::Errors;
use crate::model::{CoordKind, CoordParam, Decl, Mode, Options};

/// `super::derive` with its errors as a list.
fn derive(decl: &Decl) -> Result<Derivation, Vec<syn::Error>> {
    let mut errors = Errors::default();
    let front = crate::front::Front::of(decl);
    match super::derive::derive(decl, &front, &mut errors) {
        Some(d) if errors.is_empty() => Ok(d),
        _ => Err(errors.into_vec()),
    }
}

/// `super::expand` with its errors as a list.
fn expand(decl: &Decl) -> Result<SymbolicOutput, Vec<syn::Error>> {
    let mut errors = Errors::default();
    let front = crate::front::Front::of(decl);
    match super::expand(decl, &front, &mut errors) {
        Some(out) if errors.is_empty() => Ok(out),
        _ => Err(errors.into_vec()),
    }
}

/// A declaration from coordinates `(name, dot, vector?)`, an optional time name and a body.
fn decl(coords: &[(&str, &str, bool)], time: Option<&str>, body: &str) -> Decl {
    let mut first = 0;
    let coords = coords
        .iter()
        .map(|&(name, dot, vector)| {
            let c = CoordParam {
                kind: if vector {
                    CoordKind::Vector3
                } else {
                    CoordKind::Scalar
                },
                name: format_ident!("{}", name),
                dot: format_ident!("{}", dot),
                first_index: first,
            };
            first += c.width();
            c
        })
        .collect();
    Decl {
        rest: syn::parse_quote!(impl X {}),
        fn_attrs: Vec::new(),
        fn_ident: format_ident!("lagrangian"),
        ret_span: Span::call_site(),
        coords,
        time: time.map(|t| format_ident!("{}", t)),
        body: syn::parse_str(body).expect("test body parses"),
        self_token: syn::Token![self](Span::call_site()),
        options: Options {
            mode: Mode::Symbolic,
            mode_span: None,
            lanes: None,
        },
        dissipation: None,
        forces: None,
        constraints: None,
        contacts: None,
        velocity_constraints: None,
        scene: None,
    }
}

/// Evaluates nodes of a derivation at a state with the given field values (by field name).
fn eval(d: &Derivation, params: &[(&str, &[f64])], q: &[f64], v: &[f64], t: f64) -> Vec<f64> {
    let mut flat = Vec::new();
    let mut layout = Vec::new();
    for f in &d.fields {
        let vals = params
            .iter()
            .find(|(n, _)| *n == f.name)
            .map(|(_, v)| *v)
            .expect("test gives every field");
        assert_eq!(vals.len(), if f.vector { 3 } else { 1 }, "field {}", f.name);
        layout.push((flat.len(), f.vector));
        flat.extend_from_slice(vals);
    }
    d.dag.eval_all(&flat, &layout, &[], q, v, t)
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

const HEAVY_TOP: &str = "{
    let (s, c) = theta.sin_cos();
    self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
        + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
        - self.m * self.g * self.l * c
}";

fn heavy_top() -> Decl {
    decl(
        &[
            ("theta", "theta_dot", false),
            ("phi", "phi_dot", false),
            ("psi", "psi_dot", false),
        ],
        None,
        HEAVY_TOP,
    )
}

#[test]
fn folding_and_hash_consing() {
    let mut d = Dag::new(2);
    let x = d.q(0);
    let y = d.v(1);
    let one = d.constant(1.0);
    let zero = d.constant(0.0);
    assert_eq!(d.mul(x, one), x);
    assert_eq!(d.mul(one, x), x);
    assert_eq!(d.add(zero, x), x);
    assert_eq!(d.add(x, zero), x);
    assert_eq!(d.mul(zero, x), Dag::ZERO);
    assert_eq!(d.sub(x, x), Dag::ZERO);
    let a = d.add(x, y);
    let b = d.add(y, x);
    assert_eq!(a, b, "commutative operands are canonically ordered");
    let two = d.constant(2.0);
    let three = d.constant(3.0);
    let six = d.mul(two, three);
    assert_eq!(d.as_const(six), Some(6.0));
    // 2 (3 x) = 6 x
    let tx = d.mul(three, x);
    let st = d.mul(two, tx);
    let sx = d.mul(six, x);
    assert_eq!(st, sx);
    // −(−x) = x, x − (−y) = x + y, x / 2 = 0.5 x
    let nx = d.neg(x);
    assert_eq!(d.neg(nx), x);
    let ny = d.neg(y);
    assert_eq!(d.sub(x, ny), a);
    let half = d.div(x, two);
    assert_eq!(d.node(half), Node::Mul(d.constant(0.5), x));
    // x / 3 stays a division (1/3 is not exact)
    let third = d.div(x, three);
    assert!(matches!(d.node(third), Node::Div(..)));
    // sin(0) folds, (x²)³ = x⁶
    let s0 = d.un(Fun::Sin, zero);
    assert_eq!(s0, Dag::ZERO);
    let x2 = d.powi(x, 2);
    let x6 = d.powi(x2, 3);
    assert_eq!(d.node(x6), Node::Powi(x, 6));
    // Like terms: x + 2x = 3x, 3x − x = 2x, x + x = 2x.
    let twox = d.mul(two, x);
    let threex = d.add(x, twox);
    assert_eq!(d.node(threex), Node::Mul(three, x));
    assert_eq!(d.sub(threex, x), twox);
    assert_eq!(d.add(x, x), twox);
    assert!(d.is_state_free(six));
    assert!(!d.is_state_free(a));
}

/// Like terms of a sum cancel through a parameter factor: p (a·b − c) + p c − a·b p = 0 and
/// 2 (x − y) + p (y + x) − 2 x = (p − 2) y + p x in value; a sum without like terms is returned
/// as it is (same node).
#[test]
fn collect_terms_cancels_through_state_free_factors() {
    let mut d = Dag::new(2);
    let (x, y, p) = (d.q(0), d.v(1), d.param(0, 0));
    let ab = d.mul(x, y);
    let c = d.un(Fun::Sin, x);
    let inner = d.sub(ab, c);
    let t1 = d.mul(p, inner);
    let t2 = d.mul(p, c);
    let t3 = d.mul(ab, p);
    let s = d.add(t1, t2);
    let s = d.sub(s, t3);
    assert_ne!(s, Dag::ZERO, "the local rules alone do not see it");
    assert_eq!(d.collect_terms(s), Dag::ZERO);
    // Numerically the same where terms survive.
    let two = d.constant(2.0);
    let xmy = d.sub(x, y);
    let u = d.mul(two, xmy);
    let ypx = d.add(y, x);
    let v = d.mul(p, ypx);
    let w = d.add(u, v);
    let twox = d.mul(two, x);
    let e = d.sub(w, twox);
    let collected = d.collect_terms(e);
    assert_ne!(collected, e);
    let at = |d: &Dag, id, (xv, yv, pv): (f64, f64, f64)| {
        let mut vals = vec![0.0; d.len()];
        for k in 0..d.len() {
            vals[k] = match d.node(k as Id) {
                Node::Const(b) => f64::from_bits(b),
                Node::Q(0) => xv,
                Node::V(1) => yv,
                Node::Param(..) => pv,
                Node::Add(a, b) => vals[a as usize] + vals[b as usize],
                Node::Sub(a, b) => vals[a as usize] - vals[b as usize],
                Node::Mul(a, b) => vals[a as usize] * vals[b as usize],
                Node::Neg(a) => -vals[a as usize],
                Node::Un(Fun::Sin, a) => vals[a as usize].sin(),
                _ => f64::NAN,
            };
        }
        vals[id as usize]
    };
    for state in [(0.3, -1.2, 2.5), (1.0, 2.0, -0.5)] {
        let (xv, yv, pv) = state;
        let want = (pv - 2.0) * yv + pv * xv;
        assert!((at(&d, collected, state) - want).abs() < 1e-14);
        assert!((at(&d, e, state) - want).abs() < 1e-14);
    }
    // Nothing to cancel: the same node.
    let plain = d.add(ab, c);
    assert_eq!(d.collect_terms(plain), plain);
}

/// Every elementary rule against a central finite difference of the evaluated DAG.
#[test]
fn derivative_rules_match_finite_differences() {
    let mut d = Dag::new(1);
    let x = d.q(0);
    let c = d.constant(0.3);
    let xc = d.add(x, c); // 0.3 + x, positive near the test point
    let half = d.constant(0.5);
    let xh = d.mul(half, x); // inside (−1, 1) for asin/acos
    let mut exprs: Vec<Id> = Vec::new();
    for f in [
        Fun::Sqrt,
        Fun::Sin,
        Fun::Cos,
        Fun::Tan,
        Fun::Exp,
        Fun::Ln,
        Fun::Abs,
        Fun::Sinh,
        Fun::Cosh,
        Fun::Tanh,
        Fun::Atan,
    ] {
        exprs.push(d.un(f, xc));
    }
    exprs.push(d.un(Fun::Asin, xh));
    exprs.push(d.un(Fun::Acos, xh));
    exprs.push(d.powi(xc, -3));
    exprs.push(d.powi(xc, 5));
    let k = d.constant(1.7);
    exprs.push(d.powf(xc, k));
    exprs.push(d.powf(xc, x));
    exprs.push(d.atan2(x, xc));
    exprs.push(d.atan2(xc, k));
    let s = d.un(Fun::Sin, x);
    exprs.push(d.div(s, xc));
    exprs.push(d.mul(s, xc));
    let e = d.un(Fun::Exp, s);
    exprs.push(d.sub(e, xc));
    exprs.push(d.neg(e));
    let mut support = VarSet::new(d.vars);
    support.insert(0);
    let tans = d.tangents(&exprs, &support, &|_, n| {
        (n == Node::Q(0)).then_some(Dag::ONE)
    });
    for x0 in [0.4, 0.9, 1.3] {
        let h = 1e-6;
        let at = |x: f64| d.eval_all(&[], &[], &[], &[x], &[0.0], 0.0);
        let (vp, vm, v0) = (at(x0 + h), at(x0 - h), at(x0));
        for (k, (&e, &t)) in exprs.iter().zip(&tans).enumerate() {
            let fd = (vp[e as usize] - vm[e as usize]) / (2.0 * h);
            let an = v0[t as usize];
            assert!(close(an, fd, 1e-7), "expr {k} at {x0}: {an} vs {fd}");
        }
    }
}

#[test]
fn heavy_top_matches_closed_form() {
    let d = derive(&heavy_top()).expect("derives");
    let (ip, ia, m, g, l) = (2.0, 0.7, 1.3, 9.81, 0.4);
    let params: [(&str, &[f64]); 5] = [
        ("i_perp", &[ip]),
        ("i_par", &[ia]),
        ("m", &[m]),
        ("g", &[g]),
        ("l", &[l]),
    ];
    let q = [0.7, 0.2, -0.4];
    let v = [0.3, -1.1, 2.5];
    let val = eval(&d, &params, &q, &v, 0.0);
    let at = |id: Id| val[id as usize];
    let (s, c) = q[0].sin_cos();
    let (td, pd, sd) = (v[0], v[1], v[2]);
    let big_m = [
        [ip, 0.0, 0.0],
        [0.0, ip * s * s + ia * c * c, ia * c],
        [0.0, ia * c, ia],
    ];
    for i in 0..3 {
        for k in i..3 {
            assert!(close(at(d.mass[i][k]), big_m[i][k], 1e-14), "M[{i}][{k}]");
        }
    }
    // Structural zeros are constants, not computed.
    assert_eq!(d.mass[0][1], Dag::ZERO);
    assert_eq!(d.mass[0][2], Dag::ZERO);
    let w = sd + pd * c;
    let f = [
        ip * pd * pd * s * c - ia * w * pd * s + m * g * l * s,
        -(2.0 * ip * s * c * td * pd - ia * s * td * c * w - ia * c * (-pd * s * td)) + 0.0,
        ia * pd * s * td,
    ];
    // f₁ = −d/dt(∂L/∂φ̇) at fixed q̇ = −(2 I⊥ s c θ̇ φ̇ − I∥ s θ̇ w − I∥ c φ̇ s θ̇)
    let f1 = -(2.0 * ip * s * c * td * pd - ia * s * td * w - ia * c * pd * s * td);
    assert!(close(at(d.force[0]), f[0], 1e-13));
    assert!(close(at(d.force[1]), f1, 1e-13));
    assert!(close(at(d.force[2]), f[2], 1e-13));
    let lval = ip / 2.0 * (td * td + (pd * s).powi(2)) + ia / 2.0 * w * w - m * g * l * c;
    let h = ip / 2.0 * (td * td + (pd * s).powi(2)) + ia / 2.0 * w * w + m * g * l * c;
    assert!(close(at(d.lagrangian), lval, 1e-14));
    assert!(close(at(d.energy), h, 1e-14));
    assert!(close(at(d.momenta[2]), ia * w, 1e-14));
}

/// Mass matrix and right-hand side against finite differences of the DAG's own L, for a system
/// with a vector coordinate, time, vector fields and most of the supported syntax.
#[test]
fn vector_system_matches_finite_differences() {
    let body = "{
        let omega = Vector3::new(0.0, 0.3 * t.sin(), self.w * (1.0 + 0.1 * t.cos()));
        let v = r_dot + self.v0 * t.cos() + omega.cross(&r);
        let mut u = 0.5 * self.k * r.norm_squared();
        u += self.m * self.gravity.dot(&r);
        let (a, _b) = (r.norm(), 2.0);
        self.m / 2.0 * v.norm_squared() - u - self.k2 / (1.0 + a).powi(2) + r.x.atan2(r.y + 3.0) * s_dot.powi(2)
            + (s * r[2]).exp() * 0.01 + std::f64::consts::PI * s_dot * r.z
    }";
    let dcl = decl(
        &[("r", "r_dot", true), ("s", "s_dot", false)],
        Some("t"),
        body,
    );
    let d = derive(&dcl).expect("derives");
    let vector_fields: Vec<&str> = d
        .fields
        .iter()
        .filter(|f| f.vector)
        .map(|f| f.name.as_str())
        .collect();
    assert_eq!(
        vector_fields,
        ["v0", "gravity"],
        "field types are inferred from use"
    );
    let params: [(&str, &[f64]); 6] = [
        ("w", &[0.8]),
        ("v0", &[0.1, -0.2, 0.3]),
        ("k", &[2.0]),
        ("m", &[1.5]),
        ("gravity", &[0.0, 0.0, -9.8]),
        ("k2", &[0.7]),
    ];
    let q0 = [0.3, -0.5, 0.8, 0.2];
    let v0 = [0.4, 0.1, -0.7, 1.2];
    let t0 = 0.6;
    let l_at = |q: &[f64], v: &[f64], t: f64| eval(&d, &params, q, v, t)[d.lagrangian as usize];
    let val = eval(&d, &params, &q0, &v0, t0);
    let h = 1e-5;
    let bump = |x: &[f64], i: usize, e: f64| {
        let mut y = x.to_vec();
        y[i] += e;
        y
    };
    let p_at = |q: &[f64], v: &[f64], t: f64, i: usize| {
        (l_at(q, &bump(v, i, h), t) - l_at(q, &bump(v, i, -h), t)) / (2.0 * h)
    };
    for i in 0..4 {
        let p = p_at(&q0, &v0, t0, i);
        assert!(close(val[d.momenta[i] as usize], p, 1e-7), "p[{i}]");
        for k in i..4 {
            let mk = (p_at(&q0, &bump(&v0, k, h), t0, i) - p_at(&q0, &bump(&v0, k, -h), t0, i))
                / (2.0 * h);
            assert!(close(val[d.mass[i][k] as usize], mk, 1e-5), "M[{i}][{k}]");
        }
        let gq = (l_at(&bump(&q0, i, h), &v0, t0) - l_at(&bump(&q0, i, -h), &v0, t0)) / (2.0 * h);
        // d/dt p along q̇ at fixed q̇: Σₖ q̇ₖ ∂p/∂qₖ + ∂p/∂t
        let mut dp = (p_at(&q0, &v0, t0 + h, i) - p_at(&q0, &v0, t0 - h, i)) / (2.0 * h);
        for (k, vk) in v0.iter().enumerate() {
            dp += vk * (p_at(&bump(&q0, k, h), &v0, t0, i) - p_at(&bump(&q0, k, -h), &v0, t0, i))
                / (2.0 * h);
        }
        assert!(close(val[d.force[i] as usize], gq - dp, 1e-5), "f[{i}]");
    }
}

#[test]
fn heavy_top_equations_read_like_the_hand_derivation() {
    let out = expand(&heavy_top()).unwrap_or_else(|_| panic!("expands"));
    let lines: Vec<&str> = out.equations.lines().collect();
    assert_eq!(lines.len(), 3, "{}", out.equations);
    // θ: I⊥ θ̈ = (I⊥ − I∥) φ̇² sinθ cosθ − I∥ φ̇ ψ̇ sinθ + m g l sinθ
    assert_eq!(
        lines[0],
        "theta: i_perp θ\u{308} = −i_par φ\u{307} ψ\u{307} sin(θ) + (i_perp − i_par) φ\u{307}² sin(θ) cos(θ) + m g l sin(θ)",
        "{}",
        out.equations
    );
    // ψ: d/dt [I∥ (ψ̇ + φ̇ cos θ)] = 0
    assert_eq!(
        lines[2], "psi: i_par φ\u{308} cos(θ) + i_par ψ\u{308} = i_par θ\u{307} φ\u{307} sin(θ)",
        "{}",
        out.equations
    );
    // φ: d/dt [I⊥ φ̇ sin²θ + I∥ (ψ̇ + φ̇ cos θ) cos θ] = 0
    assert_eq!(
        lines[1],
        "phi: i_perp φ\u{308} sin²(θ) + i_par φ\u{308} cos²(θ) + i_par ψ\u{308} cos(θ) \
         = 2 (i_par − i_perp) θ\u{307} φ\u{307} sin(θ) cos(θ) + i_par θ\u{307} ψ\u{307} sin(θ)",
        "{}",
        out.equations
    );
    assert!(
        out.equations_latex.contains("\\ddot{\\theta}"),
        "{}",
        out.equations_latex
    );
    assert!(out.doc.contains(&out.equations));
}

#[test]
fn no_unit_factors_or_zero_terms_in_print() {
    let dcl = decl(
        &[("x", "x_dot", false)],
        None,
        "{ 1.0 * self.m / 2.0 * x_dot.powi(2) + 0.0 * x - 0.5 * self.k * x * x * 1.0 }",
    );
    let out = expand(&dcl).unwrap_or_else(|_| panic!("expands"));
    assert_eq!(out.equations, "x: m x\u{308} = −k x");
    assert_eq!(out.equations_latex, "m \\ddot{x} = -k x");
}

fn errors(body: &str) -> Vec<String> {
    let dcl = decl(&[("x", "x_dot", false)], None, body);
    match expand(&dcl) {
        Ok(_) => Vec::new(),
        Err(e) => e.into_iter().map(|e| e.to_string()).collect(),
    }
}

#[test]
fn unsupported_constructs_say_use_jets() {
    for (body, what) in [
        (
            "{ let mut s = 0.0; while s < 3.0 { s += x; } s }",
            "a `while` loop",
        ),
        ("{ helper(x) * x_dot }", "a call to the function `helper`"),
        ("{ x.frobnicate() * x_dot }", "the method `.frobnicate()`"),
        ("{ match 1 { _ => x } }", "`match`"),
        ("{ loop { break x; } }", "a `loop`"),
        ("{ println!(\"hi\"); x_dot }", "a macro call"),
        (
            "{ x.powi(x_dot as i32) }",
            "a `powi` exponent that depends on the state",
        ),
    ] {
        let errs = errors(body);
        assert_eq!(errs.len(), 1, "{body}: {errs:?}");
        assert!(errs[0].starts_with(what), "{body}: {errs:?}");
        assert!(errs[0].contains("mode = \"jets\""), "{body}: {errs:?}");
    }
    // Errors accumulate.
    assert_eq!(errors("{ a(x) + x.foo() + b(x_dot) }").len(), 3);
}

/// `step_by(0)` is refused with a sentence that says what is wrong and what to do (it was the
/// bare words "`step_by(0)`").
#[test]
fn step_by_zero_says_what_is_wrong() {
    let e = errors("{ let mut s = x_dot * x_dot; for k in (0..3).step_by(0) { s = s + x; } s }");
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].contains("never advances") && e[0].contains("k ≥ 1"),
        "{e:?}"
    );
}

#[test]
fn unrolling_and_inlining_stop_at_the_budget_fast() {
    // 2⁴⁰ inlined calls and 10⁶ loop iterations: the lowering ran for minutes (94 s and 4.9 GB
    // for the loops) before the budget; now one error at the call or loop that crosses it.
    for (body, what) in [
        (
            "{ fn grow(x: Scalar, n: usize) -> Scalar { \
                 if n == 0 { x } else { grow(x, n - 1) + grow(x, n - 1) } \
               } \
               0.5 * x_dot * x_dot - grow(x, 40) }",
            "this call of the function `grow`",
        ),
        (
            "{ let mut v = 0.0 * x; \
               for i in 0..1000 { for j in 0..1000 { v += ((i + j) as f64) * x; } } \
               0.5 * x_dot * x_dot - v }",
            "this loop",
        ),
        (
            "{ let f = |a: Scalar| a * 1.5; \
               let s: Scalar = (0..1000).map(|i| (0..1000).map(|j| f(x)).sum::<Scalar>()).sum(); \
               0.5 * x_dot * x_dot - s }",
            "this call of this closure",
        ),
    ] {
        let start = std::time::Instant::now();
        let errs = errors(body);
        let took = start.elapsed();
        assert_eq!(errs.len(), 1, "{body}: {errs:?}");
        assert!(errs[0].starts_with(what), "{body}: {errs:?}");
        assert!(
            errs[0].contains("100000 loop iterations and inlined calls"),
            "{errs:?}"
        );
        assert!(errs[0].contains("mode = \"jets\""), "{errs:?}");
        assert!(took.as_secs_f64() < 3.0, "{body}: {took:?}");
    }
    // The budget counts loop iterations and calls: 4 + 4 × 24 999 = 100 000 is within it, one
    // more iteration of the inner loop is not.
    let at =
        |n: usize| format!("{{ for i in 0..4 {{ for j in 0..{n} {{}} }} 0.5 * x_dot * x_dot }}");
    assert_eq!(errors(&at(24_999)), Vec::<String>::new());
    let errs = errors(&at(25_000));
    assert!(
        errs.len() == 1 && errs[0].starts_with("this loop goes past"),
        "{errs:?}"
    );
}

#[test]
fn type_errors_are_reported_not_panicked() {
    let e = errors("{ Vector3::new(x, x, x) * Vector3::new(x_dot, 0.0, 0.0) }");
    assert!(e[0].contains("cannot be multiplied"), "{e:?}");
    let e = errors("{ Vector3::new(x, x, x) }");
    assert!(e[0].contains("must be a scalar"), "{e:?}");
    let e = errors("{ x.norm() }");
    assert!(e[0].contains("must be a Vector3"), "{e:?}");
}

#[test]
fn emitted_code_is_straight_line_and_shares_subexpressions() {
    let out = expand(&heavy_top()).unwrap_or_else(|_| panic!("expands"));
    let acc = accelerations_code(&out);
    assert!(acc.contains("solve_mass_matrix"));
    // sin θ and cos θ are computed once, together.
    assert_eq!(acc.matches(". sin_cos ()").count(), 1, "{acc}");
    assert_eq!(acc.matches(". sin ()").count(), 0, "{acc}");
    assert_eq!(acc.matches(". cos ()").count(), 0, "{acc}");
    assert!(
        acc.contains("let __lagrange_p_i_perp : f64 = self . i_perp ;"),
        "{acc}"
    );
    assert!(!acc.contains("* 1.0"), "{acc}");
}

/// The code of q̈: the method's body, the parameters' loads from `self` and the generic kernel
/// (the kernels module up to its Taylor series).
fn accelerations_code(out: &SymbolicOutput) -> String {
    let items = out.items.to_string();
    let kernel = items
        .split("pub (super) fn series")
        .next()
        .unwrap_or_default();
    let load = out
        .params
        .as_ref()
        .map(|p| p.0.to_string())
        .unwrap_or_default();
    format!("{} {load} {kernel}", out.accelerations)
}

/// The N-link chain of `chain!` in examples/support/systems.rs, built as source text.
fn chain_decl(n: usize) -> Decl {
    let mut body = String::from("{");
    for k in 1..=n {
        body += &format!("let (s{k}, c{k}) = th{k}.sin_cos();");
        if k == 1 {
            body += "let mut vx = self.l * c1 * th1_dot; let mut vy = self.l * s1 * th1_dot;";
            body += "let mut y = -self.l * c1;";
            body += "let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;";
        } else {
            body += &format!(
                "vx += self.l * c{k} * th{k}_dot; vy += self.l * s{k} * th{k}_dot; y -= self.l * c{k};"
            );
            body += "lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;";
        }
    }
    body += "lag }";
    let names: Vec<(String, String)> = (1..=n)
        .map(|k| (format!("th{k}"), format!("th{k}_dot")))
        .collect();
    let coords: Vec<(&str, &str, bool)> = names
        .iter()
        .map(|(a, b)| (a.as_str(), b.as_str(), false))
        .collect();
    decl(&coords, None, &body)
}

/// Scale: the N = 16 chain expands in well under 5 s; prints the expansion time and
/// the generated size (`cargo test -p lagrange-macros --release chain_16 -- --nocapture`).
#[test]
fn chain_16_expands_fast_and_compactly() {
    let dcl = chain_decl(16);
    let start = std::time::Instant::now();
    let out = expand(&dcl).unwrap_or_else(|_| panic!("expands"));
    let elapsed = start.elapsed();
    let tokens: usize = [
        &out.accelerations,
        &out.mass_matrix,
        &out.momenta,
        &out.energy,
    ]
    .iter()
    .map(|t| t.to_string().len())
    .sum();
    println!(
        "N=16 chain: expand {:.1} ms, {} lets, {} bytes of generated bodies, equations {} bytes",
        elapsed.as_secs_f64() * 1e3,
        out.generated_lets,
        tokens,
        out.equations.len()
    );
    assert!(elapsed.as_secs_f64() < 5.0, "{elapsed:?}");
    // CSE keeps it near O(N²) per method: far from the O(N³) of an unshared expansion.
    assert!(out.generated_lets < 20_000, "{}", out.generated_lets);
    assert_eq!(out.equations.lines().count(), 16);
}

/// A large system: `accelerations` calls `pieces` (one copy of M and f), whose bodies are
/// functions in modules next to the impl (M, the right-hand side, the energy), every local
/// defined before it is read.
#[test]
fn large_bodies_go_out_of_line_in_dependency_order() {
    let out = expand(&chain_decl(40)).unwrap_or_else(|_| panic!("expands"));
    let acc = out.accelerations.to_string();
    assert!(acc.contains("pieces (self"), "{acc}");
    assert!(!acc.contains("sin_cos"), "{acc}");
    let pieces = out.pieces.to_string();
    assert!(!pieces.contains("sin_cos"), "{pieces}");
    let items = out.items.to_string();
    let modules: Vec<&str> = items
        .split("mod ")
        .skip(1)
        .filter_map(|m| m.split_whitespace().next())
        .collect();
    // M, the right-hand side and the energy.
    assert_eq!(modules.len(), 3, "{modules:?}");
    for (m, suffix) in modules.iter().zip(["_mass", "_force", "_energy"]) {
        assert!(m.starts_with("__lagrange_X_") && m.ends_with(suffix), "{m}");
        assert!(
            pieces.contains(m) || out.energy_and_momenta.to_string().contains(m),
            "{m}"
        );
    }
    // Each body binds its values level by level, each after the values it reads.
    for body in items.split("mod ").skip(1) {
        assert!(!body.contains("debug_assertions"));
        let mut defined = std::collections::HashSet::new();
        for stmt in body.split(" let ").skip(1) {
            let (lhs, rest) = stmt
                .split_once(" = ")
                .unwrap_or_else(|| panic!("a let: {stmt}"));
            let rhs = rest.split(';').next().unwrap_or_default();
            for used in rhs.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
                if used.starts_with("__lagrange_x") {
                    assert!(defined.contains(used), "{used} read before its let: {lhs}");
                }
            }
            for name in lhs.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
                if name.starts_with("__lagrange_x") {
                    defined.insert(name.to_string());
                }
            }
        }
        assert!(defined.len() > 2000, "{}", defined.len());
    }
    // Small systems: everything in the methods and the generic kernels, no out-of-line body.
    let small = expand(&chain_decl(4)).unwrap_or_else(|_| panic!("expands"));
    let items = small.items.to_string();
    assert!(
        items.contains("_kernels") && !items.contains("fn eval"),
        "{items}"
    );
}

/// Small right-hand sides are `#[inline(always)]` (every stage of an integrator inlines them);
/// large ones are left to LLVM.
#[test]
fn small_accelerations_are_always_inlined_large_ones_are_not() {
    let inline = |d: &Decl| {
        let out = expand(d).unwrap_or_else(|_| panic!("expands"));
        out.accelerations_inline.to_string().replace(' ', "")
    };
    assert_eq!(inline(&heavy_top()), "#[inline(always)]");
    assert_eq!(inline(&chain_decl(2)), "#[inline(always)]");
    assert_eq!(inline(&chain_decl(16)), "#[inline]");
}

#[test]
fn constant_if_becomes_a_select_on_a_runtime_bool() {
    let body = "{
        let f = if self.k > 0.0 { self.k * x * x } else { 0.0 * x };
        let mut l = 0.5 * x_dot * x_dot - f;
        if self.k > 0.0 { l += x_dot * x; } else if K_MAX < 2.0 { l -= x.sin(); }
        l
    }";
    let dcl = decl(&[("x", "x_dot", false)], None, body);
    let out = expand(&dcl).unwrap_or_else(|e| panic!("expands: {:?}", e[0].to_string()));
    let acc = accelerations_code(&out);
    // One bool per distinct condition, loaded as written; selects on it.
    assert_eq!(
        acc.matches("let __lagrange_b_0 : bool = self . k > 0.0 ;")
            .count(),
        1,
        "{acc}"
    );
    assert_eq!(
        acc.matches("let __lagrange_b_1 : bool = K_MAX < 2.0 ;")
            .count(),
        1,
        "{acc}"
    );
    assert!(acc.contains("if __lagrange_b_0 {"), "{acc}");
    assert!(acc.contains("select (__lagrange_b_0 ,"), "{acc}");
    // ẋ x is a total derivative (its force contribution cancels); the spring −2kx and the −cos x
    // of −sin x survive in their branches.
    assert!(
        out.equations.contains("if k > 0.0 else"),
        "{}",
        out.equations
    );
    assert!(
        out.equations.contains("if K_MAX < 2.0 else"),
        "{}",
        out.equations
    );
    assert!(
        out.equations_latex.contains("\\texttt{k > 0.0}"),
        "{}",
        out.equations_latex
    );
    // Numerically: both branches, against the hand-derived force.
    let d = derive(&dcl).unwrap_or_else(|_| panic!("derives"));
    let mut flat = Vec::new();
    let mut layout = Vec::new();
    for (kk, f) in d.fields.iter().enumerate() {
        layout.push((kk, false));
        flat.push(if f.name == "k" { 3.0 } else { 1.0 });
    }
    for (b0, b1) in [(true, true), (false, true), (false, false)] {
        let x = 0.4;
        let v = d.dag.eval_all(&flat, &layout, &[b0, b1], &[x], &[0.9], 0.0);
        let want = if b0 {
            -2.0 * 3.0 * x
        } else if b1 {
            -x.cos()
        } else {
            0.0
        };
        assert!(close(v[d.force[0] as usize], want, 1e-14), "{b0} {b1}");
        assert!(close(v[d.mass[0][0] as usize], 1.0, 1e-14));
    }
}

#[test]
fn state_dependent_if_says_why_and_use_jets() {
    for (body, name, what) in [
        (
            "{ if x > 0.0 { x } else { x_dot } }",
            "x",
            "a generalized coordinate",
        ),
        (
            "{ if x_dot.abs() > 1.0 { x } else { 0.0 * x } }",
            "x_dot",
            "a generalized velocity",
        ),
        (
            "{ let e = x_dot * x_dot; if e > self.k { e } else { x } }",
            "e",
            "a local binding",
        ),
    ] {
        let e = errors(body);
        assert_eq!(e.len(), 1, "{e:?}");
        assert!(e[0].contains(&format!("uses `{name}`, {what}")), "{e:?}");
        assert!(e[0].contains("mode = \"jets\""), "{e:?}");
    }
    // Method names and `self` fields are not mistaken for bindings.
    assert!(errors("{ let k = x; if self.k.abs() > 0.0 { k } else { x_dot } }").is_empty());
}

#[test]
fn scalar_constant_conversions_are_the_identity_on_constants() {
    let body = "{
        let a = Scalar::constant(self.k);
        let b = Scalar::from(2.0);
        let c = <Scalar as From<f64>>::from(self.k * 3.0);
        a * x_dot * x_dot + b * x + c
    }";
    let dcl = decl(&[("x", "x_dot", false)], None, body);
    let d = derive(&dcl).unwrap_or_else(|e| panic!("derives: {}", e[0]));
    let v = d
        .dag
        .eval_all(&[0.5], &[(0, false)], &[], &[0.3], &[0.7], 0.0);
    assert!(close(v[d.mass[0][0] as usize], 1.0, 1e-15));
    assert!(close(v[d.force[0] as usize], 2.0, 1e-15));
    assert!(close(
        v[d.lagrangian as usize],
        0.5 * 0.49 + 0.6 + 1.5,
        1e-15
    ));
    let e = errors("{ Scalar::constant(x) * x_dot }");
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(e[0].contains("depends on the coordinates"), "{e:?}");
}

/// The heavy top's φ–ψ block is decoupled from θ: it is solved as a pair whose determinant
/// (I⊥ s² + I∥ c²) I∥ − (I∥ c)² cancels at expansion to the single monomial I⊥ I∥ s².
#[test]
fn decoupled_pair_determinant_cancels_to_a_monomial() {
    let d = derive(&heavy_top()).expect("derives");
    assert_eq!(d.pairs.len(), 1);
    let (i, k, det, exact) = d.pairs[0];
    assert_eq!((i, k), (1, 2));
    assert!(exact, "one monomial: accurate however small");
    let p = super::poly::expand(&d.dag, det).expect("small");
    assert_eq!(p.len(), 1, "{p:?}");
    // And it is the determinant, to round-off, where the unexpanded form is still accurate.
    let (ip, ia) = (2.0, 0.7);
    let params: [(&str, &[f64]); 5] = [
        ("i_perp", &[ip]),
        ("i_par", &[ia]),
        ("m", &[1.3]),
        ("g", &[9.81]),
        ("l", &[0.4]),
    ];
    let q = [0.7, 0.2, -0.4];
    let val = eval(&d, &params, &q, &[0.3, -1.1, 2.5], 0.0);
    let s = q[0].sin();
    assert!(close(val[det as usize], ia * ip * s * s, 1e-15));
}

/// Where nothing cancels (the double pendulum's 2×2 M: the cross term is a cos(θ₁ − θ₂)
/// written as c₁c₂ + s₁s₂) the determinant is kept as m₁₁m₂₂ − m₁₂², not expanded into more terms.
#[test]
fn pair_determinant_without_cancellation_is_kept_as_written() {
    let d = derive(&chain_decl(2)).expect("derives");
    assert_eq!(d.pairs.len(), 1);
    let (det, exact) = (d.pairs[0].2, d.pairs[0].3);
    assert!(!exact);
    assert!(
        matches!(d.dag.node(det), Node::Sub(..)),
        "{:?}",
        d.dag.node(det)
    );
}

/// Expansion gives up (None) on too many terms or too deep an expression instead of blowing up.
#[test]
fn polynomial_expansion_is_bounded() {
    let mut dag = Dag::new(1);
    let x = dag.q(0);
    let v = dag.v(0);
    // (x + v)^4 = 5 terms: fine; a product of six binomials in distinct atoms, 64 terms: None.
    let s = dag.add(x, v);
    let p4 = dag.powi(s, 4);
    assert_eq!(super::poly::expand(&dag, p4).map(|p| p.len()), Some(5));
    let mut big = Dag::ONE;
    for k in 0..6 {
        let c = dag.constant(f64::from(k) + 2.0);
        let kx = dag.mul(c, x);
        let (sk, ck) = (dag.un(Fun::Sin, kx), dag.un(Fun::Cos, kx));
        let sum = dag.add(sk, ck);
        big = dag.mul(big, sum);
    }
    assert!(super::poly::expand(&dag, big).is_none());
    // A sum nested deeper than the bound.
    let mut deep = x;
    for _ in 0..100 {
        let sin = dag.un(Fun::Sin, deep);
        deep = dag.add(sin, v);
    }
    let mut chain = v;
    for _ in 0..100 {
        chain = dag.add(chain, deep);
        chain = dag.mul(chain, x);
    }
    assert!(super::poly::expand(&dag, chain).is_none());
}

/// `fn dissipation` or `fn forces` with bindings `(coordinate, velocity)` (`None`: `_`).
fn func(
    kind: crate::model::FuncKind,
    bindings: &[(Option<&str>, Option<&str>)],
    time: Option<&str>,
    body: &str,
) -> crate::model::Func {
    crate::model::Func {
        kind,
        fn_attrs: Vec::new(),
        fn_ident: format_ident!("{}", kind.user_name()),
        ret_span: Span::call_site(),
        bindings: bindings
            .iter()
            .map(|(c, v)| {
                (
                    c.map(|c| format_ident!("{}", c)),
                    v.map(|v| format_ident!("{}", v)),
                )
            })
            .collect(),
        time: time.map(|t| format_ident!("{}", t)),
        body: syn::parse_str(body).expect("test body parses"),
        self_token: syn::Token![self](Span::call_site()),
        k: 0,
        affine: false,
    }
}

fn driven_pendulum() -> Decl {
    use crate::model::FuncKind;
    let mut d = decl(
        &[("theta", "theta_dot", false)],
        None,
        "{ 0.5 * self.m * self.l * self.l * theta_dot.powi(2) + self.m * self.g * self.l * theta.cos() }",
    );
    d.dissipation = Some(func(
        FuncKind::Dissipation,
        &[(None, Some("w_dot"))],
        None,
        "{ 0.5 * self.b * w_dot.powi(2) }",
    ));
    d.forces = Some(func(
        FuncKind::Forces,
        &[(Some("th"), None)],
        Some("time"),
        "{ let drive = self.a * (self.w * time).cos(); [drive] }",
    ));
    d
}

#[test]
fn forces_and_dissipation_join_the_right_hand_side_and_the_print() {
    let d = driven_pendulum();
    let out = expand(&d).expect("derives");
    assert_eq!(
        out.equations,
        "theta: m l² θ̈ = −m l g sin(θ) + a cos(w t) − b θ̇"
    );
    assert_eq!(
        out.equations_latex,
        "m l^{2} \\ddot{\\theta} = -m l g \\sin\\left(\\theta\\right) + a \\cos\\left(w t\\right) - b \\dot{\\theta}"
    );
    let der = derive(&d).expect("derives");
    let (m, l, g, b, a, w) = (1.3, 0.7, 9.8, 0.4, 1.1, 2.3);
    let params: [(&str, &[f64]); 6] = [
        ("m", &[m]),
        ("l", &[l]),
        ("g", &[g]),
        ("b", &[b]),
        ("a", &[a]),
        ("w", &[w]),
    ];
    let (q, v, t) = (0.9, -1.7, 3.1);
    let val = eval(&der, &params, &[q], &[v], t);
    let applied = a * (w * t).cos() - b * v;
    let f_l = -m * g * l * q.sin();
    assert!(close(val[der.force[0] as usize], f_l, 1e-14));
    assert!(close(val[der.applied[0] as usize], applied, 1e-14));
    assert!(close(val[der.rhs[0] as usize], f_l + applied, 1e-14));
    assert!(close(val[der.power as usize], applied * v, 1e-14));
}

#[test]
fn without_forces_the_right_hand_side_is_f_l_and_the_power_zero() {
    let d = derive(&heavy_top()).expect("derives");
    assert_eq!(d.rhs, d.force);
    assert!(d.applied.iter().all(|&a| a == Dag::ZERO));
    assert_eq!(d.power, Dag::ZERO);
}

#[test]
fn forces_not_ending_in_an_array_literal_say_use_jets() {
    let mut d = driven_pendulum();
    if let Some(f) = &mut d.forces {
        f.body = syn::parse_str("{ let q = [self.a]; q }").expect("parses");
    }
    let errs: Vec<String> = match expand(&d) {
        Ok(_) => panic!("must not derive"),
        Err(e) => e.iter().map(ToString::to_string).collect(),
    };
    assert!(
        errs.iter().any(
            |e| e.contains("does not end in an array literal") && e.contains("mode = \"jets\"")
        ),
        "{errs:?}"
    );
}

/// The printed equations merge sin² + cos² = 1 pairs and the products that are a sine or cosine
/// of a difference: the chain's first mass entry is Σ m l² (sin² θ₁ + cos² θ₁) = 3 m l², its
/// couplings cos(θ₁ − θ₂), while a lone cos² (the heavy top's I∥ cos²θ) stays as written.
#[test]
fn printed_equations_merge_sin_squared_plus_cos_squared() {
    let out = expand(&chain_decl(3)).unwrap_or_else(|_| panic!("expands"));
    let first = out.equations.lines().next().unwrap_or_default();
    assert!(first.starts_with("th1: 3 l² m d²(th₁)/dt² + "), "{first}");
    assert!(!first.contains("sin²(th₁)"), "{first}");
    // …and sin a sin b + cos a cos b = cos(a − b), sin a cos b − cos a sin b = sin(a − b): the
    // textbook form of the chain (checked against the hand derivation of a triple pendulum).
    assert_eq!(
        first,
        "th1: 3 l² m d²(th₁)/dt² + 2 l² m d²(th₂)/dt² cos(th₁ − th₂) + l² m d²(th₃)/dt² cos(th₁ − th₃) \
         = −2 l² m (d(th₂)/dt)² sin(th₁ − th₂) − l² m (d(th₃)/dt)² sin(th₁ − th₃) − 3 l m g sin(th₁)"
    );
    // The 10-link chain of the issue (its first equation started `10 l² m q̈[0] sin²(q[0]) +
    // 10 l² m q̈[0] cos²(q[0]) + …`): no pair is left anywhere in it.
    let ten = expand(&chain_decl(10)).unwrap_or_else(|_| panic!("expands"));
    let first = ten.equations.lines().next().unwrap_or_default();
    assert!(first.starts_with("th1: 10 l² m d²(th₁)/dt² + "), "{first}");
    assert!(
        !first.contains("sin²") && !first.contains("cos²"),
        "{first}"
    );
    let top = expand(&heavy_top()).unwrap_or_else(|_| panic!("expands"));
    assert!(
        top.equations.contains("i_par φ\u{308} cos²(θ)"),
        "{}",
        top.equations
    );
}

/// The generated code uses sin² + cos² = 1 too: the chain's M₀₀ = Σ m l² (sin² θ₁ + cos² θ₁) is
/// one term, 3 m l², in the DAG the code is emitted from (its value that to round-off).
#[test]
fn mass_entries_merge_sin_squared_plus_cos_squared() {
    let d = derive(&chain_decl(3)).unwrap_or_else(|_| panic!("derives"));
    let p = super::poly::expand(&d.dag, d.mass[0][0]).expect("small");
    assert_eq!(p.len(), 1, "{p:?}");
    let mut flat = Vec::new();
    let mut layout = Vec::new();
    for (k, f) in d.fields.iter().enumerate() {
        layout.push((k, false));
        flat.push(match f.name.as_str() {
            "l" => 0.7,
            "m" => 1.3,
            _ => 9.81,
        });
    }
    let v = d
        .dag
        .eval_all(&flat, &layout, &[], &[0.3, -0.4, 1.1], &[0.0; 3], 0.0);
    assert!(close(
        v[d.mass[0][0] as usize],
        3.0 * 1.3 * 0.7 * 0.7,
        1e-15
    ));
}

/// A small deterministic generator (xorshift) for the random bodies below.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.below(1 << 53) as f64 / (1u64 << 53) as f64)
    }
}

/// A random expression over `a`, `a_dot`, `b_dot`, constants and, if `free_b`, `b` itself; `b`
/// also enters through identities that hide it (sin² b + cos² b, a rotation by b of a pair).
fn random_expr(rng: &mut Rng, depth: u32, free_b: bool) -> String {
    let atoms: &[&str] = if free_b {
        &["a", "b", "a_dot", "b_dot", "1.3", "0.5"]
    } else {
        &["a", "a_dot", "b_dot", "1.3", "0.5"]
    };
    if depth == 0 {
        return atoms[rng.below(atoms.len() as u64) as usize].to_string();
    }
    let sub = |rng: &mut Rng| random_expr(rng, depth - 1, free_b);
    match rng.below(9) {
        0 => format!("({} + {})", sub(rng), sub(rng)),
        1 => format!("({} - {})", sub(rng), sub(rng)),
        2 | 3 => format!("({} * {})", sub(rng), sub(rng)),
        4 => format!("({}).sin()", sub(rng)),
        5 => format!("({}).cos()", sub(rng)),
        6 => format!("((b.sin().powi(2) + b.cos().powi(2)) * {})", sub(rng)),
        7 => {
            let x = sub(rng);
            format!("((b.sin() * {x}).powi(2) + (b.cos() * {x}).powi(2))")
        }
        _ => {
            let (x, y) = (sub(rng), sub(rng));
            format!(
                "((b.cos() * {x} - b.sin() * {y}).powi(2) + (b.sin() * {x} + b.cos() * {y}).powi(2))"
            )
        }
    }
}

/// ∂L/∂b by central differences of the DAG's value of L.
fn dl_db(d: &Derivation, q: [f64; 2], v: [f64; 2]) -> (f64, f64) {
    let h = 1e-6;
    let at = |b: f64| eval(d, &[], &[q[0], b], &v, 0.0)[d.lagrangian as usize];
    ((at(q[1] + h) - at(q[1] - h)) / (2.0 * h), at(q[1]))
}

/// `CYCLIC` from the expression: a coordinate that leaves L only through an identity is found
/// cyclic, and one that does not cancel is never flagged (random bodies, checked against finite
/// differences at random states).
#[test]
fn cyclic_from_the_expression_never_flags_a_coordinate_l_depends_on() {
    let coords = [("a", "a_dot", false), ("b", "b_dot", false)];
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut flagged, mut kept) = (0, 0);
    for round in 0..400 {
        let free_b = round % 2 == 1;
        // Depth 2 where b hides in identities keeps the expansions within the caps; depth 3
        // for the bodies that depend on b.
        let depth = if free_b { 3 } else { 2 };
        let body = format!("{{ {} }}", random_expr(&mut rng, depth, free_b));
        let d = derive(&decl(&coords, None, &body)).unwrap_or_else(|e| panic!("{body}: {e:?}"));
        let cyclic = d.symmetry.cyclic[1];
        if !free_b {
            // b only inside identities: always found (the bodies are well within the caps).
            assert!(
                cyclic,
                "b leaves L only through identities, not flagged: {body}"
            );
        }
        if cyclic {
            flagged += 1;
            for _ in 0..5 {
                let q = [rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5)];
                let v = [rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5)];
                let (g, l) = dl_db(&d, q, v);
                // The derivative is 0; the differences carry rounding ~1e-16 |L| / 1e-6.
                assert!(
                    g.abs() <= 1e-7 * (1.0 + l.abs()),
                    "b flagged cyclic, but ∂L/∂b = {g} at q = {q:?}, q̇ = {v:?}: {body}"
                );
            }
        } else {
            kept += 1;
        }
        assert_eq!(
            d.symmetry.momentum_conserved[1], cyclic,
            "without forces the momentum is conserved exactly when the coordinate is cyclic"
        );
    }
    // Both answers occur (the test is not vacuous).
    assert!(
        flagged >= 200 && kept >= 50,
        "flagged {flagged}, kept {kept}"
    );
}

/// The heavy top written from its body angular velocity under R = R_z(φ) R_x(θ) R_z(ψ): ψ and φ
/// appear in L but leave it through sin² + cos² = 1, so both are cyclic, θ is not, and L is
/// autonomous.
#[test]
fn heavy_top_from_its_rotation_has_cyclic_phi_and_psi() {
    let body = "{
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = psi.sin_cos();
        let wx = phi_dot * st * sp + theta_dot * cp;
        let wy = phi_dot * st * cp - theta_dot * sp;
        let wz = phi_dot * ct + psi_dot;
        let (s1, c1) = phi.sin_cos();
        let up = (s1 * s1 + c1 * c1) * ct;
        0.5 * (1.3 * (wx * wx + wy * wy) + 0.7 * wz * wz) - 3.5 * up
    }";
    let coords = [
        ("theta", "theta_dot", false),
        ("phi", "phi_dot", false),
        ("psi", "psi_dot", false),
    ];
    let d = derive(&decl(&coords, None, body)).expect("derives");
    assert_eq!(d.symmetry.cyclic, [false, true, true]);
    assert_eq!(d.symmetry.momentum_conserved, [false, true, true]);
    assert!(d.symmetry.autonomous && d.symmetry.energy_conserved);
}

/// The Taylor series' explicit accelerations of the heavy top: θ̈ = f_θ / I⊥, φ̈ by Cramer's rule
/// with sin θ cancelled against the determinant I⊥ I∥ sin²θ (the quotient divides by a monomial
/// of sin θ to the first power), ψ̈ by back substitution; all three equal the closed form, also
/// at θ = 1e-7 where the unsimplified quotient would divide by ~1e-14.
#[test]
fn explicit_accelerations_of_the_heavy_top_are_its_closed_form() {
    let mut d = derive(&heavy_top()).expect("derives");
    let mut dag = d.dag.clone();
    let e = super::explicit::accelerations(&mut dag, &d).expect("block diagonal, exact pair");
    assert_eq!(e.accel.len(), 3);
    // φ̈ = (θ̇ · (…)) / (I⊥ · sin θ): the divisor is one monomial with sin θ to the first power.
    let Node::Div(_, den) = dag.node(e.accel[1]) else {
        panic!("{:?}", dag.node(e.accel[1]));
    };
    let p = super::poly::expand(&dag, den).expect("small");
    let (mono, _) = p.single().expect("one monomial");
    let sines: Vec<i32> = mono
        .iter()
        .filter(|&&(a, _)| matches!(dag.node(a), Node::Un(Fun::Sin, _)))
        .map(|&(_, e)| e)
        .collect();
    assert_eq!(sines, [1], "{mono:?}");
    let accel = e.accel.clone();
    d.dag = dag;
    let (ip, ia, m, g, l) = (2.0, 0.7, 1.3, 9.81, 0.4);
    let params: [(&str, &[f64]); 5] = [
        ("i_perp", &[ip]),
        ("i_par", &[ia]),
        ("m", &[m]),
        ("g", &[g]),
        ("l", &[l]),
    ];
    for theta in [0.7, -2.1, 1e-7] {
        let (q, v) = ([theta, 0.2, -0.4], [0.3, -1.1, 2.5]);
        let val = eval(&d, &params, &q, &v, 0.0);
        let (s, c) = theta.sin_cos();
        let w3 = v[2] + v[1] * c;
        let th = (ip * v[1] * v[1] * s * c - ia * w3 * v[1] * s + m * g * l * s) / ip;
        let ph = (ia * w3 * v[0] - 2.0 * ip * v[1] * v[0] * c) / (ip * s);
        let ps = v[1] * v[0] * s - ph * c;
        for (k, want) in [th, ph, ps].into_iter().enumerate() {
            let got = val[accel[k] as usize];
            assert!(
                close(got, want, 1e-13),
                "θ = {theta}: q̈[{k}] = {got} vs {want}"
            );
        }
    }
}

/// A coupled block of three (a triple pendulum's full M) has no explicit accelerations: its
/// series solves M₀ a_k = b_k order by order.
#[test]
fn a_coupled_block_of_three_has_no_explicit_accelerations() {
    let d = derive(&chain_decl(3)).expect("derives");
    let mut dag = d.dag.clone();
    assert!(super::explicit::accelerations(&mut dag, &d).is_none());
}

/// A rotation composed of 40 pairs of elementary rotations and differentiated by
/// `body_angular_velocity` (86 000 generated operations; 60 pairs took rustc 41 s and 4 GB) is
/// refused past the budget with the advice to use the jets mode, at the body; 10 pairs
/// (20 561 operations) expand.
#[test]
fn generated_code_past_the_budget_says_use_jets() {
    let body = |n: usize| {
        format!(
            "{{ let mut r = Rotation::about_z(a); \
               for _k in 0..{n} {{ r = r * Rotation::about_x(b) * Rotation::about_z(c); }} \
               let w = body_angular_velocity(&r); \
               0.5 * (w.x * w.x + w.y * w.y + 2.0 * w.z * w.z) - (r * Vector3::z()).z }}"
        )
    };
    let coords = [
        ("a", "a_dot", false),
        ("b", "b_dot", false),
        ("c", "c_dot", false),
    ];
    let small = expand(&decl(&coords, None, &body(10))).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(small.generated_lets < MAX_GENERATED_LETS);
    let errs: Vec<String> = match expand(&decl(&coords, None, &body(40))) {
        Ok(out) => panic!("expanded {} operations", out.generated_lets),
        Err(e) => e.iter().map(ToString::to_string).collect(),
    };
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert!(
        errs[0].contains("operations of straight-line code") && errs[0].contains("mode = \"jets\""),
        "{errs:?}"
    );
}
