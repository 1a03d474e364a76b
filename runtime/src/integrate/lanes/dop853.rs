//! DOP853 over SIMD lanes: W members of an ensemble step together, one member per lane of
//! [`Lanes`], each with its own step size, error norm and accept/reject decision (as heyoka's
//! batch mode does).
//!
//! The stages, the new state and the error sums of all lanes are one pass of vector code (the
//! system's [`Lagrangian::accelerations_in`]); everything that is per member stays the scalar
//! code of [`Dop853`] and the driver, run on that member's own stepper: the step-size controller,
//! the decision, the samples, events, dense output and errors. So on the exact lanes a lane's
//! trajectory is the scalar run's bit for bit (tests/ensemble_lanes.rs), on the fused ones
//! (`Lanes<W, true>`: the sums and the error norm with fused multiply-adds, the vector ln) to
//! round-off; and a member that ends (or fails) frees
//! its lane for the next member at once: the lanes stay full until the queue runs dry.
//!
//! A lane whose stages are not all finite (the dynamics failed there, or the state blew up) has
//! its attempt redone by the scalar stepper, which then reports exactly what a scalar run would.
//! The member plumbing (`enter`, `Slot`, `fill`, `retire`) is `members`, shared with the Taylor
//! engine; members of another method, and constrained ones, run the scalar driver.

use crate::integrate::dop853::Dop853;
use crate::integrate::explicit::{attempt, ExplicitRk};
use crate::integrate::problem::Slopes;
use crate::integrate::problem::Plain;
use crate::integrate::method::Method;
use crate::integrate::simulation::Simulation;
use crate::integrate::state::{Fault, Stats, YOf, Y};
use crate::integrate::stepper::Stepper;
use crate::lagrangian::Lagrangian;
use crate::lanes::Lanes;

use super::members::{accelerations, enter, fill, lanes_of, retire, End, Out, Slot};

/// What the DOP853 engine keeps per member.
struct Attempting {
    /// Whether the driver reads the interpolant: the accepted stages are then copied back.
    dense: bool,
    /// At a node: the next attempt opens a new step (end test, step budget, FSAL).
    at_node: bool,
    /// The trial step and whether it ends the run.
    h: f64,
    last: bool,
}

/// A DOP853 member in a lane.
type DopSlot<'p, 'a, L, const N: usize> = Slot<'p, 'a, Member<'p, L, N>, Attempting, N>;

/// A member's scalar DOP853 stepper.
type Member<'p, L, const N: usize> = ExplicitRk<Plain<'p, L>, Dop853, N>;

/// The DOP853 engine over the members of `queue` (see the module docs).
#[inline(always)]
pub(super) fn run<
    'p,
    'a: 'p,
    L: Lagrangian<N> + 'a,
    const N: usize,
    const W: usize,
    const F: bool,
