//! Linearization of the equations of motion about a state: M δq̈ + C δq̇ + K δq = 0, its
//! eigenvalues, normal modes and stability, and the equilibria from which it is usually taken.
//!
//! [`Linearize::linearize`] takes a reference motion through (q₀, q̇₀) at time t (an equilibrium,
//! q̇₀ = 0, or a steady motion such as a spinning top) and returns the exact first-order
//! variation of M(q, q̇, t) q̈ = F(q, q̇, t), F = f_L + Q − ∂D/∂q̇, about it. With a₀ = q̈(q₀, q̇₀, t)
//! and H the Hessian of L in (q, q̇),
//!
//! ```text
//! M = H_q̇q̇
//! C = (D_z H)_q̇q̇ + H_q̇q − H_qq̇ − ∂(Q − ∂D/∂q̇)/∂q̇
//! K = (D_z H)_q̇q − H_qq − ∂(Q − ∂D/∂q̇)/∂q
//! ```
//!
//! where D_z is the derivative along z = (q̇₀, a₀, 1) in (q, q̇, t): the total time derivative
//! along the reference motion. It gathers the terms ∂f_L/∂(q, q̇) ∋ −(∂/∂t + q̇₀·∂/∂q) H_q̇· and
//! ∂M/∂(q, q̇)·a₀ = (a₀·∂/∂q̇) H_q̇· into one directional derivative, taken in one evaluation of L
//! in the [`LinJet`] (exact third derivatives of L; no finite differences). At an equilibrium of
//! an autonomous L it reduces to K = −∂²L/∂q∂q and C = A − Aᵀ (+ damping), Aᵢⱼ = ∂²L/∂q̇ᵢ∂qⱼ:
//! C holds the gyroscopic (skew) part and the damping, K the potential and centrifugal parts.
//!
//! The first-order system of x = (δq, δq̇) is ẋ = A x with A = [[0, I], [−M⁻¹K, −M⁻¹C]] (the
//! companion form of the quadratic eigenvalue problem (λ²M + λC + K) v = 0), whose 2N
//! [eigenvalues](Linearization::eigenvalues) decide [stability](Linearization::stability); an
//! undamped, non-gyroscopic linearization (C = 0, K symmetric) also has real
//! [normal modes](Linearization::modes), K v = ω² M v.
//!
//! [`equilibrium`] finds q with q̈(q, 0, t) = 0 by Newton's method from a guess.
//!
//! Systems with holonomic constraints ([`Holonomic`](crate::Holonomic)) are not covered yet:
//! `linearize` treats L as unconstrained; a linearization on the constraint manifold (in
//! coordinates of its tangent space) is still to come.

use core::fmt;

use nalgebra::{Complex, DMatrix, SMatrix, SVector};

use crate::error::DynamicsError;
use crate::jet::LinJet;
use crate::lagrangian::{Lagrangian, applied_jacobian};

mod constrained;
pub(crate) use constrained::constrained_state_jacobian;
pub use constrained::{ConstrainedLinearization, LinearizeConstrained};

/// Relative tolerance of the stability classification: an eigenvalue counts as on the imaginary
/// axis when |Re λ| ≤ `STABILITY_TOL` × s, s the frequency scale of the linearization (the
/// largest of max |λ|, ‖M⁻¹C‖ and √‖M⁻¹K‖, Frobenius norms).
///
/// Why 1e-6 and not ε: a defective eigenvalue (a Jordan block, as the λ = 0 pair of a cyclic
/// coordinate whose velocity drifts) is computed in floating point split by about √ε ≈ 1.5e-8
/// of the scale, and a pair of nearly equal gyroscopic frequencies near a threshold by as much;
/// 1e-6 classifies those as on the axis while a real growth rate above 1e-6 of the frequency
/// scale still counts.
///
/// ```
/// assert_eq!(lagrange_runtime::linearize::STABILITY_TOL, 1e-6);
/// ```
pub const STABILITY_TOL: f64 = 1e-6;

/// Relative tolerance under which [`Linearization::modes`] treats C as zero and K as symmetric:
/// ‖C‖ ≤ 1e-10 s‖M‖ and ‖K − Kᵀ‖ ≤ 1e-10 ‖K‖ (Frobenius norms, s as in [`STABILITY_TOL`]).
///
/// ```
/// assert_eq!(lagrange_runtime::linearize::SYMMETRY_TOL, 1e-10);
/// ```
pub const SYMMETRY_TOL: f64 = 1e-10;

/// The linearized equations of motion M δq̈ + C δq̇ + K δq = 0 about a reference motion (see the
/// [module documentation](self) for the formulas).
///
/// ```
/// use lagrange_runtime::{Lagrangian, Linearize, Scalar};
/// /// A damped oscillator m ẍ + b ẋ + k x = 0: m = 2, b = 0.4, k = 8.
/// struct Damped;
/// impl Lagrangian<1> for Damped {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     const ENERGY_CONSERVED: bool = false;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] - q[0] * q[0] * 4.0 }
///     fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.2 }
/// }
/// let lin = Damped.linearize(&[0.0], &[0.0], 0.0).unwrap();
/// assert_eq!((lin.m[(0, 0)], lin.c[(0, 0)], lin.k[(0, 0)]), (2.0, 0.4, 8.0));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Linearization<const N: usize> {
    /// The mass matrix M = ∂²L/∂q̇∂q̇ at the reference state.
    pub m: SMatrix<f64, N, N>,
    /// The velocity matrix C: gyroscopic (skew) part and damping.
    pub c: SMatrix<f64, N, N>,
    /// The stiffness matrix K: potential and centrifugal parts (and the position dependence of
    /// the applied forces).
    pub k: SMatrix<f64, N, N>,
}

/// One normal mode of an undamped, non-gyroscopic linearization: K v = ω² M v.
///
/// ```
/// use lagrange_runtime::linearize::Mode;
/// use lagrange_runtime::SMatrix;
/// let m = Mode::<1> { omega_squared: 4.0, shape: SMatrix::from([[1.0]]) };
/// assert_eq!(m.omega(), Some(2.0));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Mode<const N: usize> {
    /// ω²: positive for an oscillation, negative for an instability (growth rate √−ω²).
    pub omega_squared: f64,
    /// The mode shape v, M-normalized (vᵀ M v = 1), its largest component positive.
    pub shape: SVector<f64, N>,
}

