//! The driver loop shared by all methods: it starts the chosen [`Method`]'s stepper, steps it to
//! the end time, records the samples, locates the events and turns a stepper's fault into the
//! error that holds the trajectory so far.

use crate::error::DynamicsError;
use crate::lagrangian::Lagrangian;

use super::dense::{Dense, Kind};
use super::error::{PartialTrajectory, SimulationError};
use super::events::{
    Direction, Event, EventHit, Jump, ZENO_INTERVALS, Zeno, brent, location_tol, zeno,
};
use super::factory::Explicit;
use super::manifold::Manifold;
use super::method::Method;
use super::problem::Plain;
use super::radau5::Radau5;
use super::rattle::Rattle;
use super::state::Stats;
use super::state::{Fault, Y};
use super::stepper::{FixedGrid, Stepper};
use super::system::System;
use super::taylor::Taylor;
use super::trajectory::{Sample, Trajectory};
use super::variational::VariationalMidpoint;

/// Runs `method` on `sys` from y0 = (q0, q̇0) under the options `o`, with `events` located and
/// steps of at most `hmax` for the adaptive methods; on the constraints of `manifold` if given
/// (the explicit methods are projected onto them after every step, the variational method takes
/// the constrained RATTLE step).
#[allow(clippy::too_many_arguments)]
pub(super) fn run<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    manifold: Option<&dyn Manifold<N>>,
    events: &[Event<'_, N>],
    method: Method,
    y0: Y<N>,
    hmax: f64,
    o: &RunOptions,
    observer: Option<&mut dyn FnMut(&Sample<N>)>,
) -> Result<Trajectory<N>, SimulationError> {
    let driver = Driver::new(sys, manifold, events, method, o, observer);
    let (t0, until) = (o.t0, o.until);
    // Each method's stepper from a state (t, y): at the start, and again after each jump of a
    // resetting event.
    if let Some(e) = Explicit::of(method) {
        return driver.run_boxed(o, t0, y0, &mut |t, y, stats| {
            e.stepper(Plain { sys }, t, y, until, hmax, stats)
        });
    }
    match method {
        Method::VariationalMidpoint { dt } => {
            // Check the dynamics at the start (a singular mass matrix is reported up front).
            if let Err(e) = sys.accelerations(&y0[0], &y0[1], t0) {
                return Err(driver.fail(Fault::Dynamics(e), t0, y0));
            }
            match manifold {
                Some(m) => driver.run(o, t0, y0, |t, y, _| {
                    Rattle::new(sys, m, FixedGrid::new(t, dt, until), y[0], y[1])
                }),
                None => driver.run(o, t0, y0, |t, y, _| {
                    Ok(VariationalMidpoint::new(
                        sys,
                        FixedGrid::new(t, dt, until),
                        y[0],
                        y[1],
                    ))
                }),
            }
        }
        Method::Taylor { tol } => {
            driver.run(o, t0, y0, |t, y, _| Ok(Taylor::new(sys, t, y, tol, hmax)))
        }
        Method::Radau5 { rtol, atol } => driver.run(o, t0, y0, |t, y, stats| {
            Radau5::new(sys, t, y, rtol, atol, hmax, stats)
        }),
        // Taken by the factory above.
        Method::Rk4 { .. } | Method::DormandPrince { .. } | Method::Dop853 { .. } => {
            Err(driver.fail(Fault::NonFinite, t0, y0))
        }
    }
}

/// Builds a run's stepper from a state (t, y): at the start, and again after each jump of a
/// resetting event.
type Make<'m, 's, const N: usize> =
    dyn FnMut(f64, Y<N>, &mut Stats) -> Result<Box<dyn Stepper<N> + 's>, Fault> + 'm;

/// What a run asks of the driver besides the method: its time span, sampling and step budget.
pub(super) struct RunOptions<'s> {
    pub(super) t0: f64,
    pub(super) until: f64,
    pub(super) sampling: Sampling<'s>,
    pub(super) max_steps: usize,
    /// Whether every sample is stored (else the first and the latest, see `Trajectory::record`).
    pub(super) keep_samples: bool,
    /// The most samples stored.
    pub(super) max_samples: usize,
    /// Whether `max_samples` is the default (a memory budget), not the user's.
    pub(super) max_samples_default: bool,
    /// When the run keeps its dense output: the most bytes it may take.
    pub(super) dense_budget: Option<usize>,
}

/// Which states the trajectory records.
pub(super) enum Sampling<'s> {
    /// Every accepted step.
    Steps,
    /// t0 + kΔ.
    Every(f64),
    /// The given increasing times; a time within `snap` of a node is taken at the node.
    At { times: &'s [f64], snap: f64 },
}