>(
    queue: impl Iterator<Item = (usize, &'p mut Simulation<'a, L, N>)>,
    out: &mut Out<'_, N>,
) {
    let mut queue = queue;
    let mut slots: [Option<DopSlot<'_, '_, L, N>>; W] = core::array::from_fn(|_| None);
    let mut params: Vec<Lanes<W, F>> = Vec::new();
    let mut k = [[[Lanes::<W, F>::ZERO; N]; 2]; 16];
    loop {
        let refreshed = fill(&mut slots, &mut queue, out, start, pending);
        let Some(lane) = lanes_of(&slots) else {
            return;
        };
        if refreshed {
            params.clear();
        }
        let members: [&L; W] = core::array::from_fn(|l| lane[l].run.stepper.problem().sys);
        // Gather: t, h, tolerances, y and f at the node (k₀) of every lane.
        let mut t = Lanes::ZERO;
        let mut h = Lanes::ZERO;
        let mut rtol = Lanes::ZERO;
        let mut atol = Lanes::ZERO;
        let mut y = [[Lanes::<W, F>::ZERO; N]; 2];
        for (l, s) in lane.iter().enumerate() {
            let (tl, yl) = s.run.stepper.node();
            let (r, a) = s.run.stepper.tolerances();
            let k0 = &s.run.stepper.stages()[0];
            (t.0[l], h.0[l], rtol.0[l], atol.0[l]) = (tl, s.own.h, r, a);
            for c in 0..2 {
                for i in 0..N {
                    y[c][i].0[l] = yl[c][i];
                    k[0][c][i].0[l] = k0[c][i];
                }
            }
        }
        let v = vector_step(&members, &mut params, t, &y, &mut k, h, rtol, atol);
        // f at y₁ for the lanes that accept (the others' values are not read).
        // An `if`, not `bool::then` with a closure: the closure was not inlined, so this
        // evaluation ran as baseline code outside the engine's AVX2 function, each fused
        // multiply-add a call to the library's `fma` (perf: 19 % of an ensemble).
        let f1 = if v.ln_err.0.iter().any(|&e| e <= 0.0) {
            Some(accelerations(&members, &mut params, &v.y1[0], &v.y1[1], t + h))
        } else {
            None
        };
        // Scatter: each busy lane settles its attempt on its own stepper.
        for l in 0..W {
            let Some(s) = slots[l].as_mut() else { continue };
            let accepted = v.ln_err.0[l] <= 0.0;
            let f1l: Option<[f64; N]> = match (&f1, accepted) {
                (Some(f1), true) => Some(core::array::from_fn(|i| f1[i].0[l])),
                _ => None,
            };
            let clean = v.finite.0[l] == 0.0 && f1l.is_none_or(|a| a.iter().all(|x| x.is_finite()));
            let attempt = if clean {
                let stats = s.run.driver.stats();
                stats.rhs_evals += 11;
                let y1: Y<N> = core::array::from_fn(|c| core::array::from_fn(|i| v.y1[c][i].0[l]));
                let f1 = f1l.map(|a| {
                    stats.rhs_evals += 1;
                    [y1[1], a]
                });
                if s.own.dense {
                    let ks = s.run.stepper.stages_mut();
                    for j in 1..12 {
                        for c in 0..2 {
                            for i in 0..N {
                                ks[j][c][i] = k[j][c][i].0[l];
                            }
                        }
                    }
                }
                s.run.stepper.take_attempt(y1, f1);
                Ok(v.ln_err.0[l])
            } else {
                // Something was not finite in this lane: the scalar attempt says what.
                redo(&mut s.run.stepper, s.own.h, s.run.driver.stats())
            };
            let until = s.run.opts.until;
            let (h, last) = (s.own.h, s.own.last);
            // An adaptive step's fault is its retry, never the run's end (`Ok`).
            if let Ok(true) = s.run
                .stepper
                .settle(h, last, until, attempt, s.run.driver.stats())
            {
                let r = &mut s.run;
                match r
                    .driver
                    .after_step(&mut r.stepper, &r.opts, &mut r.progress)
                {
                    Ok(false) => s.own.at_node = true,
                    Ok(true) => retire(&mut slots[l], End::Stopped, out),
                    Err(f) => retire(&mut slots[l], End::Failed(f), out),
                }
            }
        }
    }
}

/// The scalar attempt of a lane whose vector attempt was not finite (out of line: a cold path, and
/// the scalar step inlined into every instantiation of the engine would only cost build time).
#[inline(never)]
fn redo<L: Lagrangian<N>, const N: usize>(
    stepper: &mut Member<'_, L, N>,
    h: f64,
    stats: &mut Stats,
) -> Result<f64, Fault> {
    stepper.attempt(h, stats)
}

