//! What a body may name: free uses of a name, bindings, names mentioned inside macros.

#[allow(unused_imports)]
use super::*;

/// Whether `name` appears among the tokens of a macro invocation in `body` (opaque tokens: any
/// mention counts).
pub(super) fn mentioned_in_macro(body: &syn::Block, name: &str) -> bool {
    use syn::visit::Visit;
    struct Find<'a>(&'a str, bool);
    fn walk(ts: proc_macro2::TokenStream, name: &str) -> bool {
        ts.into_iter().any(|tt| match tt {
            proc_macro2::TokenTree::Ident(i) => crate::model::unraw(&i) == name,
            proc_macro2::TokenTree::Group(g) => walk(g.stream(), name),
            _ => false,
        })
    }
    impl<'ast> Visit<'ast> for Find<'_> {
        fn visit_macro(&mut self, m: &'ast syn::Macro) {
            self.1 |= walk(m.tokens.clone(), self.0);
        }
    }
    let mut f = Find(name, false);
    f.visit_block(body);
    f.1
}

pub(super) fn paren_less(e: &syn::Expr) -> &syn::Expr {
    match e {
        syn::Expr::Paren(p) => paren_less(&p.expr),
        syn::Expr::Group(g) => paren_less(&g.expr),
        _ => e,
    }
}

/// `(a, b)` where each is a plain name or `_` (also `_` for the whole pair).
pub(super) fn binding_pattern(
    pat: &Pat,
) -> Option<(Option<proc_macro2::Ident>, Option<proc_macro2::Ident>)> {
    let one = |p: &Pat| match p {
        Pat::Ident(pi) if pi.by_ref.is_none() && pi.mutability.is_none() && pi.subpat.is_none() => {
            Some(Some(pi.ident.clone()))
        }
        Pat::Wild(_) => Some(None),
        _ => None,
    };
    match pat {
        Pat::Wild(_) => Some((None, None)),
        Pat::Tuple(t) if t.elems.len() == 2 => Some((one(&t.elems[0])?, one(&t.elems[1])?)),
        _ => None,
    }
}

/// The first use of `name` as a value in `body`, unless the body binds it itself (a `let`, a
/// closure parameter, a pattern).
pub(super) fn free_use(body: &syn::Block, name: &str) -> Option<proc_macro2::Ident> {
    use syn::visit::Visit;
    struct Find<'a> {
        name: &'a str,
        first: Option<proc_macro2::Ident>,
        bound: bool,
    }
    impl<'ast> Visit<'ast> for Find<'_> {
        fn visit_expr_path(&mut self, p: &'ast syn::ExprPath) {
            if let Some(id) = p.path.get_ident() {
                if p.qself.is_none() && self.first.is_none() && crate::model::unraw(id) == self.name
                {
                    self.first = Some(id.clone());
                }
            }
        }
        fn visit_pat_ident(&mut self, p: &'ast syn::PatIdent) {
            if crate::model::unraw(&p.ident) == self.name {
                self.bound = true;
            }
            syn::visit::visit_pat_ident(self, p);
        }
    }
    let mut f = Find {
        name,
        first: None,
        bound: false,
    };
    f.visit_block(body);
    if f.bound {
        None
    } else {
        f.first
    }
}