impl<const N: usize> Mode<N> {
    /// The angular frequency ω = √ω², or `None` for an unstable mode (ω² < 0).
    ///
    /// ```
    /// use lagrange_runtime::{linearize::Mode, SMatrix};
    /// let m = Mode::<1> { omega_squared: -1.0, shape: SMatrix::from([[1.0]]) };
    /// assert_eq!(m.omega(), None);
    /// ```
    pub fn omega(&self) -> Option<f64> {
        (self.omega_squared >= 0.0).then(|| self.omega_squared.sqrt())
    }
}

/// The stability of a linearization, from the real parts of its eigenvalues (tolerance
/// [`STABILITY_TOL`]).
///
/// This is the spectral (linear) criterion. A marginally stable linearization may still hide a
/// secular drift (a defective eigenvalue on the axis, such as the λ = 0 pair of a cyclic
/// coordinate: a neighbouring steady motion at another rate) and says nothing about the
/// nonlinear stability, which the energy or an integral decides.
///
/// ```
/// use lagrange_runtime::linearize::Stability;
/// assert!(Stability::MarginallyStable.is_stable());
/// assert!(!Stability::Unstable { growth_rate: 0.5 }.is_stable());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stability {
    /// Every eigenvalue has Re λ < −tol: perturbations decay (damped systems).
    AsymptoticallyStable,
    /// No eigenvalue has Re λ > tol, some lie on the imaginary axis (within tol): perturbations
    /// oscillate without growing exponentially (conservative and gyroscopic systems).
    MarginallyStable,
    /// Some eigenvalue has Re λ > tol: perturbations grow like e^(growth_rate·t).
    Unstable {
        /// The largest real part of the eigenvalues.
        growth_rate: f64,
    },
}

impl Stability {
    /// `true` unless [`Stability::Unstable`].
    ///
    /// ```
    /// use lagrange_runtime::linearize::Stability;
    /// assert!(Stability::AsymptoticallyStable.is_stable());
    /// ```
    pub fn is_stable(&self) -> bool {
        !matches!(self, Stability::Unstable { .. })
    }
}

/// Why a linearization could not be analysed, or why no equilibrium was found: what happened,
/// where, and what to try.
///
/// ```
/// use lagrange_runtime::linearize::LinearizationError;
/// let e = LinearizationError::NotUndamped { message: "C ≠ 0".into() };
/// assert!(e.to_string().contains("C ≠ 0"));
/// ```
#[derive(Clone, PartialEq)]
#[non_exhaustive]
pub enum LinearizationError {
    /// The equations of motion could not be evaluated or solved (singular mass matrix, non-finite
    /// values).
    Dynamics(DynamicsError),
    /// M is not symmetric positive definite, so neither M⁻¹ nor the modes exist.
    MassNotPositiveDefinite {
        /// What was found and what to try.
        message: String,
    },
    /// [`Linearization::modes`] was asked of a linearization with damping, gyroscopic terms or
    /// a non-symmetric K, which has no real normal modes.
    NotUndamped {
        /// What was found and what to try.
        message: String,
    },
    /// An eigenvalue iteration did not converge.
    Eigen {
        /// Which problem and what to try.
        message: String,
    },
    /// A linearization on the constraint manifold could not be reduced to the coordinates and
    /// speeds asked for (an unknown name, dependent choices, or unnamed ones that drive them).
    Reduction {
        /// What was found and what to name instead.
        message: String,
    },
    /// Newton's method found no equilibrium from the guess.
    NoEquilibrium {
        /// Time.
        t: f64,
        /// The last iterate.
        q: Vec<f64>,
        /// The accelerations q̈(q, 0, t) there.
        residual: Vec<f64>,
        /// Newton iterations taken.
        iterations: usize,
        /// What happened and what to try.
        message: String,
    },
}

impl fmt::Display for Stability {
    /// `asymptotically stable`, `marginally stable`, or `unstable (growth rate 0.5)`.
    ///
    /// ```
    /// use lagrange_runtime::linearize::Stability;
    /// assert_eq!(Stability::Unstable { growth_rate: 0.5 }.to_string(), "unstable (growth rate 0.5)");
    /// assert_eq!(Stability::MarginallyStable.to_string(), "marginally stable");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stability::AsymptoticallyStable => f.write_str("asymptotically stable"),
            Stability::MarginallyStable => f.write_str("marginally stable"),
            Stability::Unstable { growth_rate } => {
                write!(f, "unstable (growth rate {growth_rate})")
            }
        }
    }
}

impl<const N: usize> fmt::Display for Linearization<N> {
    /// M δq̈ + C δq̇ + K δq = 0 with the three matrices, one row per line (`{:.3}` and the like
    /// apply to every entry).
    ///
    /// ```
    /// use lagrange_runtime::{linearize::Linearization, SMatrix};
    /// let lin = Linearization::<1> { m: SMatrix::from([[2.0]]), c: SMatrix::from([[0.4]]), k: SMatrix::from([[8.0]]) };
    /// assert_eq!(lin.to_string(), "M δq̈ + C δq̇ + K δq = 0 with\nM = [2]\nC = [0.4]\nK = [8]");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("M δq̈ + C δq̇ + K δq = 0 with")?;
        for (name, a) in [("M", &self.m), ("C", &self.c), ("K", &self.k)] {
            write!(f, "\n{name} = ")?;
            for i in 0..N {
                if i > 0 {
                    f.write_str("\n    ")?;
                }
                f.write_str("[")?;
                for j in 0..N {
                    if j > 0 {
                        f.write_str(", ")?;
                    }
                    fmt::Display::fmt(&a[(i, j)], f)?;
                }
                f.write_str("]")?;
            }
        }
        Ok(())
    }
}

impl fmt::Display for LinearizationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LinearizationError::Dynamics(e) => write!(f, "{e}"),
            LinearizationError::MassNotPositiveDefinite { message } => {
                write!(f, "mass matrix not positive definite: {message}")
            }
            LinearizationError::NotUndamped { message } => {
                write!(f, "no real normal modes: {message}")
            }
            LinearizationError::Eigen { message } => {
                write!(f, "eigenvalue iteration failed: {message}")
            }
            LinearizationError::Reduction { message } => {
                write!(f, "no reduction to these coordinates: {message}")
            }
            LinearizationError::NoEquilibrium {
                t,
                q,
                residual,
                iterations,
                message,
            } => write!(
                f,
                "no equilibrium found at t = {t} after {iterations} Newton iterations \
                 (last q = {q:?}, q̈ = {residual:?}): {message}"
            ),
        }
    }
}

