//! The driver: parse → validate → the front end (`front/`: the bodies resolved once) → the flags
//! (`analyze.rs`) and the jets back end (`jets/`) → the symbolic back end → emit, with one error
//! sink shared by every stage.

use proc_macro2::TokenStream;

use crate::errors::Errors;
use crate::model::{FuncKind, Mode};
use crate::{analyze, emit, front, jets, parse, symbolic, validate};

/// The whole macro, from the attribute's arguments and the annotated item to the output.
pub fn expand(args: TokenStream, input: TokenStream) -> TokenStream {
    let mut errors = Errors::default();
    let options = parse::options(args, &mut errors);
    let split = match parse::split(input.clone()) {
        Ok(s) => s,
        Err(e) => {
            errors.push(e);
            return emit::unparsed(&errors, input);
        }
    };
    let fallback = emit::Fallback::of(&split);
    let decl = match validate::validate(split, options, &mut errors) {
        Some(decl) if errors.is_empty() => decl,
        _ => return emit::stub(&errors, &fallback),
    };
    // A rate in `fn constraints` would be a velocity constraint (nonholonomic).
    if let Some(f) = &decl.constraints {
        if let Some(at) = crate::front::timed::reads_rates(&f.body, &decl.rest) {
            errors.push(syn::Error::new(
                at,
                "a velocity in `fn constraints`: `fn constraints` declares holonomic constraints \
                 g(q, t) = 0, written from the positions (and `t: Time`) only; a constraint on \
                 velocities (rolling without slipping, a knife edge: A(q) q̇ + b = 0) is \
                 nonholonomic: declare it in `fn velocity_constraints`, which may use `velocity` \
                 and the angular velocities",
            ));
            return emit::stub(&errors, &fallback);
        }
    }
    // A rate in `fn contacts`: gaps are functions of the positions.
    if let Some(f) = &decl.contacts {
        if let Some(at) = crate::front::timed::reads_rates(&f.body, &decl.rest) {
            errors.push(syn::Error::new(
                at,
                "a velocity in `fn contacts`: a contact's gap g(q, t) ≥ 0 (and a sticking \
                 contact's tangential coordinate) is written from the positions (and `t: Time`) \
                 only; the impact law takes the velocities from the motion. Write the gap without \
                 `velocity` or an angular velocity",
            ));
            return emit::stub(&errors, &fallback);
        }
    }
    // A rate in `fn scene`: shapes are placed from the positions.
    if let Some(f) = &decl.scene {
        if let Some(at) = crate::front::timed::reads_rates(&f.body, &decl.rest) {
            errors.push(syn::Error::new(
                at,
                "a velocity in `fn scene`: a scene places shapes from the positions (and \
                 `t: Time`) only, and the animation poses them at each state's positions; write \
                 the shapes' places without `velocity` or an angular velocity",
            ));
            return emit::stub(&errors, &fallback);
        }
    }
    let front = front::Front::of(&decl);
    let mut analysis = analyze::analyze(&decl, &front);
    let callables = &front.callables;
    let body = jets::body(&front.lagrangian, callables, &mut errors);
    let rest = jets::lower_helpers_for_jets(&decl.rest, callables, &mut errors);
    let mut jet_body = |kind| {
        front
            .func(kind)
            .map(|b| jets::body(b, callables, &mut errors))
    };
    // `fn dissipation` and `fn forces`, those present, in that order.
    let funcs: Vec<syn::Block> = [FuncKind::Dissipation, FuncKind::Forces]
        .into_iter()
        .filter_map(&mut jet_body)
        .collect();
    // `fn constraints`, `fn velocity_constraints` and `fn contacts`, in both modes the body
    // rewritten generically over the scalar type (the runtime's jets give G and the second
    // derivatives along the motion).
    let constraints = jet_body(FuncKind::Constraints);
    let velocity = jet_body(FuncKind::VelocityConstraints);
    let contacts = jet_body(FuncKind::Contacts);
    // `x ^ 2`, `2 * x`: said in the user's terms, and nothing emitted that rustc would report
    // again in the runtime's.
    if !errors.is_empty() {
        return emit::stub(&errors, &fallback);
    }
    let symbolic = match decl.options.mode {
        Mode::Jets => None,
        Mode::Symbolic => symbolic::expand(&decl, &front, &mut errors),
    };
    // With errors from the symbolic stage the impl is still emitted (with the jets `fn
    // lagrangian` and without the symbolic methods), next to the errors: see `emit::generate`.
    let symbolic = symbolic.filter(|_| errors.is_empty());
    if let Some(s) = &symbolic {
        analysis.refine(&s.symmetry);
    }
    analysis.constrain();
    let jets = emit::JetsBodies {
        rest,
        body,
        funcs,
        constraints,
        contacts,
        velocity,
    };
    emit::generate(&decl, &front, &analysis, &jets, symbolic.as_ref(), &errors)
}
