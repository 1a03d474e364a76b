//! Analyze and lower for the jets path: which bindings the bodies use (CYCLIC, AUTONOMOUS,
//! MOMENTUM_CONSERVED, ENERGY_CONSERVED, and for `fn constraints` CONSTRAINED_COORDINATES and
//! SCLERONOMIC), and each body rewritten so constants (`2.0`, `self.m`, `Vector3<f64>` fields) meet coordinate
//! values through the runtime's mixed-arithmetic traits.
//!
//! Each expression gets a kind: `Const` (no dependence on q, q̇ or t: an `f64`, a
//! `Vector3<f64>`, a bool...) or `Var` (a `Scalar` or `Vector3<Scalar>`), or a tuple of kinds.
//! Where a `Const` meets a `Var` in `+ - * /`, the operation becomes
//! `__private::ConstMul::const_mul(c, v)` (or `MulConst::mul_const(v, c)`, ...): the constant stays
//! an `f64`. Elsewhere (method arguments, comparisons, `Vector3::new`, branches of an `if`) the
//! constant is lifted with `__private::lift::<Scalar, _>(c)`. Generated calls carry the span of
//! the user's expression, so a type error points at the user's code.

use std::collections::{HashMap, HashSet};

use proc_macro2::{TokenStream, TokenTree};
use quote::{quote, quote_spanned, ToTokens};
use syn::spanned::Spanned;
use syn::visit::Visit;
use syn::{BinOp, Block, Expr, Pat, Stmt};

use crate::errors::Errors;
use crate::model::{unraw, Decl, Func, FuncKind};

/// What the analysis found.
pub struct Analysis {
    /// Names mentioned anywhere in the body of `fn lagrangian`.
    pub used: HashSet<String>,
    /// Names mentioned anywhere in the body of `fn dissipation` (empty without one).
    pub dissipation_used: HashSet<String>,
    /// Names mentioned anywhere in the body of `fn forces` (empty without one).
    pub forces_used: HashSet<String>,
    /// Names mentioned anywhere in the body of `fn constraints` (empty without one).
    pub constraints_used: HashSet<String>,
    /// CONSTRAINED_COORDINATES, one per slot: q_i appears in the body of `fn constraints` (a
    /// `Coord3` marks its three slots). Empty without `fn constraints`.
    pub constrained: Vec<bool>,
    /// SCLERONOMIC: `fn constraints` has no `t: Time`, or does not use it.
    pub scleronomic: bool,
    /// Names mentioned anywhere in the body of `fn contacts` (empty without one).
    pub contacts_used: HashSet<String>,
    /// Names mentioned anywhere in the body of `fn velocity_constraints` (empty without one).
    pub velocity_used: HashSet<String>,
    /// `Unilateral::SCLERONOMIC`: `fn contacts` has no `t: Time`, or does not use it.
    pub contacts_scleronomic: bool,
    /// CYCLIC, one per slot: q_i appears in none of L, D and Q.
    pub cyclic: Vec<bool>,
    /// AUTONOMOUS: L has no explicit t.
    pub autonomous: bool,
    /// MOMENTUM_CONSERVED, one per slot: cyclic, q̇_i absent from D, and Q's i-th entry a
    /// literal zero in the array `fn forces` ends with.
    pub momentum_conserved: Vec<bool>,
    /// ENERGY_CONSERVED: autonomous, no D, and no Q (or every entry of Q a literal zero).
    pub energy_conserved: bool,
}

