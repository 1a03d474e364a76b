//! Validate: every rule a `fn lagrangian` declaration must satisfy, each violation reported at
//! the user's token, all of them at once.

use std::collections::HashMap;

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{FnArg, ImplItemFn, Pat, ReceiverKind, ReturnType, Type};

use crate::errors::Errors;
use crate::model::{CoordKind, CoordParam, Decl, Options};
use crate::parse::Split;

const SIGNATURE_HINT: &str =
    "fn lagrangian(&self, (x, x_dot): Coord, (r, r_dot): Coord3, t: Time) -> Scalar";

/// Checks the split impl block and builds the declaration; `None` if any rule is broken
/// (the errors say which).
pub fn validate(split: Split, options: Options, errors: &mut Errors) -> Option<Decl> {
    let Split { rest, mut funcs } = split;
    if let Some((_, for_token)) = &rest.trait_ {
        errors.at(
            for_token,
            "`#[lagrangian]` goes on an inherent impl block (`impl MySystem { ... }`), not on a trait impl: it writes the `Lagrangian` impl itself",
        );
    }
    if !rest.generics.params.is_empty() || rest.generics.where_clause.is_some() {
        errors.at(
            &rest.generics,
            "`#[lagrangian]` does not support generic impl blocks: write it for a concrete type",
        );
    }
    if let Some(u) = &rest.unsafety {
        errors.at(u, "`#[lagrangian]` impl blocks cannot be `unsafe`");
    }
    if funcs.is_empty() {
        let misnamed = rest.items.iter().find_map(|item| match item {
            syn::ImplItem::Fn(f) if f.sig.inputs.iter().any(is_coordinate_param) => {
                Some(&f.sig.ident)
            }
            _ => None,
        });
        match misnamed {
            Some(ident) => errors.at(
                ident,
                "`#[lagrangian]` looks for a fn named `lagrangian`; this one takes coordinates: rename it to `lagrangian`",
            ),
            None => errors.at(
                &rest.self_ty,
                format!(
                    "no `fn lagrangian` in this impl block: `#[lagrangian]` needs `{SIGNATURE_HINT}`"
                ),
            ),
        }
        return None;
    }
    for extra in funcs.iter().skip(1) {
        errors.at(
            &extra.sig.ident,
            "a second `fn lagrangian` in this impl block: a system has one Lagrangian",
        );
    }
    let func = funcs.swap_remove(0);
    let decl = check_fn(func, rest, options, errors);
    if errors.is_empty() {
        decl
    } else {
        None
    }
}

