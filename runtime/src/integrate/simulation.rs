//! [`Simulation`]: the builder of a run (system, initial state, method, sampling, events, limits)
//! and [`Simulation::run`], which checks the options (see `validate`) and hands the run to the
//! driver.

use crate::constraints::{Constrained, Holonomic};
use crate::contact::Unilateral;
use crate::lagrangian::{Declared, Lagrangian};

use super::driver::{self, RunOptions, Sampling};
use super::error::SimulationError;
use super::events::{Event, Jump};
use super::manifold::Manifold;
use super::method::Method;
use super::system::System;
use super::trajectory::{Sample, Trajectory};

/// The set-up of a contacts run at its start (see `Options::contact_start`).
pub(super) type ContactStart<'a, const N: usize> = Box<
    dyn Fn(
            &[f64; N],
            &[f64; N],
            f64,
            bool,
            Option<&[bool]>,
        ) -> Result<(super::state::Y<N>, Option<Jump<N>>), SimulationError>
        + 'a,
>;

/// The observer of [`Simulation::observe`]: called with every recorded sample.
type Observer<'a, const N: usize> = Box<dyn FnMut(&Sample<N>) + 'a>;

/// A simulation run of a [`Lagrangian`] system from (q0, q̇0): configure with the builder methods,
/// then [`run`](Simulation::run).
///
/// Samples: with [`sample_every`](Simulation::sample_every)(Δ) the trajectory holds t0 + kΔ for
/// every k with t0 + kΔ ≤ `until` (from the dense output for the adaptive methods; fixed-step
/// methods need Δ to be a multiple of dt and record the steps that land on the grid), plus
/// `until` itself if it is not on the grid. With [`sample_at`](Simulation::sample_at)(times) it holds
/// t0, exactly the given times and `until` (SciPy's `t_eval`, with both ends kept). Without either,
/// every step is recorded. A terminal event ends the trajectory with a sample at the event.
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
/// struct Osc;
/// impl Lagrangian<1> for Osc {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
/// }
/// let tr = Simulation::new(&Osc, [0.0], [1.0])
///     .method(Method::DormandPrince { rtol: 1e-9, atol: 1e-12 })
///     .start_time(1.0)
///     .until(2.0)
///     .sample_every(0.25)
///     .run()
///     .unwrap();
/// assert_eq!(tr.t, vec![1.0, 1.25, 1.5, 1.75, 2.0]);
/// assert!((tr.q[4][0] - 1.0_f64.sin()).abs() < 1e-8);
/// ```
pub struct Simulation<'a, L, const N: usize> {
    pub(super) sys: Sys<'a, L>,
    /// Everything else: the options, checked and prepared once per N (not per system).
    pub(super) o: Options<'a, N>,
}

/// A run's options: what [`Simulation`] holds besides the system. Its checks and its
/// preparation are compiled once per N, whatever the system.
pub(super) struct Options<'a, const N: usize> {
    /// The constraints of a run made by [`Simulation::constrained`].
    pub(super) manifold: Option<Box<dyn Manifold<N> + 'a>>,
    /// Whether a constrained run starts from the projection of (q0, q̇0) onto the constraints.
    pub(super) project_initial: bool,
    pub(super) q0: [f64; N],
    pub(super) qdot0: [f64; N],
    pub(super) t0: f64,
    pub(super) until: Option<f64>,
    pub(super) method: Method,
    pub(super) sample_every: Option<f64>,
    pub(super) sample_at: Option<Vec<f64>>,
    pub(super) events: Vec<Event<'a, N>>,
    pub(super) max_steps: usize,
    pub(super) max_step: Option<f64>,
    /// `None`: the default, a memory budget ([`Simulation::max_samples`]).
    pub(super) max_samples: Option<usize>,
    pub(super) observer: Option<Observer<'a, N>>,
    pub(super) keep_samples: bool,
    /// Whether the trajectory keeps the dense output ([`Simulation::keep_dense_output`]).
    pub(super) keep_dense: bool,
    /// A run of [`Simulation::contacts`]: sets its contacts up at the run's start (t0, q0, q̇0)
    /// and gives the state the run starts from (on the touching contacts, after an impact at t0
    /// where one touches and approaches) with that impact's jump, or says why the initial state
    /// is refused.
    pub(super) contact_start: Option<ContactStart<'a, N>>,
    /// The contacts a contacts run starts closed whatever their gap (the state put on them):
    /// a shooting's iterates, which Newton moves off the contacts closed at its guess.
    pub(super) closed_at_start: Option<Vec<bool>>,
}

