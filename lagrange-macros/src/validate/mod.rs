//! Validate: every rule a `fn lagrangian` declaration (and `fn dissipation`, `fn forces` and
//! `fn constraints` next to it) must satisfy, each violation reported at the user's token, all of them at once.
//!
//! One job per file: this one the entry point and `fn lagrangian`'s signature; [`extra`] the
//! functions next to it (`dissipation`, `forces`, `constraints`); [`coords`] the coordinate
//! parameters' types and patterns; [`body`] what a body may name.

use std::collections::HashMap;

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{FnArg, ImplItemFn, Pat, ReceiverKind, ReturnType, Type};

use crate::errors::Errors;
use crate::model::{CoordKind, CoordParam, Decl, Func, FuncKind, Options};
use crate::parse::Split;

mod body;
mod coords;
mod extra;
mod linear;

use body::*;
use coords::*;
pub use coords::{coord_type, is_coordinate_param};
use extra::*;
pub use extra::{constraint_count, contact_count};

const SIGNATURE_HINT: &str =
    "fn lagrangian(&self, (x, x_dot): Coord, (r, r_dot): Coord3, t: Time) -> Scalar";

/// Checks the split impl block and builds the declaration; `None` if any rule is broken
/// (the errors say which).
pub fn validate(split: Split, options: Options, errors: &mut Errors) -> Option<Decl> {
    let Split {
        rest,
        mut funcs,
        dissipation,
        forces,
        constraints,
        contacts,
        velocity_constraints,
        scene,
    } = split;
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
    for (list, kind) in [
        (&dissipation, FuncKind::Dissipation),
        (&forces, FuncKind::Forces),
        (&constraints, FuncKind::Constraints),
        (&contacts, FuncKind::Contacts),
        (&velocity_constraints, FuncKind::VelocityConstraints),
        (&scene, FuncKind::Scene),
    ] {
        for extra in list.iter().skip(1) {
            let what = match kind {
                FuncKind::Dissipation => "a system has one Rayleigh dissipation function D: put every dissipative term into the one `fn dissipation` (they add)",
                FuncKind::Forces => "a system has one `fn forces`: add the forces on each coordinate into its one entry of the array",
                FuncKind::Constraints => "a system has one `fn constraints`: put every constraint g(q, t) = 0 into its own entry of the one array it returns",
                FuncKind::Contacts => "a system has one `fn contacts`: put every contact into its own entry of the one array it returns",
                FuncKind::VelocityConstraints => "a system has one `fn velocity_constraints`: put every velocity constraint into its own entry of the one array it returns",
                FuncKind::Scene => "a system has one `fn scene`: add every shape to the one `Scene` it returns",
            };
            errors.at(
                &extra.sig.ident,
                format!(
                    "a second `fn {}` in this impl block: {what}",
                    kind.user_name()
                ),
            );
        }
    }
    let func = funcs.swap_remove(0);
    let mut decl = check_fn(func, rest, options, errors)?;
    for (list, kind) in [
        (dissipation, FuncKind::Dissipation),
        (forces, FuncKind::Forces),
        (constraints, FuncKind::Constraints),
        (contacts, FuncKind::Contacts),
        (velocity_constraints, FuncKind::VelocityConstraints),
        (scene, FuncKind::Scene),
    ] {
        let Some(f) = list.into_iter().next() else {
            continue;
        };
        let checked = check_extra(f, kind, &decl.coords, decl.time.as_ref(), errors);
        match kind {
            FuncKind::Dissipation => decl.dissipation = checked,
            FuncKind::Forces => decl.forces = checked,
            FuncKind::Constraints => decl.constraints = checked,
            FuncKind::Contacts => decl.contacts = checked,
            FuncKind::VelocityConstraints => decl.velocity_constraints = checked,
            FuncKind::Scene => decl.scene = checked,
        }
    }
    if errors.is_empty() {
        Some(decl)
    } else {
        None
    }
}

/// Reads the receiver off `inputs` and returns its `self` token. What is not `&self` is reported
/// with `messages` (not shared, not first, no parameters at all); a first parameter that is not a
/// receiver stays in `inputs`, so a missing `&self` is not also "no coordinate".
fn receiver(
    inputs: &mut std::iter::Peekable<syn::punctuated::Iter<'_, FnArg>>,
    sig: &syn::Signature,
    messages: [String; 3],
    errors: &mut Errors,
) -> syn::token::SelfValue {
    let [not_shared, not_first, missing] = messages;
    match inputs.peek().copied() {
        Some(FnArg::Receiver(r)) => {
            inputs.next();
            if !is_shared_self(r) {
                errors.at(r, not_shared);
            }
            r.self_token
        }
        Some(other) => {
            errors.at(other, not_first);
            syn::Token![self](sig.ident.span())
        }
        None => {
            errors.at(&sig.ident, missing);
            syn::Token![self](sig.ident.span())
        }
    }
}

/// `&self`, or the same written out, `self: &Self`.
fn is_shared_self(r: &syn::Receiver) -> bool {
    if r.mutability.is_some() {
        return false;
    }
    match &r.kind {
        ReceiverKind::Reference(_, _, None) => true,
        ReceiverKind::Typed(_, ty) => matches!(
            &**ty,
            Type::Reference(rt) if rt.mutability.is_none() && is_ident_type(&rt.elem, "Self")
        ),
        _ => false,
    }
}

