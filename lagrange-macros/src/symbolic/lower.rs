//! Lowering of the Lagrangian body (a `syn::Block`) into the expression DAG.
//!
//! Values are scalars (one node), vectors (three nodes), tuples, or poison (after an error, so
//! that every unsupported construct in the body is reported at once). `self.<field>` becomes a
//! parameter symbol; whether a field is an `f64` or a `Vector3<f64>` is inferred from its use:
//! every field starts as a scalar and is re-typed as a vector (and the body lowered again) when a
//! vector is required where it flows. The emitted code loads each field with its inferred type,
//! so a wrong inference is a compile error at the field.

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit, Member, Pat, Stmt, UnOp};

use super::dag::{Dag, Fun, Id, Node};
use crate::errors::Errors;
use crate::model::{unraw, CoordKind, Decl, Func};

/// A `self.<field>` used in the body.
#[derive(Clone, Debug)]
pub struct Field {
    /// The field name.
    pub name: String,
    /// Span of the first use (typed loads point here).
    pub span: Span,
    /// The member as written (`gravity`, `r#type`, `0`).
    pub member: Member,
    /// Inferred as `Vector3<f64>`.
    pub vector: bool,
    /// Seen directly in a scalar-only position: never re-typed as a vector.
    confirmed_scalar: bool,
    /// A free name from the user's scope (a `const`, a `static`, an imported `PI`), loaded as
    /// written instead of through `self`; rustc resolves it (and reports it if it is undefined).
    pub free: bool,
    /// Parameter-only code the symbolic mode does not lower (`Self::K`, `self.n as f64`, a
    /// `match` on a parameter, `self.k[i]`, a call of the user's own function of parameters):
    /// its tokens as written (`self` resolved like the field loads), evaluated once per call as
    /// an `f64` and treated as a parameter. `name` is then its text, for the printed equations.
    pub opaque: Option<(usize, proc_macro2::TokenStream)>,
}

/// The condition of an `if` that depends on constants only: evaluated once per call, at run
/// time, as a `bool` (`let <b_k>: bool = <tokens>;`, the local named by `names::cond`).
#[derive(Clone, Debug)]
pub struct Cond {
    /// The condition as written, with `self` resolved like the field loads.
    pub tokens: proc_macro2::TokenStream,
    /// The condition for people (`k > 0.0`).
    pub text: String,
    /// Where it is written.
    pub span: Span,
    /// A zip's guard (`2 < self.k.len()`: the array field reaches this element), not written by
    /// the user: `EQUATIONS` print the guarded value as if it held (see [`Zipped`]).
    pub assumed: bool,
}

#[derive(Clone, Debug)]
enum Val {
    S(Id),
    V([Id; 3]),
    Tuple(Vec<Val>),
    /// An array (`Coords<K>` bindings, `[a, b]`, `[0.0; K]`) or a materialized iterator
    /// (`q.iter().zip(..)`, `0..K`): one value per element.
    A(Vec<Val>),
    /// An integer known when the macro runs: a loop variable, an integer literal, `q.len()`,
    /// an integer `const` of the impl block. Becomes a constant where a scalar is needed.
    I(i64),
    /// A closure, a nested `fn` item or a helper method of the impl block: inlined at each call.
    F(std::rc::Rc<Callable>),
    /// An array field of the struct (`self.m`), whose length the macro cannot know: indexed
    /// with a known integer (`self.m[i]`) or zipped with an array of known length.
    Seq(Box<Expr>),
    /// A zip with such an array field (`q.iter().zip(self.m.iter())`): see [`Zipped`].
    Z(Box<Zipped>),
    Poison,
}

/// `zip` with an array field whose length the macro does not know (`q.iter().zip(self.k.iter())`,
/// `self.k.iter().zip(q.iter())`): the elements of the side whose length it knows, each guarded.
/// Like Rust's `zip`, the sequence stops at the shorter side, so an element exists when every
/// array field it reads is longer than the position it reads there (`2 < self.k.len()`): a
/// condition on parameters, evaluated once per call. The consumers (`for`, `sum`, `product`,
/// `fold`) take each element's contribution under its condition (a `Select`), and the loads are
/// `self.k.get(2)`, so a field shorter than the coordinates neither panics nor adds terms.
#[derive(Clone, Debug)]
struct Zipped {
    items: Vec<(Val, Guard)>,
    /// The elements are in the order they were zipped in (`false` after `.rev()`): the ones that
    /// exist are then a prefix, so `.enumerate()`, `.skip(k)`, `.take(k)`, `.step_by(k)` and
    /// `.zip(..)` may follow.
    forward: bool,
}

/// The array fields an element of a [`Zipped`] reads and at which position.
type Guard = Vec<(Expr, usize)>;

/// A function the lowering inlines: its parameter patterns, its body and the bindings it sees.
struct Callable {
    /// What it is, for messages (`this closure`, `the helper method `kinetic``).
    what: String,
    params: Vec<Pat>,
    body: CallBody,
    /// The bindings visible in the body (a closure's captured scope; none for an item).
    env: Vec<(String, Val)>,
    /// A `fn` item: sees the other `fn` items of the scope it is called from, not the locals.
    item: bool,
}

enum CallBody {
    Expr(Expr),
    Block(syn::Block),
}

impl std::fmt::Debug for Callable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.what)
    }
}

/// The most elements one loop or array may unroll to.
const MAX_UNROLL: i64 = 100_000;

/// How deep helpers, closures and nested functions may call each other (recursion is an error).
const MAX_CALL_DEPTH: usize = 64;

/// The most loop iterations (of `for` loops and of `.sum()`/`.product()`) and inlined calls
/// (helpers, closures, nested `fn`s, the closures of `.map()`/`.fold()`) the lowering of one body
/// expands, in total: beyond it (1000 × 1000 nested loops, a helper that calls itself twice per
/// level) the macro would run for minutes and gigabytes, so it is a compile error that says to
/// use the jets.
const MAX_WORK: usize = 100_000;

impl Val {
    /// What the value is, for messages (`a Vector3`, `an array`).
    fn kind(&self) -> &'static str {
        match self {
            Val::S(_) => "a scalar",
            Val::V(_) => "a Vector3",
            Val::Tuple(_) => "a tuple",
            Val::A(_) => "an array",
            Val::I(_) => "an integer",
            Val::F(_) => "a function",
            Val::Seq(_) => "an array field whose length the macro does not know",
            Val::Z(_) => "a zip with an array field whose length the macro does not know",
            Val::Poison => "an erroneous value",
        }
    }
}

/// Lowering must restart because a field turned out to be a vector.
struct Retype(usize);

type R<T> = Result<T, Retype>;

/// The lowered bodies: the DAG, the nodes of L (and of D and Q, if given), and the fields and
/// conditions they read (shared: one DAG holds all three).
pub struct Lowered {
    pub dag: Dag,
    pub lagrangian: Id,
    /// D, the Rayleigh dissipation function (`fn dissipation`).
    pub dissipation: Option<Id>,
    /// Q, the generalized forces (`fn forces`), one per slot.
    pub forces: Option<Vec<Id>>,
    pub fields: Vec<Field>,
    pub conds: Vec<Cond>,
}

/// The error message for a construct the symbolic lowering cannot handle.
pub fn unsupported(span: Span, what: &str) -> syn::Error {
    syn::Error::new(
        span,
        format!(
            "{what} is not supported in symbolic mode; use `#[lagrangian(mode = \"jets\")]` on this \
             impl block to derive the equations with run-time jets instead"
        ),
    )
}

/// The values of the three bodies, before they are checked to be scalars.
struct Bodies {
    lagrangian: Val,
    dissipation: Option<Val>,
    /// `None` inside: the tail was not an array literal (an error was recorded).
    forces: Option<Option<Vec<Val>>>,
}

/// Lowers the bodies of `decl` (`fn lagrangian`, and `fn dissipation` and `fn forces` if given)
/// into one DAG; `None` (with every reason pushed to `sink`) when a body uses what the symbolic
/// mode cannot lower.
pub fn lower(decl: &Decl, sink: &mut Errors) -> Option<Lowered> {
    let mut fields: Vec<Field> = Vec::new();
    // Each retry turns one more field into a vector, so this terminates.
    loop {
        let mut lw = Lower {
            dag: Dag::new(decl.n()),
            scopes: Vec::new(),
            errors: Vec::new(),
            fields: std::mem::take(&mut fields),
            conds: Vec::new(),
            helpers: helpers(&decl.rest),
            int_consts: int_consts(&decl.rest),
            depth: 0,
            frame_base: 0,
            work: 0,
            over_budget: false,
        };
        match lw.bodies(decl) {
            Err(Retype(f)) => {
                fields = lw.fields;
                fields[f].vector = true;
                continue;
            }
            Ok(vals) => {
                let l = lw.scalar_result(vals.lagrangian, &decl.body, "the Lagrangian");
                let d = match (vals.dissipation, &decl.dissipation) {
                    (Some(v), Some(f)) => Some(lw.scalar_result(
                        v,
                        &f.body,
                        "the dissipation function D (`fn dissipation`)",
                    )),
                    _ => None,
                };
                let q = match (vals.forces, &decl.forces) {
                    (Some(Some(vs)), Some(f)) => Some(
                        vs.into_iter()
                            .map(|v| lw.scalar_result(v, &f.body, "each generalized force"))
                            .collect::<Option<Vec<Id>>>(),
                    ),
                    (Some(None), _) => Some(None),
                    _ => None,
                };
                let errors = std::mem::take(&mut lw.errors);
                // Only the errors of the last (complete) attempt count: an earlier one stopped at
                // a re-typed field.
                let complete = l.is_some()
                    && d.is_none_or(|d| d.is_some())
                    && q.as_ref().is_none_or(|q| q.is_some());
                return match (complete, errors.is_empty()) {
                    (true, true) => Some(Lowered {
                        dag: lw.dag,
                        lagrangian: l?,
                        dissipation: d.flatten(),
                        forces: q.flatten(),
                        fields: lw.fields,
                        conds: lw.conds,
                    }),
                    _ => {
                        errors.into_iter().for_each(|e| sink.push(e));
                        None
                    }
                };
            }
        }
    }
}

fn body_tail_span(b: &syn::Block) -> Span {
    match b.stmts.last() {
        Some(s) => s.span(),
        None => b.brace_token.span.join(),
    }
}

struct Lower {
    dag: Dag,
    scopes: Vec<(String, Val)>,
    errors: Vec<syn::Error>,
    fields: Vec<Field>,
    conds: Vec<Cond>,
    /// The methods of the impl block written with `Scalar` (`fn kinetic(&self, v: Scalar) ->
    /// Scalar`), inlined where the body calls them.
    helpers: std::collections::HashMap<String, std::rc::Rc<Callable>>,
    /// The integer `const`s of the impl block with a literal value (`const N: usize = 6;`).
    int_consts: std::collections::HashMap<String, i64>,
    /// How many inlined calls are open.
    depth: usize,
    /// In an inlined call, how many bindings it captured: assigning to one of them (a closure
    /// that mutates its environment) is not lowered.
    frame_base: usize,
    /// Loop iterations and inlined calls expanded in the current body (see [`MAX_WORK`]).
    work: usize,
    /// The current body went past [`MAX_WORK`] (reported once): what is left of it is not
    /// expanded.
    over_budget: bool,
}

/// The patterns of a function's parameters after `self`.
fn param_pats(sig: &syn::Signature) -> Vec<Pat> {
    sig.inputs
        .iter()
        .filter_map(|a| match a {
            syn::FnArg::Typed(pt) => Some((*pt.pat).clone()),
            syn::FnArg::Receiver(_) => None,
        })
        .collect()
}

