//! Linearization on the constraint manifold: a system with holonomic constraints g(q, t) = 0
//! and velocity constraints A(q) q̇ + b(q) = 0 about an equilibrium or a steady motion, reduced
//! to the coordinates and speeds the user names.
//!
//! Method (every derivative exact, from the jets):
//! 1. At the reference (q₀, q̇₀) the constrained accelerations a₀ and multipliers λ₀; the
//!    linearization of M q̈ − f along the reference ([`linearize_along`] at a₀) gives M, C, K,
//!    and the constraint forces' own variation δ(Gᵀλ₀) enters K (λ₀ times the Hessians of g,
//!    and the derivatives of A by q).
//! 2. The rows of the constraints at acceleration level, g̈ = G q̈ + … and ċ = A q̈ + …, are
//!    linearized too (third derivatives of g along q̇₀ from the [`LinJet`]); the saddle-point
//!    system [M −Gᵀ; G 0] (δq̈, δλ) = … then gives δq̈ as a linear map of (δq, δq̇): the
//!    Jacobian J of the constrained first-order system, 2N × 2N.
//! 3. The perturbations that keep the constraints, T = {G δq = 0, ∂ġ/∂q δq + G δq̇ = 0,
//!    ∂c/∂q δq + A δq̇ = 0}, carry the physical motion. The named coordinates and speeds z are
//!    lifted into T (least norm), and the reduced state matrix is the named rows of J on that
//!    lift; the unnamed directions of T must not drive the named rows (checked: the answer is
//!    then independent of the lift), else the reduction says which to name.
//!
//! With the speeds the rates of the named coordinates, [`reduce`](ConstrainedLinearization::reduce)
//! gives M, C, K in them: M is the mass matrix of the named speeds (the kinetic energy of the
//! least-energy admissible motion with those speeds), and C, K follow from the reduced state
//! matrix, so the eigenvalues, modes and stability are those of [`Linearization`].

use nalgebra::{Complex, DMatrix, SMatrix};

use crate::constraints::Holonomic;
use crate::error::DynamicsError;
use crate::jet::{LinColumnJet, LinJet};
use crate::linalg::lu_solve_dyn;

use super::{Linearization, LinearizationError, eigenvalues_of, linearize_along};

/// The relative size below which a singular value counts as zero (ranks, null spaces) and
/// below which the unnamed directions' drive of the named rows counts as none.
const RANK_TOL: f64 = 1e-9;

/// How far off its constraints a reference state may be, relative to each constraint's scale
/// (as a constrained run's initial state: round-off is ~1e-16, a mistake ≫ 1e-10).
const OFF_CONSTRAINTS: f64 = 1e-10;

