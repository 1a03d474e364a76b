//! The one place where the equations of motion are assembled and solved.
//!
//! Every backend — the straight-line code of the symbolic mode, the run-time jets, a hand-written
//! impl — supplies the same [`Pieces`] at a state (q, q̇, t):
//!
//! - the mass matrix M = ∂²L/∂q̇∂q̇,
//! - the Lagrangian part of the right-hand side, f_L = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t,
//! - the applied forces Q − ∂D/∂q̇ (generalized forces and Rayleigh dissipation; zero for a
//!   conservative system),
//!
//! and [`solve`] turns them into the accelerations of
//!
//! ```text
//! M q̈ = f_L + Q − ∂D/∂q̇
//! ```
//!
//! with the typed [`DynamicsError`]s (singular M, non-finite values) every backend shares.
//! [`Lagrangian::pieces`] is where a system supplies its pieces (the default derives them from
//! L with the jets); [`Lagrangian::accelerations`] is `solve(pieces)` unless a backend has a
//! faster path to the same numbers (the symbolic mode's straight-line elimination, which hands
//! every case it does not handle back to [`solve_mass_matrix`]).
//!
//! A hand-written system can supply its pieces directly:
//!
//! ```
//! use lagrange_runtime::{eom::Pieces, Lagrangian, Scalar};
//! /// A pendulum of length l in gravity g, L = l² θ̇²/2 + g l cos θ, with its pieces by hand.
//! struct Pendulum { g: f64, l: f64 }
//! impl Lagrangian<1> for Pendulum {
//!     const COORDINATES: [&'static str; 1] = ["theta"];
//!     const CYCLIC: [bool; 1] = [false];
//!     const AUTONOMOUS: bool = true;
//!     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
//!         v[0] * v[0] * (self.l * self.l / 2.0) + q[0].cos() * (self.g * self.l)
//!     }
//!     fn pieces(&self, q: &[f64; 1], _v: &[f64; 1], _t: f64) -> Pieces<1> {
//!         Pieces::new([[self.l * self.l]], [-self.g * self.l * q[0].sin()])
//!     }
//! }
//! let p = Pendulum { g: 9.81, l: 2.0 };
//! let a = p.accelerations(&[0.5], &[0.0], 0.0).unwrap();
//! assert!((a[0] + 9.81 / 2.0 * 0.5_f64.sin()).abs() < 1e-15);
//! // The jets derive the same pieces from L alone.
//! let jets = lagrange_runtime::eom::jet_pieces(&p, &[0.5], &[0.0], 0.0);
//! assert!((jets.lagrangian_force[0] - p.pieces(&[0.5], &[0.0], 0.0).lagrangian_force[0]).abs() < 1e-15);
//! ```

use crate::error::DynamicsError;
use crate::jet::{ElJet, HessianJet};
use crate::lagrangian::Lagrangian;
use crate::linalg::{solve_symmetric, SolveFailure};

/// The pieces of the equations of motion M q̈ = f_L + Q − ∂D/∂q̇ at one state, as a backend
/// supplies them.
///
/// `#[non_exhaustive]`: the pieces grow as the mechanics does (applied forces, constraint rows);
/// build them with [`Pieces::new`].
///
/// ```
/// use lagrange_runtime::eom::Pieces;
/// let p = Pieces::new([[2.0, 1.0], [0.0, 3.0]], [1.0, -1.0]);
/// assert_eq!(p.rhs(), [1.0, -1.0]);
/// assert_eq!(p.mass_entry(1, 0), 1.0); // the upper triangle, read symmetrically
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Pieces<const N: usize> {
    /// The mass matrix M = ∂²L/∂q̇∂q̇ by its upper triangle: `mass[i][k]` for k ≥ i (the entries
    /// below the diagonal are not read).
    pub mass: [[f64; N]; N],
    /// The Lagrangian part of the right-hand side, f_L = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t.
    pub lagrangian_force: [f64; N],
    /// The applied forces Q − ∂D/∂q̇: generalized forces and Rayleigh dissipation (zero unless the
    /// system has them; see [`Pieces::with_applied`]).
    pub applied: [f64; N],
}

impl<const N: usize> Pieces<N> {
    /// The pieces of a conservative system from M (upper triangle) and f_L (no applied forces).
    ///
    /// ```
    /// use lagrange_runtime::eom::Pieces;
    /// let p = Pieces::new([[1.0]], [2.0]);
    /// assert_eq!((p.lagrangian_force, p.applied), ([2.0], [0.0]));
    /// ```
    #[inline(always)]
    pub fn new(mass: [[f64; N]; N], lagrangian_force: [f64; N]) -> Self {
        Pieces {
            mass,
            lagrangian_force,
            applied: [0.0; N],
        }
    }