fn check_fn(
    func: ImplItemFn,
    rest: syn::ItemImpl,
    options: Options,
    errors: &mut Errors,
) -> Option<Decl> {
    let sig = &func.sig;
    check_qualifiers(sig, "lagrangian", errors);
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

    let mut inputs = sig.inputs.iter().peekable();
    let self_token = receiver(
        &mut inputs,
        sig,
        [
            "`fn lagrangian` takes `&self` (a shared reference): L must not change the system"
                .to_owned(),
            format!("`fn lagrangian` takes `&self` first: `{SIGNATURE_HINT}`"),
            format!("`fn lagrangian` takes `&self` and the coordinates: `{SIGNATURE_HINT}`"),
        ],
        errors,
    );
    let mut coords = Vec::new();
    let mut time: Option<proc_macro2::Ident> = None;
    let mut seen = Names::default();
    let mut check_name = |ident: &proc_macro2::Ident, errors: &mut Errors| {
        seen.bind(ident, "lagrangian", errors);
    };
    let mut next_index = 0;
    let mut declared_coordinates = 0;
    let mut unknown_types = 0;
    let mut state_names: Vec<proc_macro2::Ident> = Vec::new();
    for arg in inputs {
        let pt = match arg {
            FnArg::Typed(pt) => pt,
            FnArg::Receiver(r) => {
                errors.at(r, "`self` may only come first");
                continue;
            }
        };
        let kind = if let Some(kind) = coord_type(&pt.ty) {
            match kind {
                Ok(kind) => Some(kind),
                Err(e) => {
                    errors.push(e);
                    unknown_types += 1;
                    if let Some((name, dot)) = coord_pattern(&pt.pat) {
                        state_names.extend([name, dot]);
                    }
                    continue;
                }
            }
        } else if is_ident_type(&pt.ty, "Time") {
            None
        } else {
            errors.at(
                &pt.ty,
                "unknown parameter type: a parameter of `fn lagrangian` is `(x, x_dot): Coord`, `(r, r_dot): Coord3`, `(q, q_dot): Coords<6>` or `t: Time`",
            );
            // Meant as a coordinate or the time all the same: its names are the body's state
            // (for the body's own errors), and it is not "no coordinate" as well.
            unknown_types += 1;
            match (coord_pattern(&pt.pat), &*pt.pat) {
                (Some((name, dot)), _) => state_names.extend([name, dot]),
                (None, Pat::Ident(pi)) => state_names.push(pi.ident.clone()),
                _ => {}
            }
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
    if time.is_none() && !coords.iter().any(|c| c.name == "t" || c.dot == "t") {
        if let Some(at) = free_use(&func.block, "t") {
            errors.at(
                &at,
                format!("`t` is used in `fn lagrangian`, which has no `t: Time` parameter: add `t: Time` to its parameters to use the time: `{SIGNATURE_HINT}`"),
            );
        }
    }
    if declared_coordinates == 0 && unknown_types == 0 {
        errors.at(
            &sig.ident,
            format!("`fn lagrangian` needs at least one coordinate, e.g. `(x, x_dot): Coord`: `{SIGNATURE_HINT}`"),
        );
    }
    if !errors.is_empty() {
        // The body's own mistakes (`x ^ 2`, `2 * x`) in the same build as the signature's.
        let vars: Vec<String> = coords
            .iter()
            .flat_map(|c| [&c.name, &c.dot])
            .chain(time.as_ref())
            .chain(&state_names)
            .map(crate::model::unraw)
            .collect();
        crate::jets::lower_for_jets(
            &func.block,
            &vars,
            &crate::front::Callables::of(&rest),
            errors,
        );
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
        self_token,
        options,
        dissipation: None,
        forces: None,
        constraints: None,
        contacts: None,
        velocity_constraints: None,
        scene: None,
    })
}

/// The qualifiers no function of the macro may have (`const`, `async`, `unsafe`, an ABI,
/// variadics, generics), each an error at its token.
fn check_qualifiers(sig: &syn::Signature, name: &str, errors: &mut Errors) {
    if let Some(c) = &sig.constness {
        errors.at(c, format!("`fn {name}` cannot be `const`"));
    }
    if let Some(a) = &sig.asyncness {
        errors.at(
            a,
            format!("`fn {name}` cannot be `async`: it is evaluated at every step"),
        );
    }
    if let syn::Safety::Unsafe(u) = &sig.safety {
        errors.at(u, format!("`fn {name}` cannot be `unsafe`"));
    }
    if let Some(abi) = &sig.abi {
        errors.at(abi, format!("`fn {name}` cannot have an ABI"));
    }
    if let Some(v) = &sig.variadic {
        errors.at(v, format!("`fn {name}` cannot be variadic"));
    }
    if !sig.generics.params.is_empty() || sig.generics.where_clause.is_some() {
        errors.at(
            &sig.generics,
            format!("`fn {name}` takes no generic parameters: `Scalar` is provided by the macro; put generic helpers in functions over `S: Scalar`"),
        );
    }
}
