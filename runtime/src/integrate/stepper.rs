//! The [`Stepper`] trait every method implements for the driver, and the step grid of the
//! fixed-step methods.

use super::state::Stats;
use super::state::{Fault, Y};

/// The step grid of a fixed-step method: t_k = t0 + k·dt, with the last step shortened to end
/// exactly at `until`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FixedGrid {
    pub(crate) t0: f64,
    pub(crate) dt: f64,
    pub(crate) n: u64,
    pub(crate) until: f64,
}

impl FixedGrid {
    /// The grid from t0 in steps of dt up to `until`.
    pub(crate) fn new(t0: f64, dt: f64, until: f64) -> Self {
        let n = (((until - t0) / dt) - 1e-6).ceil().max(1.0) as u64;
        FixedGrid { t0, dt, n, until }
    }
    /// The time of node k (`until` from the last node on).
    pub(crate) fn time(&self, k: u64) -> f64 {
        if k >= self.n {
            self.until
        } else {
            self.t0 + k as f64 * self.dt
        }
    }
}

/// What every method provides to the driver.
pub(crate) trait Stepper<const N: usize> {
    /// Time of the current node.
    fn t(&self) -> f64;
    /// Time of the previous node (start of the last step).
    fn t_prev(&self) -> f64;
    /// The last accepted state as known without further computation (for error reports).
    fn last_state(&self) -> Y<N>;
    /// (q, q̇) at the current node: the last state for the explicit methods; the variational
    /// method recovers q̇ from the momenta here, on demand.
    #[inline(always)]
    fn node(&mut self, _stats: &mut Stats) -> Result<Y<N>, Fault> {
        Ok(self.last_state())
    }
    /// Replaces the state at the current node by `y` (a constrained run's projection onto the
    /// constraints, a small change) and refreshes what the next step reuses from the node (the
    /// right-hand side there: FSAL), so the next step starts from `y`.
    ///
    /// The explicit methods take the velocity half of that slope from `y` exactly and keep the
    /// acceleration half from before the projection: the projection moves the state by about
    /// the step's local error δ, so q̈ there differs by O(δ) and the next step by O(h δ), far
    /// below the tolerance, while evaluating it anew cost one right-hand side per step (1 in 13
    /// for DOP853). Measured on the quaternion top (DOP853, t = 114.3, rtol 1e-8 / 1e-10 /
    /// 1e-12): the largest error in cos θ moved 4.4e-6 → 4.8e-6, 3.58e-8 → 3.69e-8,
    /// 2.50e-10 → 2.51e-10, with the same steps, for 5 % less time.
    fn set_node(&mut self, y: Y<N>, stats: &mut Stats) -> Result<(), Fault>;
    /// Takes one accepted step, not beyond `t_end`.
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault>;
    /// (q, q̇) at t in [t_prev, t] from the method's interpolant.
    fn interp(&mut self, t: f64, stats: &mut Stats) -> Result<Y<N>, Fault>;
    /// The last step's interpolant for a run that keeps its dense output: appends the rows
    /// `interp` evaluates it from (the method's own, see `dense::Kind`) to `rows` and returns the
    /// step size h its variable is scaled by, the one `interp` divides by. Appends nothing on a
    /// fault.
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, stats: &mut Stats) -> Result<f64, Fault>;
    /// The driver recorded a sample at time `t` whose state is the method's at time `at` (the
    /// node, or the interpolant inside the last step; `at` ≠ `t` for a grid time snapped to a
    /// node). Nothing for the plain methods; the sensitivity steppers record the state
    /// transition matrix there.
    #[inline(always)]
    fn recorded(&mut self, _t: f64, _at: f64, _stats: &mut Stats) -> Result<(), Fault> {
        Ok(())
    }
    /// The driver located a hit of event `event` (its index in the run's events) at time `t`
    /// inside the last step. Nothing for the plain methods; the sensitivity steppers record the
    /// state transition matrix there.
    #[inline(always)]
    fn event_located(&mut self, _t: f64, _event: usize, _stats: &mut Stats) -> Result<(), Fault> {
        Ok(())
    }
    /// How many Gauss–Legendre points the work integral takes over a step of this method: 4
    /// (exact for degree 7, below the error of the explicit methods' interpolants) unless the
    /// method's own order is higher (the Taylor method's series).
    #[inline(always)]
    fn gauss_points(&self) -> usize {
        4
    }
}
