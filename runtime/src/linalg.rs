//! Small fixed-size dense solves for the mass matrix: LDLᵀ with scale-invariant pivot tests, and
//! LU (partial pivoting, on the equilibrated matrix) when the matrix is indefinite. The loops run
//! along rows (contiguous, vectorizable), so the same code serves N = 2 and N = 64. For the
//! constrained equations of small systems, the saddle-point solves [`saddle_solve`] and
//! [`saddle_solve_one`]: division-free elimination, the same pivot tests, a shorter chain of
//! dependent steps.

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

/// Solves A x = b + Bᵀλ, B x = d for x and λ, with A symmetric positive definite given by its
/// upper triangle and B of full row rank: the saddle-point system [A Bᵀ; B 0] of a constrained
/// solve, written for small N + K, where the run time is a chain of dependent steps rather than
/// arithmetic.
///
/// Division-free elimination: each level replaces a_ij by p_k a_ij − a_ki a_kj (p_k the pivot),
/// so no level waits for a division; the reciprocals of the pivots are independent of one another
/// and overlap with the elimination; only the last one (the multipliers') is on the critical
/// path. Level k's entries are c_k times the usual Schur complement's, c_{k+1} = c_k p_k, so the
/// LDLᵀ pivot d_k = p_k / c_k is tested as in [`ldlt_solve_with`] (d_k > [`ACCURATE_RELATIVE_PIVOT`]
/// · a_kk) by multiplications. `None` wherever that test fails (also for B A⁻¹ Bᵀ, by its own
/// diagonal), where c_k leaves [2⁻⁹⁰⁰, 2⁹⁰⁰] (it grows like the entries to the power 2^k, so
/// scale A to a unit diagonal first), or where anything is not finite: the caller then takes a
/// careful path.
///
/// ```
/// use lagrange_runtime::linalg::saddle_solve;
/// // A unit mass in the plane pushed along x by 2, held on the line x = y.
/// let (x, lambda) = saddle_solve(&[[1.0, 0.0], [0.0, 1.0]], &[2.0, 0.0], &[[1.0, -1.0]], &[0.0]).unwrap();
/// assert_eq!((x, lambda), ([1.0, 1.0], [-1.0]));
/// // Dependent rows: declined.
/// let a = [[1.0, 0.0], [0.0, 1.0]];
/// assert!(saddle_solve(&a, &[2.0, 0.0], &[[1.0, -1.0], [2.0, -2.0]], &[0.0, 0.0]).is_none());
/// ```
#[inline(always)]
pub fn saddle_solve<const N: usize, const K: usize>(
    a: &[[f64; N]; N],
    b: &[f64; N],
    rows: &[[f64; N]; K],
    d: &[f64; K],
) -> Option<([f64; N], [f64; K])> {
    let mut u = *a;
    // col[l][i]: the entry (i, N + l), B's row l, eliminated alongside.
    let mut col = *rows;
    // The constraint block, −c_N B A⁻¹ Bᵀ after the N levels (upper triangle), and its right side.
    let mut s = [[0.0; K]; K];
    let mut x = *b;
    let mut r = *d;
    let mut scale = 1.0;
    let mut ok = true;
    for k in 0..N {
        let p = u[k][k];
        ok &= p > ACCURATE_RELATIVE_PIVOT * a[k][k] * scale;
        for i in k + 1..N {
            let uki = u[k][i];
            for j in i..N {
                u[i][j] = p * u[i][j] - uki * u[k][j];
            }
            x[i] = p * x[i] - uki * x[k];
            for cl in col.iter_mut() {
                cl[i] = p * cl[i] - uki * cl[k];
            }
        }
        for l in 0..K {
            let clk = col[l][k];
            for m in l..K {
                s[l][m] = p * s[l][m] - clk * col[m][k];
            }
            r[l] = p * r[l] - clk * x[k];
        }
        scale *= p;
        ok &= in_range(scale);
    }
    // t = −s = c_N B A⁻¹ Bᵀ (positive definite), t λ = c_N (d − B A⁻¹ b) = r.
    let mut t = [[0.0; K]; K];
    for l in 0..K {
        for m in l..K {
            t[l][m] = -s[l][m];
        }
    }
    let tdiag: [f64; K] = core::array::from_fn(|l| t[l][l]);
    ok &= eliminate(&mut t, &mut r, K, K, &tdiag).0;
    if !ok {
        return None;
    }
    // Back substitution, each row divided through by its pivot (the reciprocals side by side).
    // Each sum takes the unknowns in the order they become known, so the last one found
    // waits for one product and one subtraction.
    let mut lambda = r;
    for l in (0..K).rev() {
        let mut v = lambda[l];
        for m in (l + 1..K).rev() {
            v -= t[l][m] * lambda[m];
        }
        lambda[l] = v / t[l][l];
    }
    // Row k: p_k x_k + Σ_{i>k} u_ki x_i − Σ_l col_lk λ_l = x_k (the unknown beside B is −λ),
    // divided through by p_k off the critical path.
    let mut out = x;
    for k in (0..N).rev() {
        let inv = 1.0 / u[k][k];
        let mut v = x[k] * inv;
        for l in 0..K {
            v += (col[l][k] * inv) * lambda[l];
        }
        for i in (k + 1..N).rev() {
            v -= (u[k][i] * inv) * out[i];
        }
        out[k] = v;
    }
    (all_finite(&out) && all_finite(&lambda)).then_some((out, lambda))
}