impl std::error::Error for LinearizationError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            LinearizationError::Dynamics(e) => Some(e),
            _ => None,
        }
    }
}

impl From<DynamicsError> for LinearizationError {
    fn from(e: DynamicsError) -> Self {
        LinearizationError::Dynamics(e)
    }
}

/// `linearize` and `equilibrium` as methods of every [`Lagrangian`] system (the prelude brings
/// this trait in): the linearization is built on the trait, so it lives here rather than in it.
pub trait Linearize<const N: usize>: Lagrangian<N> {
    /// The linearized equations of motion M δq̈ + C δq̇ + K δq = 0 about the motion through
    /// (q₀, q̇₀) at time t: an equilibrium (q̇₀ = 0) or a steady motion (q̇₀ ≠ 0), exact from the
    /// jets (third derivatives of L along the reference motion; no finite differences). See
    /// [`linearize`](crate::linearize) for the formulas, the eigenvalues, modes and stability.
    ///
    /// Fails where the accelerations cannot be solved (singular M, non-finite values). A system
    /// whose `#[lagrangian]` declares constraints (holonomic or velocity) is refused
    /// ([`DynamicsError::Constrained`]): this linearizes the unconstrained L; the linearization
    /// on the constraint manifold is
    /// [`linearize_on_constraints`](crate::LinearizeConstrained::linearize_on_constraints).
    ///
    /// ```
    /// use lagrange::prelude::*;
    ///
    /// /// A pendulum: ω² = g/l about the bottom.
    /// pub struct Pendulum { pub g: f64, pub l: f64 }
    ///
    /// #[lagrangian]
    /// impl Pendulum {
    ///     fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
    ///         0.5 * self.l * self.l * theta_dot * theta_dot + self.g * self.l * theta.cos()
    ///     }
    /// }
    ///
    /// let lin = Pendulum { g: 4.0, l: 1.0 }.linearize(&[0.0], &[0.0], 0.0).unwrap();
    /// assert_eq!(lin.modes().unwrap()[0].omega(), Some(2.0));
    /// assert!(lin.is_stable());
    /// ```
    fn linearize(
        &self,
        q0: &[f64; N],
        qdot0: &[f64; N],
        t: f64,
    ) -> Result<Linearization<N>, DynamicsError> {
        if Self::COMPILED.constrained {
            return Err(DynamicsError::Constrained {
                t,
                q: q0.to_vec(),
                qdot: qdot0.to_vec(),
                message: "`linearize` linearizes the unconstrained L, whose modes include motions \
                          the constraints forbid (its answer would be wrong, not approximate): \
                          call `linearize_on_constraints` (trait `LinearizeConstrained`, in the \
                          prelude) and reduce it to independent coordinates, \
                          `.reduce([\"phi\", \"delta\"])` or `.state_matrix(&coordinates, &speeds)`"
                    .to_string(),
            });
        }
        jet_linearize(self, q0, qdot0, t)
    }

    /// An equilibrium near `q_guess`: q with q̈(q, 0, t) = 0, by Newton with the exact Jacobian
    /// −M⁻¹K ([`linearize::equilibrium`](crate::linearize::equilibrium), as a method); a typed
    /// error when there is none nearby.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Linearize, Scalar};
    /// /// A pendulum, L = θ̇²/2 + 4 cos θ: the bottom is θ = 0.
    /// struct P;
    /// impl Lagrangian<1> for P {
    ///     const COORDINATES: [&'static str; 1] = ["theta"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() * 4.0 }
    /// }
    /// let q = P.equilibrium(&[0.3], 0.0).unwrap();
    /// assert!(q[0].abs() < 1e-14);
    /// ```
    fn equilibrium(&self, q_guess: &[f64; N], t: f64) -> Result<[f64; N], LinearizationError> {
        equilibrium(self, q_guess, t)
    }
}

impl<L: Lagrangian<N> + ?Sized, const N: usize> Linearize<N> for L {}

/// The linearization about (q₀, q̇₀, t) from the jets: the default of
/// [`Linearize::linearize`] (see the [module documentation](self) for the formulas).
///
/// ```
/// use lagrange_runtime::{linearize::jet_linearize, Lagrangian, Scalar};
/// /// A pendulum, L = θ̇²/2 + 9 cos θ: K = 9 at the bottom, −9 at the top.
/// struct P;
/// impl Lagrangian<1> for P {
///     const COORDINATES: [&'static str; 1] = ["theta"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() * 9.0 }
/// }
/// assert_eq!(jet_linearize(&P, &[0.0], &[0.0], 0.0).unwrap().k[(0, 0)], 9.0);
/// assert_eq!(jet_linearize(&P, &[std::f64::consts::PI], &[0.0], 0.0).unwrap().k[(0, 0)], -9.0);
/// ```
pub fn jet_linearize<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<Linearization<N>, DynamicsError>
where
    L: Lagrangian<N> + ?Sized,
{
    let a0 = sys.accelerations(q, qdot, t)?;
    linearize_along(sys, q, qdot, t, &a0)
}

