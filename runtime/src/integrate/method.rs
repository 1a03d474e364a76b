//! [`Method`]: the integration methods a [`Simulation`](super::Simulation) can run, with their
//! parameters.

/// The integration method.
///
/// The enum is `#[non_exhaustive]`: more methods are coming, so a `match` on it outside this
/// crate needs a wildcard arm (e.g. `_ => …`, or [`is_fixed_step`](Method::is_fixed_step) to tell
/// the two kinds apart).
///
/// ```
/// use lagrange::prelude::*;
///
/// /// A pendulum of length 1 under g = 9.81.
/// pub struct Pendulum;
///
/// #[lagrangian]
/// impl Pendulum {
///     fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
///         0.5 * theta_dot * theta_dot + 9.81 * theta.cos()
///     }
/// }
///
/// // The same swing by an adaptive and a symplectic fixed-step method.
/// let m = Method::Dop853 { rtol: 1e-10, atol: 1e-12 };
/// assert!(!m.is_fixed_step());
/// assert!(Method::VariationalMidpoint { dt: 1e-3 }.is_fixed_step());
/// let swing = |m| Simulation::new(&Pendulum, [0.5], [0.0]).method(m).until(1.0).run().unwrap();
/// let (a, b) = (swing(m), swing(Method::VariationalMidpoint { dt: 1e-3 }));
/// assert!((a.q.last().unwrap()[0] - b.q.last().unwrap()[0]).abs() < 1e-5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
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
        /// Absolute tolerance (≥ 0; 0 is pure relative control: a component that is exactly zero
        /// with a zero error estimate passes, one with a non-zero error estimate does not).
        atol: f64,
    },
    /// DOP853, adaptive 8th order with 7th-order dense output.
    Dop853 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance (≥ 0; 0 is pure relative control: a component that is exactly zero
        /// with a zero error estimate passes, one with a non-zero error estimate does not).
        atol: f64,
    },
    /// The variational midpoint integrator (symplectic, momentum-conserving), fixed step `dt`.
    VariationalMidpoint {
        /// Step.
        dt: f64,
    },
    /// The Taylor method: each step sums the Taylor series of the motion, whose coefficients
    /// the symbolic mode of `#[lagrangian]` generates at compile time
    /// (`Lagrangian::series_in` (hidden: what `#[lagrangian]` generates)). Order and step size
    /// follow Jorba & Zou (2005): order p = ⌈−ln(tol)/2 + 1⌉, step
    /// h = min(ρ_{p−1}, ρ_p) e^{−2−0.7/(p−1)} with ρ_k = (s/‖x_k‖∞)^{1/k}, x_k the k-th
    /// coefficients of (q, q̇) and s = max(1, ‖(q, q̇)‖∞): `tol` is an absolute tolerance for
    /// states of size ≤ 1 and a relative one for larger states, on the local error of a step.
    /// Dense output (samples, events) is the Taylor polynomial itself, at no extra cost. Needs
    /// a system that provides the series (the symbolic mode, for systems of up to 1024 series:
    /// a 16-link chain is above that); constraints are not supported yet.
    Taylor {
        /// Tolerance (see above), in [1e-26, 1): below ε the order keeps growing (29 at
        /// 1e-24), which makes the truncation error of a step negligible against round-off in long
        /// runs (tol 1e-20 keeps the heavy top's energy to 1e-13 over 10⁵ nutation periods).
        tol: f64,
    },
    /// Radau IIA of order 5 (3 stages, implicit, L-stable; Hairer & Wanner's `radau5`), adaptive,
    /// for stiff systems: a stiff spring or a strong damping next to slow motion, where the
    /// explicit methods' steps are bounded by the fast mode (the error's stiffness diagnosis says
    /// so) and this one's follow the slow motion.
    ///
    /// Each step solves its stage equations by simplified Newton with the exact Jacobian
    /// ∂q̈/∂(q, q̇) = −M⁻¹(K, C) from the jets (forces, dissipation and an explicit time
    /// dependence included), kept across steps while Newton converges fast. Dense output (samples,
    /// events, [`keep_dense_output`](crate::Simulation::keep_dense_output)) is the step's
    /// collocation polynomial (degree 3). Holonomic and velocity constraints are run as by the
    /// explicit methods (the index-1 equations, projected onto the constraints after each step,
    /// λ at every sample), with the Newton matrix of the constrained accelerations; contacts as
    /// well (the contact view's accelerations, their Jacobian by differences while a contact is
    /// closed; the method restarted at every impact and lift-off). On non-stiff problems the
    /// explicit methods are cheaper per unit of accuracy.
    ///
    /// `rtol` is mapped to 0.1·rtol^(2/3) internally (as in `radau5.f`); the global error then
    /// follows `rtol` at about 25× it (the heavy top to t = 10: 2.7e-5 at rtol 1e-6, 3.2e-7 at
    /// 1e-8, 2.4e-9 at 1e-10, slope 1.01; measured 2026-12-07): ask for rtol/25 to get rtol.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Method, Scalar, Simulation};
    /// /// Two unit masses: a soft spring (k = 1) to the wall, a stiff one (k = 10⁸) between them.
    /// struct Pair;
    /// impl Lagrangian<2> for Pair {
    ///     const COORDINATES: [&'static str; 2] = ["x1", "x2"];
    ///     const CYCLIC: [bool; 2] = [false, false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
    ///         let d = q[1] - q[0];
    ///         (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[0] * q[0] * 0.5 - d * d * 0.5e8
    ///     }
    /// }
    /// // Started on the slow mode's shape (x₂/x₁ = 1 + 5·10⁻⁹), at rest: the fast mode is not
    /// // excited (from x₁ = x₂ its velocity would oscillate at 3·10⁻⁵, above atol, and every
    /// // method would have to follow it).
    /// let tr = Simulation::new(&Pair, [1.0, 1.0 + 5e-9], [0.0, 0.0])
    ///     .method(Method::Radau5 { rtol: 1e-8, atol: 1e-10 })
    ///     .until(10.0)
    ///     .run()
    ///     .unwrap();
    /// // About 90 steps where DOP853 takes about 49,000; x₁ = cos(ω t), ω² ≈ 1/2.
    /// assert!(tr.stats.steps < 1000);
    /// let w = (0.5_f64 - 1.25e-9).sqrt();
    /// assert!((tr.q.last().unwrap()[0] - (10.0 * w).cos()).abs() < 1e-7);
    /// ```
    Radau5 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance (≥ 0).
        atol: f64,
    },
}