/// A constrained system's linearization about a reference motion, before reduction: the
/// Jacobian of its constrained first-order system and the constraints' tangent rows.
#[derive(Clone, Debug)]
pub struct ConstrainedLinearization<const N: usize> {
    names: [&'static str; N],
    /// J = ∂(q̇, q̈)/∂(q, q̇) of the constrained motion, 2N × 2N.
    jacobian: DMatrix<f64>,
    /// The rows T's perturbations satisfy: (2 KH + KV) × 2N.
    tangent: DMatrix<f64>,
    /// The velocity-level constraint rows (G of the holonomic ones, A of the velocity ones).
    velocity_rows: DMatrix<f64>,
    mass: SMatrix<f64, N, N>,
}

/// `linearize_on_constraints` as a method of every [`Holonomic`] system (the prelude brings
/// this trait in).
pub trait LinearizeConstrained<const N: usize, const K: usize>: Holonomic<N, K> {
    /// The linearization about the motion through (q₀, q̇₀) at t — an equilibrium or a steady
    /// motion on the constraints — of the constrained system (holonomic and velocity
    /// constraints), to be reduced to the coordinates and speeds that describe it
    /// ([`ConstrainedLinearization::reduce`], [`ConstrainedLinearization::state_matrix`]).
    ///
    /// Fails where the constrained accelerations cannot be solved, or for constraints that
    /// depend on time ([`DynamicsError::Constrained`]).
    ///
    /// ```
    /// use lagrange_runtime::{Holonomic, Lagrangian, LinearizeConstrained, Scalar};
    /// /// A pendulum in x, y: the rod x² + y² = l² (l = 2, g = 9.81).
    /// struct P;
    /// impl Lagrangian<2> for P {
    ///     const COORDINATES: [&'static str; 2] = ["x", "y"];
    ///     const CYCLIC: [bool; 2] = [true, false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
    ///         (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
    ///     }
    /// }
    /// impl Holonomic<2, 1> for P {
    ///     const SCLERONOMIC: bool = true;
    ///     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
    ///         [q[0] * q[0] + q[1] * q[1] - 4.0]
    ///     }
    /// }
    /// // Hanging at the bottom, in x: ω² = g/l (the restoring force is the rod's tension).
    /// let lin = P.linearize_on_constraints(&[0.0, -2.0], &[0.0, 0.0], 0.0).unwrap();
    /// let small = lin.reduce(["x"]).unwrap();
    /// assert!((small.k[(0, 0)] / small.m[(0, 0)] - 9.81 / 2.0).abs() < 1e-12);
    /// ```
    fn linearize_on_constraints(
        &self,
        q0: &[f64; N],
        qdot0: &[f64; N],
        t: f64,
    ) -> Result<ConstrainedLinearization<N>, DynamicsError> {
        constrained_linearization(self, q0, qdot0, t)
    }
}

impl<H: Holonomic<N, K> + ?Sized, const N: usize, const K: usize> LinearizeConstrained<N, K> for H {}

/// The refusal of a constrained linearization at (q, q̇, t), saying why.
fn refusal<const N: usize>(
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> impl Fn(String) -> DynamicsError {
    move |message| DynamicsError::Constrained {
        t,
        q: q.to_vec(),
        qdot: qdot.to_vec(),
        message,
    }
}

/// Whether [`constrained_linearization`] takes the reference (q, q̇, t) of `sys`: constraints
/// that do not move, and a state on them.
fn check_reference<H, const N: usize, const K: usize>(
    sys: &H,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<(), DynamicsError>
where
    H: Holonomic<N, K> + ?Sized,
{
    let refuse = refusal(q, qdot, t);
    if !H::SCLERONOMIC {
        return Err(refuse(
            "the constraints depend on time (or a velocity constraint has a velocity-free \
             term b(q, t)): the linearization on the constraint manifold takes constraints that \
             do not move, A(q) q̇ = 0 and g(q) = 0"
                .into(),
        ));
    }
    // The reference must be on the constraints: off them the tangent space, λ and the reduction
    // are those of a state the system cannot be in (a pendulum linearized 10 % off its rod gave
    // ±2.21i for ±3.13i).
    let rows = sys.constraint_rows(q, qdot, t);
    for j in 0..K {
        let g = &rows.jacobian[j];
        let size = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let sp: f64 = (0..N).map(|i| (g[i] * q[i]).abs()).sum::<f64>() + size;
        let sv: f64 = (0..N).map(|i| (g[i] * qdot[i]).abs()).sum::<f64>() + size;
        let (p, v) = (rows.value[j].abs() / sp, rows.rate[j].abs() / sv);
        if !(p <= OFF_CONSTRAINTS && v <= OFF_CONSTRAINTS) {
            return Err(refuse(format!(
                "the reference state is off constraint {j}: its residual is {:e} (positions) \
                 and {:e} (velocities), relative to the constraint's scale; linearize about a \
                 state on the constraints (g(q) = 0, G q̇ = 0, A q̇ = 0), e.g. the projection a \
                 constrained run starts from (`Simulation::new(..).project_initial_state()`)",
                rows.value[j], rows.rate[j]
            )));
        }
    }
    Ok(())
}

/// The default of [`LinearizeConstrained::linearize_on_constraints`] (see the module docs).
fn constrained_linearization<H, const N: usize, const K: usize>(
    sys: &H,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<ConstrainedLinearization<N>, DynamicsError>
where
    H: Holonomic<N, K> + ?Sized,
{
    check_reference(sys, q, qdot, t)?;
    first_order(sys, q, qdot, t)
}

/// The Jacobian of the constrained first-order system at a state, on the constraints or near
/// them (the Newton matrix of a constrained Radau5 run, taken at its projected nodes): exact from
/// the jets for constraints that do not move ([`Holonomic::SCLERONOMIC`]) and are independent;
/// for moving ones, whose acceleration-level rows have terms in t the linearization leaves out,
/// and for redundant ones, whose saddle-point system is singular, central differences of the
/// constrained accelerations (relative step ε^⅓: ~1e-10 of the Jacobian, far below what a
/// simplified Newton iteration asks of its matrix).
pub(crate) fn constrained_state_jacobian<H, const N: usize, const K: usize>(
    sys: &H,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<DMatrix<f64>, DynamicsError>
where
    H: Holonomic<N, K> + ?Sized,
{
    // Redundant constraints make the saddle-point system of the exact linearization singular:
    // differences of the constrained accelerations (least-norm multipliers) then.
    if H::SCLERONOMIC
        && let Ok(l) = first_order(sys, q, qdot, t)
    {
        return Ok(l.jacobian);
    }
    let mut jacobian = DMatrix::zeros(2 * N, 2 * N);
    for i in 0..N {
        jacobian[(i, N + i)] = 1.0;
    }
    for col in 0..2 * N {
        let (mut qp, mut vp) = (*q, *qdot);
        let x = if col < N { q[col] } else { qdot[col - N] };
        let h = f64::EPSILON.cbrt() * x.abs().max(1.0);
        let mut at = |d: f64| {
            if col < N {
                qp[col] = x + d;
            } else {
                vp[col - N] = x + d;
            }
            sys.constrained_accelerations(&qp, &vp, t).map(|(a, _)| a)
        };
        let (up, down) = (at(h)?, at(-h)?);
        for i in 0..N {
            jacobian[(N + i, col)] = (up[i] - down[i]) / (2.0 * h);
        }
    }
    if !jacobian.iter().all(|x| x.is_finite()) {
        return Err(DynamicsError::NonFinite {
            t,
            q: q.to_vec(),
            qdot: qdot.to_vec(),
            message: "the Jacobian of the constrained accelerations is not finite here".into(),
        });
    }
    Ok(jacobian)
}

/// The linearization of the constrained first-order system at (q, q̇, t), the reference unchecked
/// (see the module docs).
fn first_order<H, const N: usize, const K: usize>(
    sys: &H,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Result<ConstrainedLinearization<N>, DynamicsError>
where
    H: Holonomic<N, K> + ?Sized,
{
    let refuse = refusal(q, qdot, t);
    let (a0, lambda) = sys.constrained_accelerations(q, qdot, t)?;
    let lin = linearize_along(sys, q, qdot, t, &a0)?;
    let kh = K - H::VELOCITY_ROWS;
    // Every constraint's gradients and Hessians in (q, q̇) and the Hessians' rate along
    // (q̇₀, a₀).
    // An inline const: each system instantiates only the path its N takes.
    let values = if const { N > crate::jet::HESSIAN_BY_COLUMNS_ABOVE } {
        seconds_by_columns(sys, q, qdot, t, &a0)
    } else {
        seconds_whole(sys, q, qdot, t, &a0)
    };
    let mut g_rows = DMatrix::zeros(K, N);
    let mut hq = DMatrix::zeros(K, N);
    let mut hv = DMatrix::zeros(K, N);
    let mut tangent = DMatrix::zeros(2 * kh + H::VELOCITY_ROWS, 2 * N);
    let mut k_tilde = lin.k;
    for (j, c) in values.iter().enumerate() {
        let (gq, gv) = (&c.gq, &c.gv);
        let (hqq, hqv, hvv) = (&c.hqq, &c.hqv, &c.hvv);
        if j < kh {
            // g(q): G = ∇g, g̈ = ∇g·q̈ + q̇ᵀ∇²g q̇, so ∂g̈/∂q = ∇²g a₀ + (∇³g·q̇) q̇ and
            // ∂g̈/∂q̇ = 2 ∇²g q̇; δ(Gᵀλ) = λ ∇²g δq.
            let third = &c.third_qq;
            for k in 0..N {
                g_rows[(j, k)] = gq[k];
                let (mut sq, mut sv, mut rate) = (0.0, 0.0, 0.0);
                for i in 0..N {
                    sq += hqq[(k, i)] * a0[i] + third[(k, i)] * qdot[i];
                    sv += 2.0 * hqq[(k, i)] * qdot[i];
                    rate += hqq[(k, i)] * qdot[i];
                    k_tilde[(i, k)] -= lambda[j] * hqq[(i, k)];
                }
                hq[(j, k)] = sq;
                hv[(j, k)] = sv;
                tangent[(2 * j, k)] = gq[k];
                tangent[(2 * j + 1, k)] = rate;
                tangent[(2 * j + 1, N + k)] = gq[k];
            }
        } else {
            // c(q, q̇) = A(q) q̇ + b(q): A = ∂c/∂q̇, ċ = ∂c/∂q·q̇ + A q̈, so
            // ∂ċ/∂q = c_qq q̇ + c_q̇q a₀, ∂ċ/∂q̇ = c_qq̇ q̇ + c_q (+ c_q̇q̇ a₀ = 0);
            // δ(Aᵀλ) = λ ∂A/∂q δq.
            let row = 2 * kh + (j - kh);
            for k in 0..N {
                g_rows[(j, k)] = gv[k];
                let (mut sq, mut sv) = (0.0, gq[k]);
                for i in 0..N {
                    sq += hqq[(i, k)] * qdot[i] + hqv[(k, i)] * a0[i];
                    sv += hqv[(i, k)] * qdot[i] + hvv[(i, k)] * a0[i];
                    k_tilde[(i, k)] -= lambda[j] * hqv[(k, i)];
                }
                hq[(j, k)] = sq;
                hv[(j, k)] = sv;
                tangent[(row, k)] = gq[k];
                tangent[(row, N + k)] = gv[k];
            }
        }
    }
    // δq̈ from [M −Gᵀ; G 0] (δq̈, δλ) = (−K̃ δq − C δq̇, −Hq δq − Hv δq̇), one column per unit
    // δq_k and δq̇_k.
    let n = N + K;
    let scale = lin
        .m
        .iter()
        .chain(g_rows.iter())
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    let mut jacobian = DMatrix::zeros(2 * N, 2 * N);
    for i in 0..N {
        jacobian[(i, N + i)] = 1.0;
    }
    for col in 0..2 * N {
        let mut a = vec![0.0; n * n];
        for i in 0..N {
            for k in 0..N {
                a[i * n + k] = lin.m[(i, k)];
            }
            for j in 0..K {
                a[i * n + N + j] = -g_rows[(j, i)];
                a[(N + j) * n + i] = g_rows[(j, i)];
            }
        }
        let mut x = vec![0.0; n];
        for i in 0..N {
            x[i] = if col < N {
                -k_tilde[(i, col)]
            } else {
                -lin.c[(i, col - N)]
            };
        }
        for j in 0..K {
            x[N + j] = if col < N {
                -hq[(j, col)]
            } else {
                -hv[(j, col - N)]
            };
        }
        lu_solve_dyn(&mut a, &mut x, scale).map_err(|_| {
            refuse(
                "the constrained system [M Gᵀ; G 0] is singular at the reference (dependent \
                 constraints, or a direction without inertia)"
                    .into(),
            )
        })?;
        for i in 0..N {
            jacobian[(N + i, col)] = x[i];
        }
    }
    if !jacobian.iter().all(|x| x.is_finite()) {
        return Err(DynamicsError::NonFinite {
            t,
            q: q.to_vec(),
            qdot: qdot.to_vec(),
            message: "the linearization on the constraint manifold is not finite here".into(),
        });
    }
    Ok(ConstrainedLinearization {
        names: H::COORDINATES,
        jacobian,
        tangent,
        velocity_rows: g_rows,
        mass: lin.m,
    })
}

impl<const N: usize> ConstrainedLinearization<N> {
    /// J = ∂(q̇, q̈)/∂(q, q̇) of the constrained first-order system, before reduction (its
    /// eigenvalues include spurious zeros along the constraints' normals).
    ///
    /// ```
    /// # use lagrange_runtime::{Holonomic, Lagrangian, LinearizeConstrained, Scalar};
    /// # struct P;
    /// # impl Lagrangian<2> for P {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81 }
    /// # }
    /// # impl Holonomic<2, 1> for P {
    /// #     const SCLERONOMIC: bool = true;
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 4.0] }
    /// # }
    /// let lin = P.linearize_on_constraints(&[0.0, -2.0], &[0.0, 0.0], 0.0).unwrap();
    /// assert!((lin.jacobian()[(2, 0)] + 9.81 / 2.0).abs() < 1e-12); // δẍ = −(g/l) δx
    /// ```
    pub fn jacobian(&self) -> &DMatrix<f64> {
        &self.jacobian
    }

    /// The index of coordinate `name`.
    fn index(&self, name: &str) -> Result<usize, LinearizationError> {
        self.names
            .iter()
            .position(|n| *n == name)
            .ok_or_else(|| LinearizationError::Reduction {
                message: format!(
                    "no coordinate named \"{name}\" (the coordinates are {:?})",
                    self.names
                ),
            })
    }

    /// The reduced state matrix d/dt (δq_named, δq̇_named) = A (…) in the named coordinates and
    /// speeds (the speeds are the rates q̇ of the coordinates named in `speeds`; they need not
    /// be those of `coordinates`: a heading whose angle is ignorable has a rate that matters).
    ///
    /// Fails for an unknown name, for named variables the constraints make dependent, and when
    /// an unnamed coordinate or speed drives the named ones (its message names the largest
    /// such drive: name more, or linearize about a reference where they decouple).
    ///
    /// ```
    /// # use lagrange_runtime::{Holonomic, Lagrangian, LinearizeConstrained, Scalar};
    /// # struct P;
    /// # impl Lagrangian<2> for P {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81 }
    /// # }
    /// # impl Holonomic<2, 1> for P {
    /// #     const SCLERONOMIC: bool = true;
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 4.0] }
    /// # }
    /// let lin = P.linearize_on_constraints(&[0.0, -2.0], &[0.0, 0.0], 0.0).unwrap();
    /// let a = lin.state_matrix(&["x"], &["x"]).unwrap();
    /// assert!((a[(1, 0)] + 9.81 / 2.0).abs() < 1e-12 && (a[(0, 1)] - 1.0).abs() < 1e-15);
    /// // y is not a coordinate at the bottom: the rod fixes it to first order.
    /// assert!(lin.state_matrix(&["y"], &["y"]).is_err());
    /// ```
    pub fn state_matrix(
        &self,
        coordinates: &[&str],
        speeds: &[&str],
    ) -> Result<DMatrix<f64>, LinearizationError> {
        let mut chosen = Vec::new();
        for c in coordinates {
            chosen.push(self.index(c)?);
        }
        for s in speeds {
            chosen.push(N + self.index(s)?);
        }
        let m = chosen.len();
        let rows = m + self.tangent.nrows();
        if rows > 2 * N {
            return Err(LinearizationError::Reduction {
                message: format!(
                    "{m} named coordinates and speeds with {} constraint rows exceed the {} \
                     state variables: name fewer",
                    self.tangent.nrows(),
                    2 * N
                ),
            });
        }
        // [S; C_T]: the named components and the tangent rows, padded with zero rows to a
        // square matrix so that the decomposition's Vᵀ has the null space too.
        let mut sel = DMatrix::zeros(2 * N, 2 * N);
        for (r, &c) in chosen.iter().enumerate() {
            sel[(r, c)] = 1.0;
        }
        sel.view_mut((m, 0), (self.tangent.nrows(), 2 * N))
            .copy_from(&self.tangent);
        let svd = sel.clone().svd(true, true);
        let (Some(u), Some(v_t)) = (svd.u.as_ref(), svd.v_t.as_ref()) else {
            return Err(LinearizationError::Eigen {
                message: "the singular value decomposition of the constraint rows failed".into(),
            });
        };
        let top = svd.singular_values.iter().fold(0.0_f64, |a, b| a.max(*b));
        let rank = svd
            .singular_values
            .iter()
            .filter(|s| **s > RANK_TOL * top)
            .count();
        if rank < rows {
            return Err(LinearizationError::Reduction {
                message: format!(
                    "the named coordinates {coordinates:?} and speeds {speeds:?} are not \
                     independent on the constraints (the constraints fix some of them, to \
                     first order, from the others): name independent ones"
                ),
            });
        }
        // The least-norm lift x = L z of the named values z into T: the pseudo-inverse of
        // [S; C_T] applied to (z, 0).
        let mut lift = DMatrix::zeros(2 * N, m);
        for col in 0..m {
            // x = V Σ⁻¹ Uᵀ e_col.
            for (k, s) in svd.singular_values.iter().enumerate() {
                if *s <= RANK_TOL * top {
                    continue;
                }
                let coef = u[(col, k)] / s;
                for i in 0..2 * N {
                    lift[(i, col)] += v_t[(k, i)] * coef;
                }
            }
        }
        // The unnamed directions of T: the null space of [S; C_T] (rows of Vᵀ past the rank).
        let named_rows = DMatrix::from_fn(m, 2 * N, |r, c| self.jacobian[(chosen[r], c)]);
        let jnorm = self.jacobian.norm().max(1.0);
        let mut worst = (0.0_f64, 0usize);
        for (k, s) in svd.singular_values.iter().enumerate() {
            if *s > RANK_TOL * top {
                continue;
            }
            let dir = v_t.row(k).transpose();
            let drive = (&named_rows * &dir).norm();
            if drive > worst.0 {
                // The coordinate or speed this direction moves most.
                let (arg, _) = dir.iter().enumerate().fold((0, 0.0_f64), |b, (i, x)| {
                    if x.abs() > b.1 { (i, x.abs()) } else { b }
                });
                worst = (drive, arg);
            }
        }
        if worst.0 > 1e-8 * jnorm {
            let name = if worst.1 < N {
                format!("coordinate \"{}\"", self.names[worst.1])
            } else {
                format!("the speed of \"{}\"", self.names[worst.1 - N])
            };
            return Err(LinearizationError::Reduction {
                message: format!(
                    "the named coordinates {coordinates:?} and speeds {speeds:?} do not close: \
                     {name}, not named, drives them (by {:.3e} of ‖J‖); name it too",
                    worst.0 / jnorm
                ),
            });
        }
        Ok(&named_rows * &lift)
    }

    /// The eigenvalues of [`state_matrix`](Self::state_matrix), sorted by decreasing real part.
    ///
    /// ```
    /// # use lagrange_runtime::{Holonomic, Lagrangian, LinearizeConstrained, Scalar};
    /// # struct P;
    /// # impl Lagrangian<2> for P {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81 }
    /// # }
    /// # impl Holonomic<2, 1> for P {
    /// #     const SCLERONOMIC: bool = true;
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 4.0] }
    /// # }
    /// // At the top, in x: λ = ±√(g/l).
    /// let lin = P.linearize_on_constraints(&[0.0, 2.0], &[0.0, 0.0], 0.0).unwrap();
    /// let l = lin.eigenvalues(&["x"], &["x"]).unwrap();
    /// assert!((l[0].re - (9.81_f64 / 2.0).sqrt()).abs() < 1e-12);
    /// ```
    pub fn eigenvalues(
        &self,
        coordinates: &[&str],
        speeds: &[&str],
    ) -> Result<Vec<Complex<f64>>, LinearizationError> {
        eigenvalues_of(self.state_matrix(coordinates, speeds)?)
    }