/// The input matrix B of M δq̈ + C δq̇ + K δq = B δu: the derivatives of the applied
/// generalized forces (Q − ∂D/∂q̇, what `fn forces` and `fn dissipation` declare) at (q, q̇, t)
/// with respect to parameters u, the system at u being `make(&u)` (e.g. a cart-pole whose
/// `fn forces` pushes the cart with its field `push`).
///
/// By fourth-order central differences in each u_k, with the step of the sensitivities'
/// parameters (ε^(1/5) s for the scale s, |u_k| or 1, that Richardson's error estimate prefers
/// at this state: an input of 1e-8 is stepped within its own scale, a force sin u at u = 10⁴ on
/// the scale 1): exact up to round-off for forces affine in the parameters (inputs usually are),
/// to ~1e-12 relative for smooth ones.
/// Fails where the forces are not finite.
///
/// ```
/// use lagrange_runtime::{linearize::input_matrix, Lagrangian, Scalar};
/// /// A cart of mass 2 pushed by `push`, a pendulum bob of mass 1 on a rod of length 1.
/// struct CartPole { push: f64 }
/// impl Lagrangian<2> for CartPole {
///     const COORDINATES: [&'static str; 2] = ["x", "theta"];
///     const CYCLIC: [bool; 2] = [true, false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
///         v[0] * v[0] * 1.5 + v[0] * v[1] * q[1].cos() + v[1] * v[1] * 0.5 - q[1].cos() * 9.81
///     }
///     fn generalized_forces<S: Scalar>(&self, _q: &[S; 2], _v: &[S; 2], _t: S) -> [S; 2] {
///         [S::constant(self.push), S::constant(0.0)]
///     }
/// }
/// let b = input_matrix(|u: &[f64; 1]| CartPole { push: u[0] }, &[0.0], &[0.0, 0.0], &[0.0, 0.0], 0.0).unwrap();
/// assert_eq!((b[(0, 0)], b[(1, 0)]), (1.0, 0.0));
/// ```
pub fn input_matrix<L, F, const N: usize, const U: usize>(
    make: F,
    u0: &[f64; U],
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<SMatrix<f64, N, U>, DynamicsError>
where
    L: Lagrangian<N>,
    F: Fn(&[f64; U]) -> L,
{
    let applied = |u: &[f64; U]| make(u).pieces(q, qdot, t).applied;
    // NaN where the forces fail near u₀ (the error below).
    let mut b = SMatrix::<f64, N, U>::from_element(f64::NAN);
    for k in 0..U {
        // The forces as a function of u_k alone, `None` where they are not finite.
        let f = |x: f64| {
            let mut u = *u0;
            u[k] = x;
            let a = applied(&u);
            a.iter().all(|v| v.is_finite()).then(|| a.to_vec())
        };
        let h = crate::integrate::difference_step(u0[k], f);
        let [Some(p1), Some(m1), Some(p2), Some(m2)] =
            [h, -h, 2.0 * h, -2.0 * h].map(|d| f(u0[k] + d))
        else {
            continue;
        };
        for i in 0..N {
            b[(i, k)] = crate::integrate::central(h, [p1[i], m1[i], p2[i], m2[i]]);
        }
    }
    if b.iter().all(|x| x.is_finite()) {
        Ok(b)
    } else {
        Err(DynamicsError::NonFinite {
            t,
            q: q.to_vec(),
            qdot: qdot.to_vec(),
            message: "the applied forces are not finite near these parameters, so the input \
                      matrix does not exist here"
                .into(),
        })
    }
}

/// The first-order state-space form ẋ = A x + B u of the system `make(u)` linearized about
/// (q, q̇) at t and the inputs u₀ (a control engineer's (A, B)): the state is
/// x = (δq₀ … δq_{N−1}, δq̇₀ … δq̇_{N−1}) (coordinates in `COORDINATES` order, then their
/// velocities), u = δu. A is [`Linearization::state_matrix`] of the system at u₀ (2N × 2N) and
/// B = [0; M⁻¹ B_Q] (2N × U) with B_Q the [`input_matrix`] of the generalized forces.
///
/// Fails where the linearization or the input matrix does, or where M is singular.
///
/// ```
/// use lagrange_runtime::{linearize::state_space, Lagrangian, Scalar};
/// /// A mass of 2 on a spring of stiffness 8 pushed by the force `push`: ẍ = −4x + u/2.
/// struct Pushed { push: f64 }
/// impl Lagrangian<1> for Pushed {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] - q[0] * q[0] * 4.0 }
///     fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], _t: S) -> [S; 1] {
///         [S::constant(self.push)]
///     }
/// }
/// let (a, b) = state_space(|u: &[f64; 1]| Pushed { push: u[0] }, &[0.0], &[0.0], &[0.0], 0.0).unwrap();
/// assert_eq!((a[(0, 1)], a[(1, 0)], a[(1, 1)]), (1.0, -4.0, 0.0));
/// assert_eq!((b[(0, 0)], b[(1, 0)]), (0.0, 0.5));
/// ```
pub fn state_space<L, F, const N: usize, const U: usize>(
    make: F,
    u0: &[f64; U],
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<(DMatrix<f64>, DMatrix<f64>), LinearizationError>
where
    L: Lagrangian<N>,
    F: Fn(&[f64; U]) -> L,
{
    let lin = jet_linearize(&make(u0), q, qdot, t)?;
    let a = lin.state_matrix()?;
    let bq = input_matrix(&make, u0, q, qdot, t)?;
    let mb = dense(&lin.m)
        .lu()
        .solve(&DMatrix::from_fn(N, U, |i, k| bq[(i, k)]))
        .filter(|x| x.iter().all(|v| v.is_finite()))
        .ok_or_else(|| LinearizationError::MassNotPositiveDefinite {
            message: format!(
                "M is singular (M = {}), so ẋ = A x + B u does not exist here: choose \
                 coordinates regular at the reference state",
                fmt_matrix(&lin.m)
            ),
        })?;
    let mut b = DMatrix::zeros(2 * N, U);
    b.view_mut((N, 0), (N, U)).copy_from(&mb);
    Ok((a, b))
}

/// M, C and K of M δq̈ + C δq̇ + K δq = 0 about the motion through (q, q̇) at t with
/// accelerations `a0` (the system's own, or a constrained motion's): the derivatives of
/// M q̈ − f − Q + ∂D/∂q̇ at q̈ = `a0` from one evaluation of L in the [`LinJet`].
pub(crate) fn linearize_along<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
    a0: &[f64; N],
) -> Result<Linearization<N>, DynamicsError>
where
    L: Lagrangian<N> + ?Sized,
{
    // An inline const: each system instantiates only the path its N takes (the column path's
    // jet for every small system, or the LinJet of 200 KB per number for the large ones, would
    // otherwise be compiled and never run).
    let lin = if const { N > crate::jet::HESSIAN_BY_COLUMNS_ABOVE } {
        linearize_by_columns(sys, q, qdot, t, a0)
    } else {
        linearize_whole(sys, q, qdot, t, a0)
    };
    let finite = |a: &SMatrix<f64, N, N>| a.iter().all(|x| x.is_finite());
    if finite(&lin.m) && finite(&lin.c) && finite(&lin.k) {
        Ok(lin)
    } else {
        Err(DynamicsError::NonFinite {
            t,
            q: q.to_vec(),
            qdot: qdot.to_vec(),
            message: "the second or third derivatives of L (or the Jacobians of the forces) are \
                      not finite here, so the linearization does not exist. Check that L is smooth at \
                      this state (no sqrt or abs at zero, no division by zero), or linearize about a \
                      nearby state."
                .into(),
        })
    }
}

/// [`linearize_along`] from one evaluation of L in a [`LinJet`] (whole Hessians).
#[inline(never)]
fn linearize_whole<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
    a0: &[f64; N],
) -> Linearization<N>
where
    L: Lagrangian<N> + ?Sized,
{
    let (qj, vj, tj) = LinJet::seed(q, qdot, t, qdot, a0, 1.0);
    let l = sys.lagrangian(&qj, &vj, tj);
    let (h, dh) = (l.base(), l.along());
    let (hqq, hqv, hvv) = (h.hess_qq(), h.hess_qqdot(), h.hess_qdotqdot());
    let (dhqv, dhvv) = (dh.hess_qqdot(), dh.hess_qdotqdot());
    let applied = applied_jacobian(sys, q, qdot, t);
    let m = SMatrix::from_fn(|i, j| hvv[i][j]);
    // H_q̇ᵢqⱼ is hqv[j][i] (rows of hqv are q, columns q̇).
    let c = SMatrix::from_fn(|i, j| dhvv[i][j] + hqv[j][i] - hqv[i][j] - applied.d_qdot[i][j]);
    let k = SMatrix::from_fn(|i, j| dhqv[j][i] - hqq[i][j] - applied.d_q[i][j]);
    Linearization { m, c, k }
}

