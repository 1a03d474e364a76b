//! The classical 4th-order Runge–Kutta method as a [`Tableau`]: a fixed step, and cubic Hermite
//! interpolation between nodes (from x and F = ẋ at both ends) for samples and events.

use super::explicit::{Step, Tableau, pad, pad_row};
use super::problem::{Slopes, Space};
use super::state::Fault;

/// The classical RK4 tableau.
pub(crate) struct Rk4;

impl Tableau for Rk4 {
    const STAGES: usize = 4;
    const C: [f64; 16] = pad_row([0.0, 0.5, 0.5, 1.0]);
    const A: [[f64; 16]; 16] = pad([
        [0.0; 4],
        [0.5, 0.0, 0.0, 0.0],
        [0.0, 0.5, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    ]);
    const ORDER: i32 = 4;
    const ROWS: usize = 4;
    #[inline(always)]
    fn solution<S: Space<N>, const N: usize>(out: &mut S, x: &S, h: S::R, k: &[S; 16]) {
        S::combine::<4>(out, x, h, &Self::A[4], k, None);
    }
    /// The cubic Hermite interpolant's rows: x and F = ẋ at both nodes (`eval`'s order).
    #[inline(always)]
    fn dense<S: Space<N, R = f64>, F: Slopes<S, N, Error = Fault>, const N: usize>(
        _f: &mut F,
        step: Step<'_, S, N>,
        rows: &mut [S; 8],
    ) -> Result<(), Fault> {
        let Step { x, x1, k, .. } = step;
        rows[0] = x.clone();
        rows[1] = k[0].clone();
        rows[2] = x1.clone();
        rows[3] = k[4].clone();
        Ok(())
    }
    /// Cubic Hermite interpolation on [t₀, t₀ + h] from x and ẋ at both ends (3rd order).
    #[inline(always)]
    fn eval<S: Space<N, R = f64>, const N: usize>(rows: &[S; 8], h: f64, s: f64, out: &mut S) {
        let h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
        let h10 = s * (1.0 - s) * (1.0 - s);
        let h01 = s * s * (3.0 - 2.0 * s);
        let h11 = s * s * (s - 1.0);
        S::map(
            [&rows[0], &rows[1], &rows[2], &rows[3]],
            [out],
            |[y0, f0, y1, f1]| [h00 * y0 + h10 * h * f0 + h01 * y1 + h11 * h * f1],
        );
    }
}
