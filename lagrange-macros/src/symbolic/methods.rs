//! Emit the methods: the bodies of the generated `accelerations`, `mass_matrix`, `momenta`,
//! `energy` and `energy_and_momenta`, and the `EQUATIONS` / `EQUATIONS_LATEX` consts.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::dag::Id;
use super::derive::{Derivation, Equations};
use super::{codegen, print, solve};
use crate::model::{AuxKind, Decl};
use crate::names;

/// Up to this many generated operations (values plus N² for the solve), `accelerations` is
/// `#[inline(always)]`.
const INLINE_ALWAYS_MAX_OPS: usize = 256;

/// What the symbolic path contributes to the generated impl.
pub struct SymbolicOutput {
    /// Body of `fn accelerations(&self, q: &[f64; N], qdot: &[f64; N], t: f64)
    /// -> Result<[f64; N], ::lagrange::__private::DynamicsError>`.
    pub accelerations: TokenStream,
    /// Body of `fn mass_matrix(&self, q, qdot, t) -> ::lagrange::__private::SMatrix<f64, N, N>`.
    pub mass_matrix: TokenStream,
    /// Body of `fn pieces(&self, q, qdot, t) -> ::lagrange::__private::eom::Pieces<N>`.
    pub pieces: TokenStream,
    /// `#[inline(always)]` for a small `accelerations`, `#[inline]` otherwise.
    pub accelerations_inline: TokenStream,
    /// Body of `fn momenta(&self, q, qdot, t) -> [f64; N]`.
    pub momenta: TokenStream,
    /// Body of `fn energy(&self, q, qdot, t) -> f64`.
    pub energy: TokenStream,
    /// Body of `fn energy_and_momenta(&self, q, qdot, t) -> (f64, [f64; N])`.
    pub energy_and_momenta: TokenStream,
    /// Lint attributes to put on each of the five generated methods (machine-written code).
    pub allow: TokenStream,
    /// The Euler–Lagrange equations, plain Unicode, one line per coordinate.
    pub equations: String,
    /// The same equations in LaTeX, one line per coordinate.
    pub equations_latex: String,
    /// A rustdoc section (Markdown) presenting the equations, for the user's type.
    pub doc: String,
    /// Size of the generated code: `let` statements over all five bodies.
    #[cfg_attr(not(test), allow(dead_code))]
    pub generated_lets: usize,
}

