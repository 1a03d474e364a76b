//! Compile-time derivation (`mode = "symbolic"`, the default): the body of `fn lagrangian` is
//! lowered into a hash-consed expression DAG, differentiated symbolically (forward-mode tangents
//! over the DAG, structural zeros skipped), and emitted as straight-line Rust for the mass matrix,
//! the right-hand side of the Euler–Lagrange equations, the momenta and the energy; the equations
//! are also printed for people (Unicode and LaTeX). M q̈ = f is solved by straight-line LDLᵀ,
//! except that a 2×2 block of M coupled to nothing else is solved by Cramer's rule with its
//! determinant simplified where its terms cancel (`poly.rs`; exact near chart singularities).
//!
//! An `if` whose condition uses only constants (`self` fields, literals, names from the user's
//! scope; no coordinate, velocity, time or local binding) is supported: the condition is
//! evaluated once per call as `let b_k: bool = <condition as written>;`, both branches are
//! lowered, and every value that differs between them becomes `Node::Select(k, a, b)`, emitted as
//! `if b_k { a } else { b }` and differentiated branch by branch. The equations print it as
//! `(a if cond else b)` (LaTeX: `\left(a \;\text{if}\; \texttt{cond} \;\text{else}\; b\right)`).
//! A condition on the state is an error at the offending name that says to use `mode = "jets"`.
// Index loops mirror the textbook elimination formulas; iterator forms would obscure them.
#![allow(clippy::needless_range_loop)]

mod codegen;
mod dag;
mod lower;
mod poly;
mod print;
#[cfg(test)]
mod tests;

use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

use crate::model::Decl;
use crate::names;
use dag::{Dag, Id, Node, VarSet};

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

/// The derivatives of L as DAG nodes.
struct Derivation {
    dag: Dag,
    fields: Vec<lower::Field>,
    /// Conditions of constant `if`s (`Node::Select`).
    conds: Vec<lower::Cond>,
    #[cfg_attr(not(test), allow(dead_code))]
    lagrangian: Id,
    /// ∂L/∂q̇ᵢ.
    momenta: Vec<Id>,
    /// Mᵢₖ = ∂²L/∂q̇ᵢ∂q̇ₖ, upper triangle (`m[i][k]`, k ≥ i; zeros below).
    mass: Vec<Vec<Id>>,
    /// fᵢ = ∂L/∂qᵢ − Σₖ (∂²L/∂q̇ᵢ∂qₖ) q̇ₖ − ∂²L/∂q̇ᵢ∂t.
    force: Vec<Id>,
    /// h = Σ q̇ᵢ pᵢ − L.
    energy: Id,
    /// The 2×2 diagonal blocks of M coupled to nothing else, (i, k, det), i < k: solved by
    /// Cramer's rule with the determinant expanded and cancelled (see `poly::det2`).
    pairs: Vec<(usize, usize, Id)>,
}

/// The 2×2 blocks {i, k} of M (upper triangle) that no other coordinate couples to.
fn decoupled_pairs(mass: &[Vec<Id>]) -> Vec<(usize, usize)> {
    let n = mass.len();
    let coupled = |i: usize, k: usize| {
        let (a, b) = if i < k { (i, k) } else { (k, i) };
        mass[a][b] != Dag::ZERO
    };
    let mut pairs = Vec::new();
    for i in 0..n {
        for k in i + 1..n {
            if coupled(i, k)
                && (0..n)
                    .filter(|&j| j != i && j != k)
                    .all(|j| !coupled(i, j) && !coupled(k, j))
            {
                pairs.push((i, k));
            }
        }
    }
    pairs
}

