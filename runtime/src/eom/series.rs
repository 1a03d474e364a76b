//! The order-by-order solve of the Taylor method: M₀ a_k = f_k − Σ_{j≥1} M_j a_{k−j} for the
//! accelerations' coefficients a_k, with one factorization of M₀ per step ([`Factor`]; W members
//! at once: [`FactorLanes`]) — the equations of motion solved as the other solves of this module
//! solve them, order by order. The series kernels are in [`taylor`](crate::taylor).

use crate::error::DynamicsError;
use crate::lanes::{Lanes, Mask};
use crate::linalg::{ldlt_solve, Ldlt, ACCURATE_RELATIVE_PIVOT};

use super::solve_mass_matrix;

/// The factorization of M₀ that every order of one step shares.
///
/// ```
/// use lagrange_runtime::eom::Factor;
/// let f = Factor::new(&[[2.0]], &[4.0], ["x"], &[0.0], &[0.0], 0.0).unwrap();
/// assert_eq!(f.solve(&[4.0], ["x"], &[0.0], &[0.0], 0.0).unwrap(), [2.0]);
/// ```
#[derive(Clone, Copy, Debug)]
pub enum Factor<const N: usize> {
    /// LDLᵀ of M₀ (its upper triangle).
    Ldlt(Ldlt<N>),
    /// M₀ is not positive definite but regular: each order solves it with pivoting.
    Pivoting([[f64; N]; N]),
}

impl<const N: usize> Factor<N> {
    /// Factors M₀ (upper triangle), with the right-hand side of order 0 `b0` and the state
    /// (`names`, q, q̇, t) for an error: the error of `solve_mass_matrix` when M₀ is singular.
    #[inline]
    pub fn new(
        m0: &[[f64; N]; N],
        b0: &[f64; N],
        names: [&'static str; N],
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Result<Self, DynamicsError> {
        match Ldlt::factor(m0) {
            Ok(f) => Ok(Factor::Ldlt(f)),
            Err(_) => {
                // The shared solve either explains why M₀ is singular or solves an indefinite
                // M₀ with pivoting.
                solve_mass_matrix(m0, b0, names, q, qdot, t)?;
                Ok(Factor::Pivoting(*m0))
            }
        }
    }

    /// M₀⁻¹ b.
    #[inline]
    pub fn solve(
        &self,
        b: &[f64; N],
        names: [&'static str; N],
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Result<[f64; N], DynamicsError> {
        match self {
            Factor::Ldlt(f) => Ok(f.solve(b)),
            Factor::Pivoting(m0) => solve_mass_matrix(m0, b, names, q, qdot, t),
        }
    }
}

/// The factorization of M₀ for W members at once: the operations of [`Ldlt`] (factor and solve)
/// lane by lane, in the same order, so a lane whose factorization succeeds solves bit for bit as
/// the scalar [`Factor`] does. A lane where [`Ldlt`] would not give a factorization (a diagonal
/// entry not finite, a pivot not positive or below [`ACCURATE_RELATIVE_PIVOT`] of its diagonal
/// entry) is cleared in the mask [`new`](FactorLanes::new) returns: the caller computes that
/// member's series with the scalar code, which explains or pivots.
///
/// ```
/// use lagrange_runtime::{eom::FactorLanes, lanes::Lanes};
/// let m = [[Lanes([2.0, -1.0])]];
/// let (f, ok) = FactorLanes::<1, 2>::new(&m);
/// assert_eq!(ok.0, [true, false]);
/// assert_eq!(f.solve(&[Lanes([4.0, 4.0])])[0].0[0], 2.0);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct FactorLanes<const N: usize, const W: usize> {
    /// L below the diagonal, stored transposed in the upper triangle (as `Ldlt`).
    a: [[Lanes<W>; N]; N],
    /// 1/d_j.
    d_inv: [Lanes<W>; N],
}

impl<const N: usize, const W: usize> FactorLanes<N, W> {
    /// Factors M₀ (upper triangle) in every lane; the mask says where the factorization holds.
    #[inline(always)]
    pub fn new(m: &[[Lanes<W>; N]; N]) -> (Self, Mask<W>) {
        let mut ok = Mask::splat(true);
        for (i, row) in m.iter().enumerate() {
            ok = ok & row[i].finite();
        }
        let (mut a, mut u) = (*m, *m);
        let mut d_inv = [Lanes::ZERO; N];
        for j in 0..N {
            let (done, rest) = u.split_at_mut(j);
            let Some(row_j) = rest.first_mut() else {
                break;
            };
            for (k, row_k) in done.iter().enumerate() {
                let lkj = a[k][j];
                for (x, &y) in row_j[j..].iter_mut().zip(&row_k[j..]) {
                    *x -= lkj * y;
                }
            }
            let dj = row_j[j];
            ok = ok & dj.gt(0.0) & dj.gt(ACCURATE_RELATIVE_PIVOT * m[j][j]);
            let r = 1.0 / dj;
            d_inv[j] = r;
            for (l, &x) in a[j][j + 1..].iter_mut().zip(&row_j[j + 1..]) {
                *l = x * r;
            }
        }
        (FactorLanes { a, d_inv }, ok)
    }

    /// M₀⁻¹ b in every lane (meaningful where the factorization holds).
    #[inline(always)]
    pub fn solve(&self, b: &[Lanes<W>; N]) -> [Lanes<W>; N] {
        ldlt_solve(&self.a, &self.d_inv, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lanes factorization solves as `Ldlt` does, bit for bit, and flags the lanes `Ldlt`
    /// refuses (indefinite, tiny pivot, not finite).
    #[test]
    fn lanes_factor_is_ldlt_per_lane() {
        let ms: [[[f64; 3]; 3]; 4] = [
            [[4.0, 1.2, -0.7], [0.0, 3.1, 0.4], [0.0, 0.0, 2.2]],
            [[1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [[1.0, 1.0, 0.0], [0.0, 1.0 + 1e-12, 0.0], [0.0, 0.0, 1.0]],
            [[f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        ];
        let m: [[Lanes<4>; 3]; 3] = core::array::from_fn(|i| {
            core::array::from_fn(|j| Lanes(core::array::from_fn(|l| ms[l][i][j])))
        });
        let b = [
            Lanes([0.3, 1.0, 2.0, 3.0]),
            Lanes([-1.7, 0.0, 1.0, 0.0]),
            Lanes([0.9; 4]),
        ];
        let (f, ok) = FactorLanes::<3, 4>::new(&m);
        let x = f.solve(&b);
        for l in 0..4 {
            let scalar = Ldlt::factor(&ms[l]);
            assert_eq!(ok.0[l], scalar.is_ok(), "lane {l}");
            if let Ok(s) = scalar {
                let xs = s.solve(&core::array::from_fn(|i| b[i].0[l]));
                for i in 0..3 {
                    assert_eq!(x[i].0[l].to_bits(), xs[i].to_bits());
                }
            }
        }
    }
}
