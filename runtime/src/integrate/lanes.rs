//! DOP853 over SIMD lanes: W members of an ensemble step together, one member per lane of
//! [`Lanes`], each with its own step size, error norm and accept/reject decision (as heyoka's
//! batch mode does).
//!
//! The stages, the new state and the error sums of all lanes are one pass of vector code (the
//! system's [`Lagrangian::accelerations_lanes`]); everything that is per member stays the scalar
//! code of [`Dop853`] and the driver, run on that member's own stepper: the step-size controller,
//! the decision, the samples, events, dense output and errors. So a lane's trajectory is the
//! scalar run's bit for bit (tests/ensemble_lanes.rs), and a member that ends (or fails) frees
//! its lane for the next member at once: the lanes stay full until the queue runs dry.
//!
//! A lane whose stages are not all finite (the dynamics failed there, or the state blew up) has
//! its attempt redone by the scalar stepper, which then reports exactly what a scalar run would.
//! Taylor members run on the Taylor engine of the same shape (`taylor_lanes`), which shares the
//! member plumbing here (`enter`, `Slot`, `fill`, `retire`); members of another method, and
//! constrained ones, run the scalar driver.

use crate::lagrangian::Lagrangian;
use crate::lanes::Lanes;

use super::dop853::{Attempt, Dop853};
use super::dop853_coefficients::{A, C, E3, E5};
use super::driver::{self, Driver, Progress, RunOptions};
use super::error::SimulationError;
use super::method::Method;
use super::simulation::{Prepared, Simulation};
use super::state::{combine, weighted, Fault, YOf, Y};
use super::stepper::Stepper;
use super::taylor_lanes::run_taylor_lanes;
use super::trajectory::{Stats, Trajectory};

/// One member in a lane: its position in the input, its run (driver, stepper, options,
/// parameters) and what the engine keeps per member besides (`X`).
pub(super) struct Slot<'p, 'a, L: ?Sized, S, X, const N: usize> {
    pub(super) pos: usize,
    pub(super) run: Entered<'p, 'a, L, S, N>,
    pub(super) own: X,
}

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
type DopSlot<'p, 'a, L, const N: usize> = Slot<'p, 'a, L, Dop853<'p, L, N>, Attempting, N>;

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
    slots: &mut [Option<Slot<'p, 'a, L, S, X, N>>; W],
    queue: &mut impl Iterator<Item = (usize, &'p mut Simulation<'a, L, N>)>,
    out: &mut Out<'_, N>,
    start: impl Fn(
        usize,
        &'p mut Simulation<'a, L, N>,
        &mut Out<'_, N>,
    ) -> Option<Slot<'p, 'a, L, S, X, N>>,
    pending: impl Fn(&mut Slot<'p, 'a, L, S, X, N>) -> Result<bool, Fault>,
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

/// Loads the lane parameters of the members in `lane` (parameter p of every lane in `params[p]`).
pub(super) fn load_params<L: ?Sized, S, X, const N: usize, const W: usize>(
    params: &mut [Lanes<W>],
    lane: &[&Slot<'_, '_, L, S, X, N>; W],
) {
    for (p, v) in params.iter_mut().enumerate() {
        *v = Lanes::from_fn(|l| lane[l].run.params[p]);
    }
}

/// Runs `sims` (in order) with W members per vector, calling `out(position, result)` as each
/// member ends (not in order): DOP853 and Taylor members without constraints in lanes, any other
/// member on the scalar driver.
///
/// On an x86-64 CPU with AVX2 the engine runs as AVX2 code, chosen at run time so the same binary
/// runs everywhere; an x86-64 CPU without AVX2 runs the members one at a time (the same results:
/// a lane is its scalar run bit for bit). Lanes in SSE2's 2-wide vectors were 1.6× slower than
/// AVX2's (BENCHMARKS.md "Ensembles with SIMD lanes"), little faster than one member at a time,
/// and cost a second compiled copy of both engines for every system in every build. Other
/// architectures run the engines as their own vector code. Rust does not fuse a multiplication
/// and an addition unless asked (`mul_add`), so every path computes the same numbers.
pub(crate) fn run_lanes<L: Lagrangian<N>, const N: usize, const W: usize>(
    sims: &mut [Simulation<'_, L, N>],
    out: &mut Out<'_, N>,
) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: `run_lanes_avx2` only needs AVX2, which the CPU has (checked just above).
            #[allow(unsafe_code)]
            unsafe {
                run_lanes_avx2::<L, N, W>(sims, out)
            }
        } else {
            one_at_a_time(sims, out)
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    run_lanes_here::<L, N, W>(sims, out)
}