fn derive(decl: &Decl) -> Result<Derivation, Vec<syn::Error>> {
    let lowered = lower::lower(decl)?;
    let mut dag = lowered.dag;
    let l = lowered.lagrangian;
    let n = decl.n();
    let vars = dag.vars;
    let unit = |var: usize| {
        let mut s = VarSet::new(vars);
        s.insert(var);
        s
    };
    let mut momenta = Vec::with_capacity(n);
    for i in 0..n {
        let p = dag.tangents(&[l], &unit(vars.v(i)), &|_, node| {
            (node == Node::V(i as u32)).then_some(Dag::ONE)
        });
        momenta.push(p[0]);
    }
    let mut mass = vec![vec![Dag::ZERO; n]; n];
    for k in 0..n {
        let col = dag.tangents(&momenta[..=k], &unit(vars.v(k)), &|_, node| {
            (node == Node::V(k as u32)).then_some(Dag::ONE)
        });
        for (i, m) in col.into_iter().enumerate() {
            mass[i][k] = m;
        }
    }
    // The total time derivative of the momenta at fixed q̇: Σₖ q̇ₖ ∂/∂qₖ + ∂/∂t.
    let mut along = VarSet::new(vars);
    for k in 0..n {
        along.insert(vars.q(k));
    }
    along.insert(vars.t());
    let dp = dag.tangents(&momenta, &along, &|dag, node| match node {
        Node::Q(k) => Some(dag.v(k as usize)),
        Node::T => Some(Dag::ONE),
        _ => None,
    });
    let mut force = Vec::with_capacity(n);
    for (i, dpi) in dp.into_iter().enumerate() {
        let g = dag.tangents(&[l], &unit(vars.q(i)), &|_, node| {
            (node == Node::Q(i as u32)).then_some(Dag::ONE)
        });
        force.push(dag.sub(g[0], dpi));
    }
    let mut energy = dag.neg(l);
    for (i, &p) in momenta.iter().enumerate() {
        let v = dag.v(i);
        let vp = dag.mul(v, p);
        energy = dag.add(energy, vp);
    }
    let pairs = decoupled_pairs(&mass)
        .into_iter()
        .map(|(i, k)| {
            (
                i,
                k,
                poly::det2(&mut dag, mass[i][i], mass[k][k], mass[i][k]),
            )
        })
        .collect();
    Ok(Derivation {
        pairs,
        dag,
        fields: lowered.fields,
        conds: lowered.conds,
        lagrangian: l,
        momenta,
        mass,
        force,
        energy,
    })
}