/// Starts a DOP853 member (see [`enter`]).
fn start<'p, 'a, L: Lagrangian<N>, const N: usize>(
    pos: usize,
    sim: &'p mut Simulation<'a, L, N>,
    out: &mut Out<'_, N>,
) -> Option<DopSlot<'p, 'a, L, N>> {
    let run = enter(
        pos,
        sim,
        out,
        |method| match method {
            Method::Dop853 { rtol, atol } => Some((rtol, atol)),
            _ => None,
        },
        |sys, tol, t0, y0, hmax, stats| {
            Member::new(Plain { sys }, t0, y0, tol, 0.0, 0.0, hmax, stats)
        },
    )?;
    Some(Slot {
        pos,
        own: Attempting {
            dense: run.driver.needs_interpolant(&run.opts),
            at_node: true,
            h: 0.0,
            last: false,
        },
        run,
    })
}

/// Readies a DOP853 member's next attempt: at a node, the end test, the step budget and FSAL;
/// then the trial step. `Ok(false)` when the run has reached its end.
fn pending<L: Lagrangian<N>, const N: usize>(s: &mut DopSlot<'_, '_, L, N>) -> Result<bool, Fault> {
    let (run, own) = (&mut s.run, &mut s.own);
    if own.at_node {
        if run.stepper.t() >= run.opts.until {
            return Ok(false);
        }
        run.driver.check_budget(&run.opts)?;
        run.stepper.begin_step();
        own.at_node = false;
    }
    (own.h, own.last) = run.stepper.trial(run.opts.until)?;
    Ok(true)
}

/// The accelerations of W members (see [`accelerations`]), with the sum that is 0 in the lanes
/// where every one was finite (NaN elsewhere).
struct Members<'a, L, const W: usize, const F: bool> {
    members: &'a [&'a L; W],
    params: &'a mut Vec<Lanes<W, F>>,
    finite: Lanes<W, F>,
}

impl<L: Lagrangian<N>, const N: usize, const W: usize, const F: bool>
    Slopes<YOf<Lanes<W, F>, N>, N> for Members<'_, L, W, F>
{
    type Error = core::convert::Infallible;
    #[inline(always)]
    fn slope(
        &mut self,
        t: Lanes<W, F>,
        y: &YOf<Lanes<W, F>, N>,
        out: &mut YOf<Lanes<W, F>, N>,
    ) -> Result<(), Self::Error> {
        let a = accelerations(self.members, self.params, &y[0], &y[1], t);
        // 0 · x is 0 for finite x and NaN otherwise.
        for ai in &a {
            self.finite += *ai * 0.0;
        }
        *out = [y[1], a];
        Ok(())
    }
}

/// What [`vector_step`] gives for every lane: y₁, ln err, and the sum that is 0 where every
/// stage and y₁ was finite.
struct Attempted<R, const N: usize> {
    y1: YOf<R, N>,
    ln_err: R,
    finite: R,
}

/// The stages 1..=11 and y₁ of DOP853 for every lane, and each lane's ln err: the single run's
/// [`attempt`] at width W.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn vector_step<L: Lagrangian<N>, const N: usize, const W: usize, const F: bool>(
    members: &[&L; W],
    params: &mut Vec<Lanes<W, F>>,
    t: Lanes<W, F>,
    y: &YOf<Lanes<W, F>, N>,
    k: &mut [YOf<Lanes<W, F>, N>; 16],
    h: Lanes<W, F>,
    rtol: Lanes<W, F>,
    atol: Lanes<W, F>,
) -> Attempted<Lanes<W, F>, N> {
    let mut f = Members {
        members,
        params,
        finite: Lanes::ZERO,
    };
    let (mut arg, mut y1) = (*y, *y);
    let Ok(ln_err) = attempt::<Dop853, _, _, N>(
        &mut f,
        L::CYCLIC,
        t,
        y,
        k,
        h,
        (rtol, atol),
        &mut arg,
        &mut y1,
    );
    let mut finite = f.finite;
    for x in y1.iter().flatten() {
        finite += *x * 0.0;
    }
    Attempted { y1, ln_err, finite }
}
