//! The member plumbing every lanes engine shares: a member taken into a lane ([`enter`], its
//! [`Slot`]), the refill of free lanes from the queue ([`fill`]), the lane-by-lane view of the
//! busy slots ([`lanes_of`]), q̈ of the lanes with the per-lane fallback ([`accelerations`]) and the
//! end of a run ([`retire`]); and the scalar driver for the runs the engines do not take ([`scalar`]).

use crate::integrate::driver::{Driver, Progress, RunOptions};
use crate::integrate::error::SimulationError;
use crate::integrate::method::Method;
use crate::integrate::simulation::{Prepared, Simulation};
use crate::integrate::state::{Fault, Stats, Y};
use crate::integrate::stepper::Stepper;
use crate::integrate::trajectory::Trajectory;
use crate::lagrangian::Lagrangian;
use crate::lanes::{Lanes, Mask};

/// One member in a lane: its position in the input, its run (driver, stepper, options) and what
/// the engine keeps per member besides (`X`).
pub(super) struct Slot<'p, 'a, S, X, const N: usize> {
    pub(super) pos: usize,
    pub(super) run: Entered<'p, 'a, S, N>,
    pub(super) own: X,
}

/// Brings every lane to a pending step, filling free lanes from `queue` (`start` takes a member
/// in, `pending` readies its next step: `Ok(false)` at its end time); members that end go to
/// `out`. Whether a lane took a new member (its parameters are then to load).
pub(super) fn fill<
    'p,
    'a: 'p,
    L: Lagrangian<N> + 'a,
    S: Stepper<N>,
    X,
    const N: usize,
    const W: usize,
>(
    slots: &mut [Option<Slot<'p, 'a, S, X, N>>; W],
    queue: &mut impl Iterator<Item = (usize, &'p mut Simulation<'a, L, N>)>,
    out: &mut Out<'_, N>,
    start: impl Fn(
        usize,
        &'p mut Simulation<'a, L, N>,
        &mut Out<'_, N>,
    ) -> Option<Slot<'p, 'a, S, X, N>>,
    pending: impl Fn(&mut Slot<'p, 'a, S, X, N>) -> Result<bool, Fault>,
) -> bool {
    let mut refreshed = false;
    for slot in slots.iter_mut() {
        loop {
            let s = match slot {
                Some(s) => s,
                None => match queue.next() {
                    None => break,
                    Some((pos, sim)) => {
                        *slot = start(pos, sim, out);
                        refreshed = true;
                        continue;
                    }
                },
            };
            match pending(s) {
                Ok(true) => break,
                Ok(false) => retire(slot, End::Finished, out),
                Err(f) => retire(slot, End::Failed(f), out),
            }
        }
    }
    refreshed
}

/// Where the engines send each member's result as it ends (its position, its result). One type
/// for every caller, so that the engines, large and generic in the system, are compiled once per
/// system rather than once per ensemble closure (the test and example builds' largest cost).
pub(crate) type Out<'o, const N: usize> =
    dyn FnMut(usize, Result<Trajectory<N>, SimulationError>) + 'o;

/// The slot each lane reads: its own where busy, else the first busy one (a free lane computes a
/// copy whose results are not read); `None` when every lane is free.
pub(super) fn lanes_of<T, const W: usize>(slots: &[Option<T>; W]) -> Option<[&T; W]> {
    let busy = slots.iter().position(Option::is_some)?;
    let src: [usize; W] = core::array::from_fn(|l| if slots[l].is_some() { l } else { busy });
    let busy_lanes = slots.each_ref().map(Option::as_ref);
    Some(core::array::from_fn(|l| match busy_lanes[src[l]] {
        Some(s) => s,
        None => unreachable_free_lane(),
    }))
}

/// q̈ of every lane's member: the system's compiled kernel ([`Lagrangian::accelerations_in`]),
/// a lane it leaves out (a failed pivot test, a value not finite) by that member's own
/// [`Lagrangian::accelerations`], NaN where that fails too; every lane by its member where the
/// system has no compiled kernel. `params`: the kernel's copy of the members' parameters
/// (emptied by the engine when a lane's member changes).
///
/// ```
/// # use lagrange_runtime::{ensemble::lane_accelerations, lanes::Lanes, Lagrangian, Scalar};
/// struct Spring { k: f64 }
/// impl Lagrangian<1> for Spring {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
///         (v[0] * v[0] - q[0] * q[0] * self.k) * 0.5
///     }
/// }
/// let (a, b) = (Spring { k: 1.0 }, Spring { k: 4.0 });
/// let x = Lanes::<2>([1.0, 0.5]);
/// let qdd = lane_accelerations(&[&a, &b], &mut Vec::new(), &[x], &[Lanes::<2>([0.0; 2])], Lanes::<2>([0.0; 2]));
/// assert_eq!(qdd[0].0, [-1.0, -2.0]);
/// ```
#[inline(always)]
pub fn accelerations<L: Lagrangian<N>, const N: usize, const W: usize, const F: bool>(
    members: &[&L; W],
    params: &mut Vec<Lanes<W, F>>,
    q: &[Lanes<W, F>; N],
    qdot: &[Lanes<W, F>; N],
    t: Lanes<W, F>,
) -> [Lanes<W, F>; N] {
    match L::accelerations_in(members, params, q, qdot, t) {
        Some((x, ok)) if ok.all() => x,
        Some((x, ok)) => {
            one_by_one(members, &lanes(q), &lanes(qdot), t.0, lanes(&x), ok).map(Lanes)
        }
        None => one_by_one(
            members,
            &lanes(q),
            &lanes(qdot),
            t.0,
            [[f64::NAN; W]; N],
            Mask::splat(false),
        )
        .map(Lanes),
    }
}

