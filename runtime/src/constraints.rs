//! Holonomic constraints g(q, t) = 0 with Lagrange multipliers: the [`Holonomic`] trait, the
//! constraint rows from the jets, and [`Constrained`], the view of a constrained system that the
//! integrators step.
//!
//! With constraints the equations of motion are
//!
//! ```text
//! M q̈ = f_L + Q − ∂D/∂q̇ + Gᵀ λ,    g(q, t) = 0,    G = ∂g/∂q,
//! ```
//!
//! so λ are the constraint forces in generalized coordinates (for a pendulum written in x, y,
//! Gᵀλ is the rod's force on the bob). The integrators solve the index-1 form
//! G q̈ = −(q̇ᵀ∂²g/∂q² q̇ + 2∂²g/∂q∂t q̇ + ∂²g/∂t²) together with M q̈ = f + Gᵀλ
//! ([`eom::solve_constrained`]) and keep the state on the constraints (see
//! [`Simulation::constrained`](crate::Simulation::constrained)).
//!
//! ```
//! use lagrange_runtime::{Holonomic, Lagrangian, Scalar};
//! /// A plane pendulum written in x, y with the rod as a constraint x² + y² = l².
//! struct Pendulum { m: f64, g: f64, l: f64 }
//! impl Lagrangian<2> for Pendulum {
//!     const COORDINATES: [&'static str; 2] = ["x", "y"];
//!     const CYCLIC: [bool; 2] = [true, false];
//!     const AUTONOMOUS: bool = true;
//!     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
//!         (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m) - q[1] * (self.m * self.g)
//!     }
//! }
//! impl Holonomic<2, 1> for Pendulum {
//!     const SCLERONOMIC: bool = true;
//!     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
//!         [q[0] * q[0] + q[1] * q[1] - self.l * self.l]
//!     }
//! }
//! let p = Pendulum { m: 2.0, g: 9.81, l: 1.5 };
//! // Hanging straight down, moving at 3 m/s: the tension is m g + m v²/l along +y.
//! let (a, lambda) = p.constrained_accelerations(&[0.0, -1.5], &[3.0, 0.0], 0.0).unwrap();
//! let tension = 2.0 * 9.81 + 2.0 * 9.0 / 1.5;
//! // Gᵀλ = (2x, 2y) λ is the rod's force: (0, −3λ) = (0, tension).
//! assert!((-3.0 * lambda[0] - tension).abs() < 1e-12);
//! assert!(a[0].abs() < 1e-12 && (a[1] - 9.0 / 1.5).abs() < 1e-12); // centripetal
//! ```

use nalgebra::SMatrix;

use crate::eom::{self, ConstraintRows, Pieces};
use crate::error::{DynamicsError, DynamicsResult};
use crate::jet::ConstraintJet;
use crate::lagrangian::Lagrangian;
use crate::scalar::Scalar;

/// A [`Lagrangian`] system with `K` holonomic constraints g(q, t) = 0 on its `N` coordinates.
///
/// Implement [`constraints`](Holonomic::constraints) generically over [`Scalar`] (or write
/// `fn constraints` in a `#[lagrangian]` impl); G = ∂g/∂q and the second derivatives along the
/// motion come from the jets. The convention is M q̈ = f + Gᵀλ: λ is the constraint force in
/// generalized coordinates. The mass matrix may be singular on its own as long as the
/// constrained system [M Gᵀ; G 0] is not.
///
/// See the [module documentation](crate::constraints) for an example.
pub trait Holonomic<const N: usize, const K: usize>: Lagrangian<N> {
    /// `true` for a coordinate the constraints depend on. The default, all of them, is always
    /// correct; a precise declaration lets a cyclic coordinate that no constraint touches keep
    /// its conserved momentum (`#[lagrangian]` works it out).
    const CONSTRAINED_COORDINATES: [bool; N] = [true; N];
    /// `true` when the constraints do not depend on time (then, with a conserved energy of L,
    /// the constrained motion conserves it too). The default, `false`, is always correct.
    const SCLERONOMIC: bool = false;
    /// How many of the K rows, the last ones, are velocity constraints A(q, t) q̇ + b(q, t) = 0
    /// ([`Nonholonomic`]) rather than g(q, t) = 0: their rows come from
    /// [`constraint_rows`](Holonomic::constraint_rows) (`value` 0, `jacobian` A, `rate` the
    /// residual A q̇ + b, `curvature` its rate at q̈ = 0), and a run projects positions onto the
    /// holonomic rows only. `#[lagrangian]` sets it for `fn velocity_constraints`; 0 by default.
    const VELOCITY_ROWS: usize = 0;

