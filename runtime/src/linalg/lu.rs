//! LU with partial pivoting on the symmetrically equilibrated matrix: the fallback for an
//! indefinite M, and the dynamic-size solve of the linearization on constraints.

use super::{SINGULAR_RELATIVE_PIVOT, SolveFailure};

pub(super) fn lu_solve_upper<const N: usize>(
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
