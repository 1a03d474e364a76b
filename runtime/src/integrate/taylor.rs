//! The Taylor method: at each node the system's Taylor series of the motion
//! (`Lagrangian::series_in`, generated at compile time by the symbolic mode), summed over
//! a step chosen from its last two coefficients (Jorba & Zou 2005); the series is the dense
//! output.
//!
//! Order p = max(2, ⌈−ln(tol)/2 + 1⌉). Step: with x_k the k-th coefficients of y = (q, q̇),
//! ρ_k = (s/‖x_k‖∞)^{1/k} and s = max(1, ‖x₀‖∞) (absolute control for states of size ≤ 1,
//! relative above), h = min(ρ_{p−1}, ρ_p) · e^{−2 − 0.7/(p−1)}: the terms x_k h^k fall off
//! geometrically from there, so the truncated tail is below tol·s. Steps are never rejected.
//!
//! Where both of the top coefficients vanish (a force t²⁵ at t = 0, whose first 25 coefficients
//! are zero; an odd series cut at an even order is not this case, one of the two is non-zero),
//! ρ would be infinite and one step would run to the end. The series is then computed to
//! [`MAX_ORDER`]: where a coefficient above p appears, the step comes from the highest non-zero
//! ones and sums the whole series; where none does, the motion is taken for the polynomial its
//! series is (a free particle, a constant force) and the step is not bounded. A state-dependent
//! part whose coefficients vanish through order [`MAX_ORDER`] at a node is beyond what any series
//! of that order can see.

use crate::lagrangian::Lagrangian;
use crate::lanes::Lanes;
use crate::real::Real;
use crate::taylor::{MAX_ORDER, TaylorBuf};

use super::state::Stats;
use super::state::{Fault, Y, YOf};
use super::stepper::Stepper;

/// The order of the Taylor method for a tolerance.
pub(crate) fn order(tol: f64) -> usize {
    ((-tol.ln() / 2.0 + 1.0).ceil() as usize).max(2)
}

/// The system's series at width 1 in a function of its own: the generated kernel is inlined
/// into its caller (the lanes engine needs it in its AVX2 code), and here it measured 0.6 %
/// fewer instructions per run kept apart from the stepper's loop.
#[inline(never)]
fn series<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    params: &mut Vec<f64>,
    t: f64,
    out: &mut [Y<N>],
    buf: &mut TaylorBuf,
) -> Option<Result<bool, crate::DynamicsError>> {
    L::series_in(&[sys], params, t, out, buf)
}

/// The Taylor stepper of the motion and what a problem carries with it ([`Carried`]: nothing
/// for a plain run).
pub(crate) struct Taylor<'a, L, const N: usize, C = ()> {
    sys: &'a L,
    /// The order from the tolerance (the series may be wider for one step, see the module docs).
    p: usize,
    /// The step's safety factor e^{−2 − 0.7/(p−1)} (see [`Self::step_size`]), computed once.
    safety: f64,
    hmax: f64,
    t: f64,
    y: Y<N>,
    /// The series at the current node, once computed.
    series: Vec<Y<N>>,
    fresh: bool,
    t_old: f64,
    /// The series of the last step (from its start), for the dense output.
    old: Vec<Y<N>>,
    buf: TaylorBuf,
    /// The series kernel's copy of the system's parameters (loaded at the first call).
    params: Vec<f64>,
    /// What the problem carries (taken out while it steps the motion).
    carried: Option<C>,
}