    /// The same pieces with the applied forces Q − ∂D/∂q̇ set.
    ///
    /// ```
    /// use lagrange_runtime::eom::Pieces;
    /// let p = Pieces::new([[1.0]], [2.0]).with_applied([-0.5]);
    /// assert_eq!(p.rhs(), [1.5]);
    /// ```
    #[inline(always)]
    pub fn with_applied(mut self, applied: [f64; N]) -> Self {
        self.applied = applied;
        self
    }

    /// The right-hand side of M q̈ = rhs: everything that acts on the coordinates,
    /// f_L + Q − ∂D/∂q̇.
    ///
    /// ```
    /// use lagrange_runtime::eom::Pieces;
    /// assert_eq!(Pieces::new([[1.0]], [2.0]).with_applied([1.0]).rhs(), [3.0]);
    /// ```
    #[inline(always)]
    pub fn rhs(&self) -> [f64; N] {
        let mut b = self.lagrangian_force;
        for (b, a) in b.iter_mut().zip(&self.applied) {
            *b += a;
        }
        b
    }

    /// Mᵢₖ, read from the upper triangle whichever order i, k come in.
    ///
    /// ```
    /// use lagrange_runtime::eom::Pieces;
    /// let p = Pieces::new([[1.0, 5.0], [0.0, 1.0]], [0.0; 2]);
    /// assert_eq!((p.mass_entry(0, 1), p.mass_entry(1, 0)), (5.0, 5.0));
    /// ```
    #[inline(always)]
    pub fn mass_entry(&self, i: usize, k: usize) -> f64 {
        if i <= k {
            self.mass[i][k]
        } else {
            self.mass[k][i]
        }
    }
}

/// The pieces derived by the run-time jets: one evaluation of L in the Euler–Lagrange jet, and
/// the applied forces from [`jet_applied_forces`]. The default of [`Lagrangian::pieces`].
///
/// ```
/// use lagrange_runtime::{eom::jet_pieces, Lagrangian, Scalar};
/// /// L = m q̇²/2 − k q²/2.
/// struct Osc;
/// impl Lagrangian<1> for Osc {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
///         v[0] * v[0] * 1.0 - q[0] * q[0] * 2.0
///     }
/// }
/// let p = jet_pieces(&Osc, &[1.5], &[0.0], 0.0);
/// assert_eq!((p.mass, p.lagrangian_force), ([[2.0]], [-6.0]));
/// ```
#[inline(always)]
pub fn jet_pieces<L, const N: usize>(sys: &L, q: &[f64; N], qdot: &[f64; N], t: f64) -> Pieces<N>
where
    L: Lagrangian<N> + ?Sized,
{
    // One seeding serves L and D.
    let (qj, vj, tj) = ElJet::seed(q, qdot, t);
    let l = sys.lagrangian(&qj, &vj, tj);
    let mut mass = [[0.0; N]; N];
    for (i, row) in mass.iter_mut().enumerate() {
        for (k, e) in row.iter_mut().enumerate().skip(i) {
            *e = l.hess_qdot(i, k);
        }
    }
    let gq = l.grad_q();
    let mixed = l.mixed();
    let mut f = [0.0; N];
    for i in 0..N {
        f[i] = gq[i] - mixed[i];
    }
    let applied = applied_from(sys, &qj, &vj, tj, q, qdot, t);
    Pieces::new(mass, f).with_applied(applied)
}