impl Sampling<'_> {
    /// The k-th sample time after t0 (k = 0, 1, …), or `None` past the last one; a grid time
    /// within 1e-9 Δ of `until` is `until`.
    fn time(&self, k: usize, t0: f64, until: f64) -> Option<f64> {
        match *self {
            Sampling::Steps => None,
            Sampling::Every(ds) => {
                let ts = t0 + (k + 1) as f64 * ds;
                let ts = if (ts - until).abs() <= 1e-9 * ds {
                    until
                } else {
                    ts
                };
                (ts <= until).then_some(ts)
            }
            Sampling::At { times, .. } => times.get(k).copied(),
        }
    }

    /// Whether a sample time falls strictly between t0 and the end `until` (beyond `snap` of
    /// it): only then may a sample need the method's interpolant (t0 is the initial state, the
    /// end is the last node).
    fn inside(&self, t0: f64, until: f64) -> bool {
        let end = until - self.snap();
        match *self {
            Sampling::Steps => false,
            Sampling::Every(_) => self.time(0, t0, until).is_some_and(|t| t < end),
            Sampling::At { times, .. } => times.iter().any(|&t| t > t0 && t < end),
        }
    }

    /// How close to a node a sample time is taken at the node.
    fn snap(&self) -> f64 {
        match *self {
            Sampling::Steps => 0.0,
            Sampling::Every(ds) => 1e-9 * ds,
            Sampling::At { snap, .. } => snap,
        }
    }
}

pub(super) struct Driver<'s, 'a, 'o, const N: usize> {
    sys: &'s dyn System<N>,
    /// Whether the run records the work (the energy is not conserved); a constant per system.
    records_work: bool,
    /// The method (a failure's stiffness diagnosis reads it).
    method: Method,
    /// The constraints of a constrained run.
    manifold: Option<&'s dyn Manifold<N>>,
    /// Whether every accepted step is projected onto the constraints (explicit methods).
    project_steps: bool,
    events: &'s [Event<'a, N>],
    observer: Option<&'o mut dyn FnMut(&Sample<N>)>,
    keep: bool,
    max_samples: usize,
    max_samples_default: bool,
    /// When the run keeps its dense output: the method's interpolant and the most bytes it may
    /// take.
    dense: Option<(Kind, usize)>,
    traj: Trajectory<N>,
    stats: Stats,
    work: Work,
    /// The Gauss–Legendre rule of the work integral where the method wants more than 4 points.
    gauss: Vec<(f64, f64)>,
    /// The energy the jumps of resetting events added (the work column carries it).
    jump_work: f64,
    /// Each resetting event's hit count and its latest hit times, as many as the Zeno test reads
    /// (a long run of a periodic impact keeps no growing list).
    reset_hits: Vec<(usize, Vec<f64>)>,
    /// A jump just taken: the method restarts from this (t, y).
    pending: Option<(f64, Y<N>)>,
}

/// The work W done on the system since t0 (the integral of [`Lagrangian::power`]), known at the
/// start `t_a` of the last step and at its end, the current node.
#[derive(Clone, Copy, Debug, Default)]
struct Work {
    /// W(t_a).
    at_prev: f64,
    /// W at the current node, or NaN while the last step's quadrature has not completed.
    at_node: f64,
}

/// 4-point Gauss–Legendre on [0, 1]: nodes and weights (exact for polynomials of degree 7).
const GAUSS4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_92),
    (0.330_009_478_207_571_87, 0.326_072_577_431_273_05),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_05),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_92),
];

