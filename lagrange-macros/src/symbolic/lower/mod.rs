//! Lowering of the Lagrangian body (a `syn::Block`) into the expression DAG.
//!
//! Values are scalars (one node), vectors (three nodes), tuples, or poison (after an error, so
//! that every unsupported construct in the body is reported at once). `self.<field>` becomes a
//! parameter symbol; whether a field is an `f64` or a `Vector3<f64>` is inferred from its use:
//! every field starts as a scalar and is re-typed as a vector (and the body lowered again) when a
//! vector is required where it flows. The emitted code loads each field with its inferred type,
//! so a wrong inference is a compile error at the field.
//!
//! One job per file, all methods of [`Lower`]: this file holds the values, the scopes, the fields
//! and the entry point; [`stmt`] statements and bindings, [`expr`] expressions and arithmetic,
//! [`iter`] loops and the iterator vocabulary, [`call`] the function table, helpers and closures,
//! [`cond`] code on parameters only and the conditions of `if`.

mod call;
mod cond;
mod expr;
mod geometry;
mod iter;
mod stmt;

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit, Member, Pat, Stmt, UnOp};

use super::dag::{Dag, Fun, Id, Node};
use crate::errors::Errors;
use crate::front::callables::{FnBody, Function};
use crate::front::scope::{Bindable, Scopes};
use crate::front::vocab::Iter;
use crate::front::{int_literal, paren_less, Body, Front, Seed};
use crate::model::{unraw, CoordKind, Decl};

/// A `self.<field>` used in the body.
#[derive(Clone)]
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

#[derive(Clone)]
enum Val {
    S(Id),
    V([Id; 3]),
    /// A rotation matrix (`Rotation::about_z(a)`, …): its nine entries, row by row.
    R([Id; 9]),
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
#[derive(Clone)]
struct Zipped {
    items: Vec<(Val, Guard)>,
    /// The elements are in the order they were zipped in (`false` after `.rev()`): the ones that
    /// exist are then a prefix, so `.enumerate()`, `.skip(k)`, `.take(k)`, `.step_by(k)` and
    /// `.zip(..)` may follow.
    forward: bool,
}

/// The array fields an element of a [`Zipped`] reads and at which position.
type Guard = Vec<(Expr, usize)>;

/// A function the lowering inlines (the front end's description of it) and the bindings its
/// body sees (a closure's captured scope; none for a helper or a nested `fn`).
struct Callable {
    f: std::rc::Rc<Function>,
    env: Scopes<Val>,
}

impl Callable {
    /// A function that captures nothing.
    fn item(f: std::rc::Rc<Function>) -> Callable {
        Callable {
            f,
            env: Scopes::default(),
        }
    }
}

impl std::fmt::Debug for Callable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.f.what)
    }
}

impl Bindable for Val {
    fn parts(self, n: usize) -> Result<Vec<Val>, Val> {
        match self {
            Val::Tuple(items) if items.len() == n => Ok(items),
            Val::Poison => Ok(vec![Val::Poison; n]),
            _ => Err(Val::Poison),
        }
    }
    fn refuse(pat: &Pat) -> Option<syn::Error> {
        Some(unsupported(pat.span(), "this pattern"))
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
            Val::R(_) => "a Rotation",
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
pub fn lower(decl: &Decl, front: &Front<'_>, sink: &mut Errors) -> Option<Lowered> {
    let mut fields: Vec<Field> = Vec::new();
    // Each retry turns one more field into a vector, so this terminates.
    loop {
        let mut lw = Lower {
            dag: Dag::new(decl.n()),
            scopes: Scopes::default(),
            errors: Vec::new(),
            fields: std::mem::take(&mut fields),
            conds: Vec::new(),
            helpers: front
                .callables
                .helpers
                .iter()
                .map(|(name, f)| (name.clone(), std::rc::Rc::new(Callable::item(f.clone()))))
                .collect(),
            int_consts: front.callables.int_consts.clone(),
            depth: 0,
            frame_base: 0,
            work: 0,
            over_budget: false,
        };
        match lw.bodies(decl, front) {
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
    scopes: Scopes<Val>,
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
        self.scopes.lookup(name)
    }

    fn assign(&mut self, name: &str, val: Val) -> bool {
        match self.scopes.position(name) {
            Some(k) if self.depth > 0 && k < self.frame_base => false,
            Some(k) => {
                self.scopes.set(k, val);
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

    /// Binds a body's entry names (the front end's seeds) to the DAG's leaves, as the only
    /// scope.
    fn seed(&mut self, decl: &Decl, body: &Body<'_>) {
        self.scopes = Scopes::default();
        // Every coordinate's leaves, in declaration order (so the graph's nodes are numbered
        // the same whichever names a body binds).
        let leaves: Vec<(Val, Val)> = decl
            .coords
            .iter()
            .map(|c| {
                let i = c.first_index;
                match c.kind {
                    CoordKind::Scalar => (Val::S(self.dag.q(i)), Val::S(self.dag.v(i))),
                    CoordKind::Vector3 => (
                        Val::V([self.dag.q(i), self.dag.q(i + 1), self.dag.q(i + 2)]),
                        Val::V([self.dag.v(i), self.dag.v(i + 1), self.dag.v(i + 2)]),
                    ),
                    CoordKind::Array(k) => (
                        Val::A((i..i + k).map(|j| Val::S(self.dag.q(j))).collect()),
                        Val::A((i..i + k).map(|j| Val::S(self.dag.v(j))).collect()),
                    ),
                }
            })
            .collect();
        let time = body
            .seeds
            .iter()
            .any(|(_, s)| *s == Seed::Time)
            .then(|| self.dag.t());
        for (name, seed) in &body.seeds {
            let v = match (*seed, time) {
                (Seed::Coord(p), _) => leaves[p].0.clone(),
                (Seed::Velocity(p), _) => leaves[p].1.clone(),
                (Seed::Time, Some(t)) => Val::S(t),
                (Seed::Time, None) => Val::Poison,
            };
            self.scopes.push(name.clone(), v);
        }
    }

    fn bodies(&mut self, decl: &Decl, front: &Front<'_>) -> R<Bodies> {
        self.seed(decl, &front.lagrangian);
        self.new_body();
        let lagrangian = self.block(&decl.body)?;
        let dissipation = match front.func(crate::model::FuncKind::Dissipation) {
            Some(b) => {
                self.seed(decl, b);
                self.new_body();
                Some(self.block(b.block)?)
            }
            None => None,
        };
        let forces = match front.func(crate::model::FuncKind::Forces) {
            Some(b) => {
                self.seed(decl, b);
                self.new_body();
                Some(self.array_block(b.block, decl.n())?)
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
