//! Validate: every rule a `fn lagrangian` declaration (and `fn dissipation`, `fn forces` and
//! `fn constraints` next to it) must satisfy, each violation reported at the user's token, all of them at once.

use std::collections::HashMap;

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{FnArg, ImplItemFn, Pat, ReceiverKind, ReturnType, Type};

use crate::errors::Errors;
use crate::model::{CoordKind, CoordParam, Decl, Func, FuncKind, Options};
use crate::parse::Split;

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
    ] {
        for extra in list.iter().skip(1) {
            let what = match kind {
                FuncKind::Dissipation => "a system has one Rayleigh dissipation function D: put every dissipative term into the one `fn dissipation` (they add)",
                FuncKind::Forces => "a system has one `fn forces`: add the forces on each coordinate into its one entry of the array",
                FuncKind::Constraints => "a system has one `fn constraints`: put every constraint g(q, t) = 0 into its own entry of the one array it returns",
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
    ] {
        let Some(f) = list.into_iter().next() else {
            continue;
        };
        let checked = check_extra(f, kind, &decl.coords, decl.time.as_ref(), errors);
        match kind {
            FuncKind::Dissipation => decl.dissipation = checked,
            FuncKind::Forces => decl.forces = checked,
            FuncKind::Constraints => decl.constraints = checked,
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
        crate::analyze::lower_for_jets(&func.block, &vars, &crate::analyze::helpers(&rest), errors);
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

/// The rule for the parameters of `fn dissipation` and `fn forces`, quoted by every error about
/// them.
const EXTRA_RULE: &str = "the coordinate parameters of `dissipation` and `forces` are `lagrangian`'s, all of them, in the same order and of the same kinds (`Coord`, `Coord3`, `Coords<K>`); any binding may be `_` (`(x, _)`, `(_, _)`) and names may differ; `t: Time` is optional in each";

/// The rule for the parameters of `fn constraints`, quoted by every error about them.
const CONSTRAINTS_RULE: &str = "the coordinate parameters of `constraints` are `lagrangian`'s, all of them, in the same order and of the same kinds (`Coord`, `Coord3`, `Coords<K>`); any binding may be `_` and names may differ; the constraints g(q, t) = 0 depend on the positions only, so bind each velocity as `_` (`(x, _): Coord`); `t: Time` is optional, for a moving constraint";

/// The parameter rule quoted for `kind`.
fn extra_rule(kind: FuncKind) -> &'static str {
    match kind {
        FuncKind::Dissipation | FuncKind::Forces => EXTRA_RULE,
        FuncKind::Constraints => CONSTRAINTS_RULE,
    }
}

/// The signature `fn dissipation`, `fn forces` or `fn constraints` should have, from
/// `lagrangian`'s coordinates (`k`: the number of constraints, if known).
fn extra_hint(kind: FuncKind, coords: &[CoordParam], time: bool, k: Option<usize>) -> String {
    let mut params: Vec<String> = coords
        .iter()
        .map(|c| {
            let ty = c.kind.type_name();
            if kind == FuncKind::Constraints {
                format!("({}, _): {ty}", c.name)
            } else {
                format!("({}, {}): {ty}", c.name, c.dot)
            }
        })
        .collect();
    if time {
        params.push("t: Time".to_owned());
    }
    let n: usize = coords.iter().map(CoordParam::width).sum();
    let ret = match kind {
        FuncKind::Dissipation => "Scalar".to_owned(),
        FuncKind::Forces => format!("[Scalar; {n}]"),
        FuncKind::Constraints => match k {
            Some(k) => format!("[Scalar; {k}]"),
            None => "[Scalar; K]".to_owned(),
        },
    };
    format!(
        "fn {}(&self, {}) -> {ret}",
        kind.user_name(),
        params.join(", ")
    )
}

/// How many coordinate slots the coordinates declare, spelled out for an error message.
fn slots_text(coords: &[CoordParam]) -> String {
    let n: usize = coords.iter().map(CoordParam::width).sum();
    let names: Vec<String> = coords.iter().flat_map(CoordParam::slot_names).collect();
    let vector = if coords.iter().any(|c| c.kind == CoordKind::Vector3) {
        "; a `Coord3` counts 3 slots: x, y, z"
    } else {
        ""
    };
    format!(
        "`lagrangian` declares {n} coordinate slot{} ({}{vector})",
        if n == 1 { "" } else { "s" },
        names.join(", ")
    )
}

/// Checks `fn dissipation`, `fn forces` or `fn constraints` against the validated
/// `fn lagrangian` (its coordinates) and builds it; `None` if any rule is broken (the errors say
/// which).
fn check_extra(
    func: ImplItemFn,
    kind: FuncKind,
    lag_coords: &[CoordParam],
    lag_time: Option<&proc_macro2::Ident>,
    sink: &mut Errors,
) -> Option<Func> {
    // This function's errors, collected apart so it knows whether it found any.
    let errors = &mut Errors::default();
    let fail = |errors: &mut Errors, tokens: &dyn quote::ToTokens, msg: String| {
        errors.at(tokens, msg);
    };
    let sig = &func.sig;
    let name = kind.user_name();
    let declared_k = constraint_count(&sig.output)
        .and_then(|k| k.ok())
        .filter(|k| *k >= 1);
    let hint = extra_hint(kind, lag_coords, false, declared_k);
    let rule = extra_rule(kind);
    let n: usize = lag_coords.iter().map(CoordParam::width).sum();
    check_qualifiers(sig, name, errors);
    let ret_span = match (&sig.output, kind) {
        (ReturnType::Type(_, ty), FuncKind::Dissipation) => {
            if !is_ident_type(ty, "Scalar") {
                fail(
                    errors,
                    ty,
                    format!("`fn dissipation` returns one `Scalar`: the Rayleigh dissipation function D is a single number at each state (its −∂D/∂q̇ gives one force per coordinate); write `-> Scalar`: `{hint}`"),
                );
            }
            ty.span()
        }
        (ReturnType::Type(_, ty), FuncKind::Forces) => {
            match &**ty {
                Type::Array(a) if is_ident_type(&a.elem, "Scalar") => match &a.len {
                    syn::Expr::Lit(syn::ExprLit { lit: syn::Lit::Int(len), .. }) => {
                        if len.base10_parse::<usize>().ok() != Some(n) {
                            fail(
                                errors,
                                &a.len,
                                format!("`fn forces` returns one generalized force per coordinate slot, and {}: write `[Scalar; {n}]`", slots_text(lag_coords)),
                            );
                        }
                    }
                    other => fail(
                        errors,
                        other,
                        format!("the length of the array `fn forces` returns is written as a number: {}, so write `[Scalar; {n}]`", slots_text(lag_coords)),
                    ),
                },
                other => fail(
                    errors,
                    other,
                    format!("`fn forces` returns an array of generalized forces, one per coordinate slot: {}, so write `-> [Scalar; {n}]`: `{hint}`", slots_text(lag_coords)),
                ),
            }
            ty.span()
        }
        (ReturnType::Type(_, ty), FuncKind::Constraints) => {
            match constraint_count(&sig.output) {
                Some(Ok(k)) if k >= 1 => {}
                Some(Ok(_)) => fail(
                    errors,
                    ty,
                    format!("`fn constraints` returns at least one constraint: write `[Scalar; 1]` or more, one entry g(q, t) per constraint: `{hint}`"),
                ),
                Some(Err(len)) => fail(
                    errors,
                    len,
                    format!("the length of the array `fn constraints` returns, K, is written as a number (how many constraints g(q, t) = 0 there are): `{hint}`"),
                ),
                None => fail(
                    errors,
                    ty,
                    format!("`fn constraints` returns an array of constraints g(q, t), one entry per constraint, each zero on the constrained motion: write `-> [Scalar; K]` with K the number of constraints: `{hint}`"),
                ),
            }
            ty.span()
        }
        (ReturnType::Default, _) => {
            fail(
                errors,
                &sig.ident,
                format!("`fn {name}` must say what it returns: `{hint}`"),
            );
            sig.ident.span()
        }
    };
    let mut inputs = sig.inputs.iter().peekable();
    let self_token = receiver(
        &mut inputs,
        sig,
        [
            format!("`fn {name}` takes `&self` (a shared reference): `{hint}`"),
            format!("`fn {name}` takes `&self` first: `{hint}`"),
            format!("`fn {name}` takes `&self` and the coordinates of `lagrangian`: `{hint}`"),
        ],
        errors,
    );
    let mut bindings = Vec::new();
    let mut time: Option<proc_macro2::Ident> = None;
    let mut seen = Names::default();
    let mut check_name =
        |ident: &proc_macro2::Ident, errors: &mut Errors| seen.bind(ident, name, errors);
    for arg in inputs {
        let pt = match arg {
            FnArg::Typed(pt) => pt,
            FnArg::Receiver(r) => {
                fail(errors, r, "`self` may only come first".to_owned());
                continue;
            }
        };
        let kind_here = if let Some(kind) = coord_type(&pt.ty) {
            match kind {
                Ok(kind) => Some(kind),
                Err(e) => {
                    errors.push(e);
                    bindings.push((None, None));
                    continue;
                }
            }
        } else if is_ident_type(&pt.ty, "Time") {
            None
        } else {
            fail(
                errors,
                &pt.ty,
                format!("unknown parameter type: {rule}: `{hint}`"),
            );
            continue;
        };
        let Some(kind_here) = kind_here else {
            match &*pt.pat {
                Pat::Ident(pi)
                    if pi.by_ref.is_none() && pi.mutability.is_none() && pi.subpat.is_none() =>
                {
                    if time.is_some() {
                        fail(errors, &pt.pat, format!("a second `Time` parameter: `fn {name}` takes at most one `t: Time`"));
                    } else if check_name(&pi.ident, errors) {
                        time = Some(pi.ident.clone());
                    }
                }
                Pat::Wild(_) => {}
                other => fail(
                    errors,
                    other,
                    "time is bound to a plain name: `t: Time`".to_owned(),
                ),
            }
            continue;
        };
        let k = bindings.len();
        let ty_name = CoordKind::type_name;
        match lag_coords.get(k) {
            None => {
                fail(
                    errors,
                    pt,
                    format!(
                        "`lagrangian` declares no such coordinate: it has {} coordinate parameter{}, and this is one more; {rule}: `{hint}`",
                        lag_coords.len(),
                        if lag_coords.len() == 1 { "" } else { "s" },
                    ),
                );
                bindings.push((None, None));
            }
            Some(c) if c.kind != kind_here => {
                fail(
                    errors,
                    &pt.ty,
                    format!(
                        "coordinate {} of `lagrangian`, `({}, {}): {}`, is a `{}`, and this is a `{}`; {rule}: `{hint}`",
                        k + 1,
                        c.name,
                        c.dot,
                        ty_name(c.kind),
                        ty_name(c.kind),
                        ty_name(kind_here),
                    ),
                );
                bindings.push((None, None));
            }
            Some(_) => match binding_pattern(&pt.pat) {
                Some((a, b)) => {
                    for ident in a.iter().chain(&b) {
                        check_name(ident, errors);
                    }
                    bindings.push((a, b));
                }
                None => {
                    fail(
                        errors,
                        &pt.pat,
                        format!("a coordinate is bound as a pair, the coordinate and its velocity, each a name or `_`: `(x, x_dot): Coord`, `(x, _): Coord`; {rule}"),
                    );
                    bindings.push((None, None));
                }
            },
        }
    }
    if bindings.len() < lag_coords.len() {
        let missing: Vec<String> = lag_coords[bindings.len()..]
            .iter()
            .map(|c| format!("`{}`", c.name))
            .collect();
        fail(
            errors,
            &sig.ident,
            format!(
                "`fn {name}` lacks coordinate{} {} of `lagrangian`; {rule}: `{hint}`",
                if missing.len() == 1 { "" } else { "s" },
                missing.join(", ")
            ),
        );
    }
    if time.is_none() {
        let mut candidates = vec!["t".to_owned()];
        if let Some(lt) = lag_time {
            candidates.push(crate::model::unraw(lt));
        }
        let bound: Vec<String> = bindings
            .iter()
            .flat_map(|(a, b)| a.iter().chain(b))
            .map(crate::model::unraw)
            .collect();
        for cand in candidates {
            if bound.contains(&cand) {
                continue;
            }
            if let Some(at) = free_use(&func.block, &cand) {
                let with_time = extra_hint(kind, lag_coords, true, declared_k)
                    .replace("t: Time", &format!("{cand}: Time"));
                let msg = if kind == FuncKind::Constraints {
                    format!("`{cand}` is used in `fn constraints`, which has no `{cand}: Time` parameter: a moving (rheonomic) constraint g(q, t) declares the time, so add `{cand}: Time` to its parameters: `{with_time}`")
                } else {
                    format!("`{cand}` is used in `fn {name}`, which has no `{cand}: Time` parameter: add `{cand}: Time` to its parameters (`t: Time` is optional in each of `lagrangian`, `dissipation` and `forces`, and each one whose body uses the time declares it): `{with_time}`")
                };
                fail(errors, &at, msg);
                break;
            }
        }
    }
    if kind == FuncKind::Constraints {
        // The tail is checked against an array return type only (for another, the error at the
        // return type says it all).
        let array = constraint_count(&sig.output).is_some();
        check_constraints_body(&func.block, &bindings, declared_k, array, &hint, errors);
    }
    let ok = errors.is_empty();
    sink.push_all(std::mem::take(errors));
    if !ok {
        return None;
    }
    Some(Func {
        kind,
        fn_attrs: func.attrs,
        fn_ident: func.sig.ident,
        ret_span,
        bindings,
        time,
        body: func.block,
        self_token,
        k: declared_k.unwrap_or(0),
    })
}

/// K of a return type `[Scalar; K]`: `Some(Ok(K))` for an integer literal, `Some(Err(len))` for
/// any other length expression, `None` when it is not an array of `Scalar`.
pub fn constraint_count(output: &ReturnType) -> Option<Result<usize, &syn::Expr>> {
    let ReturnType::Type(_, ty) = output else {
        return None;
    };
    let mut ty = &**ty;
    while let Type::Group(g) = ty {
        ty = &g.elem;
    }
    match ty {
        Type::Array(a) if is_ident_type(&a.elem, "Scalar") => match &a.len {
            syn::Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Int(len),
                ..
            }) => Some(len.base10_parse::<usize>().map_err(|_| &a.len)),
            other => Some(Err(other)),
        },
        _ => None,
    }
}

/// The rules of the body of `fn constraints`: no velocity it binds is used (the constraints
/// depend on the positions and the time only), and it ends in an array literal of K entries.
fn check_constraints_body(
    body: &syn::Block,
    bindings: &[(Option<proc_macro2::Ident>, Option<proc_macro2::Ident>)],
    k: Option<usize>,
    array: bool,
    hint: &str,
    errors: &mut Errors,
) {
    for (coordinate, velocity) in bindings {
        let Some(velocity) = velocity else { continue };
        let name = crate::model::unraw(velocity);
        // A use as a value is reported there; a mention inside a macro, at the binding.
        let at = free_use(body, &name)
            .or_else(|| mentioned_in_macro(body, &name).then(|| velocity.clone()));
        if let Some(at) = at {
            let x = coordinate
                .as_ref()
                .map_or_else(|| "x".to_owned(), crate::model::unraw);
            errors.at(
                &at,
                format!("`{velocity}` is a velocity, and the constraints g(q, t) = 0 depend on the positions (and, for a moving constraint, on `t: Time`) only: bind the velocity as `_`, `({x}, _)`, and leave it out of the body: `{hint}`"),
            );
        }
    }
    if !array {
        return;
    }
    match body.stmts.last() {
        Some(syn::Stmt::Expr(e, None)) => match paren_less(e) {
            syn::Expr::Array(a) => {
                if let Some(k) = k {
                    if a.elems.len() != k {
                        errors.at(
                            a,
                            format!(
                                "`fn constraints` returns {k} constraint{} (`[Scalar; {k}]`), and this array has {} entr{}: one entry g(q, t) per constraint",
                                if k == 1 { "" } else { "s" },
                                a.elems.len(),
                                if a.elems.len() == 1 { "y" } else { "ies" },
                            ),
                        );
                    }
                }
            }
            other => errors.at(
                other,
                format!("the body of `fn constraints` ends in an array literal, one entry g(q, t) per constraint (`[x * x + y * y - self.l * self.l]`): `{hint}`"),
            ),
        },
        _ => errors.push(syn::Error::new(
            body.brace_token.span.close(),
            format!("the body of `fn constraints` ends in an array literal, one entry g(q, t) per constraint, without a semicolon (`[x * x + y * y - self.l * self.l]`): `{hint}`"),
        )),
    }
}

/// Whether `name` appears among the tokens of a macro invocation in `body` (opaque tokens: any
/// mention counts).
fn mentioned_in_macro(body: &syn::Block, name: &str) -> bool {
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

fn paren_less(e: &syn::Expr) -> &syn::Expr {
    match e {
        syn::Expr::Paren(p) => paren_less(&p.expr),
        syn::Expr::Group(g) => paren_less(&g.expr),
        _ => e,
    }
}

/// `(a, b)` where each is a plain name or `_` (also `_` for the whole pair).
fn binding_pattern(pat: &Pat) -> Option<(Option<proc_macro2::Ident>, Option<proc_macro2::Ident>)> {
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
fn free_use(body: &syn::Block, name: &str) -> Option<proc_macro2::Ident> {
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

/// The names a function's parameters bind, to report one bound twice.
#[derive(Default)]
struct Names(HashMap<String, Span>);

impl Names {
    /// Records `ident`; `false` (with an error at it) if `fn func` binds it already.
    fn bind(&mut self, ident: &proc_macro2::Ident, func: &str, errors: &mut Errors) -> bool {
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