/// Straight-line LDLᵀ of the mass matrix (upper triangle, `None` = structural zero) with the
/// sparsity known at compile time: the same elimination, in the same order, as the runtime's
/// `solve_symmetric`, with the structurally zero products left out and one reciprocal per pivot
/// whose row of L has two or more entries; the decoupled 2×2 blocks in `pairs` by Cramer's rule
/// instead (see [`cramer`]). The tokens are the statements of a block labelled `'fast` that
/// evaluates to `Some(q̈)`, or breaks with `None` whenever a pivot is not clearly positive (or
/// anything is not finite); the caller then hands over to `solve_mass_matrix`, which decides
/// between LU and a `DynamicsError` exactly as the jets path.
fn ldlt(
    m: &[Vec<Option<TokenStream>>],
    b: &[Option<TokenStream>],
    pairs: &[(usize, usize, TokenStream)],
) -> TokenStream {
    let n = m.len();
    // Indices solved as a decoupled 2×2 block (Cramer) instead of by the elimination.
    let mut paired = vec![false; n];
    for &(i, k, _) in pairs {
        paired[i] = true;
        paired[k] = true;
    }
    let a_id = names::ldl_l;
    let d_id = names::ldl_d;
    let r_id = names::ldl_r;
    let u_id = names::ldl_u;
    let x_id = names::solve_y;
    let (scale_id, tol, fast) = (names::scale(), names::tol(), names::fast_label());
    let (max, [acc, a]) = (names::max(), names::max_args());
    let mut out = TokenStream::new();
    // The largest diagonal magnitude (a NaN on the diagonal is caught by its pivot test).
    let mut scale = quote!(0.0_f64);
    for j in 0..n {
        if let Some(e) = &m[j][j] {
            scale = quote!(#max(#scale, f64::abs(#e)));
        }
    }
    out.extend(quote! {
        let #max = |#acc: f64, #a: f64| if #a > #acc { #a } else { #acc };
        let #scale_id: f64 = #scale;
        let #tol = ::lagrange::__private::linalg::SINGULAR_RELATIVE_PIVOT * #scale_id;
    });
    // l[j][i] (i > j): true when not structurally zero.
    let mut l: Vec<Vec<bool>> = vec![vec![false; n]; n];
    // Whether pivot j has a reciprocal `r_j` (used by its row of l and by y_j).
    let mut recip = vec![false; n];
    for (i, k, det) in pairs {
        out.extend(cramer(m, b, *i, *k, det));
    }
    for j in 0..n {
        if paired[j] {
            continue;
        }
        let dj = d_id(j);
        let mut e = match &m[j][j] {
            Some(x) => quote!(#x),
            None => quote!(0.0_f64),
        };
        // l_kj² d_k = l_kj u_kj, with u_kj = l_kj d_k the row before its division.
        for k in 0..j {
            if l[k][j] {
                let (lk, uk) = (a_id(k, j), u_id(k, j));
                e = quote!(#e - #lk * #uk);
            }
        }
        out.extend(quote! {
            let #dj: f64 = #e;
            if !(#dj > #tol) {
                break #fast ::core::option::Option::None;
            }
        });
        // (i, u_ji, its value)
        let mut row: Vec<(usize, Ident, TokenStream)> = Vec::new();
        for i in j + 1..n {
            let mut terms = Vec::new();
            for k in 0..j {
                if l[k][j] && l[k][i] {
                    let (lkj, uki) = (a_id(k, j), u_id(k, i));
                    terms.push(quote!(#lkj * #uki));
                }
            }
            if m[j][i].is_none() && terms.is_empty() {
                continue;
            }
            let mut s = match &m[j][i] {
                Some(x) => quote!(#x),
                None => quote!(0.0_f64),
            };
            for t in terms {
                s = quote!(#s - #t);
            }
            row.push((i, u_id(j, i), s));
            l[j][i] = true;
        }
        // A reciprocal adds a multiplication to the (latency-bound) critical path; it pays off
        // only when it replaces several divisions.
        let rj = r_id(j);
        if row.len() >= 2 {
            recip[j] = true;
            out.extend(quote!(let #rj: f64 = 1.0 / #dj;));
        }
        // Two `let`s per row keep the scope nesting shallow (see codegen): the row before its
        // division by the pivot (u), then L's row.
        if !row.is_empty() {
            let us: Vec<Ident> = row.iter().map(|(_, x, _)| x.clone()).collect();
            let ls = row.iter().map(|&(i, _, _)| a_id(j, i));
            let tys: Vec<TokenStream> = row.iter().map(|_| quote!(f64)).collect();
            let es = row.iter().map(|(_, _, e)| e);
            out.extend(quote!(let (#(#us,)*): (#(#tys,)*) = (#(#es,)*);));
            let divided = us.iter().map(|u| {
                if recip[j] {
                    quote!(#u * #rj)
                } else {
                    quote!(#u / #dj)
                }
            });
            out.extend(quote!(let (#(#ls,)*): (#(#tys,)*) = (#(#divided,)*);));
        }
    }
    for i in (0..n).filter(|&i| !paired[i]) {
        let xi = x_id(i);
        let mut e = match &b[i] {
            Some(x) => quote!(#x),
            None => quote!(0.0_f64),
        };
        for k in 0..i {
            if l[k][i] {
                let (lki, xk) = (a_id(k, i), x_id(k));
                e = quote!(#e - #lki * #xk);
            }
        }
        out.extend(quote!(let #xi: f64 = #e;));
    }
    for i in (0..n).filter(|&i| !paired[i]) {
        let (xi, di, ri) = (x_id(i), d_id(i), r_id(i));
        if recip[i] {
            out.extend(quote!(let #xi: f64 = #xi * #ri;));
        } else {
            out.extend(quote!(let #xi: f64 = #xi / #di;));
        }
    }
    for i in (0..n).rev() {
        let xi = x_id(i);
        let mut e = quote!(#xi);
        let mut any = false;
        for k in i + 1..n {
            if l[i][k] {
                let (lik, xk) = (a_id(i, k), x_id(k));
                e = quote!(#e - #lik * #xk);
                any = true;
            }
        }
        if any {
            out.extend(quote!(let #xi: f64 = #e;));
        }
    }
    let xs: Vec<Ident> = (0..n).map(x_id).collect();
    // One test for all: a sum is finite only if every term is (a finite sum that overflows only
    // sends the solve to the runtime's path, which then returns the same finite values).
    let x = names::solution();
    out.extend(quote! {
        let #x = [#(#xs),*];
        if (#(#xs)+*).is_finite() {
            ::core::option::Option::Some(#x)
        } else {
            ::core::option::Option::None
        }
    });
    out
}

/// The decoupled 2×2 block {i, k} of M q̈ = f by Cramer's rule: the same pivot tests as the
/// elimination (mᵢᵢ > tol, and the second pivot det/mᵢᵢ > tol), one division depth, and the
/// determinant as `derive` simplified it (exact where its terms cancel).
fn cramer(
    m: &[Vec<Option<TokenStream>>],
    b: &[Option<TokenStream>],
    i: usize,
    k: usize,
    det: &TokenStream,
) -> TokenStream {
    let zero = quote!(0.0_f64);
    let get = |e: &Option<TokenStream>| e.clone().unwrap_or_else(|| zero.clone());
    let (mii, mkk, mik) = (get(&m[i][i]), get(&m[k][k]), get(&m[i][k]));
    // a·x − m_ik·y with the structurally zero products left out.
    let minus = |a: &TokenStream, x: &Option<TokenStream>, y: &Option<TokenStream>| match (x, y) {
        (Some(x), Some(y)) => quote!(#a * #x - #mik * #y),
        (Some(x), None) => quote!(#a * #x),
        (None, Some(y)) => quote!(-(#mik * #y)),
        (None, None) => quote!(0.0_f64),
    };
    let (ni, nk) = (minus(&mkk, &b[i], &b[k]), minus(&mii, &b[k], &b[i]));
    let det_id = names::det(i, k);
    let (yi, yk) = (names::solve_y(i), names::solve_y(k));
    let (tol, fast) = (names::tol(), names::fast_label());
    quote! {
        if !(#mii > #tol) {
            break #fast ::core::option::Option::None;
        }
        let #det_id: f64 = #det;
        if !(#det_id > #tol * #mii) {
            break #fast ::core::option::Option::None;
        }
        let #yi: f64 = (#ni) / #det_id;
        let #yk: f64 = (#nk) / #det_id;
    }
}

/// Lowers, differentiates and emits the symbolic implementation of `decl`.
pub fn expand(decl: &Decl) -> Result<SymbolicOutput, Vec<syn::Error>> {
    let d = derive(decl)?;
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
    let rows = d.mass.iter().enumerate().map(|(i, row)| {
        let cells = row
            .iter()
            .enumerate()
            .map(|(k, &m)| if k < i { quote!(0.0) } else { op(m) });
        quote!([#(#cells),*])
    });
    let f = d.force.iter().map(|&x| op(x));
    let stmts = code.stmts;
    let mass: Vec<Vec<Option<TokenStream>>> = d
        .mass
        .iter()
        .map(|row| {
            row.iter()
                .map(|&m| (m != Dag::ZERO).then(|| op(m)))
                .collect()
        })
        .collect();
    let rhs: Vec<Option<TokenStream>> = d
        .force
        .iter()
        .map(|&x| (x != Dag::ZERO).then(|| op(x)))
        .collect();
    let pairs: Vec<(usize, usize, TokenStream)> =
        d.pairs.iter().map(|&(i, k, det)| (i, k, op(det))).collect();
    let solve = ldlt(&mass, &rhs, &pairs);
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

    let eq = print::equations(&d, decl);
    let doc = format!(
        "# Equations of motion\n\nDerived at compile time by `#[lagrangian]` \
         (d/dt ∂L/∂q̇ = ∂L/∂q, one line per coordinate):\n\n```text\n{}\n```\n",
        eq.unicode
    );
    Ok(SymbolicOutput {
        accelerations,
        accelerations_inline,
        mass_matrix,
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
    })
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
