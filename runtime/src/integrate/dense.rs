//! The dense output of a whole run, kept on request
//! ([`Simulation::keep_dense_output`](crate::Simulation::keep_dense_output)): every accepted
//! step's interpolant (the rows the method's own `interp` evaluates), bounded in memory like the
//! samples, so that [`Trajectory::at`](crate::Trajectory::at) gives the state at any time of a
//! finished run.

use core::fmt;

use super::explicit::Tableau;
use super::method::Method;
use super::state::{Fault, Stats, Y};
use super::stepper::Stepper;
use super::{dop853::Dop853, dopri5::Dopri5, radau5, rk4::Rk4, taylor, variational};

/// Which interpolant the rows of a step hold: the method's own (one per run).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// DOP853's 7th-order dense output: 8 rows, in (t − t₀)/h.
    Dop853,
    /// Dormand–Prince's 4th-order continuous extension: 5 rows, in (t − t₀)/h.
    Dopri5,
    /// RK4's cubic Hermite interpolant: y₀, ẏ₀, y₁, ẏ₁.
    Hermite,
    /// The variational method's (and RATTLE's): (q, q̇) at both nodes, q cubic Hermite, q̇ linear.
    Variational,
    /// The Taylor method's series of the step, in t − t₀ (p + 1 rows, more where widened).
    Taylor,
    /// Radau IIA's collocation polynomial (degree 3): 4 rows, in (t − t₀)/h.
    Radau5,
}

impl Kind {
    /// The interpolant of `method`.
    pub(crate) fn of(method: Method) -> Self {
        match method {
            Method::Dop853 { .. } => Kind::Dop853,
            Method::DormandPrince { .. } => Kind::Dopri5,
            Method::Rk4 { .. } => Kind::Hermite,
            Method::VariationalMidpoint { .. } => Kind::Variational,
            Method::Taylor { .. } => Kind::Taylor,
            Method::Radau5 { .. } => Kind::Radau5,
        }
    }
}

/// One kept step: its start, the h its interpolant is scaled by, where its rows begin.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Step {
    t0: f64,
    h: f64,
    start: usize,
}

/// The kept dense output of a run: the interpolants of its steps from the start up to `end`,
/// at most `budget` bytes of them.
#[derive(Clone, PartialEq)]
pub(crate) struct Dense<const N: usize> {
    kind: Kind,
    /// The run's start time.
    start: f64,
    steps: Vec<Step>,
    rows: Vec<Y<N>>,
    /// The end of the last step kept (the start before any), and the state there: what `at`
    /// returns at that time, the node itself.
    end: (f64, Y<N>),
    /// The most bytes the steps and their rows may take.
    budget: usize,
    /// When a step was refused (the budget was reached): how far the run went.
    reached: Option<f64>,
}

impl<const N: usize> fmt::Debug for Dense<N> {
    /// A summary (the rows would fill pages).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Dense")
            .field("kind", &self.kind)
            .field("span", &(self.start, self.end.0))
            .field("steps", &self.steps.len())
            .field("rows", &self.rows.len())
            .field("budget", &self.budget)
            .field("reached", &self.reached)
            .finish()
    }
}

impl<const N: usize> Dense<N> {
    /// An empty dense output of `kind` from the state y0 at t0, bounded by `budget` bytes.
    pub(crate) fn new(kind: Kind, t0: f64, y0: Y<N>, budget: usize) -> Self {
        Dense {
            kind,
            start: t0,
            steps: Vec::new(),
            rows: Vec::new(),
            end: (t0, y0),
            budget,
            reached: None,
        }
    }

    /// The bytes the kept steps take (their `Vec`s' lengths, not capacities).
    fn bytes(&self, steps: usize, rows: usize) -> usize {
        steps * core::mem::size_of::<Step>() + rows * core::mem::size_of::<Y<N>>()
    }

    /// Keeps the last step of `s` (after its node was settled: projected, for a constrained
    /// run), unless that would pass the budget: then this step and every later one are refused
    /// (`at` says so for their times) and the run goes on.
    pub(crate) fn keep(&mut self, s: &mut dyn Stepper<N>, stats: &mut Stats) -> Result<(), Fault> {
        let t1 = s.t();
        if self.reached.is_some() {
            self.reached = Some(t1);
            return Ok(());
        }
        let start = self.rows.len();
        let h = s.dense_rows(&mut self.rows, stats)?;
        let y1 = s.node(stats)?;
        if self.bytes(self.steps.len() + 1, self.rows.len()) > self.budget {
            self.rows.truncate(start);
            self.reached = Some(t1);
            return Ok(());
        }
        self.steps.push(Step {
            t0: s.t_prev(),
            h,
            start,
        });
        self.end = (t1, y1);
        Ok(())
    }

    /// A terminal event ended the run at t within the last step, in the state y there.
    pub(crate) fn stop_at(&mut self, t: f64, y: Y<N>) {
        match self.reached {
            Some(_) => self.reached = Some(t),
            None => self.end = (t, y),
        }
    }

    /// The times `at` serves: from the start to the end of the last step kept.
    pub(crate) fn span(&self) -> (f64, f64) {
        (self.start, self.end.0)
    }

