//! The functions next to `fn lagrangian`: `fn dissipation`, `fn forces` and `fn constraints`,
//! their parameters (lagrangian's coordinates) and return types.

#[allow(unused_imports)]
use super::*;

/// The rule for the parameters of `fn dissipation` and `fn forces`, quoted by every error about
/// them.
pub(super) const EXTRA_RULE: &str = "the coordinate parameters of `dissipation` and `forces` are `lagrangian`'s, all of them, in the same order and of the same kinds (`Coord`, `Coord3`, `Coords<K>`); any binding may be `_` (`(x, _)`, `(_, _)`) and names may differ; `t: Time` is optional in each";

/// The rule for the parameters of `fn constraints`, quoted by every error about them.
pub(super) const CONSTRAINTS_RULE: &str = "the coordinate parameters of `constraints` are `lagrangian`'s, all of them, in the same order and of the same kinds (`Coord`, `Coord3`, `Coords<K>`); any binding may be `_` and names may differ; the constraints g(q, t) = 0 depend on the positions only, so bind each velocity as `_` (`(x, _): Coord`); `t: Time` is optional, for a moving constraint";

/// The rule for the parameters of `fn contacts`, quoted by every error about them.
pub(super) const CONTACTS_RULE: &str = "the coordinate parameters of `contacts` are `lagrangian`'s, all of them, in the same order and of the same kinds (`Coord`, `Coord3`, `Coords<K>`); any binding may be `_` and names may differ; a contact's gap g(q, t) ≥ 0 (and a sticking contact's tangential coordinate) depend on the positions only, so bind each velocity as `_` (`(x, _): Coord`); `t: Time` is optional, for a moving surface";

/// The rule for the parameters of `fn velocity_constraints`, quoted by every error about them.
pub(super) const VELOCITY_RULE: &str = "the coordinate parameters of `velocity_constraints` are `lagrangian`'s, all of them, in the same order and of the same kinds (`Coord`, `Coord3`, `Coords<K>`); any binding may be `_` and names may differ; each entry c(q, q̇, t) = A(q, t) q̇ + b(q, t) is affine in the velocities; `t: Time` is optional";

/// The rule for the parameters of `fn scene`, quoted by every error about them.
pub(super) const SCENE_RULE: &str = "the coordinate parameters of `scene` are `lagrangian`'s, all of them, in the same order and of the same kinds (`Coord`, `Coord3`, `Coords<K>`); any binding may be `_` and names may differ; a scene places shapes from the positions only, so bind each velocity as `_` (`(x, _): Coord`); `t: Time` is optional";

/// The parameter rule quoted for `kind`.
pub(super) fn extra_rule(kind: FuncKind) -> &'static str {
    match kind {
        FuncKind::Dissipation | FuncKind::Forces => EXTRA_RULE,
        FuncKind::Constraints => CONSTRAINTS_RULE,
        FuncKind::Contacts => CONTACTS_RULE,
        FuncKind::VelocityConstraints => VELOCITY_RULE,
        FuncKind::Scene => SCENE_RULE,
    }
}