/// [`linearize_along`] for large systems: column j of M, C and K from two evaluations of L in
/// [`LinColumnJet`](crate::jet::LinColumnJet)s, seeded with the columns of q_j and q̇_j (O(N)
/// numbers each on the stack instead of the [`LinJet`]'s O(N²)).
#[inline(never)]
fn linearize_by_columns<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
    a0: &[f64; N],
) -> Linearization<N>
where
    L: Lagrangian<N> + ?Sized,
{
    use crate::jet::LinColumnJet;
    let applied = applied_jacobian(sys, q, qdot, t);
    let mut lin = Linearization {
        m: SMatrix::zeros(),
        c: SMatrix::zeros(),
        k: SMatrix::zeros(),
    };
    // The seeds on the heap, evaluated where the stack has room for the body's own copies.
    let column = |j: usize| {
        crate::jet::with_jet_stack(N, core::mem::size_of::<LinColumnJet<N>>(), || {
            let (qj, vj, tj) = LinColumnJet::seed_boxed(q, qdot, t, qdot, a0, 1.0, j);
            sys.lagrangian(&qj, &vj, tj)
        })
    };
    for j in 0..N {
        // The column of q_j: ∂²L/∂x∂q_j and its derivative along the motion.
        let by_q = column(j);
        // The column of q̇_j.
        let by_v = column(N + j);
        let (bq, dq) = (by_q.base(), by_q.along());
        let (bv, dv) = (by_v.base(), by_v.along());
        let (hq_q, hq_v, dhq_v) = (bq.column_q(), bq.column_qdot(), dq.column_qdot());
        let (hv_q, hv_v, dhv_v) = (bv.column_q(), bv.column_qdot(), dv.column_qdot());
        for i in 0..N {
            lin.m[(i, j)] = hv_v[i];
            // C_ij = D_z H_q̇ᵢq̇ⱼ + H_q̇ᵢqⱼ − H_qᵢq̇ⱼ; K_ij = D_z H_q̇ᵢqⱼ − H_qᵢqⱼ.
            lin.c[(i, j)] = dhv_v[i] + hq_v[i] - hv_q[i] - applied.d_qdot[i][j];
            lin.k[(i, j)] = dhq_v[i] - hq_q[i] - applied.d_q[i][j];
        }
    }
    lin
}

impl<const N: usize> Linearization<N> {
    /// A linearization from its three matrices.
    ///
    /// ```
    /// use lagrange_runtime::{linearize::Linearization, SMatrix};
    /// let lin = Linearization::new(SMatrix::<f64, 1, 1>::identity(), SMatrix::zeros(), SMatrix::from([[4.0]]));
    /// assert_eq!(lin.modes().unwrap()[0].omega(), Some(2.0));
    /// ```
    pub fn new(m: SMatrix<f64, N, N>, c: SMatrix<f64, N, N>, k: SMatrix<f64, N, N>) -> Self {
        Linearization { m, c, k }
    }

    /// The 2N×2N matrix A of the first-order system d/dt (δq, δq̇) = A (δq, δq̇):
    /// A = [[0, I], [−M⁻¹K, −M⁻¹C]] (the companion form of λ²M + λC + K).
    ///
    /// Fails when M is singular.
    ///
    /// ```
    /// use lagrange_runtime::{linearize::Linearization, SMatrix};
    /// let lin = Linearization::new(SMatrix::<f64, 1, 1>::from([[2.0]]), SMatrix::from([[1.0]]), SMatrix::from([[8.0]]));
    /// let a = lin.state_matrix().unwrap();
    /// assert_eq!((a[(0, 1)], a[(1, 0)], a[(1, 1)]), (1.0, -4.0, -0.5));
    /// ```
    pub fn state_matrix(&self) -> Result<DMatrix<f64>, LinearizationError> {
        let lu = dense(&self.m).lu();
        let (mk, mc) = match (lu.solve(&dense(&self.k)), lu.solve(&dense(&self.c))) {
            (Some(mk), Some(mc)) => (mk, mc),
            _ => {
                return Err(LinearizationError::MassNotPositiveDefinite {
                    message: format!(
                        "M is singular (M = {}), so the first-order system does not exist. A \
                         coordinate without kinetic term, or a singular chart (Euler angles at \
                         sin θ = 0): choose coordinates regular at the reference state.",
                        fmt_matrix(&self.m)
                    ),
                });
            }
        };
        let mut a = DMatrix::zeros(2 * N, 2 * N);
        for i in 0..N {
            a[(i, N + i)] = 1.0;
            for j in 0..N {
                a[(N + i, j)] = -mk[(i, j)];
                a[(N + i, N + j)] = -mc[(i, j)];
            }
        }
        if a.iter().all(|x: &f64| x.is_finite()) {
            Ok(a)
        } else {
            Err(LinearizationError::MassNotPositiveDefinite {
                message: "M⁻¹K or M⁻¹C is not finite: M is numerically singular. Choose \
                          coordinates regular at the reference state."
                    .into(),
            })
        }
    }

