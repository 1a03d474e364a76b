//! The explicit Runge–Kutta methods, written once: one stepper ([`ExplicitRk`]) over a
//! [`Tableau`] (RK4, Dormand–Prince 5(4), DOP853: coefficients, error estimate and dense-output
//! rule) and a [`Problem`] (a plain run, or the motion with its variations), and one attempt
//! ([`attempt`]) that the single runs, the SIMD lanes of an ensemble and the sensitivity runs all
//! take: the stages, y₁ and the error of a step, over any [`Space`] of states.

use core::marker::PhantomData;

use super::control::{Controller, StepControl, effective_atol, initial_step};

use super::problem::{Problem, Slopes, Space};
use super::state::{Fault, Real, Stats, Y, YOf, weighted_by};
use super::stepper::{FixedGrid, Stepper};
use crate::lagrangian::Lagrangian;

/// A tableau and its rules: the stages `k[0..STAGES]` of a step with
/// `k[s] = F(t + C[s] h, x + h Σ_{j<s} A[s][j] k[j])`, the new state x₁ from row `A[STAGES]`
/// ([`solution`](Self::solution)), `k[STAGES]` = F(t + h, x₁) (the next step's first stage),
/// the error estimate over the motion and the dense output.
pub(crate) trait Tableau: 'static {
    /// The stages of a step.
    const STAGES: usize;
    /// The nodes c, padded with zeros.
    const C: [f64; 16];
    /// The coefficients a (row s for stage s; row `STAGES` the weights b), padded with zeros.
    const A: [[f64; 16]; 16];
    /// The order Hairer's initial step assumes (adaptive tableaux).
    const ORDER: i32;
    /// Whether the error estimate uses `k[STAGES]` = F(t + h, x₁) (evaluated in every attempt
    /// then; otherwise only in an accepted one).
    const FSAL_IN_ERROR: bool = false;
    /// Whether the dense output is formed at every accepted step (and shifted with the node by
    /// [`shift`](Self::shift)); otherwise on first use, from the stages the step leaves.
    const EAGER_DENSE: bool = false;
    /// Whether the step is adaptive (else fixed, on a grid: the error estimate and the
    /// controller below are then not used, and a fixed-step tableau leaves them out).
    const ADAPTIVE: bool = false;
    /// The step-size controller of an adaptive tableau.
    fn controller() -> Controller {
        Controller::new(0.2, 0.0, 0.2, 10.0)
    }
    /// x₁ = x + h Σ b_j k_j (a sum of `STAGES` terms: the constant length of `combine`).
    fn solution<S: Space<N>, const N: usize>(out: &mut S, x: &S, h: S::R, k: &[S; 16]);
    /// The rows of the error estimates Σ_j E_j k_j (`ESTIMATES` of them; DOP853 has its 5th-
    /// and 3rd-order ones, Dormand–Prince one), for a state's parts other than the motion.
    const ERROR_ROWS: [[f64; 16]; 2] = [[0.0; 16]; 2];
    /// How many of [`ERROR_ROWS`](Self::ERROR_ROWS) the estimate takes.
    const ESTIMATES: usize = 0;
    /// ln err from the sums Σ (e_r,i / w_i)² of each estimate over `count` components (the
    /// motion's norm of [`ln_err`](Self::ln_err), for other parts of a state).
    fn ln_err_of(_sums: [f64; 2], _h: f64, _count: usize) -> f64 {
        0.0
    }
    /// ln of the error norm of a trial step over the motion (0 for a fixed step).
    fn ln_err<S: Space<N>, const N: usize>(_trial: Trial<'_, S, N>) -> S::R {
        S::R::ZERO
    }
    /// The dense-output rows of the step of size h from (t, x) to x₁ (its stages in `k`, with
    /// `k[STAGES]` = F at x₁), into `rows` (as many as [`eval`](Self::eval) reads); extra
    /// stages through `f`.
    fn dense<S: Space<N, R = f64>, F: Slopes<S, N, Error = Fault>, const N: usize>(
        f: &mut F,
        step: Step<'_, S, N>,
        rows: &mut [S; 8],
    ) -> Result<(), Fault>;
    /// How many of the rows [`dense`](Self::dense) fills.
    const ROWS: usize;
    /// The dense output at θ = (t − t₀)/h ∈ [0, 1] into `out`.
    fn eval<S: Space<N, R = f64>, const N: usize>(rows: &[S; 8], h: f64, theta: f64, out: &mut S);
    /// Moves eagerly formed rows so that they end at the node moved from `old` to `new` (a
    /// projection onto constraints). Nothing for lazily formed rows.
    fn shift<S: Space<N, R = f64>, const N: usize>(_rows: &mut [S; 8], _old: &S, _new: &S) {}
}