/// The signature `fn dissipation`, `fn forces` or `fn constraints` should have, from
/// `lagrangian`'s coordinates (`k`: the number of constraints, if known).
pub(super) fn extra_hint(
    kind: FuncKind,
    coords: &[CoordParam],
    time: bool,
    k: Option<usize>,
) -> String {
    let mut params: Vec<String> = coords
        .iter()
        .map(|c| {
            let ty = c.kind.type_name();
            if kind.positions_only() {
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
        FuncKind::Contacts => match k {
            Some(k) => format!("[Contact; {k}]"),
            None => "[Contact; K]".to_owned(),
        },
        FuncKind::VelocityConstraints => match k {
            Some(k) => format!("[Scalar; {k}]"),
            None => "[Scalar; K]".to_owned(),
        },
        FuncKind::Scene => "Scene".to_owned(),
    };
    format!(
        "fn {}(&self, {}) -> {ret}",
        kind.user_name(),
        params.join(", ")
    )
}

/// How many coordinate slots the coordinates declare, spelled out for an error message.
pub(super) fn slots_text(coords: &[CoordParam]) -> String {
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
pub(super) fn check_extra(
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
    let declared_k = declared_count(kind, &sig.output)
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
        (ReturnType::Type(_, ty), FuncKind::VelocityConstraints) => {
            match constraint_count(&sig.output) {
                Some(Ok(k)) if k >= 1 => {}
                Some(Ok(_)) => fail(
                    errors,
                    ty,
                    format!("`fn velocity_constraints` returns at least one constraint: write `[Scalar; 1]` or more, one entry A(q, t) q̇ + b(q, t) per constraint: `{hint}`"),
                ),
                Some(Err(len)) => fail(
                    errors,
                    len,
                    format!("the length of the array `fn velocity_constraints` returns, K, is written as a number (how many velocity constraints there are): `{hint}`"),
                ),
                None => fail(
                    errors,
                    ty,
                    format!("`fn velocity_constraints` returns an array of velocity constraints c(q, q̇, t) = A(q, t) q̇ + b(q, t), one entry per constraint, each zero on the constrained motion: write `-> [Scalar; K]`: `{hint}`"),
                ),
            }
            ty.span()
        }
        (ReturnType::Type(_, ty), FuncKind::Contacts) => {
            match contact_count(&sig.output) {
                Some(Ok(k)) if k >= 1 => {}
                Some(Ok(_)) => fail(
                    errors,
                    ty,
                    format!("`fn contacts` returns at least one contact: write `[Contact; 1]` or more, one entry per contact (`Contact::gap(y).restitution(self.e)`): `{hint}`"),
                ),
                Some(Err(len)) => fail(
                    errors,
                    len,
                    format!("the length of the array `fn contacts` returns, K, is written as a number (how many contacts there are): `{hint}`"),
                ),
                None => fail(
                    errors,
                    ty,
                    format!("`fn contacts` returns an array of contacts, one entry per contact, each made from its gap g(q, t) ≥ 0 (`Contact::gap(y).restitution(self.e)`, `.sticking(x)` for a contact point that does not slide): write `-> [Contact; K]` with K the number of contacts: `{hint}`"),
                ),
            }
            ty.span()
        }
        (ReturnType::Type(_, ty), FuncKind::Scene) => {
            if !is_ident_type(ty, "Scene") {
                fail(
                    errors,
                    ty,
                    format!("`fn scene` returns a `Scene`: the shapes placed in space at a state (`Scene::new().sphere(\"bob\", p, 0.1, Rgb::RED)`); write `-> Scene`: `{hint}`"),
                );
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
                let msg = if kind.positions_only() {
                    if kind == FuncKind::Scene {
                        format!("`{cand}` is used in `fn scene`, which has no `{cand}: Time` parameter: a scene that moves with the time declares it, so add `{cand}: Time` to its parameters: `{with_time}`")
                    } else {
                        format!("`{cand}` is used in `fn {name}`, which has no `{cand}: Time` parameter: a moving (rheonomic) {} g(q, t) declares the time, so add `{cand}: Time` to its parameters: `{with_time}`", if kind == FuncKind::Contacts { "contact" } else { "constraint" })
                    }
                } else {
                    format!("`{cand}` is used in `fn {name}`, which has no `{cand}: Time` parameter: add `{cand}: Time` to its parameters (`t: Time` is optional in each of `lagrangian`, `dissipation` and `forces`, and each one whose body uses the time declares it): `{with_time}`")
                };
                fail(errors, &at, msg);
                break;
            }
        }
    }
    if kind.positions_only() {
        // The tail is checked against an array return type only (for another, the error at the
        // return type says it all).
        let array = declared_count(kind, &sig.output).is_some();
        check_constraints_body(
            kind,
            &func.block,
            &bindings,
            declared_k,
            array,
            &hint,
            errors,
        );
    }
    let mut affine = false;
    if kind == FuncKind::VelocityConstraints && declared_count(kind, &sig.output).is_some() {
        affine = check_velocity_body(
            &func.block,
            &bindings,
            time.as_ref(),
            declared_k,
            &hint,
            errors,
        );
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
        affine,
    })
}

/// K of a return type `[Scalar; K]`: `Some(Ok(K))` for an integer literal, `Some(Err(len))` for
/// any other length expression, `None` when it is not an array of `Scalar`.
pub fn constraint_count(output: &ReturnType) -> Option<Result<usize, &syn::Expr>> {
    array_count(output, "Scalar")
}

/// K of a return type `[Contact; K]`, as [`constraint_count`] reads `[Scalar; K]`.
pub fn contact_count(output: &ReturnType) -> Option<Result<usize, &syn::Expr>> {
    array_count(output, "Contact")
}

/// K of the array `kind` returns (`fn constraints` or `fn contacts`).
fn declared_count(kind: FuncKind, output: &ReturnType) -> Option<Result<usize, &syn::Expr>> {
    match kind {
        FuncKind::Contacts => contact_count(output),
        FuncKind::Scene => None,
        _ => constraint_count(output),
    }
}

/// K of a return type `[elem; K]`.
fn array_count<'a>(output: &'a ReturnType, elem: &str) -> Option<Result<usize, &'a syn::Expr>> {
    let ReturnType::Type(_, ty) = output else {
        return None;
    };
    let mut ty = &**ty;
    while let Type::Group(g) = ty {
        ty = &g.elem;
    }
    match ty {
        Type::Array(a) if is_ident_type(&a.elem, elem) => match &a.len {
            syn::Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Int(len),
                ..
            }) => Some(len.base10_parse::<usize>().map_err(|_| &a.len)),
            other => Some(Err(other)),
        },
        _ => None,
    }
}