impl Method {
    /// Whether the method takes fixed steps (samples and events are then tied to its grid).
    ///
    /// ```
    /// assert!(lagrange_runtime::Method::Rk4 { dt: 0.1 }.is_fixed_step());
    /// ```
    pub fn is_fixed_step(&self) -> bool {
        self.spec().fixed_dt.is_some()
    }

    /// What the method is and what it takes, from one table: the facts the option checks, the
    /// driver, the sampling, the stiffness diagnosis and the refusals read (a refusal names the
    /// methods that do take what a run has, from the same table).
    ///
    /// ```
    /// use lagrange_runtime::Method;
    /// let s = Method::Dop853 { rtol: 1e-10, atol: 1e-12 }.spec();
    /// assert_eq!((s.name, s.fixed_dt, s.dense_order), ("Method::Dop853", None, Some(7)));
    /// assert!(s.constraints && s.contacts && s.sensitivities);
    /// let r = Method::Radau5 { rtol: 1e-8, atol: 1e-10 }.spec();
    /// assert!(!r.explicit && r.constraints && r.contacts);
    /// assert_eq!(Method::Rk4 { dt: 0.25 }.spec().fixed_dt, Some(0.25));
    /// ```
    pub fn spec(&self) -> MethodSpec {
        // Every method takes velocity constraints where it takes constraints by projection.
        const EXPLICIT: MethodSpec = MethodSpec {
            name: "",
            fixed_dt: None,
            tolerances: None,
            dense_order: None,
            explicit: true,
            constraints: true,
            projects: true,
            velocity_constraints: true,
            contacts: true,
            resets: true,
            sensitivities: true,
            stability_limit: None,
        };
        match *self {
            Method::Rk4 { dt } => MethodSpec {
                name: "Method::Rk4",
                fixed_dt: Some(dt),
                dense_order: Some(3),
                stability_limit: Some(RK4_LIMIT),
                ..EXPLICIT
            },
            Method::DormandPrince { rtol, atol } => MethodSpec {
                name: "Method::DormandPrince",
                tolerances: Some((rtol, atol)),
                dense_order: Some(4),
                ..EXPLICIT
            },
            Method::Dop853 { rtol, atol } => MethodSpec {
                name: "Method::Dop853",
                tolerances: Some((rtol, atol)),
                dense_order: Some(7),
                ..EXPLICIT
            },
            Method::Taylor { .. } => MethodSpec {
                name: "Method::Taylor",
                constraints: false,
                velocity_constraints: false,
                contacts: false,
                ..EXPLICIT
            },
            Method::VariationalMidpoint { dt } => MethodSpec {
                name: "Method::VariationalMidpoint",
                fixed_dt: Some(dt),
                dense_order: Some(3),
                explicit: false,
                // RATTLE: its nodes satisfy the constraints, nothing to project.
                projects: false,
                velocity_constraints: false,
                contacts: false,
                // Φ as the derivative of its discrete map (unconstrained runs).
                sensitivities: true,
                ..EXPLICIT
            },
            Method::Radau5 { rtol, atol } => MethodSpec {
                name: "Method::Radau5",
                tolerances: Some((rtol, atol)),
                dense_order: Some(3),
                explicit: false,
                // Constrained runs on the index-1 equations (the constrained accelerations),
                // projected after each step as the explicit methods are, the Newton matrix that
                // of the constrained accelerations; contacts likewise (the contact view's
                // constrained accelerations while contacts are closed, restarted at each jump).
                // Φ as the derivative of its discrete flow (`radau5::Variations`).
                sensitivities: true,
                ..EXPLICIT
            },
        }
    }