impl<'a, L: Lagrangian<N>, const N: usize> Simulation<'a, L, N> {
    /// A run of `system` from q0, q̇0 at t0 = 0 with DOP853 (rtol 1e-10, atol 1e-12); set the end
    /// time with [`until`](Simulation::until).
    ///
    /// ```
    /// use lagrange::prelude::*;
    ///
    /// /// A free particle of mass m.
    /// pub struct Free { pub m: f64 }
    ///
    /// #[lagrangian]
    /// impl Free {
    ///     fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
    ///         0.5 * self.m * x_dot * x_dot
    ///     }
    /// }
    ///
    /// let tr = Simulation::new(&Free { m: 2.0 }, [1.0], [2.0]).until(1.0).run().unwrap();
    /// assert!((tr.q.last().unwrap()[0] - 3.0).abs() < 1e-12);
    /// ```
    pub fn new(system: &'a L, q0: [f64; N], qdot0: [f64; N]) -> Self {
        Self::with(Sys::Borrowed(system), q0, qdot0)
    }

    /// The builder's defaults around a system held either way.
    pub(super) fn with(sys: Sys<'a, L>, q0: [f64; N], qdot0: [f64; N]) -> Self {
        Simulation {
            sys,
            o: Options {
                manifold: None,
                project_initial: false,
                q0,
                qdot0,
                t0: 0.0,
                until: None,
                method: Method::Dop853 {
                    rtol: 1e-10,
                    atol: 1e-12,
                },
                sample_every: None,
                sample_at: None,
                events: Vec::new(),
                max_steps: 10_000_000,
                max_samples: None,
                observer: None,
                keep_samples: true,
                keep_dense: false,
                max_step: None,
                contact_start: None,
                closed_at_start: None,
            },
        }
    }

    /// The initial state (q0, q̇0) as given.
    pub(crate) fn initial(&self) -> ([f64; N], [f64; N]) {
        (self.o.q0, self.o.qdot0)
    }

    /// Starts a contacts run with the contacts of `closed` closed whatever their gap, the state
    /// put on them (a shooting's iterates, off the contacts closed at its guess by a Newton
    /// step).
    pub(crate) fn closed_at_start(mut self, closed: Vec<bool>) -> Self {
        self.o.closed_at_start = Some(closed);
        self
    }

    /// Start from the projection of (q0, q̇0) onto the constraints (the nearest q with
    /// g(q, t0) = 0, then the nearest q̇ with G q̇ + ∂g/∂t = 0) instead of rejecting an initial
    /// state that is off them (a system without constraints starts from (q0, q̇0) as given).
    ///
    /// ```
    /// # use lagrange_runtime::{Holonomic, Lagrangian, Scalar, Simulation, SimulationError};
    /// # struct Pendulum;
    /// # impl Lagrangian<2> for Pendulum {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
    /// #         (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
    /// #     }
    /// # }
    /// # impl Holonomic<2, 1> for Pendulum {
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
    /// #         [q[0] * q[0] + q[1] * q[1] - 1.0]
    /// #     }
    /// # }
    /// let off = || Simulation::constrained(&Pendulum, [1.1, 0.0], [0.2, 0.3]).until(1.0);
    /// let err = off().run().unwrap_err();
    /// assert!(matches!(err, SimulationError::OffConstraints { .. }));
    /// let tr = off().project_initial_state().run().unwrap();
    /// assert!((tr.q[0][0] - 1.0).abs() < 1e-15 && tr.qdot[0] == [0.0, 0.3]); // nearest tangent velocity
    /// ```
    pub fn project_initial_state(mut self) -> Self {
        self.o.project_initial = true;
        self
    }

