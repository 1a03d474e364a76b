//! Emit: the `impl Lagrangian<N>` (or, while errors exist, the errors and a stub impl). Only
//! emission: the driver (`expand.rs`) runs the stages and hands their results here.

use proc_macro2::TokenStream;
use quote::{quote, quote_spanned};

use crate::analyze::Analysis;
use crate::errors::Errors;
use proc_macro2::Ident;

use crate::model::{unraw, AuxKind, CoordKind, Decl};
use crate::symbolic::SymbolicOutput;
use crate::{parse, validate};

/// The errors and the item as written, when it is not even an impl block.
pub fn unparsed(errors: &Errors, input: TokenStream) -> TokenStream {
    let errs = errors.to_compile_errors();
    quote!(#errs #input)
}

/// What is emitted in place of the impl while parse or validation errors exist.
pub struct Fallback {
    /// The impl block without `fn lagrangian` and without any function that uses the macro's
    /// own vocabulary (`Coord`, `Scalar`), so the user sees our errors and not cascades.
    rest: syn::ItemImpl,
    /// How many coordinate slots the (first) `fn lagrangian` declares, at least 1.
    n_hint: usize,
}

impl Fallback {
    /// The fallback of a split impl block, taken before validation consumes it.
    pub fn of(split: &parse::Split) -> Fallback {
        let mut rest = split.rest.clone();
        rest.items.retain(|item| !matches!(item, syn::ImplItem::Fn(f) if f.sig.inputs.iter().any(validate::is_coordinate_param)));
        let n_hint = split
            .funcs
            .first()
            .map(count_coordinate_params)
            .unwrap_or(1)
            .max(1);
        Fallback { rest, n_hint }
    }
}

/// The errors, the rest of the impl block and a stub `impl Lagrangian`.
pub fn stub(errors: &Errors, fallback: &Fallback) -> TokenStream {
    let errs = errors.to_compile_errors();
    let rest = &fallback.rest;
    let stub = stub_impl(rest, fallback.n_hint);
    quote!(#errs #rest #stub)
}

/// The `impl Lagrangian<N>`: the jets `fn lagrangian` (its body `body`, lowered for jets) and,
/// given `symbolic`, the symbolic methods and the `EQUATIONS` consts; `errors` (from the
/// symbolic stage) go after the impl, which then has only `fn lagrangian`, so rustc still
/// type-checks the body as written (a genuine type error there is reported at the user's token
/// too, and nothing cascades; the build fails either way: no silent fallback).
pub fn generate(
    decl: &Decl,
    analysis: &Analysis,
    body: &syn::Block,
    aux_bodies: &[syn::Block],
    symbolic: Option<&SymbolicOutput>,
    errors: &Errors,
) -> TokenStream {
    let n = decl.n();
    let self_ty = &decl.rest.self_ty;
    let rest = &decl.rest;
    let names = decl.coordinate_names();
    let cyclic = &analysis.cyclic;
    let autonomous = analysis.autonomous;

    // Bindings of the user's names to the jets' slots; names the body never mentions are not
    // bound (no unused-variable warnings for cyclic coordinates).
    let slots: Vec<(CoordKind, usize, Option<&Ident>, Option<&Ident>)> = decl
        .coords
        .iter()
        .map(|c| (c.kind, c.first_index, Some(&c.name), Some(&c.dot)))
        .collect();
    let lagrangian_params = params(&slots, decl.time.as_ref(), &analysis.used);
    let Bound {
        q_pat,
        qdot_pat,
        t_pat,
        bindings,
    } = lagrangian_params;

    let stmts = &body.stmts;
    let fn_attrs = &decl.fn_attrs;
    let ret = quote_spanned!(decl.ret_span=> Scalar);
    let fn_ident = &decl.fn_ident;
    let self_token = &decl.self_token;
    let (symbolic_methods, symbolic_consts) = match symbolic {
        Some(out) => crate::symbolic::methods(out, n, self_ty),
        None => (quote!(), errors.to_compile_errors()),
    };
    let nn = proc_macro2::Literal::usize_unsuffixed(n);
    let lints = quote! {
        #[allow(
            clippy::all,
            clippy::pedantic,
            clippy::nursery,
            unused_parens,
            unused_braces,
            non_snake_case
        )]
    };

    // `fn dissipation` / `fn forces` as the trait's generic methods, bound and lowered like L.
    let mut aux_methods = TokenStream::new();
    for (k, (a, lowered)) in decl.aux.iter().zip(aux_bodies).enumerate() {
        let slots: Vec<(CoordKind, usize, Option<&Ident>, Option<&Ident>)> = decl
            .coords
            .iter()
            .zip(&a.binds)
            .map(|(c, (x, v))| (c.kind, c.first_index, x.as_ref(), v.as_ref()))
            .collect();
        let Bound {
            q_pat,
            qdot_pat,
            t_pat,
            bindings,
        } = params(&slots, a.time.as_ref(), &analysis.aux_used[k]);
        let attrs = &a.attrs;
        let self_token = &a.self_token;
        let stmts = &lowered.stmts;
        let (method, ret) = match a.kind {
            AuxKind::Dissipation => (
                quote_spanned!(a.ident.span()=> dissipation),
                quote_spanned!(a.ret_span=> Scalar),
            ),
            AuxKind::Forces => (
                quote_spanned!(a.ident.span()=> generalized_forces),
                quote_spanned!(a.ret_span=> [Scalar; #nn]),
            ),
        };
        aux_methods.extend(quote! {
            #(#attrs)*
            #[inline]
            #lints
            fn #method<Scalar: ::lagrange::__private::Scalar>(
                &#self_token,
                #q_pat: &[Scalar; #nn],
                #qdot_pat: &[Scalar; #nn],
                #t_pat: Scalar,
            ) -> #ret {
                #(#bindings)*
                #(#stmts)*
            }
        });
    }
    // The conservation flags, where forces or dissipation make them differ from the defaults.
    let flags = if decl.aux.is_empty() {
        quote!()
    } else {
        let conserved = &analysis.momentum_conserved;
        let energy = analysis.energy_conserved;
        quote! {
            const MOMENTUM_CONSERVED: [bool; #nn] = [#(#conserved),*];
            const ENERGY_CONSERVED: bool = #energy;
        }
    };

    // The rest of the user's impl block, unless it was only the Lagrangian.
    let rest = if rest.items.is_empty() && rest.attrs.is_empty() {
        quote!()
    } else {
        quote!(#rest)
    };
    quote! {
        #rest

        #[automatically_derived]
        impl ::lagrange::__private::Lagrangian<#nn> for #self_ty {
            const COORDINATES: [&'static str; #nn] = [#(#names),*];
            const CYCLIC: [bool; #nn] = [#(#cyclic),*];
            const AUTONOMOUS: bool = #autonomous;
            #flags

            #(#fn_attrs)*
            #[inline]
            #lints
            fn #fn_ident<Scalar: ::lagrange::__private::Scalar>(
                &#self_token,
                #q_pat: &[Scalar; #nn],
                #qdot_pat: &[Scalar; #nn],
                #t_pat: Scalar,
            ) -> #ret {
                #(#bindings)*
                #(#stmts)*
            }
            #aux_methods
            #symbolic_methods
        }
        #symbolic_consts
    }
}

/// The parameter patterns and the `let`s binding a generated method's slots to the user's names.
struct Bound {
    q_pat: TokenStream,
    qdot_pat: TokenStream,
    t_pat: TokenStream,
    bindings: Vec<TokenStream>,
}

/// Binds each slot's coordinate and velocity name (where the body mentions it) and the time.
fn params(
    slots: &[(CoordKind, usize, Option<&Ident>, Option<&Ident>)],
    time: Option<&Ident>,
    used: &std::collections::HashSet<String>,
) -> Bound {
    let crate::names::Params { q, qdot, t } = crate::names::Params::jets();
    let mut bindings = Vec::new();
    let (mut uses_q, mut uses_qdot) = (false, false);
    for &(kind, first, name, dot) in slots {
        for (ident, array, used_flag) in [(name, &q, &mut uses_q), (dot, &qdot, &mut uses_qdot)] {
            let Some(ident) = ident else { continue };
            if !used.contains(&unraw(ident)) {
                continue;
            }
            *used_flag = true;
            let lit = proc_macro2::Literal::usize_unsuffixed;
            let (i, i1, i2) = (lit(first), lit(first + 1), lit(first + 2));
            bindings.push(match kind {
                CoordKind::Scalar => quote!(let #ident = #array[#i];),
                CoordKind::Vector3 => {
                    quote!(let #ident = ::lagrange::__private::Vector3::new(#array[#i], #array[#i1], #array[#i2]);)
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
    Bound {
        q_pat: if uses_q { quote!(#q) } else { quote!(_) },
        qdot_pat: if uses_qdot { quote!(#qdot) } else { quote!(_) },
        t_pat: if uses_t { quote!(#t) } else { quote!(_) },
        bindings,
    }
}

/// A stub impl emitted next to the errors, so uses of the type elsewhere do not cascade into
/// "trait not implemented" errors.
fn stub_impl(rest: &syn::ItemImpl, n: usize) -> TokenStream {
    if rest.trait_.is_some() || !rest.generics.params.is_empty() {
        return quote!();
    }
    let self_ty = &rest.self_ty;
    let names = (0..n).map(|i| format!("q{i}"));
    quote! {
        #[automatically_derived]
        impl ::lagrange::__private::Lagrangian<#n> for #self_ty {
            const COORDINATES: [&'static str; #n] = [#(#names),*];
            const CYCLIC: [bool; #n] = [false; #n];
            const AUTONOMOUS: bool = true;
            fn lagrangian<S: ::lagrange::__private::Scalar>(&self, _: &[S; #n], _: &[S; #n], _: S) -> S {
                ::core::unreachable!("`#[lagrangian]` reported errors for this impl")
            }
        }
    }
}

/// How many coordinate slots a (possibly invalid) `fn lagrangian` declares, for the stub.
fn count_coordinate_params(f: &syn::ImplItemFn) -> usize {
    f.sig
        .inputs
        .iter()
        .map(|a| match a {
            syn::FnArg::Typed(pt) => {
                let ty = &pt.ty;
                let s = quote!(#ty).to_string();
                if s.ends_with("Coord3") {
                    3
                } else if s.ends_with("Coord") {
                    1
                } else {
                    0
                }
            }
            syn::FnArg::Receiver(_) => 0,
        })
        .sum()
}