/// Every member on the scalar driver, in order.
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
fn one_at_a_time<L: Lagrangian<N>, const N: usize>(
    sims: &mut [Simulation<'_, L, N>],
    out: &mut Out<'_, N>,
) {
    for (pos, sim) in sims.iter_mut().enumerate() {
        out(pos, sim.prepare().and_then(scalar));
    }
}

/// [`run_lanes_here`] compiled for AVX2 (its vector code inlined here).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_lanes_avx2<L: Lagrangian<N>, const N: usize, const W: usize>(
    sims: &mut [Simulation<'_, L, N>],
    out: &mut Out<'_, N>,
) {
    run_lanes_here::<L, N, W>(sims, out)
}

/// The engines, for the instruction set of their caller: the Taylor members on the Taylor
/// engine ([`run_taylor_lanes`]), every other member on this DOP853 engine (which hands what is
/// not DOP853 to the scalar driver).
#[inline(always)]
fn run_lanes_here<L: Lagrangian<N>, const N: usize, const W: usize>(
    sims: &mut [Simulation<'_, L, N>],
    out: &mut Out<'_, N>,
) {
    let taylor = |s: &Simulation<'_, L, N>| matches!(s.method, Method::Taylor { .. });
    if sims.iter().any(taylor) {
        let queue = sims.iter_mut().enumerate().filter(|(_, s)| taylor(s));
        run_taylor_lanes::<L, N, W>(queue, out);
    }
    let queue = sims.iter_mut().enumerate().filter(|(_, s)| !taylor(s));
    run_dop853_lanes::<L, N, W>(queue, out);
}

/// The DOP853 engine over the members of `queue` (see the module docs).
#[inline(always)]
fn run_dop853_lanes<'p, 'a: 'p, L: Lagrangian<N> + 'a, const N: usize, const W: usize>(
    queue: impl Iterator<Item = (usize, &'p mut Simulation<'a, L, N>)>,
    out: &mut Out<'_, N>,
) {
    let mut queue = queue;
    let mut slots: [Option<DopSlot<'_, '_, L, N>>; W] = core::array::from_fn(|_| None);
    let mut params = vec![Lanes::<W>::ZERO; L::LANE_PARAMS];
    let mut k = [[[Lanes::<W>::ZERO; N]; 2]; 16];
    loop {
        let refreshed = fill(&mut slots, &mut queue, out, start, pending);
        let Some(lane) = lanes_of(&slots) else {
            return;
        };
        if refreshed {
            load_params(&mut params, &lane);
        }
        let members: [&L; W] = core::array::from_fn(|l| lane[l].run.stepper.sys());
        // Gather: t, h, tolerances, y and f at the node (k₀) of every lane.
        let mut t = Lanes::ZERO;
        let mut h = Lanes::ZERO;
        let mut rtol = Lanes::ZERO;
        let mut atol = Lanes::ZERO;
        let mut y = [[Lanes::<W>::ZERO; N]; 2];
        for (l, s) in lane.iter().enumerate() {
            let (tl, yl) = s.run.stepper.node_state();
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
        let v = vector_step(&members, &params, t, &y, &mut k, h, rtol, atol);
        // f at y₁ for the lanes that accept (the others' values are not read).
        let f1 = v
            .ln_err
            .0
            .iter()
            .any(|&e| e <= 0.0)
            .then(|| L::accelerations_lanes(&members, &params, &v.y1[0], &v.y1[1], t + h));
        // Scatter: each busy lane settles its attempt on its own stepper.
        for l in 0..W {
            let Some(s) = slots[l].as_mut() else { continue };
            let accepted = v.ln_err.0[l] <= 0.0;
            let f1l: Option<[f64; N]> = match (&f1, accepted) {
                (Some(f1), true) => Some(core::array::from_fn(|i| f1[i].0[l])),
                _ => None,
            };
            let clean = v.finite.0[l] == 0.0 && f1l.is_none_or(|a| a.iter().all(|x| x.is_finite()));
            let attempt: Attempt<N> = if clean {
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
                Ok((y1, v.ln_err.0[l], f1))
            } else {
                // Something was not finite in this lane: the scalar attempt says what.
                redo(&mut s.run.stepper, s.own.h, s.run.driver.stats())
            };
            let until = s.run.opts.until;
            let (h, last) = (s.own.h, s.own.last);
            if s.run
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
    stepper: &mut Dop853<'_, L, N>,
    h: f64,
    stats: &mut super::trajectory::Stats,
) -> Attempt<N> {
    stepper.attempt(h, stats)
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
pub(super) fn retire<L: Lagrangian<N>, S: Stepper<N>, X, const N: usize>(
    slot: &mut Option<Slot<'_, '_, L, S, X, N>>,
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
/// its place between steps, its scalar stepper, its options and its parameters for the lanes code.
pub(super) struct Entered<'p, 'a, L: ?Sized, S, const N: usize> {
    pub(super) driver: Driver<'p, 'a, 'p, L, N>,
    pub(super) progress: Progress,
    pub(super) stepper: S,
    pub(super) opts: RunOptions<'p>,
    pub(super) params: Vec<f64>,
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
) -> Option<Entered<'p, 'a, L, S, N>> {
    let p = match sim.prepare() {
        Ok(p) => p,
        Err(e) => {
            out(pos, Err(e));
            return None;
        }
    };
    let settings = match (takes(p.method), &p.manifold) {
        (Some(settings), None) => settings,
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
    let mut params = vec![0.0; L::LANE_PARAMS];
    sys.lane_params(&mut params);
    Some(Entered {
        driver,
        progress,
        stepper,
        opts,
        params,
    })
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
        |sys, (rtol, atol), t0, y0, hmax, stats| Dop853::new(sys, t0, y0, rtol, atol, hmax, stats),
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

/// A run the lanes do not take, on the scalar driver.
fn scalar<L: Lagrangian<N>, const N: usize>(
    p: Prepared<'_, '_, L, N>,
) -> Result<Trajectory<N>, SimulationError> {
    driver::run(
        p.sys, p.manifold, p.events, p.method, p.y0, p.hmax, &p.opts, p.observer,
    )
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

impl<L: Lagrangian<N>, S: Stepper<N>, const N: usize> Entered<'_, '_, L, S, N> {
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

/// What one vector attempt gives: y₁ and ln err per lane, and a lane sum that is 0 where every
/// stage was finite (NaN otherwise).
struct VectorStep<const N: usize, const W: usize> {
    y1: YOf<Lanes<W>, N>,
    ln_err: Lanes<W>,
    finite: Lanes<W>,
}

/// The stages 1..=11 and y₁ of DOP853 for every lane, and each lane's ln err: the arithmetic of
/// the scalar `dop853::step`, operation for operation, on W members at once.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn vector_step<L: Lagrangian<N>, const N: usize, const W: usize>(
    members: &[&L; W],
    params: &[Lanes<W>],
    t: Lanes<W>,
    y: &YOf<Lanes<W>, N>,
    k: &mut [YOf<Lanes<W>, N>; 16],
    h: Lanes<W>,
    rtol: Lanes<W>,
    atol: Lanes<W>,
) -> VectorStep<N, W> {
    let cyclic: [bool; N] = const { L::CYCLIC };
    // 0 · x is 0 for finite x and NaN otherwise: the sum is 0 only if every stage was finite.
    let mut finite = Lanes::<W>::ZERO;
    macro_rules! stages {
        ($($s:literal)*) => {$(
            let mut ys = combine::<$s, _, _, _, _>(y, h, &A[$s], k);
            // The cyclic coordinates' stage positions are not read (see `state::hold_cyclic`).
            for i in 0..N {
                if cyclic[i] {
                    ys[0][i] = y[0][i];
                }
            }
            let a = L::accelerations_lanes(members, params, &ys[0], &ys[1], t + C[$s] * h);
            for ai in &a {
                finite += *ai * 0.0;
            }
            k[$s] = [ys[1], a];
        )*};
    }
    stages!(1 2 3 4 5 6 7 8 9 10 11);
    let y1 = combine::<12, _, _, _, _>(y, h, &A[12], k);
    let e5 = weighted::<12, _, _, _, _>(&E5, k);
    let e3 = weighted::<12, _, _, _, _>(&E3, k);
    // The error weights and sums of `control::scales` and `control::sum_sq`, lane by lane.
    let mut err5 = Lanes::<W>::ZERO;
    let mut err3 = Lanes::<W>::ZERO;
    for i in 0..N {
        let sk = |c: usize| atol + rtol * y[c][i].abs().zip(y1[c][i].abs(), f64::max);
        let (s0, s1) = (sk(0), sk(1));
        let (a, b) = (e5[0][i] / s0, e5[1][i] / s1);
        err5 += a * a + b * b;
        let (a, b) = (e3[0][i] / s0, e3[1][i] / s1);
        err3 += a * a + b * b;
    }
    for c in 0..2 {
        for i in 0..N {
            finite += y1[c][i] * 0.0;
        }
    }
    let deno = err5 + 0.01 * err3;
    let ln_err = Lanes::from_fn(|l| {
        let deno = if deno.0[l] <= 0.0 { 1.0 } else { deno.0[l] };
        (h.0[l] * err5.0[l]).ln() - 0.5 * ((2 * N) as f64 * deno).ln()
    });
    VectorStep { y1, ln_err, finite }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scalar;

    /// x'' = −k x − x³ (a hand-written system: its lanes are the trait's default).
    struct Duffing {
        k: f64,
    }

    impl Lagrangian<1> for Duffing {
        const COORDINATES: [&'static str; 1] = ["x"];
        const CYCLIC: [bool; 1] = [false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
            let x2 = q[0] * q[0];
            (v[0] * v[0] - x2 * self.k - x2 * x2 * 0.5) * 0.5
        }
    }

    /// Runs `sims` through `engine`, the results in member order.
    fn collect(
        systems: &[Duffing],
        engine: impl FnOnce(&mut [Simulation<'_, Duffing, 1>], &mut Out<'_, 1>),
    ) -> Vec<Result<Trajectory<1>, SimulationError>> {
        let mut sims: Vec<Simulation<'_, Duffing, 1>> = systems
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let sim = Simulation::new(s, [0.5 + 0.1 * i as f64], [0.0]).sample_every(0.5);
                match i % 3 {
                    // A member the lanes do not take, and one that fails before its first step.
                    1 => sim.method(Method::Rk4 { dt: 0.01 }).until(3.0),
                    2 if i == 5 => sim.until(f64::NAN),
                    _ => sim.until(3.0 + i as f64 * 0.25),
                }
            })
            .collect();
        let mut slots: Vec<Option<Result<Trajectory<1>, SimulationError>>> =
            systems.iter().map(|_| None).collect();
        engine(&mut sims, &mut |pos, r| slots[pos] = Some(r));
        slots
            .into_iter()
            .map(|r| r.expect("every member ends"))
            .collect()
    }

    /// The path of an x86-64 CPU without AVX2 (members one at a time) gives what the lanes give,
    /// bit for bit, failures included.
    #[test]
    fn one_at_a_time_equals_the_lanes() {
        let systems: Vec<Duffing> = (0..11).map(|i| Duffing { k: 1.0 + i as f64 }).collect();
        let lanes = collect(&systems, run_lanes::<Duffing, 1, 4>);
        let plain = collect(&systems, one_at_a_time::<Duffing, 1>);
        for (i, (a, b)) in lanes.iter().zip(&plain).enumerate() {
            match (a, b) {
                (Ok(a), Ok(b)) => {
                    let bits = |tr: &Trajectory<1>| -> Vec<u64> {
                        tr.t.iter()
                            .chain(tr.q.iter().map(|q| &q[0]))
                            .chain(tr.qdot.iter().map(|v| &v[0]))
                            .map(|x| x.to_bits())
                            .collect()
                    };
                    assert_eq!(bits(a), bits(b), "member {i}");
                    assert_eq!(a.stats.steps, b.stats.steps, "member {i}");
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "member {i}"),
                _ => panic!("member {i}: {a:?} vs {b:?}"),
            }
        }
        assert!(plain[5].is_err() && plain.iter().filter(|r| r.is_ok()).count() == 10);
    }
}
