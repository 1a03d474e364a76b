//! [`Sensitivity`]: a [`Simulation`] that integrates the variational equations with the
//! motion, and its [`run`](Sensitivity::run).

use core::cell::RefCell;

use nalgebra::DMatrix;

use crate::lagrangian::Lagrangian;

use super::super::driver::Driver;
use super::super::error::SimulationError;
use super::super::factory::Explicit;
use super::super::jacobian::{Fields, compiled_along, kernel_slots};
use super::super::method::Method;
use super::super::radau5::{Forcing, Radau5};
use super::super::simulation::Simulation;
use super::super::state::{Fault, Y};
use super::super::stepper::FixedGrid;
use super::super::system::System;
use super::super::trajectory::{SAMPLE_BUDGET_BYTES, sample_bytes};
use super::super::variational::VariationalMidpoint;
use super::Log;
use super::augmented::Variational;
use super::event_time::at_event;
use super::result::Sensitivities;
use super::saltation::saltation;
use super::taylor::VarSeries;
use super::variation::{Parameter, Variation, affine_slots, central, difference_step, exact_dirs};

/// A run that also integrates the variational equations: built by
/// [`Simulation::sensitivity`], it gives Φ(t) = ∂(q, q̇)(t)/∂(q₀, q̇₀) and ∂(q, q̇)(t)/∂p at the
/// samples and the sensitivities of the events' times (see the
/// [module documentation](crate::integrate::sensitivity) for the method).
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar, Simulation};
/// /// ẍ = −k x from rest at x₀ = 1: x(t) = cos(√k t), ∂x/∂k = −t sin(√k t)/(2√k).
/// struct Spring { k: f64 }
/// impl Lagrangian<1> for Spring {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0] * self.k) * 0.5 }
/// }
/// let spring = Spring { k: 4.0 };
/// let run = Simulation::new(&spring, [1.0], [0.0])
///     .until(1.0)
///     .sensitivity()
///     .parameter("k", spring.k, |k| Spring { k })
///     .run()
///     .unwrap();
/// let dxdk = run.dparams.last().unwrap()[(0, 0)];
/// assert!((dxdk - (-(2.0_f64).sin() / 4.0)).abs() < 1e-9);
/// ```
pub struct Sensitivity<'a, L, const N: usize> {
    sim: Simulation<'a, L, N>,
    params: Vec<Parameter<L>>,
    motion_steps: bool,
    /// Why a parameter asked for could not be taken (`run` refuses with it).
    unknown: Option<String>,
    /// The parameters' columns at the start where the start depends on them (a constrained
    /// run: ∂/∂p of the start's projection onto the constraints of the system at p), 2N each.
    param_start: Option<Vec<f64>>,
}

impl<'a, L: Lagrangian<N>, const N: usize> Simulation<'a, L, N> {
    /// This run with the variational equations integrated along: its
    /// [`run`](Sensitivity::run) returns the trajectory with Φ(t) = ∂(q, q̇)(t)/∂(q₀, q̇₀) at
    /// every sample and the sensitivities of the events' times
    /// ([`Sensitivities`](crate::Sensitivities)). Takes the explicit methods: `Method::Dop853`
    /// (the default), `Method::DormandPrince`, `Method::Taylor` (a system with a compiled series:
    /// the symbolic mode) and `Method::Rk4`; see [`Sensitivity`] for what is refused.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// /// ẍ = x (unstable): Φ₀₀(t) = cosh t.
    /// struct Up;
    /// impl Lagrangian<1> for Up {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] + q[0] * q[0]) * 0.5 }
    /// }
    /// let run = Simulation::new(&Up, [0.0], [0.0]).until(1.0).sensitivity().run().unwrap();
    /// assert!((run.final_phi()[(0, 0)] - 1.0_f64.cosh()).abs() < 1e-10);
    /// ```
    pub fn sensitivity(self) -> Sensitivity<'a, L, N> {
        Sensitivity {
            sim: self,
            params: Vec::new(),
            motion_steps: false,
            unknown: None,
            param_start: None,
        }
    }
}

