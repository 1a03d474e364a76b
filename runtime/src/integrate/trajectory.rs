//! The result of a run: samples, the energy and momenta at each sample, events, statistics,
//! invariant drift and CSV output.

use std::io::Write;
use std::path::Path;

use super::dense::{Dense, DenseOutputError};
use super::events::{EventHit, Jump, Zeno};
use super::state::{Fault, Stats};

/// The memory the stored samples of a run may take when [`Simulation::max_samples`](crate::Simulation::max_samples)
/// is not set: 256 MiB (the default bound is this over [`sample_bytes`]).
pub(crate) const SAMPLE_BUDGET_BYTES: usize = 256 << 20;

/// The bytes one stored sample of a run with `n` coordinates and `k` constraints takes: t, q, q̇,
/// the energy, the momenta and the work, (3n + 3) · 8, and for k > 0 the multipliers λ (a `Vec`:
/// 24 + 8k). The one count both `max_samples` messages use.
pub(crate) fn sample_bytes(n: usize, k: usize) -> usize {
    let lambda = if k > 0 { 24 + 8 * k } else { 0 };
    (3 * n + 3) * 8 + lambda
}

/// The default `max_samples`: as many samples as fit in [`SAMPLE_BUDGET_BYTES`] (at least 2).
pub(crate) fn default_max_samples(n: usize, k: usize) -> usize {
    (SAMPLE_BUDGET_BYTES / sample_bytes(n, k)).max(2)
}

/// `max_samples = …` with what a sample takes and, for the default, where the bound comes from:
/// the words both `max_samples` messages (before the run and during it) say it with.
pub(crate) fn max_samples_phrase(max_samples: usize, bytes: usize, by_default: bool) -> String {
    if by_default {
        format!(
            "max_samples = {max_samples} (the default: a {} MiB budget of stored samples at \
             {bytes} bytes per sample)",
            SAMPLE_BUDGET_BYTES >> 20
        )
    } else {
        format!("max_samples = {max_samples} (at {bytes} bytes per sample)")
    }
}

/// Drift of one conserved quantity over the samples of a run.
///
/// ```
/// use lagrange_runtime::Drift;
/// let d = Drift { initial: 2.0, max_abs: 1e-9, max_rel: 5e-10 };
/// assert_eq!(d.max_rel, d.max_abs / d.initial);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drift {
    /// The value at the first sample.
    pub initial: f64,
    /// max |X(t) − X(t₀)| over the samples.
    pub max_abs: f64,
    /// `max_abs / max(|X(t₀)|, INVARIANT_FLOOR)`.
    pub max_rel: f64,
}

/// The floor of the denominator of relative drifts: a quantity that starts at exactly zero
/// (|X(t₀)| < 1e-12) is measured relative to 1e-12, i.e. its `max_rel` is 10¹² × its absolute drift.
///
/// ```
/// assert_eq!(lagrange_runtime::INVARIANT_FLOOR, 1e-12);
/// ```
pub const INVARIANT_FLOOR: f64 = 1e-12;

/// Drift of the quantities a run should conserve: the energy (when it is conserved), each
/// conserved momentum, and otherwise the energy balance h(t) − h(t0) − W(t).
///
/// ```
/// use lagrange_runtime::{Drift, Invariants};
/// let inv = Invariants::<2> {
///     energy: Some(Drift { initial: 1.0, max_abs: 1e-9, max_rel: 1e-9 }),
///     momenta: [None, None],
///     energy_balance: None,
///     constraints: None,
/// };
/// assert_eq!(inv.max_rel(), 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Invariants<const N: usize> {
    /// Energy drift; `None` when the energy is not conserved (L depends on t, or forces or
    /// dissipation act: see `energy_balance`).
    pub energy: Option<Drift>,
    /// Momentum drift per coordinate; `None` where the momentum is not conserved (the
    /// coordinate is not cyclic, or a force or dissipation acts on it).
    pub momenta: [Option<Drift>; N],
    /// When the energy is not conserved: the residual of the energy balance h(t) − h(t0) − W(t),
    /// W the recorded work ([`Trajectory::work`]), which stays at the integrator's error.
    /// `initial` is h(t0), `max_abs` the largest |h(t) − h(t0) − W(t)|, and `max_rel` that
    /// relative to the run's energy scale, max(|h(t0)|, max |W|, [`INVARIANT_FLOOR`]).
    pub energy_balance: Option<Drift>,
    /// For a constrained run ([`Simulation::constrained`](crate::Simulation::constrained)): the
    /// largest constraint residuals over the samples and the largest projection made.
    pub constraints: Option<ConstraintResidual>,
}

