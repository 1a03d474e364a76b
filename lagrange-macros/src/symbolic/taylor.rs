//! Emission of `fn taylor_series`: the Taylor coefficients of the motion, order by order, from
//! the recurrences of every node the equations of motion need (the kernels of the runtime's
//! `taylor` module), and the order-by-order solve M₀ a_k = f_k − Σ M_j a_{k−j}.
//!
//! The program is built on a copy of the derivation's DAG, because some rules need nodes of their
//! own: a function c = f(a) uses the series of f′(a) (the function table's derivative, which may
//! use c itself: exp, tan, sin ↔ cos), an integer power aⁿ is built by squaring (exact at
//! a = 0, O(log n) nodes), a negative power is 1/a⁻ⁿ, and atan2(y, x) uses x/(x² + y²) and −y/(x² + y²). The values at
//! order 0 are the straight-line code of the other methods; orders 1, 2, … call one kernel per
//! node, in id (topological) order. Nodes that depend on no coordinate, velocity or time are
//! constants of the series (their order-0 value only), and a product or quotient by one is a
//! scaling. A node the rules do not cover (a power with a state-dependent exponent) leaves the
//! method out: the Taylor method then says it needs another method.

use std::collections::BTreeSet;

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::codegen;
use super::dag::{Dag, Id, Node};
use super::derive::Derivation;
use crate::names;

/// How one node's coefficient k ≥ 1 is computed.
enum Rule {
    /// A coordinate, velocity or time: set from the series of the state.
    Leaf,
    /// Constant in time (or piecewise constant: a step): nothing after order 0.
    Constant,
    Add(Id, Id),
    Sub(Id, Id),
    Neg(Id),
    Mul(Id, Id),
    /// A product by a constant-in-time operand (the second).
    Scale(Id, Id),
    Sqr(Id),
    Div(Id, Id),
    /// A quotient by a constant-in-time operand (the second).
    DivConst(Id, Id),
    /// c = f(a) with the series of f′(a) (`Dag::ZERO`: a piecewise constant function).
    Deriv(Id, Id),
    /// atan2(y, x) with the series of ∂/∂y and ∂/∂x.
    Deriv2(Id, Id, Id, Id),
    /// a^α with α constant in time.
    Powf(Id, Id),
    /// `if cond { a } else { b }` on a constant condition.
    Select(u32, Id, Id),
}

/// The rule of `id`, creating the extra nodes it needs in `dag`; `None` where there is none.
fn rule(dag: &mut Dag, id: Id) -> Option<Rule> {
    if dag.is_state_free(id) {
        return Some(Rule::Constant);
    }
    let free = |dag: &Dag, x: Id| dag.is_state_free(x);
    Some(match dag.node(id) {
        Node::Q(_) | Node::V(_) | Node::T => Rule::Leaf,
        Node::Const(_) | Node::Param(..) => Rule::Constant,
        Node::Add(a, b) => Rule::Add(a, b),
        Node::Sub(a, b) => Rule::Sub(a, b),
        Node::Neg(a) => Rule::Neg(a),
        Node::Mul(a, b) if a == b => Rule::Sqr(a),
        Node::Mul(a, b) if free(dag, a) => Rule::Scale(b, a),
        Node::Mul(a, b) if free(dag, b) => Rule::Scale(a, b),
        Node::Mul(a, b) => Rule::Mul(a, b),
        Node::Div(a, b) if free(dag, b) => Rule::DivConst(a, b),
        Node::Div(a, b) => Rule::Div(a, b),
        Node::Powi(a, 2) => Rule::Sqr(a),
        Node::Powi(a, n) if n < 0 => {
            let p = dag.powi(a, n.checked_neg()?);
            Rule::Div(Dag::ONE, p)
        }
        // By squaring: a²ᵐ = (aᵐ)², a²ᵐ⁺¹ = a²ᵐ·a — O(log n) nodes, and exact at a = 0 (where
        // the power rule's 1/a₀ is not). One node per exponent would be 2³¹ of them for powi(i32::MAX).
        Node::Powi(a, n) if n % 2 == 0 => Rule::Sqr(dag.powi(a, n / 2)),
        Node::Powi(a, n) => Rule::Mul(dag.powi(a, n - 1), a),
        Node::Powf(a, b) if free(dag, b) => Rule::Powf(a, b),
        Node::Powf(..) => return None,
        Node::Atan2(y, x) => {
            let (xx, yy) = (dag.mul(x, x), dag.mul(y, y));
            let r = dag.add(xx, yy);
            let p = dag.div(x, r);
            let qy = dag.div(y, r);
            let q = dag.neg(qy);
            Rule::Deriv2(y, p, x, q)
        }
        Node::Un(f, a) => {
            let d = f.derivative(dag, id, a, Dag::ONE);
            Rule::Deriv(a, d)
        }
        Node::Select(c, a, b) => Rule::Select(c, a, b),
    })
}