/// Solves A x = b + g λ, g·x = d (one constraint) for x and λ, with A symmetric positive
/// semi-definite (upper triangle) as long as it is positive definite on the constraint's
/// tangent space: [`saddle_solve`] for K = 1 by coordinate partitioning, for N ≤ 5.
///
/// The constraint fixes x_p, p the coordinate with the largest g_p² / A_pp (whatever the units): the
/// other coordinates u solve the reduced system ZᵀAZ u = Zᵀ(b − A e_p d/g_p) with Z's columns
/// e_a − (g_a/g_p) e_p, written times g_p² (no division), by division-free elimination whose last
/// 2 × 2 block goes by Cramer's rule; x_p = d/g_p − Σ (g_a/g_p) u_a is found alongside the last
/// back-substitution, and λ = (A x − b)_p / g_p. A chain of dependent steps about half as long
/// as [`saddle_solve`]'s, which eliminates all N + 1 unknowns. `None` where a reduced pivot fails
/// the test of [`ldlt_solve_with`] (d_k > [`ACCURATE_RELATIVE_PIVOT`] of its diagonal entry, i.e.
/// the constrained system is singular or nearly), where g = 0, where the division-free factors
/// leave their range, where anything is not finite, and for N > 5.
///
/// ```
/// use lagrange_runtime::linalg::saddle_solve_one;
/// // A unit mass in the plane pushed along x by 2, held on the line x = y.
/// let (x, lambda) = saddle_solve_one(&[[1.0, 0.0], [0.0, 1.0]], &[2.0, 0.0], &[1.0, -1.0], 0.0).unwrap();
/// assert_eq!((x, lambda), ([1.0, 1.0], -1.0));
/// // A singular A is fine where the constraint fixes its null direction (a rank-1 A in 2D)...
/// let (x, _) = saddle_solve_one(&[[1.0, 0.0], [0.0, 0.0]], &[2.0, 0.0], &[0.0, 1.0], 0.5).unwrap();
/// assert_eq!(x, [2.0, 0.5]);
/// // ...not where it leaves a direction without inertia free.
/// assert!(saddle_solve_one(&[[1.0, 0.0], [0.0, 0.0]], &[2.0, 0.0], &[1.0, 0.0], 0.5).is_none());
/// ```
#[inline(always)]
pub fn saddle_solve_one<const N: usize>(
    a: &[[f64; N]; N],
    b: &[f64; N],
    g: &[f64; N],
    d: f64,
) -> Option<([f64; N], f64)> {
    if N > 5 {
        return None;
    }
    // The pivot: the largest g_p² / A_pp, compared by cross-multiplying (A_pp = 0 counts as
    // infinitely large when g_p ≠ 0). The ratio does not change with the units of the
    // coordinates (A_pp ∝ s_p², g_p ∝ s_p), so neither does the choice.
    let mut p = 0;
    let (mut bg, mut ba) = (g[0] * g[0], a[0][0]);
    for i in 1..N {
        let (gi, ai) = (g[i] * g[i], a[i][i]);
        if gi * ba > bg * ai {
            (bg, ba, p) = (gi, ai, i);
        }
    }
    // One copy per pivot coordinate, so every index is a constant and the arrays stay in
    // registers (an index known only at run time made the whole solve 20 % slower).
    match p {
        0 => partitioned::<N, 0>(a, b, g, d),
        1 => partitioned::<N, 1>(a, b, g, d),
        2 => partitioned::<N, 2>(a, b, g, d),
        3 => partitioned::<N, 3>(a, b, g, d),
        4 => partitioned::<N, 4>(a, b, g, d),
        _ => None,
    }
}

