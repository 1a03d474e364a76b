//! Periodic orbits by shooting: Newton's method on x(t₀ + T; x₀) − x₀ = 0 with the monodromy
//! matrix from the variational equations, and the orbit's Floquet multipliers.
//!
//! An autonomous system's period is an unknown: each Newton step solves
//!
//! ```text
//! [ Φ(T) − I   f(x(T)) ] [Δx]   [ −(x(T) − x₀) ]
//! [ f(x₀)ᵀ        0    ] [ΔT] = [      0       ]
//! ```
//!
//! (the second row is the phase condition: the correction is orthogonal to the flow, which
//! otherwise slides along the orbit). A forced system with period 2π/ω has it fixed, and Newton
//! solves (Φ(T) − I) Δx = −(x(T) − x₀) alone. Integrals of the motion (the energy, conserved
//! momenta) and symmetries make these systems singular: orbits come in families. The step is the
//! least-squares solution of least norm (the SVD, singular values below r = |x(T) − x₀|/max(1, |x₀|)
//! of the largest, clamped to [1e-9, 1e-2], taken as zero: off the orbit such an integral's
//! direction is singular only to O(r)), so Newton goes to a nearby orbit of the family. A forced
//! system without a cyclic coordinate has isolated orbits: there only singular values below 1e-9
//! of the largest are cut (near a bifurcation Φ(T) − I has a small one Newton needs). A step that
//! does not reduce the residual is halved (up to 30 times). Newton that ends on an equilibrium
//! (periodic with any period) is refused with [`OrbitError::NoConvergence`].
//!
//! A pin picks one orbit of a family: [`Shooting::pin_amplitude`] (the orbit turns in coordinate
//! i at the guess's q_i: the rows Δq_i = q₀ᵢ − q_i and Δq̇_i = −q̇_i, the latter in place of the
//! phase condition) or [`Shooting::pin_energy`] (the row ∇E·Δx = e − E(x)); the family's
//! direction is then no longer cut.
//!
//! The multipliers are the eigenvalues of the monodromy matrix Φ(T) (from the real Schur form).

use core::fmt;

use nalgebra::{Complex, DMatrix, DVector};

use crate::lagrangian::Lagrangian;

use super::super::error::SimulationError;
use super::super::events::Event;
use super::super::method::Method;
use super::super::simulation::Simulation;
use super::super::trajectory::Trajectory;

/// How far from the unit circle a multiplier may be and still count as on it, in
/// [`OrbitStability`]: 1e-6.
///
/// ```
/// assert_eq!(lagrange_runtime::sensitivity::MULTIPLIER_TOL, 1e-6);
/// ```
pub const MULTIPLIER_TOL: f64 = 1e-6;

/// Multipliers within this distance of 1 count as neutral in [`OrbitStability`] whatever their
/// modulus: 1e-3. The integrals of the motion and the symmetries (energy and period, momentum
/// and translation, angular momentum and rotation) give a conservative orbit Jordan blocks at
/// μ = 1, which the monodromy's error δ splits by δ^(1/k) for a block of size k (measured on
/// the figure-eight at rtol 1e-13: |μ| − 1 up to 1.9e-6). A growth slower than 1e-3 per period
/// is therefore not told apart from them.
///
/// ```
/// assert_eq!(lagrange_runtime::sensitivity::TRIVIAL_RADIUS, 1e-3);
/// ```
pub const TRIVIAL_RADIUS: f64 = 1e-3;

/// The linear stability of a periodic orbit from its Floquet multipliers μ (tolerance
/// [`MULTIPLIER_TOL`]).
///
/// ```
/// use lagrange_runtime::sensitivity::OrbitStability;
/// assert!(OrbitStability::Neutral.is_stable());
/// assert!(!OrbitStability::Unstable { largest: 1.5 }.is_stable());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OrbitStability {
    /// Every multiplier but the trivial one (μ = 1 along the flow of an autonomous system) has
    /// |μ| < 1: nearby motions fall onto the orbit (a damped, driven system's stable cycle, a
    /// limit cycle).
    AsymptoticallyStable,
    /// No |μ| > 1, some on the unit circle (or within [`TRIVIAL_RADIUS`] of 1) besides the
    /// trivial one: nearby motions stay near without approaching (conservative systems: the
    /// multipliers come in pairs μ, 1/μ).
    Neutral,
    /// Some |μ| > 1: nearby motions leave the orbit, by a factor `largest` per period.
    Unstable {
        /// The largest |μ|.
        largest: f64,
    },
}

impl OrbitStability {
    /// `true` unless [`OrbitStability::Unstable`].
    ///
    /// ```
    /// use lagrange_runtime::sensitivity::OrbitStability;
    /// assert!(OrbitStability::AsymptoticallyStable.is_stable());
    /// ```
    pub fn is_stable(&self) -> bool {
        !matches!(self, OrbitStability::Unstable { .. })
    }
}

impl fmt::Display for OrbitStability {
    /// `asymptotically stable`, `neutral (multipliers on the unit circle)` or
    /// `unstable (largest |μ| = …)`.
    ///
    /// ```
    /// use lagrange_runtime::sensitivity::OrbitStability;
    /// assert_eq!(OrbitStability::Unstable { largest: 2.0 }.to_string(), "unstable (largest |μ| = 2)");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OrbitStability::AsymptoticallyStable => f.write_str("asymptotically stable"),
            OrbitStability::Neutral => f.write_str("neutral (multipliers on the unit circle)"),
            OrbitStability::Unstable { largest } => write!(f, "unstable (largest |μ| = {largest})"),
        }
    }
}

