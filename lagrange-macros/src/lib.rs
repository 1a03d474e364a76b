//! The `#[lagrangian]` attribute macro of [lagrange](https://docs.rs/lagrange).
//!
//! The pipeline is parse → validate → analyze (lower) → emit, one module each; errors are
//! collected across stages, spanned at the user's tokens, and nothing but a stub impl is
//! generated while any exist. See the facade crate for the user-facing documentation.
#![forbid(unsafe_code)]

mod analyze;
mod emit;
mod errors;
mod expand;
mod model;
mod names;
mod parse;
mod symbolic;
mod validate;

use proc_macro::TokenStream;

/// Derives `impl Lagrangian<N>` from `fn lagrangian(&self, (q, q_dot): Coord, ...) -> Scalar`
/// written as plain Rust. See the `lagrange` crate documentation.
#[proc_macro_attribute]
pub fn lagrangian(args: TokenStream, input: TokenStream) -> TokenStream {
    expand::expand(args.into(), input.into()).into()
}

#[cfg(test)]
mod expanded_example;