/// Pads a tableau's coefficients to 16 × 16.
pub(crate) const fn pad<const R: usize, const C: usize>(a: [[f64; C]; R]) -> [[f64; 16]; 16] {
    let mut out = [[0.0; 16]; 16];
    let mut i = 0;
    while i < R {
        let mut j = 0;
        while j < C {
            out[i][j] = a[i][j];
            j += 1;
        }
        i += 1;
    }
    out
}

/// Pads a row to 16.
pub(crate) const fn pad_row<const C: usize>(a: [f64; C]) -> [f64; 16] {
    pad([a])[0]
}

/// A trial step as its error estimate reads it: from x to x₁ with size h, its stages and the
/// tolerances.
pub(crate) struct Trial<'a, S: Space<N>, const N: usize> {
    pub(crate) x: &'a S,
    pub(crate) x1: &'a S,
    pub(crate) k: &'a [S; 16],
    pub(crate) h: S::R,
    pub(crate) rtol: S::R,
    pub(crate) atol: S::R,
}

impl<S: Space<N>, const N: usize> Trial<'_, S, N> {
    /// The error weight atol + rtol·max(|y|, |y₁|) of the motion's component i of half c
    /// (positions 0, velocities 1).
    #[inline(always)]
    pub(crate) fn weight(&self, c: usize, i: usize) -> S::R {
        let (y, y1) = (self.x.motion(), self.x1.motion());
        self.rtol.madd(y[c][i].abs().max(y1[c][i].abs()), self.atol)
    }
    /// An error estimate Σ_{j<s} e_j k_j over the motion.
    #[inline(always)]
    pub(crate) fn estimate<const R: usize>(&self, s: usize, e: &[f64; R]) -> YOf<S::R, N> {
        weighted_by(s, e, |j| self.k[j].motion())
    }
}

/// The first four dense-output rows of Hairer's dopri5 and dop853 at one component, from the
/// step's ends y, y₁ and slopes k₀, k_end: y, y₁ − y, h k₀ − (y₁ − y),
/// (y₁ − y) − h k_end − (h k₀ − (y₁ − y)).
#[inline(always)]
pub(crate) fn end_rows(h: f64, [y, y1, k0, k_end]: [f64; 4]) -> [f64; 4] {
    let ydiff = y1 - y;
    let bspl = h * k0 - ydiff;
    [y, ydiff, bspl, ydiff - h * k_end - bspl]
}

/// An accepted step as its dense output reads it: from (t, x) to x₁ with size h, its stages
/// (`k[STAGES]` = F at x₁; extra stages go after it) and the coordinates whose stage positions
/// are held.
pub(crate) struct Step<'a, S, const N: usize> {
    pub(crate) cyclic: [bool; N],
    pub(crate) t: f64,
    pub(crate) h: f64,
    pub(crate) x: &'a S,
    pub(crate) x1: &'a S,
    pub(crate) k: &'a mut [S; 16],
}

/// A problem's slopes, counted in the run's statistics.
pub(crate) struct Counted<'a, P> {
    pub(crate) p: &'a P,
    pub(crate) stats: &'a mut Stats,
}