/// The bodies of the generated methods and the printed equations of a derivation.
pub fn output(d: &Derivation, decl: &Decl) -> SymbolicOutput {
    let n = decl.n();
    let names::Params { q, qdot, t } = names::Params::symbolic();
    let nn = Literal::usize_unsuffixed(n);
    let touch = quote!(let _ = (#q, #qdot, #t););
    let op = |id: Id| codegen::operand(&d.dag, &d.fields, id);

    // accelerations
    let mut outs: Vec<Id> = Vec::new();
    for (i, row) in d.mass.iter().enumerate() {
        outs.extend(&row[i..]);
    }
    outs.extend(&d.force);
    outs.extend(d.pairs.iter().map(|p| p.2));
    let code = codegen::emit(&d.dag, &d.fields, &d.conds, &outs);
    let mut lets = code.lets;
    // A small right-hand side is inlined at every call site (the twelve stages of DOP853 call
    // it from unrolled code; `#[inline]` alone let LLVM keep it out of line and the whole run
    // was 11 % slower); a large one is left to LLVM so code size stays in bounds.
    let accelerations_inline = if code.lets + n * n <= INLINE_ALWAYS_MAX_OPS {
        quote!(#[inline(always)])
    } else {
        quote!(#[inline])
    };
    // M and f, formed once: the fast path's solve and the fallback's arrays read the same operands.
    let lagrangian_part = Equations::of(d);
    let or_zero = |x: &Option<TokenStream>| x.clone().unwrap_or_else(|| quote!(0.0));
    let rows: Vec<TokenStream> = lagrangian_part
        .mass
        .iter()
        .map(|row| {
            let cells = row.iter().map(or_zero);
            quote!([#(#cells),*])
        })
        .collect();
    let f_lagrangian: Vec<TokenStream> = lagrangian_part.rhs.iter().map(or_zero).collect();
    // With `fn dissipation` / `fn forces`, the right-hand side is f_L + Q − ∂D/∂q̇: the applied
    // forces come from the runtime's one assembly point (`eom::jet_applied_forces`, which
    // evaluates the user's generic `dissipation` and `generalized_forces`), added here once.
    let forced = !decl.aux.is_empty();
    let applied = names::applied();
    let mut eq = lagrangian_part;
    let mut stmts = code.stmts;
    if forced {
        for (i, b) in eq.rhs.iter_mut().enumerate() {
            let i = Literal::usize_unsuffixed(i);
            *b = Some(match b.take() {
                Some(x) => quote!((#x + #applied[#i])),
                None => quote!(#applied[#i]),
            });
        }
        stmts = quote! {
            #stmts
            let #applied: [f64; #nn] =
                ::lagrange::__private::eom::jet_applied_forces(self, #q, #qdot, #t);
        };
    }
    let f = eq.rhs.iter().map(or_zero);
    let pieces_stmts = stmts.clone();
    let pairs: Vec<(usize, usize, TokenStream)> =
        d.pairs.iter().map(|&(i, k, det)| (i, k, op(det))).collect();
    let solve = solve::ldlt(&eq, &pairs);
    let (fast, fast_label, x) = (names::fast(), names::fast_label(), names::solution());
    let accelerations = quote! {
        #touch
        #stmts
        // The fast path; the arrays for the runtime's solve are only built when it fails.
        let #fast: ::core::option::Option<[f64; #nn]> = #fast_label: { #solve };
        match #fast {
            ::core::option::Option::Some(#x) => ::core::result::Result::Ok(#x),
            ::core::option::Option::None => ::lagrange::__private::solve_mass_matrix(
                &[#(#rows),*],
                &[#(#f),*],
                <Self as ::lagrange::__private::Lagrangian<#nn>>::COORDINATES,
                #q,
                #qdot,
                #t,
            ),
        }
    };

    // pieces: M, f_L and the applied forces, for readers of the one assembly point
    let with_applied = if forced {
        quote!(.with_applied(#applied))
    } else {
        quote!()
    };
    let pieces = quote! {
        #touch
        #pieces_stmts
        ::lagrange::__private::eom::Pieces::new([#(#rows),*], [#(#f_lagrangian),*])#with_applied
    };

    // mass_matrix
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
    let stmts = code.stmts;
    let mass_matrix = quote! {
        #touch
        #stmts
        ::lagrange::__private::SMatrix::<f64, #nn, #nn>::from_row_slice(&[#(#cells),*])
    };

    // momenta
    let code = codegen::emit(&d.dag, &d.fields, &d.conds, &d.momenta);
    lets += code.lets;
    let p = d.momenta.iter().map(|&x| op(x));
    let stmts = code.stmts;
    let momenta = quote! {
        #touch
        #stmts
        [#(#p),*]
    };

    // energy
    let code = codegen::emit(&d.dag, &d.fields, &d.conds, &[d.energy]);
    lets += code.lets;
    let h = op(d.energy);
    let stmts = code.stmts;
    let energy = quote! {
        #touch
        #stmts
        #h
    };

    // energy and momenta together (what an integrator records every step): shared subexpressions
    let mut outs = vec![d.energy];
    outs.extend(&d.momenta);
    let code = codegen::emit(&d.dag, &d.fields, &d.conds, &outs);
    lets += code.lets;
    let h = op(d.energy);
    let p = d.momenta.iter().map(|&x| op(x));
    let stmts = code.stmts;
    let energy_and_momenta = quote! {
        #touch
        #stmts
        (#h, [#(#p),*])
    };

    let mut eq = print::equations(d, decl);
    if forced {
        let (unicode, latex) = applied_text(decl);
        eq.unicode.push_str(&unicode);
        eq.latex.push_str(&latex);
    }
    let doc = format!(
        "# Equations of motion\n\nDerived at compile time by `#[lagrangian]` \
         (d/dt ∂L/∂q̇ = ∂L/∂q, one line per coordinate):\n\n```text\n{}\n```\n",
        eq.unicode
    );
    SymbolicOutput {
        accelerations,
        accelerations_inline,
        mass_matrix,
        pieces,
        momenta,
        energy,
        energy_and_momenta,
        allow: quote! {
            #[allow(
                unused_variables,
                unused_parens,
                non_snake_case,
                clippy::all,
                clippy::pedantic,
                clippy::nursery
            )]
        },
        equations: eq.unicode,
        equations_latex: eq.latex,
        doc,
        generated_lets: lets,
    }
}

/// The five generated `Lagrangian` methods (inside the trait impl) and the inherent impl with
/// `EQUATIONS` / `EQUATIONS_LATEX` for `self_ty`.
pub fn methods(out: &SymbolicOutput, n: usize, self_ty: &syn::Type) -> (TokenStream, TokenStream) {
    let names::Params { q, qdot, t } = names::Params::symbolic();
    let nn = Literal::usize_unsuffixed(n);
    let SymbolicOutput {
        accelerations,
        accelerations_inline,
        mass_matrix,
        pieces,
        momenta,
        energy,
        energy_and_momenta,
        allow,
        equations,
        equations_latex,
        doc,
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
        #[inline]
        fn mass_matrix(#sig) -> ::lagrange::__private::SMatrix<f64, #nn, #nn> {
            #mass_matrix
        }
        #allow
        #[inline]
        fn pieces(#sig) -> ::lagrange::__private::eom::Pieces<#nn> {
            #pieces
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
    let eq_doc = format!(
        "The Euler–Lagrange equations, derived at compile time by `#[lagrangian]`: one line per \
         coordinate, `Σₖ Mᵢₖ q̈ₖ = fᵢ` (accelerations on the left).\n\n```text\n{equations}\n```"
    );
    let latex_doc = "The Euler–Lagrange equations in LaTeX, one line per coordinate (the same \
                     equations as `EQUATIONS`).";
    let consts = quote! {
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

/// The applied forces as printed under the equations: each line gets `+ Q − ∂D/∂q̇` on its right
/// (written once, below the equations), with D and Q as the user wrote them.
fn applied_text(decl: &Decl) -> (String, String) {
    let mut unicode =
        String::from("\nwith the applied forces added to each right-hand side, + Qᵢ − ∂D/∂q̇ᵢ:");
    let mut latex = String::from("\n\\text{with } + Q_i - \\partial D / \\partial \\dot q_i \\text{ on each right-hand side:}");
    for a in &decl.aux {
        let text = tidy(&a.body);
        let (u, l) = match a.kind {
            AuxKind::Dissipation => ("D", "D"),
            AuxKind::Forces => ("Q", "Q"),
        };
        unicode.push_str(&format!("\n  {u} = {text}"));
        latex.push_str(&format!("\n{l} = \\texttt{{{}}}", text.replace('_', "\\_")));
    }
    (unicode, latex)
}

/// A body as one line of Rust: its tail expression (or the whole block when it has statements),
/// with the token spacing of `quote` tidied (`self.b * x.powi(2)`, not `self . b * x . powi (2)`).
fn tidy(body: &syn::Block) -> String {
    let tokens = match body.stmts.as_slice() {
        [syn::Stmt::Expr(e, None)] => quote!(#e).to_string(),
        _ => quote!(#body).to_string(),
    };
    let tokens = tokens
        .replace(" . ", ".")
        .replace("( ", "(")
        .replace(" )", ")")
        .replace(" ,", ",")
        .replace("[ ", "[")
        .replace(" ]", "]");
    // A call's parenthesis joins its name (`powi(2)`); an operator's keeps its space (`* (`).
    let mut out = String::with_capacity(tokens.len());
    let chars: Vec<char> = tokens.chars().collect();
    for (k, &c) in chars.iter().enumerate() {
        let call = c == ' '
            && chars.get(k + 1) == Some(&'(')
            && k > 0
            && (chars[k - 1].is_alphanumeric() || chars[k - 1] == '_');
        if !call {
            out.push(c);
        }
    }
    out
}