/// How well a constrained run kept its constraints g(q, t) = 0.
///
/// ```
/// use lagrange_runtime::ConstraintResidual;
/// let r = ConstraintResidual { position: 1e-16, velocity: 2e-16, projection: 1e-11 };
/// assert!(r.position < r.projection);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConstraintResidual {
    /// max |g_j(q, t)| over the recorded samples.
    pub position: f64,
    /// max |ġ_j| = |G q̇ + ∂g/∂t| over the recorded samples.
    pub velocity: f64,
    /// The largest correction |Δq|∞ the projection onto the constraints made after a step: how
    /// far the integrator drifted off them before being put back (zero for the variational
    /// method, whose steps satisfy them).
    pub projection: f64,
}

impl ConstraintResidual {
    fn add(&mut self, (position, velocity): (f64, f64)) {
        self.position = self.position.max(position);
        self.velocity = self.velocity.max(velocity);
    }
}

impl<const N: usize> Invariants<N> {
    /// The largest relative drift among the conserved quantities and the energy balance (0 if
    /// there are none).
    ///
    /// ```
    /// use lagrange_runtime::{Drift, Invariants};
    /// let d = |r| Some(Drift { initial: 1.0, max_abs: r, max_rel: r });
    /// let inv = Invariants::<1> { energy: d(1e-8), momenta: [d(1e-6)], energy_balance: None, constraints: None };
    /// assert_eq!(inv.max_rel(), 1e-6);
    /// ```
    pub fn max_rel(&self) -> f64 {
        self.energy
            .iter()
            .chain(self.momenta.iter().flatten())
            .chain(self.energy_balance.iter())
            .fold(0.0, |m, d| m.max(d.max_rel))
    }
}

/// One recorded state of a run, as the observer of [`Simulation::observe`](crate::Simulation::observe)
/// sees it (and as the trajectory stores it).
///
/// ```
/// use lagrange_runtime::Sample;
/// let s = Sample { t: 1.0, q: [0.5], qdot: [0.0], energy: 0.125, momenta: [0.0], work: 0.0 };
/// assert_eq!(s.q[0], 0.5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample<const N: usize> {
    /// Time.
    pub t: f64,
    /// Coordinates.
    pub q: [f64; N],
    /// Velocities.
    pub qdot: [f64; N],
    /// Energy h = q̇·p − L.
    pub energy: f64,
    /// Momenta p = ∂L/∂q̇.
    pub momenta: [f64; N],
    /// Work done on the system since t0 (see [`Trajectory::work`]).
    pub work: f64,
}

/// The drift of the invariants over every sample of a run, kept as the samples go by (what
/// [`Trajectory::invariants`] reports when not every sample is stored).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Running<const N: usize> {
    h0: f64,
    p0: [f64; N],
    energy: f64,
    momenta: [f64; N],
    balance: f64,
    work: f64,
    started: bool,
}

impl<const N: usize> Running<N> {
    const EMPTY: Self = Running {
        h0: 0.0,
        p0: [0.0; N],
        energy: 0.0,
        momenta: [0.0; N],
        balance: 0.0,
        work: 0.0,
        started: false,
    };