/// Names used in the bodies, and from them CYCLIC, AUTONOMOUS, MOMENTUM_CONSERVED and
/// ENERGY_CONSERVED. One syntactic rule for both modes, so the modes agree.
pub fn analyze(decl: &Decl) -> Analysis {
    let mentions = |b: &Block| {
        let mut v = Mentions::default();
        v.visit_block(b);
        v.0
    };
    let used = mentions(&decl.body);
    let dissipation_used = decl
        .dissipation
        .as_ref()
        .map(|f| mentions(&f.body))
        .unwrap_or_default();
    let forces_used = decl
        .forces
        .as_ref()
        .map(|f| mentions(&f.body))
        .unwrap_or_default();
    // Whether binding `k` (0: coordinate, 1: velocity) of coordinate parameter `p` of `f` is
    // used in its body.
    let in_func = |f: Option<&Func>, used: &HashSet<String>, p: usize, velocity: bool| {
        f.and_then(|f| f.bindings.get(p))
            .and_then(|(c, v)| if velocity { v.as_ref() } else { c.as_ref() })
            .is_some_and(|id| used.contains(&unraw(id)))
    };
    // Q's entries that are a literal zero (all false when the tail is not an array literal).
    let n = decl.n();
    let zero_force: Vec<bool> = match &decl.forces {
        None => vec![true; n],
        Some(f) => match tail_array(&f.body) {
            Some(elems) if elems.len() == n => elems.iter().map(|e| is_literal_zero(e)).collect(),
            _ => vec![false; n],
        },
    };
    let constraints_used = decl
        .constraints
        .as_ref()
        .map(|f| mentions(&f.body))
        .unwrap_or_default();
    let velocity_used = decl
        .velocity_constraints
        .as_ref()
        .map(|f| mentions(&f.body))
        .unwrap_or_default();
    // A coordinate is constrained when g mentions it, or a velocity constraint mentions it or
    // its velocity.
    let constrained: Vec<bool> =
        if decl.constraints.is_none() && decl.velocity_constraints.is_none() {
            Vec::new()
        } else {
            decl.coords
                .iter()
                .enumerate()
                .flat_map(|(p, c)| {
                    let used = in_func(decl.constraints.as_ref(), &constraints_used, p, false)
                        || in_func(decl.velocity_constraints.as_ref(), &velocity_used, p, false)
                        || in_func(decl.velocity_constraints.as_ref(), &velocity_used, p, true);
                    std::iter::repeat_n(used, c.width())
                })
                .collect()
        };
    // Velocity constraints with a velocity-free term b(q, t) do work on the motion, as moving
    // constraints do.
    let scleronomic = decl
        .constraints
        .as_ref()
        .and_then(|f| f.time.as_ref())
        .is_none_or(|t| !constraints_used.contains(&unraw(t)))
        && decl.velocity_constraints.as_ref().is_none_or(|f| !f.affine);
    let contacts_used = decl
        .contacts
        .as_ref()
        .map(|f| mentions(&f.body))
        .unwrap_or_default();
    let contacts_scleronomic = decl
        .contacts
        .as_ref()
        .and_then(|f| f.time.as_ref())
        .is_none_or(|t| !contacts_used.contains(&unraw(t)));
    let mut cyclic = Vec::with_capacity(n);
    let mut momentum_conserved = Vec::with_capacity(n);
    for (p, c) in decl.coords.iter().enumerate() {
        let absent = !used.contains(&unraw(&c.name))
            && !in_func(decl.dissipation.as_ref(), &dissipation_used, p, false)
            && !in_func(decl.forces.as_ref(), &forces_used, p, false);
        let undamped = !in_func(decl.dissipation.as_ref(), &dissipation_used, p, true);
        for &zero in &zero_force[c.first_index..c.first_index + c.width()] {
            cyclic.push(absent);
            momentum_conserved.push(absent && undamped && zero);
        }
    }
    let autonomous = decl.time.as_ref().is_none_or(|t| !used.contains(&unraw(t)));
    // A moving constraint (g depends on t) does work on the system.
    let energy_conserved =
        autonomous && decl.dissipation.is_none() && zero_force.iter().all(|z| *z) && scleronomic;
    Analysis {
        used,
        dissipation_used,
        forces_used,
        constraints_used,
        constrained,
        scleronomic,
        contacts_used,
        contacts_scleronomic,
        velocity_used,
        cyclic,
        autonomous,
        momentum_conserved,
        energy_conserved,
    }
}

/// The elements of the array literal a body ends with (`[a, b, c]` as its tail expression).
pub fn tail_array(body: &Block) -> Option<Vec<&Expr>> {
    match body.stmts.last() {
        Some(Stmt::Expr(e, None)) => match paren_less(e) {
            Expr::Array(a) => Some(a.elems.iter().collect()),
            _ => None,
        },
        _ => None,
    }
}

fn paren_less(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => paren_less(&p.expr),
        Expr::Group(g) => paren_less(&g.expr),
        _ => e,
    }
}

/// A number literal equal to zero (`0.0`, `0`, `-0.0`, `0.0_f64`), possibly in parentheses.
fn is_literal_zero(e: &Expr) -> bool {
    match paren_less(e) {
        Expr::Lit(l) => match &l.lit {
            syn::Lit::Float(f) => f.base10_parse::<f64>().is_ok_and(|x| x == 0.0),
            syn::Lit::Int(i) => i.base10_parse::<u64>().is_ok_and(|x| x == 0),
            _ => false,
        },
        Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => is_literal_zero(&u.expr),
        _ => false,
    }
}

impl Analysis {
    /// The flags ORed with those the symbolic mode read from the derived expressions (a
    /// coordinate that leaves L only through an identity is cyclic there): both rules only say
    /// true where it holds.
    pub fn refine(&mut self, s: &crate::symbolic::Symmetry) {
        for (c, &e) in self.cyclic.iter_mut().zip(&s.cyclic) {
            *c |= e;
        }
        for (m, &e) in self
            .momentum_conserved
            .iter_mut()
            .zip(&s.momentum_conserved)
        {
            *m |= e;
        }
        self.autonomous |= s.autonomous;
        // A moving constraint does work: the expressions of L, D and Q do not see it.
        self.energy_conserved |= s.energy_conserved && self.scleronomic;
    }

    /// The user's coordinate, velocity and time names the body mentions, in declaration order:
    /// the names the generated `fn lagrangian` binds (and the jets lowering treats as variables).
    pub fn bound(&self, decl: &Decl) -> Vec<String> {
        let coords = decl
            .coords
            .iter()
            .flat_map(|c| [unraw(&c.name), unraw(&c.dot)]);
        let time = decl.time.iter().map(unraw);
        coords
            .chain(time)
            .filter(|name| self.used.contains(name))
            .collect()
    }

    /// The names of `f` (`fn dissipation`, `fn forces` or `fn constraints`) its body mentions: what its generated
    /// method binds.
    pub fn bound_func(&self, f: &Func) -> Vec<String> {
        let used = self.func_used(f);
        f.bindings
            .iter()
            .flat_map(|(c, v)| c.iter().chain(v))
            .chain(&f.time)
            .map(unraw)
            .filter(|name| used.contains(name))
            .collect()
    }

    /// The names the body of `f` mentions.
    pub fn func_used(&self, f: &Func) -> &HashSet<String> {
        match f.kind {
            FuncKind::Dissipation => &self.dissipation_used,
            FuncKind::Forces => &self.forces_used,
            FuncKind::Constraints => &self.constraints_used,
            FuncKind::Contacts => &self.contacts_used,
            FuncKind::VelocityConstraints => &self.velocity_used,
        }
    }
}

/// Every identifier in a single-segment path expression, and every identifier inside macro
/// invocations (their tokens are opaque, so any mention counts).
#[derive(Default)]
struct Mentions(HashSet<String>);