impl<'a, L: Lagrangian<N>, const N: usize> Sensitivity<'a, L, N> {
    /// Also differentiate the motion with respect to the parameter `name`, whose value in the
    /// system of the run is `value`, with `build(p)` the same system at the value p (e.g.
    /// `|g| Pendulum { g, ..pendulum }` for a field `g`): ∂(q, q̇)/∂p at every sample
    /// ([`Sensitivities::dparams`](crate::Sensitivities::dparams)) and dt*/dp at every event.
    /// Where `build` sets fields the compiled kernels read (the symbolic mode; `p`, `2.0 * p`,
    /// `p + c`: affine in p, checked here at three values of p), ∂q̈/∂p is exact: the kernel
    /// evaluated in tangents seeded along those fields. Otherwise (the jets mode, a hand-written
    /// system, a closure that is not affine in p), and where the kernel declines at a state, it
    /// comes from a fourth-order central difference of the accelerations of the systems
    /// `build` gives at p ± h, p ± 2h, h = ε^(1/5) s with the scale s that the accelerations at
    /// the initial state vary on, |p| or 1, whichever Richardson's error estimate prefers (a mass
    /// of 1e-6 varies on 1e-6, an offset of 1000 in cos(x − x₀) on 1): accurate to about 1e-12
    /// relative for a smooth dependence, exact to round-off for one linear in p.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// /// A falling body, ẍ = −g: ∂x(t)/∂g = −t²/2.
    /// struct Fall { g: f64 }
    /// impl Lagrangian<1> for Fall {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 - q[0] * self.g }
    /// }
    /// let fall = Fall { g: 9.81 };
    /// let run = Simulation::new(&fall, [0.0], [0.0]).until(2.0).sensitivity()
    ///     .parameter("g", fall.g, |g| Fall { g })
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(run.parameters, vec!["g".to_string()]);
    /// assert!((run.dparams.last().unwrap()[(0, 0)] + 2.0).abs() < 1e-10);
    /// ```
    pub fn parameter(
        mut self,
        name: impl Into<String>,
        value: f64,
        build: impl Fn(f64) -> L,
    ) -> Self {
        // The step, from the accelerations at the run's initial state (see `difference_step`).
        let (q0, v0, t0) = (self.sim.o.q0, self.sim.o.qdot0, self.sim.o.t0);
        let h = difference_step(value, |p| {
            build(p)
                .accelerations(&q0, &v0, t0)
                .ok()
                .map(|a| a.to_vec())
        });
        let slots = if System::flags(&*self.sim.sys).constrained {
            // q̈ is then the constrained view's, not the kernel's alone.
            None
        } else {
            affine_slots(&*self.sim.sys, value, &build)
        };
        self.params
            .push(Parameter::new(name.into(), value, h, build, slots));
        self
    }

    /// Also differentiate the motion with respect to the field `name` of the system (`"g"` for
    /// `self.g`; `"r.x"` for a component of a `Vector3` field), exactly: the compiled kernels
    /// evaluated in tangents seeded along that field (the symbolic mode; the fields are those
    /// [`Lagrangian::KERNEL_FIELDS`] names, the ones L, D and Q read). Its value is the
    /// system's. [`run`](Self::run) refuses a name the kernels do not read, and a system without
    /// compiled kernels (the jets mode, a hand-written impl: give the parameter with its closure,
    /// [`parameter`](Self::parameter)); where the kernel declines at a state (a pivot of M below
    /// the accuracy bound), the run stops with a typed error.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// /// A hand-written system has no compiled kernels: its fields are not seeded.
    /// struct Fall { g: f64 }
    /// impl Lagrangian<1> for Fall {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 - q[0] * self.g }
    /// }
    /// let err = Simulation::new(&Fall { g: 9.81 }, [0.0], [0.0]).until(2.0).sensitivity()
    ///     .field("g")
    ///     .run()
    ///     .unwrap_err();
    /// assert!(err.to_string().contains(".parameter(\"g\""));
    /// ```
    pub fn field(mut self, name: &str) -> Self {
        let fields = L::KERNEL_FIELDS;
        let slots = kernel_slots(&*self.sim.sys);
        match (fields.iter().position(|f| *f == name), slots) {
            (Some(slot), Some(values)) if values.len() == fields.len() => {
                self.params.push(Parameter::field(
                    name.into(),
                    values[slot],
                    slot,
                    values.len(),
                ));
            }
            _ if self.unknown.is_some() => {}
            _ if fields.is_empty() => {
                self.unknown = Some(format!(
                    "field `{name}`: this system has no compiled kernels to seed its fields in \
                     (the jets mode or a hand-written impl; `#[lagrangian]`'s symbolic mode \
                     has them): give the parameter with its closure, \
                     `.parameter(\"{name}\", value, |p| System {{ {name}: p, ..system }})`"
                ));
            }
            _ => {
                let known: Vec<&str> = fields.iter().copied().filter(|f| !f.is_empty()).collect();
                self.unknown = Some(format!(
                    "field `{name}` is not one the compiled kernels read (they read {}): name \
                     one of those, or give the parameter with its closure, \
                     `.parameter(name, value, build)`",
                    if known.is_empty() {
                        "no field of the system".to_string()
                    } else {
                        known.join(", ")
                    }
                ));
            }
        }
        self
    }