    /// The frequency scale s = max(max |λ|, ‖M⁻¹C‖, √‖M⁻¹K‖) that [`STABILITY_TOL`] is relative to.
    fn scale(a: &DMatrix<f64>, eig: &[Complex<f64>]) -> f64 {
        let n = a.nrows() / 2;
        let (mut kk, mut cc) = (0.0_f64, 0.0_f64);
        for i in 0..n {
            for j in 0..n {
                kk += a[(n + i, j)].powi(2);
                cc += a[(n + i, n + j)].powi(2);
            }
        }
        eig.iter()
            .map(|l| l.norm())
            .fold(cc.sqrt().max(kk.sqrt().sqrt()), f64::max)
    }

    /// The 2N eigenvalues λ of the first-order system (the roots of det(λ²M + λC + K) = 0),
    /// sorted by decreasing real part, then by imaginary part.
    ///
    /// Computed from the companion matrix [`state_matrix`](Self::state_matrix) by the real
    /// Schur decomposition; never from M⁻¹K alone, which would drop the gyroscopic terms.
    ///
    /// ```
    /// use lagrange_runtime::{linearize::Linearization, SMatrix};
    /// // ẍ + 2ẋ + 5x = 0: λ = −1 ± 2i
    /// let lin = Linearization::new(SMatrix::<f64, 1, 1>::identity(), SMatrix::from([[2.0]]), SMatrix::from([[5.0]]));
    /// let l = lin.eigenvalues().unwrap();
    /// assert!((l[0].re + 1.0).abs() < 1e-14 && (l[0].im.abs() - 2.0).abs() < 1e-14);
    /// ```
    pub fn eigenvalues(&self) -> Result<Vec<Complex<f64>>, LinearizationError> {
        let a = self.state_matrix()?;
        eigenvalues_of(a)
    }

    /// The stability of the reference motion from the eigenvalues (see [`Stability`] and
    /// [`STABILITY_TOL`]).
    ///
    /// ```
    /// use lagrange_runtime::{linearize::{Linearization, Stability}, SMatrix};
    /// let m = SMatrix::<f64, 1, 1>::identity();
    /// let top = Linearization::new(m, SMatrix::zeros(), SMatrix::from([[-4.0]])); // ẍ = 4x
    /// match top.stability().unwrap() {
    ///     Stability::Unstable { growth_rate } => assert!((growth_rate - 2.0).abs() < 1e-14),
    ///     other => panic!("{other:?}"),
    /// }
    /// ```
    pub fn stability(&self) -> Result<Stability, LinearizationError> {
        let a = self.state_matrix()?;
        let eig = eigenvalues_of(a.clone())?;
        let tol = STABILITY_TOL * Self::scale(&a, &eig);
        let growth = eig.iter().map(|l| l.re).fold(f64::NEG_INFINITY, f64::max);
        Ok(if growth > tol {
            Stability::Unstable {
                growth_rate: growth,
            }
        } else if growth < -tol {
            Stability::AsymptoticallyStable
        } else {
            Stability::MarginallyStable
        })
    }

    /// `true` when [`stability`](Self::stability) is stable or marginally stable; `false` when
    /// unstable or when the stability cannot be computed (M singular).
    ///
    /// ```
    /// use lagrange_runtime::{linearize::Linearization, SMatrix};
    /// let m = SMatrix::<f64, 1, 1>::identity();
    /// assert!(Linearization::new(m, SMatrix::zeros(), SMatrix::from([[4.0]])).is_stable());
    /// ```
    pub fn is_stable(&self) -> bool {
        self.stability().is_ok_and(|s| s.is_stable())
    }

    /// The normal modes of an undamped, non-gyroscopic linearization: the N solutions of the
    /// generalized symmetric eigenproblem K v = ω² M v, by increasing ω², shapes M-normalized
    /// (vᵀMv = 1, so VᵀMV = I and VᵀKV = diag ω²) with their largest component positive.
    ///
    /// Fails with [`LinearizationError::NotUndamped`] when C ≠ 0 or K is not symmetric (within
    /// [`SYMMETRY_TOL`]): damped and gyroscopic systems have complex modes; use
    /// [`eigenvalues`](Self::eigenvalues). Fails when M is not positive definite.
    ///
    /// ```
    /// use lagrange_runtime::{linearize::Linearization, SMatrix};
    /// let lin = Linearization::new(SMatrix::<f64, 2, 2>::identity(), SMatrix::zeros(), SMatrix::from([[2.0, -1.0], [-1.0, 2.0]]));
    /// let modes = lin.modes().unwrap();
    /// assert!((modes[0].omega_squared - 1.0).abs() < 1e-14 && (modes[1].omega_squared - 3.0).abs() < 1e-14);
    /// ```
    pub fn modes(&self) -> Result<Vec<Mode<N>>, LinearizationError> {
        let a = self.state_matrix()?;
        let s = Self::scale(&a, &[]);
        if self.c.norm() > SYMMETRY_TOL * s * self.m.norm()
            || (self.k - self.k.transpose()).norm() > SYMMETRY_TOL * self.k.norm()
        {
            return Err(LinearizationError::NotUndamped {
                message: format!(
                    "C = {} is not zero or K = {} is not symmetric: this linearization has \
                     damping, gyroscopic or circulatory terms and no real normal modes. Use \
                     `eigenvalues()` (the quadratic eigenvalue problem λ²M + λC + K = 0).",
                    fmt_matrix(&self.c),
                    fmt_matrix(&self.k)
                ),
            });
        }
        let m = dense(&((self.m + self.m.transpose()) * 0.5));
        let k = dense(&((self.k + self.k.transpose()) * 0.5));
        let chol = m
            .cholesky()
            .ok_or_else(|| LinearizationError::MassNotPositiveDefinite {
                message: format!(
                    "M = {} has no Cholesky factor: the kinetic energy is not positive definite \
                     at this state. Choose coordinates regular there.",
                    fmt_matrix(&self.m)
                ),
            })?;
        // K v = ω² M v with M = LLᵀ: (L⁻¹ K L⁻ᵀ) y = ω² y, v = L⁻ᵀ y.
        let linv =
            chol.l()
                .try_inverse()
                .ok_or_else(|| LinearizationError::MassNotPositiveDefinite {
                    message: "the Cholesky factor of M is singular".into(),
                })?;
        let sym = &linv * k * linv.transpose();
        let sym = (&sym + sym.transpose()) * 0.5;
        let eig =
            nalgebra::SymmetricEigen::try_new(sym, f64::EPSILON, 10_000).ok_or_else(|| {
                LinearizationError::Eigen {
                    message: "the symmetric eigenvalue iteration of L⁻¹KL⁻ᵀ did not converge"
                        .into(),
                }
            })?;
        let back = linv.transpose();
        let mut modes: Vec<Mode<N>> = (0..N)
            .map(|i| {
                let v = &back * eig.eigenvectors.column(i);
                let big = v
                    .iter()
                    .fold(0.0_f64, |b, x| if x.abs() > b.abs() { *x } else { b });
                let sign = if big < 0.0 { -1.0 } else { 1.0 };
                Mode {
                    omega_squared: eig.eigenvalues[i],
                    shape: SVector::from_fn(|j, _| sign * v[j]),
                }
            })
            .collect();
        modes.sort_by(|a, b| a.omega_squared.total_cmp(&b.omega_squared));
        Ok(modes)
    }
}

