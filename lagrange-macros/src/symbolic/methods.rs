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
    /// The conservation flags read from the derived expressions (the macro ORs them with the
    /// rule by names).
    pub symmetry: super::derive::Symmetry,
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
    /// Whether the kernels module has the Taylor series (`series_in`): where every node has a
    /// Taylor rule and the body is analytic; else why not.
    pub taylor: Result<(), super::taylor::NoSeries>,
    /// Whether the lanes run the generic q̈ kernel (`accelerations_in`; a small system).
    pub lanes: bool,
    /// The body of the inherent `__lagrange_params(&self) -> [f64; P]`, P and the slots' field
    /// names ([`codegen::KernelParams::names`]), where there are generic kernels.
    pub params: Option<(TokenStream, usize, Vec<String>)>,
    /// Items to emit next to the user's impl: the generic kernels' module and the modules of a
    /// large system's out-of-line bodies.
    pub items: TokenStream,
    /// Whether the system has `fn dissipation` or `fn forces` (the docs then name Q and D).
    pub has_applied: bool,
    /// The Euler–Lagrange equations, plain Unicode, one line per coordinate.
    pub equations: String,
    /// The same equations in LaTeX, one line per coordinate.
    pub equations_latex: String,
    /// A rustdoc section (Markdown) presenting the equations, for the user's type.
    pub doc: String,
    /// Size of the generated code: `let` statements over all the bodies.
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
    /// The generic kernels' statements binding their parameters ([`codegen::KernelParams`]).
    binds: TokenStream,
    /// Items next to the impl (the modules of `out_of_line`).
    items: TokenStream,
    /// `let` statements over all the bodies.
    lets: usize,
}

/// The body of `accelerations` and its inline attribute; the generic kernel (for a small
/// system) and whether the lanes run it.
struct Accelerations {
    body: TokenStream,
    inline: TokenStream,
    /// `fn accelerations<R: Real>(params, q, qdot, t) -> (q̈, ok, M, f)` of the kernels module.
    kernel: Option<TokenStream>,
    lanes: bool,
}