    /// g(q, t), one entry per constraint: zero on the constraints.
    fn constraints<S: Scalar>(&self, q: &[S; N], t: S) -> [S; K];

    /// Every constraint as a function of the state: g(q, t) for the holonomic rows, then
    /// c(q, q̇, t) for the last [`VELOCITY_ROWS`](Holonomic::VELOCITY_ROWS) (what the
    /// linearization on the constraint manifold differentiates). The default, for holonomic
    /// constraints only, is [`constraints`](Holonomic::constraints).
    ///
    /// ```
    /// use lagrange_runtime::{Holonomic, Lagrangian, Scalar};
    /// struct Ring;
    /// impl Lagrangian<2> for Ring {
    ///     const COORDINATES: [&'static str; 2] = ["x", "y"];
    ///     const CYCLIC: [bool; 2] = [true, true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 }
    /// }
    /// impl Holonomic<2, 1> for Ring {
    ///     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
    /// }
    /// assert_eq!(Ring.constraint_values(&[2.0, 0.0], &[5.0, 5.0], 0.0), [3.0]);
    /// ```
    #[inline]
    fn constraint_values<S: Scalar>(&self, q: &[S; N], qdot: &[S; N], t: S) -> [S; K] {
        let _ = qdot;
        self.constraints(q, t)
    }