/// A periodic orbit found by [`Shooting`]: x(t₀ + T) = x₀.
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar};
/// use lagrange_runtime::sensitivity::Shooting;
/// /// A pendulum, θ̈ = −sin θ: its librations are periodic, multipliers 1, 1 (a Jordan block).
/// struct P;
/// impl Lagrangian<1> for P {
///     const COORDINATES: [&'static str; 1] = ["theta"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
/// }
/// let orbit = Shooting::autonomous(&P, [2.0], [0.0], 8.4).find().unwrap();
/// assert!(orbit.closure < 1e-10);
/// assert!(orbit.multipliers.iter().all(|m| (m - 1.0).norm() < 1e-3));
/// ```
#[derive(Clone, Debug)]
pub struct PeriodicOrbit<const N: usize> {
    /// The start time t₀ (the phase of a forced system's orbit).
    pub t0: f64,
    /// q at t₀.
    pub q0: [f64; N],
    /// q̇ at t₀.
    pub qdot0: [f64; N],
    /// The period T.
    pub period: f64,
    /// The monodromy matrix Φ(t₀ + T) = ∂x(t₀ + T)/∂x₀ (2N × 2N, rows and columns (q, q̇)).
    pub monodromy: DMatrix<f64>,
    /// Its eigenvalues, the Floquet multipliers, by decreasing modulus.
    pub multipliers: Vec<Complex<f64>>,
    /// The verdict from the multipliers.
    pub stability: OrbitStability,
    /// |x(t₀ + T) − x₀| (Euclidean, over the 2N components) at the orbit returned; with a pin
    /// ([`Shooting::pin_amplitude`], [`Shooting::pin_energy`]), with the pin's residuals as more
    /// components.
    pub closure: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// Why [`Shooting::find`] found no periodic orbit: what happened, where, and what to try.
///
/// ```
/// use lagrange_runtime::sensitivity::OrbitError;
/// let e = OrbitError::InvalidOptions { message: "period ≤ 0".into() };
/// assert!(e.to_string().contains("period ≤ 0"));
/// ```
#[derive(Debug)]
#[non_exhaustive]
pub enum OrbitError {
    /// The options make no sense (before any run).
    InvalidOptions {
        /// What and what to try.
        message: String,
    },
    /// A run from an iterate failed.
    Run {
        /// The iterate's period.
        period: f64,
        /// The run's error (time, state, partial trajectory).
        source: Box<SimulationError>,
    },
    /// Newton did not reach the tolerance.
    NoConvergence {
        /// Iterations taken.
        iterations: usize,
        /// The best |x(T) − x₀| reached.
        closure: f64,
        /// The iterate that reached it: q₀, q̇₀ and T.
        q: Vec<f64>,
        /// q̇₀ of that iterate.
        qdot: Vec<f64>,
        /// T of that iterate.
        period: f64,
        /// What to try.
        message: String,
    },
    /// The multipliers could not be computed (the Schur iteration did not converge).
    Eigen {
        /// What to try.
        message: String,
    },
}

impl fmt::Display for OrbitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OrbitError::InvalidOptions { message } => {
                write!(f, "invalid shooting options: {message}")
            }
            OrbitError::Run { period, source } => {
                write!(
                    f,
                    "the run of an iterate (period {period}) failed: {source}"
                )
            }
            OrbitError::NoConvergence {
                iterations,
                closure,
                q,
                qdot,
                period,
                message,
            } => write!(
                f,
                "no periodic orbit after {iterations} Newton iterations: the best iterate \
                 (q₀ = {q:?}, q̇₀ = {qdot:?}, T = {period}) closes to |x(T) − x₀| = {closure:e}: \
                 {message}"
            ),
            OrbitError::Eigen { message } => write!(f, "Floquet multipliers: {message}"),
        }
    }
}

impl std::error::Error for OrbitError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            OrbitError::Run { source, .. } => Some(&**source),
            _ => None,
        }
    }
}

/// A shooting solver for a periodic orbit of `sys` from a guess (q₀, q̇₀, T); configure, then
/// [`find`](Shooting::find). See the [module documentation](crate::sensitivity) for the method.
///
/// ```
/// use lagrange::prelude::*;
/// use lagrange::sensitivity::{OrbitStability, Shooting};
///
/// /// ẍ + ẋ + x = cos t: the periodic response x = sin t, asymptotically stable.
/// pub struct Forced;
///
/// #[lagrangian]
/// impl Forced {
///     fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
///         0.5 * (x_dot * x_dot - x * x)
///     }
///     fn dissipation(&self, (_x, x_dot): Coord) -> Scalar {
///         0.5 * x_dot * x_dot
///     }
///     fn forces(&self, (_x, _x_dot): Coord, t: Time) -> [Scalar; 1] {
///         [t.cos()]
///     }
/// }
///
/// let orbit = Shooting::forced(&Forced, [0.3], [0.5], 2.0 * std::f64::consts::PI)
///     .method(Method::Dop853 { rtol: 1e-12, atol: 1e-12 })
///     .find()
///     .unwrap();
/// assert!(orbit.q0[0].abs() < 1e-9 && (orbit.qdot0[0] - 1.0).abs() < 1e-9);
/// assert_eq!(orbit.stability, OrbitStability::AsymptoticallyStable);
/// ```
pub struct Shooting<'a, L, const N: usize> {
    sys: &'a L,
    q0: [f64; N],
    qdot0: [f64; N],
    t0: f64,
    period: f64,
    fixed_period: bool,
    method: Method,
    tolerance: f64,
    max_iterations: usize,
    pin: Option<Pin>,
    /// The events of each shot, made afresh for each (an event owns its closures).
    events: Vec<EventMaker<'a, N>>,
    /// The shift Δq the orbit closes up to: x(t₀ + T) = x₀ + (Δq, 0).
    shift: [f64; N],
    /// The Poincaré section each shot runs to (the orbit a fixed point of its return map).
    section: Option<EventMaker<'a, N>>,
}

/// What makes one of a shooting's events for each of its runs.
type EventMaker<'a, const N: usize> = Box<dyn Fn() -> Event<'a, N> + 'a>;

/// What picks one orbit out of an autonomous system's family (the energy, or the coordinate the
/// orbit passes through), as a Newton row of its own.
#[derive(Clone, Copy, Debug)]
enum Pin {
    /// The orbit turns in coordinate i at the guess's value: q_i(t₀) = q₀[i], q̇_i(t₀) = 0.
    Amplitude(usize),
    /// The energy (Jacobi integral) at t₀.
    Energy(f64),
}