    /// M, C and K in the named coordinates (their rates the speeds): M the mass matrix of the
    /// named speeds (of the admissible motion with the least kinetic energy, unnamed speeds
    /// free), C and K from the reduced state matrix [[0, I], [−M⁻¹K, −M⁻¹C]]; the eigenvalues,
    /// modes and stability are those of [`Linearization`].
    ///
    /// ```
    /// # use lagrange_runtime::{Holonomic, Lagrangian, LinearizeConstrained, Scalar};
    /// # struct P;
    /// # impl Lagrangian<2> for P {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81 }
    /// # }
    /// # impl Holonomic<2, 1> for P {
    /// #     const SCLERONOMIC: bool = true;
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 4.0] }
    /// # }
    /// let lin = P.linearize_on_constraints(&[0.0, -2.0], &[0.0, 0.0], 0.0).unwrap();
    /// let r = lin.reduce(["x"]).unwrap();
    /// assert!((r.m[(0, 0)] - 1.0).abs() < 1e-12 && (r.k[(0, 0)] - 9.81 / 2.0).abs() < 1e-12);
    /// assert!(r.is_stable());
    /// ```
    pub fn reduce<const P: usize>(
        &self,
        coordinates: [&str; P],
    ) -> Result<Linearization<P>, LinearizationError> {
        let a = self.state_matrix(&coordinates, &coordinates)?;
        let vs = self.named_speed_motions(&coordinates)?;
        let m = SMatrix::<f64, P, P>::from_fn(|r, c| {
            let mut s = 0.0;
            for i in 0..N {
                for k in 0..N {
                    s += vs[r][i] * self.mass[(i, k)] * vs[c][k];
                }
            }
            s
        });
        // A = [[0, I], [X, Y]]: K = −M X, C = −M Y.
        let x = SMatrix::<f64, P, P>::from_fn(|r, c| a[(P + r, c)]);
        let y = SMatrix::<f64, P, P>::from_fn(|r, c| a[(P + r, P + c)]);
        Ok(Linearization::new(m, -(m * y), -(m * x)))
    }

    /// The input matrix of [`reduce`](Self::reduce)'s M q̈ + C q̇ + K q = B_r u from the full
    /// one, `b` (of M δq̈ + … = b δu in all coordinates, e.g. from
    /// [`input_matrix`](crate::linearize::input_matrix)): each input's generalized force on the
    /// least-kinetic-energy admissible motion of each named speed, B_r = Vᵀ b (the constraint
    /// forces do no work on admissible motions, so they drop out).
    ///
    /// ```
    /// # use lagrange_runtime::{Holonomic, Lagrangian, LinearizeConstrained, Scalar, SMatrix};
    /// # struct P;
    /// # impl Lagrangian<2> for P {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81 }
    /// # }
    /// # impl Holonomic<2, 1> for P {
    /// #     const SCLERONOMIC: bool = true;
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 4.0] }
    /// # }
    /// // A horizontal push on the hanging bob acts fully on x; a vertical one not at all.
    /// let lin = P.linearize_on_constraints(&[0.0, -2.0], &[0.0, 0.0], 0.0).unwrap();
    /// let b = lin.reduce_inputs(["x"], &SMatrix::<f64, 2, 2>::identity()).unwrap();
    /// assert!((b[(0, 0)] - 1.0).abs() < 1e-15 && b[(0, 1)].abs() < 1e-15);
    /// ```
    pub fn reduce_inputs<const P: usize, const U: usize>(
        &self,
        coordinates: [&str; P],
        b: &SMatrix<f64, N, U>,
    ) -> Result<SMatrix<f64, P, U>, LinearizationError> {
        let vs = self.named_speed_motions(&coordinates)?;
        Ok(SMatrix::<f64, P, U>::from_fn(|r, c| {
            (0..N).map(|i| vs[r][i] * b[(i, c)]).sum()
        }))
    }

    /// For each named speed, the least-kinetic-energy admissible velocity with that speed 1 and
    /// the other named ones 0: min vᵀMv subject to [G; A] v = 0 and v_named = e_i.
    fn named_speed_motions<const P: usize>(
        &self,
        coordinates: &[&str; P],
    ) -> Result<[[f64; N]; P], LinearizationError> {
        let mut idx = [0usize; P];
        for (i, c) in coordinates.iter().enumerate() {
            idx[i] = self.index(c)?;
        }
        let kr = self.velocity_rows.nrows();
        let n = N + kr + P;
        let mut vs = [[0.0; N]; P];
        let scale = self.mass.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for (col, v) in vs.iter_mut().enumerate() {
            let mut kkt = vec![0.0; n * n];
            for i in 0..N {
                for k in 0..N {
                    kkt[i * n + k] = self.mass[(i, k)];
                }
                for j in 0..kr {
                    kkt[i * n + N + j] = self.velocity_rows[(j, i)];
                    kkt[(N + j) * n + i] = self.velocity_rows[(j, i)];
                }
            }
            for (p, &i) in idx.iter().enumerate() {
                kkt[i * n + N + kr + p] = 1.0;
                kkt[(N + kr + p) * n + i] = 1.0;
            }
            let mut x = vec![0.0; n];
            x[N + kr + col] = 1.0;
            lu_solve_dyn(&mut kkt, &mut x, scale).map_err(|_| LinearizationError::Reduction {
                message: format!(
                    "no admissible motion moves only the named speeds {coordinates:?} (the \
                     velocity constraints fix them), or one without inertia"
                ),
            })?;
            v.copy_from_slice(&x[..N]);
        }
        Ok(vs)
    }
}