    /// The integration method.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.1 }).until(1.0).run().unwrap();
    /// assert_eq!(tr.stats.steps, 10);
    /// ```
    pub fn method(mut self, method: Method) -> Self {
        self.o.method = method;
        self
    }

    /// The start time t0 (default 0).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).start_time(5.0).until(6.0).run().unwrap();
    /// assert_eq!(tr.t[0], 5.0);
    /// ```
    pub fn start_time(mut self, t0: f64) -> Self {
        self.o.t0 = t0;
        self
    }

    /// The end time (required; must be after the start time).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).until(2.5).run().unwrap();
    /// assert_eq!(*tr.t.last().unwrap(), 2.5);
    /// ```
    pub fn until(mut self, t_end: f64) -> Self {
        self.o.until = Some(t_end);
        self
    }

    /// Record samples every `dt_sample` (see the type's documentation).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).until(1.0).sample_every(0.1).run().unwrap();
    /// assert_eq!(tr.t.len(), 11);
    /// ```
    pub fn sample_every(mut self, dt_sample: f64) -> Self {
        self.o.sample_every = Some(dt_sample);
        self
    }

    /// Record samples at exactly these times, in increasing order within [t0, `until`] (irregular
    /// grids, measurement times, log-spaced times); the trajectory holds t0, these times and
    /// `until`. The adaptive methods evaluate their dense output there; the fixed-step methods
    /// need every time on their step grid t0 + k·dt (as with
    /// [`sample_every`](Simulation::sample_every)). Times out of order or out of range, and
    /// combining this with `sample_every`, are [`SimulationError::InvalidOptions`].
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// # struct Osc;
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// # }
    /// let tr = Simulation::new(&Osc, [0.0], [1.0])
    ///     .until(10.0)
    ///     .sample_at([0.01, 0.1, 1.0, 5.0])
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(tr.t, vec![0.0, 0.01, 0.1, 1.0, 5.0, 10.0]);
    /// assert!((tr.q[4][0] - 5.0_f64.sin()).abs() < 1e-9);
    /// ```
    pub fn sample_at(mut self, times: impl IntoIterator<Item = f64>) -> Self {
        self.o.sample_at = Some(times.into_iter().collect());
        self
    }

    /// Adds an event to locate.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation, Event};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let tr = Simulation::new(&Free, [-1.0], [2.0])
    ///     .until(3.0)
    ///     .event(Event::zero_crossing("x = 0", |_t, q, _v| q[0]))
    ///     .run()
    ///     .unwrap();
    /// assert!((tr.events[0].t - 0.5).abs() < 1e-12);
    /// ```
    pub fn event(mut self, event: Event<'a, N>) -> Self {
        self.o.events.push(event);
        self
    }

    /// The largest number of steps (accepted and rejected) before [`SimulationError::MaxSteps`]
    /// (default 10⁷).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.1 }).until(1.0).max_steps(3).run();
    /// assert!(r.is_err());
    /// ```
    pub fn max_steps(mut self, n: usize) -> Self {
        self.o.max_steps = n;
        self
    }

    /// The largest number of samples the trajectory stores, so memory is bounded in every mode: a
    /// sample grid that asks for more (`sample_every` over a long run, a long `sample_at` list) is
    /// [`SimulationError::InvalidOptions`] before any step; recording every step stops with
    /// [`SimulationError::MaxSamples`] (and the trajectory so far) when it reaches the limit. Each
    /// sample holds t, q, q̇, the energy, the momenta and the work, (3N + 3) · 8 bytes, and for a
    /// constrained run with K constraints λ, 24 + 8K more. The default is a memory budget: as many
    /// samples as fit in 256 MiB (2 796 202 for N = 3, 338 933 for N = 32), which keeps the
    /// trajectory (with a `Vec`'s growth, at most twice that) well within a laptop's memory. For
    /// long runs see also [`observe`](Simulation::observe) and
    /// [`keep_samples`](Simulation::keep_samples).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation, SimulationError};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let sim = || Simulation::new(&Free, [0.0], [1.0]).until(1.0).sample_every(1e-3);
    /// assert_eq!(sim().max_samples(1001).run().unwrap().t.len(), 1001);
    /// let err = sim().max_samples(1000).run().unwrap_err();
    /// assert!(matches!(err, SimulationError::InvalidOptions { .. }));
    /// ```
    pub fn max_samples(mut self, n: usize) -> Self {
        self.o.max_samples = Some(n);
        self
    }

