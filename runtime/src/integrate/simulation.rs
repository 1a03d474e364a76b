//! [`Simulation`]: the builder and the driver loop shared by all methods (sampling, events,
//! limits, errors with the partial trajectory).

use crate::lagrangian::Lagrangian;

use super::dop853::Dop853;
use super::dopri5::Dopri5;
use super::error::{PartialTrajectory, SimulationError};
use super::events::{brent, Event, EventHit};
use super::rk4::Rk4;
use super::tableau::{Fault, Y};
use super::trajectory::{Stats, Trajectory};
use super::variational::VariationalMidpoint;

/// The integration method.
///
/// ```
/// use lagrange_runtime::Method;
/// let m = Method::Dop853 { rtol: 1e-10, atol: 1e-12 };
/// assert!(!m.is_fixed_step());
/// assert!(Method::VariationalMidpoint { dt: 1e-3 }.is_fixed_step());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Classical 4th-order Runge–Kutta with fixed step `dt`.
    Rk4 {
        /// Step.
        dt: f64,
    },
    /// Dormand–Prince 5(4), adaptive (PI control), 4th-order dense output.
    DormandPrince {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// DOP853, adaptive 8th order with 7th-order dense output.
    Dop853 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// The variational midpoint integrator (symplectic, momentum-conserving), fixed step `dt`.
    VariationalMidpoint {
        /// Step.
        dt: f64,
    },
}

impl Method {
    /// Whether the method takes fixed steps (samples and events are then tied to its grid).
    ///
    /// ```
    /// assert!(lagrange_runtime::Method::Rk4 { dt: 0.1 }.is_fixed_step());
    /// ```
    pub fn is_fixed_step(&self) -> bool {
        matches!(
            self,
            Method::Rk4 { .. } | Method::VariationalMidpoint { .. }
        )
    }
}

/// The default of [`Simulation::max_samples`].
const DEFAULT_MAX_SAMPLES: usize = 100_000_000;

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
    fn new(t0: f64, dt: f64, until: f64) -> Self {
        let n = (((until - t0) / dt) - 1e-6).ceil().max(1.0) as u64;
        FixedGrid { t0, dt, n, until }
    }
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
    /// Takes one accepted step, not beyond `t_end`.
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault>;
    /// (q, q̇) at t in [t_prev, t] from the method's interpolant.
    fn interp(&mut self, t: f64, stats: &mut Stats) -> Result<Y<N>, Fault>;
}

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
pub struct Simulation<'a, L: ?Sized, const N: usize> {
    sys: &'a L,
    q0: [f64; N],
    qdot0: [f64; N],
    t0: f64,
    until: Option<f64>,
    method: Method,
    sample_every: Option<f64>,
    sample_at: Option<Vec<f64>>,
    events: Vec<Event<'a, N>>,
    max_steps: usize,
    max_step: Option<f64>,
    max_samples: usize,
}

impl<'a, L: Lagrangian<N> + ?Sized, const N: usize> Simulation<'a, L, N> {
    /// A run of `system` from q0, q̇0 at t0 = 0 with DOP853 (rtol 1e-10, atol 1e-12); set the end
    /// time with [`until`](Simulation::until).
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
    /// let tr = Simulation::new(&Free, [1.0], [2.0]).until(1.0).run().unwrap();
    /// assert!((tr.q.last().unwrap()[0] - 3.0).abs() < 1e-12);
    /// ```
    pub fn new(system: &'a L, q0: [f64; N], qdot0: [f64; N]) -> Self {
        Simulation {
            sys: system,
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
            max_samples: DEFAULT_MAX_SAMPLES,
            max_step: None,
        }
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
        self.method = method;
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
        self.t0 = t0;
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
        self.until = Some(t_end);
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
        self.sample_every = Some(dt_sample);
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
        self.sample_at = Some(times.into_iter().collect());
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
        self.events.push(event);
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
        self.max_steps = n;
        self
    }