/// One constraint's derivatives in (q, q̇) at the reference: gradient, Hessian blocks (indexed
/// as the [`HessianJet`](crate::jet::HessianJet)'s: `hqv[(i, k)]` is ∂²c/∂qᵢ∂q̇ₖ) and the rate of
/// its q-block along (q̇₀, a₀, 1), on the heap whatever N.
struct Second {
    gq: Vec<f64>,
    gv: Vec<f64>,
    hqq: DMatrix<f64>,
    hqv: DMatrix<f64>,
    hvv: DMatrix<f64>,
    third_qq: DMatrix<f64>,
}

/// Every constraint's [`Second`] from one evaluation in [`LinJet`]s, or, `by_columns`, from 2N
/// evaluations in [`LinColumnJet`]s (the two paths side by side, for the test that compares them).
#[cfg(test)]
fn constraint_seconds<H, const N: usize, const K: usize>(
    sys: &H,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
    a0: &[f64; N],
    by_columns: bool,
) -> Vec<Second>
where
    H: Holonomic<N, K> + ?Sized,
{
    if by_columns {
        seconds_by_columns(sys, q, qdot, t, a0)
    } else {
        seconds_whole(sys, q, qdot, t, a0)
    }
}

/// Zeroed [`Second`]s for K constraints in N coordinates.
fn zero_seconds(n: usize, k: usize) -> Vec<Second> {
    (0..k)
        .map(|_| Second {
            gq: vec![0.0; n],
            gv: vec![0.0; n],
            hqq: DMatrix::zeros(n, n),
            hqv: DMatrix::zeros(n, n),
            hvv: DMatrix::zeros(n, n),
            third_qq: DMatrix::zeros(n, n),
        })
        .collect()
}