impl<P: Problem<N>, const N: usize> Slopes<P::State, N> for Counted<'_, P> {
    type Error = Fault;
    #[inline(always)]
    fn slope(&mut self, t: f64, x: &P::State, out: &mut P::State) -> Result<(), Fault> {
        self.p.slope(t, x, out, self.stats)
    }
}

/// Evaluates stage s of the tableau: `k[s] = F(t + C[s] h, x + h Σ_{j<s} A[s][j] k[j])`, the
/// argument in `arg` with the cyclic coordinates' positions held at x's (see
/// [`Space::combine`]).
macro_rules! stage {
    ($tab:ty, $f:ident, $cyclic:ident, $t:ident, $x:ident, $h:ident, $k:ident, $arg:ident; $($s:literal)*) => {$(
        if $s < <$tab>::STAGES {
            let c: S::R = S::R::from(<$tab>::C[$s]);
            if S::COPY {
                // A local of its own per stage: LLVM keeps it in registers (−0.3 % for a
                // heavy-top DOP853 run against one argument for every stage).
                let mut arg = $x.clone();
                S::combine::<$s>(&mut arg, $x, $h, &<$tab>::A[$s], $k, Some(&$cyclic));
                $f.slope($t + $h * c, &arg, &mut $k[$s])?;
            } else {
                S::combine::<$s>($arg, $x, $h, &<$tab>::A[$s], $k, Some(&$cyclic));
                $f.slope($t + $h * c, $arg, &mut $k[$s])?;
            }
        }
    )*};
}

/// One attempted step of size h from (t, x) with `k[0]` = F(t, x): the stages into `k` (in
/// place), x₁ into `x1` and ln err (0 for a fixed step), `k[STAGES]` too where the error
/// estimate needs it. x₁'s finiteness is the caller's to test (the lanes test it per lane).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn attempt<T: Tableau, S: Space<N>, F: Slopes<S, N>, const N: usize>(
    f: &mut F,
    cyclic: [bool; N],
    t: S::R,
    x: &S,
    k: &mut [S; 16],
    h: S::R,
    tol: (S::R, S::R),
    arg: &mut S,
    x1: &mut S,
) -> Result<S::R, F::Error> {
    stage!(T, f, cyclic, t, x, h, k, arg; 1 2 3 4 5 6 7 8 9 10 11);
    T::solution(x1, x, h, k);
    if T::FSAL_IN_ERROR {
        if !x1.finite() {
            // The caller reports the non-finite x₁.
            return Ok(S::R::NAN);
        }
        f.slope(t + h, x1, &mut k[T::STAGES])?;
    }
    Ok(if T::ADAPTIVE {
        let (rtol, atol) = tol;
        let ln_err = T::ln_err(Trial {
            x,
            x1,
            k,
            h,
            rtol,
            atol,
        });
        // The state's other parts where they take part in the error control (a sensitivity
        // run's columns): the larger norm decides.
        let estimate = (
            &T::ERROR_ROWS[..T::ESTIMATES],
            T::ln_err_of as fn(_, _, _) -> _,
        );
        match S::parts_ln_err((x, x1, k), h, tol, estimate) {
            Some(other) => ln_err.max(other),
            None => ln_err,
        }
    } else {
        S::R::ZERO
    })
}

/// [`ExplicitRk::attempt`] from (t, x) to t₁ (the node an accepted step reaches: t + h, or the
/// grid's) with the system as an argument of its own: as a reference argument it is known not
/// to change while the step goes, so its parameters are loaded once per step, not at every stage
/// (as a field read through the problem they were not: +1.5 % for a heavy-top DOP853 run).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn attempt_at<P: Problem<N>, T: Tableau, const N: usize>(
    sys: &P::Sys,
    p: &P,
    (t, t1): (f64, f64),
    x: &P::State,
    k: &mut [P::State; 16],
    h: f64,
    tol: (f64, f64),
    x1: &mut P::State,
    stats: &mut Stats,
) -> Result<f64, Fault> {
    let cyclic = const { <P::Sys as Lagrangian<N>>::CYCLIC };
    let mut f = p.slopes(sys, stats);
    // A stage's argument: a local (in registers for the motion alone).
    let mut arg = x.clone();
    let ln_err = attempt::<T, _, _, N>(&mut f, cyclic, t, x, k, h, tol, &mut arg, x1)?;
    if !x1.finite() {
        return Err(Fault::NonFinite);
    }
    if !T::FSAL_IN_ERROR && ln_err <= 0.0 {
        // F at the new point: the next step's first stage and the dense output.
        f.slope(t1, x1, &mut k[T::STAGES])?;
    }
    Ok(ln_err)
}