    /// Take the plain run's steps: the error control of an adaptive method weighs the motion
    /// alone (by default it weighs the variations too, and the larger error decides). The
    /// motion is then the plain run's bit for bit, and Φ the exact derivative of that run's
    /// discrete flow (its steps held fixed): what a gradient of the computed trajectory needs.
    /// Φ's own error is then not controlled: at an equilibrium, where the motion allows any
    /// step, it can be large. The Taylor method always takes the motion's steps.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation};
    /// /// A pendulum, θ̈ = −sin θ.
    /// struct Pendulum;
    /// impl Lagrangian<1> for Pendulum {
    ///     const COORDINATES: [&'static str; 1] = ["theta"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// }
    /// let plain = Simulation::new(&Pendulum, [1.0], [0.0]).until(5.0).run().unwrap();
    /// let with = Simulation::new(&Pendulum, [1.0], [0.0]).until(5.0).sensitivity().motion_steps().run().unwrap();
    /// assert_eq!(with.trajectory.q, plain.q);
    /// assert_eq!(with.trajectory.stats.steps, plain.stats.steps);
    /// ```
    pub fn motion_steps(mut self) -> Self {
        self.motion_steps = true;
        self
    }

    /// Runs the motion with its variational equations.
    ///
    /// Fails like [`Simulation::run`], and with [`SimulationError::InvalidOptions`] (before any
    /// step) for what it does not cover yet: constraints (RATTLE) or a field alone with the
    /// variational integrator (`Method::VariationalMidpoint`), parameters of a run with a resetting event
    /// or contacts, of a run built with `Simulation::constrained`, or a field alone (`.field`) in
    /// a constrained run (a constrained run built by `Simulation::new` takes parameters given by
    /// their closure), a parameter whose value is not finite, a field the
    /// compiled kernels do not read ([`field`](Self::field)), an impact at the start; and with
    /// [`SimulationError::Dynamics`] where Φ has no value: an event firing grazing,
    /// contacts closing at a Zeno accumulation.
    ///
    /// Through contacts (`fn contacts`) Φ jumps at each impact, closing and lift-off by the
    /// transition's saltation matrix, each piece taken in the contacts' mode on its side of the
    /// jump (the mode before it for the event's function, f⁻ and the impact map's differences;
    /// the mode after it for f⁺); while a contact is closed the variations follow the Jacobian
    /// of the constrained accelerations.
    ///
    /// With `Method::Radau5` Φ is the exact derivative of the method's discrete flow over the
    /// steps the motion takes (the stages' Jacobians from the jets; see the
    /// [module documentation](crate::sensitivity)): its error is that of the method's, not
    /// controlled separately. With `Method::VariationalMidpoint`, the derivative of its
    /// discrete map.
    ///
    /// Through a resetting event Φ jumps with the state: Φ⁺ = S Φ⁻, S the jump's saltation
    /// matrix (see the [module documentation](crate::sensitivity)); an event that fires grazing
    /// (crossing zero at zero rate) has none, and is an error.
    ///
    /// A constrained run (holonomic or velocity constraints) integrates the variations with the
    /// Jacobian of its constrained accelerations. Its Φ(t) maps a perturbation of the start to
    /// the perturbation of the run started there after projecting it onto the constraints, as
    /// [`project_initial_state`](Simulation::project_initial_state) does: Φ(t0) = P, the
    /// derivative of that projection (the identity on perturbations tangent to the
    /// constraints, zero along their normals), and every column stays tangent to them. The samples' memory bound
    /// ([`Simulation::max_samples`]) counts Φ with each sample: by default as many samples fit
    /// in 256 MiB with their matrices.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method};
    /// /// A constant force k: x(t) = x₀ + v₀ t + k t²/2, which the variational midpoint method
    /// /// integrates exactly: ∂x(1)/∂k = 1/2.
    /// struct Push { k: f64 }
    /// impl Lagrangian<1> for Push {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
    ///         v[0] * v[0] * 0.5 + q[0] * self.k
    ///     }
    /// }
    /// let run = Simulation::new(&Push { k: 2.0 }, [0.0], [1.0])
    ///     .method(Method::VariationalMidpoint { dt: 1e-2 })
    ///     .until(1.0)
    ///     .sensitivity()
    ///     .parameter("k", 2.0, |k| Push { k })
    ///     .run()
    ///     .unwrap();
    /// assert!((run.dparams.last().unwrap()[(0, 0)] - 0.5).abs() < 1e-12);
    /// ```
    pub fn run(mut self) -> Result<Sensitivities<N>, SimulationError> {
        self.refusal().map_or(Ok(()), |message| {
            Err(SimulationError::InvalidOptions { message })
        })?;
        // A system that declares its constraints runs on its constrained view, as
        // `Simulation::run` runs it.
        let flags = System::flags(&*self.sim.sys);
        if self.sim.o.manifold.is_none() && (flags.constrained || flags.contacts) {
            let Sensitivity {
                sim: Simulation { sys, o },
                motion_steps,
                params,
                ..
            } = self;
            return (*sys).declared(Declared {
                o,
                motion_steps,
                params,
            });
        }
        let n2 = 2 * N;
        let cols = n2 + self.params.len();
        let sim = &mut self.sim;
        let mut p = sim.prepare()?;
        no_impact_at_start(p.start_jump.as_ref())?;
        // A sample of this run holds its variations too.
        let bytes = sample_bytes(N, p.manifold.map_or(0, |m| m.count())) + 8 * n2 * cols;
        if p.opts.max_samples_default {
            // The default budget holds the samples with their variations.
            p.opts.max_samples = (SAMPLE_BUDGET_BYTES / bytes).max(2);
        }
        let (t0, until, method, y0, hmax) = (p.opts.t0, p.opts.until, p.method, p.y0, p.hmax);
        let params = &self.params;
        // The parameters whose ∂q̈/∂p the kernels give exactly: their directions in the kernels'
        // parameter slots.
        let dirs = exact_dirs(params);
        let base = if dirs.is_empty() {
            None
        } else {
            kernel_slots(p.sys)
        };
        let fields = base.as_deref().map(|base| Fields { base, dirs: &dirs });
        let (mut cols0, phi_unit) = start_columns(p.manifold, t0, &y0, cols)?;
        if let Some(start) = &self.param_start {
            cols0[n2 * n2..].copy_from_slice(start);
        }
        // Φ's columns of the coordinates absent from L stay unit columns until a jump mixes
        // them (then every column is integrated).
        let unit = core::cell::Cell::new(phi_unit);
        let var = || Variation {
            sys: p.sys,
            params,
            phi_cols: n2,
            phi_unit: unit.get(),
            kernel: Default::default(),
            fields,
        };
        let log = RefCell::new(Log::default());
        let driver = Driver::new(p.sys, p.manifold, p.events, method, &p.opts, p.observer);
        let problem = || Variational {
            var: var(),
            log: Some(&log),
            control: !self.motion_steps,
        };
        // The columns a stepper starts from at (t, y): Φ(t0) at the start; after a jump, the
        // columns just before it times the jump's saltation matrix.
        let start_cols = |t: f64, y: &Y<N>| -> Result<Vec<f64>, Fault> {
            let log = log.borrow();
            let jumped = (0..log.events.len())
                .rev()
                .take_while(|&k| log.events[k].0 == t)
                .find(|&k| p.events[log.events[k].1].is_reset());
            let Some(k) = jumped.filter(|_| t > t0) else {
                return Ok(cols0.clone());
            };
            let (_, i, cols) = &log.events[k];
            let state = &log.states[k];
            if state.len() != n2 {
                return Err(Fault::NonFinite);
            }
            let before: Y<N> = [
                core::array::from_fn(|j| state[j]),
                core::array::from_fn(|j| state[N + j]),
            ];
            let s = saltation(p.sys, &p.events[*i], t, &before, y)?;
            unit.set(false);
            let minus = DMatrix::from_column_slice(n2, cols.len() / n2, cols);
            Ok((s * minus).as_slice().to_vec())
        };
        let traj = match (Explicit::of(method), method) {
            (Some(e), _) => driver.run_boxed(&p.opts, t0, y0, &mut |t, y, stats| {
                let cols = start_cols(t, &y)?;
                let p = problem();
                let x0 = p.state(y, cols);
                e.stepper(p, t, x0, until, hmax, stats)
            }),
            (None, Method::Taylor { tol }) => driver.run(&p.opts, t0, y0, |t, y, _stats| {
                let cols = start_cols(t, &y)?;
                Ok(VarSeries::stepper(
                    var(),
                    t,
                    y,
                    &cols,
                    tol,
                    hmax,
                    Some(&log),
                ))
            }),
            (None, Method::Radau5 { rtol, atol }) => driver.run(&p.opts, t0, y0, |t, y, stats| {
                let cols = start_cols(t, &y)?;
                let r = Radau5::new(p.sys, t, y, rtol, atol, hmax, stats)?;
                Ok(r.with_variations(cols, forcing(p.sys, params, fields), &log))
            }),
            (None, Method::VariationalMidpoint { dt }) => driver.run(&p.opts, t0, y0, |t, y, _| {
                let cols = start_cols(t, &y)?;
                let grid = FixedGrid::new(t, dt, until);
                let s = VariationalMidpoint::new(p.sys, grid, y[0], y[1]);
                let neighbours = params
                    .iter()
                    .filter_map(|par| par.difference.as_ref())
                    .map(|(h, systems)| (*h, systems.each_ref().map(|s| s as &dyn System<N>)))
                    .collect();
                Ok(s.with_variations(cols, neighbours, &log))
            }),
            // Refused above.
            _ => {
                return Err(SimulationError::InvalidOptions {
                    message: unsupported_method(method),
                });
            }
        }
        .map_err(|e| with_sample_bytes(e, bytes))?;
        let log = log.into_inner();
        let (phi, dparams) = at_samples(&traj.t, &log.samples, n2, cols)?;
        let events = traj
            .events
            .iter()
            .zip(&log.events)
            .zip(&log.rates)
            .map(|((hit, (t, i, c)), rate)| {
                let (ev, params) = (&p.events[*i], cols - n2);
                at_event(p.sys, ev, *t, &hit.q, &hit.qdot, c, params, rate.as_deref())
            })
            .collect();
        Ok(Sensitivities {
            trajectory: traj,
            phi,
            parameters: self.params.iter().map(|p| p.name.clone()).collect(),
            dparams,
            events,
        })
    }

