//! The saddle-point solves of small constrained systems: division-free elimination of
//! [M Gᵀ; G 0], and one constraint by coordinate partitioning.

use super::{ACCURATE_RELATIVE_PIVOT, all_finite};

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
