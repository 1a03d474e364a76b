//! Bodies that read rates: `velocity(x)`, `angular_velocity(&r)`, `body_angular_velocity(&r)`.
//!
//! Both back ends learn which bodies these are from here. The jets path evaluates such a body in
//! `Timed` numbers (a value and its rate along the motion): the trait method lifts the state
//! (q moving at q̇, t at rate 1) and calls a hidden inherent method that holds the body. The
//! symbolic mode differentiates along (q̇, 1) in its graph (`symbolic/lower/geometry.rs`).

use std::collections::{HashMap, HashSet};

use proc_macro2::{Span, TokenStream, TokenTree};
use quote::ToTokens;

use crate::model::unraw;

/// The functions that read the rate of what they are given.
pub const RATE_FUNCTIONS: &[&str] = &["velocity", "angular_velocity", "body_angular_velocity"];

/// Every identifier in `ts`, with the span of its first occurrence.
fn idents(ts: TokenStream, out: &mut HashMap<String, Span>) {
    for tt in ts {
        match tt {
            TokenTree::Ident(i) => {
                out.entry(unraw(&i)).or_insert(i.span());
            }
            TokenTree::Group(g) => idents(g.stream(), out),
            _ => {}
        }
    }
}

/// Where `body` names a rate function, directly or through the helper methods of `rest` it
/// names (to any depth): the span of the first such name, in the body itself when it is there.
pub fn reads_rates(body: &syn::Block, rest: &syn::ItemImpl) -> Option<Span> {
    let helpers: HashMap<String, &syn::ImplItemFn> = rest
        .items
        .iter()
        .filter_map(|item| match item {
            syn::ImplItem::Fn(f) => Some((unraw(&f.sig.ident), f)),
            _ => None,
        })
        .collect();
    let mut seen: HashSet<String> = HashSet::new();
    let mut stack = vec![body.to_token_stream()];
    let mut first: Option<Span> = None;
    while let Some(ts) = stack.pop() {
        let mut names = HashMap::new();
        idents(ts, &mut names);
        for f in RATE_FUNCTIONS {
            if let Some(&span) = names.get(*f) {
                // The body's own use first (it is scanned first); a helper's otherwise.
                first.get_or_insert(span);
            }
        }
        for name in names.keys() {
            if let Some(h) = helpers.get(name) {
                if seen.insert(name.clone()) {
                    stack.push(h.block.to_token_stream());
                }
            }
        }
    }
    first
}