    /// Calls `f` with every sample as it is recorded (the states the trajectory would store: every
    /// step, or the sample grid), in time order: stream a long run to a file, reduce it on the
    /// fly, or watch it. Combine with [`keep_samples(false)`](Simulation::keep_samples) to keep
    /// nothing in memory.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let mut last_x = 0.0;
    /// let mut seen = 0;
    /// let tr = Simulation::new(&Free, [0.0], [1.0])
    ///     .method(Method::Rk4 { dt: 0.001 })
    ///     .until(10.0)
    ///     .observe(|s| { seen += 1; last_x = s.q[0]; })
    ///     .keep_samples(false)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(seen, 10_001);
    /// assert!((last_x - 10.0).abs() < 1e-9);
    /// assert_eq!(tr.t.len(), 2); // the first and the last sample
    /// ```
    pub fn observe(mut self, f: impl FnMut(&Sample<N>) + 'a) -> Self {
        self.o.observer = Some(Box::new(f));
        self
    }

    /// Whether the trajectory stores every sample (default `true`). With `false` it stores the
    /// first and the latest only (the observer of [`observe`](Simulation::observe) still sees
    /// every one), and [`Trajectory::invariants`] still reports the drift over all of them.
    /// [`max_samples`](Simulation::max_samples) does not apply then (two samples are stored
    /// whatever it is).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
    /// # struct Osc;
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// # }
    /// let run = |keep| Simulation::new(&Osc, [1.0], [0.0]).method(Method::Rk4 { dt: 0.1 }).until(50.0).keep_samples(keep).run().unwrap();
    /// let (all, ends) = (run(true), run(false));
    /// assert_eq!((all.t.len(), ends.t.len()), (501, 2));
    /// assert_eq!(all.invariants(), ends.invariants());
    /// ```
    pub fn keep_samples(mut self, keep: bool) -> Self {
        self.o.keep_samples = keep;
        self
    }

    /// Whether the trajectory keeps the method's dense output over the whole run (default
    /// `false`), so that [`Trajectory::at`] gives (q, q̇) at any time of the finished run from
    /// the method's own interpolant, the one its samples and events use.
    ///
    /// Every accepted step keeps what that interpolant needs: DOP853 its 7th-order dense output
    /// (8 rows of (q, q̇), built with 3 more evaluations of the accelerations per step: 16
    /// instead of 13), Dormand–Prince its 4th-order extension (5 rows), RK4 y and ẏ at both
    /// nodes (4 rows, cubic Hermite), the variational method and RATTLE (q, q̇) at both nodes
    /// (2 rows; q cubic Hermite, q̇ linear; q̇ at every node from the inverse Legendre map), the
    /// Taylor method the step's series (p + 1 rows). Samples, events and the other results are
    /// those of the same run without it ([`Stats`](crate::Stats) counts the extra evaluations;
    /// where one of them fails, the run fails there, as for an event located in that step).
    ///
    /// Memory is bounded like the samples': the dense output takes at most as many bytes as
    /// [`max_samples`](Simulation::max_samples) samples would (256 MiB by default; the `Vec`s'
    /// growth may take up to twice that), whether or not the samples are kept. A run that
    /// reaches the bound goes on to its end without keeping more steps; [`Trajectory::at`]
    /// then refuses the times after the last step kept
    /// ([`DenseOutputError::Truncated`](crate::DenseOutputError::Truncated)) and
    /// [`Trajectory::dense_span`] shows how far it serves.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
    /// # struct Osc;
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// # }
    /// let tr = Simulation::new(&Osc, [1.0], [0.0])
    ///     .method(Method::Rk4 { dt: 0.01 })
    ///     .until(1.0)
    ///     .sample_every(0.5)
    ///     .keep_dense_output(true)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(tr.t.len(), 3);
    /// let (q, _) = tr.at(0.123).unwrap();
    /// assert!((q[0] - 0.123_f64.cos()).abs() < 1e-9);
    /// ```
    pub fn keep_dense_output(mut self, keep: bool) -> Self {
        self.o.keep_dense = keep;
        self
    }

