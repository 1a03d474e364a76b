//! LDLᵀ without pivoting, its pivot tests judged against each diagonal entry, and its solves
//! (one right-hand side, or several at once for the constrained fast path).

use super::{ACCURATE_RELATIVE_PIVOT, SolveFailure, all_finite};

/// An LDLᵀ factorization of a symmetric positive definite matrix, kept to solve with several
/// right-hand sides (the constraint rows need one solve per constraint and one for the forces).
///
/// ```
/// use lagrange_runtime::linalg::Ldlt;
/// let f = Ldlt::factor(&[[4.0, 2.0], [0.0, 3.0]]).unwrap(); // upper triangle of [[4, 2], [2, 3]]
/// let x = f.solve(&[2.0, 1.0]);
/// assert!((x[0] - 0.5).abs() < 1e-15 && x[1].abs() < 1e-15);
/// // Not positive definite: no factorization (use `solve_symmetric`, which falls back to LU).
/// assert!(Ldlt::factor(&[[1.0, 2.0], [0.0, 1.0]]).is_err());
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Ldlt<const N: usize> {
    /// L below the diagonal, stored transposed in the upper triangle (l[k][i], i < k, at a[i][k]).
    a: [[f64; N]; N],
    /// The reciprocals 1/d_j of the pivots (a solve multiplies).
    d_inv: [f64; N],
}

impl<const N: usize> Ldlt<N> {
    /// Factors `M` given by its upper triangle; a pivot that is not positive, or below
    /// [`ACCURATE_RELATIVE_PIVOT`] of its own diagonal entry, is [`SolveFailure::Singular`] at its
    /// row (an indefinite matrix reports its first non-positive pivot, `relative_pivot` ≤ 0).
    #[inline]
    pub fn factor(m: &[[f64; N]; N]) -> Result<Self, SolveFailure> {
        match Self::factor_or_indefinite(m) {
            Ok(Some(f)) => Ok(f),
            Ok(None) => {
                // Report the first non-positive pivot.
                let (mut a, mut u) = (*m, *m);
                let mut d_inv = [0.0; N];
                for j in 0..N {
                    let dj = Self::pivot(&mut a, &mut u, &mut d_inv, j);
                    if dj.is_nan() || dj <= 0.0 {
                        let mjj = m[j][j];
                        return Err(SolveFailure::Singular {
                            row: j,
                            relative_pivot: if mjj != 0.0 { dj / mjj.abs() } else { 0.0 },
                        });
                    }
                }
                Err(SolveFailure::Singular {
                    row: 0,
                    relative_pivot: 0.0,
                })
            }
            Err(e) => Err(e),
        }
    }

    /// Eliminates column j of the factorization in progress and returns its pivot d_j. Row k
    /// of `u` holds u_ki = l_ki d_k (the row before its division by the pivot), row k of `a`
    /// holds l_ki, for k < j: d_j = m_jj − Σ_k l_kj u_kj and u_ji = m_ji − Σ_k l_kj u_ki, the
    /// sums over k in increasing order (as the generated straight-line solve), each a row update.
    /// Stores 1/d_j in `d_inv`.
    #[inline(always)]
    fn pivot(a: &mut [[f64; N]; N], u: &mut [[f64; N]; N], d_inv: &mut [f64; N], j: usize) -> f64 {
        let (done, rest) = u.split_at_mut(j);
        let Some(row_j) = rest.first_mut() else {
            return f64::NAN;
        };
        for (k, row_k) in done.iter().enumerate() {
            let lkj = a[k][j];
            for (x, &y) in row_j[j..].iter_mut().zip(&row_k[j..]) {
                *x -= lkj * y;
            }
        }
        let dj = row_j[j];
        if dj.is_nan() || dj <= 0.0 {
            return dj;
        }
        let r = 1.0 / dj;
        d_inv[j] = r;
        for (l, &x) in a[j][j + 1..].iter_mut().zip(&row_j[j + 1..]) {
            *l = x * r;
        }
        dj
    }

    /// The factorization; `Ok(None)` where a pivot is not positive (indefinite: the caller may
    /// fall back to LU), an error where a positive pivot is too small against its diagonal entry.
    #[inline(always)]
    pub(super) fn factor_or_indefinite(m: &[[f64; N]; N]) -> Result<Option<Self>, SolveFailure> {
        if m.iter().enumerate().any(|(i, row)| !row[i].is_finite()) {
            return Err(SolveFailure::NonFinite);
        }
        let (mut a, mut u) = (*m, *m);
        let mut d_inv = [0.0; N];
        for j in 0..N {
            let dj = Self::pivot(&mut a, &mut u, &mut d_inv, j);
            if dj.is_nan() || dj <= 0.0 {
                return Ok(None);
            }
            if dj <= ACCURATE_RELATIVE_PIVOT * m[j][j] {
                return Err(SolveFailure::Singular {
                    row: j,
                    relative_pivot: dj / m[j][j],
                });
            }
        }
        Ok(Some(Ldlt { a, d_inv }))
    }

