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
            let r: [[f64; N]; N] = core::array::from_fn(|_| core::array::from_fn(|_| rng.next()));
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