    /// The largest step the adaptive methods may take (default: the whole interval). Events
    /// whose g changes sign twice within one step are missed; cap the step to resolve them.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).until(1.0).max_step(0.1).run().unwrap();
    /// assert!(tr.stats.steps >= 10);
    /// ```
    pub fn max_step(mut self, h: f64) -> Self {
        self.o.max_step = Some(h);
        self
    }

    /// Runs the simulation.
    ///
    /// Fails with [`SimulationError::InvalidOptions`] (before any step) for dt ≤ 0, rtol ≤ 0, an
    /// end time not after the start, a non-finite initial state, a sample interval that is not a
    /// multiple of a fixed dt, or a system whose `CYCLIC` declares a coordinate absent from L while
    /// its accelerations change with it; with the other variants (each holding the trajectory so
    /// far) when the run cannot continue.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Simulation, SimulationError, Method};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let err = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: -0.1 }).until(1.0).run().unwrap_err();
    /// assert!(matches!(err, SimulationError::InvalidOptions { .. }));
    /// ```
    pub fn run(self) -> Result<Trajectory<N>, SimulationError> {
        let Simulation { sys, o } = self;
        // The run the system declares: as it is, or with its constraints or its contacts.
        sys.declared(Run(o))
    }

    /// Checks the options and gathers what the driver needs (the lanes engine of an ensemble
    /// takes the same).
    pub(super) fn prepare(&mut self) -> Result<Prepared<'_, 'a, L, N>, SimulationError> {
        let Simulation { sys, o } = self;
        let sys: &L = sys;
        let ready = o.prepare(sys)?;
        Ok(Prepared {
            sys,
            start_jump: ready.start_jump,
            manifold: ready.manifold,
            events: ready.events,
            method: ready.method,
            y0: ready.y0,
            hmax: ready.hmax,
            opts: ready.opts,
            observer: ready.observer,
        })
    }
}

impl<'a, const N: usize> Options<'a, N> {
    /// The bytes one stored sample of this run takes (with its constraints' λ).
    pub(super) fn sample_bytes(&self) -> usize {
        super::trajectory::sample_bytes(N, self.manifold.as_ref().map_or(0, |m| m.count()))
    }

    /// The largest number of samples stored: the user's `max_samples`, else as many as fit in
    /// the memory budget.
    pub(super) fn max_samples_bound(&self) -> usize {
        self.max_samples.unwrap_or_else(|| {
            super::trajectory::default_max_samples(
                N,
                self.manifold.as_ref().map_or(0, |m| m.count()),
            )
        })
    }

    /// The most bytes the dense output may take: as many as `max_samples` samples
    /// ([`Simulation::keep_dense_output`]).
    pub(super) fn dense_budget(&self) -> usize {
        self.max_samples_bound().saturating_mul(self.sample_bytes())
    }