    /// (q, q̇) at t (see [`Trajectory::at`](crate::Trajectory::at)).
    pub(crate) fn at(&self, t: f64) -> Result<Y<N>, DenseOutputError> {
        let (start, end) = self.span();
        if t.is_nan() {
            return Err(DenseOutputError::NotANumber { start, end });
        }
        if t == end {
            return Ok(self.end.1);
        }
        if t > end
            && let Some(reached) = self.reached.filter(|&r| t <= r)
        {
            return Err(DenseOutputError::Truncated {
                t,
                kept_until: end,
                reached,
                budget_bytes: self.budget,
            });
        }
        if !(start..=end).contains(&t) {
            return Err(DenseOutputError::OutOfRange { t, start, end });
        }
        // The last step that starts at or before t (t < end, so there is one).
        let k = self.steps.partition_point(|s| s.t0 <= t).saturating_sub(1);
        let Some(&Step { t0, h, start }) = self.steps.get(k) else {
            return Ok(self.end.1);
        };
        let stop = self.steps.get(k + 1).map_or(self.rows.len(), |s| s.start);
        let r = &self.rows[start..stop];
        // A tableau's rows (up to 8) as its `eval` reads them.
        let rows = || core::array::from_fn(|j| r.get(j).copied().unwrap_or(r[0]));
        let mut y = r[0];
        Ok(match self.kind {
            Kind::Dop853 => {
                Dop853::eval(&rows(), h, (t - t0) / h, &mut y);
                y
            }
            Kind::Dopri5 => {
                Dopri5::eval(&rows(), h, (t - t0) / h, &mut y);
                y
            }
            Kind::Hermite => {
                Rk4::eval(&rows(), h, (t - t0) / h, &mut y);
                y
            }
            Kind::Variational => variational::across_step(t0, h, &r[0], &r[1], t),
            Kind::Taylor => taylor::horner(r, t - t0),
            Kind::Radau5 => radau5::eval_dense(&core::array::from_fn(|j| r[j]), (t - t0) / h),
        })
    }
}

/// Why [`Trajectory::at`](crate::Trajectory::at) could not give the state at a time: its
/// message says what happened and what to try.
///
/// ```
/// use lagrange_runtime::DenseOutputError;
/// let e = DenseOutputError::OutOfRange { t: 3.0, start: 0.0, end: 2.0 };
/// assert!(e.to_string().contains("[0, 2]"));
/// ```
#[derive(Clone, PartialEq)]
#[non_exhaustive]
pub enum DenseOutputError {
    /// The run did not keep its dense output: build it with
    /// [`keep_dense_output(true)`](crate::Simulation::keep_dense_output).
    NotKept,
    /// The time asked for is NaN.
    NotANumber {
        /// The first time `at` serves (the run's start).
        start: f64,
        /// The last time `at` serves.
        end: f64,
    },
    /// The time is outside the times the dense output covers.
    OutOfRange {
        /// The time asked for.
        t: f64,
        /// The first time `at` serves (the run's start).
        start: f64,
        /// The last time `at` serves: the run's end (a terminal event's time, or for a failed
        /// run's partial trajectory its last accepted step).
        end: f64,
    },
    /// The dense output reached its memory bound (that of
    /// [`max_samples`](crate::Simulation::max_samples)) at `kept_until`, and the run went on
    /// without keeping more: the time is in the part not kept.
    Truncated {
        /// The time asked for.
        t: f64,
        /// The end of the last step kept: `at` serves up to here.
        kept_until: f64,
        /// How far the run went.
        reached: f64,
        /// The bound, in bytes.
        budget_bytes: usize,
    },
}

impl fmt::Display for DenseOutputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            DenseOutputError::NotKept => write!(
                f,
                "this trajectory did not keep its dense output, so it cannot be evaluated between \
                 its samples. Try: build the run with .keep_dense_output(true) (it keeps every \
                 step's interpolant, bounded like the samples by .max_samples(n)), or record the \
                 times you need with .sample_at(times)"
            ),
            DenseOutputError::NotANumber { start, end } => write!(
                f,
                "the time asked for is NaN. Try: a time within the run's dense output \
                 [{start}, {end}]"
            ),
            DenseOutputError::OutOfRange { t, start, end } => write!(
                f,
                "t = {t} is outside the run's dense output [{start}, {end}]: it is not \
                 extrapolated. Try: a time within it, or a run that covers t (.start_time(t0), \
                 .until(t_end))"
            ),
            DenseOutputError::Truncated {
                t,
                kept_until,
                reached,
                budget_bytes,
            } => write!(
                f,
                "t = {t} is past the dense output kept: it reached its memory bound of \
                 {mib:.1} MiB (the samples' budget, from .max_samples) at t = {kept_until}, and \
                 the run went on to t = {reached} without keeping more. Try: raise \
                 .max_samples(n), shorten the run, loosen the tolerance (fewer, longer steps), or \
                 record the times you need with .sample_at(times)",
                mib = budget_bytes as f64 / (1 << 20) as f64
            ),
        }
    }
}

impl fmt::Debug for DenseOutputError {
    /// The sentence of `Display` (as [`SimulationError`](crate::SimulationError)'s `Debug`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl std::error::Error for DenseOutputError {}

#[cfg(test)]
mod tests;