impl<'a, L: Lagrangian<N>, const N: usize> Shooting<'a, L, N> {
    /// A periodic orbit of an autonomous system near (q₀, q̇₀) with a period near `period_guess`
    /// (both unknowns).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct Osc;
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() * 4.0 }
    /// # }
    /// // A libration of amplitude ≈ 0.5 of θ̈ = −4 sin θ: T ≈ π (1 + 0.5²/16).
    /// let orbit = Shooting::autonomous(&Osc, [0.5], [0.0], 3.2).find().unwrap();
    /// assert!(orbit.closure < 1e-10 && (orbit.period - 3.19).abs() < 0.01);
    /// ```
    pub fn autonomous(sys: &'a L, q0: [f64; N], qdot0: [f64; N], period_guess: f64) -> Self {
        Shooting {
            sys,
            q0,
            qdot0,
            t0: 0.0,
            period: period_guess,
            fixed_period: false,
            method: Method::Dop853 {
                rtol: 1e-12,
                atol: 1e-12,
            },
            tolerance: 1e-10,
            max_iterations: 30,
            pin: None,
            events: Vec::new(),
            shift: [0.0; N],
            section: None,
        }
    }

    /// A periodic orbit of period `period` (the forcing's, e.g. 2π/ω, or a multiple of it for a
    /// subharmonic) near (q₀, q̇₀) at the start time (default 0): the period is fixed.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct F;
    /// # impl Lagrangian<1> for F {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     const ENERGY_CONSERVED: bool = false;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// #     fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// #     fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], t: S) -> [S; 1] { [t.cos()] }
    /// # }
    /// let orbit = Shooting::forced(&F, [0.0], [0.0], 2.0 * std::f64::consts::PI).find().unwrap();
    /// assert_eq!(orbit.period, 2.0 * std::f64::consts::PI);
    /// ```
    pub fn forced(sys: &'a L, q0: [f64; N], qdot0: [f64; N], period: f64) -> Self {
        Shooting {
            fixed_period: true,
            ..Self::autonomous(sys, q0, qdot0, period)
        }
    }

    /// The start time t₀ (default 0): for a forced system, the phase of the orbit found.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct Osc;
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// # }
    /// let orbit = Shooting::autonomous(&Osc, [1.0], [0.0], 6.7).start_time(2.0).find().unwrap();
    /// assert_eq!(orbit.t0, 2.0);
    /// ```
    pub fn start_time(mut self, t0: f64) -> Self {
        self.t0 = t0;
        self
    }

    /// The method of the runs (default DOP853 at rtol = atol = 1e-12; `Method::Rk4` also works).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, Method};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct Osc;
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// # }
    /// let orbit = Shooting::autonomous(&Osc, [1.0], [0.0], 6.7)
    ///     .method(Method::Dop853 { rtol: 1e-13, atol: 1e-13 })
    ///     .find()
    ///     .unwrap();
    /// assert!(orbit.closure < 1e-10);
    /// ```
    pub fn method(mut self, method: Method) -> Self {
        self.method = method;
        self
    }

    /// Newton stops when |x(t₀ + T) − x₀| ≤ `tolerance` (default 1e-10; it cannot go below the
    /// runs' own error).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct Osc;
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// # }
    /// let orbit = Shooting::autonomous(&Osc, [1.0], [0.0], 6.7).tolerance(1e-6).find().unwrap();
    /// assert!(orbit.closure <= 1e-6);
    /// ```
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// The most Newton iterations (default 30).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::{OrbitError, Shooting};
    /// # struct Osc;
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// # }
    /// let err = Shooting::autonomous(&Osc, [1.0], [0.0], 5.0).max_iterations(0).find().unwrap_err();
    /// assert!(matches!(err, OrbitError::NoConvergence { .. }));
    /// ```
    pub fn max_iterations(mut self, n: usize) -> Self {
        self.max_iterations = n;
        self
    }

    /// Pins the orbit's amplitude in coordinate i: the orbit turns (q̇_i = 0) at q_i = q₀[i] at
    /// t₀, the guess's value. This replaces the phase condition (the turning point fixes the
    /// phase) and picks one orbit out of a family (an autonomous conservative system has one
    /// through every energy). Without a pin Newton takes the least-norm step, which for small,
    /// nearly isochronous oscillations and a period guess a few per cent off runs down the family
    /// to the equilibrium.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct P;
    /// # impl Lagrangian<1> for P {
    /// #     const COORDINATES: [&'static str; 1] = ["theta"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// # }
    /// // The pendulum's libration of amplitude 1, from a period guess 5 % off.
    /// let orbit = Shooting::autonomous(&P, [1.0], [0.0], 7.0).pin_amplitude(0).find().unwrap();
    /// assert!((orbit.q0[0] - 1.0).abs() < 1e-12 && orbit.qdot0[0].abs() < 1e-12);
    /// assert!((orbit.period - 6.69998).abs() < 1e-5); // 4 K(sin ½)
    /// ```
    pub fn pin_amplitude(mut self, i: usize) -> Self {
        self.pin = Some(Pin::Amplitude(i));
        self
    }

    /// Pins the orbit's energy (the Jacobi integral q̇·p − L at t₀) to `energy`: of a family of
    /// orbits, the one at that energy.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct P;
    /// # impl Lagrangian<1> for P {
    /// #     const COORDINATES: [&'static str; 1] = ["theta"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// # }
    /// // E = −cos 1: the libration of amplitude 1, from a guess at amplitude 0.9.
    /// let orbit = Shooting::autonomous(&P, [0.9], [0.0], 6.6)
    ///     .pin_energy(-(1.0_f64).cos())
    ///     .find()
    ///     .unwrap();
    /// assert!((orbit.period - 6.69998).abs() < 1e-5); // 4 K(sin ½)
    /// ```
    pub fn pin_energy(mut self, energy: f64) -> Self {
        self.pin = Some(Pin::Energy(energy));
        self
    }

    /// Adds an event to every run of the shooting, made by `make` for each: a resetting event
    /// (an impact, a walker's heel strike that swaps its legs) makes the orbit a hybrid one,
    /// which closes through its jumps; the monodromy carries each jump's saltation matrix (see
    /// [`Sensitivity::run`](crate::sensitivity::Sensitivity::run)), so its multipliers are those
    /// of the step-to-step map. Start the shooting away from the jumps, with a period guess that
    /// takes the same jumps as the orbit.
    ///
    /// ```
    /// use lagrange_runtime::{Event, Lagrangian, Scalar};
    /// use lagrange_runtime::sensitivity::Shooting;
    /// /// A rimless wheel (spokes of length 1, angle 2α apart) on a slope γ: θ̈ = sin(θ + γ)
    /// /// (unit g/l) from θ = −α to α, where the next spoke lands: θ⁺ = −α, θ̇⁺ = cos 2α θ̇⁻.
    /// struct Wheel;
    /// impl Lagrangian<1> for Wheel {
    ///     const COORDINATES: [&'static str; 1] = ["theta"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
    ///         v[0] * v[0] * 0.5 - (q[0] + 0.08).cos()
    ///     }
    /// }
    /// let alpha = std::f64::consts::PI / 8.0;
    /// let orbit = Shooting::autonomous(&Wheel, [0.0], [0.17], 3.2)
    ///     .event(move || {
    ///         Event::zero_crossing("next spoke", move |_t, q: &[f64; 1], _v| q[0] - alpha)
    ///             .rising()
    ///             .reset(move |_t, q, v| ([q[0] - 2.0 * alpha], [(2.0 * alpha).cos() * v[0]]))
    ///     })
    ///     .find()
    ///     .unwrap();
    /// // The step-to-step map's multiplier: cos² 2α = 1/2.
    /// let mu = orbit.multipliers.iter().map(|m| m.norm()).fold(f64::INFINITY, f64::min);
    /// assert!((mu - 0.5).abs() < 1e-8);
    /// ```
    pub fn event(mut self, make: impl Fn() -> Event<'a, N> + 'a) -> Self {
        self.events.push(Box::new(make));
        self
    }

    /// An orbit periodic up to a shift of its coordinates: x(t₀ + T) = x₀ + (Δq, 0), the motion
    /// repeating itself displaced (a pendulum whirling over the top, θ(T) = θ₀ + 2π; a wheel or
    /// a walker that has moved on by one step while its shape repeats). The monodromy and the
    /// multipliers are those of that closure (the shift is a symmetry: the flow commutes with it).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct P;
    /// # impl Lagrangian<1> for P {
    /// #     const COORDINATES: [&'static str; 1] = ["theta"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// # }
    /// // θ̈ = −sin θ whirling with θ̇ = 3 at the bottom (energy 3.5): one turn in 4 K(2/3)/3.
    /// let orbit = Shooting::autonomous(&P, [0.0], [3.0], 2.3)
    ///     .shift([2.0 * std::f64::consts::PI])
    ///     .pin_energy(3.5)
    ///     .find()
    ///     .unwrap();
    /// assert!((orbit.period - 2.4128900).abs() < 1e-6);
    /// ```
    pub fn shift(mut self, dq: [f64; N]) -> Self {
        self.shift = dq;
        self
    }

    /// Shoots to a Poincaré section: each run goes from x₀ until the event `make` gives (its
    /// function g and direction; made terminal) is crossed, and the orbit is a fixed point of
    /// the return map P(x₀) = x(t*) on the section g = 0; the period is the time of the return,
    /// an output (the period given to [`autonomous`](Self::autonomous) bounds the run: twice it).
    /// Newton's rows are P(x₀) − x₀ (up to a [`shift`](Self::shift)) and g(x₀) = 0, which
    /// fixes the phase in place of the phase condition. Each run measures the return to the
    /// section's level through its own start (g − g(x₀) = 0: a start a round-off off the section
    /// is not a crossing), so [`PeriodicOrbit::monodromy`] is the return map's Jacobian ∂P/∂x₀
    /// (the event's [`dstate_dx0`](crate::EventSensitivity::dstate_dx0)) and the multipliers its
    /// eigenvalues: the flow's direction maps to 0 there (the trivial multiplier 1 of the
    /// monodromy becomes 0), the others are the orbit's Floquet multipliers. With
    /// [`pin_energy`](Self::pin_energy) for a conservative family; a section is a phase
    /// condition, so it does not take [`pin_amplitude`](Self::pin_amplitude), and it is for
    /// autonomous systems.
    ///
    /// ```
    /// # use lagrange_runtime::{Event, Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Shooting;
    /// # struct P;
    /// # impl Lagrangian<1> for P {
    /// #     const COORDINATES: [&'static str; 1] = ["theta"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// # }
    /// // The libration of amplitude 1, through θ = 0 going up.
    /// let orbit = Shooting::autonomous(&P, [0.0], [0.95], 6.7)
    ///     .section(|| Event::zero_crossing("θ = 0", |_t, q: &[f64; 1], _v| q[0]).rising())
    ///     .pin_energy(-(1.0_f64).cos())
    ///     .find()
    ///     .unwrap();
    /// assert!((orbit.period - 6.69998).abs() < 1e-5); // 4 K(sin ½)
    /// assert!(orbit.multipliers.iter().any(|m| m.norm() < 1e-6)); // the flow's direction
    /// ```
    pub fn section(mut self, make: impl Fn() -> Event<'a, N> + 'a) -> Self {
        self.section = Some(Box::new(make));
        self
    }

    /// x − x₀ − (Δq, 0): the closure's residual of a shot from x.
    fn gap(&self, s: &Shot, x: &[f64]) -> Vec<f64> {
        (0..2 * N)
            .map(|i| s.end[i] - x[i] - if i < N { self.shift[i] } else { 0.0 })
            .collect()
    }

    /// The pin's residual at x and its gradient (a Newton row), if pinned.
    fn pin_row(&self, x: &[f64]) -> Option<(f64, Vec<f64>)> {
        let n2 = 2 * N;
        match self.pin? {
            Pin::Amplitude(i) => {
                let mut g = vec![0.0; n2];
                g[i] = 1.0;
                Some((x[i] - self.q0[i], g))
            }
            Pin::Energy(e) => {
                let energy = |x: &[f64]| {
                    let q: [f64; N] = core::array::from_fn(|i| x[i]);
                    let v: [f64; N] = core::array::from_fn(|i| x[N + i]);
                    self.sys.energy(&q, &v, self.t0)
                };
                // The gradient by central differences (a Newton row: its error slows the
                // iteration, never moves the orbit, whose energy is the residual's).
                let mut g = vec![0.0; n2];
                let mut xt = x.to_vec();
                for j in 0..n2 {
                    let h = f64::EPSILON.cbrt() * x[j].abs().max(1.0);
                    xt[j] = x[j] + h;
                    let up = energy(&xt);
                    xt[j] = x[j] - h;
                    let down = energy(&xt);
                    xt[j] = x[j];
                    g[j] = (up - down) / (2.0 * h);
                }
                Some((energy(x) - e, g))
            }
        }
    }

    /// The closure |x(T) − x₀| and, pinned, the pin's residuals: the size Newton drives to 0.
    fn residual(&self, s: &Shot, x: &[f64]) -> f64 {
        let closure = self.gap(s, x).iter().map(|d| d * d).sum::<f64>() + s.level * s.level;
        let pin = self.pin_row(x).map_or(0.0, |(r, _)| r * r);
        let turn = match self.pin {
            Some(Pin::Amplitude(i)) => x[N + i] * x[N + i],
            _ => 0.0,
        };
        (closure + pin + turn).sqrt()
    }

    /// x(t₀ + T), Φ(t₀ + T) and f at both ends, from a sensitivity run from x; with a section,
    /// the return x(t*) ([`section`](Self::section)), its Jacobian and the time of the return
    /// (the run bounded by t₀ + `period`).
    fn shoot(&self, x: &[f64], period: f64) -> Result<Shot, OrbitError> {
        let q: [f64; N] = core::array::from_fn(|i| x[i]);
        let v: [f64; N] = core::array::from_fn(|i| x[N + i]);
        // A system that declares constraints or contacts runs on its view, whose flow is not
        // L's own accelerations: f at the ends then comes from second-order differences of
        // the run's samples at t₀, t₀ + δ, t₀ + 2δ and T − δ, T, T + δ (δ = 1e-4 T: error
        // ≈ 1e-8 T² |x‴|, which slows Newton's rows, never moves the orbit).
        let flags = super::super::system::System::flags(self.sys);
        let declared = flags.constrained || flags.contacts;
        let delta = 1e-4 * period;
        let t_end = self.t0 + period;
        let mut sim = Simulation::new(self.sys, q, v)
            .method(self.method)
            .start_time(self.t0)
            .until(self.t0 + period);
        if flags.contacts {
            // Newton's steps move the start off the contacts closed at the guess (a gap above
            // round-off would start that contact open: a drop): each shot starts with them
            // closed, the iterate put on them.
            let at = ClosedAt {
                q: self.q0,
                qdot: self.qdot0,
                t: self.t0,
            };
            if let Some(closed) = self.sys.declared(at) {
                sim = sim.closed_at_start(closed);
            }
        } else if flags.constrained {
            // Newton's iterates leave the constraints (their normal part is the closure's to
            // remove): each run starts from the iterate's projection, and Φ(t₀) is that
            // projection's derivative.
            sim = sim.project_initial_state();
        }
        if declared {
            let t0 = self.t0;
            let start = [t0, t0 + delta, t0 + 2.0 * delta];
            sim = if self.section.is_some() {
                sim.sample_at(start)
            } else {
                sim.until(t_end + delta).sample_at(start.into_iter().chain([
                    t_end - delta,
                    t_end,
                    t_end + delta,
                ]))
            };
        }
        for make in &self.events {
            sim = sim.event(make());
        }
        // The section through the start's level, terminal, under a name of its own.
        let mut level = 0.0;
        let mut section_name = None;
        if let Some(make) = &self.section {
            let ev = make();
            level = ev.value(self.t0, &q, &v);
            let name = format!("Poincaré section `{}`", ev.name());
            let ev =
                ev.at_level(level, name.clone())
                    .ok_or_else(|| OrbitError::InvalidOptions {
                        message: format!(
                            "the {name} resets the state: a section only observes the motion; give \
                         the jump as an `.event(..)` and the section as a plain crossing"
                        ),
                    })?;
            sim = sim.event(ev.terminal());
            section_name = Some(name);
        }
        let run = sim.sensitivity().run().map_err(|e| OrbitError::Run {
            period,
            source: Box::new(e),
        })?;
        let tr = &run.trajectory;
        let (qe, ve) = match (tr.q.last(), tr.qdot.last()) {
            (Some(q), Some(v)) => (q, v),
            _ => {
                return Err(OrbitError::InvalidOptions {
                    message: "the run recorded no state".into(),
                });
            }
        };
        // The samples asked for (a declared system), by their times: a jump adds the sample
        // before it.
        let sample = |t: f64| tr.t.iter().rposition(|&s| s == t);
        let t0 = self.t0;
        let ends = [t_end - delta, t_end, t_end + delta].map(sample);
        let at_end = match ends {
            [Some(a), Some(b), Some(c)] if declared && section_name.is_none() => Some((a, b, c)),
            _ => None,
        };
        let (t_end, qe, ve, phi) = match &section_name {
            None if at_end.is_some() => {
                let k = at_end.map_or(0, |(_, b, _)| b);
                (t_end, tr.q[k], tr.qdot[k], run.phi[k].clone())
            }
            None => (t_end, *qe, *ve, run.final_phi().clone()),
            Some(name) => {
                let hit = tr.events.last().filter(|h| &h.name == name);
                let sens = run.events.last().and_then(|e| e.dstate_dx0.clone());
                let (Some(hit), Some(jac)) = (hit, sens) else {
                    return Err(OrbitError::Run {
                        period,
                        source: Box::new(SimulationError::InvalidOptions {
                            message: format!(
                                "the {name} was not crossed (in its direction) between t = {} \
                                 and t = {} from q = {q:?}, q̇ = {v:?}: give a period guess \
                                 (half the time bound) nearer the return time, or a start \
                                 nearer the orbit",
                                self.t0,
                                self.t0 + period
                            ),
                        }),
                    });
                };
                (hit.t, hit.q, hit.qdot, jac)
            }
        };
        let end: Vec<f64> = qe.iter().chain(ve.iter()).copied().collect();
        let slope = |t: f64, q: &[f64; N], v: &[f64; N]| -> Result<Vec<f64>, OrbitError> {
            let a = self
                .sys
                .accelerations(q, v, t)
                .map_err(|e| OrbitError::Run {
                    period,
                    source: Box::new(SimulationError::InvalidOptions {
                        message: format!("the accelerations failed at an end of the orbit: {e}"),
                    }),
                })?;
            Ok(v.iter().chain(a.iter()).copied().collect())
        };
        let (f_start, f_end) = if declared {
            sampled_flow(
                tr,
                [t0, t0 + delta, t0 + 2.0 * delta].map(sample),
                at_end,
                delta,
            )?
        } else {
            (slope(self.t0, &q, &v)?, slope(t_end, &qe, &ve)?)
        };
        Ok(Shot {
            f_end,
            f_start,
            end,
            phi,
            period: t_end - self.t0,
            level,
        })
    }

    /// Runs Newton from the guess and returns the orbit with its monodromy, multipliers and
    /// stability.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::{OrbitStability, Shooting};
    /// /// A pendulum's libration at amplitude ≈ 1 (any nearby amplitude is an orbit too: Newton
    /// /// goes to the nearest).
    /// struct P;
    /// impl Lagrangian<1> for P {
    ///     const COORDINATES: [&'static str; 1] = ["theta"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() }
    /// }
    /// let orbit = Shooting::autonomous(&P, [1.0], [0.0], 6.7).find().unwrap();
    /// assert!(orbit.closure < 1e-10 && (orbit.period - 6.6998).abs() < 1e-3);
    /// assert_eq!(orbit.stability, OrbitStability::Neutral);
    /// ```
    pub fn find(self) -> Result<PeriodicOrbit<N>, OrbitError> {
        self.check()?;
        let mut x: Vec<f64> = self.q0.iter().chain(self.qdot0.iter()).copied().collect();
        // A section's run is bounded by twice the period (the return time is its output).
        let bound = if self.section.is_some() { 2.0 } else { 1.0 };
        let mut shot = self.shoot(&x, bound * self.period)?;
        let mut period = shot.period;
        let mut closure = self.residual(&shot, &x);
        let mut iterations = 0;
        // A NaN closure (a run that blew up) keeps iterating until the budget ends.
        while closure.is_nan() || closure > self.tolerance {
            if iterations >= self.max_iterations {
                return Err(self.no_convergence(
                    iterations,
                    closure,
                    &x,
                    period,
                    "raise \
                    max_iterations, start nearer the orbit, or loosen the tolerance to the \
                    runs' accuracy (tighten the method's rtol to go lower)",
                ));
            }
            iterations += 1;
            // Two steps, one after the other where no fraction of the first reduces the
            // residual: the full least-norm step and the one that sets a family's directions
            // aside. Without a section the cut goes first (the flow's direction and an
            // integral's make the matrix nearly singular off the orbit, and inverting them
            // throws the iterate along the family); a section fixes the phase, and a return
            // map with a section is often that of an orbit without a family (a walker losing
            // energy at its impacts), where the cut, relative to the residual, takes
            // directions Newton needs while the guess is far: the full step goes first.
            let order = if self.section.is_some() {
                [false, true]
            } else {
                [true, false]
            };
            let mut accepted = None;
            for truncate in order {
                let step = self.newton_step(&shot, &x, closure, truncate)?;
                accepted = self.line_search(&x, period, bound, &step, closure);
                if accepted.is_some() || !self.cuts_families() {
                    break;
                }
            }
            let Some((xt, pt, s, c)) = accepted else {
                return Err(self.no_convergence(
                    iterations,
                    closure,
                    &x,
                    period,
                    match self.pin {
                        Some(Pin::Energy(_)) => {
                            "no step along Newton's direction reduces |x(T) − x₀| and the energy's \
                             residual: no orbit of that energy near the guess (is it beyond the \
                             energy's extremum, below a potential's minimum?), or the runs' error \
                             is reached: check the energy, start nearer the orbit, or loosen the \
                             tolerance"
                        }
                        _ => {
                            "no step along Newton's direction reduces |x(T) − x₀| (the runs' \
                             error is reached, or the guess is too far): loosen the tolerance or \
                             start nearer the orbit"
                        }
                    },
                ));
            };
            (x, period, shot, closure) = (xt, pt, s, c);
        }
        self.not_an_equilibrium(&shot, &x, period, (iterations, closure))?;
        let multipliers = multipliers(&shot.phi)?;
        let stability = if self.section.is_some() {
            // The return map's: the flow's direction maps to 0 (the smallest, last); the rest
            // are the Floquet multipliers without the trivial one.
            classify(&multipliers[..multipliers.len() - 1], false)
        } else {
            classify(&multipliers, !self.fixed_period)
        };
        Ok(PeriodicOrbit {
            t0: self.t0,
            q0: core::array::from_fn(|i| x[i]),
            qdot0: core::array::from_fn(|i| x[N + i]),
            period,
            monodromy: shot.phi,
            multipliers,
            stability,
            closure,
            iterations,
        })
    }

    /// The options' refusals, before any run.
    fn check(&self) -> Result<(), OrbitError> {
        if !(self.period > 0.0 && self.period.is_finite()) {
            return Err(OrbitError::InvalidOptions {
                message: format!(
                    "the period (guess) is {}: give a positive finite period",
                    self.period
                ),
            });
        }
        if self.tolerance.is_nan() || self.tolerance <= 0.0 {
            return Err(OrbitError::InvalidOptions {
                message: format!("the tolerance is {}: give a positive one", self.tolerance),
            });
        }
        match self.pin {
            Some(Pin::Amplitude(i)) if i >= N => {
                return Err(OrbitError::InvalidOptions {
                    message: format!(
                        "pin_amplitude({i}): the system's coordinates are numbered 0 to {}",
                        N - 1
                    ),
                });
            }
            Some(Pin::Energy(e)) if !e.is_finite() => {
                return Err(OrbitError::InvalidOptions {
                    message: format!("pin_energy({e}): give a finite energy"),
                });
            }
            Some(Pin::Amplitude(_)) if self.section.is_some() => {
                return Err(OrbitError::InvalidOptions {
                    message: "pin_amplitude is a phase condition (the orbit turns at t₀), and so \
                              is a Poincaré section: use one or the other (with a section, \
                              pin_energy picks an orbit out of a family)"
                        .into(),
                });
            }
            Some(_) if self.fixed_period => {
                return Err(OrbitError::InvalidOptions {
                    message: "a pin picks an orbit out of an autonomous system's family; a \
                              forced system's period is fixed and its orbits isolated: use \
                              Shooting::autonomous, or drop the pin"
                        .into(),
                });
            }
            _ => {}
        }
        if self.section.is_some() && self.fixed_period {
            return Err(OrbitError::InvalidOptions {
                message: "a Poincaré section is for an autonomous system (its return time is the \
                          period); a forced system's section is the stroboscopic one that \
                          Shooting::forced shoots to: drop the section"
                    .into(),
            });
        }
        Ok(())
    }

    /// Refuses an orbit that the closure cannot tell from an equilibrium (periodic with any
    /// period: not the orbit looked for).
    fn not_an_equilibrium(
        &self,
        shot: &Shot,
        x: &[f64],
        period: f64,
        (iterations, closure): (usize, f64),
    ) -> Result<(), OrbitError> {
        // An equilibrium is periodic with any period: not the orbit looked for. Told apart by
        // the orbit's excursion, about |f(x₀)| T, against what the closure resolves: an orbit of
        // amplitude 1e-8 is one at a tolerance of 1e-20 (not against a size of 1: it was
        // refused as an equilibrium), and is not resolved at the default 1e-10.
        let speed = shot.f_start.iter().map(|f| f * f).sum::<f64>().sqrt();
        if !self.fixed_period && speed * period <= 1e3 * self.tolerance.max(closure) {
            return Err(self.no_convergence(
                iterations,
                closure,
                x,
                period,
                &format!(
                    "Newton ended where the motion's excursion over a period, |f(x₀)| T = {:.1e}, \
                     is within 1000 times the closure tolerance {:.1e}: an equilibrium (f(x₀) = 0, \
                     periodic with any period) or an orbit too small to resolve. For a small \
                     orbit lower .tolerance(..) below its amplitude / 1000 (with an atol to \
                     match); to leave the equilibrium pin the orbit looked for \
                     (`pin_amplitude(i)` from a turning point, or `pin_energy(e)`), or start \
                     farther from it",
                    speed * period,
                    self.tolerance
                ),
            ));
        }
        Ok(())
    }

    /// Backtracking along a Newton step: halves it until the residual falls, from a step that
    /// changes the period by at most half and the state by at most 10 times its size (a trust
    /// region: where the linear model asks for more, as near an extremum of the energy pinned
    /// to a value it does not reach, a full step would shoot over an enormous period or from
    /// an enormous state, and each of the halvings runs a long shot). The accepted iterate,
    /// its period, shot and residual.
    fn line_search(
        &self,
        x: &[f64],
        period: f64,
        bound: f64,
        step: &[f64],
        closure: f64,
    ) -> Option<(Vec<f64>, f64, Shot, f64)> {
        let n2 = 2 * N;
        let dx = step[..n2].iter().map(|v| v * v).sum::<f64>().sqrt();
        let room = 10.0 * x.iter().map(|v| v * v).sum::<f64>().sqrt().max(1.0);
        let mut lambda = (room / dx).min(1.0);
        if self.free_period() {
            lambda = lambda.min(0.5 * period / step[n2].abs());
        }
        if lambda.is_nan() || lambda <= 0.0 {
            lambda = 1.0;
        }
        for _ in 0..30 {
            let xt: Vec<f64> = (0..n2).map(|i| x[i] + lambda * step[i]).collect();
            let pt = if self.free_period() {
                period + lambda * step[n2]
            } else {
                period
            };
            if pt > 0.0
                && let Ok(s) = self.shoot(&xt, bound * pt)
            {
                let c = self.residual(&s, &xt);
                if c < closure {
                    return Some((xt, s.period, s, c));
                }
            }
            lambda *= 0.5;
        }
        None
    }

    /// Whether Newton's steps set aside the directions of a family of orbits (an autonomous
    /// system without a pin, or one with a cyclic coordinate).
    fn cuts_families(&self) -> bool {
        (!self.fixed_period && self.pin.is_none()) || L::CYCLIC.iter().any(|&c| c)
    }

    /// The least-norm Newton step (Δx, ΔT) (ΔT absent for a fixed period); with `truncate`,
    /// the singular directions of a family set aside.
    fn newton_step(
        &self,
        shot: &Shot,
        x: &[f64],
        closure: f64,
        truncate: bool,
    ) -> Result<Vec<f64>, OrbitError> {
        let n2 = 2 * N;
        let pin = self.pin_row(x);
        let (rows, cols) = if self.fixed_period {
            (n2, n2)
        } else {
            let rows = n2 + 1 + usize::from(pin.is_some());
            (rows, n2 + usize::from(self.free_period()))
        };
        let mut a = DMatrix::zeros(rows, cols);
        let mut b = DVector::zeros(rows);
        let gap = self.gap(shot, x);
        for i in 0..n2 {
            for j in 0..n2 {
                a[(i, j)] = shot.phi[(i, j)] - if i == j { 1.0 } else { 0.0 };
            }
            b[i] = -gap[i];
        }
        if let Some(g) = self.section_gradient(x) {
            // The return is to the level through the start, g(x(t*)) = g(x₀), so a step that
            // moves g(x₀) by ∇g(x₀)·Δx moves the return along the flow by that over
            // ∇g(x(t*))·f(x(t*)) in time: the closure rows' Jacobian is Φ (the return to a
            // fixed level) plus f(x(t*)) ∇g(x₀)ᵀ / ∇g(x(t*))·f(x(t*)). Without that term the
            // rows contradict the section's where the iterate is off the section (Φ's row of
            // g's own coordinate is 0, the residual's derivative there is 1), and Newton stalls
            // off it instead of converging.
            if let Some(g_end) = self.section_gradient(&shot.end) {
                let rate: f64 = g_end.iter().zip(&shot.f_end).map(|(a, b)| a * b).sum();
                if rate.is_finite() && rate != 0.0 {
                    for i in 0..n2 {
                        for j in 0..n2 {
                            a[(i, j)] += shot.f_end[i] * g[j] / rate;
                        }
                    }
                }
            }
            // The start stays on the section: ∇g(x₀)·Δx = −g(x₀).
            for (j, gj) in g.iter().enumerate() {
                a[(n2, j)] = *gj;
            }
            b[n2] = -shot.level;
        } else if !self.fixed_period {
            for i in 0..n2 {
                a[(i, n2)] = shot.f_end[i];
                a[(n2, i)] = shot.f_start[i];
            }
            // An amplitude's turning point fixes the phase: q̇_i(t₀) = 0 replaces f(x₀)·Δx = 0.
            if let Some(Pin::Amplitude(i)) = self.pin {
                for j in 0..n2 {
                    a[(n2, j)] = if j == N + i { 1.0 } else { 0.0 };
                }
                b[n2] = -x[N + i];
            }
        }
        if let Some((r, g)) = &pin
            && !self.fixed_period
        {
            for (i, gi) in g.iter().enumerate() {
                a[(n2 + 1, i)] = *gi;
            }
            b[n2 + 1] = -r;
        }
        let svd = nalgebra::SVD::try_new(a, true, true, f64::EPSILON, 10_000).ok_or_else(|| {
            OrbitError::Eigen {
                message: "the SVD of the Newton matrix did not converge (non-finite monodromy?): \
                          tighten the method's tolerance"
                    .into(),
            }
        })?;
        // Singular values below the residual's relative size are taken as zero where orbits come
        // in families (an autonomous system's energy, a conserved momentum): such an integral
        // makes the matrix singular on the orbit and nearly so (by O(residual)) off it, where
        // inverting that direction would throw the iterate along the family (towards an
        // equilibrium, the trivially periodic end of many families). A forced system without a
        // cyclic coordinate has isolated orbits: only round-off is cut (1e-9), so near a
        // bifurcation, where a multiplier nears 1 and Φ(T) − I a small singular value, Newton
        // keeps the direction it needs.
        let smax = svd.singular_values.max();
        let size = x.iter().map(|v| v * v).sum::<f64>().sqrt().max(1.0);
        // A pin takes the family's direction out (the energy's, for an autonomous system).
        let cutoff = if truncate && self.cuts_families() {
            (closure / size).clamp(1e-9, 1e-2)
        } else {
            1e-9
        };
        let dx = svd
            .solve(&b, cutoff * smax)
            .map_err(|e| OrbitError::Eigen { message: e.into() })?;
        Ok(dx.iter().copied().collect())
    }

    /// Whether the period is one of Newton's unknowns (an autonomous system shot without a
    /// section).
    fn free_period(&self) -> bool {
        !self.fixed_period && self.section.is_none()
    }

    /// ∇g of the section's function at x (t₀), by central differences (a Newton row: its error
    /// slows the iteration, never moves the orbit, whose residual is g itself); `None` without
    /// a section.
    fn section_gradient(&self, x: &[f64]) -> Option<Vec<f64>> {
        let ev = (self.section.as_ref()?)();
        let g = |x: &[f64]| {
            let q: [f64; N] = core::array::from_fn(|i| x[i]);
            let v: [f64; N] = core::array::from_fn(|i| x[N + i]);
            ev.value(self.t0, &q, &v)
        };
        let mut xt = x.to_vec();
        Some(
            (0..2 * N)
                .map(|j| {
                    let h = f64::EPSILON.cbrt() * x[j].abs().max(1.0);
                    xt[j] = x[j] + h;
                    let up = g(&xt);
                    xt[j] = x[j] - h;
                    let down = g(&xt);
                    xt[j] = x[j];
                    (up - down) / (2.0 * h)
                })
                .collect(),
        )
    }

    fn no_convergence(
        &self,
        iterations: usize,
        closure: f64,
        x: &[f64],
        period: f64,
        message: &str,
    ) -> OrbitError {
        OrbitError::NoConvergence {
            iterations,
            closure,
            q: x[..N].to_vec(),
            qdot: x[N..].to_vec(),
            period,
            message: message.into(),
        }
    }
}