/// The eigenvalues of a real square matrix by the real Schur decomposition, sorted by
/// decreasing real part, then imaginary part.
///
/// Exact zero columns and rows are deflated first: each is an exact eigenvalue 0 (a cyclic
/// coordinate, whose δq column of the companion matrix is zero, and whose δq̇ row is zero when
/// nothing acts on it), and the defective λ = 0 pairs they form otherwise stall the QR
/// iteration's relative convergence test. The double-shift QR iteration (it has no exceptional
/// shifts) can also cycle on the structured spectra of mechanics (±a ± ib, as below a
/// gyroscopic threshold): then it is retried on orthogonally similar matrices.
fn eigenvalues_of(a: DMatrix<f64>) -> Result<Vec<Complex<f64>>, LinearizationError> {
    let mut a = a;
    let mut eig: Vec<Complex<f64>> = Vec::new();
    // deflate exact zero columns and rows: the remaining block has the other eigenvalues
    while let Some(j) = (0..a.nrows())
        .find(|&j| a.column(j).iter().all(|x| *x == 0.0) || a.row(j).iter().all(|x| *x == 0.0))
    {
        eig.push(Complex::new(0.0, 0.0));
        a = a.remove_row(j).remove_column(j);
    }
    let n = a.nrows();
    if n > 0 {
        eig.extend(schur_eigenvalues(&a, n)?);
    }
    eig.sort_by(|a, b| b.re.total_cmp(&a.re).then(a.im.total_cmp(&b.im)));
    Ok(eig)
}

fn schur_eigenvalues(a: &DMatrix<f64>, n: usize) -> Result<Vec<Complex<f64>>, LinearizationError> {
    // The plain matrix first, then up to four fixed orthogonal similarities QᵀAQ (Q from the QR
    // factorization of a deterministic pseudo-random matrix): the eigenvalues are the same, up to
    // rounding ε‖A‖, while the Hessenberg form and so the QR iteration's path are not.
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    for attempt in 0..5 {
        let m = if attempt == 0 {
            a.clone()
        } else {
            let r = DMatrix::from_fn(n, n, |_, _| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            });
            let q = r.qr().q();
            q.transpose() * a * q
        };
        if let Some(schur) = nalgebra::Schur::try_new(m, f64::EPSILON, 1000 * n) {
            return Ok(schur.complex_eigenvalues().iter().copied().collect());
        }
    }
    Err(LinearizationError::Eigen {
        message: "the Schur iteration of the companion matrix did not converge, even after \
                  orthogonal similarity transforms. Check that M, C and K are finite and of \
                  reasonable scale."
            .into(),
    })
}

/// The same matrix with dynamic dimensions (nalgebra's decompositions need a concrete size or
/// `Dyn`, not a generic `Const<N>`).
fn dense<const N: usize>(m: &SMatrix<f64, N, N>) -> DMatrix<f64> {
    DMatrix::from_fn(N, N, |i, j| m[(i, j)])
}

fn fmt_matrix<const N: usize>(m: &SMatrix<f64, N, N>) -> String {
    let rows: Vec<String> = (0..N)
        .map(|i| {
            let r: Vec<String> = (0..N).map(|j| format!("{:.3e}", m[(i, j)])).collect();
            format!("[{}]", r.join(", "))
        })
        .collect();
    format!("[{}]", rows.join(", "))
}

/// Newton's iterations of [`equilibrium`] before it gives up.
///
/// ```
/// assert_eq!(lagrange_runtime::linearize::EQUILIBRIUM_MAX_ITERATIONS, 50);
/// ```
pub const EQUILIBRIUM_MAX_ITERATIONS: usize = 50;