fn helpers(rest: &syn::ItemImpl) -> std::collections::HashMap<String, std::rc::Rc<Callable>> {
    rest.items
        .iter()
        .filter_map(|item| match item {
            syn::ImplItem::Fn(f) if crate::model::is_helper(f) => {
                let params = param_pats(&f.sig);
                Some((
                    unraw(&f.sig.ident),
                    std::rc::Rc::new(Callable {
                        what: format!("the helper method `{}`", f.sig.ident),
                        params,
                        body: CallBody::Block(f.block.clone()),
                        env: Vec::new(),
                        item: false,
                    }),
                ))
            }
            _ => None,
        })
        .collect()
}

fn int_consts(rest: &syn::ItemImpl) -> std::collections::HashMap<String, i64> {
    rest.items
        .iter()
        .filter_map(|item| match item {
            syn::ImplItem::Const(c) => int_literal(&c.expr).map(|k| (unraw(&c.ident), k)),
            _ => None,
        })
        .collect()
}

/// The identifiers of a path's segments (`f64::consts::PI` → ["f64", "consts", "PI"]).
/// Where an error points, computed only when one is reported: `Spanned::span` of an expression
/// walks all of its tokens, so taking it eagerly at every link of a 2000-deep chain is quadratic.
trait At {
    fn at(&self) -> Span;
    /// An error that covers the whole construct where the syntax has one (first to last token).
    fn error(&self, msg: String) -> syn::Error {
        syn::Error::new(self.at(), msg)
    }
}

impl At for Span {
    fn at(&self) -> Span {
        *self
    }
}

impl At for Expr {
    fn at(&self) -> Span {
        self.span()
    }
    fn error(&self, msg: String) -> syn::Error {
        syn::Error::new_spanned(self, msg)
    }
}

impl At for syn::ExprMethodCall {
    fn at(&self) -> Span {
        self.span()
    }
    fn error(&self, msg: String) -> syn::Error {
        syn::Error::new_spanned(self, msg)
    }
}

/// The head of a `for` loop (`for i in 0..N`), where an error about the loop points.
struct LoopHead<'a>(&'a syn::ExprForLoop);

impl At for LoopHead<'_> {
    fn at(&self) -> Span {
        self.0.for_token.span
    }
    fn error(&self, msg: String) -> syn::Error {
        let f = self.0;
        let (for_token, pat, in_token, expr) = (&f.for_token, &f.pat, &f.in_token, &f.expr);
        syn::Error::new_spanned(quote::quote!(#for_token #pat #in_token #expr), msg)
    }
}

impl At for syn::ExprCall {
    fn at(&self) -> Span {
        self.span()
    }
    fn error(&self, msg: String) -> syn::Error {
        syn::Error::new_spanned(self, msg)
    }
}

/// `a` where u ≥ v, else `b`: a·H(u − v) + b·(1 − H(u − v)), exact (one product is by 1, the
/// other by 0). With the jets' rule at a tie (the receiver, also for −0 against +0):
/// `x.max(y)` is `pick(x, y, x, y)`, `x.min(y)` is `pick(x, y, y, x)`, and `x.clamp(lo, hi)`
/// is `min(max(x, lo), hi)`, as the jets compute it.
fn pick(d: &mut Dag, a: Id, b: Id, u: Id, v: Id) -> Id {
    let diff = d.sub(u, v);
    let h = d.un(Fun::Step, diff);
    let ah = d.mul(a, h);
    let not_h = d.sub(Dag::ONE, h);
    let bn = d.mul(b, not_h);
    d.add(ah, bn)
}

fn segment_names(path: &syn::Path) -> Vec<String> {
    path.segments.iter().map(|s| s.ident.to_string()).collect()
}

fn paren_less(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => paren_less(&p.expr),
        Expr::Group(g) => paren_less(&g.expr),
        _ => e,
    }
}

/// An integer literal, possibly negated and parenthesized.
fn int_literal(e: &Expr) -> Option<i64> {
    match paren_less(e) {
        Expr::Lit(l) => match &l.lit {
            Lit::Int(i) => i.base10_parse::<i64>().ok(),
            _ => None,
        },
        Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => int_literal(&u.expr).map(|x| -x),
        _ => None,
    }
}

fn expr_kind(e: &Expr) -> &'static str {
    match e {
        Expr::If(_) => "`if`",
        Expr::Match(_) => "`match`",
        Expr::ForLoop(_) => "a `for` loop",
        Expr::While(_) => "a `while` loop",
        Expr::Loop(_) => "a `loop`",
        Expr::Closure(_) => "a closure",
        Expr::Macro(_) => "a macro call",
        Expr::Cast(_) => "an `as` cast",
        Expr::Return(_) => "`return`",
        Expr::Break(_) | Expr::Continue(_) => "`break`/`continue`",
        Expr::Array(_) | Expr::Repeat(_) => "an array",
        Expr::Range(_) => "a range",
        Expr::Struct(_) => "a struct literal",
        Expr::Try(_) => "the `?` operator",
        Expr::Unsafe(_) => "an `unsafe` block",
        Expr::Async(_) | Expr::Await(_) => "async code",
        _ => "this expression",
    }
}

impl Lower {
    fn err(&mut self, e: syn::Error) -> Val {
        self.errors.push(e);
        Val::Poison
    }

    fn unsupported(&mut self, span: Span, what: &str) -> Val {
        self.err(unsupported(span, what))
    }

    fn new_body(&mut self) {
        self.work = 0;
        self.over_budget = false;
    }

    /// Counts one loop iteration or inlined call (`what`, at `at`) against [`MAX_WORK`]: `false`
    /// once the body is past it (the first time, with an error at `at`), and then the caller
    /// expands nothing more, so the macro stops early.
    fn spend(&mut self, at: &dyn At, what: &str) -> bool {
        if self.over_budget {
            return false;
        }
        self.work += 1;
        if self.work <= MAX_WORK {
            return true;
        }
        self.over_budget = true;
        self.errors.push(at.error(format!(
            "{what} goes past {MAX_WORK} loop iterations and inlined calls in this body: the \
             symbolic mode expands every iteration and every call when the macro runs, which \
             would take minutes and gigabytes; use `#[lagrangian(mode = \"jets\")]` on this \
             impl block, which runs loops and calls as written"
        )));
        false
    }