/// The explicit Runge–Kutta stepper of a [`Problem`] with a [`Tableau`].
pub(crate) struct ExplicitRk<P: Problem<N>, T, const N: usize> {
    p: P,
    /// A fixed step's grid and the node reached on it.
    grid: FixedGrid,
    node: u64,
    /// An adaptive step's control and tolerances.
    sc: StepControl,
    tol: (f64, f64),
    t: f64,
    x: P::State,
    t_old: f64,
    x_old: P::State,
    h_old: f64,
    /// The stages of the latest step (trial steps overwrite them in place); `k[STAGES]` = F at
    /// the current node.
    k: [P::State; 16],
    /// The trial x₁ (scratch).
    x1: P::State,
    /// The dense-output rows of the last step, and whether they are formed.
    rows: [P::State; 8],
    formed: bool,
    tableau: PhantomData<T>,
}

impl<P: Problem<N>, T: Tableau, const N: usize> ExplicitRk<P, T, N> {
    /// Starts at (t0, x0) with F evaluated there: on the step grid of `dt` up to `until` for a
    /// fixed-step tableau, else with Hairer's first step for (rtol, atol).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        p: P,
        t0: f64,
        x0: P::State,
        (rtol, atol): (f64, f64),
        dt: f64,
        until: f64,
        hmax: f64,
        stats: &mut Stats,
    ) -> Result<Self, Fault> {
        let mut k: [P::State; 16] = core::array::from_fn(|_| x0.clone());
        p.slope(t0, &x0, &mut k[T::STAGES], stats)?;
        let grid = FixedGrid::new(t0, dt, until);
        let (tol, h) = if T::ADAPTIVE {
            let atol = effective_atol(atol);
            let (y0, f0) = (*x0.motion(), *k[T::STAGES].motion());
            let h = initial_step(p.sys(), t0, &y0, &f0, T::ORDER, rtol, atol, hmax, stats)?;
            ((rtol, atol), h)
        } else {
            ((0.0, 0.0), dt)
        };
        Ok(ExplicitRk {
            p,
            grid,
            node: 0,
            sc: StepControl::new(h, hmax, T::controller()),
            tol,
            t: t0,
            t_old: t0,
            h_old: 0.0,
            x1: x0.clone(),
            x_old: x0.clone(),
            rows: core::array::from_fn(|_| x0.clone()),
            formed: false,
            x: x0,
            k,
            tableau: PhantomData,
        })
    }

    /// The problem.
    pub(crate) fn problem(&self) -> &P {
        &self.p
    }

    /// The current node (t, x).
    pub(crate) fn node(&self) -> (f64, &P::State) {
        (self.t, &self.x)
    }

    /// Replaces the state at the current node by one the problem changed (the same motion:
    /// new variations), with F there evaluated anew.
    pub(crate) fn replace_node(&mut self, x: P::State, stats: &mut Stats) -> Result<(), Fault> {
        self.p.slope(self.t, &x, &mut self.k[T::STAGES], stats)?;
        self.x = x;
        self.formed = false;
        Ok(())
    }

    /// Starts the next step from the current node: its first stage is F there (FSAL).
    #[inline(always)]
    pub(crate) fn begin_step(&mut self) {
        let (head, tail) = self.k.split_at_mut(1);
        head[0].assign(&tail[T::STAGES - 1]);
    }

    /// The next trial step and whether it ends at `t_end` (adaptive tableaux; see
    /// [`StepControl::trial`]); the grid's next step for a fixed one.
    #[inline(always)]
    pub(crate) fn trial(&mut self, t_end: f64) -> Result<(f64, bool), Fault> {
        if T::ADAPTIVE {
            self.sc.trial(self.t, t_end)
        } else {
            let t1 = self.grid.time(self.node + 1);
            Ok((t1 - self.t, t1 >= self.grid.until))
        }
    }

    /// The tolerances (rtol, atol) of the error weights (0, 0 for a fixed step).
    pub(crate) fn tolerances(&self) -> (f64, f64) {
        self.tol
    }

    /// The stages: `k[0]` = F at the node after [`begin_step`](Self::begin_step); an attempt
    /// fills `k[1..STAGES]`.
    pub(crate) fn stages(&self) -> &[P::State; 16] {
        &self.k
    }

    /// The stages, to be written (the lanes copy a member's accepted stages back).
    pub(crate) fn stages_mut(&mut self) -> &mut [P::State; 16] {
        &mut self.k
    }

    /// Attempts a step of size h from the current node: x₁, ln err and, if the error is
    /// accepted, F at x₁ into `k[STAGES]`. The fault of a stage, or of a non-finite x₁.
    #[inline(always)]
    pub(crate) fn attempt(&mut self, h: f64, stats: &mut Stats) -> Result<f64, Fault> {
        let t1 = if T::ADAPTIVE {
            self.t + h
        } else {
            self.grid.time(self.node + 1)
        };
        self.attempt_to(t1, h, stats)
    }

    /// [`attempt`](Self::attempt) of a step of size h that ends at t₁.
    #[inline(always)]
    fn attempt_to(&mut self, t1: f64, h: f64, stats: &mut Stats) -> Result<f64, Fault> {
        let (t, tol) = (self.t, self.tol);
        attempt_at::<P, T, N>(
            self.p.sys(),
            &self.p,
            (t, t1),
            &self.x,
            &mut self.k,
            h,
            tol,
            &mut self.x1,
            stats,
        )
    }

    /// Takes an attempt made elsewhere (a lane of an ensemble): x₁ and, if accepted, F there.
    pub(crate) fn take_attempt(&mut self, x1: P::State, end_slope: Option<P::State>) {
        self.x1 = x1;
        if let Some(f1) = end_slope {
            self.k[T::STAGES] = f1;
        }
    }

    /// Takes the outcome of an adaptive attempt of size h (x₁ and the stages in place): accepts
    /// it and moves to x₁ (true), or records the rejection or fault and proposes the retry
    /// (false).
    #[inline(always)]
    pub(crate) fn settle(
        &mut self,
        h: f64,
        last: bool,
        t_end: f64,
        attempt: Result<f64, Fault>,
        stats: &mut Stats,
    ) -> Result<bool, Fault> {
        match attempt {
            Ok(ln_err) if ln_err <= 0.0 => {
                self.sc.accept(h, ln_err, stats);
                let t1 = if last { t_end } else { self.t + h };
                self.moved_to(t1, h, stats)?;
                Ok(true)
            }
            Ok(ln_err) => {
                self.sc.reject(h, ln_err, stats);
                Ok(false)
            }
            // A stage left the domain of the dynamics: retry with a smaller step.
            Err(f) => {
                self.sc.shrink(h, f, stats);
                Ok(false)
            }
        }
    }

    /// Moves the node to (t1, x₁) after an accepted step of size h.
    #[inline(always)]
    fn moved_to(&mut self, t1: f64, h: f64, stats: &mut Stats) -> Result<(), Fault> {
        self.formed = false;
        if T::EAGER_DENSE {
            let cyclic = const { <P::Sys as Lagrangian<N>>::CYCLIC };
            let mut f = self.p.slopes(self.p.sys(), stats);
            let step = Step {
                cyclic,
                t: self.t,
                h,
                x: &self.x,
                x1: &self.x1,
                k: &mut self.k,
            };
            T::dense(&mut f, step, &mut self.rows)?;
            self.formed = true;
        }
        self.t_old = self.t;
        self.x_old.assign(&self.x);
        self.x.assign(&self.x1);
        self.h_old = h;
        self.t = t1;
        Ok(())
    }

    /// The dense-output rows of the last step, formed on first use.
    fn rows(&mut self, stats: &mut Stats) -> Result<&[P::State; 8], Fault> {
        if !self.formed {
            let cyclic = const { <P::Sys as Lagrangian<N>>::CYCLIC };
            let mut f = self.p.slopes(self.p.sys(), stats);
            let step = Step {
                cyclic,
                t: self.t_old,
                h: self.h_old,
                x: &self.x_old,
                x1: &self.x,
                k: &mut self.k,
            };
            T::dense(&mut f, step, &mut self.rows)?;
            self.formed = true;
        }
        Ok(&self.rows)
    }

    /// The state at t in [t_prev, t] (the node itself from t on, or before the first step).
    pub(crate) fn state_at(&mut self, t: f64, stats: &mut Stats) -> Result<P::State, Fault> {
        if t >= self.t || self.h_old == 0.0 {
            return Ok(self.x.clone());
        }
        let (h, t_old) = (self.h_old, self.t_old);
        let mut out = self.x.clone();
        let rows = self.rows(stats)?;
        T::eval(rows, h, (t - t_old) / h, &mut out);
        Ok(out)
    }
}