    /// The names of the methods whose [`spec`](Method::spec) has `takes`, for a refusal's
    /// advice ("use Method::Dop853, Method::DormandPrince or Method::Rk4").
    ///
    /// ```
    /// use lagrange_runtime::Method;
    /// assert_eq!(Method::takers(|s| s.contacts), "Method::Dop853, Method::DormandPrince, Method::Rk4 or Method::Radau5");
    /// ```
    pub fn takers(takes: impl Fn(&MethodSpec) -> bool) -> String {
        let all = [
            Method::Dop853 {
                rtol: 1.0,
                atol: 1.0,
            },
            Method::DormandPrince {
                rtol: 1.0,
                atol: 1.0,
            },
            Method::Rk4 { dt: 1.0 },
            Method::Taylor { tol: 1.0 },
            Method::VariationalMidpoint { dt: 1.0 },
            Method::Radau5 {
                rtol: 1.0,
                atol: 1.0,
            },
        ];
        let names: Vec<&str> = all
            .iter()
            .map(Method::spec)
            .filter(|s| takes(s))
            .map(|s| s.name)
            .collect();
        match names.split_last() {
            None => String::new(),
            Some((last, [])) => (*last).to_string(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        }
    }
}

/// What a [`Method`] is and what it takes ([`Method::spec`]).
///
/// ```
/// let s = lagrange_runtime::Method::VariationalMidpoint { dt: 1e-3 }.spec();
/// assert!(s.constraints && !s.projects && !s.velocity_constraints);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct MethodSpec {
    /// The method as the user writes it (`"Method::Dop853"`).
    pub name: &'static str,
    /// The step of a fixed-step method (samples and events are tied to its grid).
    pub fixed_dt: Option<f64>,
    /// (rtol, atol) of a method with error control on them.
    pub tolerances: Option<(f64, f64)>,
    /// The order of its dense output (`None`: it varies, the Taylor method's series).
    pub dense_order: Option<u32>,
    /// An explicit method: its step is bounded by the fastest mode (the stiffness diagnosis
    /// applies to its failures).
    pub explicit: bool,
    /// Whether it runs holonomic constraints.
    pub constraints: bool,
    /// Whether a constrained run projects its state back onto the constraints after each step
    /// (the explicit methods), rather than stepping on them (RATTLE).
    pub projects: bool,
    /// Whether it runs velocity (nonholonomic) constraints.
    pub velocity_constraints: bool,
    /// Whether it runs contacts (impacts, resting contact, lift-off).
    pub contacts: bool,
    /// Whether it runs events that reset the state.
    pub resets: bool,
    /// Whether sensitivity runs integrate their variations with it.
    pub sensitivities: bool,
    /// Its stability limit on h·ω for an undamped oscillation, for a fixed-step explicit method
    /// (the diagnosis compares the step against it).
    pub stability_limit: Option<f64>,
}

/// RK4's stability limit on h·ω for an undamped oscillation (its region meets the imaginary axis
/// at ±2√2).
pub(crate) const RK4_LIMIT: f64 = 2.0 * core::f64::consts::SQRT_2;

/// The methods that run in SIMD lanes in an ensemble, each with its engine's file under
/// `integrate/lanes/` (a `pub(super) fn run` over that method's members) and the members it runs
/// in one pass: calls `$callback!` with the list. Making a method run in lanes is its engine's
/// file and its line here.
///
/// The widths were measured on this project's machines (AMD EPYC, AVX2 + FMA; 256 heavy tops,
/// alternating runs, 2026-11-28): the Taylor series in 8 lanes (two AVX2 vectors side by side:
/// its convolutions are chains of additions, and two vectors keep twice as many in flight) took
/// 0.59–0.61 ms per top at tol 1e-13 against 0.67–0.68 in 4; DOP853 in 8 lanes 0.76–0.84 ms at
/// rtol 1e-11 against 0.63–0.65 in 4 (its stages are bound by the arithmetic, not by latency).
macro_rules! lanes_engines {
    ($callback:ident) => {
        $callback! {
            Taylor => taylor, 8 lanes,
            Dop853 => dop853, 4 lanes,
        }
    };
}
pub(crate) use lanes_engines;