    /// Why this run cannot carry its variations (what it does not cover yet), if so.
    fn refusal(&self) -> Option<String> {
        if let Some(unknown) = &self.unknown {
            return Some(unknown.clone());
        }
        let sim = &self.sim;
        if !sim.o.method.spec().sensitivities {
            return Some(unsupported_method(sim.o.method));
        }
        // What the system declares (`Simulation::run` takes it) counts as what the run has.
        let declares = System::flags(&*sim.sys);
        if (sim.o.contact_start.is_some() || declares.contacts) && !self.params.is_empty() {
            return Some(
                "parameter sensitivities of a run with contacts are not covered yet (Φ is, \
                 through every impact and lift-off): run without parameters, or end the run \
                 before the first impact"
                    .into(),
            );
        }
        // A constrained run takes parameters as its system declares its constraints (the
        // closure builds the system; its constrained view is taken at each neighbour); a view
        // given directly (`Simulation::constrained`) has no closure that could build it.
        if sim.o.manifold.is_some() && self.param_start.is_none() && !self.params.is_empty() {
            return Some(
                "parameter sensitivities of a run built with Simulation::constrained are taken \
                 through Simulation::new, which runs the system on its constraints as declared: \
                 Simulation::new(&sys, q0, q̇0).sensitivity().parameter(name, value, |p| ..)"
                    .into(),
            );
        }
        if let Some(e) = sim.o.events.iter().find(|e| e.is_reset())
            && !self.params.is_empty()
        {
            return Some(format!(
                "event `{}` resets the state, and this run has parameters: the reset map and \
                 the event's function are closures the parameters do not reach, so the jump's \
                 dependence on them is not known; Φ through the jump is (run without \
                 parameters), or make the event terminal and start a new run from the state \
                 after it",
                e.name()
            ));
        }
        if matches!(sim.o.method, Method::VariationalMidpoint { .. }) {
            if sim.o.manifold.is_some() || declares.constrained {
                return Some(
                    "sensitivities of a constrained run with Method::VariationalMidpoint (RATTLE) \
                     are not covered yet: use Method::Dop853 {{ rtol, atol }} or Method::Radau5"
                        .into(),
                );
            }
            if let Some(p) = self.params.iter().find(|p| p.difference.is_none()) {
                return Some(format!(
                    "parameter `{}` is a field alone (`.field`): Method::VariationalMidpoint \
                     differentiates its discrete map through the systems a parameter's closure \
                     builds, so give it with its closure, .parameter(\"{}\", value, |p| ..) \
                     (or use Method::Dop853 {{ rtol, atol }}, which takes the field exactly)",
                    p.name, p.name
                ));
            }
        }
        if let Some(p) = self.params.iter().find(|p| !p.value.is_finite()) {
            return Some(format!(
                "parameter `{}` has the value {}: give its finite value in the system of the run",
                p.name, p.value
            ));
        }
        None
    }
}