/// [`saddle_solve_one`] with the pivot coordinate P.
#[inline(always)]
fn partitioned<const N: usize, const P: usize>(
    a: &[[f64; N]; N],
    b: &[f64; N],
    g: &[f64; N],
    d: f64,
) -> Option<([f64; N], f64)> {
    if P >= N || N < 2 {
        return None;
    }
    let at = |i: usize, k: usize| if i <= k { a[i][k] } else { a[k][i] };
    // idx[j]: the coordinate of the j-th reduced unknown (all but P, in order).
    let idx: [usize; N] = core::array::from_fn(|j| if j < P { j } else { (j + 1).min(N - 1) });
    let n = N - 1;
    let gp = g[P];
    let gp2 = gp * gp;
    let (app, bp) = (at(P, P), b[P]);
    // g_p² ZᵀAZ (upper triangle) and g_p² Zᵀ(b − A e_p d/g_p).
    let mut r = [[0.0; N]; N];
    let mut rhs = [0.0; N];
    for j in 0..n {
        let i = idx[j];
        let (gi, aip) = (g[i], at(i, P));
        for l in j..n {
            let k = idx[l];
            let (gk, akp) = (g[k], at(k, P));
            r[j][l] = (gp2 * at(i, k) - gp * gk * aip) + (gi * gk * app - gp * gi * akp);
        }
        rhs[j] = (gp2 * b[i] - gp * aip * d) + (gi * app * d - gp * gi * bp);
    }
    // Division-free elimination down to the last 2 × 2 block.
    let diag: [f64; N] = core::array::from_fn(|j| r[j][j]);
    let m = n.saturating_sub(2);
    let (mut ok, scale) = eliminate(&mut r, &mut rhs, n, m, &diag);
    let mut u = [0.0; N];
    if n == 1 {
        ok &= r[0][0] > ACCURATE_RELATIVE_PIVOT * diag[0];
        u[0] = rhs[0] / r[0][0];
    } else {
        // The last two pivots, a and the next level's a c − b², tested as above.
        let (j, l) = (n - 2, n - 1);
        let (pa, pb, pc) = (r[j][j], r[j][l], r[l][l]);
        let det = pa * pc - pb * pb;
        ok &= pa > ACCURATE_RELATIVE_PIVOT * diag[j] * scale;
        ok &= in_range(scale * pa);
        ok &= det > ACCURATE_RELATIVE_PIVOT * diag[l] * scale * pa;
        let inv = 1.0 / det;
        u[j] = (pc * rhs[j] - pb * rhs[l]) * inv;
        u[l] = (pa * rhs[l] - pb * rhs[j]) * inv;
    }
    if !ok {
        return None;
    }
    // x_p = d/g_p − Σ w_a u_a, w_a = g_a/g_p, with the u_k of the back-substitution (k < m)
    // written in the last two unknowns by a sweep that does not wait for them.
    let inv_gp = 1.0 / gp;
    let inv_r: [f64; N] = core::array::from_fn(|k| 1.0 / r[k][k]);
    let mut w: [f64; N] = core::array::from_fn(|j| g[idx[j]] * inv_gp);
    let mut xp = d * inv_gp;
    for k in 0..m {
        let wk = w[k] * inv_r[k];
        xp -= wk * rhs[k];
        for i in k + 1..n {
            w[i] -= wk * r[k][i];
        }
    }
    for k in (0..m).rev() {
        let mut v = rhs[k] * inv_r[k];
        for i in (k + 1..n).rev() {
            v -= (r[k][i] * inv_r[k]) * u[i];
        }
        u[k] = v;
    }
    for j in m..n {
        xp -= w[j] * u[j];
    }
    let mut x = [0.0; N];
    for j in 0..n {
        x[idx[j]] = u[j];
    }
    x[P] = xp;
    let mut ap = -bp;
    for i in 0..N {
        ap += at(P, i) * x[i];
    }
    let lambda = ap * inv_gp;
    (all_finite(&x) && lambda.is_finite()).then_some((x, lambda))
}