    /// Solves M x = b with the factorization.
    #[inline]
    pub fn solve(&self, b: &[f64; N]) -> [f64; N] {
        ldlt_solve(&self.a, &self.d_inv, b)
    }
}

/// Solves M x = b and M Yⱼ = gⱼ (j < K) for symmetric positive definite M (upper triangle)
/// with one LDLᵀ and one sweep over all K + 1 right-hand sides; `None` where a pivot is not
/// positive or fails [`ACCURATE_RELATIVE_PIVOT`], or anything is not finite (the caller then
/// takes the careful path, which says why). The constrained solve's fast path.
///
/// ```
/// use lagrange_runtime::linalg::ldlt_solve_with;
/// let m = [[4.0, 2.0], [0.0, 3.0]]; // upper triangle of [[4, 2], [2, 3]]
/// let (x, y) = ldlt_solve_with(&m, &[2.0, 1.0], &[[4.0, 2.0]]).unwrap();
/// assert!((x[0] - 0.5).abs() < 1e-15 && x[1].abs() < 1e-15);
/// assert!((y[0][0] - 1.0).abs() < 1e-15 && y[0][1].abs() < 1e-15);
/// assert!(ldlt_solve_with(&[[1.0, 2.0], [0.0, 1.0]], &[1.0, 1.0], &[[1.0, 0.0]]).is_none());
/// ```
#[inline]
pub fn ldlt_solve_with<const N: usize, const K: usize>(
    m: &[[f64; N]; N],
    b: &[f64; N],
    g: &[[f64; N]; K],
) -> Option<([f64; N], [[f64; N]; K])> {
    // l[k][i] (i > k) and u[k][i] = l[k][i] d_k, rows updated in place (as `Ldlt::pivot`; a separate loop
    // here because it measured 25 % faster on the constrained quaternion top than `Ldlt` plus
    // K + 1 solves: `cargo bench --bench constraints -- solve_only`, 1.75 vs 2.25 µs per 16).
    let mut u = *m;
    let mut l = [[0.0; N]; N];
    let mut d_inv = [0.0; N];
    // Constant-bound index loops (no slices): LLVM unrolls them for small N and keeps the
    // factors in registers.
    for j in 0..N {
        for k in 0..j {
            let lkj = l[k][j];
            for i in j..N {
                u[j][i] -= lkj * u[k][i];
            }
        }
        let dj = u[j][j];
        // Also false for NaN.
        let accurate = dj > ACCURATE_RELATIVE_PIVOT * m[j][j];
        if !accurate || !dj.is_finite() {
            return None;
        }
        let r = 1.0 / dj;
        d_inv[j] = r;
        for i in j + 1..N {
            l[j][i] = u[j][i] * r;
        }
    }
    let mut x = *b;
    let mut y = *g;
    for k in 0..N {
        let lk = &l[k];
        let xk = x[k];
        for i in k + 1..N {
            x[i] -= lk[i] * xk;
        }
        for yj in y.iter_mut() {
            let yk = yj[k];
            for i in k + 1..N {
                yj[i] -= lk[i] * yk;
            }
        }
    }
    for i in 0..N {
        x[i] *= d_inv[i];
        for yj in y.iter_mut() {
            yj[i] *= d_inv[i];
        }
    }
    for i in (0..N).rev() {
        let li = &l[i];
        for k in i + 1..N {
            x[i] -= li[k] * x[k];
            for yj in y.iter_mut() {
                yj[i] -= li[k] * yj[k];
            }
        }
    }
    (all_finite(&x) && all_finite(y.as_flattened())).then_some((x, y))
}

/// Solves L D Lᵀ x = b with L stored transposed in the upper triangle of `a` and the reciprocal
/// pivots `d_inv`: the solve of [`Ldlt`], written once for `f64` and for
/// [`Lanes`](crate::lanes::Lanes) (the Taylor method's per-lane factorization), so each lane
/// solves bit for bit as the scalar code does.
#[inline(always)]
pub(crate) fn ldlt_solve<T: crate::real::Real, const N: usize>(
    a: &[[T; N]; N],
    d_inv: &[T; N],
    b: &[T; N],
) -> [T; N] {
    let mut x = *b;
    // Forward: x_i −= l_ki x_k for k < i, k in increasing order, as row updates.
    for k in 0..N {
        let xk = x[k];
        for (xi, &l) in x[k + 1..].iter_mut().zip(&a[k][k + 1..]) {
            *xi -= l * xk;
        }
    }
    for i in 0..N {
        x[i] = x[i] * d_inv[i];
    }
    for i in (0..N).rev() {
        for k in i + 1..N {
            x[i] -= a[i][k] * x[k];
        }
    }
    x
}
