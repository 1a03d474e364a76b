//! The order-by-order solve of the Taylor method: M₀ a_k = f_k − Σ_{j≥1} M_j a_{k−j} for the
//! accelerations' coefficients a_k, with one factorization of M₀ per step — the equations of
//! motion solved as the other solves of this module solve them, order by order. One LDLᵀ
//! ([`LdlOf`]) for every width; for a single run ([`Factor`]) a failed pivot test takes the shared
//! pivoting solve (or its typed error), for lanes it clears the lane in a mask. The series kernels
//! are in [`taylor`](crate::taylor).

use crate::error::DynamicsError;
use crate::linalg::{ACCURATE_RELATIVE_PIVOT, ldlt_solve};
use crate::real::Real;

use super::solve_mass_matrix;

/// A [`Real`] with the factorization of the Taylor method's order-by-order solve: for `f64`
/// [`Factor`], which pivots or explains where LDLᵀ fails; for lanes [`LdlOf`], the failed lanes
/// in a mask. The numbers the generated series (`Lagrangian::series_in`) runs over.
///
/// ```
/// use lagrange_runtime::{eom::{SeriesFactor, SeriesReal}, lanes::Lanes};
/// fn solve<R: SeriesReal>(m: R, b: R) -> R {
///     let (f, _) = R::Factor::<1>::new(&[[m]], &[b], ["x"], &[m], &[m], m);
///     let mut x = [R::NAN];
///     let _ = f.solve(&[b], &mut x, ["x"], &[m], &[m], m);
///     x[0]
/// }
/// assert_eq!(solve(2.0, 4.0), 2.0);
/// assert_eq!(solve(Lanes::<2>([2.0, 4.0]), Lanes::<2>([4.0; 2])).0, [2.0, 1.0]);
/// ```
pub trait SeriesReal: Real {
    /// The factorization of M₀ at this width.
    type Factor<const N: usize>: SeriesFactor<Self, N>;

    /// For a series with explicit accelerations (a system whose mass matrix is block diagonal in
    /// 1×1 blocks and 2×2 blocks with exact determinants) where a divisor is zero or not finite at
    /// order 0: a single run's error (M₀'s, as the solve gives it); `None` (the default) for
    /// lanes and tangents, which clear that lane's mask instead.
    fn declined<const N: usize>(
        _m0: &[[Self; N]; N],
        _b0: &[Self; N],
        _names: [&'static str; N],
        _q: &[Self; N],
        _qdot: &[Self; N],
        _t: Self,
    ) -> Option<DynamicsError> {
        None
    }
}

impl SeriesReal for f64 {
    type Factor<const N: usize> = Factor<N>;