/// The rules of the body of `fn constraints` (and `fn contacts`): no velocity it binds is used
/// (the constraints depend on the positions and the time only), and it ends in an array literal
/// of K entries.
pub(super) fn check_constraints_body(
    kind: FuncKind,
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
            if kind == FuncKind::Scene {
                errors.at(
                    &at,
                    format!("`{velocity}` is a velocity, and `fn scene` places shapes from the positions (and `t: Time`) only: the animation poses them at each state's positions, and a velocity has no place in space. If `{velocity}` is here by mistake, bind it as `_`, `({x}, _)`: `{hint}`"),
                );
                continue;
            }
            if kind == FuncKind::Contacts {
                errors.at(
                    &at,
                    format!("`{velocity}` is a velocity, and `fn contacts` declares gaps g(q, t) ≥ 0 (and the tangential coordinates of sticking contacts), which depend on the positions (and, for a moving surface, on `t: Time`) only; the impact law takes the velocities from the motion. If `{velocity}` is here by mistake, bind it as `_`, `({x}, _)`: `{hint}`"),
                );
                continue;
            }
            errors.at(
                &at,
                format!("`{velocity}` is a velocity, and `fn constraints` declares holonomic constraints g(q, t) = 0, which depend on the positions (and, for a moving constraint, on `t: Time`) only. A constraint on the velocities (rolling without slipping, a knife edge: A(q) q̇ + b = 0) is nonholonomic: declare it in `fn velocity_constraints` (its parameters bind the velocities); leaving the velocity out would change the physics. If `{velocity}` is here by mistake, bind it as `_`, `({x}, _)`: `{hint}`"),
            );
        }
    }
    if !array {
        return;
    }
    let (what, ty, example) = match kind {
        FuncKind::Contacts => (
            "contact",
            "Contact",
            "`[Contact::gap(y).restitution(self.e)]`",
        ),
        _ => (
            "constraint",
            "Scalar",
            "`[x * x + y * y - self.l * self.l]`",
        ),
    };
    let entry = if kind == FuncKind::Contacts {
        ""
    } else {
        "g(q, t) "
    };
    match body.stmts.last() {
        Some(syn::Stmt::Expr(e, None)) => match paren_less(e) {
            syn::Expr::Array(a) => {
                if let Some(k) = k {
                    if a.elems.len() != k {
                        errors.at(
                            a,
                            format!(
                                "`fn {}` returns {k} {what}{} (`[{ty}; {k}]`), and this array has {} entr{}: one entry {entry}per {what}",
                                kind.user_name(),
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
                format!("the body of `fn {}` ends in an array literal, one entry {entry}per {what} ({example}): `{hint}`", kind.user_name()),
            ),
        },
        _ => errors.push(syn::Error::new(
            body.brace_token.span.close(),
            format!("the body of `fn {}` ends in an array literal, one entry {entry}per {what}, without a semicolon ({example}): `{hint}`", kind.user_name()),
        )),
    }
}

/// The rules of the body of `fn velocity_constraints`: it ends in an array literal of K entries,
/// each affine in the velocities and depending on them (an entry free of velocities is a
/// holonomic constraint). Returns whether some entry has a velocity-free term b(q, t) (or the
/// body uses the time).
pub(super) fn check_velocity_body(
    body: &syn::Block,
    bindings: &[(Option<proc_macro2::Ident>, Option<proc_macro2::Ident>)],
    time: Option<&proc_macro2::Ident>,
    k: Option<usize>,
    hint: &str,
    errors: &mut Errors,
) -> bool {
    use super::linear::{Form, Scope};
    const EXAMPLE: &str = "`[x_dot - self.r * psi_dot * phi.cos()]`";
    let velocities = bindings
        .iter()
        .filter_map(|(_, v)| v.as_ref().map(crate::model::unraw));
    let mut scope = Scope::new(velocities, time.map(crate::model::unraw));
    let Some((last, before)) = body.stmts.split_last() else {
        errors.push(syn::Error::new(
            body.brace_token.span.close(),
            format!("the body of `fn velocity_constraints` ends in an array literal, one entry A(q, t) q̇ + b(q, t) per constraint ({EXAMPLE}): `{hint}`"),
        ));
        return false;
    };
    for stmt in before {
        if let Err((span, msg)) = scope.statement(stmt) {
            errors.push(syn::Error::new(span, msg));
            return false;
        }
    }
    let tail = match last {
        syn::Stmt::Expr(e, None) => paren_less(e),
        _ => {
            errors.push(syn::Error::new(
                body.brace_token.span.close(),
                format!("the body of `fn velocity_constraints` ends in an array literal, one entry per constraint, without a semicolon ({EXAMPLE}): `{hint}`"),
            ));
            return false;
        }
    };
    let syn::Expr::Array(a) = tail else {
        errors.at(
            tail,
            format!("the body of `fn velocity_constraints` ends in an array literal, one entry A(q, t) q̇ + b(q, t) per constraint ({EXAMPLE}): `{hint}`"),
        );
        return false;
    };
    if let Some(k) = k {
        if a.elems.len() != k {
            errors.at(
                a,
                format!(
                    "`fn velocity_constraints` returns {k} constraint{} (`[Scalar; {k}]`), and this array has {} entr{}: one entry A(q, t) q̇ + b(q, t) per constraint",
                    if k == 1 { "" } else { "s" },
                    a.elems.len(),
                    if a.elems.len() == 1 { "y" } else { "ies" },
                ),
            );
        }
    }
    let mut affine = false;
    for entry in &a.elems {
        match scope.expr(entry) {
            Ok(Form::Free) => errors.at(
                entry,
                "this velocity constraint does not depend on the velocities: it is a condition on the positions, g(q, t) = 0, a holonomic constraint; declare it in `fn constraints` (a velocity constraint is A(q, t) q̇ + b(q, t) = 0: rolling without slipping, a knife edge)",
            ),
            Ok(Form::Linear) => {}
            Ok(Form::Affine) => affine = true,
            Err((span, msg)) => errors.push(syn::Error::new(
                span,
                format!("{msg}: a velocity constraint is affine in the velocities, A(q, t) q̇ + b(q, t) = 0 (Lagrange–d'Alembert takes no other): `{hint}`"),
            )),
        }
    }
    affine || time.is_some_and(|t| free_use(body, &crate::model::unraw(t)).is_some())
}
