//! The `#[lagrangian]` attribute macro of [lagrange](https://docs.rs/lagrange).
//!
//! The pipeline is parse → validate → the front end (`front/`: each body's entry names and
//! mentions, the callables, scopes and the pattern binder, the iterator vocabulary, the bodies
//! that read rates; resolved once) → the flags (`analyze.rs`) and the jets back end (`jets/`) →
//! the symbolic back end (`symbolic/`, `mode = "symbolic"`) → emit, one module each, run by the
//! driver in `expand.rs`.
//! Every stage pushes its errors into one sink, spanned at the user's tokens, so all are
//! reported at once. While errors exist, what is emitted is:
//!
//! - the annotated item is not an impl block: the errors and the item as written;
//! - parse or validation errors: the errors, the impl block without its `fn lagrangian`,
//!   `fn dissipation`, `fn forces` and `fn constraints` (and without any other function taking
//!   `Coord`, `Coord3` or `Time`), and, for an inherent impl
//!   without generics, a stub `impl Lagrangian<N>` whose `fn lagrangian` is `unreachable!` (and,
//!   when `fn constraints` returns `[Scalar; K]`, a stub `impl Holonomic<N, K>`), so
//!   uses of the type elsewhere do not cascade into "trait not implemented";
//! - errors of the symbolic stage (a body the symbolic mode cannot derive): the errors and the
//!   impl the jets mode would emit (the rest of the impl block, and `impl Lagrangian<N>` with
//!   `COORDINATES`, `CYCLIC`, `AUTONOMOUS` (and, with forces or dissipation,
//!   `MOMENTUM_CONSERVED` and `ENERGY_CONSERVED`), the jets `fn lagrangian` and the generic
//!   `fn dissipation` / `fn generalized_forces`, and `impl Holonomic<N, K>`), without the symbolic
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
mod front;
mod jets;
mod model;
mod names;
mod parse;
mod symbolic;
mod validate;

use proc_macro::TokenStream;

/// Derives `impl Lagrangian<N>` from `fn lagrangian(&self, (q, q_dot): Coord, ...) -> Scalar`
/// written as plain Rust. Documented, with its examples (run as the facade's doctests), where
/// users meet it: `lagrange::lagrangian`.
#[proc_macro_attribute]
pub fn lagrangian(args: TokenStream, input: TokenStream) -> TokenStream {
    // On a stack of its own (256 MiB reserved, committed as used, on this thread so the compiler's
    // token streams stay reachable): syn parses and prints nested expressions recursively.
    stacker::grow(STACK, || expand::expand(args.into(), input.into()).into())
}

/// The stack the expansion runs on.
const STACK: usize = 256 << 20;

#[cfg(test)]
mod deep_bodies;
#[cfg(test)]
mod expanded_example;
