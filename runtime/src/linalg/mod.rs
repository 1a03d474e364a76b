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

mod ldlt;
mod lu;
mod pseudo;
mod saddle;

pub(crate) use ldlt::ldlt_solve;
pub use ldlt::{Ldlt, ldlt_solve_with};
use lu::lu_solve_upper;
pub use lu::{lu_solve, lu_solve_dyn};
pub(crate) use pseudo::{RANK_TOL, least_norm_symmetric};
pub use saddle::{saddle_solve, saddle_solve_one};

#[cfg(test)]
mod tests;
