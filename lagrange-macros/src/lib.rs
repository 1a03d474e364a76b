//! The `#[lagrangian]` attribute macro of [lagrange](https://docs.rs/lagrange).
//!
//! The pipeline is parse → validate → analyze (and lower the body for jets) → derive
//! symbolically (`mode = "symbolic"`) → emit, one module each, run by the driver in `expand.rs`.
//! Every stage pushes its errors into one sink, spanned at the user's tokens, so all are
//! reported at once. While errors exist, what is emitted is:
//!
//! - the annotated item is not an impl block: the errors and the item as written;
//! - parse or validation errors: the errors, the impl block without its `fn lagrangian`,
//!   `fn dissipation` and `fn forces` (and without any other function taking `Coord`, `Coord3`
//!   or `Time`), and, for an inherent impl
//!   without generics, a stub `impl Lagrangian<N>` whose `fn lagrangian` is `unreachable!`, so
//!   uses of the type elsewhere do not cascade into "trait not implemented";
//! - errors of the symbolic stage (a body the symbolic mode cannot derive): the errors and the
//!   impl the jets mode would emit (the rest of the impl block, and `impl Lagrangian<N>` with
//!   `COORDINATES`, `CYCLIC`, `AUTONOMOUS` (and, with forces or dissipation,
//!   `MOMENTUM_CONSERVED` and `ENERGY_CONSERVED`), the jets `fn lagrangian` and the generic
//!   `fn dissipation` / `fn generalized_forces`), without the symbolic
//!   methods and the `EQUATIONS` consts: rustc still type-checks the body as written, so a
//!   genuine type error there is reported at the user's token too. The build fails either way.
//!
//! Every identifier the macro generates comes from `names.rs` and carries a reserved prefix, so
//! no name in the user's scope can collide with it. See the facade crate for the user-facing
//! documentation.
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
/// (and the optional `fn dissipation` and `fn forces`) written as plain Rust. See the `lagrange`
/// crate documentation.
#[proc_macro_attribute]
pub fn lagrangian(args: TokenStream, input: TokenStream) -> TokenStream {
    expand::expand(args.into(), input.into()).into()
}

#[cfg(test)]
mod deep_bodies;
#[cfg(test)]
mod expanded_example;
