//! Every identifier the macro generates, named in one place.
//!
//! Generated code lives next to the user's items, and a `let` pattern (or a function parameter,
//! or a `match` arm) whose name is a `const` in scope is a constant pattern, not a binding:
//! `Span::mixed_site()` does not stop that resolution. So every generated local, parameter and
//! label carries the reserved prefix [`PREFIX`], which no user name is expected to start with;
//! a user `const q`, `t`, `x3`, `scale`, `tol`, `fast`, `det_0_1` or `p_m` then cannot collide.
//! Names of the user's own bindings (coordinates, velocities, time, locals of the body) and of
//! the user's fields, constants and types are written as the user wrote them.

use proc_macro2::{Ident, Span};
use quote::format_ident;

/// The reserved prefix of every generated local, parameter and label.
pub const PREFIX: &str = "__lagrange_";

/// `__lagrange_<name>` at the call site (resolves like the user's tokens around it).
fn local(name: std::fmt::Arguments<'_>) -> Ident {
    Ident::new(&format!("{PREFIX}{name}"), Span::call_site())
}

/// The parameters q, q̇ and t of a generated method.
pub struct Params {
    /// Generalized coordinates, `&[_; N]`.
    pub q: Ident,
    /// Generalized velocities, `&[_; N]`.
    pub qdot: Ident,
    /// Time.
    pub t: Ident,
}

impl Params {
    /// The parameters of the symbolic methods (call-site spans, like the code that reads them).
    pub fn symbolic() -> Params {
        Params {
            q: local(format_args!("q")),
            qdot: local(format_args!("qdot")),
            t: local(format_args!("t")),
        }
    }

    /// The parameters of the jets `fn lagrangian` (mixed-site: the user's body cannot see them).
    pub fn jets() -> Params {
        let site = Span::mixed_site();
        Params {
            q: format_ident!("{}q", PREFIX, span = site),
            qdot: format_ident!("{}qdot", PREFIX, span = site),
            t: format_ident!("{}t", PREFIX, span = site),
        }
    }
}

/// The hidden inherent method that holds the body of trait method `method` when the body reads
/// rates (`__lagrange_timed_lagrangian`): the trait method evaluates it in `Timed` numbers.
pub fn timed(method: &Ident) -> Ident {
    Ident::new(
        &format!("{PREFIX}timed_{}", unraw_str(method)),
        method.span(),
    )
}

/// The hidden inherent method holding the body of `fn constraints` in a system that also has
/// `fn velocity_constraints` (its `Holonomic::constraints` pads it with the velocity rows).
pub fn holonomic() -> String {
    format!("{PREFIX}holonomic")
}

fn unraw_str(i: &Ident) -> String {
    let s = i.to_string();
    s.strip_prefix("r#").map(str::to_owned).unwrap_or(s)
}

/// A local or parameter of the generated `taylor_series` (`__lagrange_<name>`).
pub fn taylor(name: &str) -> Ident {
    local(format_args!("{name}"))
}

/// The local holding DAG node `id` (`x{id}`).
pub fn node(id: u32) -> Ident {
    local(format_args!("x{id}"))
}

/// The `bool` of the k-th constant `if` condition (`b_{k}`).
pub fn cond(k: u32) -> Ident {
    local(format_args!("b_{k}"))
}

/// The local a field (`p_{field}`) or a free name of the user's scope (`c_{name}`) is loaded
/// into.
pub fn field(name: &str, free: bool) -> Ident {
    if free {
        local(format_args!("c_{name}"))
    } else {
        local(format_args!("p_{name}"))
    }
}

/// The local holding the `k`-th parameter-only expression evaluated as written.
pub fn opaque(k: usize) -> Ident {
    local(format_args!("o_{k}"))
}

/// Entry (j, i) of L in the LDLᵀ solve (`l_{j}_{i}`).
pub fn ldl_l(j: usize, i: usize) -> Ident {
    local(format_args!("l_{j}_{i}"))
}

/// Entry (j, i) of the row of the LDLᵀ solve before its division by the pivot (`u_{j}_{i}`).
pub fn ldl_u(j: usize, i: usize) -> Ident {
    local(format_args!("u_{j}_{i}"))
}

/// Pivot j of the LDLᵀ solve (`d_{j}`).
pub fn ldl_d(j: usize) -> Ident {
    local(format_args!("d_{j}"))
}

/// The reciprocal of pivot j (`r_{j}`).
pub fn ldl_r(j: usize) -> Ident {
    local(format_args!("r_{j}"))
}

/// Unknown i of the solve, through its substitutions (`y_{i}`).
pub fn solve_y(i: usize) -> Ident {
    local(format_args!("y_{i}"))
}

/// The determinant of the decoupled 2×2 block {i, k} (`det_{i}_{k}`).
pub fn det(i: usize, k: usize) -> Ident {
    local(format_args!("det_{i}_{k}"))
}

/// The solution array of the fast path.
pub fn solution() -> Ident {
    local(format_args!("qddot"))
}

/// The label of the solve's block (`'fast`): left early where a pivot test fails in every lane.
pub fn fast_label() -> syn::Lifetime {
    syn::Lifetime::new(&format!("'{PREFIX}fast"), Span::call_site())
}

/// The number type parameter of the generic kernels (`R: Real`).
pub fn real() -> Ident {
    Ident::new("R", Span::call_site())
}

/// The parameters of the generic kernels' trait methods: the members, and the kernels'
/// parameter array.
pub fn lane_members() -> Ident {
    local(format_args!("members"))
}

/// See [`lane_members`].
pub fn lane_params() -> Ident {
    local(format_args!("params"))
}

/// The lanes whose pivot tests passed so far in the generated lanes solve (a `Mask`).
pub fn lane_ok() -> Ident {
    local(format_args!("ok"))
}

/// The one lint attribute of every generated impl (machine-written code, and the user's
/// functions rewritten for the jets: parentheses and braces the rewrite leaves, the coordinate
/// names the user chose, whatever clippy would say of generated arithmetic).
pub fn allow_generated() -> proc_macro2::TokenStream {
    quote::quote! {
        #[allow(
            unused_parens,
            unused_braces,
            non_snake_case,
            clippy::all,
            clippy::pedantic,
            clippy::nursery
        )]
    }
}