/// The coordinates along which K is singular, by name: the components of the null direction
/// (the right singular vector of the smallest singular value) above a tenth of its largest, e.g.
/// `x`, or `the combination of x and theta`.
fn neutral_coordinates<const N: usize>(k: &SMatrix<f64, N, N>, names: [&'static str; N]) -> String {
    let svd = dense(k).svd(false, true);
    let Some(v_t) = svd.v_t.as_ref() else {
        return "some coordinate".to_string();
    };
    let i = svd.singular_values.iamin();
    let row: Vec<f64> = (0..N).map(|j| v_t[(i, j)]).collect();
    let max = row.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let named: Vec<&str> = (0..N)
        .filter(|&j| max > 0.0 && row[j].abs() > 0.1 * max)
        .map(|j| names[j])
        .collect();
    match named.as_slice() {
        [] => "some coordinate".to_string(),
        [one] => format!("`{one}`"),
        many => format!(
            "the combination of {}",
            many.iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(" and ")
        ),
    }
}

/// An equilibrium q* (q̈(q*, 0, t) = 0) near `q_guess`, by Newton's method at time t.
///
/// Each step solves K δq = M q̈ with M and K from [`Linearize::linearize`] at (q, 0, t): the
/// Jacobian of q ↦ q̈(q, 0, t) is exactly −M⁻¹K there (K includes the (∂M/∂q)·q̈ term away from an
/// equilibrium). The step is halved (up to 30 times) until max|M q̈| decreases. Converged when a
/// full step is below 1e-13 (1 + max|q|) or q̈ = 0 exactly; at most
/// [`EQUILIBRIUM_MAX_ITERATIONS`] steps.
///
/// Fails, never panics, with [`LinearizationError::NoEquilibrium`] (the last iterate, its q̈, what
/// happened, what to try) when K is singular (a neutral direction: a cyclic coordinate or a
/// continuum of equilibria), when no step decreases the residual, or after the last iteration;
/// and with [`LinearizationError::Dynamics`] when the equations cannot be evaluated.
///
/// ```
/// use lagrange_runtime::{linearize::equilibrium, Lagrangian, Scalar};
/// /// A pendulum with a constant torque τ = 4.5: equilibrium at sin θ = τ/(m g l) = 1/2.
/// struct Pushed;
/// impl Lagrangian<1> for Pushed {
///     const COORDINATES: [&'static str; 1] = ["theta"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 + q[0].cos() * 9.0 }
///     fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], _t: S) -> [S; 1] { [S::constant(4.5)] }
/// }
/// let q = equilibrium(&Pushed, &[0.2], 0.0).unwrap();
/// assert!((q[0] - std::f64::consts::FRAC_PI_6).abs() < 1e-14);
/// ```
pub fn equilibrium<L, const N: usize>(
    sys: &L,
    q_guess: &[f64; N],
    t: f64,
) -> Result<[f64; N], LinearizationError>
where
    L: Lagrangian<N> + ?Sized,
{
    let zero = [0.0; N];
    let mut q = *q_guess;
    let fail = |q: &[f64; N], a: &[f64; N], iterations: usize, message: String| {
        LinearizationError::NoEquilibrium {
            t,
            q: q.to_vec(),
            residual: a.to_vec(),
            iterations,
            message,
        }
    };
    let residual = |lin: &Linearization<N>, a: &[f64; N]| (lin.m * SVector::from(*a)).amax();
    for it in 0..EQUILIBRIUM_MAX_ITERATIONS {
        let a = sys.accelerations(&q, &zero, t)?;
        if a.iter().all(|x| *x == 0.0) {
            return Ok(q);
        }
        let lin = sys.linearize(&q, &zero, t)?;
        let r0 = residual(&lin, &a);
        let rhs = lin.m * SVector::from(a);
        let step = dense(&lin.k)
            .lu()
            .solve(&DMatrix::from_fn(N, 1, |i, _| rhs[i]))
            .filter(|s| s.iter().all(|x: &f64| x.is_finite()));
        let Some(step) = step else {
            let neutral = neutral_coordinates(&lin.k, L::COORDINATES);
            return Err(fail(
                &q,
                &a,
                it,
                format!(
                    "the stiffness K is singular here, so Newton has no direction: along {neutral} \
                     the forces do not change (a cyclic coordinate, a uniform force, or a \
                     continuum of equilibria). Fix the neutral coordinates (remove them from the \
                     system, or hold them with a constraint), or start from another guess."
                ),
            ));
        };
        let qmax = q.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if step.amax() <= 1e-13 * (1.0 + qmax) {
            return Ok(q);
        }
        let mut lambda = 1.0;
        let mut accepted = None;
        for _ in 0..30 {
            let mut trial = q;
            for i in 0..N {
                trial[i] += lambda * step[i];
            }
            if let Ok(at) = sys.accelerations(&trial, &zero, t) {
                let m = sys.mass_matrix(&trial, &zero, t);
                let r = (m * SVector::from(at)).amax();
                if r < r0 {
                    accepted = Some(trial);
                    break;
                }
            }
            lambda *= 0.5;
        }
        match accepted {
            Some(next) => q = next,
            None => {
                return Err(fail(
                    &q,
                    &a,
                    it,
                    "no step along the Newton direction decreases the generalized force M q̈: the \
                     iteration is stuck at a minimum of |M q̈| that is not zero, so there is likely \
                     no equilibrium nearby (the applied forces exceed what the potential can \
                     balance). Check the parameters, or try another guess."
                        .into(),
                ));
            }
        }
    }
    let a = sys.accelerations(&q, &zero, t)?;
    Err(fail(
        &q,
        &a,
        EQUILIBRIUM_MAX_ITERATIONS,
        format!(
            "Newton did not converge in {EQUILIBRIUM_MAX_ITERATIONS} iterations (the residual \
             kept decreasing too slowly: a degenerate equilibrium, where K is nearly singular, or \
             none at all). Try a guess closer to the equilibrium."
        ),
    ))
}

impl core::fmt::Debug for LinearizationError {
    /// The sentence of `Display` (what happened, where, what to try), without the escapes a
    /// derived `Debug` puts on every combining dot of q̇: what `fn main() -> Result<..>` prints.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(self, f)
    }
}

#[cfg(test)]
mod column_tests {
    use super::{linearize_by_columns, linearize_whole};
    use crate::{Lagrangian, Scalar};

    /// A rheonomic, velocity-coupled L of three coordinates with every elementary function the
    /// chain rule sees (sin, cos, exp, sqrt, division), and a time dependence.
    struct Mixed;
    impl Lagrangian<3> for Mixed {
        const COORDINATES: [&'static str; 3] = ["a", "b", "c"];
        const CYCLIC: [bool; 3] = [false; 3];
        const AUTONOMOUS: bool = false;
        fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], t: S) -> S {
            let (s, c) = q[0].sin_cos();
            let m = (q[1] * 0.3).exp() + 2.0;
            (v[0] * v[0] * m + v[1] * v[1] * (q[2] * q[2] + 1.0).sqrt() + v[2] * v[2]) * 0.5
                + v[0] * v[2] * c * 0.2
                + v[1] * s * t
                - q[0] * q[1] / (q[2] + 3.0)
                - (q[2] * t).cos()
        }
    }

    /// The linearization assembled column by column (the path of systems above 16
    /// coordinates) equals the one from whole Hessians, entry by entry, to round-off.
    #[test]
    fn columns_equal_the_whole_linearization() {
        let (q, v, t, a0) = ([0.4, -0.7, 0.9], [1.3, 0.2, -0.8], 0.6, [0.5, -1.1, 0.25]);
        let whole = linearize_whole(&Mixed, &q, &v, t, &a0);
        let cols = linearize_by_columns(&Mixed, &q, &v, t, &a0);
        for (name, a, b) in [
            ("M", whole.m, cols.m),
            ("C", whole.c, cols.c),
            ("K", whole.k, cols.k),
        ] {
            for (x, y) in a.iter().zip(b.iter()) {
                assert!(
                    (x - y).abs() <= 1e-14 * x.abs().max(1.0),
                    "{name}: {a} against {b}"
                );
            }
            assert!(a.iter().any(|x| *x != 0.0), "{name} is not all zero");
        }
    }
}