/// m-point Gauss–Legendre on [0, 1] (exact for polynomials of degree 2m − 1): the roots of the
/// Legendre polynomial P_m by Newton's method from Tricomi's estimate, weights 2/((1 − x²)P′²).
pub(super) fn gauss_legendre(m: usize) -> Vec<(f64, f64)> {
    let mf = m as f64;
    let mut out = Vec::with_capacity(m);
    for i in 1..=m {
        // cos(π(i − 1/4)/(m + 1/2)): the i-th root from the right, within 1e-3 or so.
        let mut x = (core::f64::consts::PI * (i as f64 - 0.25) / (mf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_m(x) and P_m′(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=m {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
                (p0, p1) = (p1, p2);
            }
            dp = mf * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() <= 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push(((1.0 - x) / 2.0, w / 2.0));
    }
    out
}

impl<'s, 'a, 'o, const N: usize> Driver<'s, 'a, 'o, N> {
    /// The driver of a run of `method` on `sys` under the options `o`.
    pub(super) fn new(
        sys: &'s dyn System<N>,
        manifold: Option<&'s dyn Manifold<N>>,
        events: &'s [Event<'a, N>],
        method: Method,
        o: &RunOptions,
        observer: Option<&'o mut dyn FnMut(&Sample<N>)>,
    ) -> Self {
        let flags = sys.flags();
        let mut traj = Trajectory::empty(flags, manifold.map_or(0, |m| m.count()));
        if events.iter().any(|e| e.is_reset()) {
            // A jump changes the energy and the momenta: the work column carries its energy.
            traj.energy_conserved = false;
            traj.momentum_conserved = [false; N];
        }
        Driver {
            sys,
            records_work: !flags.energy_conserved,
            method,
            events,
            observer,
            keep: o.keep_samples,
            max_samples: o.max_samples,
            max_samples_default: o.max_samples_default,
            dense: o.dense_budget.map(|b| (Kind::of(method), b)),
            traj,
            work: Work::default(),
            gauss: Vec::new(),
            jump_work: 0.0,
            reset_hits: vec![(0, Vec::new()); events.len()],
            pending: None,
            stats: Stats::default(),
            manifold,
            project_steps: manifold.is_some() && method.spec().projects,
        }
    }

    /// Whether the run reads the method's interpolant between nodes (samples off the nodes,
    /// events, the work integral, the dense output kept): a lane run then keeps each member's
    /// stages.
    pub(super) fn needs_interpolant(&self, o: &RunOptions) -> bool {
        self.records_work
            || !self.events.is_empty()
            || o.sampling.inside(o.t0, o.until)
            || self.dense.is_some()
    }

    /// Starts the dense output at (t0, y0) if the run keeps it (and it has not started).
    fn start_dense(&mut self, t0: f64, y0: Y<N>) {
        if let Some((kind, budget)) = self.dense {
            self.traj.start_dense(|| Dense::new(kind, t0, y0, budget));
        }
    }

    /// The statistics so far (the lanes engine counts a member's work here).
    pub(super) fn stats(&mut self) -> &mut Stats {
        &mut self.stats
    }

    /// Records the state at t: the observer sees it, the trajectory stores it (bounded by
    /// `max_samples` when every sample is kept).
    fn push(&mut self, t: f64, y: &Y<N>, work: f64) -> Result<(), Fault> {
        if self.traj.t.last() == Some(&t) {
            return Ok(());
        }
        // A constrained run records states on the constraints (an interpolated sample between
        // two projected nodes is projected too), with the multipliers there.
        let mut y = *y;
        let constraint = match self.manifold {
            Some(m) => {
                m.project(t, &mut y)?;
                Some((m.multipliers(t, &y)?, m.residual(t, &y)))
            }
            None => None,
        };
        let y = &y;
        let (energy, momenta) = self.sys.energy_and_momenta(&y[0], &y[1], t);
        let sample = Sample {
            t,
            q: y[0],
            qdot: y[1],
            energy,
            momenta,
            work: work + self.jump_work,
        };
        if let Some(f) = self.observer.as_mut() {
            f(&sample);
        }
        self.traj
            .record(&sample, constraint, self.keep, self.max_samples)
    }

    /// ∫ power dt over [a, b] within the last step, on the method's interpolant (Gauss–Legendre,
    /// [`Stepper::gauss_points`] points: the quadrature error is below the interpolant's, so W
    /// carries the integrator's accuracy).
    fn power_integral(&mut self, s: &mut dyn Stepper<N>, a: f64, b: f64) -> Result<f64, Fault> {
        let h = b - a;
        let mut sum = 0.0;
        let m = s.gauss_points();
        if m == 4 {
            for (x, w) in GAUSS4 {
                let t = a + x * h;
                let y = s.interp(t, &mut self.stats)?;
                sum += w * self.sys.power(&y[0], &y[1], t);
            }
        } else {
            if self.gauss.len() != m {
                self.gauss = gauss_legendre(m);
            }
            for &(x, w) in &self.gauss {
                let t = a + x * h;
                let y = s.interp(t, &mut self.stats)?;
                sum += w * self.sys.power(&y[0], &y[1], t);
            }
        }
        let dw = h * sum;
        if dw.is_finite() {
            Ok(dw)
        } else {
            Err(Fault::NonFinite)
        }
    }

    /// W at t in [t_a, t_b] of the last step (W at the node itself is known already).
    fn work_at(&mut self, s: &mut dyn Stepper<N>, t: f64) -> Result<f64, Fault> {
        if !self.records_work {
            return Ok(0.0);
        }
        if t == s.t() {
            return Ok(self.work.at_node);
        }
        let t_a = s.t_prev();
        Ok(self.work.at_prev + self.power_integral(s, t_a, t)?)
    }

    /// Turns a stepper fault into the error, with the trajectory so far ending at (t, y).
    pub(super) fn fail(mut self, fault: Fault, t: f64, y: Y<N>) -> SimulationError {
        let fault = match fault {
            Fault::Dynamics(e) => Fault::Dynamics(self.sys.blame(e)),
            other => other,
        };
        if y.iter().flatten().all(|x| x.is_finite()) {
            // A run that fails before its first step has its dense output start here.
            self.start_dense(t, y);
            let w = self.work.at_node;
            // Past max_samples (or where the constraints fail there) the partial trajectory ends
            // at its last stored sample.
            let _ = self.push(t, &y, w);
        }
        self.traj.stats = self.stats;
        let (self_k, self_default) = (self.traj.constraint_count, self.max_samples_default);
        let (q, qdot) = (y[0].to_vec(), y[1].to_vec());
        // A fast mode explains a run out of steps (diagnosed where it stopped) or one blown up
        // (diagnosed at its first state: where it stopped the state may be 1e300).
        let first = match (
            self.traj.t.first(),
            self.traj.q.first(),
            self.traj.qdot.first(),
        ) {
            (Some(&t0), Some(q0), Some(v0)) => Some((t0, [*q0, *v0])),
            _ => None,
        };
        let stiffness = first.and_then(|(t0, y0)| {
            let (at, state, blew_up) = match fault {
                Fault::MaxSteps(_) => (t, y, false),
                Fault::NonFinite | Fault::Dynamics(_) => (t0, y0, true),
                _ => return None,
            };
            let constrained = self.manifold.is_some();
            let steps = self.stats.steps;
            super::stiffness::diagnose(
                self.sys,
                self.method,
                constrained,
                t0,
                at,
                &state,
                steps,
                blew_up,
            )
        });
        let partial = PartialTrajectory::new(self.traj).with_stiffness(stiffness);
        match fault {
            Fault::Dynamics(source) => SimulationError::Dynamics {
                source: Box::new(source),
                t,
                q,
                qdot,
                partial,
            },
            Fault::Underflow { h } => SimulationError::StepSizeUnderflow {
                t,
                q,
                qdot,
                h,
                partial,
            },
            Fault::MaxSteps(max_steps) => SimulationError::MaxSteps {
                t,
                q,
                qdot,
                max_steps,
                partial,
            },
            Fault::MaxSamples(max_samples) => SimulationError::MaxSamples {
                sample_bytes: super::trajectory::sample_bytes(N, self_k),
                default_limit: self_default,
                t,
                q,
                qdot,
                max_samples,
                partial,
            },
            Fault::NonFinite => SimulationError::NonFinite {
                t,
                q,
                qdot,
                partial,
            },
            Fault::Newton {
                iterations,
                residual,
                reason,
            } => SimulationError::NewtonFailed {
                t,
                q,
                qdot,
                iterations,
                residual,
                reason,
                partial,
            },
        }
    }

    /// Runs from (t0, y0) on the stepper `make` builds, built again from the state after each
    /// jump of a resetting event.
    pub(super) fn run<S: Stepper<N> + 's>(
        self,
        o: &RunOptions,
        t0: f64,
        y0: Y<N>,
        mut make: impl FnMut(f64, Y<N>, &mut Stats) -> Result<S, Fault>,
    ) -> Result<Trajectory<N>, SimulationError> {
        self.run_boxed(o, t0, y0, &mut |t, y, stats| {
            make(t, y, stats).map(|s| Box::new(s) as Box<dyn Stepper<N> + 's>)
        })
    }

    /// [`Driver::run`] on a boxed stepper: the loop is compiled once per N, not per system and
    /// method (one indirect call per step).
    pub(super) fn run_boxed(
        mut self,
        o: &RunOptions,
        t0: f64,
        y0: Y<N>,
        make: &mut Make<'_, 's, N>,
    ) -> Result<Trajectory<N>, SimulationError> {
        let mut s = match make(t0, y0, &mut self.stats) {
            Ok(s) => s,
            Err(f) => return Err(self.fail(f, t0, y0)),
        };
        let r = self.drive(&mut s, o, make);
        self.conclude(r, &*s)
    }

    fn drive(
        &mut self,
        s: &mut Box<dyn Stepper<N> + 's>,
        o: &RunOptions,
        make: &mut Make<'_, 's, N>,
    ) -> Result<(), Fault> {
        let mut p = self.begin(&mut **s, o)?;
        // After a jump, an adaptive method's steps are capped, from a small first step growing
        // 8× a step: the event that fired sits at g = 0, and a first step long enough to go up
        // and come back down past it (a polynomial motion, whose error estimate is nil) would
        // cross it unseen.
        let mut cap: Option<f64> = None;
        while s.t() < o.until {
            self.check_budget(o)?;
            // A capped step that would end within 1 % of the run's end is stretched to it, as
            // the steppers stretch their own last step: it must not leave a sliver below the
            // time resolution.
            let t_end = cap.map_or(o.until, |h| {
                if s.t() + 1.01 * h >= o.until {
                    o.until
                } else {
                    s.t() + h
                }
            });
            s.advance(t_end, &mut self.stats)?;
            cap = cap.map(|h| 8.0 * h).filter(|&h| s.t() + h < o.until);
            if self.after_step(&mut **s, o, &mut p)? {
                let Some((t, y)) = self.pending.take() else {
                    return Ok(());
                };
                *s = make(t, y, &mut self.stats)?;
                cap = self.restart(&mut p, t, &y);
            }
        }
        self.finish(&mut **s)
    }

    /// After a jump to (t, y): the events' values start afresh from the state after it (the
    /// event that fired, where the jump left it on its zero, exactly 0: neither direction's
    /// crossing starts there), and the cap on the next step. Apart from `drive`, to keep its loop short.
    fn restart(&mut self, p: &mut Progress, t: f64, y: &Y<N>) -> Option<f64> {
        for (g, e) in p.g_old.iter_mut().zip(self.events) {
            *g = e.value(t, &y[0], &y[1]);
        }
        // The event that fired: where the jump left it on its zero (an impact keeps the gap,
        // up to the round-off of the located root; a contact's function changes meaning at its
        // transition), exactly 0, so that neither direction's crossing starts there; where a
        // reset moved it (a reset to x = 1e-6, or 1e-12, still moving in), its value after the
        // jump, so that its next crossing is seen.
        if let Some(&(_, i, _)) = p.hits.iter().find(|h| h.0 == t) {
            let ev = &self.events[i];
            let before = self
                .traj
                .jumps
                .last()
                .filter(|j| j.t == t)
                .map(|j| ev.value(t, &j.before.0, &j.before.1));
            // Moved: the reset changed the event's value (beyond its round-off); a reset that
            // leaves the state where it crossed (a bounce reverses the velocity only) keeps the
            // located root, whose residual is the location's error, not a new start. A reset to
            // 1e-12 in front of a wall, about the root's own residual, is a move (it was taken for
            // one within 16 residuals, and its next crossing was missed: through the wall).
            let moved_off = match before {
                Some(b) if !ev.is_contact() => {
                    let a = p.g_old[i];
                    (a - b).abs() > 8.0 * f64::EPSILON * a.abs().max(b.abs())
                }
                _ => false,
            };
            if !moved_off {
                p.g_old[i] = 0.0;
            }
        }
        self.first_step_after_jump(t, y)
    }

    /// The cap on the first step after a jump to (t, y): a hundredth of the time the state
    /// takes to change by its own size, ‖y‖∞/‖ẏ‖∞, or the velocities by theirs, ‖q̇‖∞/‖q̈‖∞,
    /// whichever is shorter (none for the fixed-step methods, whose grid
    /// restarts at the jump, or where it is not finite).
    fn first_step_after_jump(&self, t: f64, y: &Y<N>) -> Option<f64> {
        if self.method.is_fixed_step() {
            return None;
        }
        let a = self.sys.accelerations(&y[0], &y[1], t).ok()?;
        let norm = |xs: &mut dyn Iterator<Item = &f64>| xs.fold(0.0_f64, |m, x| m.max(x.abs()));
        let size = norm(&mut y.iter().flatten()).max(1e-6);
        let rate = norm(&mut y[1].iter().chain(a.iter()));
        // And a hundredth of the time the velocities take to change by their own size: a small,
        // fast excursion (a rocking body's last rocks: a tenth of a millisecond up and back down
        // to the next impact) must not fit inside the first step unseen.
        let (speed, accel) = (norm(&mut y[1].iter()), norm(&mut a.iter()));
        let turn = if speed > 0.0 && accel > 0.0 {
            speed / accel
        } else {
            f64::INFINITY
        };
        let h = 0.01 * (size / rate).min(turn);
        (h.is_finite() && h > 0.0).then_some(h)
    }

    /// The step budget, checked before every step.
    pub(super) fn check_budget(&self, o: &RunOptions) -> Result<(), Fault> {
        if self.stats.steps + self.stats.rejected >= o.max_steps {
            return Err(Fault::MaxSteps(o.max_steps));
        }
        Ok(())
    }

    /// Records the initial state and the events' first values.
    pub(super) fn begin(
        &mut self,
        s: &mut dyn Stepper<N>,
        o: &RunOptions,
    ) -> Result<Progress, Fault> {
        let y0 = s.node(&mut self.stats)?;
        self.start_dense(o.t0, y0);
        self.push(o.t0, &y0, 0.0)?;
        s.recorded(o.t0, o.t0, &mut self.stats)?;
        let g_old: Vec<f64> = self
            .events
            .iter()
            .map(|e| e.value(o.t0, &y0[0], &y0[1]))
            .collect();
        // A step needs nothing here but the samples (no projection, no work, no events, not
        // every step recorded, no dense output kept): `after_step` then looks at the next
        // sample time alone.
        let projects = self.project_steps && self.manifold.is_some();
        let quiet = !(projects
            || self.records_work
            || !self.events.is_empty()
            || matches!(o.sampling, Sampling::Steps)
            || self.dense.is_some());
        Ok(Progress {
            g_new: g_old.clone(),
            g_old,
            hits: Vec::new(),
            next_sample: 0,
            quiet,
            next_time: o.sampling.time(0, o.t0, o.until).unwrap_or(f64::INFINITY),
            snap: o.sampling.snap(),
        })
    }

    /// The end time, if the sample grid did not land on it.
    pub(super) fn finish(&mut self, s: &mut dyn Stepper<N>) -> Result<(), Fault> {
        let y = s.node(&mut self.stats)?;
        let w = self.work.at_node;
        self.push(s.t(), &y, w)?;
        s.recorded(s.t(), s.t(), &mut self.stats)
    }

    /// What follows an accepted step of `s`: the projection of a constrained run, the work, the
    /// events located in the step, the samples in it. True when a terminal event ended the run.
    pub(super) fn after_step(
        &mut self,
        s: &mut dyn Stepper<N>,
        o: &RunOptions,
        p: &mut Progress,
    ) -> Result<bool, Fault> {
        // No sample in this step (the test of the sample loop below, with the next sample time
        // kept from the last step): nothing to do.
        if p.quiet && p.next_time > s.t() + p.snap {
            return Ok(false);
        }
        let Progress {
            g_old,
            g_new,
            hits,
            next_sample,
            next_time,
            ..
        } = p;
        let (t_a, t_b) = (s.t_prev(), s.t());
        if self.project_steps
            && let Some(m) = self.manifold
        {
            let mut y = s.last_state();
            let moved = m.project(t_b, &mut y)?;
            self.traj.note_projection(moved);
            s.set_node(y, &mut self.stats)?;
        }
        // The step's interpolant, on the settled node.
        if let Some(d) = self.traj.dense_mut() {
            d.keep(s, &mut self.stats)?;
        }
        if self.records_work {
            self.work.at_prev = self.work.at_node;
            self.work.at_node = f64::NAN;
            let dw = self.power_integral(s, t_a, t_b)?;
            self.work.at_node = self.work.at_prev + dw;
        }
        // Events: sign changes of g over the step, located on the interpolant. g is read at
        // three interior points too, so a g that turns around inside one step (a ball up and
        // back down within one long polynomial step) is found.
        self.locate_events(s, (t_a, t_b), g_old, g_new, hits)?;
        // The run stops at its first terminal hit; the stepper stops at the first jump.
        let stopping = hits
            .iter()
            .position(|h| self.events[h.1].is_terminal() || self.events[h.1].is_reset())
            .map(|k| (hits[k].0, hits[k].1));
        let stop = stopping.map(|(t, _)| t);
        let t_stop = stop.unwrap_or(t_b);
        // Samples in (t_a, t_stop], then the events up to t_stop.
        self.record_samples(s, o, t_b, stop, (next_sample, next_time))?;
        for &(tz, i, dir) in hits.iter() {
            if tz > t_stop {
                break;
            }
            let y = s.interp(tz, &mut self.stats)?;
            self.traj.events.push(EventHit {
                name: self.events[i].name().to_string(),
                t: tz,
                q: y[0],
                qdot: y[1],
                direction: dir,
            });
            s.event_located(tz, i, &mut self.stats)?;
        }
        if let Some((tz, i)) = stopping {
            let y = s.interp(tz, &mut self.stats)?;
            if let Some(d) = self.traj.dense_mut() {
                d.stop_at(tz, y);
            }
            let w = self.work_at(s, tz)?;
            self.push(tz, &y, w)?;
            s.recorded(tz, tz, &mut self.stats)?;
            let ev = &self.events[i];
            match ev.try_reset(tz, &y[0], &y[1]) {
                Some(after) if !ev.is_terminal() => self.jump(i, tz, y, after?, w)?,
                _ => self.traj.terminated_by = Some(ev.name().to_string()),
            }
            return Ok(true);
        }
        Ok(false)
    }

    /// The events' sign changes over the step (t_a, t_b] of `s`, located on its interpolant into
    /// `hits` in time order; g is read at three interior points too, so a g that turns around
    /// inside one step (a ball up and back down within one long polynomial step) is found.
    /// `g_old` holds g at t_a on entry and at t_b on return.
    #[inline]
    fn locate_events(
        &mut self,
        s: &mut dyn Stepper<N>,
        (t_a, t_b): (f64, f64),
        g_old: &mut [f64],
        g_new: &mut [f64],
        hits: &mut Vec<(f64, usize, Direction)>,
    ) -> Result<(), Fault> {
        hits.clear();
        if self.events.is_empty() {
            return Ok(());
        }
        let yb = s.node(&mut self.stats)?;
        let h = t_b - t_a;
        let mut inner = [(0.0, [[0.0; N]; 2]); 3];
        for (k, slot) in inner.iter_mut().enumerate() {
            let t = t_a + h * (k + 1) as f64 / 4.0;
            *slot = (t, s.interp(t, &mut self.stats)?);
        }
        for (i, ev) in self.events.iter().enumerate() {
            g_new[i] = ev.value(t_b, &yb[0], &yb[1]);
            if g_new[i].is_nan() && !ev.is_contact() {
                return Err(Fault::Dynamics(DynamicsError::NonFinite {
                    t: t_b,
                    q: yb[0].to_vec(),
                    qdot: yb[1].to_vec(),
                    message: format!(
                        "the function of event \"{}\" is NaN at this state, so its zero \
                         crossings cannot be found (it would never fire): check its formula \
                         where it divides or takes roots, or end the run before it leaves \
                         its domain with a terminal event",
                        ev.name()
                    ),
                }));
            }
            let mut prev = (t_a, g_old[i]);
            for k in 0..4 {
                let next = match inner.get(k) {
                    Some((t, y)) => (*t, ev.value(*t, &y[0], &y[1])),
                    None => (t_b, g_new[i]),
                };
                if let Some(dir) = ev.crosses(prev.1, next.1) {
                    // Right after a jump the next crossing can be closer than the location's
                    // tolerance (a reset to 3e-13 in front of a wall, still moving in: the
                    // root was taken at the jump's own instant, where the reset then changed
                    // nothing, and the next crossings were missed: through the wall); in the
                    // step that starts at a jump the crossings are located to round-off.
                    let after_jump = self.traj.jumps.last().is_some_and(|j| j.t == t_a);
                    let tol = if after_jump { 0.0 } else { location_tol(t_b) };
                    let stats = &mut self.stats;
                    let tz = brent(
                        &mut |t| {
                            let y = s.interp(t, stats)?;
                            Ok::<f64, Fault>(ev.value(t, &y[0], &y[1]))
                        },
                        prev.0,
                        next.0,
                        prev.1,
                        next.1,
                        tol,
                    )?;
                    hits.push((tz, i, dir));
                }
                prev = next;
            }
        }
        g_old.copy_from_slice(g_new);
        hits.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(())
    }

    /// Records the samples of the step ending at t_b up to the run's terminal time `stop` (if
    /// a terminal or resetting event stops it in this step): the grid's times (advancing
    /// `next_sample`, and `next_time` to the next grid time past the step), or the node.
    #[inline]
    fn record_samples(
        &mut self,
        s: &mut dyn Stepper<N>,
        o: &RunOptions,
        t_b: f64,
        stop: Option<f64>,
        (next_sample, next_time): (&mut usize, &mut f64),
    ) -> Result<(), Fault> {
        let t_stop = stop.unwrap_or(t_b);
        match o.sampling {
            Sampling::Every(_) | Sampling::At { .. } => {
                // A time within `snap` past this node is this node (grid rounding), unless a
                // terminal event ends the run here.
                let snap = o.sampling.snap();
                let limit = if stop.is_some() { t_stop } else { t_b + snap };
                loop {
                    let Some(ts) = o.sampling.time(*next_sample, o.t0, o.until) else {
                        *next_time = f64::INFINITY;
                        break;
                    };
                    if ts > limit {
                        *next_time = ts;
                        break;
                    }
                    let (y, w, at) = if (t_b - ts).abs() <= snap {
                        (s.node(&mut self.stats)?, self.work.at_node, t_b)
                    } else {
                        (s.interp(ts, &mut self.stats)?, self.work_at(s, ts)?, ts)
                    };
                    self.push(ts, &y, w)?;
                    s.recorded(ts, at, &mut self.stats)?;
                    *next_sample += 1;
                }
            }
            Sampling::Steps => {
                if stop.is_none() {
                    let y = s.node(&mut self.stats)?;
                    let w = self.work.at_node;
                    self.push(t_b, &y, w)?;
                    s.recorded(t_b, t_b, &mut self.stats)?;
                }
            }
        }
        Ok(())
    }

    /// The jump of resetting event `i` at tz from `before` to `after`, W(tz) being `w`: recorded,
    /// its energy into the work column, and the method restarted from `after` — unless the
    /// event's hits accumulate (Zeno), which ends the run here, before the jump, or, for an
    /// event with a resting state (a contact), jumps to that state instead.
    fn jump(
        &mut self,
        i: usize,
        tz: f64,
        before: Y<N>,
        mut after: Y<N>,
        w: f64,
    ) -> Result<(), Fault> {
        let name = self.events[i].name().to_string();
        let (count, hits) = &mut self.reset_hits[i];
        *count += 1;
        if hits.len() > ZENO_INTERVALS {
            hits.remove(0);
        }
        hits.push(tz);
        // The hits accumulate: the run ends at this one, before its jump, or rests from it.
        if let Some((ratio, t_accumulation)) = zeno(hits) {
            let rest = self.events[i].try_rest(tz, &before[0], &before[1]);
            self.traj.zeno = Some(Zeno {
                event: name.clone(),
                ratio,
                t_last: tz,
                t_accumulation,
                hits: *count,
                resting: rest.is_some(),
            });
            match rest {
                Some(r) => {
                    after = r?;
                    hits.clear();
                }
                None => {
                    self.traj.terminated_by = Some(format!("{name} (Zeno)"));
                    return Ok(());
                }
            }
        }
        if after.iter().flatten().any(|x| !x.is_finite()) {
            return Err(Fault::Dynamics(DynamicsError::NonFinite {
                t: tz,
                q: before[0].to_vec(),
                qdot: before[1].to_vec(),
                message: format!(
                    "the reset map of event \"{name}\" returned a state that is not finite \
                     (q⁺ = {:?}, q̇⁺ = {:?}) from this state: check the reset's formula where \
                     it divides or takes roots",
                    after[0], after[1]
                ),
            }));
        }
        let e0 = self.sys.energy(&before[0], &before[1], tz);
        let e1 = self.sys.energy(&after[0], &after[1], tz);
        self.traj.jumps.push(Jump {
            event: name,
            t: tz,
            before: (before[0], before[1]),
            after: (after[0], after[1]),
            energy_change: e1 - e0,
        });
        self.jump_work += e1 - e0;
        self.work.at_node = w;
        self.pending = Some((tz, after));
        Ok(())
    }

    /// The run's outcome: its trajectory, or the error with the trajectory up to the stepper's
    /// last accepted node.
    pub(super) fn conclude(
        mut self,
        r: Result<(), Fault>,
        s: &dyn Stepper<N>,
    ) -> Result<Trajectory<N>, SimulationError> {
        match r {
            Ok(()) => {
                self.traj.stats = self.stats;
                Ok(self.traj)
            }
            Err(f) => {
                // Report the last accepted node (its velocity from the stepper's own state); for
                // the sample limit the last stored sample, as `MaxSamples` documents (the node
                // can be a step past it, beyond a crossing not yet applied: a state the run
                // never reaches).
                let last = (
                    self.traj.t.last(),
                    self.traj.q.last(),
                    self.traj.qdot.last(),
                );
                let (t, y) = match (&f, last) {
                    (Fault::MaxSamples(_), (Some(&t), Some(q), Some(v))) => (t, [*q, *v]),
                    _ => (s.t(), s.last_state()),
                };
                Err(self.fail(f, t, y))
            }
        }
    }
}

/// A run's place between steps: the events' last values and the next sample.
pub(super) struct Progress {
    g_old: Vec<f64>,
    g_new: Vec<f64>,
    hits: Vec<(f64, usize, Direction)>,
    next_sample: usize,
    /// Whether a step needs nothing but its samples (see [`Driver::begin`]).
    quiet: bool,
    /// The time of sample `next_sample` (∞ past the last one).
    next_time: f64,
    /// The sampling's snap (how close to a node a sample is taken at the node), kept for the
    /// test of every step.
    snap: f64,
}

#[cfg(test)]
mod tests {
    /// The computed rules: 4 points equal the tabulated ones; 10 integrate t¹⁹ on [0, 1] (1/20)
    /// and their weights sum to 1.
    #[test]
    fn gauss_legendre_rules() {
        let g4 = super::gauss_legendre(4);
        for (a, b) in g4.iter().zip(super::GAUSS4) {
            assert!(
                (a.0 - b.0).abs() < 1e-15 && (a.1 - b.1).abs() < 1e-15,
                "{a:?} {b:?}"
            );
        }
        let g10 = super::gauss_legendre(10);
        let sum: f64 = g10.iter().map(|p| p.1).sum();
        let int: f64 = g10.iter().map(|p| p.1 * p.0.powi(19)).sum();
        assert!(
            (sum - 1.0).abs() < 1e-14 && (int - 0.05).abs() < 1e-15,
            "{sum} {int}"
        );
    }

    use super::Sampling;

    #[test]
    fn only_samples_strictly_inside_the_run_need_the_interpolant() {
        let (t0, until) = (1.0, 11.0);
        assert!(!Sampling::Steps.inside(t0, until));
        // A grid whose first time is the end (or past it, or within 1e-9 Δ of it).
        assert!(!Sampling::Every(10.0).inside(t0, until));
        assert!(!Sampling::Every(20.0).inside(t0, until));
        assert!(!Sampling::Every(10.0 - 1e-12).inside(t0, until));
        assert!(Sampling::Every(5.0).inside(t0, until));
        let at = |times: &'static [f64]| Sampling::At { times, snap: 1e-9 };
        assert!(!at(&[1.0, 11.0]).inside(t0, until));
        assert!(!at(&[0.5, 11.0 - 1e-10]).inside(t0, until));
        assert!(at(&[1.0, 6.0, 11.0]).inside(t0, until));
    }
}
