//! Emission of `fn taylor_series`: the Taylor coefficients of the motion, order by order, from
//! the recurrences of every node the equations of motion need (the kernels of the runtime's
//! `taylor` module), and the order-by-order solve M₀ a_k = f_k − Σ M_j a_{k−j} — or, where the
//! mass matrix allows it, explicit accelerations (`explicit.rs`) and no solve at all.
//!
//! The program is built on a copy of the derivation's DAG, because some rules need nodes of their
//! own: a function c = f(a) uses the series of f′(a) (the function table's derivative, which may
//! use c itself: exp, tan, sin ↔ cos), an integer power aⁿ is built by squaring (exact at
//! a = 0, O(log n) nodes), a negative power is 1/a⁻ⁿ, and atan2(y, x) uses x/(x² + y²) and
//! −y/(x² + y²). The values at order 0 are the straight-line code of the other methods; orders
//! 1, 2, … call one kernel per node, each after the operands it reads at the same order (not in id
//! order: the nodes the rules add come after the nodes that read them), and each convolution's
//! long middle sum is computed one order ahead, right after the order before is stored (see
//! `Program::emit`: the chain one order waits for is then a few multiply-adds per node). Nodes that depend on no
//! coordinate, velocity or time are constants of the series (their order-0 value only), and a
//! product or quotient by one is a scaling. A node the rules do not cover (a power with a
//! state-dependent exponent), or more than [`MAX_TAYLOR_SLOTS`] series, leaves the method out:
//! the Taylor method then says it needs another method. A body that is not analytic along the
//! motion (`abs`, `signum`, `max`, `min`, `clamp`, the square root of a square) is named in
//! [`not_analytic`]: the Taylor method refuses it.

use std::collections::BTreeSet;

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::codegen;
use super::dag::{Dag, Id, Node};
use super::derive::Derivation;
use super::explicit;
use super::functions::Rule as _;
use crate::names;

/// Systems whose series need more slots than this get no Taylor series: the code grows with the
/// slots and took 7.9 s of a release build for a 16-link chain (2690 slots) against 1.6 s without
/// it, 2.2 s at 8 links (762 slots).
pub const MAX_TAYLOR_SLOTS: usize = 1024;

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

/// The operands whose coefficient of the same order k a rule reads (the others it reads only to
/// order k − 1: a function's derivative series, a quotient's or a power's own series). The
/// kernels of order k run in an order where these come first.
fn reads_same_order(r: &Rule) -> Vec<Id> {
    match *r {
        Rule::Leaf | Rule::Constant => vec![],
        Rule::Neg(a)
        | Rule::Sqr(a)
        | Rule::Scale(a, _)
        | Rule::DivConst(a, _)
        | Rule::Deriv(a, _)
        | Rule::Powf(a, _) => vec![a],
        Rule::Add(a, b)
        | Rule::Sub(a, b)
        | Rule::Mul(a, b)
        | Rule::Div(a, b)
        | Rule::Select(_, a, b) => vec![a, b],
        Rule::Deriv2(y, _, x, _) => vec![y, x],
    }
}

/// The needed nodes in an order where every node comes after the operands it reads at the same
/// order (depth-first). Id order is not one: the rules create nodes (a power's square root
/// aᵐ for a²ᵐ, the 1/x of a negative power) after the node that reads them. `None` on a cycle,
/// which the rules above cannot make (a function reads its derivative's series one order behind).
fn kernel_order(rules: &[Option<Rule>], ids: &[Id]) -> Option<Vec<Id>> {
    let reads = |id: Id| {
        rules
            .get(id as usize)
            .and_then(Option::as_ref)
            .map(reads_same_order)
            .unwrap_or_default()
    };
    // 0: not seen, 1: on the path, 2: placed.
    let mut state = vec![0u8; rules.len().max(1)];
    let mut order = Vec::with_capacity(ids.len());
    for &root in ids {
        if state[root as usize] != 0 {
            continue;
        }
        let mut stack: Vec<(Id, Vec<Id>)> = vec![(root, reads(root))];
        state[root as usize] = 1;
        while let Some((id, pending)) = stack.last_mut() {
            let id = *id;
            match pending.pop() {
                Some(x) if x == Dag::ZERO || state.get(x as usize).copied() == Some(2) => {}
                Some(x) if state.get(x as usize).copied() == Some(1) => return None,
                Some(x) => {
                    if x as usize >= state.len() {
                        // A node without a rule (an order-0-only operand): nothing to order.
                        continue;
                    }
                    state[x as usize] = 1;
                    let r = reads(x);
                    stack.push((x, r));
                }
                None => {
                    state[id as usize] = 2;
                    order.push(id);
                    stack.pop();
                }
            }
        }
    }
    Some(order)
}