/// What one shot gives: x(T), Φ(T), f(x(T)) and f(x₀); with a section, the return, the return
/// map's Jacobian, the return time as T and the section's g at the start.
struct Shot {
    end: Vec<f64>,
    phi: DMatrix<f64>,
    f_end: Vec<f64>,
    f_start: Vec<f64>,
    period: f64,
    level: f64,
}

/// The eigenvalues of the monodromy matrix, by decreasing modulus.
///
/// ```
/// use lagrange_runtime::{sensitivity::multipliers, DMatrix};
/// let m = DMatrix::from_row_slice(2, 2, &[0.0, -2.0, 0.5, 0.0]); // μ = ±i
/// let mu = multipliers(&m).unwrap();
/// assert!(mu.iter().all(|m| (m.norm() - 1.0).abs() < 1e-15));
/// ```
pub fn multipliers(monodromy: &DMatrix<f64>) -> Result<Vec<Complex<f64>>, OrbitError> {
    let schur =
        nalgebra::Schur::try_new(monodromy.clone(), f64::EPSILON, 10_000).ok_or_else(|| {
            OrbitError::Eigen {
                message:
                    "the Schur iteration of the monodromy matrix did not converge: check that \
                      it is finite, or tighten the method's tolerance"
                        .into(),
            }
        })?;
    let mut mu: Vec<Complex<f64>> = schur.complex_eigenvalues().iter().copied().collect();
    mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(b.re.total_cmp(&a.re)));
    Ok(mu)
}

