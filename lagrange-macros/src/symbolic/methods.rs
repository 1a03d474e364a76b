//! Emit the methods: the bodies of the generated `accelerations`, `pieces`, `power`,
//! `mass_matrix`, `momenta`, `energy` and `energy_and_momenta`, and the `EQUATIONS` /
//! `EQUATIONS_LATEX` consts.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use super::dag::{Dag, Id};
use super::derive::{Derivation, Equations};
use super::{codegen, print, solve};
use crate::model::Decl;
use crate::names;

/// Up to this many generated operations (values plus N² for the solve), `accelerations` is
/// `#[inline(always)]`.
const INLINE_ALWAYS_MAX_OPS: usize = 256;

/// Up to this many generated operations (values plus N² for the solve) the system gets lanes code
/// (`accelerations_lanes`, `taylor_series_lanes`: W ensemble members per vector). Every
/// `Ensemble` instantiates the lanes engines, which inline that code at each DOP853 stage and in
/// the Taylor engine: measured release builds of a crate with one `Ensemble::run` (2026-11-26,
/// 2 cores), a 12-link chain (984 operations) took 123 s with lanes code against 11 s without
/// an ensemble and 18 s with one and no lanes code; an 8-link chain (478) 8.1 s against 3.9 s.
/// A 6-link chain has 291, the heavy top fewer. `#[lagrangian(lanes)]` asks for the lanes code
/// whatever the size (up to 32 coordinates): an 8-link chain's ensemble of 64 DOP853 members took
/// 1.8× the instructions one member at a time.
const LANES_MAX_OPS: usize = 300;

/// What the symbolic path contributes to the generated impl.
pub struct SymbolicOutput {
    /// Body of `fn accelerations(&self, q: &[f64; N], qdot: &[f64; N], t: f64)
    /// -> Result<[f64; N], ::lagrange::__private::DynamicsError>`.
    pub accelerations: TokenStream,
    /// Body of `fn pieces(&self, q, qdot, t) -> ::lagrange::__private::eom::Pieces<N>`: M, f_L
    /// and the applied forces, straight-line.
    pub pieces: TokenStream,
    /// `#[inline(always)]` for a small `pieces` (the constrained right-hand side calls it at every
    /// stage), `#[inline]` otherwise.
    pub pieces_inline: TokenStream,
    /// Body of `fn power(&self, q, qdot, t) -> f64`: (Q − ∂D/∂q̇)·q̇ − ∂L/∂t, straight-line.
    pub power: TokenStream,
    /// Body of `fn mass_matrix(&self, q, qdot, t) -> ::lagrange::__private::SMatrix<f64, N, N>`.
    pub mass_matrix: TokenStream,
    /// `#[inline(always)]` for a small `accelerations`, `#[inline]` otherwise.
    pub accelerations_inline: TokenStream,
    /// Body of `fn momenta(&self, q, qdot, t) -> [f64; N]`.
    pub momenta: TokenStream,
    /// Body of `fn energy(&self, q, qdot, t) -> f64`.
    pub energy: TokenStream,
    /// Body of `fn energy_and_momenta(&self, q, qdot, t) -> (f64, [f64; N])`.
    pub energy_and_momenta: TokenStream,
    /// Body of `fn taylor_series(&self, t, out, buf)` (the Taylor method's series) and, with
    /// lanes code, of `fn taylor_series_lanes`, where every node has a Taylor rule and the body
    /// is analytic; else why not.
    pub taylor: Result<super::taylor::Series, super::taylor::NoSeries>,
    /// The lanes code (systems with the unrolled solve): the body of `accelerations_lanes`, the
    /// body of `lane_params` and how many numbers it writes.
    pub lanes: Option<(TokenStream, TokenStream, usize)>,
    /// Items to emit next to the user's impl: the modules of a large system's out-of-line bodies.
    pub items: TokenStream,
    /// Lint attributes to put on each of the generated methods (machine-written code).
    pub allow: TokenStream,
    /// Whether the system has `fn dissipation` or `fn forces` (the docs then name Q and D).
    pub has_applied: bool,
    /// The Euler–Lagrange equations, plain Unicode, one line per coordinate.
    pub equations: String,
    /// The same equations in LaTeX, one line per coordinate.
    pub equations_latex: String,
    /// A rustdoc section (Markdown) presenting the equations, for the user's type.
    pub doc: String,
    /// Size of the generated code: `let` statements over all the bodies.
    #[cfg_attr(not(test), allow(dead_code))]
    pub generated_lets: usize,
}

