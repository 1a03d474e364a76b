//! Emit: the `impl Lagrangian<N>` (or, while errors exist, the errors and a stub impl). Only
//! emission: the driver (`expand.rs`) runs the stages and hands their results here.

use std::collections::HashSet;

use proc_macro2::{Ident, TokenStream};
use quote::{quote, quote_spanned};

use crate::analyze::Analysis;
use crate::errors::Errors;
use crate::front::Front;
use crate::model::{unraw, CoordKind, Decl, Func, FuncKind};
use crate::symbolic::SymbolicOutput;
use crate::{parse, validate};

/// The flags and the front end's bodies, for the emitters.
struct Facts<'a> {
    analysis: &'a Analysis,
    front: &'a Front<'a>,
}

impl std::ops::Deref for Facts<'_> {
    type Target = Analysis;
    fn deref(&self) -> &Analysis {
        self.analysis
    }
}

impl Facts<'_> {
    /// The names the body of `f` mentions (the front end's: what its generated method binds).
    fn func_used(&self, f: &Func) -> HashSet<String> {
        self.front
            .func(f.kind)
            .map(|b| b.used.clone())
            .unwrap_or_default()
    }
}

/// The errors and the item as written, when it is not even an impl block.
pub fn unparsed(errors: &Errors, input: TokenStream) -> TokenStream {
    let errs = errors.to_compile_errors();
    quote!(#errs #input)
}

/// What is emitted in place of the impl while parse or validation errors exist.
pub struct Fallback {
    /// The impl block without `fn lagrangian`, `fn dissipation`, `fn forces` and any function that uses the macro's
    /// own vocabulary (`Coord`, `Scalar`), so the user sees our errors and not cascades.
    rest: syn::ItemImpl,
    /// How many coordinate slots the (first) `fn lagrangian` declares, at least 1.
    n_hint: usize,
    /// K of the (first) `fn constraints`, when its return type says it (`[Scalar; K]`, K ≥ 1):
    /// the stub then implements `Holonomic<N, K>` too.
    k_hint: Option<usize>,
    /// K of the (first) `fn contacts`, when its return type says it (`[Contact; K]`, K ≥ 1):
    /// the stub then implements `Unilateral<N, K>` too.
    contacts_hint: Option<usize>,
    /// K of the (first) `fn velocity_constraints`, when its return type says it: the stub then
    /// implements `Nonholonomic<N, K>`, and `Holonomic` with these rows added.
    velocity_hint: Option<usize>,
    /// Whether the impl block has a `fn scene`: the stub then implements `Visual<N>`.
    scene: bool,
}

impl Fallback {
    /// The fallback of a split impl block, taken before validation consumes it.
    pub fn of(split: &parse::Split) -> Fallback {
        let mut rest = split.rest.clone();
        rest.items.retain(|item| !matches!(item, syn::ImplItem::Fn(f) if f.sig.inputs.iter().any(validate::is_coordinate_param) || crate::model::is_helper(f)));
        let n_hint = split
            .funcs
            .first()
            .map(count_coordinate_params)
            .unwrap_or(1)
            .max(1);
        let k_hint = split
            .constraints
            .first()
            .and_then(|f| validate::constraint_count(&f.sig.output))
            .and_then(Result::ok)
            .filter(|k| *k >= 1);
        let contacts_hint = split
            .contacts
            .first()
            .and_then(|f| validate::contact_count(&f.sig.output))
            .and_then(Result::ok)
            .filter(|k| *k >= 1);
        let velocity_hint = split
            .velocity_constraints
            .first()
            .and_then(|f| validate::constraint_count(&f.sig.output))
            .and_then(Result::ok)
            .filter(|k| *k >= 1);
        Fallback {
            rest,
            n_hint,
            k_hint,
            contacts_hint,
            velocity_hint,
            scene: !split.scene.is_empty(),
        }
    }
}

/// The errors, the rest of the impl block and a stub `impl Lagrangian`.
pub fn stub(errors: &Errors, fallback: &Fallback) -> TokenStream {
    let errs = errors.to_compile_errors();
    let rest = &fallback.rest;
    let stub = stub_impl(rest, fallback);
    quote!(#errs #rest #stub)
}

/// The bodies lowered for jets (emitted in both modes): the rest of the impl block (its helper
/// methods made generic), `fn lagrangian`'s body, those of `decl.funcs()` in that order, and
/// `fn constraints`'s.
pub struct JetsBodies {
    pub rest: syn::ItemImpl,
    pub body: syn::Block,
    pub funcs: Vec<syn::Block>,
    pub constraints: Option<syn::Block>,
    pub contacts: Option<syn::Block>,
    pub velocity: Option<syn::Block>,
}

/// The `impl Lagrangian<N>`: the jets `fn lagrangian` (its body `body`, lowered for jets), the
/// generic `fn dissipation` / `fn generalized_forces` (the bodies `funcs` of `decl.funcs()`,
/// lowered for jets, in that order), and,
/// given `symbolic`, the symbolic methods and the `EQUATIONS` consts; `errors` (from the
/// symbolic stage) go after the impl, which then has only the generic methods, so rustc still
/// type-checks the bodies as written (a genuine type error there is reported at the user's token
/// too, and nothing cascades; the build fails either way: no silent fallback).
pub fn generate(
    decl: &Decl,
    front: &Front<'_>,
    analysis: &Analysis,
    jets: &JetsBodies,
    symbolic: Option<&SymbolicOutput>,
    errors: &Errors,
) -> TokenStream {
    let analysis = &Facts { analysis, front };
    let JetsBodies {
        rest,
        body,
        funcs,
        constraints,
        contacts,
        velocity,
    } = jets;
    let constraints = constraints.as_ref();
    let n = decl.n();
    let self_ty = &decl.rest.self_ty;
    let names = decl.coordinate_names();
    let cyclic = &analysis.cyclic;
    let autonomous = analysis.autonomous;

    // Bindings of the user's names to the jets' slots; names the body never mentions are not
    // bound (no unused-variable warnings for cyclic coordinates).
    let params = crate::names::Params::jets();
    let coords: Vec<(Option<&Ident>, Option<&Ident>)> = decl
        .coords
        .iter()
        .map(|c| (Some(&c.name), Some(&c.dot)))
        .collect();
    let (bindings, [q_pat, qdot_pat, t_pat]) = bind_slots(
        decl,
        &coords,
        decl.time.as_ref(),
        &analysis.front.lagrangian.used,
        &params,
    );
    let stmts = &body.stmts;
    let fn_attrs = &decl.fn_attrs;
    let ret = quote_spanned!(decl.ret_span=> Scalar);
    let fn_ident = &decl.fn_ident;
    let self_token = &decl.self_token;
    let constrained = decl.constraints.is_some() || decl.velocity_constraints.is_some();
    let (symbolic_methods, symbolic_consts) = match symbolic {
        Some(out) => crate::symbolic::methods(
            out,
            n,
            self_ty,
            &constraint_terms(decl, analysis),
            &decl.coordinate_names(),
        ),
        // The jets mode compiles nothing of its own; a constrained system says so (its
        // `linearize` refuses).
        None if constrained => (
            quote! {
                const COMPILED: ::lagrange::__private::Compiled = ::lagrange::__private::Compiled {
                    constrained: true,
                    ..::lagrange::__private::Compiled::NONE
                };
            },
            errors.to_compile_errors(),
        ),
        None => (quote!(), errors.to_compile_errors()),
    };

    // A body that reads rates (`velocity`, angular velocities) is evaluated in `Timed` numbers:
    // the trait method lifts the state and calls a hidden inherent method holding the body.
    let mut timed_methods: Vec<TokenStream> = Vec::new();
    let lagrangian_method = {
        let generics = quote!(<Scalar: ::lagrange::__private::Scalar>);
        let n = proc_macro2::Literal::usize_unsuffixed(n);
        let params = quote! {
            #q_pat: &[Scalar; #n],
            #qdot_pat: &[Scalar; #n],
            #t_pat: Scalar,
        };
        let body = quote! {
            #(#bindings)*
            #(#stmts)*
        };
        if crate::front::timed::reads_rates(&decl.body, &decl.rest).is_some() {
            let hidden = crate::names::timed(fn_ident);
            timed_methods.push(quote! {
                #[doc(hidden)]
                #[inline]
                fn #hidden #generics(&#self_token, #params) -> #ret { #body }
            });
            let wrapper = timed_wrapper(fn_ident, &ret, &hidden, decl.n(), quote!(.untimed()));
            quote! {
                #(#fn_attrs)*
                #wrapper
            }
        } else {
            quote! {
                #(#fn_attrs)*
                #[inline]
                fn #fn_ident #generics(&#self_token, #params) -> #ret { #body }
            }
        }
    };
    let extras: Vec<TokenStream> = decl
        .funcs()
        .zip(funcs)
        .map(|(f, body)| jets_func(decl, analysis, f, body, &mut timed_methods, None))
        .collect();
    // The flags that differ from their defaults only with forces, dissipation or a moving
    // constraint.
    let conserved = if decl.dissipation.is_some() || decl.forces.is_some() || !analysis.scleronomic
    {
        let m = &analysis.momentum_conserved;
        let e = analysis.energy_conserved;
        quote! {
            const MOMENTUM_CONSERVED: [bool; #n] = [#(#m),*];
            const ENERGY_CONSERVED: bool = #e;
        }
    } else {
        quote!()
    };

    let holonomic = match (&decl.velocity_constraints, velocity, &decl.constraints) {
        (Some(fv), Some(vbody), holo) => constrained_impl(
            decl,
            analysis,
            holo.as_ref().zip(constraints),
            (fv, vbody),
            &mut timed_methods,
        ),
        (_, _, Some(f)) => match constraints {
            Some(body) => holonomic_impl(decl, analysis, f, body),
            None => quote!(),
        },
        _ => quote!(),
    };
    let unilateral = match (&decl.contacts, contacts) {
        (Some(f), Some(body)) => unilateral_impl(decl, analysis, f, body),
        _ => quote!(),
    };
    let visual = match &decl.scene {
        Some(f) => visual_impl(decl, analysis, f),
        None => quote!(),
    };

    let n = proc_macro2::Literal::usize_unsuffixed(n);
    let allow = crate::names::allow_generated();
    let timed_impl = if timed_methods.is_empty() {
        quote!()
    } else {
        let (impl_generics, _, where_clause) = decl.rest.generics.split_for_impl();
        quote! {
            #[automatically_derived]
            #allow
            impl #impl_generics #self_ty #where_clause {
                #(#timed_methods)*
            }
        }
    };
    // The rest of the user's impl block, unless it was only the Lagrangian.
    let rest = if rest.items.is_empty() && rest.attrs.is_empty() {
        quote!()
    } else {
        quote!(#rest)
    };
    // A run takes what the system declares (`Simulation::new` hands the run to this method):
    // its K constraints (holonomic, then velocity rows) or its K contacts.
    let lit = proc_macro2::Literal::usize_unsuffixed;
    let declared_run = |visit: TokenStream| {
        quote! {
            #[inline]
            fn declared<'__lagrange_s, __LagrangeV>(&'__lagrange_s self, v: __LagrangeV) -> __LagrangeV::Output
            where
                __LagrangeV: ::lagrange::__private::Declared<'__lagrange_s, Self, #n>,
            {
                #visit
            }
        }
    };
    let declares_contacts = match (
        &decl.contacts,
        &decl.constraints,
        &decl.velocity_constraints,
    ) {
        (Some(f), _, _) => {
            let k = lit(f.k);
            let method = declared_run(quote!(v.contacts::<#k>(self)));
            quote! {
                const DECLARES_CONTACTS: bool = true;
                #method
            }
        }
        (None, holo, vel) if holo.is_some() || vel.is_some() => {
            let k = lit(holo.as_ref().map_or(0, |f| f.k) + vel.as_ref().map_or(0, |f| f.k));
            declared_run(quote!(v.constrained::<#k>(self)))
        }
        _ => quote!(),
    };
    quote! {
        #rest

        #[automatically_derived]
        #allow
        impl ::lagrange::__private::Lagrangian<#n> for #self_ty {
            const COORDINATES: [&'static str; #n] = [#(#names),*];
            const CYCLIC: [bool; #n] = [#(#cyclic),*];
            const AUTONOMOUS: bool = #autonomous;
            #conserved
            #declares_contacts

            #lagrangian_method
            #(#extras)*
            #symbolic_methods
        }
        #timed_impl
        #holonomic
        #unilateral
        #visual
        #symbolic_consts
    }
}

/// The constraint forces' terms and the constraints the printed equations of a constrained
/// system show: which slots the constraints read (positions for `fn constraints`, velocities
/// for `fn velocity_constraints`) and their entries as written.
fn constraint_terms(decl: &Decl, analysis: &Facts<'_>) -> crate::symbolic::ConstraintTerms {
    let reads = |kind, seed| {
        analysis
            .front
            .func(kind)
            .is_some_and(|b: &crate::front::Body<'_>| b.reads(seed))
    };
    let per_slot = |kind, seed: fn(usize) -> crate::front::Seed| -> Vec<bool> {
        decl.coords
            .iter()
            .enumerate()
            .flat_map(|(p, c)| std::iter::repeat_n(reads(kind, seed(p)), c.width()))
            .collect()
    };
    let entries = |f: &Option<Func>| f.as_ref().map(|f| written_entries(&f.body));
    crate::symbolic::ConstraintTerms {
        holonomic: per_slot(FuncKind::Constraints, crate::front::Seed::Coord),
        velocity: per_slot(FuncKind::VelocityConstraints, crate::front::Seed::Velocity),
        g: entries(&decl.constraints),
        c: entries(&decl.velocity_constraints),
    }
}

/// The entries of the array a constraint function returns, as written (`self.` left out); the
/// function's name where its body is more than that array.
fn written_entries(body: &syn::Block) -> Vec<String> {
    let tidy = |s: String| {
        s.replace(" . ", ".")
            .replace("self.", "")
            .replace(" (", "(")
            .replace("( ", "(")
            .replace(" )", ")")
            .replace(" ,", ",")
    };
    match crate::analyze::tail_array(body) {
        Some(elems) if body.stmts.len() == 1 => {
            elems.iter().map(|e| tidy(quote!(#e).to_string())).collect()
        }
        _ => vec!["… as the function computes it".to_owned()],
    }
}

/// The trait method `ident` (returning `ret`) that evaluates the hidden method `hidden`, which
/// holds the user's body, in `Timed` numbers: the state lifted (q moving at q̇, t at rate 1), the
/// call, and `finish` turning the result back into the number type.
fn timed_wrapper(
    ident: &Ident,
    ret: &TokenStream,
    hidden: &Ident,
    n: usize,
    finish: TokenStream,
) -> TokenStream {
    let crate::names::Params { q, qdot, t } = crate::names::Params::jets();
    let n = proc_macro2::Literal::usize_unsuffixed(n);
    quote! {
        #[inline]
        fn #ident<Scalar: ::lagrange::__private::Scalar>(
            &self,
            #q: &[Scalar; #n],
            #qdot: &[Scalar; #n],
            #t: Scalar,
        ) -> #ret {
            let (#q, #qdot, #t) = ::lagrange::__private::timed_state(#q, #qdot, #t);
            Self::#hidden::<::lagrange::__private::Timed<Scalar>>(self, &#q, &#qdot, #t) #finish
        }
    }
}

/// `impl Holonomic<N, K>` from `fn constraints` (its body `body`, lowered for jets): the flags
/// CONSTRAINED_COORDINATES and SCLERONOMIC from the analysis, and the generic `fn constraints`.
fn holonomic_impl(decl: &Decl, analysis: &Facts<'_>, f: &Func, body: &syn::Block) -> TokenStream {
    let self_ty = &decl.rest.self_ty;
    let n = proc_macro2::Literal::usize_unsuffixed(decl.n());
    let k = proc_macro2::Literal::usize_unsuffixed(f.k);
    let constrained = &analysis.constrained;
    let scleronomic = analysis.scleronomic;
    let method = jets_func(decl, analysis, f, body, &mut Vec::new(), None);
    let allow = crate::names::allow_generated();
    quote! {
        #[automatically_derived]
        #allow
        impl ::lagrange::__private::Holonomic<#n, #k> for #self_ty {
            const CONSTRAINED_COORDINATES: [bool; #n] = [#(#constrained),*];
            const SCLERONOMIC: bool = #scleronomic;
            #method
        }
    }
}

/// `impl Nonholonomic<N, KV>` from `fn velocity_constraints`, and `impl Holonomic<N, KH + KV>`
/// holding the holonomic constraints of `fn constraints` (if any, KH of them) followed by the
/// velocity constraints' rows (`VELOCITY_ROWS = KV`), so `Simulation::constrained` runs both.
fn constrained_impl(
    decl: &Decl,
    analysis: &Facts<'_>,
    holonomic: Option<(&Func, &syn::Block)>,
    (fv, vbody): (&Func, &syn::Block),
    timed_methods: &mut Vec<TokenStream>,
) -> TokenStream {
    let self_ty = &decl.rest.self_ty;
    let lit = proc_macro2::Literal::usize_unsuffixed;
    let (kh, kv) = (holonomic.map_or(0, |(f, _)| f.k), fv.k);
    let (n, k, kv_lit) = (lit(decl.n()), lit(kh + kv), lit(kv));
    let constrained = &analysis.constrained;
    let scleronomic = analysis.scleronomic;
    let velocity_method = jets_func(decl, analysis, fv, vbody, timed_methods, None);
    let scalar = quote!(::lagrange::__private::Scalar);
    let allow = crate::names::allow_generated();
    let velocity_values = (0..kv).map(|i| {
        let i = lit(i);
        quote!(__lagrange_c[#i])
    });
    let held_values = (0..kh).map(|i| {
        let i = lit(i);
        quote!(__lagrange_g[#i])
    });
    let values_body = if kh == 0 {
        quote! {
            <Self as ::lagrange::__private::Nonholonomic<#n, #kv_lit>>::velocity_constraints(self, q, qdot, t)
        }
    } else {
        let ident = Ident::new(&crate::names::holonomic(), proc_macro2::Span::call_site());
        quote! {
            let __lagrange_g = self.#ident(q, t);
            let __lagrange_c = <Self as ::lagrange::__private::Nonholonomic<#n, #kv_lit>>::velocity_constraints(self, q, qdot, t);
            [#(#held_values,)* #(#velocity_values),*]
        }
    };
    let (hidden, constraints_body, rows_body) = match holonomic {
        Some((f, body)) => {
            let name = crate::names::holonomic();
            let method = jets_func(decl, analysis, f, body, &mut Vec::new(), Some(&name));
            let ident = Ident::new(&name, proc_macro2::Span::call_site());
            let held = (0..kh).map(|i| {
                let i = lit(i);
                quote!(__lagrange_g[#i])
            });
            let zeros = (0..kv).map(|_| quote!(<S as #scalar>::constant(0.0)));
            (
                quote! {
                    #[automatically_derived]
                    #allow
                    impl #self_ty {
                        #[doc(hidden)]
                        #method
                    }
                },
                quote! {
                    let __lagrange_g = self.#ident(q, t);
                    [#(#held,)* #(#zeros),*]
                },
                quote! {
                    let mut rows = ::lagrange::__private::jet_constraint_rows(self, q, qdot, t);
                    ::lagrange::__private::splice_velocity_rows(
                        &mut rows,
                        &<Self as ::lagrange::__private::Nonholonomic<#n, #kv_lit>>::velocity_constraint_rows(self, q, qdot, t),
                    );
                    rows
                },
            )
        }
        None => (
            quote!(),
            quote! {
                let _ = (q, t);
                [<S as #scalar>::constant(0.0); #k]
            },
            quote! {
                <Self as ::lagrange::__private::Nonholonomic<#n, #kv_lit>>::velocity_constraint_rows(self, q, qdot, t)
            },
        ),
    };
    quote! {
        #hidden
        #[automatically_derived]
        #allow
        impl ::lagrange::__private::Nonholonomic<#n, #kv_lit> for #self_ty {
            #velocity_method
        }
        #[automatically_derived]
        #allow
        impl ::lagrange::__private::Holonomic<#n, #k> for #self_ty {
            const CONSTRAINED_COORDINATES: [bool; #n] = [#(#constrained),*];
            const SCLERONOMIC: bool = #scleronomic;
            const VELOCITY_ROWS: usize = #kv_lit;
            #[inline]
            fn constraints<S: #scalar>(&self, q: &[S; #n], t: S) -> [S; #k] {
                #constraints_body
            }
            #[inline]
            fn constraint_values<S: #scalar>(&self, q: &[S; #n], qdot: &[S; #n], t: S) -> [S; #k] {
                #values_body
            }
            #[inline]
            fn constraint_rows(
                &self,
                q: &[f64; #n],
                qdot: &[f64; #n],
                t: f64,
            ) -> ::lagrange::__private::eom::ConstraintRows<#n, #k> {
                #rows_body
            }
        }
    }
}

/// `impl Unilateral<N, K>` from `fn contacts` (its body `body`, lowered for jets): SCLERONOMIC
/// from the analysis, and the generic `fn contacts`.
fn unilateral_impl(decl: &Decl, analysis: &Facts<'_>, f: &Func, body: &syn::Block) -> TokenStream {
    let self_ty = &decl.rest.self_ty;
    let n = proc_macro2::Literal::usize_unsuffixed(decl.n());
    let k = proc_macro2::Literal::usize_unsuffixed(f.k);
    let method = jets_func(decl, analysis, f, body, &mut Vec::new(), None);
    let allow = crate::names::allow_generated();
    // Constraints next to the contacts hold throughout the run: the view takes their rows
    // from the system's `impl Holonomic` (holonomic rows, then velocity rows).
    let kh = decl.constraints.as_ref().map_or(0, |f| f.k);
    let kv = decl.velocity_constraints.as_ref().map_or(0, |f| f.k);
    let (scleronomic, equalities) = if kh + kv == 0 {
        (analysis.contacts_scleronomic, quote!())
    } else {
        let kc = proc_macro2::Literal::usize_unsuffixed(kh + kv);
        let rows = quote!(::lagrange::__private::EqualityRows);
        let holonomic = quote!(<Self as ::lagrange::__private::Holonomic<#n, #kc>>);
        (
            analysis.contacts_scleronomic && analysis.scleronomic,
            quote! {
                fn equality_rows(&self, q: &[f64; #n], qdot: &[f64; #n], t: f64) -> #rows<#n> {
                    #rows::of(&#holonomic::constraint_rows(self, q, qdot, t), #holonomic::VELOCITY_ROWS)
                }
            },
        )
    };
    quote! {
        #[automatically_derived]
        #allow
        impl ::lagrange::__private::Unilateral<#n, #k> for #self_ty {
            const SCLERONOMIC: bool = #scleronomic;
            #method
            #equalities
        }
    }
}

/// `impl Visual<N>` from `fn scene`: its body as written, evaluated in `f64` (a scene is
/// drawn, not differentiated), the user's names bound to the positions and the time.
fn visual_impl(decl: &Decl, analysis: &Facts<'_>, f: &Func) -> TokenStream {
    let self_ty = &decl.rest.self_ty;
    let params = crate::names::Params::jets();
    let coords: Vec<(Option<&Ident>, Option<&Ident>)> =
        f.bindings.iter().map(|(c, _)| (c.as_ref(), None)).collect();
    let (bindings, [q_pat, _, t_pat]) = bind_slots(
        decl,
        &coords,
        f.time.as_ref(),
        &analysis.func_used(f),
        &params,
    );
    let n = proc_macro2::Literal::usize_unsuffixed(decl.n());
    let ret = quote_spanned!(f.ret_span=> ::lagrange::__private::Scene);
    let attrs = &f.fn_attrs;
    let self_token = &f.self_token;
    let ident = &f.fn_ident;
    let stmts = &f.body.stmts;
    let allow = crate::names::allow_generated();
    quote! {
        #[automatically_derived]
        #allow
        impl ::lagrange::__private::Visual<#n> for #self_ty {
            #(#attrs)*
            fn #ident(&#self_token, #q_pat: &[f64; #n], #t_pat: f64) -> #ret {
                // The body's number type: a scene is evaluated in `f64`.
                #[allow(dead_code)]
                type Scalar = f64;
                #(#bindings)*
                #(#stmts)*
            }
        }
    }
}

/// `let` bindings of the user's names (those `used` mentions) to the slots of the generated
/// parameters `params`, and the patterns of the three parameters (`_` for one nothing reads).
/// `coords` has one entry per coordinate parameter of `decl`: the coordinate and velocity
/// names, `None` for `_`.
fn bind_slots(
    decl: &Decl,
    coords: &[(Option<&Ident>, Option<&Ident>)],
    time: Option<&Ident>,
    used: &HashSet<String>,
    params: &crate::names::Params,
) -> (Vec<TokenStream>, [TokenStream; 3]) {
    let crate::names::Params { q, qdot, t } = params;
    let mut bindings = Vec::new();
    let (mut uses_q, mut uses_qdot) = (false, false);
    for (c, (name, dot)) in decl.coords.iter().zip(coords) {
        for (ident, array, used_flag) in [(name, q, &mut uses_q), (dot, qdot, &mut uses_qdot)] {
            let Some(ident) = ident else { continue };
            if !used.contains(&unraw(ident)) {
                continue;
            }
            *used_flag = true;
            let i = c.first_index;
            let lit = proc_macro2::Literal::usize_unsuffixed;
            let (i, i1, i2) = (lit(i), lit(i + 1), lit(i + 2));
            bindings.push(match c.kind {
                CoordKind::Scalar => quote!(let #ident = #array[#i];),
                CoordKind::Vector3 => {
                    quote!(let #ident = ::lagrange::__private::Vector3::new(#array[#i], #array[#i1], #array[#i2]);)
                }
                CoordKind::Array(k) => {
                    let slots = (c.first_index..c.first_index + k).map(lit);
                    quote!(let #ident: [Scalar; #k] = [#(#array[#slots]),*];)
                }
            });
        }
    }
    let mut uses_t = false;
    if let Some(time) = time {
        if used.contains(&unraw(time)) {
            uses_t = true;
            bindings.push(quote!(let #time = #t;));
        }
    }
    let q_pat = if uses_q { quote!(#q) } else { quote!(_) };
    let qdot_pat = if uses_qdot { quote!(#qdot) } else { quote!(_) };
    let t_pat = if uses_t { quote!(#t) } else { quote!(_) };
    (bindings, [q_pat, qdot_pat, t_pat])
}

/// The generic trait method of `fn dissipation`, `fn forces` or `fn constraints`
/// (`dissipation<Scalar>`, `generalized_forces<Scalar>`, `constraints<Scalar>`) with the user's
/// body `body`, lowered for jets.
fn jets_func(
    decl: &Decl,
    analysis: &Facts<'_>,
    f: &Func,
    body: &syn::Block,
    timed_methods: &mut Vec<TokenStream>,
    name: Option<&str>,
) -> TokenStream {
    let params = crate::names::Params::jets();
    // `fn constraints` has no velocity parameter: its velocity bindings (unused, or a local of
    // the same name shadowing them) are never bound.
    let coords: Vec<(Option<&Ident>, Option<&Ident>)> = f
        .bindings
        .iter()
        .map(|(c, v)| (c.as_ref(), v.as_ref().filter(|_| !f.kind.positions_only())))
        .collect();
    let (bindings, [q_pat, qdot_pat, t_pat]) = bind_slots(
        decl,
        &coords,
        f.time.as_ref(),
        &analysis.func_used(f),
        &params,
    );
    let n = proc_macro2::Literal::usize_unsuffixed(decl.n());
    let ret = match f.kind {
        FuncKind::Dissipation => quote_spanned!(f.ret_span=> Scalar),
        FuncKind::Forces => quote_spanned!(f.ret_span=> [Scalar; #n]),
        FuncKind::Constraints => {
            let k = proc_macro2::Literal::usize_unsuffixed(f.k);
            quote_spanned!(f.ret_span=> [Scalar; #k])
        }
        FuncKind::Contacts => {
            let k = proc_macro2::Literal::usize_unsuffixed(f.k);
            quote_spanned!(f.ret_span=> [::lagrange::__private::Contact<Scalar>; #k])
        }
        FuncKind::VelocityConstraints => {
            let k = proc_macro2::Literal::usize_unsuffixed(f.k);
            quote_spanned!(f.ret_span=> [Scalar; #k])
        }
        // Emitted by `visual_impl`, in `f64`, never as a generic method.
        FuncKind::Scene => quote_spanned!(f.ret_span=> ::lagrange::__private::Scene),
    };
    // `fn constraints(&self, q, t)` and `fn contacts(&self, q, t)` have no velocities.
    let qdot_param = if f.kind.positions_only() {
        quote!()
    } else {
        quote!(#qdot_pat: &[Scalar; #n],)
    };
    let ident = Ident::new(name.unwrap_or(f.kind.trait_method()), f.fn_ident.span());
    let attrs = &f.fn_attrs;
    let self_token = &f.self_token;
    let stmts = &body.stmts;
    // D or Q read rates: evaluated in `Timed` numbers, like L (`fn constraints` never is: a
    // rate there is a velocity constraint, refused in `expand`).
    if !f.kind.positions_only() && crate::front::timed::reads_rates(&f.body, &decl.rest).is_some() {
        let hidden = crate::names::timed(&ident);
        timed_methods.push(quote! {
            #[doc(hidden)]
            #[inline]
            fn #hidden<Scalar: ::lagrange::__private::Scalar>(
                &#self_token,
                #q_pat: &[Scalar; #n],
                #qdot_param
                #t_pat: Scalar,
            ) -> #ret {
                #(#bindings)*
                #(#stmts)*
            }
        });
        let finish = match f.kind {
            FuncKind::Dissipation => quote!(.untimed()),
            _ => quote!(.map(|__lagrange_x| __lagrange_x.untimed())),
        };
        let wrapper = timed_wrapper(&ident, &ret, &hidden, decl.n(), finish);
        return quote! {
            #(#attrs)*
            #wrapper
        };
    }
    quote! {
        #(#attrs)*
        #[inline]
        fn #ident<Scalar: ::lagrange::__private::Scalar>(
            &#self_token,
            #q_pat: &[Scalar; #n],
            #qdot_param
            #t_pat: Scalar,
        ) -> #ret {
            #(#bindings)*
            #(#stmts)*
        }
    }
}

/// A stub impl emitted next to the errors (and a stub `impl Holonomic<N, K>` given `k`), so uses
/// of the type elsewhere do not cascade into "trait not implemented" errors.
fn stub_impl(rest: &syn::ItemImpl, fallback: &Fallback) -> TokenStream {
    let n = fallback.n_hint;
    let contacts = fallback.contacts_hint;
    let k = match (fallback.k_hint, fallback.velocity_hint) {
        (None, None) => None,
        (a, b) => Some(a.unwrap_or(0) + b.unwrap_or(0)),
    };
    if rest.trait_.is_some() || !rest.generics.params.is_empty() {
        return quote!();
    }
    let self_ty = &rest.self_ty;
    let names = (0..n).map(|i| format!("q{i}"));
    let holonomic = match k {
        Some(k) => quote! {
            #[automatically_derived]
            impl ::lagrange::__private::Holonomic<#n, #k> for #self_ty {
                fn constraints<S: ::lagrange::__private::Scalar>(&self, _: &[S; #n], _: S) -> [S; #k] {
                    ::core::unreachable!("`#[lagrangian]` reported errors for this impl")
                }
            }
        },
        None => quote!(),
    };
    let nonholonomic = match fallback.velocity_hint {
        Some(k) => quote! {
            #[automatically_derived]
            impl ::lagrange::__private::Nonholonomic<#n, #k> for #self_ty {
                fn velocity_constraints<S: ::lagrange::__private::Scalar>(&self, _: &[S; #n], _: &[S; #n], _: S) -> [S; #k] {
                    ::core::unreachable!("`#[lagrangian]` reported errors for this impl")
                }
            }
        },
        None => quote!(),
    };
    let unilateral = match contacts {
        Some(k) => quote! {
            #[automatically_derived]
            impl ::lagrange::__private::Unilateral<#n, #k> for #self_ty {
                fn contacts<S: ::lagrange::__private::Scalar>(&self, _: &[S; #n], _: S) -> [::lagrange::__private::Contact<S>; #k] {
                    ::core::unreachable!("`#[lagrangian]` reported errors for this impl")
                }
            }
        },
        None => quote!(),
    };
    let visual = if fallback.scene {
        quote! {
            #[automatically_derived]
            impl ::lagrange::__private::Visual<#n> for #self_ty {
                fn scene(&self, _: &[f64; #n], _: f64) -> ::lagrange::__private::Scene {
                    ::core::unreachable!("`#[lagrangian]` reported errors for this impl")
                }
            }
        }
    } else {
        quote!()
    };
    quote! {
        #visual
        #[automatically_derived]
        impl ::lagrange::__private::Lagrangian<#n> for #self_ty {
            const COORDINATES: [&'static str; #n] = [#(#names),*];
            const CYCLIC: [bool; #n] = [false; #n];
            const AUTONOMOUS: bool = true;
            fn lagrangian<S: ::lagrange::__private::Scalar>(&self, _: &[S; #n], _: &[S; #n], _: S) -> S {
                ::core::unreachable!("`#[lagrangian]` reported errors for this impl")
            }
        }
        #holonomic
        #nonholonomic
        #unilateral
    }
}

/// How many coordinate slots a (possibly invalid) `fn lagrangian` declares, for the stub.
fn count_coordinate_params(f: &syn::ImplItemFn) -> usize {
    f.sig
        .inputs
        .iter()
        .map(|a| match a {
            syn::FnArg::Typed(pt) => match validate::coord_type(&pt.ty) {
                Some(Ok(kind)) => crate::model::CoordParam {
                    kind,
                    name: Ident::new("x", proc_macro2::Span::call_site()),
                    dot: Ident::new("x", proc_macro2::Span::call_site()),
                    first_index: 0,
                }
                .width(),
                Some(Err(_)) => 1,
                None => 0,
            },
            syn::FnArg::Receiver(_) => 0,
        })
        .sum()
}