/// The first `levels` levels of division-free elimination of the leading n × n block of a
/// symmetric matrix (upper triangle) and its right side: a_ij ← p_k a_ij − a_ki a_kj for
/// i, j > k, p_k = a_kk. Level k's entries are c_k times the Schur complement's (c_0 = 1,
/// c_{k+1} = c_k p_k), so the LDLᵀ pivot d_k = p_k / c_k is tested against
/// [`ACCURATE_RELATIVE_PIVOT`] of its diagonal entry (`diag`, before elimination) by
/// multiplications. Returns whether every pivot passed and c stayed in range, and c.
#[inline(always)]
fn eliminate<const M: usize>(
    a: &mut [[f64; M]; M],
    rhs: &mut [f64; M],
    n: usize,
    levels: usize,
    diag: &[f64; M],
) -> (bool, f64) {
    let mut scale = 1.0;
    let mut ok = true;
    for k in 0..levels {
        let pk = a[k][k];
        ok &= pk > ACCURATE_RELATIVE_PIVOT * diag[k] * scale;
        for i in k + 1..n {
            let aki = a[k][i];
            for j in i..n {
                a[i][j] = pk * a[i][j] - aki * a[k][j];
            }
            rhs[i] = pk * rhs[i] - aki * rhs[k];
        }
        scale *= pk;
        ok &= in_range(scale);
    }
    (ok, scale)
}