/// The bodies of the generated methods and the printed equations of a derivation.
/// Above this many coordinates the accelerations solve M q̈ = f with the runtime's loop-based
/// LDLᵀ (M and f from `pieces`) instead of the unrolled elimination: the measured crossover of
/// q̈ time on an N-link chain lies between 32 and 64 (BENCHMARKS.md, "Chains of N links").
const LOOP_SOLVE_ABOVE: usize = 32;

/// What every generated method's code is built from: the derivation, the names of the
/// parameters, and what the methods add up (the items next to the impl, the count of `let`s).
struct Gen<'a> {
    d: &'a Derivation,
    n: usize,
    nn: Literal,
    q: Ident,
    qdot: Ident,
    t: Ident,
    /// `let _ = (q, qdot, t);`: every method reads its parameters.
    touch: TokenStream,
    /// `<Self as Lagrangian<N>>`.
    lagrangian_trait: TokenStream,
    /// The prefix of the out-of-line modules' names.
    prefix: String,
    /// Above [`LOOP_SOLVE_ABOVE`] coordinates: the loop-based solve and out-of-line bodies.
    large: bool,
    /// `#[lagrangian(lanes)]`: the lanes code above [`LANES_MAX_OPS`] too.
    force_lanes: bool,
    /// Items next to the impl (the modules of `out_of_line`).
    items: TokenStream,
    /// `let` statements over all the bodies.
    lets: usize,
}

/// The body of `accelerations` and its inline attribute; the lanes code and its parameter loads
/// (the Taylor series over lanes reads them), for a small system.
struct Accelerations {
    body: TokenStream,
    inline: TokenStream,
    lanes: Option<(TokenStream, TokenStream, usize)>,
    lane_loads: Option<(TokenStream, usize)>,
}