/// The operands a rule reads (every one needs its own series).
fn reads(r: &Rule) -> Vec<Id> {
    match *r {
        Rule::Leaf | Rule::Constant => vec![],
        Rule::Neg(a) | Rule::Sqr(a) => vec![a],
        Rule::Add(a, b)
        | Rule::Sub(a, b)
        | Rule::Mul(a, b)
        | Rule::Scale(a, b)
        | Rule::Div(a, b)
        | Rule::DivConst(a, b)
        | Rule::Deriv(a, b)
        | Rule::Powf(a, b)
        | Rule::Select(_, a, b) => vec![a, b],
        Rule::Deriv2(y, p, x, q) => vec![y, p, x, q],
    }
}

/// The body of `fn taylor_series(&self, t, out, buf)`, or `None` where some node has no rule.
pub fn body(d: &Derivation, n: usize) -> Option<TokenStream> {
    let mut dag = d.dag.clone();
    let mut outputs: Vec<Id> = Vec::new();
    for (i, row) in d.mass.iter().enumerate() {
        outputs.extend(row.iter().skip(i).copied());
    }
    outputs.extend(d.rhs.iter().copied());
    // Every node the outputs need, with the nodes their rules need, to a fixed point.
    let mut rules: Vec<Option<Rule>> = Vec::new();
    let mut need: BTreeSet<Id> = BTreeSet::new();
    let mut stack = outputs.clone();
    while let Some(id) = stack.pop() {
        if !need.insert(id) {
            continue;
        }
        let r = rule(&mut dag, id)?;
        let idx = id as usize;
        if rules.len() <= idx {
            rules.resize_with(idx + 1, || None);
        }
        // Order 0 of a Rule::Constant node is its straight-line value: its operands need none.
        if !matches!(r, Rule::Constant) {
            stack.extend(reads(&r));
            stack.extend(dag.node(id).children());
        }
        rules[idx] = Some(r);
    }
    need.insert(Dag::ZERO);
    // Slots: 0 is the zero series; then each needed node.
    let ids: Vec<Id> = need.iter().copied().filter(|&i| i != Dag::ZERO).collect();
    let mut slot = vec![0usize; dag.len()];
    for (s, &id) in ids.iter().enumerate() {
        slot[id as usize] = s + 1;
    }
    // The accelerations' series after the nodes.
    let nslots = Literal::usize_unsuffixed(ids.len() + 1 + n);
    let accel = (0..n).map(|l| Literal::usize_unsuffixed(ids.len() + 1 + l));
    let names::Params { q, qdot, t } = names::Params::symbolic();
    let (out, buf, k, factor) = (
        names::taylor("out"),
        names::taylor("buf"),
        names::taylor("k"),
        names::taylor("factor"),
    );
    let rt = quote!(::lagrange::__private::taylor);
    // Order 0: the straight-line values of every needed node.
    let code0 = codegen::emit(&dag, &d.fields, &d.conds, &ids);
    let stmts0 = &code0.stmts;
    let mut set0 = TokenStream::new();
    for &id in &ids {
        let s = Literal::usize_unsuffixed(slot[id as usize]);
        let v = codegen::operand(&dag, &d.fields, id);
        set0.extend(quote!(#buf.set(#s, 0, #v);));
    }
    // Orders ≥ 1: one kernel per node.
    let mut step = TokenStream::new();
    for &id in &ids {
        let r = rules[id as usize].as_ref()?;
        let sl = |x: Id| Literal::usize_unsuffixed(slot[x as usize]);
        let s = sl(id);
        step.extend(match *r {
            Rule::Constant => continue,
            Rule::Leaf => match dag.node(id) {
                Node::Q(i) => {
                    let i = Literal::usize_unsuffixed(i as usize);
                    quote!(#buf.set(#s, #k, #out[#k][0][#i]);)
                }
                Node::V(i) => {
                    let i = Literal::usize_unsuffixed(i as usize);
                    quote!(#buf.set(#s, #k, #out[#k][1][#i]);)
                }
                _ => quote!(#buf.set(#s, #k, if #k == 1 { 1.0 } else { 0.0 });),
            },
            Rule::Add(a, b) => {
                let (a, b) = (sl(a), sl(b));
                quote!(#buf.add(#s, #a, #b, #k);)
            }
            Rule::Sub(a, b) => {
                let (a, b) = (sl(a), sl(b));
                quote!(#buf.sub(#s, #a, #b, #k);)
            }
            Rule::Neg(a) => {
                let a = sl(a);
                quote!(#buf.neg(#s, #a, #k);)
            }
            Rule::Mul(a, b) => {
                let (a, b) = (sl(a), sl(b));
                quote!(#buf.mul(#s, #a, #b, #k);)
            }
            Rule::Sqr(a) => {
                let a = sl(a);
                quote!(#buf.sqr(#s, #a, #k);)
            }
            Rule::Scale(a, c) => {
                let (a, c) = (sl(a), sl(c));
                quote!(#buf.scale(#s, #a, #buf.get(#c, 0), #k);)
            }
            Rule::Div(a, b) => {
                let (a, b) = (sl(a), sl(b));
                quote!(#buf.div(#s, #a, #b, #k);)
            }
            Rule::DivConst(a, c) => {
                let (a, c) = (sl(a), sl(c));
                quote!(#buf.scale(#s, #a, 1.0 / #buf.get(#c, 0), #k);)
            }
            Rule::Deriv(_, dd) if dd == Dag::ZERO => continue,
            Rule::Deriv(a, dd) => {
                let (a, dd) = (sl(a), sl(dd));
                quote!(#buf.deriv(#s, #a, #dd, 0.0, #k);)
            }
            Rule::Deriv2(y, p, x, qq) => {
                let (y, p, x, qq) = (sl(y), sl(p), sl(x), sl(qq));
                quote!(#buf.deriv2(#s, #y, #p, #x, #qq, 0.0, #k);)
            }
            Rule::Powf(a, e) => {
                let (a, e) = (sl(a), sl(e));
                quote!(#buf.powf(#s, #a, #buf.get(#e, 0), #k);)
            }
            Rule::Select(c, a, b) => {
                let (a, b) = (sl(a), sl(b));
                let c = names::cond(c);
                quote!(#buf.copy(#s, if #c { #a } else { #b }, #k);)
            }
        });
    }
    // The slots of M (upper triangle) and of the right-hand side.
    let mass_rows = (0..n).map(|i| {
        let cols = (0..n).map(|kk| {
            let id = if kk >= i { d.mass[i][kk] } else { Dag::ZERO };
            Literal::usize_unsuffixed(if id == Dag::ZERO {
                0
            } else {
                slot[id as usize]
            })
        });
        quote!([#(#cols),*])
    });
    let varying_rows = (0..n).map(|i| {
        let cols = (0..n).map(|kk| kk >= i && !dag.is_state_free(d.mass[i][kk]));
        quote!([#(#cols),*])
    });
    let rhs = d.rhs.iter().map(|&id| {
        Literal::usize_unsuffixed(if id == Dag::ZERO {
            0
        } else {
            slot[id as usize]
        })
    });
    let nn = Literal::usize_unsuffixed(n);
    Some(quote! {
        if #out.len() < 2 {
            return ::core::option::Option::Some(::core::result::Result::Ok(()));
        }
        let __lagrange_order = #out.len() - 1;
        #buf.reset(#nslots, __lagrange_order);
        let __lagrange_y0: [[f64; #nn]; 2] = #out[0];
        let (#q, #qdot): (&[f64; #nn], &[f64; #nn]) = (&__lagrange_y0[0], &__lagrange_y0[1]);
        #stmts0
        #set0
        let __lagrange_slots = #rt::Slots::<#nn> {
            mass: [#(#mass_rows),*],
            varying: [#(#varying_rows),*],
            rhs: [#(#rhs),*],
            accel: [#(#accel),*],
        };
        let mut #factor = #rt::Factor::None;
        for #k in 0..__lagrange_order {
            if #k > 0 {
                #step
            }
            if let ::core::result::Result::Err(__lagrange_e) = #rt::solve_order(
                #buf,
                &__lagrange_slots,
                <Self as ::lagrange::__private::Lagrangian<#nn>>::COORDINATES,
                #t,
                #out,
                #k,
                &mut #factor,
            ) {
                return ::core::option::Option::Some(::core::result::Result::Err(__lagrange_e));
            }
        }
        ::core::option::Option::Some(::core::result::Result::Ok(()))
    })
}
