//! Dormand–Prince 5(4) (`dopri5` of Hairer, Nørsett & Wanner): FSAL, local extrapolation, PI
//! step-size control and the 4th-order continuous extension of Dormand & Prince / Shampine.

use crate::lagrangian::Lagrangian;

use super::control::{Controller, StepControl, effective_atol, initial_step, scales, sum_sq};
use super::state::Stats;
use super::state::{Fault, Y, combine, finite, rhs, stages, weighted};
use super::stepper::Stepper;

pub(crate) const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
pub(crate) const A: [[f64; 6]; 7] = [
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
    // the 5th-order weights b (FSAL: stage 7 is f(t + h, y₁))
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
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
pub(crate) const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// One Dormand–Prince step of size h from (t, y) with k₀ = f(t, y) already in `k[0]`: the stages
/// into `k` in place (k₆ = f(t+h, y₁)), y₁ and the error estimate h Σ eⱼkⱼ.
#[inline(always)]
pub(crate) fn step<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    t: f64,
    y: &Y<N>,
    k: &mut [Y<N>; 7],
    h: f64,
    stats: &mut Stats,
) -> Result<(Y<N>, Y<N>), Fault> {
    stages!((A, C), sys, t, y, h, k, stats; 1 2 3 4 5);
    let y1 = combine::<6, _, _, _, _>(y, h, &A[6], k);
    if !finite(&y1) {
        return Err(Fault::NonFinite);
    }
    k[6] = rhs(sys, t + h, &y1, stats)?;
    let mut err = weighted::<7, _, _, _, _>(&E, k);
    for row in err.iter_mut() {
        for e in row.iter_mut() {
            *e *= h;
        }
    }
    Ok((y1, err))
}

/// The coefficients of the continuous extension on [t, t + h].
pub(crate) fn dense<const N: usize>(y: &Y<N>, y1: &Y<N>, k: &[Y<N>; 7], h: f64) -> [Y<N>; 5] {
    let mut r = [[[0.0; N]; 2]; 5];
    let d = weighted::<7, _, _, _, _>(&D, k);
    for c in 0..2 {
        for i in 0..N {
            let ydiff = y1[c][i] - y[c][i];
            let bspl = h * k[0][c][i] - ydiff;
            r[0][c][i] = y[c][i];
            r[1][c][i] = ydiff;
            r[2][c][i] = bspl;
            r[3][c][i] = ydiff - h * k[6][c][i] - bspl;
            r[4][c][i] = h * d[c][i];
        }
    }
    r
}

/// Evaluates the continuous extension at θ = (t − t_old)/h ∈ [0, 1].
pub(crate) fn eval_dense<const N: usize>(r: &[Y<N>; 5], theta: f64) -> Y<N> {
    let t1 = 1.0 - theta;
    let mut out = [[0.0; N]; 2];
    for c in 0..2 {
        for i in 0..N {
            out[c][i] = r[0][c][i]
                + theta * (r[1][c][i] + t1 * (r[2][c][i] + theta * (r[3][c][i] + t1 * r[4][c][i])));
        }
    }
    out
}

/// The adaptive Dormand–Prince 5(4) stepper.
pub(crate) struct Dopri5<'a, L, const N: usize> {
    sys: &'a L,
    rtol: f64,
    atol: f64,
    t: f64,
    y: Y<N>,
    /// The stages of the latest step; `k[0]` = f(t, y) at the current node.
    k: [Y<N>; 7],
    t_old: f64,
    h_old: f64,
    r: [Y<N>; 5],
    sc: StepControl,
}

impl<'a, L: Lagrangian<N>, const N: usize> Dopri5<'a, L, N> {
    /// Starts at (t0, y0); evaluates f there and picks the first step.
    pub(crate) fn new(
        sys: &'a L,
        t0: f64,
        y0: Y<N>,
        rtol: f64,
        atol: f64,
        hmax: f64,
        stats: &mut Stats,
    ) -> Result<Self, Fault> {
        let atol = effective_atol(atol);
        let f = rhs(sys, t0, &y0, stats)?;
        let h = initial_step(sys, t0, &y0, &f, 5, rtol, atol, hmax, stats)?;
        Ok(Dopri5 {
            sys,
            rtol,
            atol,
            t: t0,
            y: y0,
            k: [f; 7],
            t_old: t0,
            h_old: 0.0,
            r: [y0; 5],
            // β = 0.04, expo1 = 1/5 − 0.75 β: Hairer's defaults for dopri5.
            sc: StepControl::new(h, hmax, Controller::new(0.2 - 0.04 * 0.75, 0.04, 0.2, 10.0)),
        })
    }
}

impl<L: Lagrangian<N>, const N: usize> Stepper<N> for Dopri5<'_, L, N> {
    fn t(&self) -> f64 {
        self.t
    }
    fn t_prev(&self) -> f64 {
        self.t_old
    }
    fn last_state(&self) -> Y<N> {
        self.y
    }
    fn set_node(&mut self, y: Y<N>, _stats: &mut Stats) -> Result<(), Fault> {
        // The dense output y_old + θ(r1 + (1−θ)(r2 + θ(r3 + (1−θ) r4))) with r1 = y1 − y_old,
        // r2 = h k0 − r1, r3 = r1 − h k6 − r2: rebuilt for y1 + δ it is r1 + δ, r2 − δ, r3 + 2δ,
        // so it ends at y.
        for c in 0..2 {
            for i in 0..N {
                let d = y[c][i] - self.y[c][i];
                self.r[1][c][i] += d;
                self.r[2][c][i] -= d;
                self.r[3][c][i] += 2.0 * d;
            }
        }
        // The slope there (FSAL) as `Stepper::set_node` says: q̇ from y, q̈ kept.
        self.k[0][0] = y[1];
        self.y = y;
        Ok(())
    }
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        loop {
            let (h, last) = self.sc.trial(self.t, t_end)?;
            match step(self.sys, self.t, &self.y, &mut self.k, h, stats) {
                Ok((y1, e)) => {
                    let sk = scales(self.rtol, self.atol, &self.y, &y1);
                    // ln of err = √(Σ / 2N); +∞ or NaN for a non-finite estimate (`reject`
                    // shrinks the step then).
                    let ln_err = 0.5 * (sum_sq(&e, &sk) / (2 * N) as f64).ln();
                    if ln_err <= 0.0 {
                        self.sc.accept(h, ln_err, stats);
                        self.r = dense(&self.y, &y1, &self.k, h);
                        self.t_old = self.t;
                        self.h_old = h;
                        self.t = if last { t_end } else { self.t + h };
                        self.y = y1;
                        self.k[0] = self.k[6];
                        return Ok(());
                    }
                    self.sc.reject(h, ln_err, stats);
                }
                // A stage left the domain of the dynamics: retry with a smaller step.
                Err(f) => self.sc.shrink(h, f, stats),
            }
        }
    }
    fn interp(&mut self, t: f64, _stats: &mut Stats) -> Result<Y<N>, Fault> {
        if t >= self.t {
            return Ok(self.y);
        }
        let theta = (t - self.t_old) / self.h_old;
        Ok(eval_dense(&self.r, theta))
    }
    /// The 5 rows of the continuous extension (`eval_dense`'s), scaled by h.
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, _stats: &mut Stats) -> Result<f64, Fault> {
        rows.extend_from_slice(&self.r);
        Ok(self.h_old)
    }
}
