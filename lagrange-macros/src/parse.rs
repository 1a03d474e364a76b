//! Parse: the attribute arguments and the impl block, split into `fn lagrangian`, the optional
//! `fn dissipation`, `fn forces` and `fn constraints`, and the rest.

use proc_macro2::TokenStream;
use syn::parse::Parser;
use syn::punctuated::Punctuated;
use syn::{Expr, ExprLit, ImplItem, ImplItemFn, ItemImpl, Lit, Meta, Token};

use crate::errors::Errors;
use crate::model::{Mode, Options};

/// The mode used when the attribute does not name one.
pub const DEFAULT_MODE: Mode = Mode::Symbolic;

/// Parses `mode = "jets" | "symbolic"` and `lanes`; anything else is an error at that argument.
pub fn options(args: TokenStream, errors: &mut Errors) -> Options {
    let mut options = Options {
        mode: DEFAULT_MODE,
        mode_span: None,
        lanes: None,
    };
    let metas = match Punctuated::<Meta, Token![,]>::parse_terminated.parse2(args) {
        Ok(m) => m,
        Err(e) => {
            errors.push(e);
            return options;
        }
    };
    for meta in metas {
        match &meta {
            Meta::NameValue(nv) if nv.path.is_ident("mode") => {
                if options.mode_span.is_some() {
                    errors.at(&meta, "`mode` is given twice");
                    continue;
                }
                match &nv.value {
                    Expr::Lit(ExprLit { lit: Lit::Str(s), .. }) => match s.value().as_str() {
                        "jets" => options.mode = Mode::Jets,
                        "symbolic" => options.mode = Mode::Symbolic,
                        other => {
                            errors.at(s, format!("unknown mode `{other}`: expected `\"symbolic\"` or `\"jets\"`"));
                            continue;
                        }
                    },
                    other => {
                        errors.at(other, "expected a string: `mode = \"symbolic\"` or `mode = \"jets\"`");
                        continue;
                    }
                }
                options.mode_span = Some(syn::spanned::Spanned::span(&nv.value));
            }
            Meta::Path(p) if p.is_ident("lanes") => {
                if options.lanes.is_some() {
                    errors.at(&meta, "`lanes` is given twice");
                    continue;
                }
                options.lanes = Some(syn::spanned::Spanned::span(p));
            }
            _ => errors.at(
                &meta,
                "unknown argument to `#[lagrangian]`: the arguments are `mode = \"symbolic\"` or `mode = \"jets\"`, and `lanes`",
            ),
        }
    }
    if let (Some(span), Mode::Jets) = (options.lanes, options.mode) {
        errors.push(syn::Error::new(
            span,
            "`lanes` asks for the symbolic mode's lanes code (SIMD ensembles), which the jets mode does \
             not generate: remove `lanes`, or `mode = \"jets\"`",
        ));
    }
    options
}

/// The impl block with every `fn lagrangian`, `fn dissipation`, `fn forces` and
/// `fn constraints` taken out (in order of appearance).
pub struct Split {
    /// The impl block without them.
    pub rest: ItemImpl,
    /// Every `fn lagrangian` found.
    pub funcs: Vec<ImplItemFn>,
    /// Every `fn dissipation` found.
    pub dissipation: Vec<ImplItemFn>,
    /// Every `fn forces` found.
    pub forces: Vec<ImplItemFn>,
    /// Every `fn constraints` found.
    pub constraints: Vec<ImplItemFn>,
    /// Every `fn contacts` found.
    pub contacts: Vec<ImplItemFn>,
    /// Every `fn velocity_constraints` found.
    pub velocity_constraints: Vec<ImplItemFn>,
    /// Every `fn scene` found.
    pub scene: Vec<ImplItemFn>,
}

/// Parses the annotated item as an impl block and takes out `fn lagrangian`, `fn dissipation`,
/// `fn forces` and `fn constraints`.
pub fn split(input: TokenStream) -> syn::Result<Split> {
    let mut rest: ItemImpl = syn::parse2(input).map_err(|e| {
        syn::Error::new(
            e.span(),
            format!("`#[lagrangian]` goes on an inherent impl block (`impl MySystem {{ fn lagrangian(...) }}`): {e}"),
        )
    })?;
    let (mut funcs, mut dissipation, mut forces, mut constraints, mut contacts) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut velocity_constraints = Vec::new();
    let mut scene = Vec::new();
    let items = std::mem::take(&mut rest.items);
    for item in items {
        match item {
            ImplItem::Fn(f) if f.sig.ident == "lagrangian" => funcs.push(f),
            ImplItem::Fn(f) if f.sig.ident == "dissipation" => dissipation.push(f),
            ImplItem::Fn(f) if f.sig.ident == "forces" => forces.push(f),
            ImplItem::Fn(f) if f.sig.ident == "constraints" => constraints.push(f),
            ImplItem::Fn(f) if f.sig.ident == "contacts" => contacts.push(f),
            ImplItem::Fn(f) if f.sig.ident == "scene" => scene.push(f),
            ImplItem::Fn(f) if f.sig.ident == "velocity_constraints" => {
                velocity_constraints.push(f)
            }
            other => rest.items.push(other),
        }
    }
    Ok(Split {
        rest,
        funcs,
        dissipation,
        forces,
        constraints,
        contacts,
        velocity_constraints,
        scene,
    })
}
