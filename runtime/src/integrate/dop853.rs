//! DOP853 (Hairer, Nørsett & Wanner): explicit Runge–Kutta of order 8 with the 5th/3rd-order
//! combined error estimate, PI step-size control and the 7th-order dense output (three extra
//! stages, evaluated only for steps where a sample or an event needs the interpolant).

use crate::lagrangian::Lagrangian;

use super::control::{effective_atol, initial_step, scales, sum_sq, Controller, StepControl};
use super::dop853_coefficients::{A, C, D, E3, E5};
use super::state::Stats;
use super::state::{combine, finite, rhs, stages, weighted, Fault, Y};
use super::stepper::Stepper;

/// One DOP853 step of size h from (t, y) with k₀ = f(t, y) already in `k[0]`: the stages 1..=11
/// into `k` (in place: no copy of the stage array per step), y₁ and the logarithm of the error
/// norm (Hairer's blend of the 5th- and 3rd-order estimates). Stage 12 (f at y₁) is not yet evaluated.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn step<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    t: f64,
    y: &Y<N>,
    k: &mut [Y<N>; 16],
    h: f64,
    rtol: f64,
    atol: f64,
    stats: &mut Stats,
) -> Result<(Y<N>, f64), Fault> {
    stages!((A, C), sys, t, y, h, k, stats; 1 2 3 4 5 6 7 8 9 10 11);
    let y1 = combine::<12, _, _, _, _>(y, h, &A[12], k);
    if !finite(&y1) {
        return Err(Fault::NonFinite);
    }
    let e5 = weighted::<12, _, _, _, _>(&E5, k);
    let e3 = weighted::<12, _, _, _, _>(&E3, k);
    let sk = scales(rtol, atol, y, &y1);
    let err5 = sum_sq(&e5, &sk);
    let err3 = sum_sq(&e3, &sk);
    let mut deno = err5 + 0.01 * err3;
    if deno <= 0.0 {
        deno = 1.0;
    }
    // err = h · err5 / √(2N · deno), as its logarithm: the two logarithms run in parallel where
    // a division and a square root were a chain between this step and the next.
    let ln_err = (h * err5).ln() - 0.5 * ((2 * N) as f64 * deno).ln();
    Ok((y1, ln_err))
}

/// The 7th-order dense-output coefficients on [t, t + h]; `k[12]` must hold f(t + h, y₁).
/// Evaluates the three extra stages into `k[13..16]`.
pub(crate) fn dense<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    t: f64,
    y: &Y<N>,
    y1: &Y<N>,
    k: &mut [Y<N>; 16],
    h: f64,
    stats: &mut Stats,
) -> Result<[Y<N>; 8], Fault> {
    stages!((A, C), sys, t, y, h, k, stats; 13 14 15);
    let mut r = [[[0.0; N]; 2]; 8];
    for (j, dj) in D.iter().enumerate() {
        let w = weighted::<16, _, _, _, _>(dj, k);
        for c in 0..2 {
            for i in 0..N {
                r[4 + j][c][i] = h * w[c][i];
            }
        }
    }
    for c in 0..2 {
        for i in 0..N {
            let ydiff = y1[c][i] - y[c][i];
            let bspl = h * k[0][c][i] - ydiff;
            r[0][c][i] = y[c][i];
            r[1][c][i] = ydiff;
            r[2][c][i] = bspl;
            r[3][c][i] = ydiff - h * k[12][c][i] - bspl;
        }
    }
    Ok(r)
}

/// Evaluates the dense output at s = (t − t_old)/h ∈ [0, 1].
pub(crate) fn eval_dense<const N: usize>(r: &[Y<N>; 8], s: f64) -> Y<N> {
    let s1 = 1.0 - s;
    let mut out = [[0.0; N]; 2];
    for c in 0..2 {
        for i in 0..N {
            let conpar = r[4][c][i] + s * (r[5][c][i] + s1 * (r[6][c][i] + s * r[7][c][i]));
            out[c][i] =
                r[0][c][i] + s * (r[1][c][i] + s1 * (r[2][c][i] + s * (r[3][c][i] + s1 * conpar)));
        }
    }
    out
}

