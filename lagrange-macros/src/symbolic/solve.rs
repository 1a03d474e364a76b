//! Emit the solve of M q̈ = f: straight-line LDLᵀ with the sparsity known at compile time, and
//! Cramer's rule for the decoupled 2×2 blocks.
// Index loops mirror the textbook elimination formulas; iterator forms would obscure them.
#![allow(clippy::needless_range_loop)]

use proc_macro2::{Ident, TokenStream};
use quote::quote;

use super::derive::Equations;
use crate::names;

/// Straight-line LDLᵀ of the mass matrix (upper triangle, `None` = structural zero) with the
/// sparsity known at compile time: the same elimination, in the same order, as the runtime's
/// `solve_symmetric`, with the structurally zero products left out and one reciprocal per pivot
/// whose row of L has two or more entries; the decoupled 2×2 blocks in `pairs` by Cramer's rule
/// instead (see [`cramer`]). The tokens are the statements of a block labelled [`names::fast_label`] that
/// evaluates to `Some(q̈)`, or breaks with `None` whenever a pivot fails the runtime's test
/// (d_j > √ε·m_jj: more than half the digits kept) or anything is not finite; the caller then
/// hands over to `solve_mass_matrix`, which decides between LU and a `DynamicsError` exactly as
/// the jets path.
pub fn ldlt(eq: &Equations, pairs: &[(usize, usize, TokenStream, bool)]) -> TokenStream {
    ldlt_as(eq, pairs, None)
}

/// The numbers a solve is emitted over: `f64`, or a lane type (every lane the scalar solve's
/// operations; a pivot test passes only if it passes in every lane).
#[derive(Clone, Copy)]
pub struct Num<'a>(pub Option<&'a TokenStream>);

impl Num<'_> {
    /// The type of a local.
    fn ty(self) -> TokenStream {
        match self.0 {
            Some(l) => quote!(#l),
            None => quote!(f64),
        }
    }
    /// A value bound to a local: a constant operand becomes a lane value.
    fn value(self, e: TokenStream) -> TokenStream {
        match self.0 {
            Some(l) => quote!(<#l>::from(#e)),
            None => e,
        }
    }
    /// The test `a > b`: in scalar code, a `break` out of the fast path where it fails; in lanes
    /// code, the lanes where it fails are cleared from the mask [`names::lane_ok`] (every lane
    /// runs the whole solve, and the caller hands the cleared lanes to the scalar path).
    fn require(self, a: TokenStream, b: TokenStream) -> TokenStream {
        let fast = names::fast_label();
        match self.0 {
            Some(l) => {
                let ok = names::lane_ok();
                quote!(let #ok = #ok & <#l>::from(#a).gt(#b);)
            }
            None => quote! {
                if !(#a > #b) {
                    break #fast ::core::option::Option::None;
                }
            },
        }
    }
}

/// [`ldlt`] over the numbers `num` (`None`: `f64`).
pub fn ldlt_as(
    eq: &Equations,
    pairs: &[(usize, usize, TokenStream, bool)],
    num: Option<&TokenStream>,
) -> TokenStream {
    let num = Num(num);
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
            None => quote!(0.0_f64),
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
            None => quote!(0.0_f64),
        };
        let e = num.value(e);
        let test = num.require(quote!(#dj), quote!(#accurate * #mjj));
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
                None => quote!(0.0_f64),
            };
            for t in terms {
                s = quote!(#s - #t);
            }
            row.push((i, u_id(j, i), num.value(s)));
            l[j][i] = true;
        }
        // A reciprocal adds a multiplication to the (latency-bound) critical path; it pays off
        // only when it replaces several divisions.
        let rj = r_id(j);
        if row.len() >= 2 {
            recip[j] = true;
            out.extend(quote!(let #rj: #ty = 1.0 / #dj;));
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
            None => quote!(0.0_f64),
        };
        for k in 0..i {
            if l[k][i] {
                let (lki, xk) = (a_id(k, i), x_id(k));
                e = quote!(#e - #lki * #xk);
            }
        }
        let e = num.value(e);
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
    let x = names::solution();
    match num.0 {
        // Lanes: (q̈, the lanes whose pivots passed and whose values are finite).
        Some(l) => {
            let ok = names::lane_ok();
            let w = names::lane_width();
            let mut head = quote! {
                let #ok = ::lagrange::__private::lanes::Mask::<#w>::splat(true);
            };
            head.extend(out);
            head.extend(quote! {
                let #ok = #ok & <#l>::from(#(#xs)+*).finite();
                ([#(#xs),*], #ok)
            });
            head
        }
        None => {
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
    }
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
    let det_test = if exact {
        num.require(quote!(#det_id), quote!(0.0))
    } else {
        num.require(
            quote!(#det_id),
            quote!(::lagrange::__private::linalg::ACCURATE_RELATIVE_PIVOT * #mii * #mkk),
        )
    };
    let mii_test = num.require(mii.clone(), quote!(0.0));
    let det = num.value(det.clone());
    let (ni, nk) = (
        num.value(quote!((#ni) / #det_id)),
        num.value(quote!((#nk) / #det_id)),
    );
    quote! {
        #mii_test
        let #det_id: #ty = #det;
        #det_test
        let #yi: #ty = #ni;
        let #yk: #ty = #nk;
    }
}
