//! Small fixed-size dense solves for the mass matrix: LDLᵀ with scale-invariant pivot tests, and
//! LU (partial pivoting, on the equilibrated matrix) when the matrix is indefinite. The loops run
//! along rows (contiguous, vectorizable), so the same code serves N = 2 and N = 64.

/// Why a small solve failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolveFailure {
    /// A pivot vanished, or was so small against its own diagonal entry that the solution would
    /// have lost more than half its digits, at this row.
    Singular {
        /// Row (coordinate index) where elimination broke down.
        row: usize,
        /// The pivot found, relative to its own diagonal entry (LDLᵀ) or to the equilibrated
        /// matrix's scale (LU): about 10^(−k) means k of the 16 digits are lost.
        relative_pivot: f64,
    },
    /// The matrix or right-hand side has a NaN or infinity.
    NonFinite,
}

/// Pivots at or below this multiple of the matrix scale count as zero in the LU fallback (on the
/// equilibrated matrix); the LDLᵀ test, shared with the generated code, is
/// [`ACCURATE_RELATIVE_PIVOT`].
pub const SINGULAR_RELATIVE_PIVOT: f64 = 64.0 * f64::EPSILON;

/// √ε: an LDLᵀ pivot below this fraction of its own diagonal entry means the solution would
/// have lost more than half its digits (the error grows like ε / (d_j / m_jj)), so the solve
/// reports it as singular instead of returning it.
pub const ACCURATE_RELATIVE_PIVOT: f64 = 1.490_116_119_384_765_6e-8;