/// The adaptive DOP853 stepper.
pub(crate) struct Dop853<'a, L, const N: usize> {
    sys: &'a L,
    rtol: f64,
    atol: f64,
    t: f64,
    y: Y<N>,
    t_old: f64,
    y_old: Y<N>,
    h_old: f64,
    /// Stages of the last accepted step (the trial steps of `advance` overwrite them in place);
    /// `k[12]` = f(t, y) at the current node.
    k: [Y<N>; 16],
    /// Dense-output coefficients of the last step, once evaluated.
    r: Option<[Y<N>; 8]>,
    sc: StepControl,
}

impl<'a, L: Lagrangian<N>, const N: usize> Dop853<'a, L, N> {
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
        let h = initial_step(sys, t0, &y0, &f, 8, rtol, atol, hmax, stats)?;
        let mut k = [[[0.0; N]; 2]; 16];
        k[12] = f;
        Ok(Dop853 {
            sys,
            rtol,
            atol,
            t: t0,
            y: y0,
            t_old: t0,
            y_old: y0,
            h_old: 0.0,
            k,
            r: None,
            // The shared PI controller with β = 0.04 (expo1 = 1/8 − 0.2 β) and Hairer's dop853
            // factor limits [1/3, 6]. `dop853.f` defaults to β = 0 (as SciPy's controller does);
            // over 30 heavy tops β = 0.04 needs fewer evaluations than that and drifts less
            // (BENCHMARKS.md, "Drift against SciPy over 30 tops").
            sc: StepControl::new(
                h,
                hmax,
                Controller::new(1.0 / 8.0 - 0.04 * 0.2, 0.04, 0.333, 6.0),
            ),
        })
    }
}

/// What one attempted step produced: y₁, ln err and, for an accepted step, f(t + h, y₁); or the
/// fault of a stage.
pub(crate) type Attempt<const N: usize> = Result<(Y<N>, f64, Option<Y<N>>), Fault>;

impl<'a, L: Lagrangian<N>, const N: usize> Dop853<'a, L, N> {
    /// Starts the next step from the current node: its first stage is f there (FSAL).
    #[inline(always)]
    pub(crate) fn begin_step(&mut self) {
        self.k[0] = self.k[12];
    }

    /// The next trial step and whether it ends at `t_end` (see [`StepControl::trial`]).
    #[inline(always)]
    pub(crate) fn trial(&mut self, t_end: f64) -> Result<(f64, bool), Fault> {
        self.sc.trial(self.t, t_end)
    }

    /// Attempts a step of size h from the current node; f at y₁ only if the error is accepted.
    #[inline(always)]
    pub(crate) fn attempt(&mut self, h: f64, stats: &mut Stats) -> Attempt<N> {
        step(
            self.sys,
            self.t,
            &self.y,
            &mut self.k,
            h,
            self.rtol,
            self.atol,
            stats,
        )
        .and_then(|(y1, ln_err)| {
            if ln_err <= 0.0 {
                // f at the new point: needed for the next step (FSAL) and the dense output.
                let f1 = rhs(self.sys, self.t + h, &y1, stats)?;
                Ok((y1, ln_err, Some(f1)))
            } else {
                Ok((y1, ln_err, None))
            }
        })
    }