/// The columns at the start and whether Φ's are unit columns: Φ(t0) = I, S(t0) = 0; on
/// constraints (or closed contacts), Φ(t0) = P, the derivative of the projection onto them at
/// y0 (see `tangent_projector`). `cols` columns of 2N.
fn start_columns<const N: usize>(
    manifold: Option<&dyn super::super::manifold::Manifold<N>>,
    t0: f64,
    y0: &Y<N>,
    cols: usize,
) -> Result<(Vec<f64>, bool), SimulationError> {
    let n2 = 2 * N;
    // The columns at the start: Φ(t0) = I, S(t0) = 0; on constraints, Φ(t0) = P, the
    // derivative of the projection onto them at y0 (see `tangent_projector`).
    let mut cols0 = vec![0.0; n2 * cols];
    let phi_unit = match manifold {
        None => {
            for j in 0..n2 {
                cols0[n2 * j + j] = 1.0;
            }
            true
        }
        Some(m) => {
            let projector =
                tangent_projector(m, t0, y0).map_err(|fault| SimulationError::InvalidOptions {
                    message: format!(
                        "the projection onto the constraints near the initial state failed \
                         ({fault:?}), so the derivative of the run with respect to its start \
                         is not defined there: start away from where the constraints are \
                         singular"
                    ),
                })?;
            cols0[..n2 * n2].copy_from_slice(&projector);
            false
        }
    };
    Ok((cols0, phi_unit))
}