impl<'ast> Visit<'ast> for Mentions {
    fn visit_expr_path(&mut self, p: &'ast syn::ExprPath) {
        if p.qself.is_none() && p.path.segments.len() == 1 {
            self.0.insert(unraw(&p.path.segments[0].ident));
        }
        syn::visit::visit_expr_path(self, p);
    }
    fn visit_macro(&mut self, m: &'ast syn::Macro) {
        idents_in(m.tokens.clone(), &mut self.0);
    }
}

fn idents_in(ts: TokenStream, out: &mut HashSet<String>) {
    for tt in ts {
        match tt {
            TokenTree::Ident(i) => {
                out.insert(unraw(&i));
            }
            TokenTree::Group(g) => idents_in(g.stream(), out),
            _ => {}
        }
    }
}

/// The kind of an expression's value.
#[derive(Clone, Debug, PartialEq)]
enum Kind {
    Const,
    Var,
    Tuple(Vec<Kind>),
}

impl Kind {
    fn is_var(&self) -> bool {
        match self {
            Kind::Const => false,
            Kind::Var => true,
            Kind::Tuple(ks) => ks.iter().any(Kind::is_var),
        }
    }
    fn join(a: Kind, b: Kind) -> Kind {
        match (a, b) {
            (Kind::Tuple(x), Kind::Tuple(y)) if x.len() == y.len() => Kind::Tuple(
                x.into_iter()
                    .zip(y)
                    .map(|(a, b)| Kind::join(a, b))
                    .collect(),
            ),
            (a, b) if a.is_var() || b.is_var() => Kind::Var,
            _ => Kind::Const,
        }
    }
}

/// Rewrites the body for the jets path. `vars` are the bindings that carry coordinates or time.
pub fn lower_for_jets(
    body: &Block,
    vars: &[String],
    helpers: &Helpers,
    errors: &mut Errors,
) -> Block {
    rewrite(errors, helpers, |rw| {
        rw.scopes = vec![vars.iter().map(|v| (v.clone(), Kind::Var)).collect()];
        let mut body = body.clone();
        let kind = rw.block(&mut body);
        if kind == Kind::Const {
            lift_block_tail(&mut body);
        }
        body
    })
}

/// Runs a rewrite until every `let mut` binding that is later assigned a variable value
/// (`let mut sum = 0.0; … sum += m * v * v;`) is a variable from its `let` on (its constant
/// initial value lifted): each run may find more such bindings, so it runs again with them.
fn rewrite<T>(
    errors: &mut Errors,
    helpers: &Helpers,
    mut run: impl FnMut(&mut Rewriter) -> T,
) -> T {
    let mut promote = HashSet::new();
    loop {
        let mut rw = Rewriter {
            scopes: Vec::new(),
            errors: Vec::new(),
            promote: promote.clone(),
            found: HashSet::new(),
            helpers: helpers.clone(),
            closure_hint: None,
        };
        let out = run(&mut rw);
        if rw.found.is_subset(&promote) {
            rw.errors.into_iter().for_each(|e| errors.push(e));
            return out;
        }
        promote.extend(rw.found);
    }
}

/// Rewrites the body of `fn forces` (an array of `Scalar`s) for the jets path: as
/// [`lower_for_jets`], and a tail of constants becomes an array of `Scalar`s (each element of an
/// array literal lifted, any other array mapped through the lift).
pub fn lower_array_for_jets(
    body: &Block,
    vars: &[String],
    helpers: &Helpers,
    errors: &mut Errors,
) -> Block {
    rewrite(errors, helpers, |rw| lower_array_body(rw, body, vars))
}