    /// Takes the outcome of an attempt of size h (the stages in `k`): accepts it and moves to
    /// y₁ (true), or records the rejection or fault and proposes the retry (false).
    #[inline(always)]
    pub(crate) fn settle(
        &mut self,
        h: f64,
        last: bool,
        t_end: f64,
        attempt: Attempt<N>,
        stats: &mut Stats,
    ) -> bool {
        match attempt {
            Ok((y1, ln_err, Some(f1))) => {
                self.sc.accept(h, ln_err, stats);
                self.k[12] = f1;
                self.r = None;
                self.t_old = self.t;
                self.y_old = self.y;
                self.h_old = h;
                self.t = if last { t_end } else { self.t + h };
                self.y = y1;
                true
            }
            Ok((_, ln_err, None)) => {
                self.sc.reject(h, ln_err, stats);
                false
            }
            // A stage left the domain of the dynamics: retry with a smaller step.
            Err(f) => {
                self.sc.shrink(h, f, stats);
                false
            }
        }
    }

    /// The tolerances (rtol, atol) the error weights use.
    pub(crate) fn tolerances(&self) -> (f64, f64) {
        (self.rtol, self.atol)
    }

    /// The current node (t, y).
    pub(crate) fn node_state(&self) -> (f64, &Y<N>) {
        (self.t, &self.y)
    }

    /// The system.
    pub(crate) fn sys(&self) -> &'a L {
        self.sys
    }

    /// The stages (see [`stages_mut`](Self::stages_mut)).
    pub(crate) fn stages(&self) -> &[Y<N>; 16] {
        &self.k
    }

    /// The stages: `k[0]` = f at the node after [`begin_step`](Self::begin_step); an attempt
    /// fills `k[1..12]`.
    pub(crate) fn stages_mut(&mut self) -> &mut [Y<N>; 16] {
        &mut self.k
    }
}

impl<L: Lagrangian<N>, const N: usize> Stepper<N> for Dop853<'_, L, N> {
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
        // The dense output (built lazily from y_old, y and the stages) then ends at y; the slope
        // there (FSAL) as `Stepper::set_node` says: q̇ from y, q̈ kept.
        self.k[12][0] = y[1];
        self.y = y;
        self.r = None;
        Ok(())
    }
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        // The loop of `begin_step`, `trial`, `attempt` and `settle` (which the lanes engine calls
        // one by one), written out: as calls, the single-run loop was 2 % slower.
        self.k[0] = self.k[12];
        loop {
            let (h, last) = self.sc.trial(self.t, t_end)?;
            let attempt = step(
                self.sys,
                self.t,
                &self.y,
                &mut self.k,
                h,
                self.rtol,
                self.atol,
                stats,
            )
            .and_then(|(y1, ln_err)| {
                if ln_err <= 0.0 {
                    // f at the new point: needed for the next step (FSAL) and the dense output.
                    let f1 = rhs(self.sys, self.t + h, &y1, stats)?;
                    Ok((y1, ln_err, Some(f1)))
                } else {
                    Ok((y1, ln_err, None))
                }
            });
            match attempt {
                Ok((y1, ln_err, Some(f1))) => {
                    self.sc.accept(h, ln_err, stats);
                    self.k[12] = f1;
                    self.r = None;
                    self.t_old = self.t;
                    self.y_old = self.y;
                    self.h_old = h;
                    self.t = if last { t_end } else { self.t + h };
                    self.y = y1;
                    return Ok(());
                }
                Ok((_, ln_err, None)) => self.sc.reject(h, ln_err, stats),
                // A stage left the domain of the dynamics: retry with a smaller step.
                Err(f) => self.sc.shrink(h, f, stats),
            }
        }
    }
    fn interp(&mut self, t: f64, stats: &mut Stats) -> Result<Y<N>, Fault> {
        if t >= self.t {
            return Ok(self.y);
        }
        let r = match self.r {
            Some(r) => r,
            None => {
                let r = dense(
                    self.sys,
                    self.t_old,
                    &self.y_old,
                    &self.y,
                    &mut self.k,
                    self.h_old,
                    stats,
                )?;
                self.r = Some(r);
                r
            }
        };
        Ok(eval_dense(&r, (t - self.t_old) / self.h_old))
    }
}