/// Q − ∂D/∂q̇ with D evaluated on jets already seeded at (q, q̇, t).
#[inline(always)]
fn applied_from<L, const N: usize>(
    sys: &L,
    qj: &[ElJet<N>; N],
    vj: &[ElJet<N>; N],
    tj: ElJet<N>,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> [f64; N]
where
    L: Lagrangian<N> + ?Sized,
{
    let mut applied = sys.generalized_forces(q, qdot, t);
    let dd = sys.dissipation(qj, vj, tj).grad_qdot();
    for (a, d) in applied.iter_mut().zip(dd) {
        *a -= d;
    }
    applied
}

/// The applied forces Q − ∂D/∂q̇ at a state: [`Lagrangian::generalized_forces`] evaluated in
/// `f64`, ∂D/∂q̇ from one evaluation of [`Lagrangian::dissipation`] in the jet. Zero (and free
/// after inlining) for a system that supplies neither.
///
/// ```
/// use lagrange_runtime::{eom::jet_applied_forces, Lagrangian, Scalar};
/// struct Drag;
/// impl Lagrangian<1> for Drag {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
///     fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * v[0].abs() / 3.0 }
///     fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], t: S) -> [S; 1] { [t] }
/// }
/// // Q − ∂D/∂ẋ = t − ẋ|ẋ| at ẋ = 2, t = 1
/// assert_eq!(jet_applied_forces(&Drag, &[0.0], &[2.0], 1.0), [1.0 - 4.0]);
/// ```
#[inline(always)]
pub fn jet_applied_forces<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> [f64; N]
where
    L: Lagrangian<N> + ?Sized,
{
    let (qj, vj, tj) = ElJet::seed(q, qdot, t);
    applied_from(sys, &qj, &vj, tj, q, qdot, t)
}

/// The power dh/dt = (Q − ∂D/∂q̇)·q̇ − ∂L/∂t from the jets: the default of
/// [`Lagrangian::power`]. ∂L/∂t comes from a jet that moves t alone (exact, and skipped for an
/// autonomous L).
///
/// ```
/// use lagrange_runtime::{eom::jet_power, Lagrangian, Scalar};
/// /// A particle in a potential that grows in time, L = ẋ²/2 − t x².
/// struct Growing;
/// impl Lagrangian<1> for Growing {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = false;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], t: S) -> S { v[0] * v[0] * 0.5 - t * q[0] * q[0] }
/// }
/// assert_eq!(jet_power(&Growing, &[3.0], &[1.0], 2.0), 9.0); // −∂L/∂t = x²
/// ```
pub fn jet_power<L, const N: usize>(sys: &L, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64
where
    L: Lagrangian<N> + ?Sized,
{
    let applied = jet_applied_forces(sys, q, qdot, t);
    let mut p = 0.0;
    for i in 0..N {
        p += applied[i] * qdot[i];
    }
    if !L::AUTONOMOUS {
        let (qj, vj, tj) = ElJet::seed_time(q, qdot, t);
        p -= sys.lagrangian(&qj, &vj, tj).directional();
    }
    p
}

/// Assembles M q̈ = rhs from the pieces and solves it for q̈ (the default of
/// [`Lagrangian::accelerations`]).
///
/// ```
/// use lagrange_runtime::eom::{solve, Pieces};
/// let a = solve(&Pieces::new([[2.0]], [4.0]), ["x"], &[0.0], &[0.0], 0.0).unwrap();
/// assert_eq!(a, [2.0]);
/// ```
#[inline(always)]
pub fn solve<const N: usize>(
    pieces: &Pieces<N>,
    names: [&'static str; N],
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<[f64; N], DynamicsError> {
    solve_mass_matrix(&pieces.mass, &pieces.rhs(), names, q, qdot, t)
}

/// Solves M q̈ = rhs for a mass matrix given by its upper triangle, turning a failure into a
/// [`DynamicsError`] that names the state, the coordinate and what to try. Every backend's
/// solve ends here when its own fast path does not apply.
///
/// ```
/// use lagrange_runtime::{solve_mass_matrix, DynamicsError};
/// let ok = solve_mass_matrix(&[[2.0]], &[4.0], ["x"], &[0.0], &[0.0], 0.0).unwrap();
/// assert_eq!(ok, [2.0]);
/// let err = solve_mass_matrix(&[[0.0]], &[1.0], ["x"], &[0.0], &[0.0], 0.0).unwrap_err();
/// assert!(matches!(err, DynamicsError::SingularMassMatrix { .. }));
/// ```
pub fn solve_mass_matrix<const N: usize>(
    m: &[[f64; N]; N],
    rhs: &[f64; N],
    names: [&'static str; N],
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<[f64; N], DynamicsError> {
    match solve_symmetric(m, rhs) {
        Ok(a) if a.iter().all(|x| x.is_finite()) => Ok(a),
        Ok(_) | Err(SolveFailure::NonFinite) => Err(non_finite(q, qdot, t)),
        Err(SolveFailure::Singular {
            row,
            relative_pivot,
        }) => {
            let name = names.get(row).copied().unwrap_or("?");
            let what = if relative_pivot > 0.0 && relative_pivot.is_finite() {
                let lost = (-relative_pivot.log10()).round();
                format!(
                    "nearly singular: elimination at coordinate `{name}` left a pivot of \
                     {relative_pivot:.1e} of its diagonal entry, so the accelerations would lose \
                     about {lost} of 16 digits (more than half)"
                )
            } else {
                format!("singular: elimination broke down at coordinate `{name}`")
            };
            Err(DynamicsError::SingularMassMatrix {
                t,
                q: q.to_vec(),
                qdot: qdot.to_vec(),
                message: format!(
                    "the mass matrix ∂²L/∂q̇∂q̇ is {what}. Two coordinates (nearly) describe the same \
                     motion here: typically a singularity of the chart (for Euler angles sin θ = 0, \
                     where φ and ψ turn about the same axis). Try: start away from that configuration, \
                     or orient the reference axes (or choose other coordinates) so the motion avoids \
                     it. If a coordinate has no kinetic term at all, L is degenerate and that \
                     coordinate is a constraint, not a degree of freedom."
                ),
            })
        }
    }
}

fn non_finite<const N: usize>(q: &[f64; N], qdot: &[f64; N], t: f64) -> DynamicsError {
    let what = if q.iter().chain(qdot).any(|x| !x.is_finite()) || !t.is_finite() {
        "the state itself is not finite"
    } else {
        "the derivatives of L are not finite here"
    };
    DynamicsError::NonFinite {
        t,
        q: q.to_vec(),
        qdot: qdot.to_vec(),
        message: format!(
            "{what} (NaN or ∞). Check the parameters and the initial state, and whether L is defined \
             at this state (a sqrt or ln of a negative number, a division by zero); if an integrator got \
             here, a smaller step or a tighter tolerance may keep the solution from blowing up."
        ),
    }
}

/// The applied forces F = Q − ∂D/∂q̇ at a state with their derivatives, exact from the Hessian
/// jet: what an implicit integrator's Newton Jacobian (and a linearization's damping) needs.
///
/// ```
/// use lagrange_runtime::{eom::applied_jacobian, Lagrangian, Scalar};
/// /// Drag D = c ẋ² x²/2 and a force Q = x t.
/// struct S;
/// impl Lagrangian<1> for S {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S2: Scalar>(&self, _q: &[S2; 1], v: &[S2; 1], _t: S2) -> S2 { v[0] * v[0] * 0.5 }
///     fn dissipation<S2: Scalar>(&self, q: &[S2; 1], v: &[S2; 1], _t: S2) -> S2 { v[0] * v[0] * q[0] * q[0] * 0.5 }
///     fn generalized_forces<S2: Scalar>(&self, q: &[S2; 1], _v: &[S2; 1], t: S2) -> [S2; 1] { [q[0] * t] }
/// }
/// let j = applied_jacobian(&S, &[2.0], &[3.0], 5.0);
/// assert_eq!(j.value, [10.0 - 3.0 * 4.0]);     // x t − ẋ x²
/// assert_eq!(j.d_q, [[5.0 - 2.0 * 3.0 * 2.0]]); // t − 2 ẋ x
/// assert_eq!(j.d_qdot, [[-4.0]]);                // −x²
/// ```
pub fn applied_jacobian<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> AppliedJacobian<N>
where
    L: Lagrangian<N> + ?Sized,
{
    let (qj, vj) = HessianJet::seed(q, qdot);
    let tj = HessianJet::from(t);
    let forces = sys.generalized_forces(&qj, &vj, tj);
    let d = sys.dissipation(&qj, &vj, tj);
    let (dv, dqv, dvv) = (d.grad_qdot(), d.hess_qqdot(), d.hess_qdotqdot());
    let mut out = AppliedJacobian {
        value: [0.0; N],
        d_q: [[0.0; N]; N],
        d_qdot: [[0.0; N]; N],
    };
    for i in 0..N {
        let (gq, gv) = (forces[i].grad_q(), forces[i].grad_qdot());
        out.value[i] = forces[i].value() - dv[i];
        for k in 0..N {
            out.d_q[i][k] = gq[k] - dqv[k][i];
            out.d_qdot[i][k] = gv[k] - dvv[i][k];
        }
    }
    out
}

/// The applied forces F = Q − ∂D/∂q̇ and their Jacobians (see [`applied_jacobian`]).
///
/// ```
/// use lagrange_runtime::eom::AppliedJacobian;
/// let j = AppliedJacobian::<1> { value: [1.0], d_q: [[0.0]], d_qdot: [[-0.5]] };
/// assert_eq!(j.d_qdot[0][0], -0.5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AppliedJacobian<const N: usize> {
    /// Fᵢ.
    pub value: [f64; N],
    /// ∂Fᵢ/∂qₖ (`d_q[i][k]`).
    pub d_q: [[f64; N]; N],
    /// ∂Fᵢ/∂q̇ₖ (`d_qdot[i][k]`).
    pub d_qdot: [[f64; N]; N],
}
