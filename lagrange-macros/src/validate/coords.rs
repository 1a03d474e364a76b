//! The coordinate parameters: `Coord`, `Coord3`, `Coords<K>` and `Time`, their patterns, and the
//! names a signature binds.

#[allow(unused_imports)]
use super::*;

/// Whether a parameter is typed `Coord`, `Coord3`, `Coords<K>` or `Time` (to recognise a misnamed Lagrangian).
pub fn is_coordinate_param(arg: &FnArg) -> bool {
    match arg {
        FnArg::Typed(pt) => coord_type(&pt.ty).is_some() || is_ident_type(&pt.ty, "Time"),
        FnArg::Receiver(_) => false,
    }
}

/// The coordinate kind a parameter type names: `Coord`, `Coord3`, `Coords<K>` (optionally
/// qualified); `None` for any other type, an error for `Coords` without a literal length ≥ 1.
pub fn coord_type(ty: &Type) -> Option<syn::Result<CoordKind>> {
    match ty {
        Type::Group(g) => return coord_type(&g.elem),
        Type::Paren(p) => return coord_type(&p.elem),
        _ => {}
    }
    if is_ident_type(ty, "Coord") {
        return Some(Ok(CoordKind::Scalar));
    }
    if is_ident_type(ty, "Coord3") {
        return Some(Ok(CoordKind::Vector3));
    }
    let Type::Path(p) = ty else { return None };
    if p.qself.is_some() {
        return None;
    }
    let seg = p.path.segments.last()?;
    if seg.ident != "Coords" {
        return None;
    }
    let bad = |at: &dyn quote::ToTokens| {
        Some(Err(syn::Error::new_spanned(
            at,
            "`Coords` takes the number of coordinates as an integer literal: `(q, q_dot): Coords<6>`",
        )))
    };
    let syn::PathArguments::AngleBracketed(args) = &seg.arguments else {
        return bad(seg);
    };
    if args.args.len() != 1 {
        return bad(args);
    }
    let lit = match &args.args[0] {
        syn::GenericArgument::Const(syn::Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Int(i),
            ..
        })) => i,
        syn::GenericArgument::Const(syn::Expr::Block(b)) => match b.block.stmts.as_slice() {
            [syn::Stmt::Expr(
                syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Int(i),
                    ..
                }),
                None,
            )] => i,
            _ => return bad(&args.args[0]),
        },
        other => return bad(other),
    };
    match lit.base10_parse::<usize>() {
        Ok(k) if (1..=4096).contains(&k) => Some(Ok(CoordKind::Array(k))),
        _ => Some(Err(syn::Error::new_spanned(
            lit,
            "`Coords<K>` takes 1 to 4096 coordinates",
        ))),
    }
}

/// `(name, name)` with plain identifiers.
pub(super) fn coord_pattern(pat: &Pat) -> Option<(proc_macro2::Ident, proc_macro2::Ident)> {
    let Pat::Tuple(t) = pat else { return None };
    if t.elems.len() != 2 {
        return None;
    }
    let plain = |p: &Pat| match p {
        Pat::Ident(pi) if pi.by_ref.is_none() && pi.mutability.is_none() && pi.subpat.is_none() => {
            Some(pi.ident.clone())
        }
        _ => None,
    };
    Some((plain(&t.elems[0])?, plain(&t.elems[1])?))
}

/// Whether `ty` is the path `name` (optionally qualified, e.g. `lagrange::Coord`).
pub(super) fn is_ident_type(ty: &Type, name: &str) -> bool {
    match ty {
        Type::Path(p) if p.qself.is_none() => p
            .path
            .segments
            .last()
            .is_some_and(|s| s.ident == name && matches!(s.arguments, syn::PathArguments::None)),
        Type::Group(g) => is_ident_type(&g.elem, name),
        Type::Paren(p) => is_ident_type(&p.elem, name),
        _ => false,
    }
}

/// The names a function's parameters bind, to report one bound twice.
#[derive(Default)]
pub(super) struct Names(HashMap<String, Span>);

impl Names {
    /// Records `ident`; `false` (with an error at it) if `fn func` binds it already.
    pub(super) fn bind(
        &mut self,
        ident: &proc_macro2::Ident,
        func: &str,
        errors: &mut Errors,
    ) -> bool {
        let n = crate::model::unraw(ident);
        if self.0.insert(n.clone(), ident.span()).is_some() {
            errors.at(
                ident,
                format!("`{n}` is bound twice in the parameters of `fn {func}`"),
            );
            false
        } else {
            true
        }
    }
}