    /// The largest number of samples a sample grid may ask for (default 10⁸): `sample_every` over
    /// a long run, or a long `sample_at` list, beyond it is [`SimulationError::InvalidOptions`]
    /// before any step, instead of a run that exhausts memory. Each sample holds t, q, q̇, the
    /// energy and the momenta: (3N + 2) · 8 bytes.
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
        self.max_samples = n;
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
        self.max_step = Some(h);
        self
    }

    fn validate(&self) -> Result<f64, String> {
        let until = self
            .until
            .ok_or_else(|| "no end time: call .until(t_end) before .run()".to_string())?;
        if !self.t0.is_finite() || !until.is_finite() {
            return Err(format!(
                "start time {} and end time {until} must be finite",
                self.t0
            ));
        }
        if until <= self.t0 {
            return Err(format!(
                "the end time {until} is not after the start time {}: integration runs forward; \
                 choose until > start_time",
                self.t0
            ));
        }
        if self
            .q0
            .iter()
            .chain(self.qdot0.iter())
            .any(|x| !x.is_finite())
        {
            return Err(format!(
                "the initial state is not finite: q0 = {:?}, q̇0 = {:?}",
                self.q0, self.qdot0
            ));
        }
        let positive = |name: &str, x: f64| {
            if x > 0.0 && x.is_finite() {
                Ok(())
            } else {
                Err(format!("{name} = {x} must be positive and finite"))
            }
        };
        match self.method {
            Method::Rk4 { dt } | Method::VariationalMidpoint { dt } => positive("dt", dt)?,
            Method::DormandPrince { rtol, atol } | Method::Dop853 { rtol, atol } => {
                positive("rtol", rtol)?;
                if !(atol >= 0.0 && atol.is_finite()) {
                    return Err(format!("atol = {atol} must be non-negative and finite"));
                }
                if rtol < 1e-15 {
                    return Err(format!(
                        "rtol = {rtol:e} is below what double precision can deliver; use rtol ≥ 1e-15 \
                         (1e-13 is a practical floor)"
                    ));
                }
            }
        }
        if let Some(h) = self.max_step {
            positive("max_step", h)?;
        }
        if let Some(ds) = self.sample_every {
            positive("sample_every", ds)?;
            if let Method::Rk4 { dt } | Method::VariationalMidpoint { dt } = self.method {
                let ratio = ds / dt;
                if ratio < 1.0 - 1e-9 || (ratio - ratio.round()).abs() > 1e-9 * ratio {
                    return Err(format!(
                        "sample_every = {ds} is not a multiple of the fixed step dt = {dt}: fixed-step \
                         methods record the steps that land on the sample grid; choose \
                         sample_every = k·dt (e.g. {}) or dt = sample_every / k",
                        dt * ratio.round().max(1.0)
                    ));
                }
            }
        }
        // The trajectory's length: t0 + kΔ for k = 0 … ⌊(until − t0)/Δ⌋ and `until` if it is off
        // that grid; or t0, sample_at's times and `until`.
        let samples = match (self.sample_every, &self.sample_at) {
            (Some(ds), _) => {
                let k = ((until - self.t0) / ds + 1e-9).floor();
                let on_end = ((until - self.t0) - k * ds).abs() <= 1e-9 * ds;
                k + if on_end { 1.0 } else { 2.0 }
            }
            (None, Some(times)) => {
                let ends = [self.t0, until];
                (times.len() + ends.iter().filter(|e| !times.contains(e)).count()) as f64
            }
            (None, None) => 0.0,
        };
        if samples > self.max_samples as f64 {
            let asked = match self.sample_every {
                Some(ds) => format!(
                    "sample_every = {ds:e} over [{}, {until}] asks for {samples:.3e} samples",
                    self.t0
                ),
                None => format!("sample_at asks for {samples} samples (with t0 and until)"),
            };
            return Err(format!(
                "{asked}, more than max_samples = {}: sample less often, shorten the run, or \
                 raise the limit with .max_samples(n) (each sample holds (3N + 2) · 8 bytes)",
                self.max_samples
            ));
        }
        if let Some(times) = &self.sample_at {
            if self.sample_every.is_some() {
                return Err(
                    "both sample_every and sample_at are set: choose one (sample_at can hold a \
                     regular grid too)"
                        .to_string(),
                );
            }
            for (i, &ts) in times.iter().enumerate() {
                if !(ts >= self.t0 && ts <= until) {
                    return Err(format!(
                        "sample_at time {ts} (index {i}) is outside the run [{}, {until}]: sample \
                         times must lie between the start time and until",
                        self.t0
                    ));
                }
                if i > 0 && ts <= times[i - 1] {
                    return Err(format!(
                        "sample_at times must increase, but time {ts} (index {i}) follows {}: sort \
                         them and remove duplicates",
                        times[i - 1]
                    ));
                }
                if let Method::Rk4 { dt } | Method::VariationalMidpoint { dt } = self.method {
                    let k = (ts - self.t0) / dt;
                    if ts != until && (k - k.round()).abs() > 1e-9 * k.max(1.0) {
                        return Err(format!(
                            "sample_at time {ts} (index {i}) is not on the fixed step grid \
                             t0 + k·dt (t0 = {}, dt = {dt}): fixed-step methods record the steps \
                             that land on the sample times; choose times on the grid (e.g. {}) or \
                             use an adaptive method, whose dense output serves any time",
                            self.t0,
                            self.t0 + k.round() * dt
                        ));
                    }
                }
            }
        }
        if self.max_steps == 0 {
            return Err("max_steps must be at least 1".to_string());
        }
        Ok(until)
    }

    /// Checks the system's `CYCLIC` declaration at the initial state: q̈ must not change when a
    /// coordinate declared cyclic is shifted. The explicit methods rely on it (they do not form
    /// the stage positions of cyclic coordinates), and the momenta reported as conserved do too.
    /// Skipped where the dynamics fail at the initial state (the run reports that).
    fn check_cyclic(&self) -> Result<(), String> {
        const SHIFT: f64 = 0.739_085_133_215_160_6;
        let Ok(a0) = self.sys.accelerations(&self.q0, &self.qdot0, self.t0) else {
            return Ok(());
        };
        for i in (0..N).filter(|&i| L::CYCLIC[i]) {
            let mut q = self.q0;
            q[i] += SHIFT;
            let a1 = self.sys.accelerations(&q, &self.qdot0, self.t0);
            let same = a1.as_ref().is_ok_and(|a1| {
                a0.iter()
                    .zip(a1)
                    .all(|(x, y)| (x - y).abs() <= 1e-9 * (x.abs() + y.abs()) + 1e-300)
            });
            if !same {
                let name = L::COORDINATES[i];
                let shifted = a1.map_or_else(|e| format!("an error ({e})"), |a| format!("{a:?}"));
                return Err(format!(
                    "CYCLIC declares the coordinate `{name}` absent from L, but the accelerations \
                     change with it (at t = {}, q = {:?}, q̇ = {:?}, shifting {name} by {SHIFT} \
                     changes q̈ from {a0:?} to {shifted}): set CYCLIC[{i}] = false, or derive the \
                     declaration with #[lagrangian], which finds the cyclic coordinates itself",
                    self.t0, self.q0, self.qdot0,
                ));
            }
        }
        Ok(())
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
        let until = self
            .validate()
            .and_then(|until| self.check_cyclic().map(|()| until))
            .map_err(|message| SimulationError::InvalidOptions { message })?;
        let mut driver = Driver {
            sys: self.sys,
            events: &self.events,
            traj: Trajectory::empty(L::COORDINATES, L::CYCLIC, L::AUTONOMOUS),
            stats: Stats::default(),
        };
        let y0 = [self.q0, self.qdot0];
        let hmax = self.max_step.unwrap_or(until - self.t0);
        let sampling = match (&self.sample_at, self.sample_every) {
            (Some(times), _) => Sampling::At {
                times,
                // A fixed-step method records the node a sample time lands on (the grid test of
                // `validate` allows 1e-9 of a step); the adaptive ones interpolate any other time.
                snap: match self.method {
                    Method::Rk4 { dt } | Method::VariationalMidpoint { dt } => 1e-9 * dt,
                    _ => 0.0,
                },
            },
            (None, Some(ds)) => Sampling::Every(ds),
            (None, None) => Sampling::Steps,
        };
        let opts = RunOptions {
            t0: self.t0,
            until,
            sampling,
            max_steps: self.max_steps,
        };
        match self.method {
            Method::Rk4 { dt } => {
                let grid = FixedGrid::new(self.t0, dt, until);
                match Rk4::new(self.sys, grid, y0, &mut driver.stats) {
                    Ok(s) => driver.run(s, &opts),
                    Err(f) => Err(driver.fail(f, self.t0, y0)),
                }
            }
            Method::VariationalMidpoint { dt } => {
                let grid = FixedGrid::new(self.t0, dt, until);
                // Check the dynamics at the start (a singular mass matrix is reported up front).
                match self.sys.accelerations(&self.q0, &self.qdot0, self.t0) {
                    Ok(_) => {
                        let s = VariationalMidpoint::new(self.sys, grid, self.q0, self.qdot0);
                        driver.run(s, &opts)
                    }
                    Err(e) => Err(driver.fail(Fault::Dynamics(e), self.t0, y0)),
                }
            }
            Method::DormandPrince { rtol, atol } => {
                match Dopri5::new(self.sys, self.t0, y0, rtol, atol, hmax, &mut driver.stats) {
                    Ok(s) => driver.run(s, &opts),
                    Err(f) => Err(driver.fail(f, self.t0, y0)),
                }
            }
            Method::Dop853 { rtol, atol } => {
                match Dop853::new(self.sys, self.t0, y0, rtol, atol, hmax, &mut driver.stats) {
                    Ok(s) => driver.run(s, &opts),
                    Err(f) => Err(driver.fail(f, self.t0, y0)),
                }
            }
        }
    }
}