    fn add(&mut self, s: &Sample<N>) {
        if !self.started {
            self.h0 = s.energy;
            self.p0 = s.momenta;
            self.started = true;
        }
        self.energy = self.energy.max((s.energy - self.h0).abs());
        for i in 0..N {
            self.momenta[i] = self.momenta[i].max((s.momenta[i] - self.p0[i]).abs());
        }
        self.balance = self.balance.max((s.energy - self.h0 - s.work).abs());
        self.work = self.work.max(s.work.abs());
    }
}

/// A simulated trajectory: samples (t, q, q̇) with the energy and momenta there, the located
/// events and the run's counters.
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
/// struct Free;
/// impl Lagrangian<1> for Free {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
/// }
/// let tr = Simulation::new(&Free, [0.0], [2.0]).method(Method::Rk4 { dt: 0.5 }).until(1.0).run().unwrap();
/// assert_eq!(tr.t, vec![0.0, 0.5, 1.0]);
/// assert!((tr.q[2][0] - 2.0).abs() < 1e-15);
/// assert_eq!(tr.momenta[2], [2.0]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory<const N: usize> {
    /// Sample times.
    pub t: Vec<f64>,
    /// Coordinates at the samples.
    pub q: Vec<[f64; N]>,
    /// Velocities at the samples.
    pub qdot: Vec<[f64; N]>,
    /// Energy (Jacobi integral q̇·∂L/∂q̇ − L) at the samples.
    pub energy: Vec<f64>,
    /// Momenta ∂L/∂q̇ at the samples.
    pub momenta: Vec<[f64; N]>,
    /// The work W(t) done on the system since t0 at the samples: the integral of
    /// [`Lagrangian::power`](crate::Lagrangian::power), (Q − ∂D/∂q̇)·q̇ − ∂L/∂t, by Gauss–Legendre
    /// quadrature on each step's interpolant (to the integrator's accuracy), so that
    /// h(t) − h(t0) − W(t) measures the integrator's error. All zero when the energy is conserved.
    /// In a failed run's partial trajectory the last entry is NaN if the failing step's work was
    /// not integrated.
    pub work: Vec<f64>,
    /// Located events, in time order.
    pub events: Vec<EventHit<N>>,
    /// The jumps of the state at resetting events ([`Event::reset`](crate::Event::reset)), in
    /// time order.
    pub jumps: Vec<Jump<N>>,
    /// The accumulation of a resetting event's hits that ended the run, if one did.
    pub zeno: Option<Zeno>,
    /// Counters.
    pub stats: Stats,
    /// The coordinate names.
    pub coordinates: [&'static str; N],
    /// Which coordinates are cyclic.
    pub cyclic: [bool; N],
    /// Whether L has no explicit time dependence.
    pub autonomous: bool,
    /// Which momenta are conserved ([`Lagrangian::MOMENTUM_CONSERVED`](crate::Lagrangian::MOMENTUM_CONSERVED)).
    pub momentum_conserved: [bool; N],
    /// Whether the energy is conserved ([`Lagrangian::ENERGY_CONSERVED`](crate::Lagrangian::ENERGY_CONSERVED)).
    pub energy_conserved: bool,
    /// The terminal event that ended the run early, if any.
    pub terminated_by: Option<String>,
    /// The multipliers λ at the samples, for a constrained run (one entry of K per sample; empty
    /// otherwise): M q̈ = f + Gᵀλ, so Gᵀλ is the constraint force in generalized coordinates.
    pub lambda: Vec<Vec<f64>>,
    /// The number of constraints K (0 for a run without constraints).
    pub constraint_count: usize,
    /// The largest constraint residuals and projection so far.
    residual: ConstraintResidual,
    /// Drift over every sample seen, stored or not.
    running: Running<N>,
    /// Whether every sample was stored (`keep_samples(true)`, the default).
    complete: bool,
    /// The dense output of the whole run, when kept (`keep_dense_output(true)`).
    dense: Option<Box<Dense<N>>>,
}

