//! Code on parameters only: integer and boolean constants the macro evaluates, opaque
//! expressions evaluated once per call as written, the conditions of `if` on parameters, and
//! the merge of two branches into selects.

use super::*;

impl Lower {
    /// An integer known when the macro expands, read from the syntax (no lowering): literals,
    /// integer bindings (loop variables), `Self::N`, `q.len()`, and `+ - * / %` of them.
    pub(super) fn const_int(&self, e: &Expr) -> Option<i64> {
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
    pub(super) fn const_bool(&self, e: &Expr) -> Option<bool> {
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

    pub(super) fn merge(&mut self, c: u32, a: Val, b: Val, span: Span) -> Val {
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
    pub(super) fn opaque(&mut self, e: &Expr) -> Option<Val> {
        self.opaque_shown(e, None)
    }

    /// [`Self::opaque`], printed in the equations as `shown` instead of as `e` (the exponent
    /// `N` of `powi(N)`, evaluated as `(N) as f64`). The same tokens share one parameter.
    pub(super) fn opaque_shown(&mut self, e: &Expr, shown: Option<String>) -> Option<Val> {
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
    pub(super) fn condition(&mut self, e: &Expr) -> Option<u32> {
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
    pub(super) fn guard_cond(&mut self, g: &Guard, span: Span) -> Option<u32> {
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
    pub(super) fn guarded(&mut self, g: &Guard, v: Val, other: Val, span: Span) -> Val {
        match self.guard_cond(g, span) {
            Some(c) => self.merge(c, v, other, span),
            None => v,
        }
    }

    pub(super) fn cond_tokens(
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
    pub(super) fn walk_self(
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
}