/// Refuses a run that starts with an impact (a contact touching and approaching at t0): Φ
/// through it is not covered.
fn no_impact_at_start<const N: usize>(
    jump: Option<&super::super::events::Jump<N>>,
) -> Result<(), SimulationError> {
    match jump {
        None => Ok(()),
        Some(jump) => Err(SimulationError::InvalidOptions {
            message: format!(
                "the run starts with an impact (contact `{}` touches and approaches at t = {}): \
                 Φ through an impact at the start is not covered; start the sensitivity run \
                 from the state after it (q = {:?}, q̇ = {:?})",
                jump.event, jump.t, jump.after.0, jump.after.1
            ),
        }),
    }
}

/// The refusal of a method the sensitivity runs do not take.
fn unsupported_method(method: Method) -> String {
    format!(
        "sensitivity runs integrate the variational equations with {}; {method:?} is not \
         covered yet: use Method::Dop853 {{ rtol, atol }} (the default, adaptive, with dense \
         output for samples and events)",
        Method::takers(|s| s.sensitivities)
    )
}

/// The parameters' ∂f/∂p at a state (their columns' forcing in Radau5's steps): exact from the
/// kernels along `fields`' directions where a parameter has one, else its differences; none
/// without parameters.
fn forcing<'a, L: Lagrangian<N>, const N: usize>(
    sys: &'a L,
    params: &'a [Parameter<L>],
    fields: Option<Fields<'a>>,
) -> Option<Forcing<'a, N>> {
    (!params.is_empty()).then(|| {
        let kernel = RefCell::new(Vec::new());
        Box::new(move |t: f64, y: &Y<N>| {
            let [q, v] = y;
            let exact = fields
                .and_then(|f| {
                    compiled_along::<L, N, true>(
                        sys,
                        &mut kernel.borrow_mut(),
                        Some(f),
                        false,
                        q,
                        v,
                        t,
                    )
                })
                .map_or(Vec::new(), |(_, _, d)| d);
            let mut exact = exact.iter();
            let mut fp = vec![0.0; 2 * N * params.len()];
            for (k, par) in params.iter().enumerate() {
                let a = match par.slots.as_ref().and_then(|_| exact.next()) {
                    Some(d) => *d,
                    None => par.difference_at(q, v, t)?,
                };
                fp[2 * N * k + N..2 * N * (k + 1)].copy_from_slice(&a);
            }
            Ok(fp)
        }) as Forcing<'a, N>
    })
}