impl<P: Problem<N>, T: Tableau, const N: usize> Stepper<N> for ExplicitRk<P, T, N> {
    fn t(&self) -> f64 {
        self.t
    }
    fn t_prev(&self) -> f64 {
        self.t_old
    }
    fn last_state(&self) -> Y<N> {
        *self.x.motion()
    }
    fn set_node(&mut self, y: Y<N>, _stats: &mut Stats) -> Result<(), Fault> {
        let mut x = self.x.clone();
        *x.motion_mut() = y;
        if T::EAGER_DENSE && self.formed {
            T::shift(&mut self.rows, &self.x, &x);
        } else {
            self.formed = false;
        }
        // The slope there (FSAL) as `Stepper::set_node` says: q̇ from y, q̈ kept.
        self.k[T::STAGES].motion_mut()[0] = y[1];
        self.x = x;
        Ok(())
    }
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        // The loop of `begin_step`, `trial`, `attempt` and `settle` (which the lanes engine
        // calls one by one), written out.
        self.begin_step();
        if !T::ADAPTIVE {
            // The grid's next node, computed once (`trial` and `attempt` each compute it).
            let t1 = self.grid.time(self.node + 1);
            let h = t1 - self.t;
            self.attempt_to(t1, h, stats)?;
            stats.steps += 1;
            self.node += 1;
            return self.moved_to(t1, h, stats);
        }
        loop {
            let (h, last) = self.sc.trial(self.t, t_end)?;
            let attempt = self.attempt(h, stats);
            if self.settle(h, last, t_end, attempt, stats)? {
                return Ok(());
            }
        }
    }
    fn interp(&mut self, t: f64, stats: &mut Stats) -> Result<Y<N>, Fault> {
        if t >= self.t {
            return Ok(*self.x.motion());
        }
        Ok(*self.state_at(t, stats)?.motion())
    }
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, stats: &mut Stats) -> Result<f64, Fault> {
        let h = self.h_old;
        let r = self.rows(stats)?;
        rows.extend(r[..T::ROWS].iter().map(|x| *x.motion()));
        Ok(h)
    }
    fn recorded(&mut self, t: f64, at: f64, stats: &mut Stats) -> Result<(), Fault> {
        if P::OBSERVES {
            let x = self.state_at(at, stats)?;
            self.p.recorded(t, &x);
        }
        Ok(())
    }
    fn event_located(&mut self, t: f64, event: usize, stats: &mut Stats) -> Result<(), Fault> {
        if P::OBSERVES {
            let x = self.state_at(t, stats)?;
            self.p.event_located(t, event, &x);
        }
        Ok(())
    }
}