/// Every constraint's [`Second`] from 2N evaluations in [`LinColumnJet`]s (above
/// [`HESSIAN_BY_COLUMNS_ABOVE`](crate::jet::HESSIAN_BY_COLUMNS_ABOVE) coordinates: O(N) numbers
/// each on the stack instead of the [`LinJet`]'s O(N²)).
#[inline(never)]
fn seconds_by_columns<H, const N: usize, const K: usize>(
    sys: &H,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
    a0: &[f64; N],
) -> Vec<Second>
where
    H: Holonomic<N, K> + ?Sized,
{
    let mut out = zero_seconds(N, K);
    for col in 0..2 * N {
        let values = crate::jet::with_jet_stack(N, core::mem::size_of::<LinColumnJet<N>>(), || {
            let (qj, vj, tj) = LinColumnJet::seed_boxed(q, qdot, t, qdot, a0, 1.0, col);
            Box::new(sys.constraint_values(&qj, &vj, tj))
        });
        for (c, v) in out.iter_mut().zip(values.iter()) {
            let (b, d) = (v.base(), v.along());
            let (cq, cv, dq) = (b.column_q(), b.column_qdot(), d.column_q());
            if col == 0 {
                c.gq.copy_from_slice(&b.grad_q());
                c.gv.copy_from_slice(&b.grad_qdot());
            }
            for i in 0..N {
                if col < N {
                    // The column of q_col: ∂²c/∂qᵢ∂q_col and ∂²c/∂q̇ᵢ∂q_col.
                    c.hqq[(i, col)] = cq[i];
                    c.hqv[(col, i)] = cv[i];
                    c.third_qq[(i, col)] = dq[i];
                } else {
                    c.hvv[(i, col - N)] = cv[i];
                }
            }
        }
    }
    out
}

