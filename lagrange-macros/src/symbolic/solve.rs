//! Emit the solve of M q̈ = f: straight-line LDLᵀ with the sparsity known at compile time, and
//! Cramer's rule for the decoupled 2×2 blocks.
// Index loops mirror the textbook elimination formulas; iterator forms would obscure them.
#![allow(clippy::needless_range_loop)]

use proc_macro2::{Ident, TokenStream};
use quote::quote;

use super::codegen;
use super::derive::Equations;
use crate::names;

/// The numbers a solve is emitted over: the type parameter `R: Real` of a generic kernel (its
/// `f64` instance is the single run, its lanes instance every lane's scalar operations).
#[derive(Clone, Copy)]
pub struct Num<'a>(pub &'a TokenStream, usize);

impl Num<'_> {
    /// The type of a local.
    fn ty(self) -> TokenStream {
        let r = self.0;
        quote!(#r)
    }
    /// The constant `c` (an `f64` literal) as an `R`.
    fn konst(self, c: TokenStream) -> TokenStream {
        codegen::real_const(self.0, &c)
    }
    /// The test `a > b` (both `R`): the lanes where it fails are cleared from the mask
    /// [`names::lane_ok`] (every lane runs the whole solve, and the caller hands the cleared lanes
    /// to the careful path).
    fn require(self, a: TokenStream, b: TokenStream) -> TokenStream {
        let (ok, fast) = (names::lane_ok(), names::fast_label());
        let n = proc_macro2::Literal::usize_unsuffixed(self.1);
        let r = self.0;
        let rt = quote!(::lagrange::__private::Real);
        // A single run whose test fails needs nothing after it: it leaves the block (the
        // branch measured 3 % fewer instructions per q̈ than computing on; in lanes, where every
        // lane computes on, the test is a mask operation and no branch: 11 % fewer there).
        quote! {
            let #ok = #ok & <#r as #rt>::greater(#a, #b);
            if <#r as #rt>::WIDTH == 1 && !<#r as #rt>::all(#ok) {
                break #fast ([<#r as #rt>::NAN; #n], #ok);
            }
        }
    }
}