/// The verdict from the multipliers; `autonomous`: one multiplier 1 (the flow's direction) is
/// trivial and not counted. Multipliers within [`TRIVIAL_RADIUS`] of 1 are neutral.
fn classify(mu: &[Complex<f64>], autonomous: bool) -> OrbitStability {
    let near_one = |m: &Complex<f64>| (m - 1.0).norm() <= TRIVIAL_RADIUS;
    let others: Vec<f64> = mu
        .iter()
        .filter(|m| !near_one(m))
        .map(|m| m.norm())
        .collect();
    let largest = others.iter().copied().fold(0.0, f64::max);
    if largest > 1.0 + MULTIPLIER_TOL {
        return OrbitStability::Unstable { largest };
    }
    let n_near = mu.len() - others.len();
    let only_trivial = n_near == 0 || (autonomous && n_near == 1);
    if only_trivial && others.iter().all(|m| *m < 1.0 - MULTIPLIER_TOL) {
        OrbitStability::AsymptoticallyStable
    } else {
        OrbitStability::Neutral
    }
}

/// Which contacts a system that declares contacts has closed at (q, q̇, t) (its contact view's
/// start); `None` for any other system.
struct ClosedAt<const N: usize> {
    q: [f64; N],
    qdot: [f64; N],
    t: f64,
}