impl Gen<'_> {
    /// `accelerations`: the unrolled solve with the pivot test and the fallback, or for a large
    /// system the runtime's solve of `pieces`; with the lanes code of a small system.
    fn accelerations(&mut self) -> Accelerations {
        let Gen {
            d,
            n,
            ref nn,
            ref q,
            ref qdot,
            ref t,
            ref touch,
            ref lagrangian_trait,
            large,
            ..
        } = *self;
        let op = |id: Id| codegen::operand(&d.dag, &d.fields, id);
        let mut lets = 0;
        let mut lanes = None;
        // The lanes code's parameter loads and their count, for the Taylor series over lanes.
        let mut lane_loads: Option<(TokenStream, usize)> = None;
        let (accelerations, accelerations_inline) = if large {
            // Large N: M (upper triangle) and the right-hand side from `pieces` (one copy of their
            // code, kept out of line), solved by the runtime's row-oriented LDLᵀ (the same pivot
            // test and fallback): O(N²) code instead of the O(N³) of the unrolled elimination, which
            // costs minutes of build and is slower at this size (BENCHMARKS.md, "Chains of N links").
            let body = quote! {
                #touch
                let __lagrange_pieces = #lagrangian_trait::pieces(self, #q, #qdot, #t);
                ::lagrange::__private::solve_mass_matrix(
                    &__lagrange_pieces.mass,
                    &__lagrange_pieces.rhs(),
                    #lagrangian_trait::COORDINATES,
                    #q,
                    #qdot,
                    #t,
                )
            };
            (body, quote!(#[inline]))
        } else {
            let mut outs: Vec<Id> = Vec::new();
            for (i, row) in d.mass.iter().enumerate() {
                outs.extend(&row[i..]);
            }
            outs.extend(&d.rhs);
            outs.extend(d.pairs.iter().map(|p| p.2));
            let code = codegen::emit(&d.dag, &d.fields, &d.conds, &outs);
            lets += code.lets;
            // A small right-hand side is inlined at every call site (the twelve stages of DOP853
            // call it from unrolled code; `#[inline]` alone let LLVM keep it out of line and the
            // whole run was 11 % slower); a large one is left to LLVM so code size stays in bounds.
            let inline = if code.lets + n * n <= INLINE_ALWAYS_MAX_OPS {
                quote!(#[inline(always)])
            } else {
                quote!(#[inline])
            };
            // M and the right-hand side, formed once: the fast path's solve and the fallback's
            // arrays read the same operands.
            let eq = Equations::of(d);
            let or_zero = |x: &Option<TokenStream>| x.clone().unwrap_or_else(|| quote!(0.0));
            let rows = eq.mass.iter().map(|row| {
                let cells = row.iter().map(or_zero);
                quote!([#(#cells),*])
            });
            let f = eq.rhs.iter().map(or_zero);
            let stmts = code.stmts();
            let pairs: Vec<(usize, usize, TokenStream, bool)> = d
                .pairs
                .iter()
                .map(|&(i, k, det, exact)| (i, k, op(det), exact))
                .collect();
            let (fast, fast_label, x) = (names::fast(), names::fast_label(), names::solution());
            let solve = solve::ldlt(&eq, &pairs);
            // The same code over lanes: W members at once, each lane the scalar value bit for bit;
            // where a pivot test fails in any lane, every lane takes the scalar path. Only for a small
            // system (see LANES_MAX_OPS): a larger one's ensembles run members one at a time.
            if code.lets + n * n <= LANES_MAX_OPS || self.force_lanes {
                let lane = codegen::lane_type();
                let (members, params, out) = (
                    names::lane_members(),
                    names::lane_params(),
                    names::lane_out(),
                );
                let lane_code = codegen::emit_as(&d.dag, &d.fields, &d.conds, &outs, Some(&lane));
                let (loads, params_body, count) = codegen::lane_loads(&code, &params, &out);
                let values = &lane_code.values;
                let lane_solve = solve::ldlt_as(&eq, &pairs, Some(&lane));
                let pc = Literal::usize_unsuffixed(count);
                let one_by_one = quote!(::lagrange::__private::lagrangian_lanes_one_by_one(
                    #members, #q, #qdot, #t
                ));
                let ok = names::lane_ok();
                let body = quote! {
                    #touch
                    let #params: &[#lane; #pc] = match <&[#lane; #pc]>::try_from(#params) {
                        ::core::result::Result::Ok(#params) => #params,
                        ::core::result::Result::Err(_) => return #one_by_one,
                    };
                    #loads
                    #values
                    // Every lane runs the whole solve; a lane whose pivot test failed (or whose
                    // values are not finite) takes its member's scalar path, the others keep theirs.
                    let (#x, #ok) = { #lane_solve };
                    if #ok.all() {
                        #x
                    } else {
                        ::lagrange::__private::lagrangian_lanes_patch(#members, #q, #qdot, #t, #x, #ok)
                    }
                };
                let params_body = quote! {
                    if let ::core::option::Option::Some(#out) = #out.get_mut(..#pc) {
                        #params_body
                    }
                };
                lanes = Some((body, params_body, count));
                lane_loads = Some((loads, count));
            }
            let body = quote! {
                #touch
                #stmts
                // The fast path; the arrays for the runtime's solve are only built when it fails.
                let #fast: ::core::option::Option<[f64; #nn]> = #fast_label: { #solve };
                match #fast {
                    ::core::option::Option::Some(#x) => ::core::result::Result::Ok(#x),
                    ::core::option::Option::None => ::lagrange::__private::solve_mass_matrix(
                        &[#(#rows),*],
                        &[#(#f),*],
                        #lagrangian_trait::COORDINATES,
                        #q,
                        #qdot,
                        #t,
                    ),
                }
            };
            (body, inline)
        };
        self.lets += lets;
        Accelerations {
            body: accelerations,
            inline: accelerations_inline,
            lanes,
            lane_loads,
        }
    }

    /// `pieces`: M (upper triangle), f_L and the applied forces (a large system's out of line),
    /// with its inline attribute.
    fn pieces(&mut self) -> (TokenStream, TokenStream) {
        let Gen {
            d,
            n,
            ref nn,
            ref touch,
            ref prefix,
            large,
            ..
        } = *self;
        let op = |id: Id| codegen::operand(&d.dag, &d.fields, id);
        let mut lets = 0;
        let mut items = TokenStream::new();
        let code = (!large).then(|| {
            let mut outs: Vec<Id> = Vec::new();
            for (i, row) in d.mass.iter().enumerate() {
                outs.extend(&row[i..]);
            }
            outs.extend(&d.force);
            outs.extend(&d.applied);
            codegen::emit(&d.dag, &d.fields, &d.conds, &outs)
        });
        // A small `pieces` is inlined where it is called (the constrained right-hand side calls it
        // at every stage, as the integrators call `accelerations`).
        let pieces_inline = match &code {
            Some(code) if code.lets + n * n <= INLINE_ALWAYS_MAX_OPS => quote!(#[inline(always)]),
            _ => quote!(#[inline]),
        };
        let rows = d.mass.iter().enumerate().map(|(i, row)| {
            let cells = row
                .iter()
                .enumerate()
                .map(|(k, &m)| if k < i { quote!(0.0) } else { op(m) });
            quote!([#(#cells),*])
        });
        let f = d.force.iter().map(|&x| op(x));
        let a = d.applied.iter().map(|&x| op(x));
        let conservative = d.applied.iter().all(|&a| a == Dag::ZERO);
        let pieces = if large {
            // M, and f_L with Q − ∂D/∂q̇, each computed by a function in a module of its own (see
            // `out_of_line`): LLVM optimizes them in parallel (and the energy's).
            let mut outs: Vec<Id> = Vec::new();
            for (i, row) in d.mass.iter().enumerate() {
                outs.extend(&row[i..]);
            }
            let code = codegen::emit(&d.dag, &d.fields, &d.conds, &outs);
            lets += code.lets;
            let mass = out_of_line(
                &code,
                format_ident!("{prefix}_mass"),
                nn,
                quote!([[f64; #nn]; #nn]),
                quote!([#(#rows),*]),
                &mut items,
            );
            let mut outs: Vec<Id> = d.force.clone();
            outs.extend(&d.applied);
            let code = codegen::emit(&d.dag, &d.fields, &d.conds, &outs);
            lets += code.lets;
            let force = out_of_line(
                &code,
                format_ident!("{prefix}_force"),
                nn,
                quote!(([f64; #nn], [f64; #nn])),
                quote!(([#(#f),*], [#(#a),*])),
                &mut items,
            );
            let (m, f, a) = (
                format_ident!("__lagrange_mass"),
                format_ident!("__lagrange_lagrangian_force"),
                format_ident!("__lagrange_applied"),
            );
            quote! {
                #touch
                let #m: [[f64; #nn]; #nn] = { #mass };
                let (#f, #a): ([f64; #nn], [f64; #nn]) = { #force };
                ::lagrange::__private::eom::Pieces::new(#m, #f).with_applied(#a)
            }
        } else {
            let new = quote!(::lagrange::__private::eom::Pieces::new([#(#rows),*], [#(#f),*]));
            let stmts = code.map(|c| {
                lets += c.lets;
                c.stmts()
            });
            if conservative {
                quote! {
                    #touch
                    #stmts
                    #new
                }
            } else {
                quote! {
                    #touch
                    #stmts
                    #new.with_applied([#(#a),*])
                }
            }
        };
        self.lets += lets;
        self.items.extend(items);
        (pieces, pieces_inline)
    }

    /// `power`: the power of the applied forces.
    fn power(&mut self) -> TokenStream {
        let Gen { d, ref touch, .. } = *self;
        let op = |id: Id| codegen::operand(&d.dag, &d.fields, id);
        let mut lets = 0;
        let code = codegen::emit(&d.dag, &d.fields, &d.conds, &[d.power]);
        lets += code.lets;
        let w = op(d.power);
        let stmts = code.stmts();
        let power = quote! {
            #touch
            #stmts
            #w
        };
        self.lets += lets;
        power
    }

    /// `mass_matrix`, `momenta` and `energy`; for a large system from `pieces` and
    /// `energy_and_momenta` (one copy of the code of M, of p and of H).
    fn matrix_momenta_energy(&mut self) -> (TokenStream, TokenStream, TokenStream) {
        let Gen {
            d,
            n,
            ref nn,
            ref q,
            ref qdot,
            ref t,
            ref touch,
            ref lagrangian_trait,
            large,
            ..
        } = *self;
        let op = |id: Id| codegen::operand(&d.dag, &d.fields, id);
        let mut lets = 0;
        let (mass_matrix, momenta, energy) = if large {
            (
                quote! {
                    let __lagrange_pieces = #lagrangian_trait::pieces(self, #q, #qdot, #t);
                    ::lagrange::__private::SMatrix::<f64, #nn, #nn>::from_fn(|__lagrange_i, __lagrange_k| {
                        __lagrange_pieces.mass_entry(__lagrange_i, __lagrange_k)
                    })
                },
                quote!(#lagrangian_trait::energy_and_momenta(self, #q, #qdot, #t).1),
                quote!(#lagrangian_trait::energy_and_momenta(self, #q, #qdot, #t).0),
            )
        } else {
            let mut outs: Vec<Id> = Vec::new();
            for (i, row) in d.mass.iter().enumerate() {
                outs.extend(&row[i..]);
            }
            let code = codegen::emit(&d.dag, &d.fields, &d.conds, &outs);
            lets += code.lets;
            let cells = (0..n)
                .flat_map(|i| (0..n).map(move |k| (i, k)))
                .map(|(i, k)| {
                    let id = if k >= i { d.mass[i][k] } else { d.mass[k][i] };
                    op(id)
                });
            let stmts = code.stmts();
            let mass_matrix = quote! {
                #touch
                #stmts
                ::lagrange::__private::SMatrix::<f64, #nn, #nn>::from_row_slice(&[#(#cells),*])
            };
            let code = codegen::emit(&d.dag, &d.fields, &d.conds, &d.momenta);
            lets += code.lets;
            let p = d.momenta.iter().map(|&x| op(x));
            let stmts = code.stmts();
            let momenta = quote! {
                #touch
                #stmts
                [#(#p),*]
            };
            let code = codegen::emit(&d.dag, &d.fields, &d.conds, &[d.energy]);
            lets += code.lets;
            let h = op(d.energy);
            let stmts = code.stmts();
            let energy = quote! {
                #touch
                #stmts
                #h
            };
            (mass_matrix, momenta, energy)
        };
        self.lets += lets;
        (mass_matrix, momenta, energy)
    }

    /// `energy_and_momenta` (what an integrator records every step): shared subexpressions.
    fn energy_and_momenta(&mut self) -> TokenStream {
        let Gen {
            d,
            ref nn,
            ref touch,
            ref prefix,
            large,
            ..
        } = *self;
        let op = |id: Id| codegen::operand(&d.dag, &d.fields, id);
        let mut lets = 0;
        let mut items = TokenStream::new();
        let mut outs = vec![d.energy];
        outs.extend(&d.momenta);
        let code = codegen::emit(&d.dag, &d.fields, &d.conds, &outs);
        lets += code.lets;
        let h = op(d.energy);
        let p = d.momenta.iter().map(|&x| op(x));
        let energy_and_momenta = if large {
            let body = out_of_line(
                &code,
                format_ident!("{prefix}_energy"),
                nn,
                quote!((f64, [f64; #nn])),
                quote!((#h, [#(#p),*])),
                &mut items,
            );
            quote! {
                #touch
                #body
            }
        } else {
            let stmts = code.stmts();
            quote! {
                #touch
                #stmts
                (#h, [#(#p),*])
            }
        };
        self.lets += lets;
        self.items.extend(items);
        energy_and_momenta
    }
}

pub fn output(d: &Derivation, decl: &Decl) -> SymbolicOutput {
    let n = decl.n();
    let names::Params { q, qdot, t } = names::Params::symbolic();
    let nn = Literal::usize_unsuffixed(n);
    let mut gen = Gen {
        d,
        n,
        touch: quote!(let _ = (#q, #qdot, #t);),
        lagrangian_trait: quote!(<Self as ::lagrange::__private::Lagrangian<#nn>>),
        nn,
        q,
        qdot,
        t,
        prefix: module_prefix(&decl.rest.self_ty),
        large: n > LOOP_SOLVE_ABOVE,
        force_lanes: decl.options.lanes.is_some(),
        items: TokenStream::new(),
        lets: 0,
    };
    let Accelerations {
        body: accelerations,
        inline: accelerations_inline,
        lanes,
        lane_loads,
    } = gen.accelerations();
    let (pieces, pieces_inline) = gen.pieces();
    let power = gen.power();
    let (mass_matrix, momenta, energy) = gen.matrix_momenta_energy();
    let energy_and_momenta = gen.energy_and_momenta();
    let (items, lets) = (gen.items, gen.lets);

    let eq = print::equations(d, decl);
    let has_applied = decl.dissipation.is_some() || decl.forces.is_some();
    let law = if has_applied {
        "d/dt ∂L/∂q̇ = ∂L/∂q + Q − ∂D/∂q̇"
    } else {
        "d/dt ∂L/∂q̇ = ∂L/∂q"
    };
    let doc = format!(
        "# Equations of motion\n\nDerived at compile time by `#[lagrangian]` \
         ({law}, one line per coordinate):\n\n```text\n{}\n```\n",
        eq.unicode
    );
    SymbolicOutput {
        items,
        lanes,
        accelerations,
        accelerations_inline,
        pieces,
        pieces_inline,
        power,
        mass_matrix,
        momenta,
        energy,
        energy_and_momenta,
        allow: allow_generated(),
        has_applied,
        taylor: super::taylor::body(
            d,
            n,
            lane_loads
                .as_ref()
                .map(|(loads, count)| super::taylor::LaneLoads {
                    loads,
                    count: *count,
                }),
        ),
        equations: eq.unicode,
        equations_latex: eq.latex,
        doc,
        generated_lets: lets,
    }
}

/// The lint attributes of every generated function (machine-written code).
fn allow_generated() -> TokenStream {
    quote! {
        #[allow(
            unused_variables,
            unused_parens,
            non_snake_case,
            clippy::all,
            clippy::pedantic,
            clippy::nursery
        )]
    }
}

/// The straight-line `code` of a large system as a function `eval` in a module of its own, next to
/// the user's impl (pushed to `items`), and the tokens that load the parameters and call it:
/// rustc optimizes each module that is not inside a function in a codegen unit of its own, so
/// LLVM works on the large bodies in parallel (the methods of one type otherwise share one
/// unit, optimized one after the other). The function reads nothing of the user's scope: only
/// its arguments, `f64` and `::lagrange` paths.
fn out_of_line(
    code: &codegen::Code,
    module: Ident,
    nn: &Literal,
    ret: TokenStream,
    tail: TokenStream,
    items: &mut TokenStream,
) -> TokenStream {
    let names::Params { q, qdot, t } = names::Params::symbolic();
    let params = code.inputs.iter().map(|(x, ty)| quote!(#x: #ty));
    let args = code.inputs.iter().map(|(x, _)| x);
    let (loads, values) = (&code.loads, &code.values);
    let allow = allow_generated();
    items.extend(quote! {
        #[doc(hidden)]
        #[allow(non_snake_case, clippy::all, clippy::pedantic, clippy::nursery)]
        mod #module {
            #allow
            #[inline(never)]
            pub(super) fn eval(
                #(#params,)*
                #q: &[f64; #nn],
                #qdot: &[f64; #nn],
                #t: f64,
            ) -> #ret {
                let _ = (#q, #qdot, #t);
                #values
                #tail
            }
        }
    });
    quote! {
        #loads
        #module::eval(#(#args,)* #q, #qdot, #t)
    }
}

/// The prefix of the modules of [`out_of_line`] for the impl of `self_ty`: the type's last
/// identifier and a hash of its tokens (unique among the impls of one scope).
fn module_prefix(self_ty: &syn::Type) -> String {
    use std::hash::{Hash, Hasher};
    let text = quote!(#self_ty).to_string();
    let mut h = std::collections::hash_map::DefaultHasher::new();
    text.hash(&mut h);
    let ident: String = text
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .rfind(|w| !w.is_empty())
        .unwrap_or("system")
        .to_string();
    format!("__lagrange_{ident}_{:08x}", h.finish() as u32)
}

/// The generated `Lagrangian` methods (inside the trait impl) and the inherent impl with
/// `EQUATIONS` / `EQUATIONS_LATEX` for `self_ty`.
pub fn methods(out: &SymbolicOutput, n: usize, self_ty: &syn::Type) -> (TokenStream, TokenStream) {
    let names::Params { q, qdot, t } = names::Params::symbolic();
    let nn = Literal::usize_unsuffixed(n);
    let SymbolicOutput {
        accelerations,
        accelerations_inline,
        pieces,
        pieces_inline,
        power,
        mass_matrix,
        momenta,
        energy,
        energy_and_momenta,
        allow,
        equations,
        equations_latex,
        doc,
        has_applied,
        taylor,
        items,
        lanes,
        ..
    } = out;
    let sig = quote!(&self, #q: &[f64; #nn], #qdot: &[f64; #nn], #t: f64);
    let methods = quote! {
        #allow
        #accelerations_inline
        fn accelerations(#sig) -> ::core::result::Result<[f64; #nn], ::lagrange::__private::DynamicsError> {
            #accelerations
        }
        #allow
        #pieces_inline
        fn pieces(#sig) -> ::lagrange::__private::eom::Pieces<#nn> {
            #pieces
        }
        #allow
        #[inline]
        fn power(#sig) -> f64 {
            #power
        }
        #allow
        #[inline]
        fn mass_matrix(#sig) -> ::lagrange::__private::SMatrix<f64, #nn, #nn> {
            #mass_matrix
        }
        #allow
        #[inline]
        fn momenta(#sig) -> [f64; #nn] {
            #momenta
        }
        #allow
        #[inline]
        fn energy(#sig) -> f64 {
            #energy
        }
        #allow
        #[inline]
        fn energy_and_momenta(#sig) -> (f64, [f64; #nn]) {
            #energy_and_momenta
        }
    };
    let methods = match lanes {
        Some((body, params_body, count)) => {
            let lane = codegen::lane_type();
            let w = names::lane_width();
            let (members, params, out) = (
                names::lane_members(),
                names::lane_params(),
                names::lane_out(),
            );
            let count = Literal::usize_unsuffixed(*count);
            quote! {
                #methods
                const LANE_PARAMS: usize = #count;
                const VECTORIZED_LANES: bool = true;
                #allow
                #[inline]
                fn lane_params(&self, #out: &mut [f64]) {
                    #params_body
                }
                #allow
                #accelerations_inline
                fn accelerations_lanes<const #w: usize>(
                    #members: &[&Self; #w],
                    #params: &[#lane],
                    #q: &[#lane; #nn],
                    #qdot: &[#lane; #nn],
                    #t: #lane,
                ) -> [#lane; #nn]
                where
                    Self: ::core::marker::Sized,
                {
                    #body
                }
            }
        }
        None => methods,
    };
    let methods = match taylor {
        Ok(series) => {
            let (out, buf) = (names::taylor("out"), names::taylor("buf"));
            let body = &series.scalar;
            let lanes = series.lanes.as_ref().map(|body| {
                let lane = codegen::lane_type();
                let w = names::lane_width();
                let (members, params) = (names::lane_members(), names::lane_params());
                // Inlined into the lanes engine, which is compiled for AVX2 where the CPU has
                // it: out of line, the series would be SSE2 code.
                quote! {
                    #allow
                    #[inline(always)]
                    fn taylor_series_lanes<const #w: usize>(
                        #members: &[&Self; #w],
                        #params: &[#lane],
                        #t: #lane,
                        #out: &mut [[[#lane; #nn]; 2]],
                        #buf: &mut ::lagrange::__private::taylor::SeriesBuf<#lane>,
                    ) -> ::core::option::Option<::lagrange::__private::lanes::Mask<#w>>
                    where
                        Self: ::core::marker::Sized,
                    {
                        #body
                    }
                }
            });
            quote! {
                #methods
                #allow
                fn taylor_series(
                    &self,
                    #t: f64,
                    #out: &mut [[[f64; #nn]; 2]],
                    #buf: &mut ::lagrange::__private::taylor::TaylorBuf,
                ) -> ::core::option::Option<::core::result::Result<(), ::lagrange::__private::DynamicsError>> {
                    #body
                }
                #lanes
            }
        }
        Err(super::taylor::NoSeries::NotAnalytic(what)) => quote! {
            #methods
            const NOT_ANALYTIC: ::core::option::Option<&'static str> =
                ::core::option::Option::Some(#what);
        },
        Err(super::taylor::NoSeries::Unsupported) => methods,
    };
    let form = if *has_applied {
        "`Σₖ Mᵢₖ q̈ₖ = fᵢ + Qᵢ − ∂D/∂q̇ᵢ` (accelerations on the left; on the right the terms of L, \
         then the generalized forces Q, then the dissipative forces −∂D/∂q̇, each as its own group)"
    } else {
        "`Σₖ Mᵢₖ q̈ₖ = fᵢ` (accelerations on the left)"
    };
    let eq_doc = format!(
        "The Euler–Lagrange equations, derived at compile time by `#[lagrangian]`: one line per \
         coordinate, {form}.\n\n```text\n{equations}\n```"
    );
    let latex_doc = "The Euler–Lagrange equations in LaTeX, one line per coordinate (the same \
                     equations as `EQUATIONS`).";
    let consts = quote! {
        #items
        #[doc = #doc]
        impl #self_ty {
            #[doc = #eq_doc]
            pub const EQUATIONS: &'static str = #equations;
            #[doc = #latex_doc]
            pub const EQUATIONS_LATEX: &'static str = #equations_latex;
        }
    };
    (methods, consts)
}
