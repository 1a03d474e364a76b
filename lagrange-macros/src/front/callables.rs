//! The functions a body may call besides the function table, each described once: the helper
//! methods of the impl block (written with `Scalar`), the `fn` items nested in a body, closures,
//! and the impl block's integer `const`s. The jets back end makes the functions generic over the
//! number type and lifts a constant argument where a parameter is a `Scalar`; the symbolic back
//! end inlines them.

use std::collections::HashMap;
use std::rc::Rc;

use quote::ToTokens;
use syn::{Expr, Pat};

use crate::model::{mentions_scalar, unraw};

/// How a parameter is declared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// Its type names `Scalar` (`v: Scalar`, `r: Vector3<Scalar>`): a number of the motion.
    Scalar,
    /// Another type (`m: f64`, `k: usize`): taken as it is.
    Other,
    /// No type (a closure's `|x|`): what the caller passes.
    Untyped,
}

/// A function's body.
#[derive(Clone)]
pub enum FnBody {
    /// A closure's expression.
    Expr(Expr),
    /// A function's block.
    Block(syn::Block),
}

/// A function a body may call: a helper method, a nested `fn` or a closure.
#[derive(Clone)]
pub struct Function {
    /// What it is, for messages (`this closure`, `the helper method `kinetic``).
    pub what: String,
    /// The parameter patterns (after `self`), without their types.
    pub params: Vec<Pat>,
    /// How each parameter is declared.
    pub types: Vec<ParamType>,
    /// The body.
    pub body: FnBody,
    /// A `fn` item (a nested function): it sees the other `fn` items of the scope it is called
    /// from, not the locals.
    pub item: bool,
}

/// The impl block's helper methods by name and its integer `const`s with a literal value.
#[derive(Clone, Default)]
pub struct Callables {
    /// `fn kinetic(&self, v: Scalar) -> Scalar` and the like ([`crate::model::is_helper`]).
    pub helpers: HashMap<String, Rc<Function>>,
    /// `const N: usize = 6;`.
    pub int_consts: HashMap<String, i64>,
}

impl Callables {
    /// The helpers and integer constants of `rest` (the impl block without the macro's own
    /// functions).
    pub fn of(rest: &syn::ItemImpl) -> Callables {
        let mut out = Callables::default();
        for item in &rest.items {
            match item {
                syn::ImplItem::Fn(f) if crate::model::is_helper(f) => {
                    let what = format!("the helper method `{}`", f.sig.ident);
                    let function = signature(&f.sig, what, FnBody::Block(f.block.clone()), false);
                    out.helpers.insert(unraw(&f.sig.ident), Rc::new(function));
                }
                syn::ImplItem::Const(c) => {
                    if let Some(k) = super::int_literal(&c.expr) {
                        out.int_consts.insert(unraw(&c.ident), k);
                    }
                }
                _ => {}
            }
        }
        out
    }

    /// The helper method called `name`, if there is one.
    pub fn helper(&self, name: &str) -> Option<&Rc<Function>> {
        self.helpers.get(name)
    }
}

/// A `fn` item nested in a body.
pub fn nested(f: &syn::ItemFn) -> Function {
    let what = format!("the function `{}`", f.sig.ident);
    signature(&f.sig, what, FnBody::Block((*f.block).clone()), true)
}

/// A closure.
pub fn closure(c: &syn::ExprClosure) -> Function {
    Function {
        what: "this closure".to_owned(),
        params: c.inputs.iter().cloned().collect(),
        types: closure_params(c),
        body: FnBody::Expr((*c.body).clone()),
        item: false,
    }
}

/// How each parameter of a closure is declared.
pub fn closure_params(c: &syn::ExprClosure) -> Vec<ParamType> {
    c.inputs
        .iter()
        .map(|p| match p {
            Pat::Type(pt) => type_of(&pt.ty),
            _ => ParamType::Untyped,
        })
        .collect()
}

fn signature(sig: &syn::Signature, what: String, body: FnBody, item: bool) -> Function {
    let (params, types) = sig
        .inputs
        .iter()
        .filter_map(|a| match a {
            syn::FnArg::Typed(pt) => Some(((*pt.pat).clone(), type_of(&pt.ty))),
            syn::FnArg::Receiver(_) => None,
        })
        .unzip();
    Function {
        what,
        params,
        types,
        body,
        item,
    }
}

/// How a parameter of type `ty` is declared.
pub fn type_of(ty: &syn::Type) -> ParamType {
    if mentions_scalar(ty.to_token_stream()) {
        ParamType::Scalar
    } else {
        ParamType::Other
    }
}

/// An integer literal, possibly negated and parenthesized.
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helpers_and_constants_of_an_impl_block() {
        let rest: syn::ItemImpl = syn::parse_quote! {
            impl Top {
                const N: usize = 6;
                const M: i32 = -(2);
                const X: f64 = 1.0;
                fn kinetic(&self, v: Scalar, m: f64) -> Scalar { 0.5 * m * v * v }
                fn plain(&self) -> f64 { 1.0 }
            }
        };
        let c = Callables::of(&rest);
        assert_eq!(c.int_consts.get("N"), Some(&6));
        assert_eq!(c.int_consts.get("M"), Some(&-2));
        assert!(!c.int_consts.contains_key("X"));
        let k = c.helper("kinetic").expect("a helper");
        assert_eq!(k.types, [ParamType::Scalar, ParamType::Other]);
        assert_eq!(k.what, "the helper method `kinetic`");
        assert!(c.helper("plain").is_none());
        let cl: syn::ExprClosure = syn::parse_quote!(|x, m: f64, v: Scalar| m * x * v);
        assert_eq!(
            closure(&cl).types,
            [ParamType::Untyped, ParamType::Other, ParamType::Scalar]
        );
    }
}
