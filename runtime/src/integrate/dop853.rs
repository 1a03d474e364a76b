//! DOP853 (Hairer, Nørsett & Wanner): explicit Runge–Kutta of order 8 with the 5th/3rd-order
//! combined error estimate, PI step-size control and the 7th-order dense output (three extra
//! stages, evaluated only for steps where a sample or an event needs the interpolant).

use crate::lagrangian::Lagrangian;

use crate::real::Real;

use super::control::{Controller, StepControl, effective_atol, initial_step};
use super::dop853_coefficients::{A, C, D, E3, E5};
use super::state::Stats;
use super::state::{Fault, Y, YOf, combine, finite, rhs, stages, weighted};
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
    let out = step_of(L::CYCLIC, Single { sys, stats }, t, y, k, h, rtol, atol)?;
    if !finite(&out.y1) {
        return Err(Fault::NonFinite);
    }
    Ok((out.y1, out.ln_err))
}

/// The arithmetic of one DOP853 attempt at any width (`f64` for a single run, lanes for W
/// ensemble members, each lane the single run's operations): the stages 1..=11 into `k` with
/// `f(t, y, a)` writing the accelerations (an error ends the attempt), y₁, ln err, and for lanes a sum that
/// is 0 in the lanes where every stage and y₁ is finite (NaN elsewhere; 0 for a single run,
/// whose right-hand side reports its own failures).
///
/// The stage positions of cyclic coordinates are not formed (see
/// [`hold_cyclic`](super::state::hold_cyclic)).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn step_of<R: Real, F: Accelerations<R, N>, const N: usize>(
    cyclic: [bool; N],
    mut f: F,
    t: R,
    y: &YOf<R, N>,
    k: &mut [YOf<R, N>; 16],
    h: R,
    rtol: R,
    atol: R,
) -> Result<Attempted<R, N>, F::Error> {
    // 0 · x is 0 for finite x and NaN otherwise.
    let mut finite = R::ZERO;
    macro_rules! stages {
        ($($s:literal)*) => {$(
            let mut ys = combine::<$s, _, _, _, _>(y, h, &A[$s], k);
            // The same values either way; LLVM keeps the fewest instructions with the whole row
            // rebuilt at width 1 (−1.0 % for a run) and with single stores in lanes (−4.6 %).
            if R::WIDTH == 1 {
                let held: [R; N] =
                    core::array::from_fn(|i| if cyclic[i] { y[0][i] } else { ys[0][i] });
                ys[0] = held;
            } else {
                for i in 0..N {
                    if cyclic[i] {
                        ys[0][i] = y[0][i];
                    }
                }
            }
            let a = f.at(t + h * C[$s], &ys)?;
            if R::WIDTH > 1 {
                for ai in &a {
                    finite += *ai * 0.0;
                }
            }
            k[$s] = [ys[1], a];
        )*};
    }
    stages!(1 2 3 4 5 6 7 8 9 10 11);
    let y1 = combine::<12, _, _, _, _>(y, h, &A[12], k);
    if R::WIDTH > 1 {
        for x in y1.iter().flatten() {
            finite += *x * 0.0;
        }
    }
    let e5 = weighted::<12, _, _, _, _>(&E5, k);
    let e3 = weighted::<12, _, _, _, _>(&E3, k);
    // The weights atol + rtol·max(|y|, |y₁|) and the sums Σ (e/w)² of both estimates, the q and
    // q̇ halves added pairwise (a serial chain of N additions: it is on the critical path).
    let (mut err5, mut err3) = (R::ZERO, R::ZERO);
    for i in 0..N {
        let w = |c: usize| rtol.madd(y[c][i].abs().max(y1[c][i].abs()), atol);
        let (w0, w1) = (w(0), w(1));
        let (a, b) = (e5[0][i] / w0, e5[1][i] / w1);
        err5 += a.madd(a, b * b);
        let (a, b) = (e3[0][i] / w0, e3[1][i] / w1);
        err3 += a.madd(a, b * b);
    }
    let deno = err5 + err3 * 0.01;
    let deno = R::select(deno.at_most(R::ZERO), R::from(1.0), deno);
    // err = h · err5 / √(2N · deno), as its logarithm: the two logarithms run in parallel where
    // a division and a square root were a chain between this step and the next.
    let ln_err = (h * err5).ln() - (deno * (2 * N) as f64).ln() * 0.5;
    Ok(Attempted { y1, ln_err, finite })
}

/// The accelerations at a stage of [`step_of`]: a method rather than a closure, so that it is
/// inlined at each of the eleven stages whatever its size (a closure's body is LLVM's to inline
/// or not: it did not, and the cyclic positions' dead sums stayed, +8 % for a run).
pub(crate) trait Accelerations<R, const N: usize> {
    /// Why the right-hand side failed.
    type Error;
    /// q̈ at (t, y).
    fn at(&mut self, t: R, y: &YOf<R, N>) -> Result<[R; N], Self::Error>;
}

/// A single run's accelerations, counted in its statistics.
struct Single<'a, L> {
    sys: &'a L,
    stats: &'a mut Stats,
}

impl<L: Lagrangian<N>, const N: usize> Accelerations<f64, N> for Single<'_, L> {
    type Error = Fault;
    #[inline(always)]
    fn at(&mut self, t: f64, y: &Y<N>) -> Result<[f64; N], Fault> {
        Ok(rhs(self.sys, t, y, self.stats)?[1])
    }
}

/// What [`step_of`] gives: y₁, ln err, and (lanes) the sum that is 0 where everything was finite.
/// An out parameter, not a `Result`'s payload: a `Result` around lanes keeps LLVM from holding
/// them in vector registers.
#[derive(Clone, Copy)]
pub(crate) struct Attempted<R, const N: usize> {
    pub(crate) y1: YOf<R, N>,
    pub(crate) ln_err: R,
    pub(crate) finite: R,
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
        let r = self.dense_output(stats)?;
        Ok(eval_dense(&r, (t - self.t_old) / self.h_old))
    }
    /// The 8 rows of the 7th-order dense output (`eval_dense`'s), scaled by h.
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, stats: &mut Stats) -> Result<f64, Fault> {
        let r = self.dense_output(stats)?;
        rows.extend_from_slice(&r);
        Ok(self.h_old)
    }
}

impl<L: Lagrangian<N>, const N: usize> Dop853<'_, L, N> {
    /// The dense-output coefficients of the last step, evaluated on first use (three more
    /// stages) and kept until the next step.
    fn dense_output(&mut self, stats: &mut Stats) -> Result<[Y<N>; 8], Fault> {
        if let Some(r) = self.r {
            return Ok(r);
        }
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
        Ok(r)
    }
}