/// The most sums of one kind the generated series computes side by side in one loop
/// (`taylor::muls_mid`, `sqrs_mid`, `derivs_mid`): each keeps its running sum in a register.
const GROUP: usize = 8;

/// `jobs` in the fewest groups of at most [`GROUP`], of sizes that differ by one at most (nine
/// products as 5 + 4, not 8 + 1: a group of one is a chain of k additions none overlaps).
fn balanced<T>(jobs: &[T]) -> impl Iterator<Item = &[T]> {
    let groups = jobs.len().div_ceil(GROUP);
    let (base, extra) = match groups {
        0 => (0, 0),
        g => (jobs.len() / g, jobs.len() % g),
    };
    let mut rest = jobs;
    (0..groups).map(move |g| {
        let (head, tail) = rest.split_at((base + usize::from(g < extra)).min(rest.len()));
        rest = tail;
        head
    })
}

/// Whether a rule is a convolution (its coefficient k a sum over orders 0..=k), not O(1).
fn convolves(r: &Rule) -> bool {
    matches!(
        r,
        Rule::Mul(..)
            | Rule::Sqr(_)
            | Rule::Div(..)
            | Rule::Deriv(..)
            | Rule::Deriv2(..)
            | Rule::Powf(..)
    )
}

/// The first construct among `ids` whose value is not analytic along the motion, named for the
/// user: the Taylor method would step over its kink (a series taken on one side of x = 0 sums to
/// the other side's continuation: `|x|` becomes `x`), so it refuses such a body. Functions of the
/// parameters alone are constants of the series and do not count.
pub fn not_analytic(dag: &Dag, ids: &[Id]) -> Option<&'static str> {
    use super::functions::Fun;
    let square = |x: Id| match dag.node(x) {
        Node::Mul(a, b) => a == b,
        Node::Powi(_, n) => n % 2 == 0,
        _ => false,
    };
    // The step H(u) is also in the derivative of `abs`: it is named only where nothing else is.
    let what = |id: Id| {
        if dag.is_state_free(id) {
            return None;
        }
        match dag.node(id) {
            Node::Un(Fun::Abs, _) => Some("`abs` (|x| has a kink at x = 0)"),
            Node::Un(Fun::Signum, _) => Some("`signum` (a step at 0, as in Coulomb friction)"),
            Node::Un(Fun::Step, _) => {
                Some("`abs`, `max`, `min` or `clamp` (a kink: the slope jumps where the argument crosses 0 or the arguments meet)")
            }
            Node::Un(Fun::Sqrt, a) if square(a) => {
                Some("the square root of a square (`sqrt(x * x)` is |x|, with a kink at x = 0)")
            }
            Node::Powf(a, e) if square(a) && dag.as_const(e).is_none_or(|e| e.fract() != 0.0) => {
                Some("a fractional power of a square (`(x * x).powf(0.5)` is |x|, with a kink at x = 0)")
            }
            _ => None,
        }
    };
    let step = |id: &Id| matches!(dag.node(*id), Node::Un(Fun::Step, _));
    ids.iter()
        .filter(|id| !step(id))
        .find_map(|&id| what(id))
        .or_else(|| ids.iter().filter(|id| step(id)).find_map(|&id| what(id)))
}

/// Why a system has no Taylor series.
pub enum NoSeries {
    /// A node has no rule, or the series would need more than [`MAX_TAYLOR_SLOTS`] slots.
    Unsupported,
    /// The body is not analytic along the motion: the construct ([`not_analytic`]).
    NotAnalytic(&'static str),
}

/// `fn series<R: Real>(params, names, t, out, buf)` of the kernels module (the Taylor
/// coefficients of the motion, generic over the width), or why there is none; `binds` binds the
/// kernels' parameters.
pub fn body(d: &Derivation, n: usize, binds: &TokenStream) -> Result<TokenStream, NoSeries> {
    series(d, n, binds)
        .ok_or(NoSeries::Unsupported)?
        .map_err(NoSeries::NotAnalytic)
}

/// [`body`]: `None` where some node has no rule, `Some(Err(construct))` for a body that is not
/// analytic.
fn series(
    d: &Derivation,
    n: usize,
    binds: &TokenStream,
) -> Option<Result<TokenStream, &'static str>> {
    series_with(d, n, binds, true)
}