/// A run's failure with the memory limit's message counting the bytes of a sample with its
/// variations.
fn with_sample_bytes(e: SimulationError, bytes: usize) -> SimulationError {
    match e {
        SimulationError::MaxSamples {
            t,
            q,
            qdot,
            max_samples,
            default_limit,
            partial,
            ..
        } => SimulationError::MaxSamples {
            t,
            q,
            qdot,
            max_samples,
            sample_bytes: bytes,
            default_limit,
            partial,
        },
        e => e,
    }
}

/// Φ and S (2N × 2N and 2N × (cols − 2N)) at the samples the trajectory kept (times `kept`):
/// the log has every sample recorded (a repeated time once more, all of them where the
/// trajectory keeps the first and the latest), in the same order.
#[allow(clippy::type_complexity)]
fn at_samples(
    kept: &[f64],
    samples: &[(f64, Vec<f64>)],
    n2: usize,
    cols: usize,
) -> Result<(Vec<DMatrix<f64>>, Vec<DMatrix<f64>>), SimulationError> {
    let mut phi = Vec::with_capacity(kept.len());
    let mut dparams = Vec::with_capacity(kept.len());
    let mut next = 0;
    for &t in kept {
        while next < samples.len() && samples[next].0 != t {
            next += 1;
        }
        let Some((_, c)) = samples.get(next) else {
            return Err(SimulationError::InvalidOptions {
                message: format!(
                    "internal: no variations were recorded with the sample at t = {t}; please \
                     report this with the run's options"
                ),
            });
        };
        phi.push(DMatrix::from_column_slice(n2, n2, &c[..n2 * n2]));
        dparams.push(DMatrix::from_column_slice(n2, cols - n2, &c[n2 * n2..]));
    }
    Ok((phi, dparams))
}

/// The run of a system as it declares itself with these options and its variations: a system
/// with constraints runs on its constrained view (the one `Simulation::run` takes).
struct Declared<'a, L, const N: usize> {
    o: super::super::simulation::Options<'a, N>,
    motion_steps: bool,
    params: Vec<Parameter<L>>,
}