/// Solves `M x = b` for symmetric `M` given by its upper triangle (`m[i][k]`, `i ≤ k`).
///
/// Tries LDLᵀ without pivoting (mass matrices are positive definite away from chart
/// singularities). Each pivot d_j is judged against its own diagonal entry m_jj, a test that
/// does not change when coordinates are rescaled (M = diag(10¹⁴, 1) is as well conditioned as
/// the identity): a pivot below [`ACCURATE_RELATIVE_PIVOT`] · m_jj is singular, because the
/// solution would have lost more than half its digits. A pivot that is not positive at all (an
/// indefinite M) falls back to LU with partial pivoting on the symmetrically equilibrated matrix.
///
/// ```
/// use lagrange_runtime::linalg::solve_symmetric;
/// let m = [[4.0, 2.0], [0.0, 3.0]]; // upper triangle of [[4, 2], [2, 3]]
/// let x = solve_symmetric(&m, &[2.0, 1.0]).unwrap();
/// assert!((x[0] - 0.5).abs() < 1e-15 && x[1].abs() < 1e-15);
/// // Badly scaled is not singular.
/// assert_eq!(solve_symmetric(&[[1e14, 0.0], [0.0, 1.0]], &[1e14, 2.0]).unwrap(), [1.0, 2.0]);
/// // Nearly singular (the answer would lose ~12 digits) is an error, not a silent loss.
/// assert!(solve_symmetric(&[[1.0, 1.0], [0.0, 1.0 + 1e-12]], &[1.0, 1.0]).is_err());
/// ```
#[inline]
pub fn solve_symmetric<const N: usize>(
    m: &[[f64; N]; N],
    b: &[f64; N],
) -> Result<[f64; N], SolveFailure> {
    if b.iter().any(|x| !x.is_finite()) {
        return Err(SolveFailure::NonFinite);
    }
    match Ldlt::factor_or_indefinite(m)? {
        Some(f) => Ok(f.solve(b)),
        None => lu_solve_upper(m, b),
    }
}

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
    fn factor_or_indefinite(m: &[[f64; N]; N]) -> Result<Option<Self>, SolveFailure> {
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

fn lu_solve_upper<const N: usize>(
    m: &[[f64; N]; N],
    b: &[f64; N],
) -> Result<[f64; N], SolveFailure> {
    // Symmetric equilibration D M D with D = 1/√|m_jj| (1 where the diagonal vanishes), so the
    // pivot test does not depend on the units of the coordinates; x = D y.
    let mut dscale = [1.0; N];
    for j in 0..N {
        let mjj = m[j][j].abs();
        if mjj > 0.0 {
            dscale[j] = 1.0 / mjj.sqrt();
        }
    }
    let mut full = [[0.0; N]; N];
    let mut scale = 0.0_f64;
    for i in 0..N {
        for k in i..N {
            let e = dscale[i] * m[i][k] * dscale[k];
            full[i][k] = e;
            full[k][i] = e;
            scale = scale.max(e.abs());
        }
    }
    let mut rhs = *b;
    for i in 0..N {
        rhs[i] *= dscale[i];
    }
    let mut x = lu_solve(&full, &rhs, scale)?;
    for i in 0..N {
        x[i] *= dscale[i];
    }
    Ok(x)
}

/// Solves `A x = b` by LU with partial pivoting; pivots below `SINGULAR_RELATIVE_PIVOT · scale`
/// are reported as singular. `scale` is the magnitude the pivots are compared with (pass the
/// largest absolute entry of `A` when in doubt).
///
/// ```
/// use lagrange_runtime::linalg::lu_solve;
/// let a = [[0.0, 1.0], [1.0, 0.0]];
/// assert_eq!(lu_solve(&a, &[2.0, 3.0], 1.0).unwrap(), [3.0, 2.0]);
/// assert!(lu_solve(&[[1.0, 1.0], [1.0, 1.0]], &[1.0, 1.0], 1.0).is_err());
/// ```
pub fn lu_solve<const N: usize>(
    a: &[[f64; N]; N],
    b: &[f64; N],
    scale: f64,
) -> Result<[f64; N], SolveFailure> {
    let mut a = *a;
    let mut x = *b;
    lu_in_place(a.as_flattened_mut(), N, &mut x, scale)?;
    Ok(x)
}

/// [`lu_solve`] for a system whose size is known at run time (the constrained implicit step,
/// N coordinates and K multipliers): `a` is the n × n matrix by rows, solved in place; `x` holds
/// b on entry and the solution on exit.
///
/// ```
/// use lagrange_runtime::linalg::lu_solve_dyn;
/// let mut a = vec![0.0, 1.0, 1.0, 0.0];
/// let mut x = vec![2.0, 3.0];
/// lu_solve_dyn(&mut a, &mut x, 1.0).unwrap();
/// assert_eq!(x, [3.0, 2.0]);
/// ```
pub fn lu_solve_dyn(a: &mut [f64], x: &mut [f64], scale: f64) -> Result<(), SolveFailure> {
    let n = x.len();
    if a.len() != n * n {
        return Err(SolveFailure::NonFinite);
    }
    lu_in_place(a, n, x, scale)
}

/// LU with partial pivoting on the n × n row-major `a`, solving for `x` in place.
#[inline]
fn lu_in_place(a: &mut [f64], n: usize, x: &mut [f64], scale: f64) -> Result<(), SolveFailure> {
    if a.iter().chain(x.iter()).any(|v| !v.is_finite()) {
        return Err(SolveFailure::NonFinite);
    }
    let tol = SINGULAR_RELATIVE_PIVOT * scale;
    for col in 0..n {
        let mut p = col;
        for r in col + 1..n {
            if a[r * n + col].abs() > a[p * n + col].abs() {
                p = r;
            }
        }
        let piv = a[p * n + col].abs();
        if piv <= tol {
            return Err(SolveFailure::Singular {
                row: col,
                relative_pivot: if scale > 0.0 { piv / scale } else { 0.0 },
            });
        }
        if p != col {
            for c in 0..n {
                a.swap(col * n + c, p * n + c);
            }
            x.swap(col, p);
        }
        let acc = a[col * n + col];
        for r in col + 1..n {
            let f = a[r * n + col] / acc;
            for c in col..n {
                a[r * n + c] -= f * a[col * n + c];
            }
            x[r] -= f * x[col];
        }
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            x[i] -= a[i * n + k] * x[k];
        }
        x[i] /= a[i * n + i];
    }
    Ok(())
}

/// Whether every value is finite, in one branch-free pass the compiler unrolls: Σ 0·x is exactly
/// 0 when no x is infinite or NaN (0·±∞ and 0·NaN are NaN). `Iterator::all` over chained arrays
/// stayed an out-of-line call in the constrained solve (17 % of its time).
///
/// ```
/// use lagrange_runtime::linalg::all_finite;
/// assert!(all_finite(&[1.0, -2.0, f64::MAX]));
/// assert!(!all_finite(&[1.0, f64::INFINITY]));
/// assert!(!all_finite(&[f64::NAN, 0.0]));
/// ```
#[inline(always)]
pub fn all_finite(xs: &[f64]) -> bool {
    let mut acc = 0.0;
    for &x in xs {
        acc += 0.0 * x;
    }
    acc == 0.0
}

/// Solves L D Lᵀ x = b with L stored transposed in the upper triangle of `a` and the reciprocal
/// pivots `d_inv`: the solve of [`Ldlt`], written once for `f64` and for
/// [`Lanes`](crate::lanes::Lanes) (the Taylor method's per-lane factorization), so each lane
/// solves bit for bit as the scalar code does.
#[inline(always)]
pub(crate) fn ldlt_solve<T: crate::taylor::Coefficient, const N: usize>(
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
