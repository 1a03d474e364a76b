//! DOP853 (Hairer, Nørsett & Wanner) as a [`Tableau`]: explicit Runge–Kutta of order 8 with the
//! 5th/3rd-order combined error estimate and the 7th-order dense output (three extra stages,
//! evaluated only for steps where a sample or an event needs the interpolant).

use super::control::Controller;
use super::dop853_coefficients::{A, C, D, E3, E5};
use super::explicit::pad_row;
use super::explicit::{Step, Tableau, Trial, end_rows};
use super::problem::{Slopes, Space};
use super::state::{Fault, Real};

/// The DOP853 tableau.
pub(crate) struct Dop853;

impl Tableau for Dop853 {
    const STAGES: usize = 12;
    const C: [f64; 16] = C;
    const A: [[f64; 16]; 16] = A;
    const ERROR_ROWS: [[f64; 16]; 2] = [pad_row(E5), pad_row(E3)];
    const ESTIMATES: usize = 2;
    /// Hairer's blend h·err5/√(count·(err5 + 0.01·err3)), as its logarithm.
    fn ln_err_of(sums: [f64; 2], h: f64, count: usize) -> f64 {
        let [err5, err3] = sums;
        let deno = err5 + 0.01 * err3;
        let deno = if deno <= 0.0 { 1.0 } else { deno };
        (h * err5).ln() - (deno * count as f64).ln() * 0.5
    }
    const ORDER: i32 = 8;
    const ROWS: usize = 8;
    /// The shared PI controller with β = 0.04 (expo1 = 1/8 − 0.2 β) and Hairer's dop853 factor
    /// limits [1/3, 6]. `dop853.f` defaults to β = 0 (as SciPy's controller does); over 30 heavy
    /// tops β = 0.04 needs fewer evaluations than that and drifts less (BENCHMARKS.md, "Drift
    /// against SciPy over 30 tops").
    const ADAPTIVE: bool = true;
    fn controller() -> Controller {
        Controller::new(1.0 / 8.0 - 0.04 * 0.2, 0.04, 0.333, 6.0)
    }
    #[inline(always)]
    fn solution<S: Space<N>, const N: usize>(out: &mut S, x: &S, h: S::R, k: &[S; 16]) {
        S::combine::<12>(out, x, h, &A[12], k, None);
    }
    /// Hairer's blend of the 5th- and 3rd-order estimates over the motion, as a logarithm.
    #[inline(always)]
    fn ln_err<S: Space<N>, const N: usize>(trial: Trial<'_, S, N>) -> S::R {
        let (e5, e3) = (trial.estimate(12, &E5), trial.estimate(12, &E3));
        // The sums Σ (e/w)² of both estimates, the q and q̇ halves added pairwise (a serial
        // chain of N additions: it is on the critical path).
        let (mut err5, mut err3) = (S::R::ZERO, S::R::ZERO);
        for i in 0..N {
            let (w0, w1) = (trial.weight(0, i), trial.weight(1, i));
            let (a, b) = (e5[0][i] / w0, e5[1][i] / w1);
            err5 += a.madd(a, b * b);
            let (a, b) = (e3[0][i] / w0, e3[1][i] / w1);
            err3 += a.madd(a, b * b);
        }
        let deno = err5 + err3 * 0.01;
        let deno = S::R::select(deno.at_most(S::R::ZERO), S::R::from(1.0), deno);
        // err = h · err5 / √(2N · deno), as its logarithm: the two logarithms run in parallel
        // where a division and a square root were a chain between this step and the next.
        (trial.h * err5).ln() - (deno * (2 * N) as f64).ln() * 0.5
    }
    /// The 7th-order dense output's rows, scaled by h: the three extra stages into `k[13..16]`
    /// (`k[12]` must hold F at x₁).
    #[inline(always)]
    fn dense<S: Space<N, R = f64>, F: Slopes<S, N, Error = Fault>, const N: usize>(
        f: &mut F,
        step: Step<'_, S, N>,
        rows: &mut [S; 8],
    ) -> Result<(), Fault> {
        let Step {
            cyclic,
            t,
            h,
            x,
            x1,
            k,
        } = step;
        let mut arg = x.clone();
        S::combine::<13>(&mut arg, x, h, &A[13], k, Some(&cyclic));
        f.slope(t + C[13] * h, &arg, &mut k[13])?;
        S::combine::<14>(&mut arg, x, h, &A[14], k, Some(&cyclic));
        f.slope(t + C[14] * h, &arg, &mut k[14])?;
        S::combine::<15>(&mut arg, x, h, &A[15], k, Some(&cyclic));
        f.slope(t + C[15] * h, &arg, &mut k[15])?;
        let mut w = x.clone();
        for (j, dj) in D.iter().enumerate() {
            S::weighted::<16>(&mut w, dj, k);
            S::map([&w], [&mut rows[4 + j]], |[w]| [h * w]);
        }
        let [r0, r1, r2, r3, ..] = rows;
        S::map([x, x1, &k[0], &k[12]], [r0, r1, r2, r3], |ends| {
            end_rows(h, ends)
        });
        Ok(())
    }
    /// The dense output at s = (t − t_old)/h ∈ [0, 1].
    #[inline(always)]
    fn eval<S: Space<N, R = f64>, const N: usize>(r: &[S; 8], _h: f64, s: f64, out: &mut S) {
        let s1 = 1.0 - s;
        S::map(
            [&r[0], &r[1], &r[2], &r[3], &r[4], &r[5], &r[6], &r[7]],
            [out],
            |[r0, r1, r2, r3, r4, r5, r6, r7]| {
                let conpar = r4 + s * (r5 + s1 * (r6 + s * r7));
                [r0 + s * (r1 + s1 * (r2 + s * (r3 + s1 * conpar)))]
            },
        );
    }
}