impl<const N: usize> Trajectory<N> {
    /// An empty trajectory of the system `L`, with its names and flags.
    pub(crate) fn empty(flags: super::system::Flags<N>, constraint_count: usize) -> Self {
        Trajectory {
            t: Vec::new(),
            q: Vec::new(),
            qdot: Vec::new(),
            energy: Vec::new(),
            momenta: Vec::new(),
            work: Vec::new(),
            events: Vec::new(),
            jumps: Vec::new(),
            zeno: None,
            stats: Stats::default(),
            coordinates: flags.coordinates,
            cyclic: flags.cyclic,
            autonomous: flags.autonomous,
            momentum_conserved: flags.momentum_conserved,
            energy_conserved: flags.energy_conserved,
            terminated_by: None,
            lambda: Vec::new(),
            constraint_count,
            residual: ConstraintResidual::default(),
            running: Running::EMPTY,
            complete: true,
            dense: None,
        }
    }

    /// The dense output being kept, if the run keeps it and it has started.
    pub(crate) fn dense_mut(&mut self) -> Option<&mut Dense<N>> {
        self.dense.as_deref_mut()
    }

    /// Starts keeping the dense output (at the run's initial state), unless it has started.
    pub(crate) fn start_dense(&mut self, dense: impl FnOnce() -> Dense<N>) {
        if self.dense.is_none() {
            self.dense = Some(Box::new(dense()));
        }
    }

    /// Records a sample: stored when `keep` (at most `max_samples`, else [`Fault::MaxSamples`]);
    /// otherwise only the first and the latest sample are stored, whatever `max_samples` is (the
    /// bound is on memory, and two samples take next to none). The running drift sees them all.
    pub(crate) fn record(
        &mut self,
        s: &Sample<N>,
        constraint: Option<(Vec<f64>, (f64, f64))>,
        keep: bool,
        max_samples: usize,
    ) -> Result<(), Fault> {
        if let Some((lambda, residual)) = constraint {
            self.residual.add(residual);
            if keep || self.t.len() < 2 {
                if !keep || self.t.len() < max_samples {
                    self.lambda.push(lambda);
                }
            } else if let Some(last) = self.lambda.last_mut() {
                *last = lambda;
            }
        }
        if keep || self.t.len() < 2 {
            if keep && self.t.len() >= max_samples {
                return Err(Fault::MaxSamples(max_samples));
            }
            self.t.push(s.t);
            self.q.push(s.q);
            self.qdot.push(s.qdot);
            self.energy.push(s.energy);
            self.momenta.push(s.momenta);
            self.work.push(s.work);
        } else {
            self.complete = false;
            let k = self.t.len() - 1;
            self.t[k] = s.t;
            self.q[k] = s.q;
            self.qdot[k] = s.qdot;
            self.energy[k] = s.energy;
            self.momenta[k] = s.momenta;
            self.work[k] = s.work;
        }
        self.running.add(s);
        Ok(())
    }

    /// Notes the size of a projection onto the constraints after a step.
    pub(crate) fn note_projection(&mut self, moved: f64) {
        self.residual.projection = self.residual.projection.max(moved);
    }