    /// The constraint rows at (q, q̇, t): g, G = ∂g/∂q, ġ and g̈ at q̈ = 0, from one evaluation
    /// of [`constraints`](Holonomic::constraints) per constraint in the [`ConstraintJet`].
    ///
    /// ```
    /// use lagrange_runtime::{Holonomic, Lagrangian, Scalar};
    /// /// A bead on the moving line x = t (one coordinate, one rheonomic constraint).
    /// struct Bead;
    /// impl Lagrangian<1> for Bead {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// }
    /// impl Holonomic<1, 1> for Bead {
    ///     fn constraints<S: Scalar>(&self, q: &[S; 1], t: S) -> [S; 1] { [q[0] - t * t] }
    /// }
    /// let rows = Bead.constraint_rows(&[1.0], &[2.0], 1.0);
    /// assert_eq!((rows.value, rows.jacobian, rows.rate, rows.curvature), ([0.0], [[1.0]], [0.0], [-2.0]));
    /// ```
    #[inline]
    fn constraint_rows(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> ConstraintRows<N, K> {
        jet_constraint_rows(self, q, qdot, t)
    }

    /// The accelerations q̈ and the multipliers λ of M q̈ = f + Gᵀλ, G q̈ = −g̈|_{q̈=0}: the
    /// [`pieces`](Lagrangian::pieces) and the [`constraint_rows`](Holonomic::constraint_rows)
    /// solved by [`eom::solve_constrained`].
    ///
    /// Fails with [`DynamicsError::DependentConstraints`] where the constraints are dependent,
    /// [`DynamicsError::SingularMassMatrix`] where the constrained system is singular, and
    /// [`DynamicsError::NonFinite`].
    ///
    /// ```
    /// use lagrange_runtime::{Holonomic, Lagrangian, Scalar};
    /// /// Two unit masses on a line joined by a rigid rod of length 1, the first pulled by a spring.
    /// struct Dumbbell;
    /// impl Lagrangian<2> for Dumbbell {
    ///     const COORDINATES: [&'static str; 2] = ["x1", "x2"];
    ///     const CYCLIC: [bool; 2] = [false, true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
    ///         (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[0] * q[0] * 0.5
    ///     }
    /// }
    /// impl Holonomic<2, 1> for Dumbbell {
    ///     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[1] - q[0] - 1.0] }
    /// }
    /// let (a, lambda) = Dumbbell.constrained_accelerations(&[1.0, 2.0], &[0.0, 0.0], 0.0).unwrap();
    /// assert!((a[0] + 0.5).abs() < 1e-15 && (a[1] + 0.5).abs() < 1e-15); // 2 m ẍ = −k x
    /// assert!((lambda[0] + 0.5).abs() < 1e-15); // the rod pulls the second mass back
    /// ```
    #[inline]
    fn constrained_accelerations(
        &self,
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Result<([f64; N], [f64; K]), DynamicsError> {
        eom::solve_constrained(
            &self.pieces(q, qdot, t),
            &self.constraint_rows(q, qdot, t),
            Self::COORDINATES,
            q,
            qdot,
            t,
        )
    }
}

/// The constraint rows from the jets: g evaluated once in the [`ConstraintJet`] seeded at
/// (q, q̇, t). The default of [`Holonomic::constraint_rows`].
///
/// ```
/// use lagrange_runtime::{constraints::jet_constraint_rows, Holonomic, Lagrangian, Scalar};
/// struct Ring;
/// impl Lagrangian<2> for Ring {
///     const COORDINATES: [&'static str; 2] = ["x", "y"];
///     const CYCLIC: [bool; 2] = [true, true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 }
/// }
/// impl Holonomic<2, 1> for Ring {
///     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
/// }
/// let rows = jet_constraint_rows(&Ring, &[1.0, 0.0], &[0.0, 2.0], 0.0);
/// assert_eq!((rows.jacobian, rows.curvature), ([[2.0, 0.0]], [8.0])); // g̈ = 2|v|²
/// ```
#[inline]
pub fn jet_constraint_rows<H, const N: usize, const K: usize>(
    sys: &H,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> ConstraintRows<N, K>
where
    H: Holonomic<N, K> + ?Sized,
{
    let (qj, tj) = ConstraintJet::seed(q, qdot, t);
    let g = sys.constraints(&qj, tj);
    ConstraintRows {
        value: core::array::from_fn(|j| g[j].value()),
        jacobian: core::array::from_fn(|j| g[j].grad_q()),
        rate: core::array::from_fn(|j| g[j].rate()),
        curvature: core::array::from_fn(|j| g[j].curvature()),
    }
}

/// A [`Lagrangian`] system with `K` velocity (nonholonomic) constraints
/// c(q, q̇, t) = A(q, t) q̇ + b(q, t) = 0: rolling without slipping, knife edges.
///
/// With them the equations of motion are those of Lagrange–d'Alembert, M q̈ = f + Aᵀλ with
/// A q̈ = −ċ|_{q̈=0}: λ are the constraint forces in generalized coordinates, as for holonomic
/// constraints. `#[lagrangian]` implements it from `fn velocity_constraints` and folds its rows
/// into the system's [`Holonomic`] impl (after the holonomic ones, [`Holonomic::VELOCITY_ROWS`]
/// of them), so [`Simulation::constrained`](crate::Simulation::constrained) runs both.
///
/// ```
/// use lagrange_runtime::{constraints::Nonholonomic, Lagrangian, Scalar};
/// /// A knife edge in the plane: (x, y, heading φ), sliding only along its heading.
/// struct Skate;
/// impl Lagrangian<3> for Skate {
///     const COORDINATES: [&'static str; 3] = ["x", "y", "phi"];
///     const CYCLIC: [bool; 3] = [true, true, true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 3], v: &[S; 3], _t: S) -> S {
///         (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * 0.5
///     }
/// }
/// impl Nonholonomic<3, 1> for Skate {
///     fn velocity_constraints<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> [S; 1] {
///         [v[1] * q[2].cos() - v[0] * q[2].sin()]
///     }
/// }
/// // Heading along x, moving along x and turning: A = (0, 1, 0), ċ = −ẋ φ̇.
/// let rows = Skate.velocity_constraint_rows(&[0.0, 0.0, 0.0], &[2.0, 0.0, 0.5], 0.0);
/// assert_eq!((rows.jacobian, rows.rate, rows.curvature), ([[0.0, 1.0, 0.0]], [0.0], [-1.0]));
/// ```
pub trait Nonholonomic<const N: usize, const K: usize>: Lagrangian<N> {
    /// c(q, q̇, t), one entry per constraint, affine in q̇: zero on the constrained motion.
    fn velocity_constraints<S: Scalar>(&self, q: &[S; N], qdot: &[S; N], t: S) -> [S; K];

    /// The rows at (q, q̇, t): `value` 0 (no position part), `jacobian` A = ∂c/∂q̇, `rate` the
    /// residual c, `curvature` ċ at q̈ = 0 (so the acceleration-level constraint is
    /// A q̈ = −`curvature`), from one evaluation of
    /// [`velocity_constraints`](Nonholonomic::velocity_constraints) in the [`ConstraintJet`]
    /// seeded with the gradient on q̇ and the direction (q̇, 0, 1) on (q, q̇, t).
    fn velocity_constraint_rows(
        &self,
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> ConstraintRows<N, K> {
        let (vj, tj) = ConstraintJet::seed(qdot, &[0.0; N], t);
        // q moves along q̇ and carries no gradient: position jets with the velocity as rate.
        let qj: [ConstraintJet<N>; N] =
            core::array::from_fn(|i| ConstraintJet::moving(q[i], qdot[i]));
        let c = self.velocity_constraints(&qj, &vj, tj);
        ConstraintRows {
            value: [0.0; K],
            jacobian: core::array::from_fn(|j| c[j].grad_q()),
            rate: core::array::from_fn(|j| c[j].value()),
            curvature: core::array::from_fn(|j| c[j].rate()),
        }
    }
}

/// Writes the rows of `K - KV` holonomic constraints and `KV` velocity constraints into one set
/// of rows, the velocity ones last: what `#[lagrangian]`'s `constraint_rows` returns for a
/// system with `fn velocity_constraints`.
///
/// ```
/// use lagrange_runtime::constraints::splice_velocity_rows;
/// use lagrange_runtime::eom::ConstraintRows;
/// let mut rows = ConstraintRows { value: [1.0, 0.0], jacobian: [[1.0], [0.0]], rate: [2.0, 0.0], curvature: [3.0, 0.0] };
/// let v = ConstraintRows { value: [0.0], jacobian: [[5.0]], rate: [6.0], curvature: [7.0] };
/// splice_velocity_rows(&mut rows, &v);
/// assert_eq!((rows.jacobian, rows.rate, rows.curvature), ([[1.0], [5.0]], [2.0, 6.0], [3.0, 7.0]));
/// ```
pub fn splice_velocity_rows<const N: usize, const K: usize, const KV: usize>(
    rows: &mut ConstraintRows<N, K>,
    velocity: &ConstraintRows<N, KV>,
) {
    let first = K - KV;
    for j in 0..KV {
        rows.value[first + j] = 0.0;
        rows.jacobian[first + j] = velocity.jacobian[j];
        rows.rate[first + j] = velocity.rate[j];
        rows.curvature[first + j] = velocity.curvature[j];
    }
}

/// `a[i] && !b[i]`, in a const context.
const fn and_not<const N: usize>(a: [bool; N], b: [bool; N]) -> [bool; N] {
    let mut r = [false; N];
    let mut i = 0;
    while i < N {
        r[i] = a[i] && !b[i];
        i += 1;
    }
    r
}

/// A constrained system seen as the [`Lagrangian`] the integrators step: its accelerations are
/// the constrained ones ([`Holonomic::constrained_accelerations`]), everything else (L, the
/// energy, the momenta, the forces) is the system's own. What
/// [`Simulation::constrained`](crate::Simulation::constrained) runs.
///
/// Its flags are those of the constrained motion: a coordinate is cyclic (and its momentum
/// conserved) only if no constraint depends on it, and the energy is conserved only if the
/// constraints do not depend on time.
///
/// ```
/// use lagrange_runtime::{constraints::Constrained, Holonomic, Lagrangian, Scalar};
/// struct Ring;
/// impl Lagrangian<2> for Ring {
///     const COORDINATES: [&'static str; 2] = ["x", "y"];
///     const CYCLIC: [bool; 2] = [true, true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 }
/// }
/// impl Holonomic<2, 1> for Ring {
///     const SCLERONOMIC: bool = true;
///     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
/// }
/// let c = Constrained::new(&Ring);
/// assert_eq!(<Constrained<Ring, 2, 1> as Lagrangian<2>>::CYCLIC, [false, false]);
/// assert!(<Constrained<Ring, 2, 1> as Lagrangian<2>>::ENERGY_CONSERVED);
/// // Uniform circular motion: q̈ = −q |v|².
/// let a = c.accelerations(&[1.0, 0.0], &[0.0, 2.0], 0.0).unwrap();
/// assert!((a[0] + 4.0).abs() < 1e-14 && a[1].abs() < 1e-14);
/// ```
pub struct Constrained<'a, H: ?Sized, const N: usize, const K: usize> {
    sys: &'a H,
}

impl<H: ?Sized, const N: usize, const K: usize> Clone for Constrained<'_, H, N, K> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<H: ?Sized, const N: usize, const K: usize> Copy for Constrained<'_, H, N, K> {}

impl<'a, H: Holonomic<N, K> + ?Sized, const N: usize, const K: usize> Constrained<'a, H, N, K> {
    /// The constrained view of `sys`.
    ///
    /// ```
    /// # use lagrange_runtime::{constraints::Constrained, Holonomic, Lagrangian, Scalar};
    /// # struct Ring;
    /// # impl Lagrangian<2> for Ring {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 }
    /// # }
    /// # impl Holonomic<2, 1> for Ring {
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
    /// # }
    /// let c = Constrained::new(&Ring);
    /// assert_eq!(c.system().constraints(&[1.0, 0.0], 0.0), [0.0]);
    /// ```
    pub fn new(sys: &'a H) -> Self {
        Constrained { sys }
    }

    /// The system itself.
    ///
    /// ```
    /// # use lagrange_runtime::{constraints::Constrained, Holonomic, Lagrangian, Scalar};
    /// # struct Ring;
    /// # impl Lagrangian<2> for Ring {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 }
    /// # }
    /// # impl Holonomic<2, 1> for Ring {
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
    /// # }
    /// assert!(std::ptr::eq(Constrained::new(&Ring).system(), &Ring));
    /// ```
    pub fn system(&self) -> &'a H {
        self.sys
    }
}

/// The [`Lagrangian`] methods a view of a system (a constrained run's, a contact run's) takes
/// from the system unchanged: L, D, Q, the pieces, M, the momenta and the energy. The view
/// writes its flags, its power and its accelerations itself.
macro_rules! forward_to_system {
    () => {
        #[inline(always)]
        fn lagrangian<S: Scalar>(&self, q: &[S; N], qdot: &[S; N], t: S) -> S {
            self.sys.lagrangian(q, qdot, t)
        }
        #[inline(always)]
        fn dissipation<S: Scalar>(&self, q: &[S; N], qdot: &[S; N], t: S) -> S {
            self.sys.dissipation(q, qdot, t)
        }
        #[inline(always)]
        fn generalized_forces<S: Scalar>(&self, q: &[S; N], qdot: &[S; N], t: S) -> [S; N] {
            self.sys.generalized_forces(q, qdot, t)
        }
        #[inline(always)]
        fn pieces(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Pieces<N> {
            self.sys.pieces(q, qdot, t)
        }
        fn mass_matrix(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> SMatrix<f64, N, N> {
            self.sys.mass_matrix(q, qdot, t)
        }
        fn momenta(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> [f64; N] {
            self.sys.momenta(q, qdot, t)
        }
        fn energy_and_momenta(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> (f64, [f64; N]) {
            self.sys.energy_and_momenta(q, qdot, t)
        }
        fn energy(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64 {
            self.sys.energy(q, qdot, t)
        }
    };
}
pub(crate) use forward_to_system;

impl<H: Holonomic<N, K> + ?Sized, const N: usize, const K: usize> Lagrangian<N>
    for Constrained<'_, H, N, K>
{
    forward_to_system!();
    const COORDINATES: [&'static str; N] = H::COORDINATES;
    const CYCLIC: [bool; N] = and_not(H::CYCLIC, H::CONSTRAINED_COORDINATES);
    const AUTONOMOUS: bool = H::AUTONOMOUS;
    const MOMENTUM_CONSERVED: [bool; N] =
        and_not(H::MOMENTUM_CONSERVED, H::CONSTRAINED_COORDINATES);
    const ENERGY_CONSERVED: bool = H::ENERGY_CONSERVED && H::SCLERONOMIC;
    // A system with contacts as well: the run refuses this view, which would drop them.
    const DECLARES_CONTACTS: bool = H::DECLARES_CONTACTS;

    /// The system's power plus that of the constraint forces, λ·(G q̇) (non-zero only for
    /// constraints that move in time); NaN where the constrained accelerations fail.
    fn power(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64 {
        let mut p = self.sys.power(q, qdot, t);
        if !H::SCLERONOMIC {
            let rows = self.sys.constraint_rows(q, qdot, t);
            match eom::solve_constrained(
                &self.sys.pieces(q, qdot, t),
                &rows,
                H::COORDINATES,
                q,
                qdot,
                t,
            ) {
                Ok((_, lambda)) => {
                    for j in 0..K {
                        let gv: f64 = (0..N).map(|i| rows.jacobian[j][i] * qdot[i]).sum();
                        p += lambda[j] * gv;
                    }
                }
                Err(_) => return f64::NAN,
            }
        }
        p
    }
    #[inline(always)]
    fn accelerations(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> DynamicsResult<[f64; N]> {
        self.sys
            .constrained_accelerations(q, qdot, t)
            .map(|(a, _)| a)
    }
    fn first_order_jacobian(
        &self,
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Option<DynamicsResult<nalgebra::DMatrix<f64>>> {
        Some(crate::linearize::constrained_state_jacobian(
            self.sys, q, qdot, t,
        ))
    }
}
