//! The body of `fn velocity_constraints`: each entry must be affine in the velocities,
//! c = A(q, t) q̇ + b(q, t). Checked on the syntax: sums of terms, each a velocity (or a rate
//! function of positions: `velocity(p)`, the angular velocities) times factors free of
//! velocities; anything else that touches a velocity is reported at its token.

use std::collections::HashMap;

use proc_macro2::Span;
use quote::ToTokens;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Pat, Stmt, UnOp};

use crate::front::timed::RATE_FUNCTIONS;

/// How an expression depends on the velocities.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// Not at all.
    Free,
    /// Linearly, with no velocity-free term: A q̇.
    Linear,
    /// Linearly, with a velocity-free term: A q̇ + b.
    Affine,
}

impl Form {
    /// The form of a sum (or difference) of two terms.
    fn sum(self, other: Form) -> Form {
        match (self, other) {
            (Form::Free, Form::Free) => Form::Free,
            (Form::Linear, Form::Linear) => Form::Linear,
            _ => Form::Affine,
        }
    }
    /// The form of a branch's result: the wider.
    fn join(self, other: Form) -> Form {
        match (self, other) {
            (Form::Free, f) | (f, Form::Free) => f,
            (Form::Linear, Form::Linear) => Form::Linear,
            _ => Form::Affine,
        }
    }
}

/// What breaks linearity: where, and why.
pub type NotLinear = (Span, String);

/// The names a body binds: velocities (`Form::Linear`), and locals as they are met.
pub struct Scope {
    names: HashMap<String, Form>,
    /// The time's name: a rate function of something that depends on it has a ∂/∂t part.
    time: Option<String>,
}

impl Scope {
    /// The scope of a body whose velocity parameters are `velocities`, with time `time`.
    pub fn new(velocities: impl IntoIterator<Item = String>, time: Option<String>) -> Self {
        Scope {
            names: velocities.into_iter().map(|v| (v, Form::Linear)).collect(),
            time,
        }
    }

    /// Whether `e` mentions a name this scope marks as depending on the velocities, or a rate
    /// function.
    fn touches(&self, e: &impl ToTokens) -> bool {
        fn walk(ts: proc_macro2::TokenStream, s: &Scope) -> bool {
            ts.into_iter().any(|tt| match tt {
                proc_macro2::TokenTree::Ident(i) => {
                    let name = crate::model::unraw(&i);
                    RATE_FUNCTIONS.contains(&name.as_str())
                        || s.names.get(&name).is_some_and(|f| *f != Form::Free)
                }
                proc_macro2::TokenTree::Group(g) => walk(g.stream(), s),
                _ => false,
            })
        }
        walk(e.to_token_stream(), self)
    }

    /// Whether `e` mentions the time.
    fn mentions_time(&self, e: &impl ToTokens) -> bool {
        let Some(t) = &self.time else { return false };
        fn walk(ts: proc_macro2::TokenStream, t: &str) -> bool {
            ts.into_iter().any(|tt| match tt {
                proc_macro2::TokenTree::Ident(i) => crate::model::unraw(&i) == t,
                proc_macro2::TokenTree::Group(g) => walk(g.stream(), t),
                _ => false,
            })
        }
        walk(e.to_token_stream(), t)
    }

    /// The form of a block's statements and tail (`let`s bind their forms).
    pub fn block(&mut self, b: &syn::Block) -> Result<Form, NotLinear> {
        let saved = self.names.clone();
        let mut tail = Form::Free;
        for stmt in &b.stmts {
            let f = self.statement(stmt)?;
            if matches!(stmt, Stmt::Expr(_, None)) {
                tail = f;
            }
        }
        self.names = saved;
        Ok(tail)
    }

    /// One statement: a `let` binds its names with the form of its value (and gives `Free`);
    /// an expression gives its form.
    pub fn statement(&mut self, stmt: &Stmt) -> Result<Form, NotLinear> {
        match stmt {
            Stmt::Local(l) => {
                let form = match &l.init {
                    Some(init) => self.expr(&init.expr)?,
                    None => Form::Free,
                };
                self.bind(&l.pat, form);
                Ok(Form::Free)
            }
            Stmt::Expr(e, _) => self.expr(e),
            Stmt::Item(_) => Ok(Form::Free),
            Stmt::Macro(m) => {
                if self.touches(&m.mac.tokens) {
                    Err(unknown(m.span()))
                } else {
                    Ok(Form::Free)
                }
            }
        }
    }

    /// Binds every name of `pat` with `form`.
    fn bind(&mut self, pat: &Pat, form: Form) {
        match pat {
            Pat::Ident(p) => {
                self.names.insert(crate::model::unraw(&p.ident), form);
            }
            Pat::Type(t) => self.bind(&t.pat, form),
            Pat::Tuple(t) => t.elems.iter().for_each(|p| self.bind(p, form)),
            Pat::Slice(s) => s.elems.iter().for_each(|p| self.bind(p, form)),
            Pat::Reference(r) => self.bind(&r.pat, form),
            _ => {}
        }
    }