    fn lookup(&self, name: &str) -> Option<Val> {
        self.scopes
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.clone())
    }

    fn assign(&mut self, name: &str, val: Val) -> bool {
        match self.scopes.iter().rposition(|(n, _)| n == name) {
            Some(k) if self.depth > 0 && k < self.frame_base => false,
            Some(k) => {
                self.scopes[k].1 = val;
                true
            }
            None => false,
        }
    }

    fn field(&mut self, member: &Member, span: Span) -> Val {
        self.param(member, span, false)
    }

    fn param(&mut self, member: &Member, span: Span, free: bool) -> Val {
        let name = match member {
            Member::Named(n) => unraw(n),
            Member::Unnamed(i) => i.index.to_string(),
        };
        let idx = match self
            .fields
            .iter()
            .position(|f| f.name == name && f.free == free)
        {
            Some(i) => i,
            None => {
                self.fields.push(Field {
                    name,
                    span,
                    member: member.clone(),
                    vector: false,
                    confirmed_scalar: false,
                    free,
                    opaque: None,
                });
                self.fields.len() - 1
            }
        };
        if self.fields[idx].vector {
            let c = [1, 2, 3].map(|k| self.dag.param(idx as u32, k));
            Val::V(c)
        } else {
            Val::S(self.dag.param(idx as u32, 0))
        }
    }

    /// A scalar-only position. `None`: an error was recorded (or the value is poison).
    fn scalar(&mut self, v: Val, at: &dyn At, what: &str) -> Option<Id> {
        match v {
            Val::S(id) => {
                if let Node::Param(f, 0) = self.dag.node(id) {
                    self.fields[f as usize].confirmed_scalar = true;
                }
                Some(id)
            }
            Val::Poison => None,
            // An integer where a float is needed: rustc says so at the user's token (the
            // jets `fn lagrangian` is type-checked as written); here it is its value.
            Val::I(k) => Some(self.dag.constant(k as f64)),
            other => {
                let kind = other.kind();
                self.err(syn::Error::new(
                    at.at(),
                    format!("{what} must be a scalar, but this is {kind}"),
                ));
                None
            }
        }
    }

    /// A vector-only position: a scalar that a field could make a vector triggers a retype.
    fn vector(&mut self, v: Val, at: &dyn At, what: &str) -> R<Option<[Id; 3]>> {
        match v {
            Val::V(c) => Ok(Some(c)),
            Val::Poison => Ok(None),
            Val::S(id) => {
                if let Some(f) = self.retype_candidate(id) {
                    return Err(Retype(f));
                }
                self.err(syn::Error::new(
                    at.at(),
                    format!("{what} must be a Vector3, but this is a scalar"),
                ));
                Ok(None)
            }
            other => {
                let kind = other.kind();
                self.err(syn::Error::new(
                    at.at(),
                    format!("{what} must be a Vector3, but this is {kind}"),
                ));
                Ok(None)
            }
        }
    }

    /// The last-read scalar field feeding `id` that may still be a vector.
    fn retype_candidate(&self, id: Id) -> Option<usize> {
        let mut seen = std::collections::HashSet::new();
        let mut stack = vec![id];
        let mut best: Option<(Id, usize)> = None;
        while let Some(n) = stack.pop() {
            if !seen.insert(n) {
                continue;
            }
            let node = self.dag.node(n);
            if let Node::Param(f, 0) = node {
                let fi = &self.fields[f as usize];
                if !fi.vector && !fi.confirmed_scalar && best.is_none_or(|(b, _)| n > b) {
                    best = Some((n, f as usize));
                }
            }
            // Only through operations a vector could flow through unchanged in kind.
            match node {
                Node::Add(..) | Node::Sub(..) | Node::Mul(..) | Node::Neg(_) => {
                    stack.extend(node.children())
                }
                Node::Div(a, _) => stack.push(a),
                _ => {}
            }
        }
        best.map(|(_, f)| f)
    }

    /// Binds a function's coordinate (and time) names to the DAG's leaves, as the only scope.
    fn seed(
        &mut self,
        decl: &Decl,
        bindings: &[(Option<&proc_macro2::Ident>, Option<&proc_macro2::Ident>)],
        time: Option<&proc_macro2::Ident>,
    ) {
        self.scopes.clear();
        for (c, (name, dot)) in decl.coords.iter().zip(bindings) {
            let i = c.first_index;
            let (q, v) = match c.kind {
                CoordKind::Scalar => (Val::S(self.dag.q(i)), Val::S(self.dag.v(i))),
                CoordKind::Vector3 => (
                    Val::V([self.dag.q(i), self.dag.q(i + 1), self.dag.q(i + 2)]),
                    Val::V([self.dag.v(i), self.dag.v(i + 1), self.dag.v(i + 2)]),
                ),
                CoordKind::Array(k) => (
                    Val::A((i..i + k).map(|j| Val::S(self.dag.q(j))).collect()),
                    Val::A((i..i + k).map(|j| Val::S(self.dag.v(j))).collect()),
                ),
            };
            if let Some(name) = name {
                self.scopes.push((unraw(name), q));
            }
            if let Some(dot) = dot {
                self.scopes.push((unraw(dot), v));
            }
        }
        if let Some(t) = time {
            let t_id = self.dag.t();
            self.scopes.push((unraw(t), Val::S(t_id)));
        }
    }

    /// Lowers L, then D and Q (if given) into the same DAG.
    fn bodies(&mut self, decl: &Decl) -> R<Bodies> {
        let own: Vec<_> = decl
            .coords
            .iter()
            .map(|c| (Some(&c.name), Some(&c.dot)))
            .collect();
        self.seed(decl, &own, decl.time.as_ref());
        self.new_body();
        let lagrangian = self.block(&decl.body)?;
        fn bindings(f: &Func) -> Vec<(Option<&proc_macro2::Ident>, Option<&proc_macro2::Ident>)> {
            f.bindings
                .iter()
                .map(|(c, v)| (c.as_ref(), v.as_ref()))
                .collect()
        }
        let dissipation = match &decl.dissipation {
            Some(f) => {
                self.seed(decl, &bindings(f), f.time.as_ref());
                self.new_body();
                Some(self.block(&f.body)?)
            }
            None => None,
        };
        let forces = match &decl.forces {
            Some(f) => {
                self.seed(decl, &bindings(f), f.time.as_ref());
                self.new_body();
                Some(self.array_block(&f.body, decl.n())?)
            }
            None => None,
        };
        Ok(Bodies {
            lagrangian,
            dissipation,
            forces,
        })
    }

    /// The value of a body that must be one scalar (`what` names it in the error).
    fn scalar_result(&mut self, v: Val, body: &syn::Block, what: &str) -> Option<Id> {
        match v {
            Val::S(id) => Some(id),
            Val::I(k) => Some(self.dag.constant(k as f64)),
            Val::Poison => None,
            other => {
                let kind = other.kind();
                self.errors.push(syn::Error::new(
                    body_tail_span(body),
                    format!("{what} must be a scalar; this is {kind}"),
                ));
                None
            }
        }
    }

    /// The body of `fn forces`: statements, then an array literal of `n` values (`None`, with an
    /// error, for any other tail).
    fn array_block(&mut self, b: &syn::Block, n: usize) -> R<Option<Vec<Val>>> {
        let depth = self.scopes.len();
        let (init, tail) = match b.stmts.split_last() {
            Some((Stmt::Expr(e, None), init)) => (init, Some(e)),
            _ => (&b.stmts[..], None),
        };
        self.stmts(init)?;
        let result = match tail.map(paren_less) {
            Some(Expr::Array(a)) if a.elems.len() == n => {
                let mut vals = Vec::with_capacity(n);
                for e in &a.elems {
                    vals.push(self.expr(e)?);
                }
                Some(vals)
            }
            Some(Expr::Array(a)) => {
                self.errors.push(syn::Error::new(
                    a.span(),
                    format!(
                        "`fn forces` returns one generalized force per coordinate slot: {n} here, and this array has {}",
                        a.elems.len()
                    ),
                ));
                None
            }
            _ => {
                self.errors.push(unsupported(
                    body_tail_span(b),
                    "a body of `fn forces` that does not end in an array literal (`[f_x, f_y]`, \
                     one force per coordinate slot)",
                ));
                None
            }
        };
        self.scopes.truncate(depth);
        Ok(result)
    }

    fn block(&mut self, b: &syn::Block) -> R<Val> {
        let depth = self.scopes.len();
        let result = self.stmts(&b.stmts)?;
        self.scopes.truncate(depth);
        Ok(result)
    }

    /// Lowers statements in the current scope; the value of the last one if it is a tail
    /// expression, `()` otherwise.
    fn stmts(&mut self, stmts: &[Stmt]) -> R<Val> {
        let mut result = Val::Tuple(Vec::new());
        let n = stmts.len();
        // Nested `fn` items are visible in the whole block.
        for stmt in stmts {
            if let Stmt::Item(syn::Item::Fn(f)) = stmt {
                let params = param_pats(&f.sig);
                let callable = Callable {
                    what: format!("the function `{}`", f.sig.ident),
                    params,
                    body: CallBody::Block((*f.block).clone()),
                    env: Vec::new(),
                    item: true,
                };
                self.scopes
                    .push((unraw(&f.sig.ident), Val::F(std::rc::Rc::new(callable))));
            }
        }
        for (k, stmt) in stmts.iter().enumerate() {
            let last = k + 1 == n;
            match stmt {
                Stmt::Local(local) => {
                    let Some(init) = &local.init else {
                        self.unsupported(local.span(), "a `let` without a value");
                        continue;
                    };
                    if let Some((else_tok, _)) = &init.diverge {
                        self.unsupported(else_tok.span, "`let ... else`");
                        continue;
                    }
                    let v = self.expr(&init.expr)?;
                    self.bind(&local.pat, v);
                }
                Stmt::Expr(e, semi) => {
                    let v = self.expr(e)?;
                    if last && semi.is_none() {
                        result = v;
                    }
                }
                Stmt::Item(syn::Item::Fn(_)) => {}
                // `const K: f64 = 2.0;`: its value, if it does not depend on the state.
                Stmt::Item(syn::Item::Const(c)) => {
                    let v = self.expr(&c.expr)?;
                    self.scopes.push((unraw(&c.ident), v));
                }
                Stmt::Item(item) => {
                    self.unsupported(
                        item.span(),
                        "an item other than `fn` or `const` inside the body",
                    );
                }
                Stmt::Macro(m) => {
                    self.unsupported(m.span(), "a macro call");
                }
            }
        }
        Ok(result)
    }

    fn bind(&mut self, pat: &Pat, v: Val) {
        match pat {
            Pat::Ident(p) if p.by_ref.is_none() && p.subpat.is_none() => {
                self.scopes.push((unraw(&p.ident), v));
            }
            Pat::Wild(_) => {}
            Pat::Type(t) => self.bind(&t.pat, v),
            Pat::Paren(p) => self.bind(&p.pat, v),
            Pat::Reference(r) => self.bind(&r.pat, v),
            Pat::Tuple(t) => match v {
                Val::Tuple(items) if items.len() == t.elems.len() => {
                    for (p, item) in t.elems.iter().zip(items) {
                        self.bind(p, item);
                    }
                }
                Val::Poison => {
                    for p in &t.elems {
                        self.bind(p, Val::Poison);
                    }
                }
                _ => {
                    self.err(syn::Error::new(
                        t.span(),
                        "this tuple pattern does not match the value's shape",
                    ));
                    for p in &t.elems {
                        self.bind(p, Val::Poison);
                    }
                }
            },
            other => {
                self.unsupported(other.span(), "this pattern");
            }
        }
    }

    fn expr(&mut self, e: &Expr) -> R<Val> {
        Ok(match e {
            Expr::Paren(p) => self.expr(&p.expr)?,
            Expr::Group(g) => self.expr(&g.expr)?,
            Expr::Reference(r) => self.expr(&r.expr)?,
            Expr::Unary(u) => match u.op {
                UnOp::Deref(_) => self.expr(&u.expr)?,
                UnOp::Neg(_) => {
                    let v = self.expr(&u.expr)?;
                    self.neg(v)
                }
                _ => self.unsupported(u.span(), "this operator"),
            },
            Expr::Lit(l) => match &l.lit {
                Lit::Float(f) => match f.base10_parse::<f64>() {
                    Ok(x) => Val::S(self.dag.constant(x)),
                    Err(e) => self.err(e),
                },
                Lit::Int(i) => match (i.suffix(), i.base10_parse::<i64>()) {
                    (
                        "" | "i8" | "i16" | "i32" | "i64" | "isize" | "u8" | "u16" | "u32" | "u64"
                        | "usize",
                        Ok(k),
                    ) => Val::I(k),
                    _ => match i.base10_parse::<f64>() {
                        Ok(x) => Val::S(self.dag.constant(x)),
                        Err(e) => self.err(e),
                    },
                },
                other => self.unsupported(other.span(), "this literal"),
            },
            Expr::Path(p) => self.path(p),
            Expr::Tuple(t) => {
                let mut items = Vec::new();
                for e in &t.elems {
                    items.push(self.expr(e)?);
                }
                Val::Tuple(items)
            }
            Expr::Block(b) if b.label.is_none() => self.block(&b.block)?,
            Expr::Field(f) => self.field_access(f)?,
            Expr::Index(ix) => {
                // `self.k[i]`, `self.g[2]`: parameter-only, read as written (a loop variable
                // in the index by its value).
                if let Some(v) = self.opaque(e) {
                    return Ok(v);
                }
                let base = self.expr(&ix.expr)?;
                let index = self.expr(&ix.index)?;
                self.index(base, index, ix)?
            }
            Expr::Array(a) => {
                let mut items = Vec::with_capacity(a.elems.len());
                for e in &a.elems {
                    items.push(self.expr(e)?);
                }
                Val::A(items)
            }
            Expr::Repeat(r) => {
                let v = self.expr(&r.expr)?;
                match self.expr(&r.len)? {
                    Val::I(k) if (0..=MAX_UNROLL).contains(&k) => Val::A(vec![v; k as usize]),
                    Val::Poison => Val::Poison,
                    _ => self.unsupported(r.len.span(), "an array length that is not an integer known when the macro expands (a literal or a `const` of this impl block, `Self::N`)"),
                }
            }
            Expr::Range(r) => self.range(r)?,
            Expr::ForLoop(f) => self.for_loop(f)?,
            Expr::Closure(c) => Val::F(std::rc::Rc::new(Callable {
                what: "this closure".to_owned(),
                params: c.inputs.iter().cloned().collect(),
                body: CallBody::Expr((*c.body).clone()),
                env: self.scopes.clone(),
                item: false,
            })),
            Expr::Binary(b) => self.binary(b)?,
            Expr::Assign(a) => {
                let v = self.expr(&a.right)?;
                self.store(&a.left, v);
                Val::Tuple(Vec::new())
            }
            Expr::MethodCall(m) => self.method(m)?,
            Expr::Call(c) => self.call(c)?,
            Expr::If(i) => self.if_expr(i)?,
            Expr::Cast(c) => match self.const_int(&c.expr) {
                // `i as f64` of a loop variable: its value.
                Some(k) if is_float_type(&c.ty) => Val::S(self.dag.constant(k as f64)),
                Some(k) => Val::I(k),
                None => match self.opaque(e) {
                    Some(v) => v,
                    None => self.unsupported(e.span(), expr_kind(e)),
                },
            },
            Expr::Match(_) => match self.opaque(e) {
                Some(v) => v,
                None => self.unsupported(e.span(), expr_kind(e)),
            },
            other => {
                let kind = expr_kind(other);
                self.unsupported(other.span(), kind)
            }
        })
    }

    /// `if cond { .. } else { .. }` on a constant condition: both branches are lowered, and every
    /// value that differs between them (the result and any binding assigned in a branch) becomes
    /// a `Select` on the condition.
    fn if_expr(&mut self, i: &syn::ExprIf) -> R<Val> {
        // A condition known when the macro expands (`if i > 0` in an unrolled loop): only the
        // branch taken is lowered.
        if let Some(b) = self.const_bool(&i.cond) {
            return match (b, &i.else_branch) {
                (true, _) => self.block(&i.then_branch),
                (false, Some((_, e))) => self.expr(e),
                (false, None) => Ok(Val::Tuple(Vec::new())),
            };
        }
        let cond = self.condition(&i.cond);
        let before = self.scopes.clone();
        let a = self.block(&i.then_branch)?;
        let after_a = std::mem::replace(&mut self.scopes, before.clone());
        let b = match &i.else_branch {
            Some((_, e)) => self.expr(e)?,
            None => Val::Tuple(Vec::new()),
        };
        let after_b = std::mem::replace(&mut self.scopes, before);
        let Some(c) = cond else {
            return Ok(Val::Poison);
        };
        let span = i.if_token.span;
        for (k, ((_, va), (_, vb))) in after_a.into_iter().zip(after_b).enumerate() {
            let v = self.merge(c, va, vb, span);
            self.scopes[k].1 = v;
        }
        Ok(self.merge(c, a, b, span))
    }

    /// `base[index]`: an element of an array, a component of a vector, an element of an array
    /// field; the index must be known when the macro expands.
    fn index(&mut self, base: Val, index: Val, ix: &syn::ExprIndex) -> R<Val> {
        Ok(match (base, index) {
            (Val::Poison, _) | (_, Val::Poison) => Val::Poison,
            (Val::A(items), Val::I(k)) => {
                match usize::try_from(k).ok().and_then(|k| items.get(k)) {
                    Some(v) => v.clone(),
                    None => self.err(syn::Error::new(
                        ix.index.span(),
                        format!(
                            "index {k} is out of bounds: the array has {} elements",
                            items.len()
                        ),
                    )),
                }
            }
            (Val::Seq(b), Val::I(k)) => {
                let k = proc_macro2::Literal::i64_unsuffixed(k);
                let e: Expr = syn::parse_quote_spanned!(ix.index.span()=> #b[#k]);
                match self.opaque(&e) {
                    Some(v) => v,
                    None => self.unsupported(ix.span(), "this indexing"),
                }
            }
            (base @ (Val::S(_) | Val::V(_)), Val::I(k @ 0..=2)) => {
                match self.vector(base, &*ix.expr, "an indexed value")? {
                    Some(c) => Val::S(c[k as usize]),
                    None => Val::Poison,
                }
            }
            (_, Val::I(_)) | (Val::S(_) | Val::V(_), _) => self.unsupported(
                ix.span(),
                "indexing other than an array by a known integer or a Vector3 by 0, 1 or 2",
            ),
            (_, _) => self.unsupported(
                ix.index.span(),
                "an index that is not known when the macro expands (it may be a literal, a loop \
                 variable, or an integer `const` of this impl block, `Self::N`)",
            ),
        })
    }

    /// `a..b`, `a..=b` with bounds known when the macro expands: the array of its integers.
    fn range(&mut self, r: &syn::ExprRange) -> R<Val> {
        let bound = |this: &mut Self, e: &Option<Box<Expr>>| -> R<Option<Val>> {
            match e {
                Some(e) => this.expr(e).map(Some),
                None => Ok(None),
            }
        };
        let lo = bound(self, &r.start)?;
        let hi = bound(self, &r.end)?;
        let inclusive = matches!(r.limits, syn::RangeLimits::Closed(_));
        Ok(match (lo, hi) {
            (Some(Val::Poison), _) | (_, Some(Val::Poison)) => Val::Poison,
            (Some(Val::I(a)), Some(Val::I(b))) => {
                let b = if inclusive { b.saturating_add(1) } else { b };
                if b.saturating_sub(a) > MAX_UNROLL {
                    return Ok(self.err(syn::Error::new(
                        r.span(),
                        format!("this range has {} elements: the symbolic mode unrolls at most {MAX_UNROLL}", b - a),
                    )));
                }
                Val::A((a..b).map(Val::I).collect())
            }
            _ => self.err(syn::Error::new(
                r.span(),
                "the symbolic mode unrolls loops, so a range's bounds must be known when the macro \
                 expands: integer literals, loop variables, `q.len()` of a coordinate array, or \
                 integer `const`s of this impl block (`const N: usize = 6;` written `Self::N`; a \
                 `const` declared elsewhere is not visible to the macro); or use \
                 `#[lagrangian(mode = \"jets\")]` on this impl block",
            )),
        })
    }

    /// `for pat in iterable { body }`, unrolled: the body lowered once per element.
    fn for_loop(&mut self, f: &syn::ExprForLoop) -> R<Val> {
        if let Some(label) = &f.label {
            return Ok(self.unsupported(label.span(), "a loop label"));
        }
        if self.over_budget {
            return Ok(Val::Poison);
        }
        let items = match self.seq_or_expr(&f.expr)? {
            Val::A(items) => items.into_iter().map(|v| (v, Guard::new())).collect(),
            Val::Z(z) => z.items,
            Val::Poison => return Ok(Val::Poison),
            Val::Seq(b) => {
                return Ok(self.err(syn::Error::new(
                    f.expr.span(),
                    format!(
                        "the length of `{}` is not known when the macro expands: loop over a range \
                         (`for i in 0..K`) and index it, or zip it with a coordinate array \
                         (`q.iter().zip({}.iter())`)",
                        cond_text(&quote::ToTokens::to_token_stream(&b)),
                        quote::ToTokens::to_token_stream(&b),
                    ),
                )))
            }
            other => {
                let kind = other.kind();
                return Ok(self.err(syn::Error::new(
                    f.expr.span(),
                    format!("a `for` loop over {kind}: the symbolic mode unrolls loops over arrays, ranges with known bounds and their iterators (`.iter()`, `.enumerate()`, `.zip(..)`, `.rev()`)"),
                )));
            }
        };
        let head = LoopHead(f);
        for (item, guard) in items {
            if !self.spend(&head, "this loop") {
                return Ok(Val::Poison);
            }
            let depth = self.scopes.len();
            let span = f.for_token.span;
            let before = self
                .guard_cond(&guard, span)
                .map(|c| (c, self.scopes.clone()));
            self.bind(&f.pat, item);
            self.block(&f.body)?;
            self.scopes.truncate(depth);
            // An element of a zip that may not exist: what the body assigned, under its guard.
            if let Some((c, before)) = before {
                let after = std::mem::replace(&mut self.scopes, before.clone());
                for (k, ((_, va), (_, vb))) in after.into_iter().zip(before).enumerate() {
                    let v = self.merge(c, va, vb, span);
                    self.scopes[k].1 = v;
                }
            }
        }
        Ok(Val::Tuple(Vec::new()))
    }

    /// `e`, or an array field of unknown length when `e` is `self.f` (`&self.f`,
    /// `self.f.iter()`): where an iterable is expected.
    fn seq_or_expr(&mut self, e: &Expr) -> R<Val> {
        match self_field_seq(e) {
            Some(b) => Ok(Val::Seq(Box::new(b))),
            None => self.expr(e),
        }
    }

    /// An integer known when the macro expands, read from the syntax (no lowering): literals,
    /// integer bindings (loop variables), `Self::N`, `q.len()`, and `+ - * / %` of them.
    fn const_int(&self, e: &Expr) -> Option<i64> {
        match paren_less(e) {
            Expr::Lit(l) => match &l.lit {
                Lit::Int(i) if !matches!(i.suffix(), "f32" | "f64") => i.base10_parse().ok(),
                _ => None,
            },
            Expr::Path(p) if p.qself.is_none() => {
                if let Some(id) = p.path.get_ident() {
                    return match self.lookup(&unraw(id))? {
                        Val::I(k) => Some(k),
                        _ => None,
                    };
                }
                match segment_names(&p.path).as_slice() {
                    [s, name] if s == "Self" => self.int_consts.get(name).copied(),
                    _ => None,
                }
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => {
                self.const_int(&u.expr)?.checked_neg()
            }
            Expr::Binary(b) => {
                let (x, y) = (self.const_int(&b.left)?, self.const_int(&b.right)?);
                match b.op {
                    BinOp::Add(_) => x.checked_add(y),
                    BinOp::Sub(_) => x.checked_sub(y),
                    BinOp::Mul(_) => x.checked_mul(y),
                    BinOp::Div(_) => x.checked_div(y),
                    BinOp::Rem(_) => x.checked_rem(y),
                    _ => None,
                }
            }
            Expr::Cast(c) if !is_float_type(&c.ty) => self.const_int(&c.expr),
            Expr::MethodCall(m) if m.method == "len" && m.args.is_empty() => {
                match paren_less(&m.receiver) {
                    Expr::Path(p) => match self.lookup(&unraw(p.path.get_ident()?))? {
                        Val::A(items) => i64::try_from(items.len()).ok(),
                        _ => None,
                    },
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// A condition known when the macro expands (`i > 0`, `i + 1 < Self::N`, `true`).
    fn const_bool(&self, e: &Expr) -> Option<bool> {
        match paren_less(e) {
            Expr::Lit(l) => match &l.lit {
                Lit::Bool(b) => Some(b.value),
                _ => None,
            },
            Expr::Unary(u) if matches!(u.op, UnOp::Not(_)) => Some(!self.const_bool(&u.expr)?),
            Expr::Binary(b) => match b.op {
                BinOp::And(_) => Some(self.const_bool(&b.left)? && self.const_bool(&b.right)?),
                BinOp::Or(_) => Some(self.const_bool(&b.left)? || self.const_bool(&b.right)?),
                _ => {
                    let (x, y) = (self.const_int(&b.left)?, self.const_int(&b.right)?);
                    match b.op {
                        BinOp::Eq(_) => Some(x == y),
                        BinOp::Ne(_) => Some(x != y),
                        BinOp::Lt(_) => Some(x < y),
                        BinOp::Le(_) => Some(x <= y),
                        BinOp::Gt(_) => Some(x > y),
                        BinOp::Ge(_) => Some(x >= y),
                        _ => None,
                    }
                }
            },
            _ => None,
        }
    }

    /// Inlines a call of `f` (a closure, a nested `fn`, a helper method) with `args`.
    fn call_fn(&mut self, f: &Callable, args: Vec<Val>, at: &dyn At) -> R<Val> {
        if !self.spend(at, &format!("this call of {}", f.what)) {
            return Ok(Val::Poison);
        }
        if self.depth >= MAX_CALL_DEPTH {
            return Ok(self.err(syn::Error::new(
                at.at(),
                format!(
                    "{} is called {MAX_CALL_DEPTH} calls deep: the symbolic mode inlines every \
                     call, so it cannot follow recursion; use `#[lagrangian(mode = \"jets\")]` on \
                     this impl block",
                    f.what
                ),
            )));
        }
        if args.len() != f.params.len() {
            return Ok(self.err(syn::Error::new(
                at.at(),
                format!(
                    "{} takes {} argument(s), and this call gives {}",
                    f.what,
                    f.params.len(),
                    args.len()
                ),
            )));
        }
        // A nested `fn` sees the other `fn` items of the scope it is called from.
        let env = if f.item {
            self.scopes
                .iter()
                .filter(|(_, v)| matches!(v, Val::F(c) if c.item))
                .cloned()
                .collect()
        } else {
            f.env.clone()
        };
        let base = env.len();
        let saved = std::mem::replace(&mut self.scopes, env);
        let saved_base = std::mem::replace(&mut self.frame_base, base);
        self.depth += 1;
        for (p, a) in f.params.iter().zip(args) {
            self.bind(p, a);
        }
        let result = match &f.body {
            CallBody::Expr(e) => self.expr(e),
            CallBody::Block(b) => self.block(b),
        };
        self.depth -= 1;
        self.scopes = saved;
        self.frame_base = saved_base;
        result
    }

    fn merge(&mut self, c: u32, a: Val, b: Val, span: Span) -> Val {
        match (a, b) {
            (Val::S(x), Val::S(y)) => Val::S(self.dag.select(c, x, y)),
            (Val::V(x), Val::V(y)) => Val::V([0, 1, 2].map(|k| self.dag.select(c, x[k], y[k]))),
            (Val::Tuple(x), Val::Tuple(y)) if x.len() == y.len() => Val::Tuple(
                x.into_iter()
                    .zip(y)
                    .map(|(p, q)| self.merge(c, p, q, span))
                    .collect(),
            ),
            (Val::A(x), Val::A(y)) if x.len() == y.len() => Val::A(
                x.into_iter()
                    .zip(y)
                    .map(|(p, q)| self.merge(c, p, q, span))
                    .collect(),
            ),
            (Val::I(x), Val::I(y)) if x == y => Val::I(x),
            (Val::I(x), Val::S(y)) => {
                let x = self.dag.constant(x as f64);
                Val::S(self.dag.select(c, x, y))
            }
            (Val::S(x), Val::I(y)) => {
                let y = self.dag.constant(y as f64);
                Val::S(self.dag.select(c, x, y))
            }
            (Val::I(x), Val::I(y)) => {
                let (x, y) = (self.dag.constant(x as f64), self.dag.constant(y as f64));
                Val::S(self.dag.select(c, x, y))
            }
            (Val::F(x), Val::F(y)) if std::rc::Rc::ptr_eq(&x, &y) => Val::F(x),
            (Val::Poison, _) | (_, Val::Poison) => Val::Poison,
            _ => self.err(syn::Error::new(
                span,
                "the two branches of this `if` give values of different shapes (scalar, Vector3, \
                 array or tuple)",
            )),
        }
    }

    /// `e` as a parameter when it mentions no coordinate, velocity, time or local binding:
    /// its tokens evaluated once per call, as written (see [`Field::opaque`]). `None` otherwise
    /// (the caller reports what it cannot lower).
    fn opaque(&mut self, e: &Expr) -> Option<Val> {
        self.opaque_shown(e, None)
    }

    /// [`Self::opaque`], printed in the equations as `shown` instead of as `e` (the exponent
    /// `N` of `powi(N)`, evaluated as `(N) as f64`). The same tokens share one parameter.
    fn opaque_shown(&mut self, e: &Expr, shown: Option<String>) -> Option<Val> {
        let mut offenders = Vec::new();
        let tokens = self.walk_self(quote::ToTokens::to_token_stream(e), &mut offenders);
        if !offenders.is_empty() {
            return None;
        }
        let text = cond_text(&tokens);
        let idx = match self
            .fields
            .iter()
            .position(|f| matches!(&f.opaque, Some((_, t)) if cond_text(t) == text))
        {
            Some(i) => i,
            None => {
                let k = self.fields.iter().filter(|f| f.opaque.is_some()).count();
                self.fields.push(Field {
                    name: shown.unwrap_or_else(|| text.replace("self.", "")),
                    span: e.span(),
                    member: Member::Unnamed(syn::Index::from(k)),
                    vector: false,
                    confirmed_scalar: true,
                    free: true,
                    opaque: Some((k, tokens)),
                });
                self.fields.len() - 1
            }
        };
        Some(Val::S(self.dag.param(idx as u32, 0)))
    }

    /// Checks that an `if` condition depends on constants only and registers it. A name bound
    /// in the body (a coordinate, a velocity, the time or a local binding) is an error at it.
    fn condition(&mut self, e: &Expr) -> Option<u32> {
        if let Expr::Let(l) = paren_less(e) {
            self.unsupported(l.span(), "`if let`");
            return None;
        }
        let mut bad = false;
        let tokens = self.cond_tokens(quote::ToTokens::to_token_stream(e), &mut bad);
        if bad {
            return None;
        }
        let text = cond_text(&tokens);
        if let Some(k) = self.conds.iter().position(|c| c.text == text) {
            return Some(k as u32);
        }
        self.conds.push(Cond {
            tokens,
            text,
            span: e.span(),
            assumed: false,
        });
        Some(self.conds.len() as u32 - 1)
    }

    /// The condition that an element guarded by `g` exists (`2 < self.k.len() && ..`), registered
    /// as an assumed condition (see [`Zipped`]). `None` for an element that always exists.
    fn guard_cond(&mut self, g: &Guard, span: Span) -> Option<u32> {
        if g.is_empty() {
            return None;
        }
        let terms = g.iter().map(|(b, k)| {
            let k = proc_macro2::Literal::usize_unsuffixed(*k);
            quote::quote_spanned!(span=> #k < <[f64]>::len(&#b))
        });
        let ts = quote::quote_spanned!(span=> #(#terms)&&*);
        let mut offenders = Vec::new();
        let tokens = self.walk_self(ts, &mut offenders);
        let text = cond_text(&tokens);
        if let Some(k) = self.conds.iter().position(|c| c.assumed && c.text == text) {
            return Some(k as u32);
        }
        self.conds.push(Cond {
            tokens,
            text,
            span,
            assumed: true,
        });
        Some(self.conds.len() as u32 - 1)
    }

    /// `v` where the guard `g` holds and `other` where it does not.
    fn guarded(&mut self, g: &Guard, v: Val, other: Val, span: Span) -> Val {
        match self.guard_cond(g, span) {
            Some(c) => self.merge(c, v, other, span),
            None => v,
        }
    }

    fn cond_tokens(
        &mut self,
        ts: proc_macro2::TokenStream,
        bad: &mut bool,
    ) -> proc_macro2::TokenStream {
        let mut offenders = Vec::new();
        let out = self.walk_self(ts, &mut offenders);
        for (id, what) in offenders {
            self.err(syn::Error::new(
                id.span(),
                format!(
                    "this `if` condition uses `{id}`, {what}: in symbolic mode \
                     the equations are derived once for every state, so an `if` \
                     condition may only use constants (`self` fields, literals, \
                     names from the enclosing scope); use \
                     `#[lagrangian(mode = \"jets\")]` on this impl block to \
                     branch at run time"
                ),
            ));
            *bad = true;
        }
        out
    }

    /// The tokens with `self` resolved like the field loads; every name bound in the body that
    /// they use (a coordinate, a velocity, the time, a local binding) goes to `offenders`.
    fn walk_self(
        &self,
        ts: proc_macro2::TokenStream,
        offenders: &mut Vec<(proc_macro2::Ident, &'static str)>,
    ) -> proc_macro2::TokenStream {
        use proc_macro2::{Group, TokenTree};
        let mut out = Vec::new();
        let mut prev: Option<TokenTree> = None;
        let mut prev2: Option<TokenTree> = None;
        for tt in ts {
            let new = match &tt {
                TokenTree::Group(g) => {
                    let inner = self.walk_self(g.stream(), offenders);
                    let mut ng = Group::new(g.delimiter(), inner);
                    ng.set_span(g.span());
                    TokenTree::Group(ng)
                }
                TokenTree::Ident(id) => {
                    let member = matches!(&prev, Some(TokenTree::Punct(p)) if p.as_char() == '.');
                    let path_seg = matches!(
                        (&prev2, &prev),
                        (Some(TokenTree::Punct(a)), Some(TokenTree::Punct(b)))
                            if a.as_char() == ':' && b.as_char() == ':'
                    );
                    if id == "self" {
                        TokenTree::Ident(proc_macro2::Ident::new(
                            "self",
                            Span::call_site().located_at(id.span()),
                        ))
                    } else {
                        if !member && !path_seg {
                            if let Some(Val::I(k)) = self.lookup(&unraw(id)) {
                                // A loop variable: its value.
                                let mut lit = proc_macro2::Literal::i64_unsuffixed(k);
                                lit.set_span(id.span());
                                prev2 = prev.take();
                                prev = Some(tt.clone());
                                out.push(if k >= 0 {
                                    TokenTree::Literal(lit)
                                } else {
                                    TokenTree::Group(proc_macro2::Group::new(
                                        proc_macro2::Delimiter::Parenthesis,
                                        TokenTree::Literal(lit).into(),
                                    ))
                                });
                                continue;
                            }
                            if let Some(v) = self.lookup(&unraw(id)) {
                                let what = match v {
                                    Val::S(n) | Val::V([n, ..]) => match self.dag.node(n) {
                                        Node::Q(_) => "a generalized coordinate",
                                        Node::V(_) => "a generalized velocity",
                                        Node::T => "the time",
                                        _ => "a local binding of the body",
                                    },
                                    _ => "a local binding of the body",
                                };
                                offenders.push((id.clone(), what));
                            }
                        }
                        tt.clone()
                    }
                }
                _ => tt.clone(),
            };
            prev2 = prev.take();
            prev = Some(tt);
            out.push(new);
        }
        out.into_iter().collect()
    }

    fn store(&mut self, target: &Expr, v: Val) {
        // `a`, `a[i]`, `a[i][j]`: the root binding and the indices, outermost last.
        let mut indices = Vec::new();
        let mut root = paren_less(target);
        while let Expr::Index(ix) = root {
            indices.push(&*ix.index);
            root = paren_less(&ix.expr);
        }
        indices.reverse();
        if let Expr::Path(p) = root {
            if let Some(id) = p.path.get_ident() {
                let name = unraw(id);
                if self.depth > 0
                    && self
                        .scopes
                        .iter()
                        .rposition(|(n, _)| *n == name)
                        .is_some_and(|k| k < self.frame_base)
                {
                    self.unsupported(
                        target.span(),
                        "a closure that assigns to a binding it captures",
                    );
                    return;
                }
                if indices.is_empty() {
                    if self.assign(&name, v) {
                        return;
                    }
                } else if let Some(mut whole) = self.lookup(&name) {
                    let mut ks = Vec::new();
                    for e in &indices {
                        match self.const_int(e) {
                            Some(k) => ks.push(k),
                            None => {
                                self.unsupported(
                                    e.span(),
                                    "an index that is not known when the macro expands (it may \
                                     be a literal, a loop variable, or an integer `const` of this \
                                     impl block, `Self::N`)",
                                );
                                return;
                            }
                        }
                    }
                    match set_element(&mut whole, &ks, v) {
                        Ok(()) => {
                            self.assign(&name, whole);
                        }
                        Err(msg) => {
                            self.err(syn::Error::new(target.span(), msg));
                        }
                    }
                    return;
                }
            }
        }
        self.unsupported(
            target.span(),
            "assigning to anything but a local binding or an element of a local array",
        );
    }

    fn path(&mut self, p: &syn::ExprPath) -> Val {
        if p.qself.is_none() {
            if let Some(id) = p.path.get_ident() {
                if let Some(v) = self.lookup(&unraw(id)) {
                    return v;
                }
                // A name from the user's scope: an opaque constant, loaded once as written.
                return self.param(&Member::Named(id.clone()), id.span(), true);
            }
            let segs = segment_names(&p.path);
            let n = segs.len();
            if let [s, name] = segs.as_slice() {
                if s == "Self" {
                    if let Some(k) = self.int_consts.get(name) {
                        return Val::I(*k);
                    }
                }
            }
            if n >= 3 && segs[n - 3] == "f64" && segs[n - 2] == "consts" {
                if let Some(c) = f64_const(&segs[n - 1]) {
                    return Val::S(self.dag.constant(c));
                }
            }
        }
        let segs = segment_names(&p.path);
        if let [.., ty, name] = segs.as_slice() {
            if ty == "f64" {
                if let Some(c) = f64_assoc_const(name) {
                    return Val::S(self.dag.constant(c));
                }
            }
        }
        // `Self::K`, `crate::G`: a constant of the user's scope, read as written.
        let e = Expr::Path(p.clone());
        match self.opaque(&e) {
            Some(v) => v,
            None => self.unsupported(p.span(), "this path"),
        }
    }

    fn field_access(&mut self, f: &syn::ExprField) -> R<Val> {
        if let Expr::Path(p) = paren_less(&f.base) {
            if p.path.is_ident("self") {
                return Ok(self.field(&f.member, f.span()));
            }
        }
        let base = self.expr(&f.base)?;
        Ok(match &f.member {
            Member::Named(name) => {
                let k = match name.to_string().as_str() {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    other => {
                        return Ok(self.unsupported(name.span(), &format!("the field `.{other}`")))
                    }
                };
                match self.vector(base, &*f.base, "the value of `.x`/`.y`/`.z`")? {
                    Some(c) => Val::S(c[k]),
                    None => Val::Poison,
                }
            }
            Member::Unnamed(i) => match base {
                Val::Tuple(items) if (i.index as usize) < items.len() => {
                    items[i.index as usize].clone()
                }
                Val::Poison => Val::Poison,
                _ => self.err(syn::Error::new(i.span, "no such tuple field")),
            },
        })
    }

    fn neg(&mut self, v: Val) -> Val {
        match v {
            Val::S(a) => Val::S(self.dag.neg(a)),
            Val::V(c) => Val::V(c.map(|a| self.dag.neg(a))),
            Val::I(k) => Val::I(-k),
            Val::A(items) => Val::A(items.into_iter().map(|v| self.neg(v)).collect()),
            _ => Val::Poison,
        }
    }

    /// A chain of binary operators `a + b + c …` (left-nested): walked down its left operands
    /// with a loop, so a 2000-term sum does not overflow the compiler's stack.
    fn binary(&mut self, b: &syn::ExprBinary) -> R<Val> {
        let mut spine = vec![b];
        while let Expr::Binary(inner) = &*spine[spine.len() - 1].left {
            spine.push(inner);
        }
        let mut acc: Option<Val> = None;
        while let Some(b) = spine.pop() {
            acc = Some(self.binary_one(b, acc)?);
        }
        Ok(acc.unwrap_or(Val::Poison))
    }

    /// One operator of a chain, with its left operand's value when the chain already has it.
    fn binary_one(&mut self, b: &syn::ExprBinary, left: Option<Val>) -> R<Val> {
        let (op, assign) = match b.op {
            BinOp::Add(_) => ('+', false),
            BinOp::Sub(_) => ('-', false),
            BinOp::Mul(_) => ('*', false),
            BinOp::Div(_) => ('/', false),
            BinOp::Rem(_) => ('%', false),
            BinOp::RemAssign(_) => ('%', true),
            BinOp::AddAssign(_) => ('+', true),
            BinOp::SubAssign(_) => ('-', true),
            BinOp::MulAssign(_) => ('*', true),
            BinOp::DivAssign(_) => ('/', true),
            _ => return Ok(self.unsupported(b.span(), "this operator")),
        };
        let l = match left {
            Some(l) => l,
            None => self.expr(&b.left)?,
        };
        let r = self.expr(&b.right)?;
        let v = self.arith(op, l, r, &b.left, &b.right)?;
        if assign {
            self.store(&b.left, v);
            Ok(Val::Tuple(Vec::new()))
        } else {
            Ok(v)
        }
    }

    fn arith(&mut self, op: char, l: Val, r: Val, le: &Expr, re: &Expr) -> R<Val> {
        // Integers known when the macro runs stay integers among themselves (`i + 1`), and
        // become constants where they meet a scalar.
        let (l, r) = match (l, r) {
            (Val::I(a), Val::I(b)) => {
                let v = match op {
                    '+' => a.checked_add(b),
                    '-' => a.checked_sub(b),
                    '*' => a.checked_mul(b),
                    '/' => a.checked_div(b),
                    _ => a.checked_rem(b),
                };
                return Ok(match v {
                    Some(v) => Val::I(v),
                    None => self.err(syn::Error::new(
                        le.span().join(re.span()).unwrap_or_else(|| re.span()),
                        "this integer arithmetic overflows or divides by zero",
                    )),
                });
            }
            (Val::I(a), r) => (Val::S(self.dag.constant(a as f64)), r),
            (l, Val::I(b)) => (l, Val::S(self.dag.constant(b as f64))),
            lr => lr,
        };
        if op == '%' {
            return Ok(match (l, r) {
                (Val::Poison, _) | (_, Val::Poison) => Val::Poison,
                _ => self.unsupported(
                    re.span(),
                    "`%` on values that are not integers known when the macro expands",
                ),
            });
        }
        let d = &mut self.dag;
        Ok(match (op, l, r) {
            (_, Val::Poison, _) | (_, _, Val::Poison) => Val::Poison,
            ('+', Val::S(a), Val::S(b)) => Val::S(d.add(a, b)),
            ('-', Val::S(a), Val::S(b)) => Val::S(d.sub(a, b)),
            ('*', Val::S(a), Val::S(b)) => Val::S(d.mul(a, b)),
            ('/', Val::S(a), Val::S(b)) => Val::S(d.div(a, b)),
            ('+', Val::V(a), Val::V(b)) => Val::V([0, 1, 2].map(|k| d.add(a[k], b[k]))),
            ('-', Val::V(a), Val::V(b)) => Val::V([0, 1, 2].map(|k| d.sub(a[k], b[k]))),
            ('*', Val::S(s), Val::V(v)) | ('*', Val::V(v), Val::S(s)) => {
                Val::V(v.map(|x| d.mul(s, x)))
            }
            ('/', Val::V(v), Val::S(s)) => Val::V(v.map(|x| d.div(x, s))),
            ('+' | '-', Val::S(s), Val::V(_)) => {
                let _ = self.vector(Val::S(s), le, "the left operand")?;
                Val::Poison
            }
            ('+' | '-', Val::V(_), Val::S(s)) => {
                let _ = self.vector(Val::S(s), re, "the right operand")?;
                Val::Poison
            }
            ('*', Val::V(_), Val::V(_)) => self.err(syn::Error::new(
                re.span(),
                "two Vector3 values cannot be multiplied with `*`; use `.dot(&v)` or `.cross(&v)`",
            )),
            ('/', _, Val::V(_)) => {
                self.err(syn::Error::new(re.span(), "cannot divide by a Vector3"))
            }
            _ => self.err(syn::Error::new(
                le.span().join(re.span()).unwrap_or_else(|| le.span()),
                "these operands cannot be combined (a tuple, an array, a function or a unit value \
                 is involved)",
            )),
        })
    }

    fn call(&mut self, c: &syn::ExprCall) -> R<Val> {
        let Expr::Path(p) = paren_less(&c.func) else {
            return Ok(self.unsupported(c.func.span(), "calling this"));
        };
        // A closure or a nested `fn` of the body, or `Self::kinetic(self, v)`: inlined.
        let callee = match p.path.get_ident() {
            Some(id) => match self.lookup(&unraw(id)) {
                Some(Val::F(f)) => Some((f, 0)),
                _ => None,
            },
            None => match segment_names(&p.path).as_slice() {
                [s, name] if s == "Self" && p.qself.is_none() => {
                    self.helpers.get(name).cloned().map(|f| (f, 1))
                }
                _ => None,
            },
        };
        if let Some((f, skip)) = callee {
            let mut args = Vec::with_capacity(c.args.len());
            for a in c.args.iter().skip(skip) {
                args.push(self.expr(a)?);
            }
            return self.call_fn(&f, args, c);
        }
        let segs = segment_names(&p.path);
        let n = segs.len();
        // `Scalar::constant(c)`, `Scalar::from(c)`, `<Scalar as From<f64>>::from(c)`: the
        // identity on a constant.
        let scalar_self = match &p.qself {
            Some(q) => {
                matches!(&*q.ty, syn::Type::Path(t) if t.qself.is_none() && t.path.is_ident("Scalar"))
            }
            None => false,
        };
        let is_constant_ctor = c.args.len() == 1
            && match (&p.qself, segs.as_slice()) {
                (None, [s, m]) => s == "Scalar" && (m == "constant" || m == "from"),
                (Some(_), [t, m]) => scalar_self && t == "From" && m == "from",
                _ => false,
            };
        if is_constant_ctor {
            let arg = &c.args[0];
            let v = self.expr(arg)?;
            let Some(id) = self.scalar(v, arg, "the argument of this conversion") else {
                return Ok(Val::Poison);
            };
            if !self.dag.is_state_free(id) {
                return Ok(self.err(syn::Error::new(
                    arg.span(),
                    "this converts an f64 constant into a Scalar, but the argument depends on \
                     the coordinates, velocities or time; it is already a Scalar, so write it \
                     without the conversion",
                )));
            }
            return Ok(Val::S(id));
        }
        if n >= 2 && segs[n - 2] == "Vector3" {
            match segs[n - 1].as_str() {
                "new" if c.args.len() == 3 => {
                    let mut comps = [Dag::ZERO; 3];
                    let mut poison = false;
                    for (k, a) in c.args.iter().enumerate() {
                        let v = self.expr(a)?;
                        match self.scalar(v, a, "a component of `Vector3::new`") {
                            Some(id) => comps[k] = id,
                            None => poison = true,
                        }
                    }
                    return Ok(if poison { Val::Poison } else { Val::V(comps) });
                }
                "zeros" if c.args.is_empty() => return Ok(Val::V([Dag::ZERO; 3])),
                _ => {}
            }
        }
        // `f64::sin(x)`, `Scalar::powi(x, 2)`: method calls in function form.
        if n == 2 && matches!(segs[0].as_str(), "f64" | "Scalar") && !c.args.is_empty() {
            let mut args = c.args.iter();
            if let Some(recv_e) = args.next() {
                let rest: Vec<&Expr> = args.collect();
                let method = &p.path.segments[1].ident;
                let recv = self.expr(recv_e)?;
                return self.apply_method(recv, recv_e, method, &rest, c);
            }
        }
        // A function of parameters only (the user's own `fn`, `f64::max(self.a, self.b)`):
        // evaluated once per call, as written.
        if let Some(v) = self.opaque(&Expr::Call(c.clone())) {
            return Ok(v);
        }
        let name = segs.join("::");
        Ok(self.unsupported(c.func.span(), &format!("a call to the function `{name}`")))
    }

    /// A chain of method calls `x.sin().cos()…`: walked along its receivers with a loop, so a
    /// 2000-deep chain does not overflow the compiler's stack; innermost call first.
    fn method(&mut self, m: &syn::ExprMethodCall) -> R<Val> {
        // `self.kinetic(v)`: a helper method of the impl block, inlined.
        if let Some(h) = self.helper_called(m) {
            let mut args = Vec::with_capacity(m.args.len());
            for a in &m.args {
                args.push(self.expr(a)?);
            }
            return self.call_fn(&h, args, m);
        }
        // A method the symbolic mode does not know, on parameters only (`self.n.count_ones()`,
        // `self.table.len()`): evaluated once per call, as written.
        let name = m.method.to_string();
        let adaptor = crate::analyze::ITERATOR_METHODS.contains(&name.as_str())
            && !matches!(name.as_str(), "sum" | "product" | "fold" | "count" | "len");
        if Fun::from_method(&name).is_none() && !KNOWN_METHODS.contains(&name.as_str()) && !adaptor
        {
            if let Some(v) = self.opaque(&Expr::MethodCall(m.clone())) {
                return Ok(v);
            }
        }
        let mut spine = vec![m];
        while let Expr::MethodCall(inner) = &*spine[spine.len() - 1].receiver {
            if self.helper_called(inner).is_some() {
                break;
            }
            spine.push(inner);
        }
        let Some(innermost) = spine.last() else {
            return Ok(Val::Poison);
        };
        // `self.m.iter()`: an array field, whose length the macro does not know.
        let seq = matches!(innermost.method.to_string().as_str(), "iter" | "into_iter")
            .then(|| self_field_seq(&innermost.receiver))
            .flatten();
        let mut recv = match seq {
            Some(b) => Val::Seq(Box::new(b)),
            None => self.expr(&innermost.receiver)?,
        };
        while let Some(m) = spine.pop() {
            let args: Vec<&Expr> = m.args.iter().collect();
            recv = self.apply_method(recv, &m.receiver, &m.method, &args, m)?;
        }
        Ok(recv)
    }

    /// The helper method `m` calls (`self.kinetic(v)`), if it calls one.
    fn helper_called(&self, m: &syn::ExprMethodCall) -> Option<std::rc::Rc<Callable>> {
        if !matches!(paren_less(&m.receiver), Expr::Path(p) if p.path.is_ident("self")) {
            return None;
        }
        self.helpers.get(&unraw(&m.method)).cloned()
    }

    /// An iterator method (`iter`, `enumerate`, `zip`, `map`, `sum`, `fold`, ...) on an array
    /// (or an array field of unknown length): `None` when `name` is not one or `recv` is not
    /// an array.
    fn iterator_method(
        &mut self,
        recv: &Val,
        recv_e: &Expr,
        name: &str,
        args: &[&Expr],
        whole: &dyn At,
    ) -> R<Option<Val>> {
        let nargs = args.len();
        let items = match recv {
            Val::A(items) => items.clone(),
            Val::Seq(b) => {
                return Ok(match (name, nargs) {
                    ("iter" | "into_iter" | "copied" | "cloned", 0) => Some(Val::Seq(b.clone())),
                    ("zip", 1) => {
                        let other = self.seq_or_expr(args[0])?;
                        match other {
                            Val::A(ys) => {
                                let xs = self.guarded_elements(b, ys.len(), whole);
                                let ys = ys.into_iter().map(|y| (y, Guard::new())).collect();
                                Some(zip_guarded(xs, ys))
                            }
                            Val::Z(z) if z.forward => {
                                let xs = self.guarded_elements(b, z.items.len(), whole);
                                Some(zip_guarded(xs, z.items))
                            }
                            Val::Z(_) => Some(self.after_rev("zip", whole)),
                            Val::Poison => Some(Val::Poison),
                            _ => Some(self.unknown_length(b, whole)),
                        }
                    }
                    (
                        "enumerate" | "map" | "sum" | "product" | "fold" | "rev" | "len" | "skip"
                        | "take",
                        _,
                    ) => Some(self.unknown_length(b, whole)),
                    _ => None,
                });
            }
            Val::Z(z) => return self.zipped_method((**z).clone(), recv_e, name, args, whole),
            _ => return Ok(None),
        };
        Ok(Some(match (name, nargs) {
            ("iter" | "into_iter" | "copied" | "cloned" | "by_ref", 0) => Val::A(items),
            ("len" | "count", 0) => Val::I(items.len() as i64),
            ("enumerate", 0) => Val::A(
                items
                    .into_iter()
                    .enumerate()
                    .map(|(k, x)| Val::Tuple(vec![Val::I(k as i64), x]))
                    .collect(),
            ),
            ("rev", 0) => Val::A(items.into_iter().rev().collect()),
            ("skip" | "take" | "step_by", 1) => match self.int_arg(name, args[0])? {
                Ok(k) => Val::A(match name {
                    "skip" => items.into_iter().skip(k).collect(),
                    "take" => items.into_iter().take(k).collect(),
                    _ => items.into_iter().step_by(k).collect(),
                }),
                Err(v) => v,
            },
            ("zip", 1) => match self.seq_or_expr(args[0])? {
                Val::A(ys) => Val::A(
                    items
                        .into_iter()
                        .zip(ys)
                        .map(|(x, y)| Val::Tuple(vec![x, y]))
                        .collect(),
                ),
                Val::Seq(b) => {
                    let ys = self.guarded_elements(&b, items.len(), whole);
                    let xs = items.into_iter().map(|x| (x, Guard::new())).collect();
                    zip_guarded(xs, ys)
                }
                Val::Z(z) if z.forward => {
                    let xs = items.into_iter().map(|x| (x, Guard::new())).collect();
                    zip_guarded(xs, z.items)
                }
                Val::Z(_) => self.after_rev("zip", whole),
                Val::Poison => Val::Poison,
                other => {
                    let kind = other.kind();
                    self.err(syn::Error::new(
                        args[0].span(),
                        format!("`.zip()` over {kind}: it zips arrays and their iterators"),
                    ))
                }
            },
            ("map", 1) => {
                let f = self.expr(args[0])?;
                let Val::F(f) = f else {
                    return Ok(Some(self.unsupported(
                        args[0].span(),
                        "a `.map()` argument that is not a closure or a function of the body",
                    )));
                };
                let mut out = Vec::with_capacity(items.len());
                for x in items {
                    out.push(self.call_fn(&f, vec![x], args[0])?);
                }
                Val::A(out)
            }
            ("fold", 2) => {
                let mut acc = self.expr(args[0])?;
                let Val::F(f) = self.expr(args[1])? else {
                    return Ok(Some(self.unsupported(
                        args[1].span(),
                        "a `.fold()` argument that is not a closure or a function of the body",
                    )));
                };
                for x in items {
                    acc = self.call_fn(&f, vec![acc, x], args[1])?;
                }
                acc
            }
            ("sum" | "product", 0) => {
                let op = if name == "sum" { '+' } else { '*' };
                let mut it = items.into_iter();
                match it.next() {
                    None => Val::S(if op == '+' { Dag::ZERO } else { Dag::ONE }),
                    Some(first) => {
                        let mut acc = first;
                        for x in it {
                            if !self.spend(whole, &format!("this `.{name}()`")) {
                                return Ok(Some(Val::Poison));
                            }
                            acc = self.arith(op, acc, x, recv_e, recv_e)?;
                        }
                        acc
                    }
                }
            }
            _ => return Ok(None),
        }))
    }

    /// The integer argument of `.skip(k)`, `.take(k)`, `.step_by(k)` (`Err`: the error's value).
    fn int_arg(&mut self, name: &str, e: &Expr) -> R<Result<usize, Val>> {
        Ok(match self.expr(e)? {
            Val::I(k) => match usize::try_from(k) {
                Ok(0) if name == "step_by" => {
                    Err(self.err(syn::Error::new(
                        e.span(),
                        "`step_by(0)`: a step of 0 never advances (std's `step_by` panics on \
                         it); give `.step_by(k)` a step k ≥ 1",
                    )))
                }
                Ok(k) => Ok(k),
                Err(_) => Err(self.unsupported(
                    e.span(),
                    &format!("a `.{name}()` argument that is not an integer known when the macro expands"),
                )),
            },
            _ => Err(self.unsupported(
                e.span(),
                &format!("a `.{name}()` argument that is not an integer known when the macro expands"),
            )),
        })
    }

    /// The first `n` elements of the array field `b` that a zip may read, each a parameter
    /// guarded by `k < b.len()` and loaded without a bounds panic (`self.m.get(k)`; see
    /// [`Zipped`]), printed as `m[k]`.
    fn guarded_elements(&mut self, b: &Expr, n: usize, whole: &dyn At) -> Vec<(Val, Guard)> {
        (0..n)
            .map(|k| {
                let lit = proc_macro2::Literal::usize_unsuffixed(k);
                // Paths, not methods: a user's trait in scope cannot change what they call.
                let e: Expr = syn::parse_quote_spanned!(whole.at()=>
                ::core::option::Option::<f64>::unwrap_or(
                    ::core::option::Option::<&f64>::copied(<[f64]>::get(&#b, #lit)),
                    0.0,
                ));
                let shown = cond_text(&quote::quote!(#b[#lit]));
                let v = self.opaque_shown(&e, Some(shown)).unwrap_or(Val::Poison);
                (v, vec![(b.clone(), k)])
            })
            .collect()
    }

    fn after_rev(&mut self, name: &str, whole: &dyn At) -> Val {
        self.unsupported(
            whole.at(),
            &format!(
                "`.{name}()` after `.rev()` on a zip with an array field whose length the macro \
                 does not know (write `.{name}()` before `.rev()`)"
            ),
        )
    }

    /// An iterator method on a zip with an array field of unknown length (see [`Zipped`]).
    fn zipped_method(
        &mut self,
        z: Zipped,
        recv_e: &Expr,
        name: &str,
        args: &[&Expr],
        whole: &dyn At,
    ) -> R<Option<Val>> {
        let Zipped { items, forward } = z;
        let span = whole.at();
        let z =
            |items: Vec<(Val, Guard)>, forward: bool| Val::Z(Box::new(Zipped { items, forward }));
        Ok(Some(match (name, args.len()) {
            ("iter" | "into_iter" | "copied" | "cloned" | "by_ref", 0) => z(items, forward),
            ("rev", 0) => z(items.into_iter().rev().collect(), !forward),
            ("enumerate" | "skip" | "take" | "step_by" | "zip", _) if !forward => {
                self.after_rev(name, whole)
            }
            ("enumerate", 0) => z(
                items
                    .into_iter()
                    .enumerate()
                    .map(|(k, (x, g))| (Val::Tuple(vec![Val::I(k as i64), x]), g))
                    .collect(),
                true,
            ),
            ("skip" | "take" | "step_by", 1) => match self.int_arg(name, args[0])? {
                Ok(k) => z(
                    match name {
                        "skip" => items.into_iter().skip(k).collect(),
                        "take" => items.into_iter().take(k).collect(),
                        _ => items.into_iter().step_by(k).collect(),
                    },
                    true,
                ),
                Err(v) => v,
            },
            ("zip", 1) => match self.seq_or_expr(args[0])? {
                Val::A(ys) => {
                    zip_guarded(items, ys.into_iter().map(|y| (y, Guard::new())).collect())
                }
                Val::Seq(b) => {
                    let ys = self.guarded_elements(&b, items.len(), whole);
                    zip_guarded(items, ys)
                }
                Val::Z(o) if o.forward => zip_guarded(items, o.items),
                Val::Z(_) => self.after_rev(name, whole),
                Val::Poison => Val::Poison,
                other => {
                    let kind = other.kind();
                    self.err(syn::Error::new(
                        args[0].span(),
                        format!("`.zip()` over {kind}: it zips arrays and their iterators"),
                    ))
                }
            },
            ("map", 1) => {
                let Val::F(f) = self.expr(args[0])? else {
                    return Ok(Some(self.unsupported(
                        args[0].span(),
                        "a `.map()` argument that is not a closure or a function of the body",
                    )));
                };
                let mut out = Vec::with_capacity(items.len());
                for (x, g) in items {
                    out.push((self.call_fn(&f, vec![x], args[0])?, g));
                }
                z(out, forward)
            }
            ("fold", 2) => {
                let mut acc = self.expr(args[0])?;
                let Val::F(f) = self.expr(args[1])? else {
                    return Ok(Some(self.unsupported(
                        args[1].span(),
                        "a `.fold()` argument that is not a closure or a function of the body",
                    )));
                };
                for (x, g) in items {
                    let next = self.call_fn(&f, vec![acc.clone(), x], args[1])?;
                    acc = self.guarded(&g, next, acc, span);
                }
                acc
            }
            ("sum" | "product", 0) => {
                let op = if name == "sum" { '+' } else { '*' };
                let mut acc: Option<Val> = None;
                for (x, g) in items {
                    if !self.spend(whole, &format!("this `.{name}()`")) {
                        return Ok(Some(Val::Poison));
                    }
                    // An element that does not exist adds 0 (multiplies by 1).
                    let x = match x {
                        Val::V(_) if op == '+' => self.guarded(&g, x, Val::V([Dag::ZERO; 3]), span),
                        Val::S(_) | Val::I(_) | Val::V(_) => {
                            let unit = Val::S(if op == '+' { Dag::ZERO } else { Dag::ONE });
                            self.guarded(&g, x, unit, span)
                        }
                        other => other,
                    };
                    acc = Some(match acc {
                        None => x,
                        Some(a) => self.arith(op, a, x, recv_e, recv_e)?,
                    });
                }
                acc.unwrap_or(Val::S(if op == '+' { Dag::ZERO } else { Dag::ONE }))
            }
            ("len" | "count", 0) => self.unsupported(
                span,
                &format!(
                    "`.{name}()` of a zip with an array field whose length the macro does not \
                     know (its length is known at run time only)"
                ),
            ),
            _ => return Ok(None),
        }))
    }

    fn unknown_length(&mut self, b: &Expr, whole: &dyn At) -> Val {
        let text = cond_text(&quote::ToTokens::to_token_stream(b));
        self.err(syn::Error::new(
            whole.at(),
            format!(
                "the length of `{text}` is not known when the macro expands: zip it with a \
                 coordinate array (`q.iter().zip({}.iter())`), or loop over a range and index \
                 it (`for i in 0..K {{ .. self.{text}[i] .. }}`)",
                quote::ToTokens::to_token_stream(b)
            ),
        ))
    }

    /// `recv.method(args)`, the receiver `recv_e` already lowered to `recv`.
    fn apply_method(
        &mut self,
        recv: Val,
        recv_e: &Expr,
        method: &syn::Ident,
        args: &[&Expr],
        whole: &dyn At,
    ) -> R<Val> {
        let name = method.to_string();
        let nargs = args.len();
        let bad_arity = |this: &mut Self, k: usize| -> Val {
            this.err(syn::Error::new(
                whole.at(),
                format!("`.{name}()` takes {k} argument(s) here"),
            ))
        };
        if let Some(v) = self.iterator_method(&recv, recv_e, &name, args, whole)? {
            return Ok(v);
        }
        if matches!(recv, Val::Poison) {
            return Ok(Val::Poison);
        }
        let fun = Fun::from_method(&name);
        if let Some(f) = fun {
            if nargs != 0 {
                return Ok(bad_arity(self, 0));
            }
            let Some(x) = self.scalar(recv, recv_e, &format!("the receiver of `.{name}()`")) else {
                return Ok(Val::Poison);
            };
            return Ok(Val::S(self.dag.un(f, x)));
        }
        match name.as_str() {
            "clone" | "to_owned" if nargs == 0 => return Ok(recv),
            "sin_cos" | "recip" | "powi" | "powf" | "atan2" | "hypot" | "mul_add" | "max"
            | "min" | "clamp" => {
                let want = match name.as_str() {
                    "sin_cos" | "recip" => 0,
                    "mul_add" | "clamp" => 2,
                    _ => 1,
                };
                if nargs != want {
                    return Ok(bad_arity(self, want));
                }
                let Some(x) = self.scalar(recv, recv_e, &format!("the receiver of `.{name}()`"))
                else {
                    return Ok(Val::Poison);
                };
                if name == "powi" {
                    return Ok(
                        match int_literal(args[0]).and_then(|k| i32::try_from(k).ok()) {
                            Some(k) => Val::S(self.dag.powi(x, k)),
                            None if matches!(paren_less(args[0]), Expr::Lit(l) if matches!(l.lit, Lit::Float(_))) => {
                                self.err(syn::Error::new(
                                    args[0].span(),
                                    "`powi` takes an integer exponent (`powi(2)`); for a real exponent use `powf`",
                                ))
                            }
                            // A constant exponent (`powi(N)`, `powi(Self::K)`): a parameter,
                            // x^N as x.powf(N as f64), exact for integers also at x < 0.
                            None => {
                                let e = args[0];
                                let cast: Expr = syn::parse_quote_spanned!(e.span()=> (#e) as f64);
                                let shown = cond_text(&quote::ToTokens::to_token_stream(e));
                                match self.opaque_shown(&cast, Some(shown)) {
                                    Some(Val::S(n)) => Val::S(self.dag.powf(x, n)),
                                    _ => self.unsupported(
                                        args[0].span(),
                                        "a `powi` exponent that depends on the state (it must be \
                                         a constant: a literal, a `const`, a parameter)",
                                    ),
                                }
                            }
                        },
                    );
                }
                let mut ys = Vec::new();
                for a in args {
                    let v = self.expr(a)?;
                    match self.scalar(v, *a, &format!("the argument of `.{name}()`")) {
                        Some(y) => ys.push(y),
                        None => return Ok(Val::Poison),
                    }
                }
                let d = &mut self.dag;
                return Ok(match name.as_str() {
                    "sin_cos" => {
                        Val::Tuple(vec![Val::S(d.un(Fun::Sin, x)), Val::S(d.un(Fun::Cos, x))])
                    }
                    "recip" => Val::S(d.div(Dag::ONE, x)),
                    "powf" => Val::S(d.powf(x, ys[0])),
                    "atan2" => Val::S(d.atan2(x, ys[0])),
                    "max" => Val::S(pick(d, x, ys[0], x, ys[0])),
                    "min" => Val::S(pick(d, x, ys[0], ys[0], x)),
                    "clamp" => {
                        let (lo, hi) = (ys[0], ys[1]);
                        let m = pick(d, x, lo, x, lo);
                        Val::S(pick(d, m, hi, hi, m))
                    }
                    "hypot" => {
                        let a = d.powi(x, 2);
                        let b = d.powi(ys[0], 2);
                        let s = d.add(a, b);
                        Val::S(d.un(Fun::Sqrt, s))
                    }
                    _ => {
                        let p = d.mul(x, ys[0]);
                        Val::S(d.add(p, ys[1]))
                    }
                });
            }
            "dot" | "cross" | "norm" | "norm_squared" | "magnitude" | "magnitude_squared"
            | "normalize" | "scale" | "component_mul" => {
                let want = match name.as_str() {
                    "dot" | "cross" | "scale" | "component_mul" => 1,
                    _ => 0,
                };
                if nargs != want {
                    return Ok(bad_arity(self, want));
                }
                let Some(a) = self.vector(recv, recv_e, &format!("the receiver of `.{name}()`"))?
                else {
                    return Ok(Val::Poison);
                };
                if name == "scale" {
                    let v = self.expr(args[0])?;
                    let Some(s) = self.scalar(v, args[0], "the argument of `.scale()`") else {
                        return Ok(Val::Poison);
                    };
                    return Ok(Val::V(a.map(|x| self.dag.mul(s, x))));
                }
                let b = if want == 1 {
                    let v = self.expr(args[0])?;
                    match self.vector(v, args[0], &format!("the argument of `.{name}()`"))? {
                        Some(b) => b,
                        None => return Ok(Val::Poison),
                    }
                } else {
                    a
                };
                let d = &mut self.dag;
                let dot = |d: &mut Dag| {
                    let x = d.mul(a[0], b[0]);
                    let y = d.mul(a[1], b[1]);
                    let z = d.mul(a[2], b[2]);
                    let s = d.add(x, y);
                    d.add(s, z)
                };
                let sq = |d: &mut Dag| {
                    let x = d.powi(a[0], 2);
                    let y = d.powi(a[1], 2);
                    let z = d.powi(a[2], 2);
                    let s = d.add(x, y);
                    d.add(s, z)
                };
                return Ok(match name.as_str() {
                    "dot" => Val::S(dot(d)),
                    "component_mul" => Val::V([0, 1, 2].map(|k| d.mul(a[k], b[k]))),
                    "cross" => {
                        let c = |d: &mut Dag, i: usize, j: usize| {
                            let p = d.mul(a[i], b[j]);
                            let q = d.mul(a[j], b[i]);
                            d.sub(p, q)
                        };
                        Val::V([c(d, 1, 2), c(d, 2, 0), c(d, 0, 1)])
                    }
                    "norm_squared" | "magnitude_squared" => Val::S(sq(d)),
                    "norm" | "magnitude" => {
                        let s = sq(d);
                        Val::S(d.un(Fun::Sqrt, s))
                    }
                    _ => {
                        let s = sq(d);
                        let n = d.un(Fun::Sqrt, s);
                        Val::V(a.map(|x| d.div(x, n)))
                    }
                });
            }
            _ => {}
        }
        Ok(self.unsupported(method.span(), &format!("the method `.{name}()`")))
    }
}

/// A condition for people: the tokens with Rust's spacing tidied and `self.` dropped.
fn cond_text(ts: &proc_macro2::TokenStream) -> String {
    let s = ts.to_string();
    let s = s
        .replace(" . ", ".")
        .replace(" :: ", "::")
        .replace("( ", "(")
        .replace(" )", ")")
        .replace(" ,", ",")
        .replace(" [", "[")
        .replace("[ ", "[")
        .replace(" ]", "]")
        .replace("! ", "!");
    // A call's parenthesis follows its name directly.
    let mut out = String::with_capacity(s.len());
    let chars: Vec<char> = s.chars().collect();
    for (k, &ch) in chars.iter().enumerate() {
        let call = ch == ' '
            && chars.get(k + 1) == Some(&'(')
            && k > 0
            && (chars[k - 1].is_alphanumeric() || chars[k - 1] == '_');
        if !call {
            out.push(ch);
        }
    }
    out.replace("self.", "")
}

/// The methods [`Lower::apply_method`] lowers besides those of the function table.
const KNOWN_METHODS: &[&str] = &[
    "clone",
    "to_owned",
    "sin_cos",
    "recip",
    "powi",
    "powf",
    "atan2",
    "hypot",
    "mul_add",
    "max",
    "min",
    "clamp",
    "dot",
    "cross",
    "norm",
    "norm_squared",
    "magnitude",
    "magnitude_squared",
    "normalize",
    "scale",
    "component_mul",
];

/// `f64::EPSILON` and the other finite associated constants of `f64`.
fn f64_assoc_const(name: &str) -> Option<f64> {
    Some(match name {
        "EPSILON" => f64::EPSILON,
        "MAX" => f64::MAX,
        "MIN" => f64::MIN,
        "MIN_POSITIVE" => f64::MIN_POSITIVE,
        _ => return None,
    })
}

fn f64_const(name: &str) -> Option<f64> {
    use std::f64::consts as c;
    Some(match name {
        "PI" => c::PI,
        "TAU" => c::TAU,
        "E" => c::E,
        "SQRT_2" => c::SQRT_2,
        "FRAC_PI_2" => c::FRAC_PI_2,
        "FRAC_PI_3" => c::FRAC_PI_3,
        "FRAC_PI_4" => c::FRAC_PI_4,
        "FRAC_PI_6" => c::FRAC_PI_6,
        "FRAC_PI_8" => c::FRAC_PI_8,
        "FRAC_1_PI" => c::FRAC_1_PI,
        "FRAC_2_PI" => c::FRAC_2_PI,
        "FRAC_1_SQRT_2" => c::FRAC_1_SQRT_2,
        "LN_2" => c::LN_2,
        "LN_10" => c::LN_10,
        "FRAC_2_SQRT_PI" => c::FRAC_2_SQRT_PI,
        "LOG2_E" => c::LOG2_E,
        "LOG10_E" => c::LOG10_E,
        "LOG2_10" => c::LOG2_10,
        "LOG10_2" => c::LOG10_2,
        _ => return None,
    })
}

/// Whether a type is `f64` or `f32` (a cast to it makes a float).
fn is_float_type(ty: &syn::Type) -> bool {
    matches!(ty, syn::Type::Path(p) if p.path.is_ident("f64") || p.path.is_ident("f32") || p.path.is_ident("Scalar"))
}

/// `self.f`, `&self.f`, `self.f.iter()`, `self.f.into_iter()` (and `.copied()`/`.cloned()`
/// after them): the field `self.f`, an array whose length the macro does not know.
fn self_field_seq(e: &Expr) -> Option<Expr> {
    match paren_less(e) {
        Expr::Reference(r) => self_field_seq(&r.expr),
        Expr::Field(f) if matches!(paren_less(&f.base), Expr::Path(p) if p.path.is_ident("self")) => {
            Some(Expr::Field(f.clone()))
        }
        Expr::MethodCall(m)
            if m.args.is_empty()
                && matches!(
                    m.method.to_string().as_str(),
                    "iter" | "into_iter" | "copied" | "cloned"
                ) =>
        {
            self_field_seq(&m.receiver)
        }
        _ => None,
    }
}

/// `xs.zip(ys)`: pairs, each guarded by both sides' guards (see [`Zipped`]).
fn zip_guarded(xs: Vec<(Val, Guard)>, ys: Vec<(Val, Guard)>) -> Val {
    Val::Z(Box::new(Zipped {
        items: xs
            .into_iter()
            .zip(ys)
            .map(|((x, mut g), (y, h))| {
                g.extend(h);
                (Val::Tuple(vec![x, y]), g)
            })
            .collect(),
        forward: true,
    }))
}

/// Sets the element of `whole` at the indices `ks` (outermost first) to `v`.
fn set_element(whole: &mut Val, ks: &[i64], v: Val) -> Result<(), String> {
    let Some((&k, rest)) = ks.split_first() else {
        *whole = v;
        return Ok(());
    };
    match whole {
        Val::A(items) => {
            let n = items.len();
            match usize::try_from(k).ok().and_then(|k| items.get_mut(k)) {
                Some(slot) => set_element(slot, rest, v),
                None => Err(format!(
                    "index {k} is out of bounds: the array has {n} elements"
                )),
            }
        }
        Val::V(c) if rest.is_empty() && (0..3).contains(&k) => match v {
            Val::S(id) => {
                c[k as usize] = id;
                Ok(())
            }
            other => Err(format!(
                "a Vector3 component must be a scalar, and this is {}",
                other.kind()
            )),
        },
        Val::Poison => Ok(()),
        other => Err(format!("this assigns to an element of {}", other.kind())),
    }
}
