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
//!
//! A system with holonomic constraints g(q, t) = 0 ([`Holonomic`](crate::Holonomic)) adds its
//! [`ConstraintRows`] (G = ∂g/∂q and g̈ at q̈ = 0), and [`solve_constrained`] solves
//!
//! ```text
//! M q̈ = f_L + Q − ∂D/∂q̇ + Gᵀ λ,    G q̈ = −(q̇ᵀ ∂²g/∂q² q̇ + 2 ∂²g/∂q∂t q̇ + ∂²g/∂t²)
//! ```
//!
//! for q̈ and the multipliers λ (the constraint forces in generalized coordinates are Gᵀλ).
//! [`Lagrangian::pieces`](crate::Lagrangian::pieces) is where a system supplies its pieces (the default derives them from
//! L with the jets); [`Lagrangian::accelerations`](crate::Lagrangian::accelerations) is `solve(pieces)` unless a backend has a
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
//! let jets = lagrange_runtime::lagrangian::jet_pieces(&p, &[0.5], &[0.0], 0.0);
//! assert!((jets.lagrangian_force[0] - p.pieces(&[0.5], &[0.0], 0.0).lagrangian_force[0]).abs() < 1e-15);
//! ```

pub mod series;
pub use series::{Factor, LdlOf, SeriesFactor, SeriesReal};

use crate::error::DynamicsError;
use crate::linalg::{Ldlt, SolveFailure, all_finite, solve_symmetric};

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

/// Assembles M q̈ = rhs from the pieces and solves it for q̈ (the default of
/// [`Lagrangian::accelerations`](crate::Lagrangian::accelerations)).
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

/// The constraint rows at a state (q, q̇, t): what a system with holonomic constraints
/// g(q, t) = 0 adds to the [`Pieces`] (see [`solve_constrained`]).
///
/// ```
/// use lagrange_runtime::eom::ConstraintRows;
/// let rows = ConstraintRows { value: [0.0], jacobian: [[1.0, 0.0]], rate: [0.0], curvature: [2.0] };
/// assert_eq!(rows.jacobian[0][0], 1.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstraintRows<const N: usize, const K: usize> {
    /// g(q, t): zero on the constraints.
    pub value: [f64; K],
    /// G = ∂g/∂q, one row per constraint (`jacobian[j][i]` = ∂g_j/∂q_i).
    pub jacobian: [[f64; N]; K],
    /// ġ = G q̇ + ∂g/∂t: zero when the velocities are tangent to the constraints.
    pub rate: [f64; K],
    /// g̈ at q̈ = 0, q̇ᵀ(∂²g/∂q²)q̇ + 2(∂²g/∂q∂t)q̇ + ∂²g/∂t²: the acceleration-level constraint
    /// is G q̈ = −`curvature`.
    pub curvature: [f64; K],
}