    /// The form of one expression.
    pub fn expr(&mut self, e: &Expr) -> Result<Form, NotLinear> {
        if !self.touches(e) {
            return Ok(Form::Free);
        }
        match e {
            Expr::Paren(p) => self.expr(&p.expr),
            Expr::Group(g) => self.expr(&g.expr),
            Expr::Path(p) => Ok(p
                .path
                .get_ident()
                .and_then(|i| self.names.get(&crate::model::unraw(i)).copied())
                .unwrap_or(Form::Free)),
            Expr::Unary(u) => match u.op {
                UnOp::Neg(_) | UnOp::Deref(_) => self.expr(&u.expr),
                _ => Err(unknown(u.span())),
            },
            Expr::Reference(r) => self.expr(&r.expr),
            Expr::Field(f) => self.expr(&f.base),
            Expr::Index(i) => {
                if self.touches(&i.index) {
                    return Err(unknown(i.index.span()));
                }
                self.expr(&i.expr)
            }
            Expr::Binary(b) => {
                let (l, r) = (self.expr(&b.left)?, self.expr(&b.right)?);
                match b.op {
                    BinOp::Add(_) | BinOp::Sub(_) => Ok(l.sum(r)),
                    BinOp::Mul(_) => match (l, r) {
                        (Form::Free, f) | (f, Form::Free) => Ok(f),
                        _ => Err((
                            b.op.span(),
                            "a product of two factors that both depend on the velocities: not \
                             linear in q̇"
                                .to_owned(),
                        )),
                    },
                    BinOp::Div(_) => match r {
                        Form::Free => Ok(l),
                        _ => Err((
                            b.right.span(),
                            "a division by an expression of the velocities: not linear in q̇"
                                .to_owned(),
                        )),
                    },
                    _ => Err((
                        b.op.span(),
                        "this operator on the velocities is not linear in q̇".to_owned(),
                    )),
                }
            }
            Expr::Array(a) => a
                .elems
                .iter()
                .try_fold(Form::Free, |f, e| Ok(f.join(self.expr(e)?))),
            Expr::Tuple(t) => t
                .elems
                .iter()
                .try_fold(Form::Free, |f, e| Ok(f.join(self.expr(e)?))),
            Expr::Block(b) => self.block(&b.block),
            Expr::Call(c) => self.call(c),
            Expr::MethodCall(m) => self.method(m),
            other => Err(unknown(other.span())),
        }
    }

    /// A function call: a rate function of positions (linear, affine with the time), or a
    /// `Vector3::new` of affine components.
    fn call(&mut self, c: &syn::ExprCall) -> Result<Form, NotLinear> {
        let name = match &*c.func {
            Expr::Path(p) => p
                .path
                .segments
                .iter()
                .map(|s| s.ident.to_string())
                .collect::<Vec<_>>()
                .join("::"),
            _ => String::new(),
        };
        let last = name.rsplit("::").next().unwrap_or("");
        if RATE_FUNCTIONS.contains(&last) {
            for a in &c.args {
                if self.expr(a)? != Form::Free {
                    return Err((
                        a.span(),
                        format!("`{last}` of an expression of the velocities: its rate is not linear in q̇ (write it of positions only)"),
                    ));
                }
            }
            let moving = c.args.iter().any(|a| self.mentions_time(a));
            return Ok(if moving { Form::Affine } else { Form::Linear });
        }
        if name.ends_with("Vector3::new") || name == "new" {
            return c
                .args
                .iter()
                .try_fold(Form::Free, |f, e| Ok(f.join(self.expr(e)?)));
        }
        Err((
            c.func.span(),
            format!("`{name}` of an expression of the velocities: a function call on them is not linear in q̇"),
        ))
    }

    /// A method call: `dot`, `cross` and `scale` are linear in each side; a field-like
    /// accessor (`x()`, `transpose()`) keeps the form; anything else on a velocity is not linear.
    fn method(&mut self, m: &syn::ExprMethodCall) -> Result<Form, NotLinear> {
        let r = self.expr(&m.receiver)?;
        let args = m
            .args
            .iter()
            .map(|a| self.expr(a))
            .collect::<Result<Vec<_>, _>>()?;
        let name = m.method.to_string();
        match name.as_str() {
            "dot" | "cross" | "scale" | "component_mul" => {
                let varying = std::iter::once(r)
                    .chain(args.iter().copied())
                    .filter(|f| *f != Form::Free)
                    .count();
                if varying > 1 {
                    return Err((
                        m.method.span(),
                        format!("`{name}` of two factors that both depend on the velocities: not linear in q̇"),
                    ));
                }
                Ok(args.iter().fold(r, |f, a| f.join(*a)))
            }
            "x" | "y" | "z" | "transpose" | "clone" | "neg"
                if args.iter().all(|a| *a == Form::Free) =>
            {
                Ok(r)
            }
            _ => Err((
                m.method.span(),
                format!("`{name}` of an expression of the velocities is not linear in q̇"),
            )),
        }
    }
}

/// The error for a construct the check does not read through.
fn unknown(span: Span) -> NotLinear {
    (
        span,
        "this construct touches the velocities, and the check that each velocity constraint is \
         affine in q̇ (A(q, t) q̇ + b(q, t)) does not read through it: write the entries as sums \
         of velocities (or `velocity(p)` of positions) times factors of positions and time, \
         with `let` bindings"
            .to_owned(),
    )
}