    /// The checked options of a run of `sys`, ready for the driver (compiled once per N).
    fn prepare<'p>(&'p mut self, sys: &dyn System<N>) -> Result<Ready<'p, 'a, N>, SimulationError> {
        let until = self
            .validate(sys)
            .and_then(|until| self.check_cyclic(sys).map(|()| until))
            .map_err(|message| SimulationError::InvalidOptions { message })?;
        let (y0, start_jump) = self.initial_state()?;
        let hmax = self.max_step.unwrap_or(until - self.t0);
        let max_samples = self.max_samples_bound();
        let dense_budget = self.keep_dense.then(|| self.dense_budget());
        let sampling = match (&self.sample_at, self.sample_every) {
            (Some(times), _) => Sampling::At {
                times,
                // A fixed-step method records the node a sample time lands on (the grid test of
                // `validate` allows 1e-9 of a step); the adaptive ones interpolate any other time.
                snap: self.method.spec().fixed_dt.map_or(0.0, |dt| 1e-9 * dt),
            },
            (None, Some(ds)) => Sampling::Every(ds),
            (None, None) => Sampling::Steps,
        };
        let opts = RunOptions {
            t0: self.t0,
            until,
            sampling,
            max_steps: self.max_steps,
            keep_samples: self.keep_samples,
            max_samples,
            max_samples_default: self.max_samples.is_none(),
            dense_budget,
        };
        Ok(Ready {
            start_jump,
            manifold: self.manifold.as_deref(),
            events: &self.events,
            method: self.method,
            y0,
            hmax,
            opts,
            observer: self
                .observer
                .as_mut()
                .map(|f| &mut **f as &mut dyn FnMut(&Sample<N>)),
        })
    }
}

/// The run of a system as it declares itself ([`Lagrangian::declared`]) with these options: a
/// system with constraints or contacts runs as [`Simulation::constrained`] or
/// [`Simulation::contacts`] would run it, with every option of the builder.
struct Run<'a, const N: usize>(Options<'a, N>);

impl<'s, 'a: 's, L: Lagrangian<N> + 's, const N: usize> Declared<'s, L, N> for Run<'a, N> {
    type Output = Result<Trajectory<N>, SimulationError>;

    #[inline(always)]
    fn plain(self, sys: &'s L) -> Self::Output {
        let mut sim = Simulation {
            sys: Sys::Borrowed(sys),
            o: self.0,
        };
        let p = sim.prepare()?;
        run_prepared(p)
    }

    fn constrained<const K: usize>(self, sys: &'s L) -> Self::Output
    where
        L: Holonomic<N, K>,
    {
        let mut sim = Simulation::constrained(sys, self.0.q0, self.0.qdot0);
        sim.o = sim.o.adopt(self.0);
        sim.run()
    }

    fn contacts<const K: usize>(self, sys: &'s L) -> Self::Output
    where
        L: Unilateral<N, K>,
    {
        let mut sim = Simulation::contacts(sys, self.0.q0, self.0.qdot0);
        sim.o = sim.o.adopt(self.0);
        sim.run()
    }
}

impl<'a, const N: usize> Options<'a, N> {
    /// These options of a constrained or contacts run (its constraints, its contact set-up and
    /// events, its initial state) with every option the user gave on the builder (`plain`):
    /// method, times, samples, events (after the contacts' own), observer, limits.
    pub(super) fn adopt(self, plain: Options<'a, N>) -> Options<'a, N> {
        let mut events = self.events;
        events.extend(plain.events);
        Options {
            manifold: self.manifold,
            project_initial: self.project_initial | plain.project_initial,
            q0: self.q0,
            qdot0: self.qdot0,
            contact_start: self.contact_start,
            events,
            ..plain
        }
    }
}

/// The run of a prepared simulation on the scalar driver.
pub(super) fn run_prepared<L: Lagrangian<N>, const N: usize>(
    p: Prepared<'_, '_, L, N>,
) -> Result<Trajectory<N>, SimulationError> {
    let start_jump = p.start_jump;
    let mut tr = driver::run(
        p.sys, p.manifold, p.events, p.method, p.y0, p.hmax, &p.opts, p.observer,
    )?;
    // An impact at t0 (a contact touching and approaching at the start) comes first.
    if let Some(jump) = start_jump {
        tr.jumps.insert(0, jump);
    }
    Ok(tr)
}

/// [`Prepared`] without the system.
struct Ready<'p, 'a, const N: usize> {
    start_jump: Option<Jump<N>>,
    manifold: Option<&'p (dyn Manifold<N> + 'a)>,
    events: &'p [Event<'a, N>],
    method: Method,
    y0: super::state::Y<N>,
    hmax: f64,
    opts: RunOptions<'p>,
    observer: Option<&'p mut dyn FnMut(&Sample<N>)>,
}

pub(super) struct Prepared<'p, 'a, L, const N: usize> {
    pub(super) sys: &'p L,
    /// The jump of an impact at t0 (a contacts run), recorded first.
    pub(super) start_jump: Option<Jump<N>>,
    pub(super) manifold: Option<&'p (dyn Manifold<N> + 'a)>,
    pub(super) events: &'p [Event<'a, N>],
    pub(super) method: Method,
    pub(super) y0: super::state::Y<N>,
    pub(super) hmax: f64,
    pub(super) opts: RunOptions<'p>,
    pub(super) observer: Option<&'p mut dyn FnMut(&Sample<N>)>,
}