    /// Number of samples.
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
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 0.25 }).until(1.0).run().unwrap();
    /// assert_eq!(tr.len(), 5);
    /// ```
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no samples.
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
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).until(1.0).run().unwrap();
    /// assert!(!tr.is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// The state (q, q̇) at any time t of the run, from the method's own interpolant: needs
    /// [`Simulation::keep_dense_output`](crate::Simulation::keep_dense_output).
    ///
    /// Between the steps' nodes it is the interpolant the run's samples and events use (DOP853's
    /// 7th-order dense output, Dormand–Prince's 4th-order extension, RK4's cubic Hermite, the
    /// variational method's q cubic Hermite and q̇ linear, the Taylor method's series), so a
    /// sample recorded between nodes is `at` its time bit for bit, and so is a sample on a node
    /// (it is the node's state) — in a constrained run up to the samples' own projection onto
    /// the constraints, which `at` does not repeat. Errors ([`DenseOutputError`]): the dense
    /// output was not kept, t is NaN, t is outside [`dense_span`](Trajectory::dense_span), or t
    /// lies past the part kept within the memory bound.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method, DenseOutputError};
    /// struct Osc;
    /// impl Lagrangian<1> for Osc {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// }
    /// let tr = Simulation::new(&Osc, [1.0], [0.0])
    ///     .method(Method::Dop853 { rtol: 1e-10, atol: 1e-12 })
    ///     .until(10.0)
    ///     .keep_dense_output(true)
    ///     .run()
    ///     .unwrap();
    /// let (q, qdot) = tr.at(2.345).unwrap();
    /// assert!((q[0] - 2.345_f64.cos()).abs() < 1e-9 && (qdot[0] + 2.345_f64.sin()).abs() < 1e-9);
    /// assert!(matches!(tr.at(11.0), Err(DenseOutputError::OutOfRange { .. })));
    /// ```
    pub fn at(&self, t: f64) -> Result<([f64; N], [f64; N]), DenseOutputError> {
        let dense = self.dense.as_deref().ok_or(DenseOutputError::NotKept)?;
        let [q, qdot] = dense.at(t)?;
        Ok((q, qdot))
    }

    /// The times [`at`](Trajectory::at) serves, (start, end): the whole run (up to a terminal
    /// event; for a failed run's partial trajectory, up to its last accepted step) unless the
    /// dense output reached its memory bound first. `None` when it was not kept.
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
    /// let run = |keep| Simulation::new(&Free, [0.0], [1.0]).start_time(1.0).until(3.0).keep_dense_output(keep).run().unwrap();
    /// assert_eq!(run(true).dense_span(), Some((1.0, 3.0)));
    /// assert_eq!(run(false).dense_span(), None);
    /// ```
    pub fn dense_span(&self) -> Option<(f64, f64)> {
        self.dense.as_deref().map(Dense::span)
    }

    /// Max drift of the energy (when conserved) and of each conserved momentum over the samples,
    /// relative to max(|initial value|, [`INVARIANT_FLOOR`]) (over every sample of the run, also
    /// those an observer saw but the trajectory did not store); when the energy is not conserved,
    /// the residual of the energy balance h(t) − h(t0) − W(t) instead (see
    /// [`Invariants::energy_balance`]).
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
    /// struct Free;
    /// impl Lagrangian<1> for Free {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).until(3.0).run().unwrap();
    /// let inv = tr.invariants();
    /// assert_eq!(inv.energy.unwrap().max_rel, 0.0);
    /// assert_eq!(inv.momenta[0].unwrap().initial, 1.0);
    /// ```
    pub fn invariants(&self) -> Invariants<N> {
        if !self.complete {
            return self.running_invariants();
        }
        fn drift(xs: impl Iterator<Item = f64>) -> Option<Drift> {
            let mut it = xs;
            let initial = it.next()?;
            let max_abs = it.fold(0.0_f64, |m, x| m.max((x - initial).abs()));
            Some(Drift {
                initial,
                max_abs,
                max_rel: max_abs / initial.abs().max(INVARIANT_FLOOR),
            })
        }
        let energy = if self.energy_conserved {
            drift(self.energy.iter().copied())
        } else {
            None
        };
        let mut momenta = [None; N];
        for (i, m) in momenta.iter_mut().enumerate() {
            if self.momentum_conserved[i] {
                *m = drift(self.momenta.iter().map(|p| p[i]));
            }
        }
        let energy_balance = match (self.energy_conserved, self.energy.first()) {
            (false, Some(&h0)) => {
                let (mut max_abs, mut w_max) = (0.0_f64, 0.0_f64);
                for (h, w) in self.energy.iter().zip(&self.work) {
                    max_abs = max_abs.max((h - h0 - w).abs());
                    w_max = w_max.max(w.abs());
                }
                Some(Drift {
                    initial: h0,
                    max_abs,
                    max_rel: max_abs / h0.abs().max(w_max).max(INVARIANT_FLOOR),
                })
            }
            _ => None,
        };
        Invariants {
            energy,
            momenta,
            energy_balance,
            constraints: self.constraint_residual(),
        }
    }

    /// The invariants from the running drift (every sample seen, also those not stored).
    fn running_invariants(&self) -> Invariants<N> {
        let r = &self.running;
        let drift = |initial: f64, max_abs: f64| Drift {
            initial,
            max_abs,
            max_rel: max_abs / initial.abs().max(INVARIANT_FLOOR),
        };
        let mut momenta = [None; N];
        for (i, m) in momenta.iter_mut().enumerate() {
            if self.momentum_conserved[i] && r.started {
                *m = Some(drift(r.p0[i], r.momenta[i]));
            }
        }
        Invariants {
            energy: (self.energy_conserved && r.started).then(|| drift(r.h0, r.energy)),
            momenta,
            energy_balance: (!self.energy_conserved && r.started).then(|| Drift {
                initial: r.h0,
                max_abs: r.balance,
                max_rel: r.balance / r.h0.abs().max(r.work).max(INVARIANT_FLOOR),
            }),
            constraints: self.constraint_residual(),
        }
    }

    /// The constraint residuals of a constrained run.
    fn constraint_residual(&self) -> Option<ConstraintResidual> {
        (self.constraint_count > 0).then_some(self.residual)
    }

    /// Writes the samples as CSV: `t`, the coordinate names, their velocities (`name_dot`), `energy`
    /// and the momenta (`p_name`), `work` when the energy is not conserved, and the multipliers
    /// `lambda_0…` of a constrained run; one row per sample, full precision. Missing parent folders are created; an I/O error names the path.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
    /// struct Free;
    /// impl Lagrangian<1> for Free {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// }
    /// let tr = Simulation::new(&Free, [0.0], [1.0]).method(Method::Rk4 { dt: 1.0 }).until(1.0).run().unwrap();
    /// let path = std::env::temp_dir().join("lagrange_doctest_free.csv");
    /// tr.write_csv(&path).unwrap();
    /// let text = std::fs::read_to_string(&path).unwrap();
    /// assert_eq!(text.lines().next(), Some("t,x,x_dot,energy,p_x"));
    /// let row: Vec<f64> = text.lines().nth(2).unwrap().split(',').map(|x| x.parse().unwrap()).collect();
    /// assert_eq!(row.len(), 5);
    /// assert!((row[1] - 1.0).abs() < 1e-15 && row[3] == 0.5);
    /// ```
    pub fn write_csv(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        let path = path.as_ref();
        let named = |e: std::io::Error| {
            std::io::Error::new(e.kind(), format!("writing {}: {e}", path.display()))
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(named)?;
        }
        let file = std::fs::File::create(path).map_err(named)?;
        let mut w = std::io::BufWriter::new(file);
        let mut header = vec!["t".to_string()];
        header.extend(self.coordinates.iter().map(|n| n.to_string()));
        header.extend(self.coordinates.iter().map(|n| format!("{n}_dot")));
        header.push("energy".to_string());
        header.extend(self.coordinates.iter().map(|n| format!("p_{n}")));
        let with_work = !self.energy_conserved;
        if with_work {
            header.push("work".to_string());
        }
        header.extend((0..self.constraint_count).map(|j| format!("lambda_{j}")));
        writeln!(w, "{}", header.join(",")).map_err(named)?;
        for k in 0..self.len() {
            let mut row = vec![self.t[k]];
            row.extend_from_slice(&self.q[k]);
            row.extend_from_slice(&self.qdot[k]);
            row.push(self.energy[k]);
            row.extend_from_slice(&self.momenta[k]);
            if with_work {
                row.push(self.work[k]);
            }
            if self.constraint_count > 0 {
                match self.lambda.get(k) {
                    Some(l) => row.extend_from_slice(l),
                    None => row.extend(std::iter::repeat_n(f64::NAN, self.constraint_count)),
                }
            }
            let cells: Vec<String> = row.iter().map(|x| format!("{x}")).collect();
            writeln!(w, "{}", cells.join(",")).map_err(named)?;
        }
        w.flush().map_err(named)
    }
}