fn check_fn(
    func: ImplItemFn,
    rest: syn::ItemImpl,
    options: Options,
    errors: &mut Errors,
) -> Option<Decl> {
    let sig = &func.sig;
    if let Some(c) = &sig.constness {
        errors.at(c, "`fn lagrangian` cannot be `const`");
    }
    if let Some(a) = &sig.asyncness {
        errors.at(
            a,
            "`fn lagrangian` cannot be `async`: it is evaluated at every step",
        );
    }
    if let syn::Safety::Unsafe(u) = &sig.safety {
        errors.at(u, "`fn lagrangian` cannot be `unsafe`");
    }
    if let Some(abi) = &sig.abi {
        errors.at(abi, "`fn lagrangian` cannot have an ABI");
    }
    if let Some(v) = &sig.variadic {
        errors.at(v, "`fn lagrangian` cannot be variadic");
    }
    if !sig.generics.params.is_empty() || sig.generics.where_clause.is_some() {
        errors.at(
            &sig.generics,
            "`fn lagrangian` takes no generic parameters: `Scalar` is provided by the macro; put generic helpers in functions over `S: Scalar`",
        );
    }
    let ret_span = match &sig.output {
        ReturnType::Type(_, ty) if is_ident_type(ty, "Scalar") => ty.span(),
        ReturnType::Type(_, ty) => {
            errors.at(
                ty,
                "`fn lagrangian` returns `Scalar` (the macro's number type), not a concrete type",
            );
            ty.span()
        }
        ReturnType::Default => {
            errors.at(
                &sig.ident,
                format!("`fn lagrangian` must return `Scalar`: `{SIGNATURE_HINT}`"),
            );
            sig.ident.span()
        }
    };

    let mut inputs = sig.inputs.iter();
    match inputs.next() {
        Some(FnArg::Receiver(r)) => {
            let ok =
                matches!(&r.kind, ReceiverKind::Reference(_, _, None)) && r.mutability.is_none();
            if !ok {
                errors.at(r, "`fn lagrangian` takes `&self` (a shared reference): L must not change the system");
            }
        }
        Some(other) => {
            errors.at(
                other,
                format!("`fn lagrangian` takes `&self` first: `{SIGNATURE_HINT}`"),
            );
        }
        None => errors.at(
            &sig.ident,
            format!("`fn lagrangian` takes `&self` and the coordinates: `{SIGNATURE_HINT}`"),
        ),
    }
    let mut coords = Vec::new();
    let mut time: Option<proc_macro2::Ident> = None;
    let mut seen: HashMap<String, Span> = HashMap::new();
    let mut check_name = |ident: &proc_macro2::Ident, errors: &mut Errors| {
        let name = crate::model::unraw(ident);
        if seen.insert(name.clone(), ident.span()).is_some() {
            errors.at(
                ident,
                format!("`{name}` is bound twice in the parameters of `fn lagrangian`"),
            );
        }
    };
    let mut next_index = 0;
    let mut declared_coordinates = 0;
    for arg in inputs {
        let pt = match arg {
            FnArg::Typed(pt) => pt,
            FnArg::Receiver(r) => {
                errors.at(r, "`self` may only come first");
                continue;
            }
        };
        let kind = if is_ident_type(&pt.ty, "Coord") {
            Some(CoordKind::Scalar)
        } else if is_ident_type(&pt.ty, "Coord3") {
            Some(CoordKind::Vector3)
        } else if is_ident_type(&pt.ty, "Time") {
            None
        } else {
            errors.at(
                &pt.ty,
                "unknown parameter type: a parameter of `fn lagrangian` is `(x, x_dot): Coord`, `(r, r_dot): Coord3` or `t: Time`",
            );
            continue;
        };
        if kind.is_some() {
            declared_coordinates += 1;
        }
        match kind {
            Some(kind) => match coord_pattern(&pt.pat) {
                Some((name, dot)) => {
                    check_name(&name, errors);
                    check_name(&dot, errors);
                    let p = CoordParam { kind, name, dot, first_index: next_index };
                    next_index += p.width();
                    coords.push(p);
                }
                None => errors.at(
                    &pt.pat,
                    "a coordinate is bound as a pair of names, the coordinate and its velocity: `(x, x_dot): Coord`",
                ),
            },
            None => match &*pt.pat {
                Pat::Ident(pi) if pi.by_ref.is_none() && pi.mutability.is_none() && pi.subpat.is_none() => {
                    if time.is_some() {
                        errors.at(&pt.pat, "a second `Time` parameter: L has one time `t: Time`");
                    } else {
                        check_name(&pi.ident, errors);
                        time = Some(pi.ident.clone());
                    }
                }
                other => errors.at(other, "time is bound to a plain name: `t: Time`"),
            },
        }
    }
    if declared_coordinates == 0 {
        errors.at(
            &sig.ident,
            format!("`fn lagrangian` needs at least one coordinate, e.g. `(x, x_dot): Coord`: `{SIGNATURE_HINT}`"),
        );
    }
    if !errors.is_empty() {
        return None;
    }
    Some(Decl {
        rest,
        fn_attrs: func.attrs,
        fn_ident: func.sig.ident,
        ret_span,
        coords,
        time,
        body: func.block,
        options,
    })
}

/// Whether a parameter is typed `Coord`, `Coord3` or `Time` (to recognise a misnamed Lagrangian).
pub fn is_coordinate_param(arg: &FnArg) -> bool {
    match arg {
        FnArg::Typed(pt) => ["Coord", "Coord3", "Time"]
            .iter()
            .any(|n| is_ident_type(&pt.ty, n)),
        FnArg::Receiver(_) => false,
    }
}

/// `(name, name)` with plain identifiers.
fn coord_pattern(pat: &Pat) -> Option<(proc_macro2::Ident, proc_macro2::Ident)> {
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
fn is_ident_type(ty: &Type, name: &str) -> bool {
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
