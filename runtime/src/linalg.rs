//! Small fixed-size dense solves for the mass matrix: LDLᵀ with scale-invariant pivot tests, and
//! LU (partial pivoting, on the equilibrated matrix) when the matrix is indefinite. Written for
//! N ≤ ~20 where loop overhead dominates.

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
    if m.iter().enumerate().any(|(i, row)| !row[i].is_finite()) || b.iter().any(|x| !x.is_finite())
    {
        return Err(SolveFailure::NonFinite);
    }
    // LDLᵀ in place on the upper triangle: l[k][i] (i<k) stored at a[i][k].
    let mut a = *m;
    let mut d = [0.0; N];
    for j in 0..N {
        let mut dj = a[j][j];
        for k in 0..j {
            dj -= a[k][j] * a[k][j] * d[k];
        }
        if dj.is_nan() || dj <= 0.0 {
            return lu_solve_upper(m, b);
        }
        if dj <= ACCURATE_RELATIVE_PIVOT * m[j][j] {
            return Err(SolveFailure::Singular {
                row: j,
                relative_pivot: dj / m[j][j],
            });
        }
        d[j] = dj;
        for i in j + 1..N {
            let mut s = a[j][i];
            for k in 0..j {
                s -= a[k][j] * a[k][i] * d[k];
            }
            a[j][i] = s / dj;
        }
    }
    let mut x = *b;
    for i in 0..N {
        for k in 0..i {
            x[i] -= a[k][i] * x[k];
        }
    }
    for i in 0..N {
        x[i] /= d[i];
    }
    for i in (0..N).rev() {
        for k in i + 1..N {
            x[i] -= a[i][k] * x[k];
        }
    }
    Ok(x)
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
    if a.iter().flatten().chain(x.iter()).any(|v| !v.is_finite()) {
        return Err(SolveFailure::NonFinite);
    }
    let tol = SINGULAR_RELATIVE_PIVOT * scale;
    for col in 0..N {
        let mut p = col;
        for r in col + 1..N {
            if a[r][col].abs() > a[p][col].abs() {
                p = r;
            }
        }
        if a[p][col].abs() <= tol {
            return Err(SolveFailure::Singular {
                row: col,
                relative_pivot: if scale > 0.0 {
                    a[p][col].abs() / scale
                } else {
                    0.0
                },
            });
        }
        a.swap(col, p);
        x.swap(col, p);
        for r in col + 1..N {
            let f = a[r][col] / a[col][col];
            let pivot_row = a[col];
            for (e, p) in a[r].iter_mut().zip(pivot_row).skip(col) {
                *e -= f * p;
            }
            x[r] -= f * x[col];
        }
    }
    for i in (0..N).rev() {
        for k in i + 1..N {
            x[i] -= a[i][k] * x[k];
        }
        x[i] /= a[i][i];
    }
    Ok(x)
}
