//! Least-norm solves of symmetric positive semi-definite systems that may be rank deficient:
//! the multipliers of redundant constraints (G M⁻¹ Gᵀ λ = r with dependent rows of G) and the
//! projection onto them (G Gᵀ μ = r), by a symmetric eigendecomposition.

use nalgebra::{DMatrix, SymmetricEigen};

/// Eigenvalues at or below this fraction of the largest count as zero: √ε, where the LDLᵀ pivot
/// test ([`ACCURATE_RELATIVE_PIVOT`](super::ACCURATE_RELATIVE_PIVOT)) calls a system singular,
/// so a system that test refuses has at least one direction dropped here.
pub(crate) const RANK_TOL: f64 = super::ACCURATE_RELATIVE_PIVOT;

/// The least-norm solution of S x = r on S's range, and what of r lies outside it.
#[derive(Clone, Debug)]
pub(crate) struct LeastNorm {
    /// x = Σ over the kept eigenpairs of (vᵢ·r / σᵢ) vᵢ: orthogonal to S's null space.
    pub(crate) x: Vec<f64>,
    /// The largest |vᵢ·r| over the dropped eigenvectors: zero (to round-off) when S x = r is
    /// consistent.
    pub(crate) outside: f64,
    /// The rows the worst dropped eigenvector involves (its entries above a tenth of its
    /// largest), for a message naming the rows that contradict each other.
    pub(crate) rows: Vec<usize>,
}

/// The least-norm solution of S x = r for symmetric S given by its upper triangle (`s(i, k)`,
/// i ≤ k, of a k × k system), dropping the eigenvalues at or below [`RANK_TOL`] of the largest.
/// `None` for a non-finite S or r, or an S that is zero.
pub(crate) fn least_norm_symmetric(
    k: usize,
    s: impl Fn(usize, usize) -> f64,
    r: &[f64],
) -> Option<LeastNorm> {
    let m = DMatrix::from_fn(k, k, |i, j| if i <= j { s(i, j) } else { s(j, i) });
    if !(m.iter().chain(r).all(|x| x.is_finite())) || k != r.len() {
        return None;
    }
    let eig = SymmetricEigen::try_new(m, f64::EPSILON, 0)?;
    let big = eig.eigenvalues.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if big == 0.0 {
        return None;
    }
    let mut x = vec![0.0; k];
    let (mut outside, mut worst) = (0.0_f64, None);
    for (i, &sigma) in eig.eigenvalues.iter().enumerate() {
        let v = eig.eigenvectors.column(i);
        let along: f64 = (0..k).map(|j| v[j] * r[j]).sum();
        if sigma.abs() <= RANK_TOL * big {
            if worst.is_none() || along.abs() > outside {
                outside = outside.max(along.abs());
                worst = Some(i);
            }
        } else {
            for j in 0..k {
                x[j] += along / sigma * v[j];
            }
        }
    }
    let rows = match worst {
        Some(i) => {
            let v = eig.eigenvectors.column(i);
            let top = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            (0..k).filter(|&j| v[j].abs() > 0.1 * top).collect()
        }
        None => Vec::new(),
    };
    Some(LeastNorm { x, outside, rows })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// S = [[1, 2], [2, 4]] (rank 1): x = r's range part over 5 along (1, 2)/√5; r = (1, 2) is
    /// consistent (x = (1, 2)/5), r = (1, 0) is not (its part along (2, −1)/√5 is 2/√5).
    #[test]
    fn rank_one_least_norm_and_consistency() {
        let s = [[1.0, 2.0], [2.0, 4.0]];
        let ok = least_norm_symmetric(2, |i, j| s[i][j], &[1.0, 2.0]).unwrap();
        assert!((ok.x[0] - 0.2).abs() < 1e-15 && (ok.x[1] - 0.4).abs() < 1e-15);
        assert!(ok.outside < 1e-15);
        let bad = least_norm_symmetric(2, |i, j| s[i][j], &[1.0, 0.0]).unwrap();
        assert!((bad.outside - 2.0 / 5.0_f64.sqrt()).abs() < 1e-15);
        assert_eq!(bad.rows, vec![0, 1]);
        // Full rank: the solution itself.
        let full = least_norm_symmetric(2, |i, j| [[2.0, 0.0], [0.0, 4.0]][i][j], &[1.0, 1.0]);
        let full = full.unwrap();
        assert!((full.x[0] - 0.5).abs() < 1e-15 && (full.x[1] - 0.25).abs() < 1e-15);
        assert!(full.outside == 0.0 && full.rows.is_empty());
        assert!(least_norm_symmetric(2, |_, _| 0.0, &[1.0, 0.0]).is_none());
    }
}