impl Gen<'_> {
    /// The kernels module's path, its parameters' names and the generic `R`.
    fn kernel_names(&self) -> (Ident, Ident, TokenStream) {
        (
            format_ident!("{}_kernels", self.prefix),
            names::lane_params(),
            codegen::real_type(),
        )
    }

    /// `accelerations`: for a small system the generic kernel (the unrolled solve with its
    /// per-lane pivot tests) at `f64`, with the runtime's careful solve where a test fails; for a
    /// large system the runtime's solve of `pieces`.
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
        if large {
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
            return Accelerations {
                body,
                inline: quote!(#[inline]),
                kernel: None,
                lanes: false,
            };
        }
        let (module, params, r) = self.kernel_names();
        let mut outs: Vec<Id> = Vec::new();
        for (i, row) in d.mass.iter().enumerate() {
            outs.extend(&row[i..]);
        }
        outs.extend(&d.rhs);
        outs.extend(d.pairs.iter().map(|p| p.2));
        let code = codegen::emit_as(&d.dag, &d.fields, &d.conds, &outs, Some(&r));
        self.lets += code.lets;
        // A small right-hand side is inlined at every call site (the twelve stages of DOP853
        // call it from unrolled code; `#[inline]` alone let LLVM keep it out of line and the
        // whole run was 11 % slower); a large one is left to LLVM so code size stays in bounds.
        let inline = if code.lets + n * n <= INLINE_ALWAYS_MAX_OPS {
            quote!(#[inline(always)])
        } else {
            quote!(#[inline])
        };
        // M and the right-hand side, formed once: the solve and the careful path's arrays read
        // the same operands.
        let eq = Equations::of(d, &r);
        let zero = codegen::real_const(&r, &quote!(0.0));
        let or_zero = |x: &Option<TokenStream>| x.clone().unwrap_or_else(|| zero.clone());
        let rows = eq.mass.iter().map(|row| {
            let cells = row.iter().map(or_zero);
            quote!([#(#cells),*])
        });
        let f = eq.rhs.iter().map(or_zero);
        let pairs: Vec<(usize, usize, TokenStream, bool)> = d
            .pairs
            .iter()
            .map(|&(i, k, det, exact)| {
                (
                    i,
                    k,
                    codegen::operand_as(&d.dag, &d.fields, det, Some(&r)),
                    exact,
                )
            })
            .collect();
        let solve = solve::ldlt(&eq, &pairs, &r);
        let (x, ok, fast_label) = (names::solution(), names::lane_ok(), names::fast_label());
        let (values, binds) = (&code.values, &self.binds);
        let rt = quote!(::lagrange::__private::Real);
        let kernel = quote! {
            /// q̈ from M q̈ = f (the straight-line LDLᵀ) and the lanes where every pivot test
            /// passed and every value is finite, handed to `done`; where that declines, M (upper
            /// triangle) and f to `careful` (formed only on that path).
            #inline
            pub(super) fn accelerations<#r: #rt, O>(
                #params: &[#r; PARAMS],
                #q: &[#r; #nn],
                #qdot: &[#r; #nn],
                #t: #r,
                done: impl FnOnce([#r; #nn], <#r as #rt>::Mask) -> ::core::option::Option<O>,
                careful: impl FnOnce(&[[#r; #nn]; #nn], &[#r; #nn]) -> O,
            ) -> O {
                let _ = (#q, #qdot, #t);
                #binds
                #values
                let (#x, #ok) = #fast_label: { #solve };
                match done(#x, #ok) {
                    ::core::option::Option::Some(o) => o,
                    ::core::option::Option::None => careful(&[#(#rows),*], &[#(#f),*]),
                }
            }
        };
        // The lanes code: only for a small system (see LANES_MAX_OPS); a larger one's ensembles
        // run members one at a time.
        let lanes = code.lets + n * n <= LANES_MAX_OPS || self.force_lanes;
        let (m, fv) = (format_ident!("__lagrange_m"), format_ident!("__lagrange_f"));
        let body = quote! {
            #module::accelerations::<f64, _>(
                &Self::__lagrange_params(self),
                #q,
                #qdot,
                #t,
                |#x, #ok| #ok.then_some(::core::result::Result::Ok(#x)),
                |#m, #fv| {
                    ::lagrange::__private::solve_mass_matrix(
                        #m,
                        #fv,
                        #lagrangian_trait::COORDINATES,
                        #q,
                        #qdot,
                        #t,
                    )
                },
            )
        };
        Accelerations {
            body,
            inline,
            kernel: Some(kernel),
            lanes,
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
            // h is the same DAG node in `energy_and_momenta`: the same value bit for bit, and
            // the momenta it also computes are most of h's cost (h = q̇·p − L).
            let energy = quote!(#lagrangian_trait::energy_and_momenta(self, #q, #qdot, #t).0);
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
    let params = codegen::kernel_params(&d.dag, &d.fields, &d.conds, &names::lane_params());
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
        binds: params.binds.clone(),
        items: TokenStream::new(),
        lets: 0,
    };
    let Accelerations {
        body: accelerations,
        inline: accelerations_inline,
        kernel,
        lanes,
    } = gen.accelerations();
    let (pieces, pieces_inline) = gen.pieces();
    let power = gen.power();
    let (mass_matrix, momenta, energy) = gen.matrix_momenta_energy();
    let energy_and_momenta = gen.energy_and_momenta();
    let taylor = super::taylor::body(d, n, &params.binds);
    // The generic kernels (q̈ of a small system, the Taylor series) in a module next to the impl,
    // with the number of parameters they read.
    let (module, _, _) = gen.kernel_names();
    let series = taylor.as_ref().ok();
    let kernels = (kernel.is_some() || series.is_some()).then(|| {
        let count = Literal::usize_unsuffixed(params.count);
        let allow = allow_generated();
        quote! {
            #[doc(hidden)]
            #allow
            mod #module {
                /// How many numbers `__lagrange_params` loads (the kernels' parameters).
                pub(super) const PARAMS: usize = #count;
                #kernel
                #series
            }
        }
    });
    let params_load = kernels
        .as_ref()
        .map(|_| (params.load.clone(), params.count, params.names.clone()));
    gen.items.extend(kernels);
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
        symmetry: d.symmetry.clone(),
        items,
        lanes,
        params: params_load,
        accelerations,
        accelerations_inline,
        pieces,
        pieces_inline,
        power,
        mass_matrix,
        momenta,
        energy,
        energy_and_momenta,
        has_applied,
        taylor: taylor.map(|_| ()),
        equations: eq.unicode,
        equations_latex: eq.latex,
        doc,
        generated_lets: lets,
    }
}

/// The lint attributes of every generated function (machine-written code).
fn allow_generated() -> TokenStream {
    let mut allow = names::allow_generated();
    allow.extend(quote!(#[allow(unused_variables)]));
    allow
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

/// What the printed equations of a constrained system add to L's: per coordinate slot, whether
/// the holonomic constraints read its position (a term λ·∂g/∂q of the constraint force Gᵀλ) and
/// whether the velocity constraints read its velocity (λ·∂c/∂q̇ of Aᵀλ), and the constraints
/// as written.
#[derive(Default)]
pub struct ConstraintTerms {
    /// Per slot: G's column is not zero.
    pub holonomic: Vec<bool>,
    /// Per slot: A's column is not zero.
    pub velocity: Vec<bool>,
    /// The entries of `fn constraints`, as written (`None` without it).
    pub g: Option<Vec<String>>,
    /// The entries of `fn velocity_constraints`, as written.
    pub c: Option<Vec<String>>,
}

impl ConstraintTerms {
    /// The equations (one line per coordinate, `label: lhs = rhs` or in LaTeX `lhs = rhs`, the
    /// coordinates' `labels` in slot order) with the constraint forces' terms on the right and
    /// the constraints after them; unchanged without constraints.
    pub fn apply(&self, equations: &str, labels: &[String], latex: bool) -> String {
        if self.g.is_none() && self.c.is_none() {
            return equations.to_owned();
        }
        let both = self.g.is_some() && self.c.is_some();
        let (lg, lc) = match (both, latex) {
            (true, false) => ("λ_g", "λ_c"),
            (true, true) => ("\\lambda_g", "\\lambda_c"),
            (false, false) => ("λ", "λ"),
            (false, true) => ("\\lambda", "\\lambda"),
        };
        let mut out = String::new();
        let mut lines = equations.lines();
        for (i, label) in labels.iter().enumerate() {
            let Some(line) = lines.next() else { break };
            out.push_str(line);
            // A coordinate's line (not "… more equations, too large to print").
            let coordinate = latex || line.starts_with(&format!("{label}: "));
            if coordinate && self.holonomic.get(i) == Some(&true) {
                out.push_str(&if latex {
                    format!(" + {lg} \\cdot \\partial g / \\partial q_{{{i}}}")
                } else {
                    format!(" + {lg}·∂g/∂{label}")
                });
            }
            if coordinate && self.velocity.get(i) == Some(&true) {
                out.push_str(&if latex {
                    format!(" + {lc} \\cdot \\partial c / \\partial \\dot q_{{{i}}}")
                } else {
                    format!(" + {lc}·∂c/∂{label}\u{307}")
                });
            }
            out.push('\n');
        }
        for line in lines {
            out.push_str(line);
            out.push('\n');
        }
        let list = |entries: &[String]| entries.join(", ");
        if let Some(g) = &self.g {
            out.push_str(&if latex {
                format!(
                    "\\text{{with }} g(q, t) = [\\texttt{{{}}}] = 0",
                    latex_text(&list(g))
                )
            } else {
                format!(
                    "with g(q, t) = [{}] = 0 (fn constraints; {lg} its multipliers)",
                    list(g)
                )
            });
            out.push('\n');
        }
        if let Some(c) = &self.c {
            out.push_str(&if latex {
                format!(
                    "\\text{{with }} c(q, \\dot q, t) = [\\texttt{{{}}}] = 0",
                    latex_text(&list(c))
                )
            } else {
                format!(
                    "with c(q, q̇, t) = [{}] = 0 (fn velocity_constraints; {lc} its multipliers)",
                    list(c)
                )
            });
            out.push('\n');
        }
        out.trim_end().to_owned()
    }
}

/// Source text inside LaTeX's `\texttt`: its special characters escaped.
fn latex_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '_' | '&' | '%' | '$' | '#' | '{' | '}' => {
                out.push('\\');
                out.push(ch);
            }
            _ => out.push(ch),
        }
    }
    out
}

/// The generated `Lagrangian` methods (inside the trait impl) and the inherent impl with
/// `EQUATIONS` / `EQUATIONS_LATEX` for `self_ty` (with the constraint forces' terms and the
/// constraints of `terms`).
pub fn methods(
    out: &SymbolicOutput,
    n: usize,
    self_ty: &syn::Type,
    terms: &ConstraintTerms,
    labels: &[String],
) -> (TokenStream, TokenStream) {
    let constrained = terms.g.is_some() || terms.c.is_some();
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
        equations: plain_equations,
        equations_latex,
        doc,
        has_applied,
        taylor,
        items,
        lanes,
        params: params_load,
        ..
    } = out;
    let sig = quote!(&self, #q: &[f64; #nn], #qdot: &[f64; #nn], #t: f64);
    let methods = quote! {
        #accelerations_inline
        fn accelerations(#sig) -> ::core::result::Result<[f64; #nn], ::lagrange::__private::DynamicsError> {
            #accelerations
        }
        #pieces_inline
        fn pieces(#sig) -> ::lagrange::__private::eom::Pieces<#nn> {
            #pieces
        }
        #[inline]
        fn power(#sig) -> f64 {
            #power
        }
        #[inline]
        fn mass_matrix(#sig) -> ::lagrange::__private::SMatrix<f64, #nn, #nn> {
            #mass_matrix
        }
        #[inline]
        fn momenta(#sig) -> [f64; #nn] {
            #momenta
        }
        #[inline]
        fn energy(#sig) -> f64 {
            #energy
        }
        #[inline]
        fn energy_and_momenta(#sig) -> (f64, [f64; #nn]) {
            #energy_and_momenta
        }
    };
    let (members, params) = (names::lane_members(), names::lane_params());
    let r = codegen::real_type();
    let rt = quote!(::lagrange::__private::Real);
    let module = format_ident!("{}_kernels", module_prefix(self_ty));
    // The kernels' parameters: loaded into the kernel's array where it is empty.
    let load = quote! {
        ::lagrange::__private::kernel_params(#members, #params, Self::__lagrange_params)?
    };
    let mut methods = methods;
    if *lanes {
        methods.extend(quote! {
            #[inline(always)]
            fn accelerations_in<#r: #rt>(
                #members: &[&Self],
                #params: &mut ::std::vec::Vec<#r>,
                #q: &[#r; #nn],
                #qdot: &[#r; #nn],
                #t: #r,
            ) -> ::core::option::Option<([#r; #nn], <#r as #rt>::Mask)> {
                ::core::option::Option::Some(#module::accelerations::<#r, _>(
                    #load,
                    #q,
                    #qdot,
                    #t,
                    |__lagrange_x, __lagrange_ok| ::core::option::Option::Some((__lagrange_x, __lagrange_ok)),
                    |_, _| ([<#r as #rt>::NAN; #nn], <#r as #rt>::finite(<#r as #rt>::NAN)),
                ))
            }
        });
    }
    let not_analytic = match taylor {
        Ok(()) => {
            let (out, buf) = (names::taylor("out"), names::taylor("buf"));
            // Inlined into the lanes engine, which is compiled for AVX2 where the CPU has it: out
            // of line, the lanes series would be SSE2 code.
            methods.extend(quote! {
                #[inline(always)]
                fn series_in<#r: ::lagrange::__private::eom::SeriesReal>(
                    #members: &[&Self],
                    #params: &mut ::std::vec::Vec<#r>,
                    #t: #r,
                    #out: &mut [[[#r; #nn]; 2]],
                    #buf: &mut ::lagrange::__private::taylor::SeriesBuf<#r>,
                ) -> ::core::option::Option<
                    ::core::result::Result<<#r as #rt>::Mask, ::lagrange::__private::DynamicsError>,
                > {
                    ::core::option::Option::Some(#module::series::<#r>(
                        #load,
                        <Self as ::lagrange::__private::Lagrangian<#nn>>::COORDINATES,
                        #t,
                        #out,
                        #buf,
                    ))
                }
            });
            None
        }
        Err(super::taylor::NoSeries::NotAnalytic(what)) => Some(*what),
        Err(super::taylor::NoSeries::Unsupported) => None,
    };
    if *lanes || not_analytic.is_some() || constrained {
        let not_analytic = match not_analytic {
            Some(what) => quote!(::core::option::Option::Some(#what)),
            None => quote!(::core::option::Option::None),
        };
        methods.extend(quote! {
            const COMPILED: ::lagrange::__private::Compiled = ::lagrange::__private::Compiled {
                lanes: #lanes,
                not_analytic: #not_analytic,
                constrained: #constrained,
            };
        });
    }
    if let Some((_, _, names)) = params_load.as_ref() {
        // The kernels' parameters by field, for exact parameter derivatives (a slot seeded in
        // tangents).
        methods.extend(quote! {
            const KERNEL_FIELDS: &'static [&'static str] = &[#(#names),*];
        });
    }
    let params_fn = params_load.as_ref().map(|(body, count, _)| {
        let count = Literal::usize_unsuffixed(*count);
        quote! {
            /// The parameters of the generic kernels, loaded from `self`.
            #[doc(hidden)]
            #[inline(always)]
            fn __lagrange_params(&self) -> [f64; #count] {
                #body
            }
        }
    });
    let equations = terms.apply(plain_equations, labels, false);
    let equations_latex = terms.apply(equations_latex, labels, true);
    let doc = doc.replace(plain_equations.as_str(), &equations);
    let form = if *has_applied {
        "`Σₖ Mᵢₖ q̈ₖ = fᵢ + Qᵢ − ∂D/∂q̇ᵢ` (accelerations on the left; on the right the terms of L, \
         then the generalized forces Q, then the dissipative forces −∂D/∂q̇, each as its own group)"
    } else {
        "`Σₖ Mᵢₖ q̈ₖ = fᵢ` (accelerations on the left)"
    };
    let with = if constrained {
        ", plus the constraint forces (λ·∂g/∂q for `fn constraints`, λ·∂c/∂q̇ for \
         `fn velocity_constraints`, with λ the multipliers a run records) and the constraints \
         after the equations"
    } else {
        ""
    };
    let eq_doc = format!(
        "The Euler–Lagrange equations, derived at compile time by `#[lagrangian]`: one line per \
         coordinate, {form}{with}.\n\n```text\n{equations}\n```"
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
            #params_fn
        }
    };
    (methods, consts)
}