/// Every constraint's [`Second`] from one evaluation in [`LinJet`]s.
#[inline(never)]
fn seconds_whole<H, const N: usize, const K: usize>(
    sys: &H,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
    a0: &[f64; N],
) -> Vec<Second>
where
    H: Holonomic<N, K> + ?Sized,
{
    let mut out = zero_seconds(N, K);
    let (qj, vj, tj) = LinJet::seed(q, qdot, t, qdot, a0, 1.0);
    let values = sys.constraint_values(&qj, &vj, tj);
    for (c, v) in out.iter_mut().zip(values.iter()) {
        let (b, d) = (v.base(), v.along());
        c.gq.copy_from_slice(&b.grad_q());
        c.gv.copy_from_slice(&b.grad_qdot());
        let (hqq, hqv, hvv, third) = (b.hess_qq(), b.hess_qqdot(), b.hess_qdotqdot(), d.hess_qq());
        for i in 0..N {
            for k in 0..N {
                c.hqq[(i, k)] = hqq[i][k];
                c.hqv[(i, k)] = hqv[i][k];
                c.hvv[(i, k)] = hvv[i][k];
                c.third_qq[(i, k)] = third[i][k];
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::constraint_seconds;
    use crate::{Holonomic, Lagrangian, Scalar};

    /// Two coordinates, a curved holonomic constraint and a velocity constraint with a
    /// q-dependent A(q).
    struct Curved;
    impl Lagrangian<3> for Curved {
        const COORDINATES: [&'static str; 3] = ["x", "y", "z"];
        const CYCLIC: [bool; 3] = [false; 3];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, _q: &[S; 3], v: &[S; 3], _t: S) -> S {
            (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * 0.5
        }
    }
    impl Holonomic<3, 2> for Curved {
        const VELOCITY_ROWS: usize = 1;
        fn constraints<S: Scalar>(&self, q: &[S; 3], _t: S) -> [S; 2] {
            [q[0] * q[0] * q[1] + q[2].sin() - 1.0, S::constant(0.0)]
        }
        fn constraint_values<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], t: S) -> [S; 2] {
            let g = self.constraints(q, t)[0];
            [
                g,
                v[0] * q[2].cos() - v[1] * (q[0] * q[1]).exp() + v[2] * q[1],
            ]
        }
    }

    /// The constraints' second derivatives assembled column by column (the path of systems
    /// above 16 coordinates) equal the ones from whole Hessians, to round-off.
    #[test]
    fn columns_equal_the_whole_constraint_hessians() {
        let (q, v, a0) = ([0.7, 1.1, -0.4], [0.3, -0.9, 1.2], [0.2, 0.5, -0.6]);
        let whole = constraint_seconds(&Curved, &q, &v, 0.0, &a0, false);
        let cols = constraint_seconds(&Curved, &q, &v, 0.0, &a0, true);
        let close = |a: &[f64], b: &[f64]| {
            a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-14 * x.abs().max(1.0))
        };
        for (w, c) in whole.iter().zip(&cols) {
            assert!(close(&w.gq, &c.gq) && close(&w.gv, &c.gv));
            assert!(
                close(w.hqq.as_slice(), c.hqq.as_slice()),
                "{} {}",
                w.hqq,
                c.hqq
            );
            assert!(
                close(w.hqv.as_slice(), c.hqv.as_slice()),
                "{} {}",
                w.hqv,
                c.hqv
            );
            assert!(
                close(w.hvv.as_slice(), c.hvv.as_slice()),
                "{} {}",
                w.hvv,
                c.hvv
            );
            assert!(close(w.third_qq.as_slice(), c.third_qq.as_slice()));
            assert!(w.hqq.iter().any(|x| *x != 0.0) && w.third_qq.iter().any(|x| *x != 0.0));
        }
        assert!(whole[1].hqv.iter().any(|x| *x != 0.0));
    }
}