struct RunOptions<'s> {
    t0: f64,
    until: f64,
    sampling: Sampling<'s>,
    max_steps: usize,
}

/// Which states the trajectory records.
enum Sampling<'s> {
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

    /// How close to a node a sample time is taken at the node.
    fn snap(&self) -> f64 {
        match *self {
            Sampling::Steps => 0.0,
            Sampling::Every(ds) => 1e-9 * ds,
            Sampling::At { snap, .. } => snap,
        }
    }
}

struct Driver<'s, 'a, L: ?Sized, const N: usize> {
    sys: &'s L,
    events: &'s [Event<'a, N>],
    traj: Trajectory<N>,
    stats: Stats,
}

impl<L: Lagrangian<N> + ?Sized, const N: usize> Driver<'_, '_, L, N> {
    fn push(&mut self, t: f64, y: &Y<N>) {
        if self.traj.t.last() == Some(&t) {
            return;
        }
        let (e, p) = self.sys.energy_and_momenta(&y[0], &y[1], t);
        self.traj.t.push(t);
        self.traj.q.push(y[0]);
        self.traj.qdot.push(y[1]);
        self.traj.energy.push(e);
        self.traj.momenta.push(p);
    }

    /// Turns a stepper fault into the error, with the trajectory so far ending at (t, y).
    fn fail(mut self, fault: Fault, t: f64, y: Y<N>) -> SimulationError {
        if y.iter().flatten().all(|x| x.is_finite()) {
            self.push(t, &y);
        }
        self.traj.stats = self.stats;
        let (q, qdot) = (y[0].to_vec(), y[1].to_vec());
        let partial = PartialTrajectory::new(self.traj);
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

    fn run<S: Stepper<N>>(
        mut self,
        mut s: S,
        o: &RunOptions,
    ) -> Result<Trajectory<N>, SimulationError> {
        match self.drive(&mut s, o) {
            Ok(()) => {
                self.traj.stats = self.stats;
                Ok(self.traj)
            }
            Err(f) => {
                // Report the last accepted node (its velocity from the stepper's own state).
                let (t, y) = (s.t(), s.last_state());
                Err(self.fail(f, t, y))
            }
        }
    }

    fn drive<S: Stepper<N>>(&mut self, s: &mut S, o: &RunOptions) -> Result<(), Fault> {
        let y0 = s.node(&mut self.stats)?;
        self.push(o.t0, &y0);
        let mut g_old: Vec<f64> = self
            .events
            .iter()
            .map(|e| e.value(o.t0, &y0[0], &y0[1]))
            .collect();
        let mut g_new = g_old.clone();
        let mut hits: Vec<(f64, usize, super::events::Direction)> = Vec::new();
        let mut next_sample: usize = 0;
        while s.t() < o.until {
            if self.stats.steps + self.stats.rejected >= o.max_steps {
                return Err(Fault::MaxSteps(o.max_steps));
            }
            s.advance(o.until, &mut self.stats)?;
            let (t_a, t_b) = (s.t_prev(), s.t());
            // Events: sign changes of g over the step, located on the interpolant.
            hits.clear();
            if !self.events.is_empty() {
                let yb = s.node(&mut self.stats)?;
                for (i, ev) in self.events.iter().enumerate() {
                    g_new[i] = ev.value(t_b, &yb[0], &yb[1]);
                    if let Some(dir) = ev.crosses(g_old[i], g_new[i]) {
                        let tol = 1e-12_f64.max(4.0 * f64::EPSILON * t_b.abs());
                        let stats = &mut self.stats;
                        let tz = brent(
                            |t| {
                                let y = s.interp(t, stats)?;
                                Ok::<f64, Fault>(ev.value(t, &y[0], &y[1]))
                            },
                            t_a,
                            t_b,
                            g_old[i],
                            g_new[i],
                            tol,
                        )?;
                        hits.push((tz, i, dir));
                    }
                }
                g_old.copy_from_slice(&g_new);
                hits.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            let stop = hits
                .iter()
                .position(|h| self.events[h.1].is_terminal())
                .map(|k| hits[k].0);
            let t_stop = stop.unwrap_or(t_b);
            // Samples in (t_a, t_stop], then the events up to t_stop.
            match o.sampling {
                Sampling::Every(_) | Sampling::At { .. } => {
                    // A time within `snap` past this node is this node (grid rounding), unless a
                    // terminal event ends the run here.
                    let snap = o.sampling.snap();
                    let limit = if stop.is_some() { t_stop } else { t_b + snap };
                    while let Some(ts) = o.sampling.time(next_sample, o.t0, o.until) {
                        if ts > limit {
                            break;
                        }
                        let y = if (t_b - ts).abs() <= snap {
                            s.node(&mut self.stats)?
                        } else {
                            s.interp(ts, &mut self.stats)?
                        };
                        self.push(ts, &y);
                        next_sample += 1;
                    }
                }
                Sampling::Steps => {
                    if stop.is_none() {
                        let y = s.node(&mut self.stats)?;
                        self.push(t_b, &y);
                    }
                }
            }
            for &(tz, i, dir) in &hits {
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
            }
            if let Some(tz) = stop {
                let y = s.interp(tz, &mut self.stats)?;
                self.push(tz, &y);
                if let Some(h) = self.traj.events.last() {
                    self.traj.terminated_by = Some(h.name.clone());
                }
                return Ok(());
            }
        }
        // The end time, if the sample grid did not land on it.
        let y = s.node(&mut self.stats)?;
        self.push(s.t(), &y);
        Ok(())
    }
}