/// [`series`], with explicit accelerations where `try_explicit` and the system has them and
/// they take fewer convolutions per order than the solve (its products and its tails).
fn series_with(
    d: &Derivation,
    n: usize,
    binds: &TokenStream,
    try_explicit: bool,
) -> Option<Result<TokenStream, &'static str>> {
    let mut dag = d.dag.clone();
    let explicit = if try_explicit {
        explicit::accelerations(&mut dag, d)
    } else {
        None
    };
    let mut outputs: Vec<Id> = Vec::new();
    for (i, row) in d.mass.iter().enumerate() {
        outputs.extend(row.iter().skip(i).copied());
    }
    outputs.extend(d.rhs.iter().copied());
    let solve_roots = outputs.clone();
    if let Some(e) = &explicit {
        outputs.extend(&e.accel);
        outputs.extend(&e.tests);
    }
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
    // Slots: 0 is the zero series; then each needed node; then the accelerations.
    let ids: Vec<Id> = need.iter().copied().filter(|&i| i != Dag::ZERO).collect();
    if let Some(what) = not_analytic(&dag, &ids) {
        return Some(Err(what));
    }
    if ids.len() > MAX_TAYLOR_SLOTS {
        return if explicit.is_some() {
            series_with(d, n, binds, false)
        } else {
            None
        };
    }
    let mut slot = vec![0usize; dag.len()];
    for (s, &id) in ids.iter().enumerate() {
        slot[id as usize] = s + 1;
    }
    let kernels = kernel_order(&rules, &ids)?;
    let split = match &explicit {
        None => None,
        Some(e) => {
            let ours = per_order(&rules, &e.accel);
            let theirs = per_order(&rules, &solve_roots);
            let convolutions = |set: &BTreeSet<Id>| {
                set.iter()
                    .filter(|&&x| rules[x as usize].as_ref().is_some_and(convolves))
                    .count()
            };
            let tails = (0..n)
                .flat_map(|i| (0..n).map(move |l| (i, l)))
                .filter(|&(i, l)| {
                    let x = if i <= l { d.mass[i][l] } else { d.mass[l][i] };
                    x != Dag::ZERO && !dag.is_state_free(x)
                })
                .count();
            if convolutions(&ours) >= convolutions(&theirs) + tails {
                return series_with(d, n, binds, false);
            }
            Some(Split {
                accel: &e.accel,
                tests: &e.tests,
                kernels: kernels
                    .iter()
                    .copied()
                    .filter(|x| ours.contains(x))
                    .collect(),
            })
        }
    };
    let program = Program {
        d,
        n,
        dag: &dag,
        rules: &rules,
        ids: &ids,
        kernels: &kernels,
        slot: &slot,
        explicit: split.as_ref(),
    };
    Some(Ok(program.emit(binds)?))
}

/// The nodes whose coefficients of orders ≥ 1 the series of `roots` reads (the roots, and what
/// their rules read, to a fixed point; a constant reads nothing past order 0).
fn per_order(rules: &[Option<Rule>], roots: &[Id]) -> BTreeSet<Id> {
    let mut seen = BTreeSet::new();
    let mut stack: Vec<Id> = roots.iter().copied().filter(|&x| x != Dag::ZERO).collect();
    while let Some(x) = stack.pop() {
        if !seen.insert(x) {
            continue;
        }
        if let Some(r) = rules.get(x as usize).and_then(Option::as_ref) {
            stack.extend(reads(r).into_iter().filter(|&y| y != Dag::ZERO));
        }
    }
    seen
}

/// What the emission reads: the derivation, the extended DAG, every needed node's rule and slot.
struct Program<'a> {
    d: &'a Derivation,
    n: usize,
    dag: &'a Dag,
    rules: &'a [Option<Rule>],
    ids: &'a [Id],
    /// The order of the kernels at orders ≥ 1 ([`kernel_order`]).
    kernels: &'a [Id],
    slot: &'a [usize],
    /// The explicit accelerations and which kernels each way needs, where the series uses them.
    explicit: Option<&'a Split<'a>>,
}