impl<'s, L: Lagrangian<N> + 's, const N: usize> crate::lagrangian::Declared<'s, L, N>
    for ClosedAt<N>
{
    type Output = Option<Vec<bool>>;

    fn plain(self, _sys: &'s L) -> Self::Output {
        None
    }

    fn constrained<const K: usize>(self, _sys: &'s L) -> Self::Output
    where
        L: crate::constraints::Holonomic<N, K>,
    {
        None
    }

    fn contacts<const K: usize>(self, sys: &'s L) -> Self::Output
    where
        L: crate::contact::Unilateral<N, K>,
    {
        super::super::contacts::ContactView::new(sys, &self.q, &self.qdot, self.t)
            .ok()
            .map(|view| view.closed().to_vec())
    }
}

/// f at a shot's start and end by second-order differences of its samples: one-sided at the
/// start (the samples at t₀, t₀ + δ, t₀ + 2δ: `starts`), central at the end (T ∓ δ of `ends`;
/// NaN where there are none: a section's end, whose Newton rows do not take it).
fn sampled_flow<const N: usize>(
    tr: &Trajectory<N>,
    starts: [Option<usize>; 3],
    ends: Option<(usize, usize, usize)>,
    delta: f64,
) -> Result<(Vec<f64>, Vec<f64>), OrbitError> {
    let [Some(k0), Some(k1), Some(k2)] = starts else {
        return Err(OrbitError::InvalidOptions {
            message: "the run did not record the samples of the flow at its start (an event \
                      ended it within 2e-4 of the period): start away from the events"
                .into(),
        });
    };
    let y = |k: usize| -> Vec<f64> { tr.q[k].iter().chain(&tr.qdot[k]).copied().collect() };
    let (y0, y1, y2) = (y(k0), y(k1), y(k2));
    let forward = (0..2 * N)
        .map(|i| (-3.0 * y0[i] + 4.0 * y1[i] - y2[i]) / (2.0 * delta))
        .collect();
    let central = match ends {
        Some((a, _, c)) => {
            let (a, b) = (y(a), y(c));
            (0..2 * N).map(|i| (b[i] - a[i]) / (2.0 * delta)).collect()
        }
        None => vec![f64::NAN; 2 * N],
    };
    Ok((forward, central))
}