/// The system of a run: borrowed from the caller ([`Simulation::new`]) or a view made for the
/// run ([`Simulation::constrained`]).
pub(super) enum Sys<'a, L> {
    Borrowed(&'a L),
    Owned(Box<L>),
}

impl<L> core::ops::Deref for Sys<'_, L> {
    type Target = L;
    fn deref(&self) -> &L {
        match self {
            Sys::Borrowed(s) => s,
            Sys::Owned(s) => s,
        }
    }
}

impl<const N: usize> Options<'_, N> {
    /// y0 = (q0, q̇0), on the constraints of a constrained run: checked, or projected there when
    /// asked.
    fn initial_state(&self) -> Result<([[f64; N]; 2], Option<Jump<N>>), SimulationError> {
        if let Some(start) = &self.contact_start {
            return start(
                &self.q0,
                &self.qdot0,
                self.t0,
                self.project_initial,
                self.closed_at_start.as_deref(),
            );
        }
        let mut y0 = [self.q0, self.qdot0];
        let Some(m) = self.manifold.as_deref() else {
            return Ok((y0, None));
        };
        start_on(m, self.t0, &mut y0, self.project_initial)?;
        Ok((y0, None))
    }
}

/// Puts an initial state `y0` on the constraints of `m` at t0 where `project`
/// ([`Simulation::project_initial_state`]), else checks that it is on them: each residual
/// against its own scale, an [`OffConstraints`](SimulationError::OffConstraints) error beyond
/// 1e-10 of it.
pub(super) fn start_on<const N: usize>(
    m: &dyn Manifold<N>,
    t0: f64,
    y0: &mut super::state::Y<N>,
    project: bool,
) -> Result<(), SimulationError> {
    let (q0, qdot0) = (y0[0], y0[1]);
    if project {
        m.project(t0, y0)
            .map_err(|f| SimulationError::InvalidOptions {
                message: format!(
                    "projecting the initial state onto the constraints failed at t = {t0}, \
                 q0 = {q0:?}, q̇0 = {qdot0:?} ({f:?}): start nearer to the constraints"
                ),
            })?;
        return Ok(());
    }
    // Each residual against its own scale: |g_j| against Σ_i |∂g_j/∂q_i · q_i| (the size
    // of the terms that cancel in g_j), |ġ_j| against Σ_i |∂g_j/∂q_i · q̇_i| + |∂g_j/∂t|.
    let rows = m.rows(&y0[0], &y0[1], t0);
    let still = m.rows(&y0[0], &[0.0; N], t0);
    let mut worst = (0, 0.0_f64);
    let (mut pos, mut vel) = (0.0_f64, 0.0_f64);
    for j in 0..m.count() {
        let gq = &rows.jacobian[j];
        let sp: f64 = (0..N).map(|i| (gq[i] * y0[0][i]).abs()).sum();
        let sv: f64 = (0..N).map(|i| (gq[i] * y0[1][i]).abs()).sum::<f64>() + still.rate[j].abs();
        let rel = (rows.value[j].abs() / sp.max(f64::MIN_POSITIVE))
            .max(rows.rate[j].abs() / sv.max(f64::MIN_POSITIVE));
        pos = pos.max(rows.value[j].abs());
        vel = vel.max(rows.rate[j].abs());
        if rel > worst.1 {
            worst = (j, rel);
        }
    }
    if worst.1 > INITIAL_TOLERANCE || !pos.is_finite() || !vel.is_finite() {
        return Err(SimulationError::OffConstraints {
            t: t0,
            q: q0.to_vec(),
            qdot: qdot0.to_vec(),
            position_residual: pos,
            velocity_residual: vel,
            worst: worst.0,
        });
    }
    Ok(())
}