/// The code of orders ≥ 1 for a list of kernels: what order k computes (`step`), and the sums'
/// parts for order k + 1 (`next`, after order k is stored).
struct Pass {
    step: TokenStream,
    next: TokenStream,
}

/// A series with explicit accelerations ([`explicit::accelerations`]): the accelerations, the
/// divisors that must be finite and not zero at order 0, and the kernels of orders ≥ 1 the
/// accelerations read, in [`kernel_order`]'s order.
struct Split<'a> {
    accel: &'a [Id],
    tests: &'a [Id],
    kernels: Vec<Id>,
}

impl Program<'_> {
    /// The kernel, generic over `R: Real`: its `f64` instance is the single run's series, its
    /// lanes instance computes every lane's scalar coefficients (the same kernels in the same
    /// order).
    fn emit(&self, binds: &TokenStream) -> Option<TokenStream> {
        let Program {
            d,
            n,
            dag,
            rules,
            ids,
            kernels,
            slot,
            explicit: _,
        } = *self;
        let num = codegen::real_type();
        let real = quote!(::lagrange::__private::Real);
        let zero = quote!(<#num as #real>::ZERO);
        let accel: Vec<Literal> = (0..n)
            .map(|l| Literal::usize_unsuffixed(ids.len() + 1 + l))
            .collect();
        let names::Params { q, qdot, t } = names::Params::symbolic();
        let (out, buf, k, c) = (
            names::taylor("out"),
            names::taylor("buf"),
            names::taylor("k"),
            names::taylor("c"),
        );
        let (order, factor, b, a) = (
            names::taylor("order"),
            names::taylor("factor"),
            names::taylor("b"),
            names::taylor("a"),
        );
        // The runtime's kernels under a short local name (the series calls one per node and order).
        let rt = names::taylor("rt");
        let rt = quote!(#rt);
        let sl = |x: Id| Literal::usize_unsuffixed(slot[x as usize]);
        let op = |x: Id| codegen::operand_as(dag, &d.fields, x, Some(&num));
        // Order 0: the straight-line values of every needed node.
        let stmts0 = codegen::emit_as(dag, &d.fields, &d.conds, ids, Some(&num)).values;
        let mut set0 = TokenStream::new();
        // 1 / b₀ of each quotient a / b the orders ≥ 1 compute (`taylor::div_rest`; by a constant
        // b, each coefficient is a_k · (1 / b)): a multiplication on the chain of an order where
        // a division was (measured: the heavy top's θ̈ = f_θ / I⊥ ended each order in a divsd).
        let per_order_kernels: &[Id] = self.explicit.map_or(kernels, |e| &e.kernels);
        for &id in per_order_kernels {
            if let Some(Rule::Div(_, y) | Rule::DivConst(_, y)) = rules[id as usize] {
                let (r, y) = (names::taylor(&format!("r{id}")), op(y));
                let one = codegen::real_const(&num, &quote!(1.0));
                set0.extend(quote!(let #r: #num = #one / #y;));
            }
        }
        let entry = |i: usize, l: usize| {
            let (r, cc) = if i <= l { (i, l) } else { (l, i) };
            d.mass[r][cc]
        };
        // Σ_{j ≥ 1} M_j a_{k−j} over the entries of M that vary along the motion (the others have
        // no coefficient past order 0); none with explicit accelerations.
        let tails: Vec<(usize, usize)> = match self.explicit {
            Some(_) => Vec::new(),
            None => (0..n)
                .flat_map(|i| (0..n).map(move |l| (i, l)))
                .filter(|&(i, l)| entry(i, l) != Dag::ZERO && !dag.is_state_free(entry(i, l)))
                .collect(),
        };
        // Slots: 0 the zero series, the nodes, the accelerations, the tails' parts.
        let nslots = Literal::usize_unsuffixed(ids.len() + 1 + n + tails.len());
        // The nodes that keep a row past order 0: those a kernel reads at other orders than its own
        // (a convolution's operands, a quotient's divisor and own series, a power's own series, a
        // function's derivative series, the entries of M in the tails, the explicit accelerations),
        // the leaves and the constants. The others (sums, differences, scalings, selections, a
        // quotient's numerator: read at their own order only) are locals of the order: no store,
        // no row in the cache.
        let mut kept = vec![false; dag.len()];
        // Whether a kernel reads a node's row (not only its coefficient of the same order).
        let mut row_read = vec![false; dag.len()];
        for &id in ids {
            let Some(r) = rules.get(id as usize).and_then(Option::as_ref) else {
                continue;
            };
            let keep: Vec<Id> = match *r {
                Rule::Mul(a, b) | Rule::Deriv(a, b) => vec![a, b],
                Rule::Sqr(a) => vec![a],
                Rule::Div(_, b) => vec![b, id],
                Rule::Powf(a, _) => vec![a, id],
                Rule::Deriv2(y, p, x, q) => vec![y, p, x, q],
                Rule::Leaf | Rule::Constant => vec![id],
                _ => vec![],
            };
            for x in keep {
                if let Some(k) = kept.get_mut(x as usize) {
                    *k = true;
                }
                if x != id {
                    if let Some(k) = row_read.get_mut(x as usize) {
                        *k = true;
                    }
                }
            }
        }
        for &(i, l) in &tails {
            kept[entry(i, l) as usize] = true;
        }
        for &x in self.explicit.map_or(&[][..], |e| e.accel) {
            if let Some(k) = kept.get_mut(x as usize) {
                *k = true;
            }
        }
        // Order 0 of every row (the kernels read it at every order) and of what the solve, its
        // error or the tests read at order 0 (M₀, b₀, the divisors); the other nodes' order-0
        // values are the straight-line locals above.
        let mut order0: BTreeSet<Id> = BTreeSet::new();
        for (i, row) in d.mass.iter().enumerate() {
            order0.extend(row.iter().skip(i).copied());
        }
        order0.extend(&d.rhs);
        order0.extend(self.explicit.map_or(&[][..], |e| e.tests));
        // A node constant past order 0 (a constant, a step, the zero series) has coefficients
        // k ≥ 1 of zero: read as zero where an order computes, its row zeroed (the buffer may
        // have held another layout) only where a kernel reads it as a row.
        let flat_rule = |x: Id| {
            matches!(
                rules.get(x as usize).and_then(Option::as_ref),
                Some(Rule::Constant | Rule::Deriv(_, Dag::ZERO))
            )
        };
        let mut flat = vec![Literal::usize_unsuffixed(0)];
        for &id in ids {
            let s = sl(id);
            if kept[id as usize] || order0.contains(&id) {
                let v = op(id);
                set0.extend(quote!(#c[#s][0] = #v;));
            }
            if flat_rule(id) && row_read[id as usize] {
                flat.push(s);
            }
        }
        let local = |x: Id| {
            !kept.get(x as usize).copied().unwrap_or(true)
                && matches!(
                    rules.get(x as usize).and_then(Option::as_ref),
                    Some(
                        Rule::Add(..)
                            | Rule::Sub(..)
                            | Rule::Neg(_)
                            | Rule::Scale(..)
                            | Rule::DivConst(..)
                            | Rule::Select(..)
                    )
                )
        };
        let local_name = |x: Id| names::taylor(&format!("t{x}"));
        // Coefficient k of x: zero, its local or its row.
        let at = |x: Id| {
            if flat_rule(x) {
                zero.clone()
            } else if local(x) {
                let t = local_name(x);
                quote!(#t)
            } else {
                let s = sl(x);
                quote!(#c[#s][#k])
            }
        };

        let reciprocal_name = |x: Id| names::taylor(&format!("r{x}"));
        // Where a tail's part for the next order waits (its own row, after the accelerations').
        let tail_slot = |t: usize| Literal::usize_unsuffixed(ids.len() + 1 + n + t);
        let tail_name = |t: usize| names::taylor(&format!("tail{t}"));
        // Orders ≥ 1, software-pipelined. Every convolution's sum Σ_{j=2..k−2} (the terms that
        // read coefficients below k − 1) is computed for order k + 1 right after order k is
        // stored, side by side in groups of up to [`GROUP`] per kind: none reads another, nor
        // anything order k is still computing, so they overlap order k's chain. Order k then
        // finishes node by node, each after what it reads at order k ([`kernel_order`]), with
        // the O(1) rest (the terms that read k − 1 and k: a product's a₀ b_k + a_k b₀, …). The
        // chain each order waits for is a few multiply-adds per node, not a convolution per level.
        let pass = |list: &[Id]| -> Option<Pass> {
            // (its part's local, x, y) of the sums Σ x_j y_{k−j}: products, quotients (divisor
            // and own series) and the mass tails.
            let mut products: Vec<(Literal, Literal, Literal)> = Vec::new();
            let mut squares: Vec<(Literal, Literal)> = Vec::new();
            let mut functions: Vec<(Literal, Literal, Literal)> = Vec::new();
            let mut finish = TokenStream::new();
            // When each node's coefficient k is ready, in additions' latencies from the start of
            // the order (a product's is one multiply-add after its later operand): a product
            // finishes with the later operand's a_k b₀ last (`taylor::mul_rest`), so the chain
            // through it is one multiply-add.
            let mut ready: std::collections::HashMap<Id, u32> = std::collections::HashMap::new();
            for &id in list {
                let r = rules[id as usize].as_ref()?;
                let latest = reads_same_order(r)
                    .iter()
                    .filter_map(|x| ready.get(x).copied())
                    .max()
                    .unwrap_or(0);
                ready.insert(id, latest + if convolves(r) { 2 } else { 1 });
                // A convolution's part of the sums for this order, computed at the end of the order
                // before, waits in its own row at this order (`taylor::mul_at`, …, overwrite it
                // with the coefficient: one short call per node and order).
                let s = sl(id);
                let value = match *r {
                    Rule::Constant | Rule::Deriv(_, Dag::ZERO) => continue,
                    Rule::Mul(x, y) => {
                        let later = |v: Id| ready.get(&v).copied().unwrap_or(0);
                        let (x, y) = if later(y) > later(x) { (y, x) } else { (x, y) };
                        let (x, y) = (sl(x), sl(y));
                        products.push((s.clone(), x.clone(), y.clone()));
                        finish.extend(quote!(#rt::mul_at(#c, #s, #x, #y, #k);));
                        continue;
                    }
                    Rule::Sqr(x) => {
                        let x = sl(x);
                        squares.push((s.clone(), x.clone()));
                        finish.extend(quote!(#rt::sqr_at(#c, #s, #x, #k);));
                        continue;
                    }
                    Rule::Deriv(x, dd) => {
                        let (x, dd) = (sl(x), sl(dd));
                        functions.push((s.clone(), x.clone(), dd.clone()));
                        finish.extend(quote!(#rt::deriv_at(#c, #s, #x, #dd, #k);));
                        continue;
                    }
                    Rule::Div(x, y) => {
                        let (x, y, r) = (at(x), sl(y), reciprocal_name(id));
                        products.push((s.clone(), y.clone(), s.clone()));
                        finish.extend(quote!(#rt::div_at(#c, #s, #x, #y, #r, #k);));
                        continue;
                    }
                    Rule::Leaf => match dag.node(id) {
                        Node::Q(i) => {
                            let i = Literal::usize_unsuffixed(i as usize);
                            quote!(#out[#k][0][#i])
                        }
                        Node::V(i) => {
                            let i = Literal::usize_unsuffixed(i as usize);
                            quote!(#out[#k][1][#i])
                        }
                        _ => codegen::real_const(&num, &quote!(if #k == 1 { 1.0 } else { 0.0 })),
                    },
                    Rule::Add(x, y) => {
                        let (x, y) = (at(x), at(y));
                        quote!(#x + #y)
                    }
                    Rule::Sub(x, y) => {
                        let (x, y) = (at(x), at(y));
                        quote!(#x - #y)
                    }
                    Rule::Neg(x) => {
                        let x = at(x);
                        quote!(-#x)
                    }
                    Rule::Scale(x, f) => {
                        let (x, f) = (at(x), op(f));
                        quote!(#f * #x)
                    }
                    Rule::DivConst(x, _) => {
                        let (x, r) = (at(x), reciprocal_name(id));
                        quote!(#x * #r)
                    }
                    Rule::Deriv2(y, p, x, qq) => {
                        let (y, p, x, qq) = (sl(y), sl(p), sl(x), sl(qq));
                        quote!(#rt::deriv2(&#c[#y], &#c[#p], &#c[#x], &#c[#qq], #k))
                    }
                    Rule::Powf(x, e) => {
                        let (x, e) = (sl(x), op(e));
                        quote!(#rt::powf(&#c[#x], &#c[#s], #e, #k))
                    }
                    Rule::Select(cond, x, y) => {
                        let (x, y) = (at(x), at(y));
                        let cond = names::cond(cond);
                        quote!(<#num as #real>::select(#cond, #x, #y))
                    }
                };
                if local(id) {
                    let t = local_name(id);
                    finish.extend(quote!(let #t: #num = #value;));
                } else {
                    finish.extend(quote!(#c[#s][#k] = #value;));
                }
            }
            for (t, &(i, l)) in tails.iter().enumerate() {
                products.push((tail_slot(t), sl(entry(i, l)), accel[l].clone()));
            }
            // Each sum's part that reads below k − 1, for order k + 1, computed right after order
            // k is finished (`next`), into the row it belongs to at k + 1 (rows, not locals
            // carried through the loop: LLVM took such locals of lanes apart into scalars); order
            // k + 1 completes it with the terms that read k and k + 1 (`taylor::mul_rest`, …).
            let mut next = TokenStream::new();
            let k1 = quote!(#k + 1);
            for group in balanced(&products) {
                let ss = group.iter().map(|j| &j.0);
                let xs = group.iter().map(|j| &j.1);
                let ys = group.iter().map(|j| &j.2);
                next.extend(quote! {
                    #rt::muls_mid_at(#c, [#(#ss),*], [#(#xs),*], [#(#ys),*], #k1);
                });
            }
            for group in balanced(&squares) {
                let ss = group.iter().map(|j| &j.0);
                let xs = group.iter().map(|j| &j.1);
                next.extend(quote!(#rt::sqrs_mid_at(#c, [#(#ss),*], [#(#xs),*], #k1);));
            }
            for group in balanced(&functions) {
                let ss = group.iter().map(|j| &j.0);
                let xs = group.iter().map(|j| &j.1);
                let ys = group.iter().map(|j| &j.2);
                next.extend(quote! {
                    #rt::derivs_mid_at(#c, [#(#ss),*], [#(#xs),*], [#(#ys),*], #k1);
                });
            }
            Some(Pass { step: finish, next })
        };
        // M₀ (upper triangle) and the right-hand side of order 0 (the solve's, or the error's
        // where explicit accelerations do not apply).
        let m0_slots = (0..n).map(|i| {
            let cols = (0..n).map(|l| match d.mass[i][l] {
                id if l >= i && id != Dag::ZERO => sl(id),
                _ => Literal::usize_unsuffixed(0),
            });
            quote!([#(#cols),*])
        });
        let b0_slots = (0..n).map(|i| match d.rhs[i] {
            Dag::ZERO => Literal::usize_unsuffixed(0),
            id => sl(id),
        });
        let m0 = quote!(#rt::order0_matrix(#c, [#(#m0_slots),*]));
        let b0 = quote!(#rt::order0_column(#c, [#(#b0_slots),*]));
        let nn = Literal::usize_unsuffixed(n);
        let names_ = names::taylor("names");
        let ii = (0..n).map(Literal::usize_unsuffixed);
        let max = quote!(#rt::MAX_ORDER);
        let params = names::lane_params();
        // The accelerations' rows are read by the mass tails only.
        let accel_rows = if tails.is_empty() {
            TokenStream::new()
        } else {
            quote!(#( #c[#accel][#k] = #a[#ii]; )*)
        };
        let store = quote! {
            #accel_rows
            #rt::next_order(#out, #a, #k);
        };
        let solve = match self.explicit {
            None => {
                let factor_ty = quote!(<<#num as ::lagrange::__private::eom::SeriesReal>::Factor<#nn> as ::lagrange::__private::eom::SeriesFactor<#num, #nn>>);
                let Pass { step, next } = pass(kernels)?;
                let rhs = (0..n).map(|i| {
                    let f = match d.rhs[i] {
                        Dag::ZERO => zero.clone(),
                        id => at(id),
                    };
                    let tail = tails
                        .iter()
                        .enumerate()
                        .filter(|(_, &(row, _))| row == i)
                        .map(|(t, _)| {
                            let v = tail_name(t);
                            quote!(- #v)
                        });
                    quote!(#f #(#tail)*)
                });
                let tail_finish = tails.iter().enumerate().map(|(t, &(i, l))| {
                    let (v, h, m, al) = (tail_name(t), tail_slot(t), sl(entry(i, l)), &accel[l]);
                    quote!(let #v: #num = #rt::tail_rest(#c[#h][#k], &#c[#m], &#c[#al], #k);)
                });
                quote! {
                    // A single run pivots where M₀ has no LDLᵀ (or returns why it is singular); a
                    // lane where it has none is left out of the mask: the caller takes its member's
                    // single-run series.
                    let (#factor, __lagrange_ok) =
                        #factor_ty::new(&#m0, &#b0, #names_, #q, #qdot, #t);
                    if let ::core::option::Option::Some(__lagrange_e) =
                        ::lagrange::__private::eom::SeriesFactor::error(&#factor, #names_, #q, #qdot, #t)
                    {
                        return ::core::result::Result::Err(__lagrange_e);
                    }
                    let mut #a = [<#num as #real>::ZERO; #nn];
                    for #k in 0..#order {
                        let #b: [#num; #nn] = if #k == 0 {
                            #b0
                        } else {
                            #step
                            #(#tail_finish)*
                            [#(#rhs),*]
                        };
                        ::lagrange::__private::eom::SeriesFactor::solve(
                            &#factor, &#b, &mut #a, #names_, #q, #qdot, #t,
                        )?;
                        #store
                        if #k + 1 < #order {
                            #next
                        }
                    }
                }
            }
            Some(split) => {
                let tests = split.tests.iter().map(|&x| sl(x));
                let value = |i: usize| match split.accel[i] {
                    Dag::ZERO => zero.clone(),
                    x => {
                        let x = sl(x);
                        quote!(#c[#x][#k])
                    }
                };
                let values = (0..n).map(value);
                let Pass { step, next } = pass(&split.kernels)?;
                quote! {
                    // The explicit accelerations, where their divisors are finite and not zero at
                    // order 0 (a lane where one is not is left out of the mask: the caller takes
                    // its member's single-run series; a single run returns why M₀ is singular).
                    let __lagrange_ok = #rt::divisors_ok(#c, [#(#tests),*]);
                    if !<#num as #real>::all(__lagrange_ok) {
                        if let ::core::option::Option::Some(__lagrange_e) =
                            <#num as ::lagrange::__private::eom::SeriesReal>::declined(
                                &#m0, &#b0, #names_, #q, #qdot, #t,
                            )
                        {
                            return ::core::result::Result::Err(__lagrange_e);
                        }
                    }
                    let mut #a: [#num; #nn];
                    for #k in 0..#order {
                        if #k > 0 {
                            #step
                        }
                        #a = [#(#values),*];
                        #store
                        if #k + 1 < #order {
                            #next
                        }
                    }
                }
            }
        };
        Some(quote! {
            /// The Taylor coefficients of the motion through `out[0]` at t (see
            /// `Lagrangian::series_in`), in the lanes of the mask.
            #[inline(always)]
            pub(super) fn series<#num: ::lagrange::__private::eom::SeriesReal>(
                #params: &[#num; PARAMS],
                #names_: [&'static str; #nn],
                #t: #num,
                #out: &mut [[[#num; #nn]; 2]],
                #buf: &mut ::lagrange::__private::taylor::SeriesBuf<#num>,
            ) -> ::core::result::Result<<#num as #real>::Mask, ::lagrange::__private::DynamicsError> {
                use ::lagrange::__private::taylor as #rt;
                if #out.len() < 2 {
                    return ::core::result::Result::Ok(<#num as #real>::EVERY_LANE);
                }
                let #order = (#out.len() - 1).min(#max);
                let #c: &mut [#rt::RowOf<#num>; #nslots] = #buf.slots::<#nslots>();
                let __lagrange_y0: [[#num; #nn]; 2] = #out[0];
                let (#q, #qdot): (&[#num; #nn], &[#num; #nn]) = (&__lagrange_y0[0], &__lagrange_y0[1]);
                #binds
                #stmts0
                #set0
                #( #c[#flat][1..=#order].fill(#zero); )*
                #solve
                // Orders past MAX_ORDER are not computed.
                for __lagrange_x in &mut #out[#order + 1..] {
                    *__lagrange_x = [[<#num as #real>::NAN; #nn]; 2];
                }
                ::core::result::Result::Ok(__lagrange_ok)
            }
        })
    }
}
