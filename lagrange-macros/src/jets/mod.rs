//! The jets back end: each body rewritten so constants (`2.0`, `self.m`, `Vector3<f64>` fields)
//! meet values of the motion through the runtime's mixed-arithmetic traits, and the helper
//! methods made generic over the number type. It walks the body with the front end's scopes,
//! pattern binder, callables and iterator vocabulary (`crate::front`).
//!
//! Each expression gets a kind: `Const` (no dependence on q, q̇ or t: an `f64`, a
//! `Vector3<f64>`, a bool...) or `Var` (a `Scalar` or `Vector3<Scalar>`), or a tuple of kinds.
//! Where a `Const` meets a `Var` in `+ - * /`, the operation becomes
//! `__private::ConstMul::const_mul(c, v)` (or `MulConst::mul_const(v, c)`, ...): the constant stays
//! an `f64`. Elsewhere (method arguments, comparisons, `Vector3::new`, branches of an `if`) the
//! constant is lifted with `__private::lift::<Scalar, _>(c)`. Generated calls carry the span of
//! the user's expression, so a type error points at the user's code. The walk also reports the
//! mistakes a physicist makes that rustc would report in the runtime's terms (`x ^ 2`, `2 * x`),
//! in both modes (the jets bodies are emitted in both).
//!
//! [`rewrite`] holds the statements, bindings and expressions; [`ops`] the method chains and the
//! operators.

mod ops;
mod rewrite;

use std::collections::HashSet;

use proc_macro2::TokenStream;
use quote::quote_spanned;
use syn::spanned::Spanned;
use syn::{Block, Expr, Pat, Stmt};

use crate::errors::Errors;
use crate::front::callables::Callables;
use crate::front::paren_less;
use crate::front::scope::{Bindable, Scopes};
use crate::model::{mentions_scalar, unraw};

/// The kind of an expression's value.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Kind {
    Const,
    Var,
    Tuple(Vec<Kind>),
}

impl Kind {
    pub(crate) fn is_var(&self) -> bool {
        match self {
            Kind::Const => false,
            Kind::Var => true,
            Kind::Tuple(ks) => ks.iter().any(Kind::is_var),
        }
    }
    pub(crate) fn join(a: Kind, b: Kind) -> Kind {
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

impl Bindable for Kind {
    fn parts(self, n: usize) -> Result<Vec<Kind>, Kind> {
        Ok(match self {
            Kind::Tuple(ks) => (0..n)
                .map(|i| ks.get(i).cloned().unwrap_or(Kind::Var))
                .collect(),
            other => vec![other; n],
        })
    }
    /// A binding typed with `Scalar` is a variable whatever its value.
    fn typed(self, ty: &syn::Type) -> Kind {
        if mentions_scalar(quote::ToTokens::to_token_stream(ty)) {
            Kind::Var
        } else {
            self
        }
    }
}

/// Rewrites the body for the jets path. `vars` are the bindings that carry coordinates or time.
pub fn lower_for_jets(
    body: &Block,
    vars: &[String],
    callables: &Callables,
    errors: &mut Errors,
) -> Block {
    rewrite(errors, callables, |rw| {
        rw.scopes = Scopes::of(vars.iter().map(|v| (v.clone(), Kind::Var)).collect());
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
    callables: &Callables,
    mut run: impl FnMut(&mut Rewriter<'_>) -> T,
) -> T {
    let mut promote = HashSet::new();
    loop {
        let mut rw = Rewriter {
            scopes: Scopes::default(),
            errors: Vec::new(),
            promote: promote.clone(),
            found: HashSet::new(),
            callables,
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
    callables: &Callables,
    errors: &mut Errors,
) -> Block {
    rewrite(errors, callables, |rw| lower_array_body(rw, body, vars))
}

fn lower_array_body(rw: &mut Rewriter<'_>, body: &Block, vars: &[String]) -> Block {
    rw.scopes = Scopes::of(vars.iter().map(|v| (v.clone(), Kind::Var)).collect());
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
    callables: &Callables,
    errors: &mut Errors,
) -> syn::ItemImpl {
    let mut rest = rest.clone();
    for item in &mut rest.items {
        if let syn::ImplItem::Fn(f) = item {
            if crate::model::is_helper(f) {
                let (sig, block) = rewrite(errors, callables, |rw| {
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

struct Rewriter<'a> {
    scopes: Scopes<Kind>,
    /// Mistakes a physicist makes that rustc would report in terms of the runtime's traits:
    /// `x ^ 2` meant as a power, `2 * x` with an integer literal.
    errors: Vec<syn::Error>,
    /// `let mut` bindings to make variables at their `let` (see [`rewrite`]).
    promote: HashSet<String>,
    /// Constant bindings this run saw assigned a variable value.
    found: HashSet<String>,
    /// The helper methods of the impl block.
    callables: &'a Callables,
    /// The kinds of the parameters of the closure about to be rewritten, when an iterator
    /// method passes it elements of known kinds.
    closure_hint: Option<Vec<Kind>>,
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

/// Whether a type names `Scalar`.
fn type_mentions_scalar(ty: &syn::Type) -> bool {
    mentions_scalar(quote::ToTokens::to_token_stream(ty))
}

/// A body of the front end rewritten for the jets: a scalar one (`fn lagrangian`,
/// `fn dissipation`) as [`lower_for_jets`], an array one (the others) as
/// [`lower_array_for_jets`]; its bound names carry the motion.
pub fn body(b: &crate::front::Body<'_>, callables: &Callables, errors: &mut Errors) -> Block {
    let vars = b.bound();
    match b.kind {
        None | Some(crate::model::FuncKind::Dissipation) => {
            lower_for_jets(b.block, &vars, callables, errors)
        }
        Some(_) => lower_array_for_jets(b.block, &vars, callables, errors),
    }
}