/// The division-free eliminations' factor c_k within [2⁻⁹⁰⁰, 2⁹⁰⁰] (it grows like the entries
/// to the power 2^k; outside, the caller takes another path).
#[inline(always)]
fn in_range(scale: f64) -> bool {
    scale > f64::from_bits(123 << 52) && scale < f64::from_bits(1923 << 52)
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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// xorshift64*: uniform in [−1, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
            bits as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// A = RᵀR + δ I (positive definite, condition up to ~1e6 with δ small), B, b, d random;
    /// then the same problem in other units of the coordinates, q_i → q_i / s_i with s_i
    /// spread over ±`spread` decades: A → S A S, B → B S, b → S b (x → S⁻¹ x, λ unchanged).
    #[allow(clippy::type_complexity)]
    fn problem<const N: usize, const K: usize>(
        rng: &mut Rng,
        spread: f64,
    ) -> ([[f64; N]; N], [f64; N], [[f64; N]; K], [f64; K], [f64; N]) {
        let r: [[f64; N]; N] = core::array::from_fn(|_| core::array::from_fn(|_| rng.next()));
        let delta = 10f64.powf(-6.0 * rng.next().abs());
        let scale: [f64; N] = core::array::from_fn(|_| 10f64.powf(spread * rng.next()));
        let mut a = [[0.0; N]; N];
        for i in 0..N {
            for k in i..N {
                let mut s = if i == k { delta } else { 0.0 };
                for row in &r {
                    s += row[i] * row[k];
                }
                a[i][k] = s * scale[i] * scale[k];
            }
        }
        let b = core::array::from_fn(|i| rng.next() * scale[i]);
        let rows = core::array::from_fn(|_| core::array::from_fn(|i| rng.next() * scale[i]));
        let d = core::array::from_fn(|_| rng.next());
        (a, b, rows, d, scale)
    }

    /// The saddle-point system [A Bᵀ; B 0][x; −λ] = [b; d] by nalgebra's LU with full pivoting.
    fn reference<const N: usize, const K: usize>(
        a: &[[f64; N]; N],
        b: &[f64; N],
        rows: &[[f64; N]; K],
        d: &[f64; K],
    ) -> (Vec<f64>, Vec<f64>) {
        let n = N + K;
        let mut m = DMatrix::<f64>::zeros(n, n);
        for i in 0..N {
            for k in 0..N {
                m[(i, k)] = if i <= k { a[i][k] } else { a[k][i] };
            }
            for (j, row) in rows.iter().enumerate() {
                m[(i, N + j)] = row[i];
                m[(N + j, i)] = row[i];
            }
        }
        let rhs = DVector::from_iterator(n, b.iter().chain(d).copied());
        let sol = m.full_piv_lu().solve(&rhs).expect("regular test system");
        (
            sol.as_slice()[..N].to_vec(),
            sol.as_slice()[N..].iter().map(|v| -v).collect(),
        )
    }

    fn agrees<const N: usize, const K: usize>(seed: u64, spread: f64) {
        let mut rng = Rng(seed);
        let mut worst = [0.0_f64; 2];
        for case in 0..500 {
            let (a, b, rows, d, scale) = problem::<N, K>(&mut rng, spread);
            let (x, lambda) = saddle_solve(&a, &b, &rows, &d)
                .unwrap_or_else(|| panic!("N = {N}, K = {K}, case {case}: declined {a:?}"));
            let (xr, lr) = reference(&a, &b, &rows, &d);
            // Against the reference, in the units where the problem is well scaled (S x):
            // relative to the solution's size, within what the conditioning (δ down to 1e-6,
            // so ~1e6 ε) allows.
            let sx = |x: &[f64]| -> Vec<f64> { x.iter().zip(&scale).map(|(v, s)| v * s).collect() };
            let (x_s, xr_s) = (sx(&x), sx(&xr));
            let size = xr_s.iter().chain(&lr).fold(0.0_f64, |m, v| m.max(v.abs()));
            for (got, want) in x_s.iter().chain(&lambda).zip(xr_s.iter().chain(&lr)) {
                assert!(
                    (got - want).abs() <= 1e-8 * size,
                    "N = {N}, K = {K}, case {case}: {got} against {want}"
                );
            }
            // The residuals, each relative to the size of the terms it sums: A x − b − Bᵀλ;
            // and B x − d, whose x is found as z + Yλ (z = A⁻¹b, Y = A⁻¹Bᵀ, for any method
            // that eliminates A first), so its terms are B z and B Y λ (they cancel where A is
            // small against B).
            let (z, y) = ldlt_solve_with(&a, &b, &rows).expect("LDLᵀ solves");
            let at = |i: usize, k: usize| if i <= k { a[i][k] } else { a[k][i] };
            for i in 0..N {
                let terms = (0..N)
                    .map(|k| at(i, k) * x[k])
                    .chain((0..K).map(|j| -rows[j][i] * lambda[j]));
                let (sum, size) = terms.fold((-b[i], b[i].abs()), |(s, m), v| (s + v, m + v.abs()));
                worst[0] = worst[0].max(sum.abs() / size);
            }
            for (j, row) in rows.iter().enumerate() {
                let bx: f64 = row.iter().zip(&x).map(|(g, v)| g * v).sum();
                let size: f64 = (0..N)
                    .map(|i| {
                        let yl: f64 = (0..K).map(|l| (y[l][i] * lambda[l]).abs()).sum();
                        row[i].abs() * (z[i].abs() + yl)
                    })
                    .sum::<f64>()
                    + d[j].abs();
                worst[1] = worst[1].max((bx - d[j]).abs() / size);
            }
        }
        // Backward stable in practice: the largest seen is 1.7e-15 (N = 4, K = 2).
        assert!(
            worst[0] <= 1e-14 && worst[1] <= 1e-14,
            "N = {N}, K = {K}: relative residuals {worst:?}"
        );
    }

    #[test]
    fn saddle_solve_agrees_with_full_pivoting_lu() {
        agrees::<1, 1>(1, 0.0);
        agrees::<2, 1>(2, 0.0);
        agrees::<3, 1>(3, 0.0);
        agrees::<3, 2>(4, 0.0);
        agrees::<4, 1>(5, 0.0);
        agrees::<4, 2>(6, 0.0);
        agrees::<5, 1>(7, 0.0);
        agrees::<2, 2>(8, 0.0);
        // Coordinates in units 10⁻⁴…10⁴ apart: the pivot test is relative to each diagonal.
        agrees::<4, 1>(9, 4.0);
        agrees::<3, 2>(10, 4.0);
    }

    /// [`saddle_solve_one`] on random systems: A positive definite, or of rank N − 1 (the
    /// quaternion top's kind: the constraint fixes the direction without inertia), in units
    /// ±`spread` decades apart.
    fn one_agrees<const N: usize>(seed: u64, spread: f64, singular: bool) {
        let mut rng = Rng(seed);
        let mut worst = [0.0_f64; 2];
        for case in 0..500 {
            let (mut a, b, rows, d, scale) = problem::<N, 1>(&mut rng, spread);
            if singular {
                // A = S RᵀR S with R of N − 1 rows: rank N − 1.
                let r: [[f64; N]; N] =
                    core::array::from_fn(|_| core::array::from_fn(|_| rng.next()));
                for i in 0..N {
                    for k in i..N {
                        let s: f64 = r[..N - 1].iter().map(|row| row[i] * row[k]).sum();
                        a[i][k] = s * scale[i] * scale[k];
                    }
                }
            }
            let (x, lambda) = saddle_solve_one(&a, &b, &rows[0], d[0])
                .unwrap_or_else(|| panic!("N = {N}, case {case}: declined {a:?} {rows:?}"));
            let (xr, lr) = reference(&a, &b, &rows, &d);
            let sx = |x: &[f64]| -> Vec<f64> { x.iter().zip(&scale).map(|(v, s)| v * s).collect() };
            let (x_s, xr_s) = (sx(&x), sx(&xr));
            let size = xr_s.iter().chain(&lr).fold(0.0_f64, |m, v| m.max(v.abs()));
            for (got, want) in x_s.iter().chain([&lambda]).zip(xr_s.iter().chain(&lr)) {
                assert!(
                    (got - want).abs() <= 1e-8 * size,
                    "N = {N}, case {case}: {got} against {want}"
                );
            }
            // Residuals relative to the terms summed: A x − b − gλ, and g·x − d (x_p is found
            // from the constraint, so that one holds to the rounding of its own sum).
            let at = |i: usize, k: usize| if i <= k { a[i][k] } else { a[k][i] };
            for i in 0..N {
                let terms = (0..N)
                    .map(|k| at(i, k) * x[k])
                    .chain([-rows[0][i] * lambda]);
                let (sum, size) = terms.fold((-b[i], b[i].abs()), |(s, m), v| (s + v, m + v.abs()));
                worst[0] = worst[0].max(sum.abs() / size);
            }
            let terms = (0..N).map(|i| rows[0][i] * x[i]);
            let (sum, size) = terms.fold((-d[0], d[0].abs()), |(s, m), v| (s + v, m + v.abs()));
            worst[1] = worst[1].max(sum.abs() / size);
        }
        // The largest seen: 2.4e-15 and 2.6e-16.
        assert!(
            worst[0] <= 1e-14 && worst[1] <= 1e-15,
            "N = {N}: relative residuals {worst:?}"
        );
    }

    #[test]
    fn saddle_solve_one_agrees_with_full_pivoting_lu() {
        one_agrees::<2>(11, 0.0, false);
        one_agrees::<3>(12, 0.0, false);
        one_agrees::<4>(13, 0.0, false);
        one_agrees::<5>(14, 0.0, false);
        one_agrees::<3>(15, 0.0, true);
        one_agrees::<4>(16, 0.0, true);
        one_agrees::<5>(17, 0.0, true);
        one_agrees::<4>(18, 4.0, false);
        one_agrees::<4>(19, 4.0, true);
    }

    #[test]
    fn saddle_solve_one_declines_singular_systems_and_large_n() {
        let eye = [[1.0, 0.0], [0.0, 1.0]];
        // g = 0, or not finite.
        assert!(saddle_solve_one(&eye, &[1.0, 0.0], &[0.0, 0.0], 0.0).is_none());
        assert!(saddle_solve_one(&eye, &[1.0, 0.0], &[f64::NAN, 1.0], 0.0).is_none());
        assert!(saddle_solve_one(&eye, &[f64::INFINITY, 0.0], &[1.0, 1.0], 0.0).is_none());
        // A direction without inertia that the constraint does not fix (3 coordinates, the
        // constraint on the first, no inertia along the third).
        let a = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]];
        assert!(saddle_solve_one(&a, &[1.0, 0.0, 0.0], &[1.0, 0.0, 0.0], 0.0).is_none());
        // Nearly so: a pivot below √ε of its diagonal (the last 2 × 2 block's determinant).
        let a = [[1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0 + 1e-10]];
        assert!(saddle_solve_one(&a, &[1.0, 0.0, 0.0], &[1.0, 0.0, 0.0], 0.0).is_none());
        let a = [[1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0 + 1e-6]];
        assert!(saddle_solve_one(&a, &[1.0, 0.0, 0.0], &[1.0, 0.0, 0.0], 0.0).is_some());
        // Six coordinates: not this solve's sizes.
        let mut a6 = [[0.0; 6]; 6];
        for (i, row) in a6.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        assert!(saddle_solve_one(&a6, &[0.0; 6], &[1.0; 6], 0.0).is_none());
    }

    #[test]
    fn saddle_solve_declines_where_ldlt_would() {
        let g = [[1.0, 0.0]];
        // A pivot below √ε of its diagonal: the LDLᵀ test, by multiplications.
        let a = [[1.0, 1.0], [0.0, 1.0 + 1e-10]];
        assert!(ldlt_solve_with(&a, &[1.0, 0.0], &g).is_none());
        assert!(saddle_solve(&a, &[1.0, 0.0], &g, &[0.0]).is_none());
        // Just above it: both solve.
        let a = [[1.0, 1.0], [0.0, 1.0 + 1e-6]];
        assert!(ldlt_solve_with(&a, &[1.0, 0.0], &g).is_some());
        assert!(saddle_solve(&a, &[1.0, 0.0], &g, &[0.0]).is_some());
        // Indefinite A.
        assert!(saddle_solve(&[[1.0, 0.0], [0.0, -1.0]], &[1.0, 0.0], &g, &[0.0]).is_none());
        // A zero row of B, and two dependent rows.
        let eye = [[1.0, 0.0], [0.0, 1.0]];
        assert!(saddle_solve(&eye, &[1.0, 0.0], &[[0.0, 0.0]], &[0.0]).is_none());
        let dep = [[1.0, 2.0], [-2.0, -4.0 * (1.0 + 1e-12)]];
        assert!(saddle_solve(&eye, &[1.0, 0.0], &dep, &[0.0, 0.0]).is_none());
        // Not finite.
        assert!(saddle_solve(&eye, &[f64::NAN, 0.0], &g, &[0.0]).is_none());
        assert!(saddle_solve(&eye, &[1.0, 0.0], &[[f64::INFINITY, 0.0]], &[0.0]).is_none());
        // Entries far from one: the growing factor leaves its range and the caller is told
        // (solve_constrained scales by a power of two first, so this does not happen there).
        let tiny = [[1e-200, 0.0, 0.0], [0.0, 1e-200, 0.0], [0.0, 0.0, 1e-200]];
        assert!(saddle_solve(&tiny, &[1.0, 0.0, 0.0], &[[1.0, 1.0, 0.0]], &[0.0]).is_none());
    }
}