    /// ```
    /// use lagrange_runtime::{eom::SeriesReal, DynamicsError};
    /// let e = f64::declined(&[[0.0]], &[1.0], ["x"], &[0.0], &[0.0], 0.0);
    /// assert!(matches!(e, Some(DynamicsError::SingularMassMatrix { .. })));
    /// ```
    fn declined<const N: usize>(
        m0: &[[f64; N]; N],
        b0: &[f64; N],
        names: [&'static str; N],
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Option<DynamicsError> {
        Some(match solve_mass_matrix(m0, b0, names, q, qdot, t) {
            Err(e) => e,
            // M₀ is regular, yet a determinant computed as one product of its factors is zero or
            // not finite: its entries are out of the range of a product.
            Ok(_) => DynamicsError::NonFinite {
                t,
                q: q.to_vec(),
                qdot: qdot.to_vec(),
                message: "the Taylor series divides by a determinant of a 2×2 block of the mass \
                          matrix ∂²L/∂q̇∂q̇ (or by a diagonal entry) that is zero or not finite in \
                          floating point here, although the matrix itself can be solved: its \
                          entries are too large or too small for their product. Try: other units \
                          for the coordinates or parameters, or another method (DOP853 solves \
                          M q̈ = f by elimination)."
                    .to_string(),
            },
        })
    }
}

impl<const W: usize, const F: bool> SeriesReal for crate::lanes::Lanes<W, F> {
    type Factor<const N: usize> = LdlOf<Self, N>;
}

/// The factorization of M₀ that every order of one Taylor step shares, over the kernels' number
/// type `R` (its [`SeriesReal::Factor`]): what the generated series calls. Nothing here wraps
/// the numbers in a `Result`: a `Result` around lanes would keep LLVM from holding them in vector
/// registers (measured: 27 % more instructions for the lanes series of the heavy top).
pub trait SeriesFactor<R: Real, const N: usize>: Sized {
    /// Factors M₀ (upper triangle), with the right-hand side of order 0 `b0` and the state
    /// (`names`, q, q̇, t) for an error. Returns the lanes where the factorization holds; a single
    /// run whose M₀ is singular keeps the error ([`error`](SeriesFactor::error)).
    fn new(
        m0: &[[R; N]; N],
        b0: &[R; N],
        names: [&'static str; N],
        q: &[R; N],
        qdot: &[R; N],
        t: R,
    ) -> (Self, R::Mask);

    /// Why M₀ has no solve (a single run's singular M₀), if so; the state as for `new`.
    fn error(
        &self,
        names: [&'static str; N],
        q: &[R; N],
        qdot: &[R; N],
        t: R,
    ) -> Option<DynamicsError>;

    /// x = M₀⁻¹ b (meaningful in the lanes where the factorization holds).
    fn solve(
        &self,
        b: &[R; N],
        x: &mut [R; N],
        names: [&'static str; N],
        q: &[R; N],
        qdot: &[R; N],
        t: R,
    ) -> Result<(), DynamicsError>;
}

/// LDLᵀ of M₀ over any [`Real`]: the operations of [`Ldlt`](crate::linalg::Ldlt) (factor and
/// solve) in the same order, so a lane whose factorization succeeds solves bit for bit as `Ldlt`
/// does. A lane where `Ldlt` would not give a factorization (a diagonal entry not finite, a pivot
/// not positive or below [`ACCURATE_RELATIVE_PIVOT`] of its diagonal entry) is cleared in the
/// mask [`factor`](LdlOf::factor) returns.
///
/// ```
/// use lagrange_runtime::{eom::LdlOf, lanes::Lanes};
/// let m = [[Lanes::<2>([2.0, -1.0])]];
/// let (f, ok) = LdlOf::<Lanes<2>, 1>::factor(&m);
/// assert_eq!(ok.0, [true, false]);
/// assert_eq!(f.solve(&[Lanes::<2>([4.0, 4.0])])[0].0[0], 2.0);
/// let (f, ok) = LdlOf::<f64, 1>::factor(&[[2.0]]);
/// assert!(ok && f.solve(&[4.0]) == [2.0]);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct LdlOf<R, const N: usize> {
    /// L below the diagonal, stored transposed in the upper triangle (as `Ldlt`).
    a: [[R; N]; N],
    /// 1/d_j.
    d_inv: [R; N],
}

impl<R: Real, const N: usize> LdlOf<R, N> {
    /// Factors M₀ (upper triangle) in every lane; the mask says where the factorization holds.
    #[inline(always)]
    pub fn factor(m: &[[R; N]; N]) -> (Self, R::Mask) {
        let mut ok = R::EVERY_LANE;
        for (i, row) in m.iter().enumerate() {
            ok = ok & row[i].finite();
        }
        let (mut a, mut u) = (*m, *m);
        let mut d_inv = [R::ZERO; N];
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
            ok = ok & dj.greater(R::ZERO) & dj.greater(m[j][j] * ACCURATE_RELATIVE_PIVOT);
            let r = R::from(1.0) / dj;
            d_inv[j] = r;
            for (l, &x) in a[j][j + 1..].iter_mut().zip(&row_j[j + 1..]) {
                *l = x * r;
            }
        }
        (LdlOf { a, d_inv }, ok)
    }

    /// M₀⁻¹ b in every lane (meaningful where the factorization holds).
    #[inline(always)]
    pub fn solve(&self, b: &[R; N]) -> [R; N] {
        ldlt_solve(&self.a, &self.d_inv, b)
    }
}

impl<R: Real, const N: usize> SeriesFactor<R, N> for LdlOf<R, N> {
    #[inline(always)]
    fn new(
        m0: &[[R; N]; N],
        _b0: &[R; N],
        _names: [&'static str; N],
        _q: &[R; N],
        _qdot: &[R; N],
        _t: R,
    ) -> (Self, R::Mask) {
        Self::factor(m0)
    }

    #[inline(always)]
    fn error(
        &self,
        _names: [&'static str; N],
        _q: &[R; N],
        _qdot: &[R; N],
        _t: R,
    ) -> Option<DynamicsError> {
        None
    }

    #[inline(always)]
    fn solve(
        &self,
        b: &[R; N],
        x: &mut [R; N],
        _names: [&'static str; N],
        _q: &[R; N],
        _qdot: &[R; N],
        _t: R,
    ) -> Result<(), DynamicsError> {
        *x = LdlOf::solve(self, b);
        Ok(())
    }
}

/// The factorization of M₀ of a single run: [`LdlOf`], or where its pivot test fails the shared
/// pivoting solve at every order (or that solve's error where M₀ is singular).
///
/// ```
/// use lagrange_runtime::eom::{Factor, SeriesFactor};
/// let (f, ok) = Factor::new(&[[2.0]], &[4.0], ["x"], &[0.0], &[0.0], 0.0);
/// assert!(ok && f.error(["x"], &[0.0], &[0.0], 0.0).is_none());
/// let mut x = [0.0];
/// f.solve(&[4.0], &mut x, ["x"], &[0.0], &[0.0], 0.0).unwrap();
/// assert_eq!(x, [2.0]);
/// let (f, _) = Factor::new(&[[0.0]], &[4.0], ["x"], &[0.0], &[0.0], 0.0);
/// assert!(f.error(["x"], &[0.0], &[0.0], 0.0).is_some());
/// ```
#[derive(Clone, Copy, Debug)]
pub enum Factor<const N: usize> {
    /// LDLᵀ of M₀ (its upper triangle).
    Ldlt(LdlOf<f64, N>),
    /// M₀ is not positive definite but regular: each order solves it with pivoting.
    Pivoting([[f64; N]; N]),
    /// M₀ is singular (M₀ and the right-hand side of order 0, for the shared solve's error).
    Singular([[f64; N]; N], [f64; N]),
}

impl<const N: usize> SeriesFactor<f64, N> for Factor<N> {
    #[inline(always)]
    fn new(
        m0: &[[f64; N]; N],
        b0: &[f64; N],
        names: [&'static str; N],
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> (Self, bool) {
        match LdlOf::factor(m0) {
            (f, true) => (Factor::Ldlt(f), true),
            // The shared solve either explains why M₀ is singular or solves an indefinite M₀
            // with pivoting.
            (_, false) => match solve_mass_matrix(m0, b0, names, q, qdot, t) {
                Ok(_) => (Factor::Pivoting(*m0), true),
                Err(_) => (Factor::Singular(*m0, *b0), true),
            },
        }
    }

    #[inline(always)]
    fn error(
        &self,
        names: [&'static str; N],
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Option<DynamicsError> {
        match self {
            Factor::Singular(m0, b0) => solve_mass_matrix(m0, b0, names, q, qdot, t).err(),
            _ => None,
        }
    }

    #[inline(always)]
    fn solve(
        &self,
        b: &[f64; N],
        x: &mut [f64; N],
        names: [&'static str; N],
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Result<(), DynamicsError> {
        *x = match self {
            Factor::Ldlt(f) => f.solve(b),
            Factor::Pivoting(m0) => solve_mass_matrix(m0, b, names, q, qdot, t)?,
            Factor::Singular(m0, b0) => {
                solve_mass_matrix(m0, b0, names, q, qdot, t)?;
                solve_mass_matrix(m0, b, names, q, qdot, t)?
            }
        };
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::Lanes;
    use crate::linalg::Ldlt;

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
        let (f, ok) = LdlOf::<Lanes<4>, 3>::factor(&m);
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
