//! Statements, bindings and expressions of the jets rewrite.

use std::collections::HashSet;

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned, ToTokens};
use syn::spanned::Spanned;
use syn::{Block, Expr, Pat, Stmt};

use super::*;
use crate::front::callables::{closure_params, type_of, ParamType};
use crate::front::{idents_in, scope};

impl Rewriter<'_> {
    fn lookup(&self, name: &str) -> Option<Kind> {
        self.scopes.lookup(name)
    }

    /// Binds `pat` to `kind` with the front end's binder (every pattern Rust has: rustc checks
    /// it against the value as written).
    pub(super) fn bind(&mut self, pat: &Pat, kind: Kind) {
        let mut errors = Vec::new();
        scope::bind(&mut self.scopes, pat, kind, &mut errors);
        self.errors.extend(errors);
    }

    pub(super) fn block(&mut self, b: &mut Block) -> Kind {
        let mark = self.scopes.mark();
        let mut kind = Kind::Const;
        let n = b.stmts.len();
        for (i, stmt) in b.stmts.iter_mut().enumerate() {
            let k = self.stmt(stmt);
            if i + 1 == n {
                kind = k;
            }
        }
        self.scopes.truncate(mark);
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
                        if type_mentions_scalar(&pt.ty) && !kind.is_var() {
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
                let saved = self.scopes.take();
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
    pub(super) fn generic_fn(&mut self, sig: &mut syn::Signature, block: &mut Block) {
        sig.generics
            .params
            .push(syn::parse_quote!(Scalar: ::lagrange::__private::Scalar));
        let mark = self.scopes.mark();
        for arg in &sig.inputs {
            if let syn::FnArg::Typed(pt) = arg {
                let kind = match type_of(&pt.ty) {
                    ParamType::Scalar => Kind::Var,
                    ParamType::Other | ParamType::Untyped => Kind::Const,
                };
                self.bind(&pt.pat, kind);
            }
        }
        let kind = self.block(block);
        self.scopes.truncate(mark);
        let returns_scalar = matches!(&sig.output, syn::ReturnType::Type(_, t) if matches!(&**t, syn::Type::Path(p) if p.path.is_ident("Scalar")));
        if kind == Kind::Const && returns_scalar {
            lift_block_tail(block);
        }
    }

    pub(super) fn macro_kind(&self, tokens: &TokenStream) -> Kind {
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

    pub(super) fn expr(&mut self, e: &mut Expr) -> Kind {
        match e {
            Expr::Lit(_) => Kind::Const,
            Expr::Path(p) => {
                if p.qself.is_none() && p.path.segments.len() == 1 {
                    self.lookup(&unraw(&p.path.segments[0].ident))
                        .unwrap_or(Kind::Const)
                } else if mentions_scalar(quote!(#p)) {
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
                let kf = if mentions_scalar(c.func.to_token_stream()) {
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
                    let mark = self.scopes.mark();
                    self.bind(&arm.pat, ks.clone());
                    kinds.push(self.expr(&mut arm.body));
                    self.scopes.truncate(mark);
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
                let mark = self.scopes.mark();
                // A parameter typed with anything but `Scalar` (`|m: f64, v: Scalar|`) is a
                // constant; an untyped one has the kind of the elements an iterator method
                // passes it (`.map(|(v, m)| ..)` after a `.zip`), or may carry the coordinates.
                let hint = self.closure_hint.take().unwrap_or_default();
                for (i, (p, ty)) in c.inputs.iter().zip(closure_params(c)).enumerate() {
                    let k = match ty {
                        ParamType::Scalar => Kind::Var,
                        ParamType::Other => Kind::Const,
                        ParamType::Untyped => hint.get(i).cloned().unwrap_or(Kind::Var),
                    };
                    self.bind(p, k);
                }
                let k = self.expr(&mut c.body);
                self.scopes.truncate(mark);
                if k.is_var() || self.macro_kind(&quote!(#c)).is_var() {
                    Kind::Var
                } else {
                    Kind::Const
                }
            }
            Expr::ForLoop(f) => {
                let k = self.expr(&mut f.expr);
                let mark = self.scopes.mark();
                self.bind(&f.pat, k);
                self.block(&mut f.body);
                self.scopes.truncate(mark);
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
}
