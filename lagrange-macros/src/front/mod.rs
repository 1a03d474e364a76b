//! The front end of the body language, run once per impl block before either back end: what
//! each body binds at its entry ([`Body::seeds`]: coordinates, velocities, the time) and which
//! names it mentions, the functions it may call ([`callables`]: helper methods, nested `fn`s,
//! closures, integer `const`s), the scopes and the one pattern binder ([`scope`]), the
//! iterator vocabulary ([`vocab`]) and which bodies read rates ([`timed`]: `velocity`, the
//! angular velocities, through helpers to any depth). The jets back end (`jets/`: the body rewritten generically
//! over the number type) and the symbolic back end (`symbolic/lower/`: the body unrolled into
//! the expression graph) both consume it; `analyze.rs` reads the flags from it.

pub mod callables;
pub mod scope;
pub mod timed;
pub mod vocab;

use std::collections::HashSet;

use proc_macro2::{Ident, TokenStream, TokenTree};
use syn::visit::Visit;
use syn::Expr;

use crate::model::{unraw, Decl, FuncKind};

pub use callables::Callables;

/// What a name bound at a body's entry holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Seed {
    /// The coordinate of the `p`-th coordinate parameter.
    Coord(usize),
    /// The velocity of the `p`-th coordinate parameter.
    Velocity(usize),
    /// The time.
    Time,
}

/// One body of the macro's functions, resolved at its entry.
pub struct Body<'a> {
    /// `None` for `fn lagrangian`.
    pub kind: Option<FuncKind>,
    /// The body as written.
    pub block: &'a syn::Block,
    /// The names its signature binds, in declaration order (coordinates and velocities of each
    /// parameter, then the time), `_` bindings left out.
    pub seeds: Vec<(String, Seed)>,
    /// Every name the body mentions (single-segment paths, and any identifier inside a macro
    /// call, whose tokens are opaque).
    pub used: HashSet<String>,
}

impl Body<'_> {
    /// The bound names the body mentions, in declaration order: what a generated method binds
    /// (the others it leaves `_`), and the names that carry the motion into the body.
    pub fn bound(&self) -> Vec<String> {
        self.seeds
            .iter()
            .filter(|(name, _)| self.used.contains(name))
            .map(|(name, _)| name.clone())
            .collect()
    }

    /// Whether the body binds and mentions `seed`.
    pub fn reads(&self, seed: Seed) -> bool {
        self.seeds
            .iter()
            .any(|(name, s)| *s == seed && self.used.contains(name))
    }
}

/// The front end's result for one impl block.
pub struct Front<'a> {
    /// `fn lagrangian`'s body.
    pub lagrangian: Body<'a>,
    /// The other functions' bodies (`fn dissipation`, `fn forces`, `fn constraints`,
    /// `fn velocity_constraints`, `fn contacts`), those present.
    pub funcs: Vec<Body<'a>>,
    /// The helper methods and integer constants of the impl block.
    pub callables: Callables,
}

impl<'a> Front<'a> {
    /// Resolves the declaration's bodies.
    pub fn of(decl: &'a Decl) -> Front<'a> {
        let own: Vec<(Option<&Ident>, Option<&Ident>)> = decl
            .coords
            .iter()
            .map(|c| (Some(&c.name), Some(&c.dot)))
            .collect();
        let lagrangian = body(None, &decl.body, &own, decl.time.as_ref());
        let funcs = [
            &decl.dissipation,
            &decl.forces,
            &decl.constraints,
            &decl.velocity_constraints,
            &decl.contacts,
            &decl.scene,
        ]
        .into_iter()
        .flatten()
        .map(|f| {
            let bindings: Vec<_> = f
                .bindings
                .iter()
                .map(|(c, v)| (c.as_ref(), v.as_ref()))
                .collect();
            body(Some(f.kind), &f.body, &bindings, f.time.as_ref())
        })
        .collect();
        Front {
            lagrangian,
            funcs,
            callables: Callables::of(&decl.rest),
        }
    }

    /// The body of the function of kind `kind`, if the impl block has one.
    pub fn func(&self, kind: FuncKind) -> Option<&Body<'a>> {
        self.funcs.iter().find(|b| b.kind == Some(kind))
    }
}

fn body<'a>(
    kind: Option<FuncKind>,
    block: &'a syn::Block,
    bindings: &[(Option<&Ident>, Option<&Ident>)],
    time: Option<&Ident>,
) -> Body<'a> {
    let mut seeds = Vec::new();
    for (p, (c, v)) in bindings.iter().enumerate() {
        if let Some(c) = c {
            seeds.push((unraw(c), Seed::Coord(p)));
        }
        if let Some(v) = v {
            seeds.push((unraw(v), Seed::Velocity(p)));
        }
    }
    if let Some(t) = time {
        seeds.push((unraw(t), Seed::Time));
    }
    Body {
        kind,
        block,
        seeds,
        used: mentions(block),
    }
}

/// Every name a block mentions: single-segment paths, and every identifier inside macro calls.
pub fn mentions(b: &syn::Block) -> HashSet<String> {
    let mut v = Mentions::default();
    v.visit_block(b);
    v.0
}

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

/// Every identifier in `ts`, into `out`.
pub fn idents_in(ts: TokenStream, out: &mut HashSet<String>) {
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

/// `e` without the parentheses (and invisible groups) around it.
pub fn paren_less(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => paren_less(&p.expr),
        Expr::Group(g) => paren_less(&g.expr),
        _ => e,
    }
}

/// An integer literal, possibly negated and parenthesized (`6`, `-(2)`).
pub fn int_literal(e: &Expr) -> Option<i64> {
    match paren_less(e) {
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Int(i),
            ..
        }) => i.base10_parse::<i64>().ok(),
        Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => int_literal(&u.expr).map(|x| -x),
        _ => None,
    }
}