/// The lanes of each entry of `v`, as plain arrays.
#[inline(always)]
fn lanes<const N: usize, const W: usize, const F: bool>(v: &[Lanes<W, F>; N]) -> [[f64; W]; N] {
    v.map(|x| x.0)
}

/// `x` (entry i, lane l), with every lane not set in `ok` replaced by its member's own
/// [`Lagrangian::accelerations`] (NaN where that fails). On plain arrays, so that the exact and
/// the fused lanes share one copy.
// Out of line: a cold path for generated systems, and inlining a jets derivation at each of the
// twelve stages of every instantiation costs build time for nothing.
#[inline(never)]
fn one_by_one<L: Lagrangian<N>, const N: usize, const W: usize>(
    members: &[&L; W],
    q: &[[f64; W]; N],
    qdot: &[[f64; W]; N],
    t: [f64; W],
    mut x: [[f64; W]; N],
    ok: Mask<W>,
) -> [[f64; W]; N] {
    for (l, sys) in members.iter().enumerate() {
        if ok.0[l] {
            continue;
        }
        let ql: [f64; N] = core::array::from_fn(|i| q[i][l]);
        let vl: [f64; N] = core::array::from_fn(|i| qdot[i][l]);
        let a = sys.accelerations(&ql, &vl, t[l]).unwrap_or([f64::NAN; N]);
        for i in 0..N {
            x[i][l] = a[i];
        }
    }
    x
}

/// How a member's run ended.
pub(super) enum End {
    /// It reached its end time (its last sample is still to record).
    Finished,
    /// A terminal event ended it.
    Stopped,
    /// A fault stopped it.
    Failed(Fault),
}

/// Ends the run in `slot` and sends its result to `out`.
#[inline(never)]
pub(super) fn retire<S: Stepper<N>, X, const N: usize>(
    slot: &mut Option<Slot<'_, '_, S, X, N>>,
    end: End,
    out: &mut Out<'_, N>,
) {
    if let Some(s) = slot.take() {
        out(s.pos, s.run.end(end));
    }
}

/// `src` maps every lane to a busy one, so this is never called.
#[cold]
fn unreachable_free_lane() -> ! {
    unreachable!("every lane reads a busy slot")
}

/// A member taken into a lane, whatever its method: its driver (samples, events, trajectory),
/// its place between steps, its scalar stepper and its options.
pub(super) struct Entered<'p, 'a, S, const N: usize> {
    pub(super) driver: Driver<'p, 'a, 'p, N>,
    pub(super) progress: Progress,
    pub(super) stepper: S,
    pub(super) opts: RunOptions<'p>,
}

/// Starts the run of `sim` for a lanes engine, where `takes` finds the engine's method (and
/// gives its settings) and the run has no constraints: the stepper from `make`. Any other run (or
/// one that fails before its first step) runs or ends here and goes to `out`.
pub(super) fn enter<'p, 'a, L: Lagrangian<N>, S: Stepper<N>, P, const N: usize>(
    pos: usize,
    sim: &'p mut Simulation<'a, L, N>,
    out: &mut Out<'_, N>,
    takes: impl FnOnce(Method) -> Option<P>,
    make: impl FnOnce(&'p L, P, f64, Y<N>, f64, &mut Stats) -> Result<S, Fault>,
) -> Option<Entered<'p, 'a, S, N>> {
    let p = match sim.prepare() {
        Ok(p) => p,
        Err(e) => {
            out(pos, Err(e));
            return None;
        }
    };
    // Members whose events reset the state run on the scalar driver (its restarts).
    let resets = p.events.iter().any(|e| e.is_reset());
    let settings = match (takes(p.method), &p.manifold) {
        (Some(settings), None) if !resets => settings,
        _ => {
            out(pos, scalar(p));
            return None;
        }
    };
    let Prepared {
        sys,
        events,
        method,
        y0,
        hmax,
        opts,
        observer,
        ..
    } = p;
    let mut driver = Driver::new(sys, None, events, method, &opts, observer);
    let t0 = opts.t0;
    let mut stepper = match make(sys, settings, t0, y0, hmax, driver.stats()) {
        Ok(s) => s,
        Err(f) => {
            out(pos, Err(driver.fail(f, t0, y0)));
            return None;
        }
    };
    let progress = match driver.begin(&mut stepper, &opts) {
        Ok(p) => p,
        Err(f) => {
            out(pos, driver.conclude(Err(f), &stepper));
            return None;
        }
    };
    Some(Entered {
        driver,
        progress,
        stepper,
        opts,
    })
}

impl<S: Stepper<N>, const N: usize> Entered<'_, '_, S, N> {
    /// The run's result, however it ended (on reaching the end time its last sample is recorded
    /// here).
    pub(super) fn end(self, end: End) -> Result<Trajectory<N>, SimulationError> {
        let Entered {
            mut driver,
            mut stepper,
            ..
        } = self;
        let r = match end {
            End::Finished => driver.finish(&mut stepper),
            End::Stopped => Ok(()),
            End::Failed(f) => Err(f),
        };
        driver.conclude(r, &stepper)
    }
}

/// A run the lanes do not take, on the scalar driver.
pub(super) fn scalar<L: Lagrangian<N>, const N: usize>(
    p: Prepared<'_, '_, L, N>,
) -> Result<Trajectory<N>, SimulationError> {
    super::super::simulation::run_prepared(p)
}
