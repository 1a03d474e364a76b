//! Compile-time derivation (`mode = "symbolic"`, the default): the body of `fn lagrangian` (and
//! of `fn dissipation` and `fn forces`, if given: one DAG, shared fields and conditions) is
//! lowered into a hash-consed expression DAG, differentiated symbolically (forward-mode tangents
//! over the DAG, structural zeros skipped), and emitted as straight-line Rust for the mass matrix,
//! the right-hand side of the Euler–Lagrange equations (f_L + Q − ∂D/∂q̇, formed once), the
//! pieces, the power, the momenta and the energy; the equations are also printed for people
//! (Unicode and LaTeX). M q̈ = f is solved by straight-line LDLᵀ,
//! except that a 2×2 block of M coupled to nothing else is solved by Cramer's rule with its
//! determinant simplified where its terms cancel (`poly.rs`; exact near chart singularities).
//!
//! An `if` whose condition uses only constants (`self` fields, literals, names from the user's
//! scope; no coordinate, velocity, time or local binding) is supported: the condition is
//! evaluated once per call as `let <b_k>: bool = <condition as written>;` (the local named by
//! `names::cond`), both branches are lowered, and every value that differs between them becomes
//! `Node::Select(k, a, b)`, emitted as `if <b_k> { a } else { b }` and differentiated branch by
//! branch. The equations print it as
//! `(a if cond else b)` (LaTeX: `\left(a \;\text{if}\; \texttt{cond} \;\text{else}\; b\right)`).
//! A condition on the state is an error at the offending name that says to use `mode = "jets"`.
//!
//! The jobs, one file each: `lower` (bodies → DAG), `derive` (M, f_L, the applied forces, the
//! right-hand side, momenta, energy, power, decoupled blocks), `solve` (the straight-line solve),
//! `explicit` (q̈ as expressions where M's blocks allow, for the Taylor series), `taylor` (the
//! Taylor series), `codegen` (DAG → `let`s), `methods` (the generated
//! method bodies and consts), `print` (the equations for people); `dag` is the expression DAG,
//! `functions` the table of elementary functions, `poly` the polynomial expander.

mod codegen;
mod dag;
mod derive;
mod explicit;
mod functions;
mod lower;
mod methods;
mod poly;
mod print;
mod solve;
mod taylor;
#[cfg(test)]
mod tests;

use crate::errors::Errors;
use crate::model::Decl;
pub use derive::Symmetry;
pub use methods::{methods, ConstraintTerms, SymbolicOutput};

/// Lowers, differentiates and emits the symbolic implementation of `decl`; `None` (with every
/// reason pushed to `errors`) when the body cannot be derived symbolically.
pub fn expand(
    decl: &Decl,
    front: &crate::front::Front<'_>,
    errors: &mut Errors,
) -> Option<SymbolicOutput> {
    let d = derive::derive(decl, front, errors)?;
    let out = methods::output(&d, decl);
    if out.generated_lets > MAX_GENERATED_LETS {
        errors.at(
            &decl.body,
            format!(
                "the symbolic mode would emit {} operations of straight-line code for this body's \
                 equations (the limit is {MAX_GENERATED_LETS}; a 64-link chain takes 31 000, and \
                 each rotation composed in a loop and differentiated by \
                 `body_angular_velocity` about 2 000), which rustc would compile in tens of \
                 seconds and gigabytes; use `#[lagrangian(mode = \"jets\")]` on this impl \
                 block, which evaluates the body as written",
                out.generated_lets
            ),
        );
        return None;
    }
    Some(out)
}

/// The most operations (`let`s over all the generated bodies) the symbolic mode emits for one
/// impl block. A 64-link chain emits 31 000 (rustc builds them in seconds); a rotation composed
/// of 60 pairs of elementary rotations, differentiated by `body_angular_velocity`, about 130 000,
/// which took rustc 41 s and 4 GB (the jets mode: 0.9 s and 0.2 GB).
pub const MAX_GENERATED_LETS: usize = 65_536;