/// Solves the constrained equations of motion M q̈ = f + Gᵀλ, G q̈ = −`curvature` for q̈ and λ
/// (f = [`Pieces::rhs`]); M may be singular as long as the constrained system
/// [M Gᵀ; G 0] is not (a rigid body in unit-quaternion coordinates has a rank-3 M).
///
/// Method: on the constraints G q̈ = −c, so M q̈ = f + Gᵀλ is equivalent to
/// (M + w GᵀG) q̈ = f − w Gᵀc + Gᵀλ for any w; with w = (largest Mᵢᵢ)/(largest |G row|²) the
/// matrix M̃ = M + w GᵀG is positive definite exactly when the constrained system is regular,
/// and one LDLᵀ of M̃ gives q̈ = M̃⁻¹(f − wGᵀc) + M̃⁻¹Gᵀλ, with λ from the K × K system
/// (G M̃⁻¹ Gᵀ) λ = −c − G M̃⁻¹(f − wGᵀc). Everything stays on the stack.
///
/// Small systems (N + K ≤ 6), where a right-hand side's time is a chain of dependent steps,
/// go faster ways first and fall back to the above wherever those decline: one constraint by
/// coordinate partitioning ([`linalg::saddle_solve_one`](crate::linalg::saddle_solve_one): no
/// w, the reduced system tested as the LDLᵀ is), then (and for K ≥ 2) the saddle-point system
/// [M̃ Gᵀ; G 0] by division-free elimination ([`linalg::saddle_solve`](crate::linalg::saddle_solve):
/// the same pivot tests; M̃ scaled by a power of two first so the units of mass do not matter).
/// The errors are always those of the careful path.
///
/// Errors: [`DynamicsError::DependentConstraints`] naming the constraint whose row depends on
/// the others, [`DynamicsError::SingularMassMatrix`] naming the coordinate along which the
/// constrained system has no inertia, [`DynamicsError::NonFinite`].
///
/// ```
/// use lagrange_runtime::eom::{solve_constrained, ConstraintRows, Pieces};
/// // A unit mass in the plane on the line x = y, pushed along x by 2: it accelerates along the
/// // line at 1, and the line pushes back with λ = −1 along (1, −1).
/// let p = Pieces::new([[1.0, 0.0], [0.0, 1.0]], [2.0, 0.0]);
/// let rows = ConstraintRows { value: [0.0], jacobian: [[1.0, -1.0]], rate: [0.0], curvature: [0.0] };
/// let (a, lambda) = solve_constrained(&p, &rows, ["x", "y"], &[0.0; 2], &[0.0; 2], 0.0).unwrap();
/// assert!((a[0] - 1.0).abs() < 1e-15 && (a[1] - 1.0).abs() < 1e-15);
/// assert!((lambda[0] + 1.0).abs() < 1e-15);
/// ```
#[inline]
pub fn solve_constrained<const N: usize, const K: usize>(
    pieces: &Pieces<N>,
    rows: &ConstraintRows<N, K>,
    names: [&'static str; N],
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<([f64; N], [f64; K]), DynamicsError> {
    let f = pieces.rhs();
    let g = &rows.jacobian;
    let c = &rows.curvature;
    if !(all_finite(g.as_flattened()) && all_finite(c)) {
        return Err(non_finite(q, qdot, t));
    }
    if let Some(out) = solve_rescaled(pieces, rows, names, q, qdot, t) {
        return out;
    }
    if K == 1
        && N + K <= SADDLE_MAX
        && let Some((a, l)) = crate::linalg::saddle_solve_one(&pieces.mass, &f, &g[0], -c[0])
    {
        let mut lambda = [0.0; K];
        lambda[0] = l;
        return Ok((a, lambda));
    }
    let mut mscale = 0.0_f64;
    for i in 0..N {
        mscale = mscale.max(pieces.mass[i][i].abs());
    }
    if mscale == 0.0 || !mscale.is_finite() {
        mscale = 1.0;
    }
    let mut gscale = 0.0_f64;
    for (j, row) in g.iter().enumerate() {
        let n2: f64 = row.iter().map(|x| x * x).sum();
        if n2 == 0.0 {
            return Err(dependent(
                j,
                "its row (∂g/∂q of a holonomic constraint, A of a velocity constraint A q̇ + b = 0) is zero here",
                q,
                qdot,
                t,
            ));
        }
        gscale = gscale.max(n2);
    }
    let w = if K == 0 {
        0.0
    } else {
        power_of_two_ratio(mscale, gscale)
    };
    // M̃ = M + w GᵀG (upper triangle) and b̃ = f − w Gᵀ c, both times `unit`: a power of two
    // (exact) that brings the largest diagonal entry to order one for the division-free fast
    // path of small systems, whose growing factor then stays in range whatever the units (λ
    // scales back below); 1 otherwise.
    let small = N + K <= SADDLE_MAX;
    let unit = if small {
        power_of_two_ratio(1.0, mscale)
    } else {
        1.0
    };
    let wu = w * unit;
    let mut mt = pieces.mass;
    let mut bt = f;
    for i in 0..N {
        for k in i..N {
            let mut s = 0.0;
            for row in g {
                s += row[i] * row[k];
            }
            mt[i][k] = mt[i][k] * unit + wu * s;
        }
        bt[i] *= unit;
        for j in 0..K {
            bt[i] -= wu * g[j][i] * c[j];
        }
    }
    // The fast path (`constrained_fast`: the saddle-point elimination for small systems, else
    // one factorization and one sweep for z = M̃⁻¹ b̃ and Y_j = M̃⁻¹ G_jᵀ and the K×K system by
    // Cholesky); anything unusual (a small pivot, an indefinite M̃, dependent rows, a non-finite
    // value) goes to the careful path below, which says what happened. λ of the scaled system
    // is `unit` λ.
    let back = if small {
        power_of_two_ratio(mscale, 1.0)
    } else {
        1.0
    };
    if let Some((a, lambda)) = constrained_fast(&mt, &bt, g, c) {
        return Ok((a, lambda.map(|l| l * back)));
    }
    constrained_careful(&mt, &bt, g, c, back, rows, (&names, q, qdot, t))
}

/// What [`solve_constrained`] gives: (q̈, λ) or why not.
type Solved<const N: usize, const K: usize> = Result<([f64; N], [f64; K]), DynamicsError>;

/// [`solve_constrained`] of rows whose squared norms leave f64's normal range, scaled first;
/// `None` for other rows (every system in practice).
#[inline(always)]
fn solve_rescaled<const N: usize, const K: usize>(
    pieces: &Pieces<N>,
    rows: &ConstraintRows<N, K>,
    names: [&'static str; N],
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Option<Solved<N, K>> {
    // A row whose squared norm leaves f64's normal range (a constraint 1e-200 (x − 1) has a
    // gradient that squares to 0, and was called a zero gradient) is scaled by a power of two to
    // order one, exactly, and its multiplier scaled back; other systems do not pass here.
    let out_of_range = |row: &[f64; N]| {
        let n2: f64 = row.iter().map(|x| x * x).sum();
        !n2.is_normal() && row.iter().any(|x| *x != 0.0)
    };
    if !rows.jacobian.iter().any(out_of_range) {
        return None;
    }
    let mut scaled = *rows;
    let mut s = [1.0; K];
    for j in 0..K {
        let m = rows.jacobian[j].iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if m > 0.0 {
            s[j] = power_of_two_ratio(1.0, m);
            for x in &mut scaled.jacobian[j] {
                *x *= s[j];
            }
            scaled.curvature[j] *= s[j];
            scaled.rate[j] *= s[j];
            scaled.value[j] *= s[j];
        }
    }
    // (Scaled to its largest entry, a non-zero row's squared norm is in [1, N].)
    if !scaled.jacobian.iter().any(out_of_range) {
        return Some(
            solve_constrained(pieces, &scaled, names, q, qdot, t).map(|(a, lambda)| {
                let mut out = lambda;
                for j in 0..K {
                    out[j] *= s[j];
                }
                (a, out)
            }),
        );
    }
    None
}

/// The careful path of [`solve_constrained`] (where the fast one declined): one factorization
/// of M̃ (LDLᵀ, LU where M̃ is indefinite) for z = M̃⁻¹ b̃ and Y_j = M̃⁻¹ G_jᵀ, then
/// (G M̃⁻¹ Gᵀ) λ = −c − G z; says what went wrong, at (q, q̇, t) of `at`. λ is scaled by `back`.
#[inline(always)]
fn constrained_careful<const N: usize, const K: usize>(
    mt: &[[f64; N]; N],
    bt: &[f64; N],
    g: &[[f64; N]; K],
    c: &[f64; K],
    back: f64,
    rows: &ConstraintRows<N, K>,
    (names, q, qdot, t): (&[&'static str; N], &[f64; N], &[f64; N], f64),
) -> Result<([f64; N], [f64; K]), DynamicsError> {
    // z = M̃⁻¹ b̃ and Y_j = M̃⁻¹ G_jᵀ, from one factorization.
    let singular = |row: usize, relative_pivot: f64| {
        singular_constrained(*names, row, relative_pivot, q, qdot, t)
    };
    let (z, y) = match Ldlt::factor(mt) {
        Ok(fac) => (fac.solve(bt), core::array::from_fn(|j| fac.solve(&g[j]))),
        Err(SolveFailure::NonFinite) => return Err(non_finite(q, qdot, t)),
        Err(SolveFailure::Singular {
            row,
            relative_pivot,
        }) if relative_pivot > 0.0 => return Err(singular(row, relative_pivot)),
        Err(SolveFailure::Singular { .. }) => {
            // Indefinite M̃ (an M that is not positive semi-definite): LU for each column.
            let lu = |b: &[f64; N]| match solve_symmetric(mt, b) {
                Ok(x) => Ok(x),
                Err(SolveFailure::NonFinite) => Err(non_finite(q, qdot, t)),
                Err(SolveFailure::Singular {
                    row,
                    relative_pivot,
                }) => Err(singular(row, relative_pivot)),
            };
            let z = lu(bt)?;
            let mut y = [[0.0; N]; K];
            for j in 0..K {
                y[j] = lu(&g[j])?;
            }
            (z, y)
        }
    };
    // (G M̃⁻¹ Gᵀ) λ = −c − G z.
    let (s, r) = multiplier_system(g, &y, &z, c);
    let lambda = match solve_symmetric(&s, &r) {
        Ok(l) => l,
        Err(SolveFailure::NonFinite) => return Err(non_finite(q, qdot, t)),
        Err(SolveFailure::Singular { row, .. }) => {
            redundant(&s, &r, c, row, rows, (names, q, qdot, t))?
        }
    };
    let mut a = z;
    for j in 0..K {
        for i in 0..N {
            a[i] += lambda[j] * y[j][i];
        }
    }
    if all_finite(&a) && all_finite(&lambda) {
        Ok((a, lambda.map(|l| l * back)))
    } else {
        Err(non_finite(q, qdot, t))
    }
}

/// The multipliers of redundant constraints (S = G M̃⁻¹ Gᵀ singular: rows of G that depend on
/// the others, everywhere or at this configuration): the least-norm λ of S λ = r, which gives
/// the one constraint force Gᵀλ and accelerations the constraints determine. Fails with
/// [`DynamicsError::DependentConstraints`] naming the rows when they are inconsistent (r has a
/// part outside S's range: the dependent rows ask for accelerations that contradict each other,
/// so no motion satisfies them), or when the least-norm solve itself fails (then naming `row`,
/// where the pivot test broke down).
///
/// Inconsistency is judged on the constraints only. Off them (a Runge–Kutta stage, Radau5's
/// Newton iterates, the perturbed states of a difference quotient) dependent rows are
/// inconsistent to the order of the distance from them — Bricard's linkage asks 5e-6 of
/// contradiction 6e-6 away — and there λ is the least-norm least-squares one (a smooth
/// extension of the accelerations off the constraints), the step's projection bringing the
/// state back. Refusing there had DOP853 reject its steps down to 1/25 of their size.
#[inline(never)]
fn redundant<const N: usize, const K: usize>(
    s: &[[f64; K]; K],
    r: &[f64; K],
    c: &[f64; K],
    row: usize,
    rows: &ConstraintRows<N, K>,
    (_names, q, qdot, t): (&[&'static str; N], &[f64; N], &[f64; N], f64),
) -> Result<[f64; K], DynamicsError> {
    let Some(sol) = crate::linalg::least_norm_symmetric(K, |i, k| s[i][k], r) else {
        return Err(dependent(
            row,
            "its row (∂g/∂q of a holonomic constraint, A of a velocity constraint A q̇ + b = 0) is (nearly) a combination of the rows before it",
            q,
            qdot,
            t,
        ));
    };
    // Consistent rows leave only round-off outside S's range: a few ulps of r and of the
    // curvature terms it is made of.
    let size = r
        .iter()
        .chain(c.iter())
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    if sol.outside > 1e-8 * size && off_constraints(rows, q, qdot) <= 1e-8 {
        let rows: Vec<String> = sol.rows.iter().map(ToString::to_string).collect();
        return Err(DynamicsError::DependentConstraints {
            t,
            q: q.to_vec(),
            qdot: qdot.to_vec(),
            message: format!(
                "constraints {} (counting from 0: the holonomic constraints in the order \
                 `fn constraints` returns them, then the velocity constraints) are dependent \
                 here and inconsistent: they ask for accelerations that contradict each other \
                 (a part {:.3e} of their right-hand side that no multipliers meet), so no \
                 motion satisfies them all; remove the constraint that contradicts the others, \
                 or correct it so that it holds along the motion the others allow",
                rows.join(", "),
                sol.outside
            ),
        });
    }
    Ok(core::array::from_fn(|j| sol.x[j]))
}

/// How far (q, q̇) is off the constraints of `rows`, relatively: the largest of |g_j| against
/// Σ_i |∂g_j/∂q_i q_i| (the terms that cancel in g_j) and |ġ_j| against
/// Σ_i |∂g_j/∂q_i q̇_i| + |∂g_j/∂t|, each scale plus the row's largest entry (a floor at q = 0
/// or at rest).
fn off_constraints<const N: usize, const K: usize>(
    rows: &ConstraintRows<N, K>,
    q: &[f64; N],
    qdot: &[f64; N],
) -> f64 {
    (0..K).fold(0.0_f64, |worst, j| {
        let g = &rows.jacobian[j];
        let size = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let sp: f64 = (0..N).map(|i| (g[i] * q[i]).abs()).sum::<f64>() + size;
        let gv: f64 = (0..N).map(|i| g[i] * qdot[i]).sum();
        let sv: f64 =
            (0..N).map(|i| (g[i] * qdot[i]).abs()).sum::<f64>() + (rows.rate[j] - gv).abs() + size;
        worst
            .max(rows.value[j].abs() / sp)
            .max(rows.rate[j].abs() / sv)
    })
}

/// A power of two within a factor 2 of a / b (a, b > 0), from the exponents: no division on the
/// constrained solve's critical path (the weight w of M + w GᵀG only sets the conditioning, and
/// scaling by a power of two is exact). Falls back to a / b outside the normal range.
#[inline(always)]
pub(crate) fn power_of_two_ratio(a: f64, b: f64) -> f64 {
    let exponent = |x: f64| ((x.to_bits() >> 52) & 0x7ff) as i64;
    let e = exponent(a) - exponent(b) + 1023;
    if a.is_normal() && b.is_normal() && (1..=2046).contains(&e) {
        f64::from_bits((e as u64) << 52)
    } else {
        a / b
    }
}

/// The multipliers' system S λ = r of [`solve_constrained`]: S = G Y (upper triangle) with
/// Y_j = M̃⁻¹ G_jᵀ, and r = −c − G z with z = M̃⁻¹ b̃.
#[inline(always)]
fn multiplier_system<const N: usize, const K: usize>(
    g: &[[f64; N]; K],
    y: &[[f64; N]; K],
    z: &[f64; N],
    c: &[f64; K],
) -> ([[f64; K]; K], [f64; K]) {
    let mut s = [[0.0; K]; K];
    let mut r = [0.0; K];
    for j in 0..K {
        for l in j..K {
            s[j][l] = (0..N).map(|i| g[j][i] * y[l][i]).sum();
        }
        r[j] = -c[j] - (0..N).map(|i| g[j][i] * z[i]).sum::<f64>();
    }
    (s, r)
}

/// Up to this many coordinates plus constraints, [`solve_constrained`] tries
/// [`linalg::saddle_solve_one`](crate::linalg::saddle_solve_one) (K = 1) and
/// [`linalg::saddle_solve`](crate::linalg::saddle_solve) before the LDLᵀ of M̃ with K + 1
/// right-hand sides. The quaternion top (4 + 1, DOP853 rtol 1e-10) ran 3.43 ms with the LDLᵀ,
/// 2.93 with `saddle_solve`, and (after the projection's change in `Stepper::set_node`) 2.82
/// → 2.28 with `saddle_solve_one`; the four-bar linkage (3 + 2) 2.89 → 2.80 ms with
/// `saddle_solve` (BENCHMARKS.md). Larger systems are unmeasured and keep the LDLᵀ.
const SADDLE_MAX: usize = 6;

/// [`solve_constrained`] after M̃ and b̃: `None` wherever the careful path must decide.
#[inline(always)]
fn constrained_fast<const N: usize, const K: usize>(
    mt: &[[f64; N]; N],
    bt: &[f64; N],
    g: &[[f64; N]; K],
    c: &[f64; K],
) -> Option<([f64; N], [f64; K])> {
    if N + K <= SADDLE_MAX {
        return crate::linalg::saddle_solve(mt, bt, g, &c.map(|x| -x));
    }
    let (z, y) = crate::linalg::ldlt_solve_with(mt, bt, g)?;
    // S is symmetric positive definite for independent rows.
    let (s, r) = multiplier_system(g, &y, &z, c);
    let lambda: [f64; K] = if K == 1 {
        // The careful path's test for a 1×1 system: a positive pivot.
        if s[0][0].is_nan() || s[0][0] <= 0.0 {
            return None;
        }
        let mut out = [0.0; K];
        out[0] = r[0] / s[0][0];
        out
    } else {
        crate::linalg::ldlt_solve_with(&s, &r, &[])?.0
    };
    let mut a = z;
    for j in 0..K {
        for i in 0..N {
            a[i] += lambda[j] * y[j][i];
        }
    }
    (all_finite(&a) && all_finite(&lambda)).then_some((a, lambda))
}

fn dependent<const N: usize>(
    j: usize,
    why: &str,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> DynamicsError {
    DynamicsError::DependentConstraints {
        t,
        q: q.to_vec(),
        qdot: qdot.to_vec(),
        message: format!(
            "constraint {j} (counting from 0: the holonomic constraints in the order \
             `constraints` returns them, then the velocity constraints of \
             `velocity_constraints`) is dependent: {why}, so the multipliers are not determined. \
             Try: remove the redundant constraint (a closed chain often repeats one; a velocity \
             constraint may repeat what a holonomic one implies, or a rolling condition written \
             twice), or write a holonomic one in a form whose gradient does not vanish on it \
             (g = x² − a² rather than g = (x − a)²) and a velocity one with a row A(q) that \
             does not vanish where the system goes."
        ),
    }
}

fn singular_constrained<const N: usize>(
    names: [&'static str; N],
    row: usize,
    relative_pivot: f64,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> DynamicsError {
    let name = names.get(row).copied().unwrap_or("?");
    let how = if relative_pivot > 0.0 && relative_pivot.is_finite() {
        format!(
            "nearly singular (a pivot of {relative_pivot:.1e} of its diagonal entry at coordinate \
             `{name}`)"
        )
    } else {
        format!("singular at coordinate `{name}`")
    };
    DynamicsError::SingularMassMatrix {
        t,
        q: q.to_vec(),
        qdot: qdot.to_vec(),
        message: format!(
            "the constrained system [M Gᵀ; G 0] is {how}: the coordinates there have no inertia in \
             ∂²L/∂q̇∂q̇ that the constraints do not already fix. Try: give every coordinate a \
             kinetic term or fix it by a constraint; if the chart is singular here (Euler angles \
             at sin θ = 0), start elsewhere or use coordinates without the singularity."
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{ConstraintRows, Pieces, solve_constrained};

    /// A constraint of gradient 1e-200 (its squared norm underflows to 0) is a constraint, not a
    /// zero gradient: the mass on the line x = y pushed by (2, 0) accelerates at
    /// (1, 1), and λ = −1e200 (Gᵀλ = (−1, 1)); 1e200 likewise (its square overflows).
    #[test]
    fn tiny_and_huge_constraint_gradients_are_scaled_not_refused() {
        let p = Pieces::new([[1.0, 0.0], [0.0, 1.0]], [2.0, 0.0]);
        for (k, lambda_expected) in [(1e-200, -1e200), (1e200, -1e-200)] {
            let rows = ConstraintRows {
                value: [0.0],
                jacobian: [[k, -k]],
                rate: [0.0],
                curvature: [0.0],
            };
            let (a, lambda) = solve_constrained(&p, &rows, ["x", "y"], &[0.0; 2], &[0.0; 2], 0.0)
                .expect("a regular constraint");
            assert!(
                (a[0] - 1.0).abs() < 1e-15 && (a[1] - 1.0).abs() < 1e-15,
                "{a:?}"
            );
            assert!(
                (lambda[0] / lambda_expected - 1.0).abs() < 1e-15,
                "{lambda:?} against {lambda_expected:e}"
            );
        }
        // Two constraints, one tiny: the particle in 3-D held on x = y and at z = 0.
        let p = Pieces::new(
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [2.0, 0.0, 5.0],
        );
        let rows = ConstraintRows {
            value: [0.0; 2],
            jacobian: [[1e-200, -1e-200, 0.0], [0.0, 0.0, 1.0]],
            rate: [0.0; 2],
            curvature: [0.0; 2],
        };
        let (a, lambda) = solve_constrained(&p, &rows, ["x", "y", "z"], &[0.0; 3], &[0.0; 3], 0.0)
            .expect("regular constraints");
        assert!((a[0] - 1.0).abs() < 1e-15 && (a[1] - 1.0).abs() < 1e-15 && a[2].abs() < 1e-15);
        assert!((lambda[0] / -1e200 - 1.0).abs() < 1e-15 && (lambda[1] + 5.0).abs() < 1e-15);
    }
}
