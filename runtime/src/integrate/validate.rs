//! The checks of a [`Simulation`]'s options before any step: ranges, the sample grid, and the
//! system's `CYCLIC` declaration. A failed check is
//! [`SimulationError::InvalidOptions`](super::SimulationError::InvalidOptions).

use super::method::Method;
use super::simulation::Options;
use super::system::System;

impl<const N: usize> Options<'_, N> {
    /// Checks the options of a run of `sys`: the end time, or the message of the error.
    pub(super) fn validate(&self, sys: &dyn System<N>) -> Result<f64, String> {
        let until = self.check_times()?;
        self.check_declared(sys)?;
        self.check_takes()?;
        let spec = self.method.spec();
        if let Some(dt) = spec.fixed_dt {
            self.check_fixed_step(dt, until)?;
        }
        if let Some((rtol, atol)) = spec.tolerances {
            self.check_tolerances(rtol, atol, until)?;
        }
        if let Method::Taylor { tol } = self.method {
            self.check_taylor(sys, tol, until)?;
        }
        if let Some(h) = self.max_step {
            positive("max_step", h)?;
        }
        self.check_sampling(until)?;
        if self.max_steps == 0 {
            return Err("max_steps must be at least 1".to_string());
        }
        Ok(until)
    }

    /// The end time, after it and the start time and the initial state are checked.
    fn check_times(&self) -> Result<f64, String> {
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
        Ok(until)
    }

    /// What the system declares is never dropped: a run that reaches here without its
    /// constraints or contacts would step the unconstrained motion (a pendulum in x, y falling
    /// off its rod, two masses passing through each other) and answer wrongly without a word.
    /// `Simulation::run` takes them from the system (`Lagrangian::declared`); what comes here
    /// without them is an analysis that does not take them yet, or a hand-written impl that
    /// does not say how many it has.
    fn check_declared(&self, sys: &dyn System<N>) -> Result<(), String> {
        let flags = sys.flags();
        if self.manifold.is_none() && flags.constrained {
            return Err("this system declares constraints (`fn constraints` or \
                 `fn velocity_constraints`), which this run would drop (it would step the \
                 unconstrained motion): Lyapunov exponents and periodic orbits (Shooting) do not \
                 take constraints yet, so write the system in coordinates that satisfy them; a \
                 hand-written `impl Holonomic<N, K>` runs with Simulation::constrained(&system, \
                 q0, q̇0), or with Simulation::new once its `Lagrangian::declared` says \
                 `v.constrained::<K>(self)`"
                .to_string());
        }
        if self.contact_start.is_none() && flags.contacts {
            return Err(
                "this system declares contacts (`fn contacts`), which this run would drop \
                 (bodies would pass through each other): Lyapunov exponents and periodic orbits \
                 (Shooting) do not take contacts yet, and Simulation::constrained runs the \
                 constraints alone — Simulation::new runs a system's contacts with its \
                 constraints; a hand-written `impl Unilateral<N, K>` runs with \
                 Simulation::contacts(&system, q0, q̇0), or with Simulation::new once its \
                 `Lagrangian::declared` says `v.contacts::<K>(self)`"
                    .to_string(),
            );
        }
        Ok(())
    }

    /// Whether the method takes what the run has (contacts, constraints, velocity constraints,
    /// resets), from its [`spec`](Method::spec); a refusal names the methods that do.
    fn check_takes(&self) -> Result<(), String> {
        let spec = self.method.spec();
        let name = spec.name;
        if self.contact_start.is_some() {
            if !spec.contacts {
                return Err(format!(
                    "{name} does not run contacts (their closed set changes at every impact and \
                     lift-off): use {}",
                    Method::takers(|s| s.contacts)
                ));
            }
            return Ok(());
        }
        let Some(m) = &self.manifold else {
            return Ok(());
        };
        if let Some(e) = self.events.iter().find(|e| e.is_reset()) {
            return Err(format!(
                "event \"{}\" resets the state, and this run has constraints: a jump must \
                 land on the constraints (q on g = 0, q̇ with G q̇ + ∂g/∂t = 0), which a reset map \
                 does not know, so constrained runs take no resetting events yet; run the system \
                 without constraints (in coordinates that satisfy them), or end the run with a \
                 terminal event and start a new one from the state you want",
                e.name()
            ));
        }
        if !spec.constraints {
            return Err(format!(
                "{name} does not take holonomic constraints yet: use {} for a constrained run \
                 (Method::Dop853, the default, projects the state onto the constraints after \
                 every step; Method::VariationalMidpoint is RATTLE, whose nodes satisfy them)",
                Method::takers(|s| s.constraints)
            ));
        }
        if m.velocity_rows() > 0 && !spec.velocity_constraints {
            return Err(format!(
                "{name} keeps holonomic constraints g(q) = 0 at every node, and this system has \
                 {} velocity (nonholonomic) constraint(s), which its discrete form does not take \
                 yet: use {} (Method::Dop853, the default, projects q̇ onto A q̇ + b = 0 after \
                 every step)",
                m.velocity_rows(),
                Method::takers(|s| s.velocity_constraints)
            ));
        }
        Ok(())
    }

    /// The fixed step dt against the time resolution of the run.
    fn check_fixed_step(&self, dt: f64, until: f64) -> Result<(), String> {
        positive("dt", dt)?;
        // Adjacent f64 times near the end of the run differ by up to ε·|t|: a step that is not
        // many times larger cannot be represented (t + dt rounds to t, or the steps come out
        // uneven by whole ulps).
        let spacing = self.t0.abs().max(until.abs()) * f64::EPSILON;
        if dt < 1024.0 * spacing {
            return Err(format!(
                "dt = {dt:e} is below the time resolution of the run: near t = {:e} adjacent f64 \
                 times differ by about {spacing:.1e}, so the step grid t0 + k·dt cannot be \
                 represented (steps of zero or uneven length). Shift the time origin (start at \
                 t0 = 0 and add the offset inside your forces or L), or take dt ≥ {:.1e}",
                self.t0.abs().max(until.abs()),
                1024.0 * spacing
            ));
        }
        Ok(())
    }

    /// The tolerances of an adaptive method, and the run against the time resolution.
    fn check_tolerances(&self, rtol: f64, atol: f64, until: f64) -> Result<(), String> {
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
        // The time resolution: a run shorter than 1024 adjacent f64 times cannot be cut into
        // steps (t + h rounds to t), whatever the dynamics (t0 = 1e15: times are 0.125 apart);
        // the step would underflow and look like stiffness.
        let far = self.t0.abs().max(until.abs());
        let spacing = far * f64::EPSILON;
        if until - self.t0 < 1024.0 * spacing {
            return Err(format!(
                "the run from t0 = {:e} to {until:e} is below the time resolution: near \
                 t = {far:e} adjacent f64 times differ by about {spacing:.1e}, so the run of \
                 {:.1e} cannot be cut into steps. Shift the time origin (start at t0 = 0 and add \
                 the offset inside your forces or L if they read t)",
                self.t0,
                until - self.t0
            ));
        }
        Ok(())
    }

    /// The Taylor method's tolerance against the time resolution, and the system's series.
    fn check_taylor(&self, sys: &dyn System<N>, tol: f64, until: f64) -> Result<(), String> {
        if !(1e-26..1.0).contains(&tol) {
            return Err(format!(
                "the Taylor method's tol = {tol:e} must be in [1e-26, 1) (it is the local error \
                 per step, absolute for states of size ≤ 1, relative above)"
            ));
        }
        // The time resolution: adjacent f64 times near the run differ by `spacing`. A run
        // shorter than 1024 of them cannot be cut into steps (as for the fixed steps), and where
        // rounding each step's end time (up to spacing / 2) moves the state by 1000 times the
        // error a step is allowed, the answer is the rounding's, not the method's (t0 = 1e9:
        // spacing 1.2e-7 against tol 1e-12).
        let far = self.t0.abs().max(until.abs());
        let spacing = far * f64::EPSILON;
        if until - self.t0 < 1024.0 * spacing {
            return Err(format!(
                "the run [{}, {until}] is below the time resolution: near t = {far:e} adjacent \
                 f64 times differ by about {spacing:.1e}, so the run cannot be cut into Taylor \
                 steps. Shift the time origin (start at t0 = 0 and add the offset inside your \
                 forces or L), or make the run longer than {:.1e}",
                self.t0,
                1024.0 * spacing
            ));
        }
        if 0.5 * spacing > 1e3 * tol {
            // A run far from t = 0 moves its origin; a long run from near 0 is cut into
            // segments short enough for this tol (spacing(len) / 2 ≤ 1000 tol).
            let fix = if self.t0.abs() >= 0.5 * until.abs() {
                "Shift the time origin (start at t0 = 0 and add the offset inside your forces or \
                 L)"
                .to_string()
            } else {
                format!(
                    "Cut the run into segments of at most {:.1e} in time, each started at t0 = 0 \
                     from the previous segment's end state (with the elapsed time added inside \
                     your forces or L if they read t)",
                    2e3 * tol / f64::EPSILON
                )
            };
            return Err(format!(
                "the Taylor method's tol = {tol:e} is far below the time resolution of the run: \
                 near t = {far:e} adjacent f64 times differ by about {spacing:.1e}, so rounding \
                 each step's end time moves the state by more than 1000 × tol per step (a wrong \
                 answer that looks accurate). {fix}, or take tol ≥ {:.1e}",
                spacing / 2e3
            ));
        }
        if let Some(what) = sys.not_analytic() {
            return Err(format!(
                "the Taylor method needs a body that is analytic along the motion (each step \
                 sums one series, which runs straight across a kink or a jump without seeing \
                 it), and this system uses {what}. Use Method::Dop853 (an adaptive step resolves \
                 the kink; an Event at the switch locates it), or write the body with a smooth \
                 function (x.abs() ≈ (x * x + ε²).sqrt())"
            ));
        }
        if !sys.has_series(&[self.q0, self.qdot0], self.t0) {
            return Err("the Taylor method needs the system's Taylor series, which \
                 `#[lagrangian]` generates in its default symbolic mode for systems of up to \
                 1024 series (expression nodes the equations need; more would cost seconds of \
                 build time): this system was written in jets mode or by hand, or is larger. Use \
                 Method::Dop853, or declare the system with the symbolic mode"
                .to_string());
        }
        Ok(())
    }

    /// The sample grid or the sample times: on a fixed-step method's grid, within the run, in
    /// order, and within the memory bound.
    fn check_sampling(&self, until: f64) -> Result<(), String> {
        let fixed_dt = self.method.spec().fixed_dt;
        if let Some(ds) = self.sample_every {
            positive("sample_every", ds)?;
            if let Some(dt) = fixed_dt {
                let ratio = ds / dt;
                if ratio < 1.0 - 1e-9 || (ratio - ratio.round()).abs() > 1e-9 * ratio {
                    return Err(format!(
                        "sample_every = {ds} is not a multiple of the fixed step dt = {dt}: \
                         fixed-step methods record the steps that land on the sample grid; \
                         choose sample_every = k·dt (e.g. {}) or dt = sample_every / k",
                        dt * ratio.round().max(1.0)
                    ));
                }
            }
        }
        self.check_sample_count(until)?;
        let Some(times) = &self.sample_at else {
            return Ok(());
        };
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
            if let Some(dt) = fixed_dt {
                let k = (ts - self.t0) / dt;
                if ts != until && (k - k.round()).abs() > 1e-9 * k.max(1.0) {
                    return Err(format!(
                        "sample_at time {ts} (index {i}) is not on the fixed step grid t0 + k·dt \
                         (t0 = {}, dt = {dt}): fixed-step methods record the steps that land on \
                         the sample times; choose times on the grid (e.g. {}) or use an adaptive \
                         method, whose dense output serves any time",
                        self.t0,
                        self.t0 + k.round() * dt
                    ));
                }
            }
        }
        Ok(())
    }

    /// The trajectory's length against the memory bound: t0 + kΔ for k = 0 … ⌊(until − t0)/Δ⌋
    /// and `until` if it is off that grid; or t0, sample_at's times and `until`.
    fn check_sample_count(&self, until: f64) -> Result<(), String> {
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
        let max_samples = self.max_samples_bound();
        // Without keep_samples the trajectory stores two samples whatever the grid is.
        if self.keep_samples && samples > max_samples as f64 {
            let asked = match self.sample_every {
                Some(ds) => format!(
                    "sample_every = {ds:e} over [{}, {until}] asks for {samples:.3e} samples",
                    self.t0
                ),
                None => format!("sample_at asks for {samples} samples (with t0 and until)"),
            };
            return Err(format!(
                "{asked}, more than {}: sample less often, shorten the run, or raise the limit \
                 with .max_samples(n)",
                super::trajectory::max_samples_phrase(
                    max_samples,
                    self.sample_bytes(),
                    self.max_samples.is_none()
                )
            ));
        }
        Ok(())
    }

    /// Checks the system's `CYCLIC` declaration at the initial state: q̈ must not change when a
    /// coordinate declared cyclic is shifted. The explicit methods rely on it (they do not form
    /// the stage positions of cyclic coordinates), and the momenta reported as conserved do too.
    /// Skipped where the dynamics fail at the initial state (the run reports that).
    pub(super) fn check_cyclic(&self, sys: &dyn System<N>) -> Result<(), String> {
        const SHIFT: f64 = 0.739_085_133_215_160_6;
        let Ok(a0) = sys.accelerations(&self.q0, &self.qdot0, self.t0) else {
            return Ok(());
        };
        let flags = sys.flags();
        for i in (0..N).filter(|&i| flags.cyclic[i]) {
            let mut q = self.q0;
            q[i] += SHIFT;
            let a1 = sys.accelerations(&q, &self.qdot0, self.t0);
            let same = a1.as_ref().is_ok_and(|a1| {
                a0.iter()
                    .zip(a1)
                    .all(|(x, y)| (x - y).abs() <= 1e-9 * (x.abs() + y.abs()) + 1e-300)
            });
            if !same {
                let name = flags.coordinates[i];
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
}

/// `x` positive and finite, or the message naming it.
fn positive(name: &str, x: f64) -> Result<(), String> {
    if x > 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err(format!("{name} = {x} must be positive and finite"))
    }
}
