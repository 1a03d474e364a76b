//! Dormand–Prince 5(4) (`dopri5` of Hairer, Nørsett & Wanner) as a [`Tableau`]: FSAL, local
//! extrapolation, the error estimate of the embedded 4th-order solution and the 4th-order
//! continuous extension of Dormand & Prince / Shampine.

use super::control::Controller;
use super::explicit::{Step, Tableau, Trial, end_rows};
use super::explicit::{pad, pad_row};
use super::problem::{Slopes, Space};
use super::state::{Fault, Real};

/// The Dormand–Prince 5(4) tableau.
pub(crate) struct Dopri5;

/// b − b̂ (the embedded 4th-order solution), over the 7 stages.
pub(crate) const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// Dense-output coefficients (rcont5 of `dopri5.f`), over the 7 stages.
pub(crate) const D: [f64; 16] = pad_row([
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
]);

impl Tableau for Dopri5 {
    const STAGES: usize = 6;
    const C: [f64; 16] = pad_row([0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0]);
    const A: [[f64; 16]; 16] = pad([
        [0.0; 6],
        [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        // the 5th-order weights b (FSAL: stage 6 is F(t + h, x₁))
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ]);
    const ERROR_ROWS: [[f64; 16]; 2] = [pad_row(E), [0.0; 16]];
    const ESTIMATES: usize = 1;
    /// dopri5's norm √(h² Σ (e/w)² / count), as its logarithm.
    fn ln_err_of(sums: [f64; 2], h: f64, count: usize) -> f64 {
        0.5 * (h * h * sums[0] / count as f64).ln()
    }
    const ORDER: i32 = 5;
    const FSAL_IN_ERROR: bool = true;
    const EAGER_DENSE: bool = true;
    const ROWS: usize = 5;
    /// β = 0.04, expo1 = 1/5 − 0.75 β: Hairer's defaults for dopri5.
    const ADAPTIVE: bool = true;
    fn controller() -> Controller {
        Controller::new(0.2 - 0.04 * 0.75, 0.04, 0.2, 10.0)
    }
    #[inline(always)]
    fn solution<S: Space<N>, const N: usize>(out: &mut S, x: &S, h: S::R, k: &[S; 16]) {
        S::combine::<6>(out, x, h, &Self::A[6], k, None);
    }
    /// dopri5's norm √(Σ (h eᵢ/wᵢ)² / 2N), wᵢ = atol + rtol max(|xᵢ|, |x₁ᵢ|), as its logarithm.
    #[inline(always)]
    fn ln_err<S: Space<N>, const N: usize>(trial: Trial<'_, S, N>) -> S::R {
        let (e, h) = (trial.estimate(7, &E), trial.h);
        let mut s = S::R::ZERO;
        for i in 0..N {
            let (a, b) = (
                (e[0][i] * h) / trial.weight(0, i),
                (e[1][i] * h) / trial.weight(1, i),
            );
            s += a * a + b * b;
        }
        (s / S::R::from((2 * N) as f64)).ln() * 0.5
    }
    /// The continuous extension's rows (rcont of `dopri5.f`), scaled by h.
    #[inline(always)]
    fn dense<S: Space<N, R = f64>, F: Slopes<S, N, Error = Fault>, const N: usize>(
        _f: &mut F,
        step: Step<'_, S, N>,
        rows: &mut [S; 8],
    ) -> Result<(), Fault> {
        let Step { h, x, x1, k, .. } = step;
        let mut d = x.clone();
        S::weighted::<7>(&mut d, &D, k);
        let [r0, r1, r2, r3, r4, ..] = rows;
        S::map(
            [x, x1, &k[0], &k[6], &d],
            [r0, r1, r2, r3, r4],
            |[y, y1, k0, k6, d]| {
                let [a, b, c, e] = end_rows(h, [y, y1, k0, k6]);
                [a, b, c, e, h * d]
            },
        );
        Ok(())
    }
    /// y_old + θ(r1 + (1−θ)(r2 + θ(r3 + (1−θ) r4))).
    #[inline(always)]
    fn eval<S: Space<N, R = f64>, const N: usize>(rows: &[S; 8], _h: f64, theta: f64, out: &mut S) {
        let t1 = 1.0 - theta;
        S::map(
            [&rows[0], &rows[1], &rows[2], &rows[3], &rows[4]],
            [out],
            |[r0, r1, r2, r3, r4]| [r0 + theta * (r1 + t1 * (r2 + theta * (r3 + t1 * r4)))],
        );
    }
    /// Rebuilt for x₁ + δ the rows are r1 + δ, r2 − δ, r3 + 2δ: the output then ends at the new
    /// node.
    fn shift<S: Space<N, R = f64>, const N: usize>(rows: &mut [S; 8], old: &S, new: &S) {
        let [_, r1, r2, r3, ..] = rows;
        let (a, b, c) = (r1.clone(), r2.clone(), r3.clone());
        S::map([old, new, &a, &b, &c], [r1, r2, r3], |[o, n, a, b, c]| {
            let d = n - o;
            [a + d, b - d, c + 2.0 * d]
        });
    }
}