/// What a Taylor run carries along with the motion, problem-side: nothing for a plain run
/// (`()`); a sensitivity run's columns of variations, whose series come from the same generated
/// code and are summed at the motion's step. The stepper ([`Taylor`]'s `Stepper`) is written
/// once; a problem says here how its step goes and what it records.
pub(crate) trait Carried<L: Lagrangian<N>, const N: usize>: Sized {
    /// Takes the next step of the motion `m`, not beyond `t_end`, with what is carried.
    fn advance(
        &mut self,
        m: &mut Taylor<'_, L, N, Self>,
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), Fault>;
    /// The driver recorded a sample at time `t` whose state is the motion's at `at`.
    fn recorded(&mut self, _m: &Taylor<'_, L, N, Self>, _t: f64, _at: f64) {}
    /// The driver located a hit of event `event` at time `t`.
    fn event_located(&mut self, _m: &Taylor<'_, L, N, Self>, _t: f64, _event: usize) {}
}

/// A plain run carries nothing: the motion's step.
impl<L: Lagrangian<N>, const N: usize> Carried<L, N> for () {
    #[inline(always)]
    fn advance(
        &mut self,
        m: &mut Taylor<'_, L, N, ()>,
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), Fault> {
        let (h, t1) = m.plan(t_end, stats)?;
        m.take(h, t1, stats)
    }
}

impl<'a, L: Lagrangian<N>, const N: usize> Taylor<'a, L, N> {
    /// Starts a plain run at (t0, y0).
    pub(crate) fn new(sys: &'a L, t0: f64, y0: Y<N>, tol: f64, hmax: f64) -> Self {
        Taylor::carrying(sys, t0, y0, tol, hmax, ())
    }
}

impl<'a, L: Lagrangian<N>, const N: usize, C> Taylor<'a, L, N, C> {
    /// Starts at (t0, y0) carrying `carried`.
    pub(crate) fn carrying(sys: &'a L, t0: f64, y0: Y<N>, tol: f64, hmax: f64, carried: C) -> Self {
        let p = order(tol);
        Taylor {
            sys,
            p,
            safety: (-2.0 - 0.7 / (p - 1) as f64).exp(),
            hmax,
            t: t0,
            y: y0,
            series: vec![[[0.0; N]; 2]; p + 1],
            fresh: false,
            t_old: t0,
            old: vec![y0; p + 1],
            buf: TaylorBuf::new(),
            params: Vec::new(),
            carried: Some(carried),
        }
    }

    /// The series at the current node.
    fn compute(&mut self, stats: &mut Stats) -> Result<(), Fault> {
        if self.fresh {
            return Ok(());
        }
        self.series_to(self.p, stats)?;
        self.fresh = true;
        Ok(())
    }

    /// The series at the current node to order `p`, checked finite.
    fn series_to(&mut self, p: usize, stats: &mut Stats) -> Result<(), Fault> {
        self.series.resize(p + 1, [[0.0; N]; 2]);
        self.series[0] = self.y;
        stats.rhs_evals += 1;
        match series(
            self.sys,
            &mut self.params,
            self.t,
            &mut self.series,
            &mut self.buf,
        ) {
            // A single run's factorization pivots where LDLᵀ fails: its mask is always set.
            Some(Ok(_)) => {}
            Some(Err(e)) => return Err(Fault::Dynamics(e)),
            // `Simulation::run` checks this before the first step.
            None => return Err(Fault::NonFinite),
        }
        if !self
            .series
            .iter()
            .flatten()
            .flatten()
            .all(|x| x.is_finite())
        {
            return Err(Fault::NonFinite);
        }
        Ok(())
    }

    /// The system.
    pub(crate) fn sys(&self) -> &'a L {
        self.sys
    }

    /// The order of the series.
    pub(crate) fn order(&self) -> usize {
        self.p
    }

    /// (t, y) at the current node.
    pub(crate) fn node_state(&self) -> (f64, Y<N>) {
        (self.t, self.y)
    }

    /// y at t within the last step (the node's at or after it): what `interp` gives, by
    /// reference.
    pub(crate) fn motion_at(&self, t: f64) -> Y<N> {
        if t >= self.t || self.old.is_empty() {
            return self.y;
        }
        horner(&self.old, t - self.t_old)
    }

    /// Takes the series at the current node from lane `l` of the lanes engine's series `src`
    /// (whose orders are at least this stepper's), counted as one evaluation as `compute` counts
    /// its own. The caller has checked that the lane's coefficients are finite.
    pub(crate) fn take_series<const W: usize, const F: bool>(
        &mut self,
        src: &[YOf<Lanes<W, F>, N>],
        l: usize,
        stats: &mut Stats,
    ) {
        lane_rows(&mut self.series, self.p, self.y, src, l);
        stats.rhs_evals += 1;
        self.fresh = true;
    }

    /// The largest |coefficient| of order k.
    fn norm(&self, k: usize) -> f64 {
        self.series[k]
            .iter()
            .flatten()
            .fold(0.0_f64, |m, x| m.max(x.abs()))
    }

    /// The Jorba–Zou step from the current series (the tolerance enters through the order: with
    /// p − 1 = −ln(tol)/2, e^{−2} = tol^{1/(p−1)}); infinite where the top two coefficients
    /// vanish (see [`Self::widen`]).
    fn step_size(&self) -> f64 {
        let p = self.p;
        let top = self.series.len() - 1;
        if top == p {
            return self.step_from_norms(self.norm(0), self.norm(p - 1), self.norm(p));
        }
        // A widened series: the highest non-zero coefficients above p.
        let s = self.norm(0).max(1.0);
        let r = (p + 1..=top)
            .map(|k| rho(s, self.norm(k), k))
            .fold(f64::INFINITY, f64::min);
        r * self.safety
    }

    /// [`Self::step_size`] of a series of order p from the largest |coefficient| of orders 0,
    /// p − 1 and p.
    fn step_from_norms(&self, n0: f64, n_before_top: f64, n_top: f64) -> f64 {
        let (p, s) = (self.p, n0.max(1.0));
        rho(s, n_before_top, p - 1).min(rho(s, n_top, p)) * self.safety
    }

    /// The step a proposed h allows toward `t_end` (at most hmax; `t_end` itself for the last):
    /// h and the time the step ends at, or the underflow.
    fn bounded(&self, h: f64, t_end: f64) -> Result<(f64, f64), Fault> {
        let mut h = h.min(self.hmax);
        let last = self.t + h >= t_end;
        if last {
            h = t_end - self.t;
        }
        if h.is_nan() || h <= 0.0 || self.t + h == self.t {
            return Err(Fault::Underflow { h });
        }
        Ok((h, if last { t_end } else { self.t + h }))
    }

    /// The series at the current node (widened where its top coefficients vanish) and the step
    /// it allows toward `t_end`: h and the time the step ends at (`t_end` itself for the last).
    pub(crate) fn plan(&mut self, t_end: f64, stats: &mut Stats) -> Result<(f64, f64), Fault> {
        self.compute(stats)?;
        self.widen(stats)?;
        self.bounded(self.step_size(), t_end)
    }

    /// What [`Self::plan`] would give for a series of this stepper's order whose largest
    /// |coefficient| of orders 0, p − 1 and p the lanes engine measured; `None` where `plan`
    /// has more to do (the top two coefficients vanish: it widens) or fails (it says why).
    pub(crate) fn plan_from_norms(&self, norms: [f64; 3], t_end: f64) -> Option<(f64, f64)> {
        let [n0, n_before_top, n_top] = norms;
        if n_top == 0.0 && n_before_top == 0.0 && self.p < MAX_ORDER {
            return None;
        }
        self.bounded(self.step_from_norms(n0, n_before_top, n_top), t_end)
            .ok()
    }

    /// Lands a step the lanes engine took for this member from its node: the series counted as
    /// one evaluation, the step as [`Self::take`] counts it, y₁ its sum at the end time t₁ from
    /// [`Self::plan_from_norms`]. `dense` is the member's series (lane `l` of the engine's) where
    /// the driver reads the step's interpolant: it becomes the step's dense output, as the
    /// series does in `take`; without it the interpolant is not kept.
    pub(crate) fn land<const W: usize, const F: bool>(
        &mut self,
        t1: f64,
        y1: Y<N>,
        dense: Option<(&[YOf<Lanes<W, F>, N>], usize)>,
        stats: &mut Stats,
    ) {
        stats.rhs_evals += 1;
        stats.steps += 1;
        if let Some((src, l)) = dense {
            lane_rows(&mut self.old, self.p, self.y, src, l);
        }
        self.t_old = self.t;
        self.t = t1;
        self.y = y1;
        self.fresh = false;
    }

    /// Takes the series at the current node, to this stepper's order, from values computed
    /// elsewhere (the value parts of the variational series: the same operations on the same
    /// numbers; the caller counts that evaluation). Where they are not finite the stepper
    /// computes its own, which says why.
    pub(crate) fn install(&mut self, rows: impl Iterator<Item = Y<N>>) {
        self.series.clear();
        self.series.extend(rows.take(self.p + 1));
        self.fresh = self.series.len() == self.p + 1
            && self
                .series
                .iter()
                .flatten()
                .flatten()
                .all(|x| x.is_finite());
    }

    /// The series at the current node as [`plan`](Self::plan) left it (order 0 the node's state).
    pub(crate) fn node_series(&self) -> &[Y<N>] {
        &self.series
    }

    /// Takes the step [`plan`](Self::plan) chose: the series summed at h.
    pub(crate) fn take(&mut self, h: f64, t1: f64, stats: &mut Stats) -> Result<(), Fault> {
        let y1 = horner(&self.series, h);
        if !y1.iter().flatten().all(|x| x.is_finite()) {
            return Err(Fault::NonFinite);
        }
        stats.steps += 1;
        core::mem::swap(&mut self.old, &mut self.series);
        self.t_old = self.t;
        self.t = t1;
        self.y = y1;
        self.fresh = false;
        Ok(())
    }

    /// Where the top two coefficients of order p vanish, the series to [`MAX_ORDER`] instead
    /// (see the module docs).
    fn widen(&mut self, stats: &mut Stats) -> Result<(), Fault> {
        if self.p >= MAX_ORDER || self.norm(self.p) != 0.0 || self.norm(self.p - 1) != 0.0 {
            return Ok(());
        }
        self.series_to(MAX_ORDER, stats)
    }
}

/// `rows` = the series of order p of lane `l` of the lanes engine's `src`, with `y` (the node,
/// bit for bit the lane's order 0) as order 0.
fn lane_rows<const N: usize, const W: usize, const F: bool>(
    rows: &mut Vec<Y<N>>,
    p: usize,
    y: Y<N>,
    src: &[YOf<Lanes<W, F>, N>],
    l: usize,
) {
    rows.resize(p + 1, [[0.0; N]; 2]);
    rows[0] = y;
    for (row, from) in rows.iter_mut().zip(src).skip(1) {
        for (part, from) in row.iter_mut().zip(from) {
            for (v, x) in part.iter_mut().zip(from) {
                *v = x.0[l];
            }
        }
    }
}

/// ρ_k = (s/n_k)^{1/k} from the largest |coefficient| n_k of order k (infinite where it is 0).
fn rho(s: f64, n: f64, k: usize) -> f64 {
    if n == 0.0 {
        f64::INFINITY
    } else {
        (s / n).powf(1.0 / k as f64)
    }
}

/// Σ x_k τ^k for every component, over any [`Real`] (single runs, their dense output and the
/// lanes engine's members: one body): Horner's rule in τ² on the even and on the odd
/// coefficients side by side, then even + τ·odd — two chains of ⌈n/2⌉ multiply-adds where one
/// chain of n was (the sum's latency, not its arithmetic, bounds it: 6 components). Never fused
/// (not `Real::madd`): a member of an ensemble on the fused lanes sums its step as its single run
/// does, bit for bit. Inlined: the lanes engine's instance must take its caller's instruction set.
#[inline(always)]
pub(crate) fn horner<R: Real, const N: usize>(series: &[YOf<R, N>], tau: R) -> YOf<R, N> {
    let n = series.len();
    let Some(&last) = series.last() else {
        return [[R::ZERO; N]; 2];
    };
    if n == 1 {
        return last;
    }
    let t2 = tau * tau;
    // The highest even and odd indices, and the chains started there.
    let (top_even, top_odd) = if n % 2 == 1 {
        (n - 1, n - 2)
    } else {
        (n - 2, n - 1)
    };
    let (mut even, mut odd) = (series[top_even], series[top_odd]);
    for j in (0..=(n - 1) / 2).rev() {
        let (ke, ko) = (2 * j, 2 * j + 1);
        if ke < top_even {
            let x = &series[ke];
            for c in 0..2 {
                for i in 0..N {
                    even[c][i] = even[c][i] * t2 + x[c][i];
                }
            }
        }
        if ko < top_odd {
            let x = &series[ko];
            for c in 0..2 {
                for i in 0..N {
                    odd[c][i] = odd[c][i] * t2 + x[c][i];
                }
            }
        }
    }
    for c in 0..2 {
        for i in 0..N {
            even[c][i] = odd[c][i] * tau + even[c][i];
        }
    }
    even
}

impl<L: Lagrangian<N>, const N: usize, C: Carried<L, N>> Stepper<N> for Taylor<'_, L, N, C> {
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
        self.y = y;
        self.fresh = false;
        Ok(())
    }
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        // Out while it steps the motion; always back (it is missing only inside this call).
        let Some(mut c) = self.carried.take() else {
            return Err(Fault::NonFinite);
        };
        let r = c.advance(self, t_end, stats);
        self.carried = Some(c);
        r
    }
    fn recorded(&mut self, t: f64, at: f64, _stats: &mut Stats) -> Result<(), Fault> {
        if let Some(mut c) = self.carried.take() {
            c.recorded(self, t, at);
            self.carried = Some(c);
        }
        Ok(())
    }
    fn event_located(&mut self, t: f64, event: usize, _stats: &mut Stats) -> Result<(), Fault> {
        if let Some(mut c) = self.carried.take() {
            c.event_located(self, t, event);
            self.carried = Some(c);
        }
        Ok(())
    }
    /// The step's polynomial has degree p (up to 31 widened): ⌈(p + 1)/2⌉ points integrate a
    /// power of that degree exactly, so the work carries the step's own error (4 points left
    /// 4e-8 relative at tol 1e-15).
    fn gauss_points(&self) -> usize {
        self.old.len().div_ceil(2).max(4)
    }
    fn interp(&mut self, t: f64, _stats: &mut Stats) -> Result<Y<N>, Fault> {
        Ok(self.motion_at(t))
    }
    /// The series of the last step (p + 1 rows, more where it was widened), in t − t_prev.
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, _stats: &mut Stats) -> Result<f64, Fault> {
        rows.extend_from_slice(&self.old);
        Ok(self.t - self.t_old)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// p = ⌈−ln(tol)/2 + 1⌉: 10 at 1e-8, 19 at 1e-15.
    #[test]
    fn order_from_tolerance() {
        assert_eq!((order(1e-8), order(1e-15), order(0.5)), (11, 19, 2));
    }

    /// Horner's rule sums the series (cos τ to 8th order at τ = 0.1 vs cos).
    #[test]
    fn horner_sums_the_series() {
        let mut s = vec![[[0.0; 1]; 2]; 9];
        let mut f = 1.0;
        for k in 0..9 {
            if k > 0 {
                f *= k as f64;
            }
            s[k][0][0] = [1.0, 0.0, -1.0, 0.0][k % 4] / f;
        }
        let y = horner(&s, 0.1);
        assert!((y[0][0] - 0.1_f64.cos()).abs() < 1e-15);
    }
}