/// Straight-line LDLᵀ of the mass matrix (upper triangle, `None` = structural zero; every entry
/// an `R`) with the sparsity known at compile time: the same elimination, in the same order, as
/// the runtime's `solve_symmetric`, with the structurally zero products left out and one
/// reciprocal per pivot whose row of L has two or more entries; the decoupled 2×2 blocks in
/// `pairs` by Cramer's rule instead (see [`cramer`]). The tokens are the statements of a block
/// labelled [`names::fast_label`] that evaluates to `([q̈; N], ok)`: `ok` (an `R::Mask`) clears every lane where a pivot failed
/// the runtime's test (d_j > √ε·m_jj: more than half the digits kept) or anything is not finite;
/// the caller hands those to `solve_mass_matrix`, which decides between LU and a `DynamicsError`
/// exactly as the jets path.
pub fn ldlt(
    eq: &Equations,
    pairs: &[(usize, usize, TokenStream, bool)],
    r: &TokenStream,
) -> TokenStream {
    let num = Num(r, eq.mass.len());
    let ty = num.ty();
    let (m, b) = (&eq.mass, &eq.rhs);
    let n = m.len();
    // Indices solved as a decoupled 2×2 block (Cramer) instead of by the elimination.
    let mut paired = vec![false; n];
    for &(i, k, _, _) in pairs {
        paired[i] = true;
        paired[k] = true;
    }
    let a_id = names::ldl_l;
    let d_id = names::ldl_d;
    let r_id = names::ldl_r;
    let u_id = names::ldl_u;
    let x_id = names::solve_y;
    let accurate = quote!(::lagrange::__private::linalg::ACCURATE_RELATIVE_PIVOT);
    let mut out = TokenStream::new();
    // l[j][i] (i > j): true when not structurally zero.
    let mut l: Vec<Vec<bool>> = vec![vec![false; n]; n];
    // Whether pivot j has a reciprocal `r_j` (used by its row of l and by y_j).
    let mut recip = vec![false; n];
    for (i, k, det, exact) in pairs {
        out.extend(cramer(m, b, *i, *k, det, *exact, num));
    }
    for j in 0..n {
        if paired[j] {
            continue;
        }
        let dj = d_id(j);
        let mut e = match &m[j][j] {
            Some(x) => quote!(#x),
            None => num.konst(quote!(0.0)),
        };
        // l_kj² d_k = l_kj u_kj, with u_kj = l_kj d_k the row before its division.
        for k in 0..j {
            if l[k][j] {
                let (lk, uk) = (a_id(k, j), u_id(k, j));
                e = quote!(#e - #lk * #uk);
            }
        }
        // The runtime's test (`solve_symmetric`): the pivot against its own diagonal entry,
        // so the units of the coordinates do not matter and a pass here is a pass there.
        let mjj = match &m[j][j] {
            Some(x) => quote!(#x),
            None => num.konst(quote!(0.0)),
        };
        // m_jj · √ε is √ε · m_jj bit for bit (a product of two numbers commutes).
        let test = num.require(quote!(#dj), quote!(#mjj * #accurate));
        out.extend(quote! {
            let #dj: #ty = #e;
            #test
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
                None => num.konst(quote!(0.0)),
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
            let one = num.konst(quote!(1.0));
            out.extend(quote!(let #rj: #ty = #one / #dj;));
        }
        // Two `let`s per row keep the scope nesting shallow (see codegen): the row before its
        // division by the pivot (u), then L's row.
        if !row.is_empty() {
            let us: Vec<Ident> = row.iter().map(|(_, x, _)| x.clone()).collect();
            let ls = row.iter().map(|&(i, _, _)| a_id(j, i));
            let tys: Vec<TokenStream> = row.iter().map(|_| ty.clone()).collect();
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
            None => num.konst(quote!(0.0)),
        };
        for k in 0..i {
            if l[k][i] {
                let (lki, xk) = (a_id(k, i), x_id(k));
                e = quote!(#e - #lki * #xk);
            }
        }
        out.extend(quote!(let #xi: #ty = #e;));
    }
    for i in (0..n).filter(|&i| !paired[i]) {
        let (xi, di, ri) = (x_id(i), d_id(i), r_id(i));
        if recip[i] {
            out.extend(quote!(let #xi: #ty = #xi * #ri;));
        } else {
            out.extend(quote!(let #xi: #ty = #xi / #di;));
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
            out.extend(quote!(let #xi: #ty = #e;));
        }
    }
    let xs: Vec<Ident> = (0..n).map(x_id).collect();
    // One test for all: a sum is finite only if every term is (a finite sum that overflows only
    // sends the solve to the runtime's path, which then returns the same finite values).
    let ok = names::lane_ok();
    let mut head = quote! {
        let #ok = <#r as ::lagrange::__private::Real>::EVERY_LANE;
    };
    head.extend(out);
    head.extend(quote! {
        let #ok = #ok & <#r as ::lagrange::__private::Real>::finite(#(#xs)+*);
        ([#(#xs),*], #ok)
    });
    head
}

/// The decoupled 2×2 block {i, k} of M q̈ = f by Cramer's rule, one division depth, with the
/// determinant as `derive` simplified it. When that determinant is `exact` (its terms cancelled
/// symbolically to one monomial, such as I⊥ I∥ sin²θ for the top), it carries no rounding
/// beyond a few ulps however small it is, and any positive value is accepted: the answer is as
/// accurate as its inputs. Otherwise the elimination's test applies (the second pivot det/mᵢᵢ
/// against its own diagonal mₖₖ, as in `solve_symmetric`).
fn cramer(
    m: &[Vec<Option<TokenStream>>],
    b: &[Option<TokenStream>],
    i: usize,
    k: usize,
    det: &TokenStream,
    exact: bool,
    num: Num<'_>,
) -> TokenStream {
    let ty = num.ty();
    let zero = num.konst(quote!(0.0));
    let get = |e: &Option<TokenStream>| e.clone().unwrap_or_else(|| zero.clone());
    let (mii, mkk, mik) = (get(&m[i][i]), get(&m[k][k]), get(&m[i][k]));
    // a·x − m_ik·y with the structurally zero products left out.
    let minus = |a: &TokenStream, x: &Option<TokenStream>, y: &Option<TokenStream>| match (x, y) {
        (Some(x), Some(y)) => quote!(#a * #x - #mik * #y),
        (Some(x), None) => quote!(#a * #x),
        (None, Some(y)) => quote!(-(#mik * #y)),
        (None, None) => zero.clone(),
    };
    let (ni, nk) = (minus(&mkk, &b[i], &b[k]), minus(&mii, &b[k], &b[i]));
    let det_id = names::det(i, k);
    let (yi, yk) = (names::solve_y(i), names::solve_y(k));
    let det_test = if exact {
        num.require(quote!(#det_id), zero.clone())
    } else {
        // (m_ii · √ε) · m_kk is (√ε · m_ii) · m_kk bit for bit.
        num.require(
            quote!(#det_id),
            quote!(#mii * ::lagrange::__private::linalg::ACCURATE_RELATIVE_PIVOT * #mkk),
        )
    };
    let mii_test = num.require(mii.clone(), zero.clone());
    let (ni, nk) = (quote!((#ni) / #det_id), quote!((#nk) / #det_id));
    quote! {
        #mii_test
        let #det_id: #ty = #det;
        #det_test
        let #yi: #ty = #ni;
        let #yk: #ty = #nk;
    }
}