fn lower_array_body(rw: &mut Rewriter, body: &Block, vars: &[String]) -> Block {
    rw.scopes = vec![vars.iter().map(|v| (v.clone(), Kind::Var)).collect()];
    let mut body = body.clone();
    let kind = rw.block(&mut body);
    if kind == Kind::Const {
        if let Some(Stmt::Expr(e, None)) = body.stmts.last_mut() {
            match e {
                Expr::Array(a) => a.elems.iter_mut().for_each(lift_in_place),
                other => {
                    let span = other.span();
                    *other = Expr::Verbatim(
                        quote_spanned!(span=> (#other).map(::lagrange::__private::lift::<Scalar, _>)),
                    );
                }
            }
        }
    }
    body
}

/// The helper methods of the impl block (those written with `Scalar`, see
/// [`crate::model::is_helper`]) made generic over the number type, their bodies rewritten as
/// [`lower_for_jets`] does; the other items as written.
pub fn lower_helpers_for_jets(
    rest: &syn::ItemImpl,
    helpers: &Helpers,
    errors: &mut Errors,
) -> syn::ItemImpl {
    let mut rest = rest.clone();
    for item in &mut rest.items {
        if let syn::ImplItem::Fn(f) = item {
            if crate::model::is_helper(f) {
                let (sig, block) = rewrite(errors, helpers, |rw| {
                    let (mut sig, mut block) = (f.sig.clone(), f.block.clone());
                    rw.generic_fn(&mut sig, &mut block);
                    (sig, block)
                });
                f.sig = sig;
                f.block = block;
                // The rewritten arithmetic keeps the user's parentheses as call arguments.
                f.attrs
                    .push(syn::parse_quote!(#[allow(unused_parens, unused_braces)]));
            }
        }
    }
    rest
}

struct Rewriter {
    scopes: Vec<HashMap<String, Kind>>,
    /// Mistakes a physicist makes that rustc would report in terms of the runtime's traits:
    /// `x ^ 2` meant as a power, `2 * x` with an integer literal.
    errors: Vec<syn::Error>,
    /// `let mut` bindings to make variables at their `let` (see [`rewrite`]).
    promote: HashSet<String>,
    /// Constant bindings this run saw assigned a variable value.
    found: HashSet<String>,
    /// The helper methods of the impl block (see [`helpers`]).
    helpers: Helpers,
    /// The kinds of the parameters of the closure about to be rewritten, when an iterator
    /// method passes it elements of known kinds.
    closure_hint: Option<Vec<Kind>>,
}

/// The helper methods of the impl block by name ([`crate::model::is_helper`]): for each
/// parameter after `self`, whether its type uses `Scalar` (a constant argument is lifted for
/// it) or not (an `f64` parameter takes the constant as it is).
pub type Helpers = std::rc::Rc<HashMap<String, Vec<bool>>>;

/// The helper methods of `rest`.
pub fn helpers(rest: &syn::ItemImpl) -> Helpers {
    std::rc::Rc::new(
        rest.items
            .iter()
            .filter_map(|item| match item {
                syn::ImplItem::Fn(f) if crate::model::is_helper(f) => Some((
                    unraw(&f.sig.ident),
                    f.sig
                        .inputs
                        .iter()
                        .filter_map(|a| match a {
                            syn::FnArg::Typed(pt) => Some(mentions_scalar(&pt.ty)),
                            syn::FnArg::Receiver(_) => None,
                        })
                        .collect(),
                )),
                _ => None,
            })
            .collect(),
    )
}

/// `v.norm().powi(2k)` → `v.norm_squared().powi(k)` (and `magnitude` alike): the same value,
/// but smooth at v = 0, where the jets of the square root are ∞·0 = NaN. The symbolic mode
/// folds √x to an even power the same way.
fn norm_power_to_norm_squared(m: &mut syn::ExprMethodCall) {
    if m.method != "powi" || m.args.len() != 1 {
        return;
    }
    let Some(Expr::Lit(syn::ExprLit {
        lit: syn::Lit::Int(n),
        ..
    })) = m.args.first()
    else {
        return;
    };
    let Ok(n) = n.base10_parse::<i32>() else {
        return;
    };
    let Expr::MethodCall(inner) = &mut *m.receiver else {
        return;
    };
    if n % 2 != 0
        || !inner.args.is_empty()
        || !(inner.method == "norm" || inner.method == "magnitude")
    {
        return;
    }
    let span = inner.method.span();
    inner.method = syn::Ident::new(&format!("{}_squared", inner.method), span);
    let half = proc_macro2::Literal::i32_unsuffixed(n / 2);
    m.args[0] = Expr::Verbatim(quote_spanned!(span=> #half));
}

/// The integer literal `e` is (through parentheses), if it is one without a float suffix.
fn int_literal(e: &Expr) -> Option<&syn::LitInt> {
    match paren_less(e) {
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Int(i),
            ..
        }) if i.suffix().is_empty() => Some(i),
        _ => None,
    }
}

fn is_float_literal(e: &Expr) -> bool {
    matches!(
        paren_less(e),
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Float(_),
            ..
        })
    )
}

/// A stand-in for an operand detached while a chain is walked (never emitted).
fn placeholder() -> Expr {
    Expr::Verbatim(TokenStream::new())
}

fn lift_tokens(e: &Expr) -> Expr {
    let span = e.span();
    Expr::Verbatim(quote_spanned!(span=> ::lagrange::__private::lift::<Scalar, _>(#e)))
}

fn lift_in_place(e: &mut Expr) {
    // Lift under a reference so `&self.g` becomes `&lift(self.g)`.
    if let Expr::Reference(r) = e {
        lift_in_place(&mut r.expr);
        return;
    }
    if let Expr::Paren(p) = e {
        lift_in_place(&mut p.expr);
        return;
    }
    *e = lift_tokens(e);
}

fn lift_block_tail(b: &mut Block) {
    if let Some(Stmt::Expr(e, None)) = b.stmts.last_mut() {
        lift_in_place(e);
    }
}

impl Rewriter {
    fn lookup(&self, name: &str) -> Option<Kind> {
        self.scopes.iter().rev().find_map(|s| s.get(name).cloned())
    }

    fn bind(&mut self, pat: &Pat, kind: Kind) {
        match pat {
            Pat::Ident(pi) => {
                if let Some(scope) = self.scopes.last_mut() {
                    scope.insert(unraw(&pi.ident), kind.clone());
                }
                if let Some((_, sub)) = &pi.subpat {
                    self.bind(sub, kind);
                }
            }
            Pat::Tuple(t) => {
                for (i, p) in t.elems.iter().enumerate() {
                    let k = match &kind {
                        Kind::Tuple(ks) => ks.get(i).cloned().unwrap_or(Kind::Var),
                        other => other.clone(),
                    };
                    self.bind(p, k);
                }
            }
            Pat::Type(pt) => {
                let k = if mentions_scalar(&pt.ty) {
                    Kind::Var
                } else {
                    kind
                };
                self.bind(&pt.pat, k);
            }
            Pat::Reference(r) => self.bind(&r.pat, kind),
            Pat::Paren(p) => self.bind(&p.pat, kind),
            Pat::Slice(s) => {
                for p in &s.elems {
                    self.bind(p, kind.clone());
                }
            }
            Pat::TupleStruct(ts) => {
                for p in &ts.elems {
                    self.bind(p, kind.clone());
                }
            }
            Pat::Struct(ps) => {
                for f in &ps.fields {
                    self.bind(&f.pat, kind.clone());
                }
            }
            Pat::Or(o) => {
                for p in &o.cases {
                    self.bind(p, kind.clone());
                }
            }
            _ => {}
        }
    }

    fn block(&mut self, b: &mut Block) -> Kind {
        self.scopes.push(HashMap::new());
        let mut kind = Kind::Const;
        let n = b.stmts.len();
        for (i, stmt) in b.stmts.iter_mut().enumerate() {
            let k = self.stmt(stmt);
            if i + 1 == n {
                kind = k;
            }
        }
        self.scopes.pop();
        kind
    }

    fn stmt(&mut self, s: &mut Stmt) -> Kind {
        match s {
            Stmt::Local(local) => {
                let mut kind = Kind::Const;
                if let Some(init) = &mut local.init {
                    kind = self.expr(&mut init.expr);
                    if let Some((_, diverge)) = &mut init.diverge {
                        self.expr(diverge);
                    }
                    if let Pat::Type(pt) = &local.pat {
                        if mentions_scalar(&pt.ty) && !kind.is_var() {
                            lift_in_place(&mut init.expr);
                            kind = Kind::Var;
                        }
                    }
                    // `let (mut a, mut b) = (0.0, 0.0);`: each element as its own `let`.
                    if let (Pat::Tuple(pt), Expr::Tuple(et), Kind::Tuple(ks)) =
                        (&local.pat, &mut *init.expr, &mut kind)
                    {
                        if pt.elems.len() == et.elems.len() && ks.len() == et.elems.len() {
                            for ((p, e), k) in pt.elems.iter().zip(et.elems.iter_mut()).zip(ks) {
                                if *k == Kind::Const
                                    && mut_binding(p).is_some_and(|n| self.promote.contains(&n))
                                {
                                    lift_in_place(e);
                                    *k = Kind::Var;
                                }
                            }
                        }
                    }
                    if kind == Kind::Const
                        && mut_binding(&local.pat).is_some_and(|n| self.promote.contains(&n))
                    {
                        match &mut *init.expr {
                            Expr::Array(a) => a.elems.iter_mut().for_each(lift_in_place),
                            Expr::Repeat(r) => lift_in_place(&mut r.expr),
                            other => lift_in_place(other),
                        }
                        kind = Kind::Var;
                    }
                }
                self.bind(&local.pat, kind);
                Kind::Const
            }
            Stmt::Expr(e, semi) => {
                let k = self.expr(e);
                if semi.is_some() {
                    Kind::Const
                } else {
                    k
                }
            }
            Stmt::Macro(m) => self.macro_kind(&m.mac.tokens),
            Stmt::Item(syn::Item::Fn(f)) if crate::model::uses_scalar(&f.sig) => {
                // A nested `fn` written with `Scalar`: generic over it, like the body's own.
                let saved = std::mem::take(&mut self.scopes);
                self.generic_fn(&mut f.sig, &mut f.block);
                self.scopes = saved;
                Kind::Const
            }
            Stmt::Item(_) => Kind::Const,
        }
    }

    /// A function written with `Scalar` (a helper method, a nested `fn`): generic over the
    /// number type, its parameters typed with `Scalar` variables, its body rewritten, and a
    /// constant tail lifted when it returns a `Scalar`.
    fn generic_fn(&mut self, sig: &mut syn::Signature, block: &mut Block) {
        sig.generics
            .params
            .push(syn::parse_quote!(Scalar: ::lagrange::__private::Scalar));
        self.scopes.push(HashMap::new());
        for arg in &sig.inputs {
            if let syn::FnArg::Typed(pt) = arg {
                self.bind(
                    &pt.pat,
                    if mentions_scalar(&pt.ty) {
                        Kind::Var
                    } else {
                        Kind::Const
                    },
                );
            }
        }
        let kind = self.block(block);
        self.scopes.pop();
        let returns_scalar = matches!(&sig.output, syn::ReturnType::Type(_, t) if matches!(&**t, syn::Type::Path(p) if p.path.is_ident("Scalar")));
        if kind == Kind::Const && returns_scalar {
            lift_block_tail(block);
        }
    }

    fn macro_kind(&self, tokens: &TokenStream) -> Kind {
        let mut ids = HashSet::new();
        idents_in(tokens.clone(), &mut ids);
        if ids
            .iter()
            .any(|i| self.lookup(i).is_some_and(|k| k.is_var()))
        {
            Kind::Var
        } else {
            Kind::Const
        }
    }

    fn expr(&mut self, e: &mut Expr) -> Kind {
        match e {
            Expr::Lit(_) => Kind::Const,
            Expr::Path(p) => {
                if p.qself.is_none() && p.path.segments.len() == 1 {
                    self.lookup(&unraw(&p.path.segments[0].ident))
                        .unwrap_or(Kind::Const)
                } else if tokens_mention_scalar(quote!(#p)) {
                    // `<Scalar as Trait>::CONST`, `Scalar::from_...`: a value of the scalar type.
                    Kind::Var
                } else {
                    Kind::Const
                }
            }
            Expr::Field(f) => {
                let k = self.expr(&mut f.base);
                match (&k, &f.member) {
                    (Kind::Tuple(ks), syn::Member::Unnamed(i)) => {
                        ks.get(i.index as usize).cloned().unwrap_or(Kind::Var)
                    }
                    _ => Kind::join(k, Kind::Const),
                }
            }
            Expr::Paren(p) => self.expr(&mut p.expr),
            Expr::Group(g) => self.expr(&mut g.expr),
            Expr::Reference(r) => self.expr(&mut r.expr),
            Expr::Unary(u) => {
                let k = self.expr(&mut u.expr);
                match u.op {
                    syn::UnOp::Not(_) => Kind::Const,
                    // `*v` of an element of `q.iter()`, which is by value here (see
                    // `method_chain`), or of a reference: the value either way.
                    syn::UnOp::Deref(_) if k == Kind::Var => {
                        let inner = &u.expr;
                        let span = u.op.span();
                        *e = Expr::Verbatim(
                            quote_spanned!(span=> ::lagrange::__private::by_value(#inner)),
                        );
                        k
                    }
                    _ => k,
                }
            }
            Expr::Binary(_) => self.binary(e),
            Expr::MethodCall(_) => self.method_chain(e),
            Expr::Call(c) => {
                // A callee that names `Scalar` (`Scalar::constant(2.0)`, `zero::<Scalar>()`,
                // `Vector3::<Scalar>::zeros()`) returns a scalar-typed value even when every
                // argument is a constant.
                let kf = if tokens_mention_scalar(c.func.to_token_stream()) {
                    self.expr(&mut c.func);
                    Kind::Var
                } else {
                    self.expr(&mut c.func)
                };
                let kargs: Vec<Kind> = c.args.iter_mut().map(|a| self.expr(a)).collect();
                let any_var = kf.is_var() || kargs.iter().any(Kind::is_var);
                if any_var && is_constructor(&c.func) {
                    for (a, k) in c.args.iter_mut().zip(&kargs) {
                        if *k == Kind::Const {
                            lift_in_place(a);
                        }
                    }
                }
                if any_var {
                    Kind::Var
                } else {
                    Kind::Const
                }
            }
            Expr::Tuple(t) => Kind::Tuple(t.elems.iter_mut().map(|x| self.expr(x)).collect()),
            Expr::Array(a) => {
                let ks: Vec<Kind> = a.elems.iter_mut().map(|x| self.expr(x)).collect();
                let any_var = ks.iter().any(Kind::is_var);
                if any_var {
                    for (x, k) in a.elems.iter_mut().zip(&ks) {
                        if *k == Kind::Const {
                            lift_in_place(x);
                        }
                    }
                    Kind::Var
                } else {
                    Kind::Const
                }
            }
            Expr::Block(b) => self.block(&mut b.block),
            Expr::Unsafe(b) => self.block(&mut b.block),
            Expr::If(i) => {
                self.expr(&mut i.cond);
                let kt = self.block(&mut i.then_branch);
                match &mut i.else_branch {
                    Some((_, els)) => {
                        let ke = self.expr(els);
                        if kt == Kind::Const && ke == Kind::Var {
                            lift_block_tail(&mut i.then_branch);
                        } else if kt == Kind::Var && ke == Kind::Const {
                            lift_in_place(els);
                        }
                        Kind::join(kt, ke)
                    }
                    None => Kind::Const,
                }
            }
            Expr::Match(m) => {
                let ks = self.expr(&mut m.expr);
                let mut kinds = Vec::new();
                for arm in &mut m.arms {
                    self.scopes.push(HashMap::new());
                    self.bind(&arm.pat, ks.clone());
                    kinds.push(self.expr(&mut arm.body));
                    self.scopes.pop();
                }
                let joined = kinds.iter().cloned().fold(Kind::Const, Kind::join);
                if joined == Kind::Var {
                    for (arm, k) in m.arms.iter_mut().zip(&kinds) {
                        if *k == Kind::Const {
                            lift_in_place(&mut arm.body);
                        }
                    }
                }
                joined
            }
            Expr::Let(l) => {
                let k = self.expr(&mut l.expr);
                self.bind(&l.pat, k);
                Kind::Const
            }
            Expr::Cast(c) => self.expr(&mut c.expr),
            Expr::Index(i) => {
                let k = self.expr(&mut i.expr);
                // An index is an integer (`q[i - 1]`): no "write 1.0" inside it.
                let n = self.errors.len();
                self.expr(&mut i.index);
                self.errors.truncate(n);
                Kind::join(k, Kind::Const)
            }
            Expr::Assign(a) => {
                let kl = self.expr(&mut a.left);
                let kr = self.expr(&mut a.right);
                if kl.is_var() && kr == Kind::Const {
                    lift_in_place(&mut a.right);
                }
                if kl == Kind::Const && kr.is_var() {
                    self.found.extend(assigned_root(&a.left));
                }
                Kind::Const
            }
            Expr::Closure(c) => {
                self.scopes.push(HashMap::new());
                // A parameter typed with anything but `Scalar` (`|m: f64, v: Scalar|`) is a
                // constant; an untyped one has the kind of the elements an iterator method
                // passes it (`.map(|(v, m)| ..)` after a `.zip`), or may carry the coordinates.
                let hint = self.closure_hint.take().unwrap_or_default();
                for (i, p) in c.inputs.iter().enumerate() {
                    let k = match p {
                        Pat::Type(pt) if !mentions_scalar(&pt.ty) => Kind::Const,
                        Pat::Type(_) => Kind::Var,
                        _ => hint.get(i).cloned().unwrap_or(Kind::Var),
                    };
                    self.bind(p, k);
                }
                let k = self.expr(&mut c.body);
                self.scopes.pop();
                if k.is_var() || self.macro_kind(&quote!(#c)).is_var() {
                    Kind::Var
                } else {
                    Kind::Const
                }
            }
            Expr::ForLoop(f) => {
                let k = self.expr(&mut f.expr);
                self.scopes.push(HashMap::new());
                self.bind(&f.pat, k);
                self.block(&mut f.body);
                self.scopes.pop();
                Kind::Const
            }
            Expr::While(w) => {
                self.expr(&mut w.cond);
                self.block(&mut w.body);
                Kind::Const
            }
            Expr::Loop(l) => {
                self.block(&mut l.body);
                Kind::Const
            }
            Expr::Return(r) => {
                if let Some(x) = &mut r.expr {
                    if self.expr(x) == Kind::Const {
                        lift_in_place(x);
                    }
                }
                Kind::Const
            }
            Expr::Macro(m) => self.macro_kind(&m.mac.tokens),
            other => self.macro_kind(&quote!(#other)),
        }
    }

    /// A chain of method calls `x.sin().cos()…`, walked along its receivers with a loop (a
    /// 2000-deep chain must not overflow the compiler's stack), innermost call first.
    fn method_chain(&mut self, e: &mut Expr) -> Kind {
        let mut spine = Vec::new();
        let mut cur = std::mem::replace(e, placeholder());
        while let Expr::MethodCall(mut m) = cur {
            cur = std::mem::replace(&mut *m.receiver, placeholder());
            spine.push(m);
        }
        let mut kr = self.expr(&mut cur);
        while let Some(mut m) = spine.pop() {
            *m.receiver = cur;
            // `q.iter()` of an array of the number type: by value, so the elements are
            // `Scalar`s (generic code has no arithmetic on `&Scalar`); `*v` on them is dropped.
            if kr.is_var() && m.method == "iter" && m.args.is_empty() {
                let recv = &m.receiver;
                let span = m.method.span();
                cur = Expr::Verbatim(
                    quote_spanned!(span=> ::core::iter::IntoIterator::into_iter(#recv)),
                );
                continue;
            }
            kr = self.method_one(&mut m, kr);
            cur = Expr::MethodCall(m);
        }
        *e = cur;
        kr
    }

    /// One call of a chain, its receiver's kind `kr` known.
    fn method_one(&mut self, m: &mut syn::ExprMethodCall, kr: Kind) -> Kind {
        norm_power_to_norm_squared(m);
        let name = m.method.to_string();
        let mut kargs: Vec<Kind> = Vec::with_capacity(m.args.len());
        for (i, a) in m.args.iter_mut().enumerate() {
            // The kinds of the elements a closure argument of an iterator method receives.
            if matches!(a, Expr::Closure(_)) {
                self.closure_hint = match (name.as_str(), i) {
                    ("map" | "for_each" | "filter" | "any" | "all", 0) => Some(vec![kr.clone()]),
                    ("fold", 1) => Some(vec![kargs[0].clone(), kr.clone()]),
                    _ => None,
                };
            }
            kargs.push(self.expr(a));
            self.closure_hint = None;
        }
        if m.method == "powi" {
            return kr;
        }
        let any_var = kr.is_var() || kargs.iter().any(Kind::is_var);
        if !any_var {
            return Kind::Const;
        }
        // Iterator adaptors take what they are given (`q.iter().zip(self.m.iter())`); the
        // kind is their elements'.
        if ITERATOR_METHODS.contains(&name.as_str()) {
            return match (name.as_str(), kargs.as_slice()) {
                ("zip", [k]) => Kind::Tuple(vec![kr, k.clone()]),
                ("enumerate", _) => Kind::Tuple(vec![Kind::Const, kr]),
                ("map", [k]) => k.clone(),
                ("fold", [a, b]) => Kind::join(a.clone(), b.clone()),
                ("sum" | "product", _) => Kind::join(kr, Kind::Const),
                ("count" | "len", _) => Kind::Const,
                _ => kr,
            };
        }
        // A method of the user's own type (`self.omega(t)`) takes its arguments as
        // declared: `self` is never lifted.
        if kr == Kind::Const && !is_self(&m.receiver) {
            lift_in_place(&mut m.receiver);
        }
        // A helper method takes a constant as it is where it declares an `f64`.
        let declared = if is_self(&m.receiver) {
            self.helpers.get(&unraw(&m.method)).cloned()
        } else {
            None
        };
        // A contact's restitution coefficient and name (`Contact::gap(y).restitution(self.e)`)
        // are an `f64` and a `&str`, not numbers of the motion.
        let as_written = matches!(name.as_str(), "restitution" | "named");
        for (i, (a, k)) in m.args.iter_mut().zip(&kargs).enumerate() {
            let wants_scalar = !as_written
                && declared
                    .as_ref()
                    .is_none_or(|d| d.get(i).copied().unwrap_or(true));
            if *k == Kind::Const && wants_scalar {
                lift_in_place(a);
            }
        }
        Kind::Var
    }

    /// A chain of binary operators `a + b + c …` (left-nested), walked down its left operands
    /// with a loop (a 2000-term sum must not overflow the compiler's stack), innermost first.
    fn binary(&mut self, e: &mut Expr) -> Kind {
        let mut spine = Vec::new();
        let mut cur = std::mem::replace(e, placeholder());
        while let Expr::Binary(mut b) = cur {
            cur = std::mem::replace(&mut *b.left, placeholder());
            spine.push(b);
        }
        let mut kl = self.expr(&mut cur);
        while let Some(mut b) = spine.pop() {
            *b.left = cur;
            let mut node = Expr::Binary(b);
            kl = self.binary_one(&mut node, kl);
            cur = node;
        }
        *e = cur;
        kl
    }

    /// One operator of a chain, its left operand's kind `kl` known; may replace `e` by the
    /// mixed-operand call it needs.
    fn binary_one(&mut self, e: &mut Expr, kl: Kind) -> Kind {
        let Expr::Binary(b) = e else {
            return Kind::Const;
        };
        let kr = self.expr(&mut b.right);
        if matches!(b.op, BinOp::BitXor(_) | BinOp::BitXorAssign(_)) {
            self.errors.push(syn::Error::new(
                b.op.span(),
                "`^` is bitwise xor in Rust, not a power: write `x.powi(2)` for an integer power \
                 (`x.powf(p)` for a real one)",
            ));
        }
        if matches!(
            b.op,
            BinOp::Add(_)
                | BinOp::Sub(_)
                | BinOp::Mul(_)
                | BinOp::Div(_)
                | BinOp::AddAssign(_)
                | BinOp::SubAssign(_)
                | BinOp::MulAssign(_)
                | BinOp::DivAssign(_)
        ) {
            // An integer literal next to a value of the coordinates or a float: the number
            // type is f64, so `2` must be `2.0`.
            for (lit, other, ko) in [(&*b.left, &*b.right, &kr), (&*b.right, &*b.left, &kl)] {
                if let Some(i) = int_literal(lit) {
                    if ko.is_var() || is_float_literal(other) {
                        self.errors.push(syn::Error::new(
                            i.span(),
                            format!(
                                "an integer literal where a number of type f64 is needed: write `{}.0`",
                                i.base10_digits()
                            ),
                        ));
                    }
                }
            }
        }
        let mixed = |kl: &Kind, kr: &Kind| {
            (kl.is_var() && *kr == Kind::Const) || (*kl == Kind::Const && kr.is_var())
        };
        let arith = match b.op {
            BinOp::Add(_) => Some(("ConstAdd", "const_add", "AddConst", "add_const")),
            BinOp::Sub(_) => Some(("ConstSub", "const_sub", "SubConst", "sub_const")),
            BinOp::Mul(_) => Some(("ConstMul", "const_mul", "MulConst", "mul_const")),
            BinOp::Div(_) => Some(("ConstDiv", "const_div", "DivConst", "div_const")),
            _ => None,
        };
        if let Some((ct, cf, vt, vf)) = arith {
            if mixed(&kl, &kr) {
                let span = b.op.span();
                let (l, r) = (&b.left, &b.right);
                let (tr, f) = if kl == Kind::Const {
                    (ct, cf)
                } else {
                    (vt, vf)
                };
                let tr = syn::Ident::new(tr, span);
                let f = syn::Ident::new(f, span);
                *e = Expr::Verbatim(quote_spanned!(span=> ::lagrange::__private::#tr::#f(#l, #r)));
                return Kind::Var;
            }
            return Kind::join(kl, kr);
        }
        match b.op {
            BinOp::Rem(_) => {
                if mixed(&kl, &kr) {
                    if kl == Kind::Const {
                        lift_in_place(&mut b.left);
                    } else {
                        lift_in_place(&mut b.right);
                    }
                }
                Kind::join(kl, kr)
            }
            BinOp::Eq(_)
            | BinOp::Ne(_)
            | BinOp::Lt(_)
            | BinOp::Le(_)
            | BinOp::Gt(_)
            | BinOp::Ge(_) => {
                if mixed(&kl, &kr) {
                    if kl == Kind::Const {
                        lift_in_place(&mut b.left);
                    } else {
                        lift_in_place(&mut b.right);
                    }
                }
                Kind::Const
            }
            BinOp::AddAssign(_)
            | BinOp::SubAssign(_)
            | BinOp::MulAssign(_)
            | BinOp::DivAssign(_)
            | BinOp::RemAssign(_) => {
                if kl.is_var() && kr == Kind::Const {
                    lift_in_place(&mut b.right);
                }
                if kl == Kind::Const && kr.is_var() {
                    self.found.extend(assigned_root(&b.left));
                }
                Kind::Const
            }
            _ => Kind::join(kl, kr),
        }
    }
}

/// Iterator methods: their receiver and arguments are never lifted.
pub const ITERATOR_METHODS: &[&str] = &[
    "iter",
    "into_iter",
    "enumerate",
    "zip",
    "map",
    "rev",
    "skip",
    "take",
    "step_by",
    "copied",
    "cloned",
    "sum",
    "product",
    "fold",
    "count",
    "len",
];

/// The name a `let mut name` (or `let mut name: T`) binds.
fn mut_binding(pat: &Pat) -> Option<String> {
    match pat {
        Pat::Ident(pi) if pi.mutability.is_some() => Some(unraw(&pi.ident)),
        Pat::Type(pt) => mut_binding(&pt.pat),
        _ => None,
    }
}

/// The binding an assignment writes to: `x` of `x`, `x[i]`, `x[i][j]`.
fn assigned_root(e: &Expr) -> Option<String> {
    match paren_less(e) {
        Expr::Index(ix) => assigned_root(&ix.expr),
        Expr::Path(p) => p.path.get_ident().map(unraw),
        _ => None,
    }
}

/// The bare `self` path.
fn is_self(e: &Expr) -> bool {
    matches!(e, Expr::Path(p) if p.qself.is_none() && p.path.is_ident("self"))
}

/// `Vector3::new(..)`-like calls (a path of two or more segments ending in `new`): their
/// arguments must all be of one number type, so constants are lifted.
fn is_constructor(func: &Expr) -> bool {
    match func {
        Expr::Path(p) => {
            p.path.segments.len() >= 2 && p.path.segments.last().is_some_and(|s| s.ident == "new")
        }
        _ => false,
    }
}

fn mentions_scalar(ty: &syn::Type) -> bool {
    tokens_mention_scalar(quote!(#ty))
}

fn tokens_mention_scalar(ts: TokenStream) -> bool {
    let mut ids = HashSet::new();
    idents_in(ts, &mut ids);
    ids.contains("Scalar")
}