/// How far off its constraints an initial state may be, relative to each constraint's scale
/// (see `initial_state`): round-off in computing q0 from angles is ~1e-16, a mistake is ≫ 1e-10.
const INITIAL_TOLERANCE: f64 = 1e-10;

impl<'a, H, const N: usize, const K: usize> Simulation<'a, Constrained<'a, H, N, K>, N>
where
    H: Holonomic<N, K>,
{
    /// A run of a system with holonomic constraints from (q0, q̇0): the same builder and methods
    /// as [`Simulation::new`], and the same run as `Simulation::new` gives a system that declares
    /// its constraints ([`Lagrangian::declared`]: every `#[lagrangian]` impl with
    /// `fn constraints` or `fn velocity_constraints`); this constructor names K for a
    /// hand-written `impl Holonomic<N, K>` that does not.
    ///
    /// The explicit methods integrate M q̈ = f + Gᵀλ, G q̈ = −g̈|_{q̈=0} and project (q, q̇) back
    /// onto g = 0 and G q̇ + ∂g/∂t = 0 after every accepted step (and every recorded sample);
    /// the variational method takes a constrained discrete Euler–Lagrange step (RATTLE) that
    /// satisfies the constraints at every node. The trajectory records λ at every sample
    /// ([`Trajectory::lambda`], CSV columns `lambda_0…`), and
    /// [`Invariants::constraints`](crate::Invariants::constraints) reports the largest residual.
    ///
    /// The initial state must be on the constraints (else [`SimulationError::OffConstraints`],
    /// which says by how much) unless [`project_initial_state`](Simulation::project_initial_state)
    /// is asked for.
    ///
    /// ```
    /// use lagrange::prelude::*;
    ///
    /// /// A plane pendulum in x, y: L = m|v|²/2 − m g y, x² + y² = l².
    /// pub struct Pendulum;
    ///
    /// #[lagrangian]
    /// impl Pendulum {
    ///     fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
    ///         0.5 * (x_dot * x_dot + y_dot * y_dot) - 9.81 * y
    ///     }
    ///     fn constraints(&self, (x, _): Coord, (y, _): Coord) -> [Scalar; 1] {
    ///         [x * x + y * y - 1.0]
    ///     }
    /// }
    ///
    /// let tr = Simulation::constrained(&Pendulum, [1.0, 0.0], [0.0, 0.0]).until(5.0).run().unwrap();
    /// let inv = tr.invariants();
    /// assert!(inv.constraints.unwrap().position < 1e-14);
    /// assert!(inv.energy.unwrap().max_abs < 1e-8);
    /// // At the bottom (x = 0) the bob is at full speed and the rod pulls hardest: 3 m g.
    /// ```
    pub fn constrained(system: &'a H, q0: [f64; N], qdot0: [f64; N]) -> Self {
        let view = Constrained::new(system);
        let mut sim = Self::with(Sys::Owned(Box::new(view)), q0, qdot0);
        sim.o.manifold = Some(Box::new(view));
        sim
    }

    /// This constrained run with every option of `plain` (method, end time, samples, events,
    /// observer, limits): how an ensemble gives its members' constrained runs the options it was
    /// configured with on the plain builder.
    pub(crate) fn options_from<M>(self, plain: Simulation<'a, M, N>) -> Self {
        Simulation {
            sys: self.sys,
            o: self.o.adopt(plain.o),
        }
    }
}