impl<'s, 'a: 's, L: Lagrangian<N> + 's, const N: usize> crate::lagrangian::Declared<'s, L, N>
    for Declared<'a, L, N>
{
    type Output = Result<Sensitivities<N>, SimulationError>;

    fn plain(self, sys: &'s L) -> Self::Output {
        let mut run = Simulation {
            sys: super::super::simulation::Sys::Borrowed(sys),
            o: self.o,
        }
        .sensitivity();
        run.motion_steps = self.motion_steps;
        run.params = self.params;
        run.run()
    }

    /// The run on the constrained view; each parameter's ∂q̈/∂p from the views of the systems
    /// its closure built (the constrained accelerations' fourth-order difference: the
    /// constraints may read the parameter too), its column at the start from those views'
    /// projections of the start (the start moves with a constraint that reads p).
    fn constrained<const K: usize>(self, sys: &'s L) -> Self::Output
    where
        L: crate::constraints::Holonomic<N, K>,
    {
        use super::super::manifold::Manifold;
        let Declared {
            o,
            motion_steps,
            params,
        } = self;
        let (t0, y0) = (o.t0, [o.q0, o.qdot0]);
        let n2 = 2 * N;
        let mut start = vec![0.0; n2 * params.len()];
        let mut views = Vec::with_capacity(params.len());
        for (k, par) in params.iter().enumerate() {
            let Some((h, systems)) = &par.difference else {
                return Err(SimulationError::InvalidOptions {
                    message: format!(
                        "parameter `{}` is a field alone (`.field`), whose derivative comes from \
                         the unconstrained kernel; a constrained run differentiates the \
                         constrained accelerations: give it with its closure, \
                         .parameter(\"{}\", value, |p| ..)",
                        par.name, par.name
                    ),
                });
            };
            let view = systems.each_ref().map(crate::constraints::Constrained::new);
            let mut ends = [y0; 4];
            for (v, y) in view.iter().zip(ends.iter_mut()) {
                v.project(t0, y)
                    .map_err(|fault| SimulationError::InvalidOptions {
                        message: format!(
                            "the start's projection onto the constraints with parameter `{}` moved \
                         to a neighbouring value failed ({fault:?}): the derivative with \
                         respect to it is not defined at this start",
                            par.name
                        ),
                    })?;
            }
            for i in 0..n2 {
                let at = |e: usize| ends[e][i / N][i % N];
                start[n2 * k + i] = central(*h, [at(0), at(1), at(2), at(3)]);
            }
            views.push(Parameter {
                name: par.name.clone(),
                value: par.value,
                slots: None,
                difference: Some((*h, view)),
            });
        }
        let mut sim = Simulation::constrained(sys, o.q0, o.qdot0);
        sim.o = sim.o.adopt(o);
        let mut run = sim.sensitivity();
        run.motion_steps = motion_steps;
        run.params = views;
        run.param_start = Some(start);
        run.run()
    }

    fn contacts<const K: usize>(self, sys: &'s L) -> Self::Output
    where
        L: crate::contact::Unilateral<N, K>,
    {
        let mut sim = Simulation::contacts(sys, self.o.q0, self.o.qdot0);
        sim.o = sim.o.adopt(self.o);
        let mut run = sim.sensitivity();
        run.motion_steps = self.motion_steps;
        run.run()
    }
}

/// P = ∂π/∂y at y0 for the projection π onto the constraints that a run starts with
/// ([`Manifold::project`]: q along the rows of G, then q̇), column-major 2N × 2N: central
/// differences of π over steps ε^⅓ max(|y_k|, 1) (error ~1e-10 of P's entries, which are of
/// order one: P is a projector).
fn tangent_projector<const N: usize>(
    m: &dyn super::super::manifold::Manifold<N>,
    t0: f64,
    y0: &super::super::state::Y<N>,
) -> Result<Vec<f64>, super::super::state::Fault> {
    let n2 = 2 * N;
    let mut p = vec![0.0; n2 * n2];
    for k in 0..n2 {
        let x = y0[k / N][k % N];
        let h = f64::EPSILON.cbrt() * x.abs().max(1.0);
        let at = |d: f64| {
            let mut y = *y0;
            y[k / N][k % N] = x + d;
            m.project(t0, &mut y).map(|_| y)
        };
        let (up, down) = (at(h)?, at(-h)?);
        for i in 0..n2 {
            p[n2 * k + i] = (up[i / N][i % N] - down[i / N][i % N]) / (2.0 * h);
        }
    }
    Ok(p)
}
