//! What a constrained run asks of its constraints besides the accelerations: projecting a state
//! back onto g = 0 and ġ = 0, the multipliers and residuals at the samples, and the constraint
//! rows (with K known only at run time) for the constrained implicit step.
//!
//! The driver sees the constraints through the object-safe [`Manifold`] (K erased), so one
//! driver serves constrained and unconstrained runs.

use crate::constraints::{Constrained, Holonomic};
use crate::linalg::{SolveFailure, least_norm_symmetric, lu_solve_dyn, solve_symmetric};

use super::newton::inf_norm;
use super::state::{Fault, Y};

/// At most this many Newton iterations when projecting positions onto g(q, t) = 0.
const MAX_PROJECTION: usize = 10;

/// The constraint rows at one point with K known at run time: g, G (one row per constraint) and
/// ġ = G q̇ + ∂g/∂t.
pub(crate) struct Rows<const N: usize> {
    pub(crate) value: Vec<f64>,
    pub(crate) jacobian: Vec<[f64; N]>,
    pub(crate) rate: Vec<f64>,
}

/// The constraints of a run, K erased.
pub(crate) trait Manifold<const N: usize> {
    /// The number of constraints K.
    fn count(&self) -> usize;
    /// The rows at (q, q̇, t).
    fn rows(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Rows<N>;
    /// λ at a state (from the constrained accelerations).
    fn multipliers(&self, t: f64, y: &Y<N>) -> Result<Vec<f64>, Fault>;

    /// Projects y onto the constraints: q onto g(q, t) = 0 by Newton's method along the rows of
    /// G (the nearest point in the Euclidean norm of q), then q̇ onto G q̇ + ∂g/∂t = 0
    /// (the nearest velocity, one linear solve). Returns the size |Δq|∞ of the position
    /// correction.
    fn project(&self, t: f64, y: &mut Y<N>) -> Result<f64, Fault>;

    /// The largest |g| and |ġ| at a state.
    fn residual(&self, t: f64, y: &Y<N>) -> (f64, f64);

    /// How many of the rows (the last ones) are velocity constraints A q̇ + b = 0, which have
    /// no position part (zero for holonomic constraints and contacts).
    fn velocity_rows(&self) -> usize {
        0
    }
}

/// The least-norm Δ = Gᵀ(GGᵀ)⁻¹ r of G Δ = r, with the number of rows known at run time.
pub(crate) fn least_norm_dyn<const N: usize>(
    g: &[[f64; N]],
    r: &[f64],
    reason: &'static str,
) -> Result<[f64; N], Fault> {
    let k = g.len();
    let mut ggt = vec![0.0; k * k];
    let mut big = 0.0_f64;
    for a in 0..k {
        for b in 0..k {
            ggt[a * k + b] = (0..N).map(|i| g[a][i] * g[b][i]).sum();
            big = big.max(ggt[a * k + b].abs());
        }
    }
    let mut mu = r.to_vec();
    if lu_solve_dyn(&mut ggt, &mut mu, big).is_err() {
        // Redundant rows: the least-squares correction of least norm (G Gᵀ from the rows again:
        // the LU worked in place).
        let gram = |a: usize, b: usize| (0..N).map(|i| g[a][i] * g[b][i]).sum::<f64>();
        mu = least_norm_symmetric(k, gram, r)
            .ok_or(Fault::Newton {
                iterations: 0,
                residual: r.iter().fold(0.0_f64, |m, x| m.max(x.abs())),
                reason,
            })?
            .x;
    }
    let mut d = [0.0; N];
    for a in 0..k {
        for i in 0..N {
            d[i] += g[a][i] * mu[a];
        }
    }
    Ok(d)
}

/// The least-norm solution Δ = Gᵀ(GGᵀ)⁻¹ r of G Δ = r. Its failure's reason, like the
/// projection's, begins with [`PROJECTION`](super::error::PROJECTION).
fn least_norm<const N: usize, const K: usize>(
    g: &[[f64; N]; K],
    r: &[f64; K],
) -> Result<[f64; N], Fault> {
    let mut ggt = [[0.0; K]; K];
    for a in 0..K {
        for b in a..K {
            ggt[a][b] = (0..N).map(|i| g[a][i] * g[b][i]).sum();
        }
    }
    let mu = match solve_symmetric(&ggt, r) {
        Ok(mu) => mu,
        Err(SolveFailure::NonFinite) => return Err(Fault::NonFinite),
        // Redundant rows (one constraint repeats the others, everywhere or here): the
        // least-squares correction of least norm, which Newton's iteration takes to the
        // constraints as it does for independent rows.
        Err(SolveFailure::Singular { .. }) => {
            let sol = least_norm_symmetric(K, |a, b| ggt[a][b], r).ok_or(Fault::Newton {
                iterations: 0,
                residual: r.iter().fold(0.0_f64, |m, x| m.max(x.abs())),
                reason: "projecting onto the constraints: their gradients vanish here",
            })?;
            core::array::from_fn(|j| sol.x[j])
        }
    };
    let mut d = [0.0; N];
    for a in 0..K {
        for i in 0..N {
            d[i] += g[a][i] * mu[a];
        }
    }
    Ok(d)
}

impl<H: Holonomic<N, K>, const N: usize, const K: usize> Manifold<N> for Constrained<'_, H, N, K> {
    fn count(&self) -> usize {
        K
    }
    fn rows(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Rows<N> {
        let r = self.system().constraint_rows(q, qdot, t);
        Rows {
            value: r.value.to_vec(),
            jacobian: r.jacobian.to_vec(),
            rate: r.rate.to_vec(),
        }
    }
    fn project(&self, t: f64, y: &mut Y<N>) -> Result<f64, Fault> {
        let sys = self.system();
        let zero = [0.0; N];
        let mut moved = 0.0_f64;
        let mut converged = false;
        let mut residual = f64::NAN;
        let mut previous = f64::INFINITY;
        for _ in 0..MAX_PROJECTION {
            let rows = sys.constraint_rows(&y[0], &zero, t);
            residual = rows.value.iter().fold(0.0_f64, |m, g| m.max(g.abs()));
            if residual == 0.0 {
                converged = true;
                break;
            }
            // Newton stalls only at round-off: a residual that no longer halves, and is below
            // 1e-12 of |G| times the size of q (at least 1), is g's own rounding (coordinates
            // near zero make the step test below unreachable).
            let gradient = rows
                .jacobian
                .iter()
                .flatten()
                .fold(0.0_f64, |m, x| m.max(x.abs()));
            if residual > 0.5 * previous && residual <= 1e-12 * gradient * inf_norm(&y[0]).max(1.0)
            {
                converged = true;
                break;
            }
            previous = residual;
            // Velocity constraints (the last VELOCITY_ROWS rows) have no position part: q moves
            // along the holonomic rows only.
            let held = K - H::VELOCITY_ROWS;
            let dq = if H::VELOCITY_ROWS == 0 {
                least_norm(&rows.jacobian, &rows.value)?
            } else {
                least_norm_dyn(
                    &rows.jacobian[..held],
                    &rows.value[..held],
                    "projecting onto the holonomic constraints: their gradients are dependent \
                     or vanish here (one constraint repeats the others)",
                )?
            };
            for i in 0..N {
                y[0][i] -= dq[i];
                moved = moved.max(dq[i].abs());
            }
            if !y[0].iter().all(|x| x.is_finite()) {
                return Err(Fault::NonFinite);
            }
            if inf_norm(&dq) <= 4.0 * f64::EPSILON * inf_norm(&y[0]) {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(Fault::Newton {
                iterations: MAX_PROJECTION,
                residual,
                reason: "projecting the state back onto the constraints g(q, t) = 0 did not \
                         converge (the constraints may have no solution near this state, or the \
                         step was too large: try a tighter tolerance or a smaller step)",
            });
        }
        let rows = sys.constraint_rows(&y[0], &y[1], t);
        let dv = least_norm(&rows.jacobian, &rows.rate)?;
        for i in 0..N {
            y[1][i] -= dv[i];
        }
        Ok(moved)
    }
    fn residual(&self, t: f64, y: &Y<N>) -> (f64, f64) {
        let rows = self.system().constraint_rows(&y[0], &y[1], t);
        let max = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        (max(&rows.value), max(&rows.rate))
    }
    fn multipliers(&self, t: f64, y: &Y<N>) -> Result<Vec<f64>, Fault> {
        let (_, lambda) = self.system().constrained_accelerations(&y[0], &y[1], t)?;
        Ok(lambda.to_vec())
    }
    fn velocity_rows(&self) -> usize {
        H::VELOCITY_ROWS
    }
}
