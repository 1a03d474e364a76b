//! Newton's method for the implicit methods: the caller gives the residual R(x) (with the sizes
//! its convergence is measured against) and the solve of the linearised equation for the
//! correction Δx; this module owns the iteration, the convergence tests, the counts in
//! [`Stats`] and the [`Fault::Newton`] report when the iteration does not converge.

use super::state::Fault;
use super::state::Stats;

/// At most this many Newton iterations per solve.
pub(crate) const MAX_NEWTON: usize = 30;

/// The largest absolute component.
#[inline]
pub(crate) fn inf_norm<const N: usize>(x: &[f64; N]) -> f64 {
    x.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// Adds a full Newton correction (Δx to x, Δν to the multipliers ν) and counts the iteration,
/// which formed the exact Jacobian and factorized it (the full Newton method of the variational
/// integrator and RATTLE); |Δx|∞.
pub(crate) fn corrected<const N: usize>(
    x: &mut [f64; N],
    dx: &[f64; N],
    nu: &mut [f64],
    dnu: &[f64],
    stats: &mut Stats,
) -> f64 {
    for i in 0..N {
        x[i] += dx[i];
    }
    for (n, d) in nu.iter_mut().zip(dnu) {
        *n += d;
    }
    stats.newton_iterations += 1;
    stats.jacobians += 1;
    stats.decompositions += 1;
    inf_norm(dx)
}

/// One evaluation of the residual at the current iterate x.
pub(crate) struct Residual<const N: usize, J> {
    /// R(x).
    pub(crate) r: [f64; N],
    /// The size of the terms that make up R: R has converged when |R|∞ ≤ 8ε · `scale`.
    pub(crate) scale: f64,
    /// The size of x: the iteration has converged when the last correction has
    /// |Δx|∞ ≤ 4ε · `x_scale`.
    pub(crate) x_scale: f64,
    /// What the correction needs (e.g. the Hessian jet) and what the caller keeps at
    /// convergence.
    pub(crate) data: J,
}

/// Solves R(x) = 0 from the initial guess in `x` by Newton's method, at most [`MAX_NEWTON`]
/// iterations.
///
/// Each iteration evaluates `residual(x, stats)` (which counts its own evaluations and returns
/// [`Fault::NonFinite`] itself where R or x is not finite); stops with success when
/// |R|∞ ≤ 8ε·scale or the previous correction was |Δx|∞ ≤ 4ε·x_scale; otherwise asks
/// `correction(x, residual, |R|∞, stats)` for Δx, adds it to x and counts one Newton iteration.
/// On success `x` holds the solution and the converged evaluation's `data` is returned; after
/// [`MAX_NEWTON`] corrections without convergence the result is [`Fault::Newton`] with the last
/// |R|∞ and `reason`.
#[inline]
pub(crate) fn solve<const N: usize, J>(
    x: &mut [f64; N],
    stats: &mut Stats,
    reason: &'static str,
    mut residual: impl FnMut(&[f64; N], &mut Stats) -> Result<Residual<N, J>, Fault>,
    mut correction: impl FnMut(&[f64; N], &Residual<N, J>, f64, &Stats) -> Result<[f64; N], Fault>,
) -> Result<J, Fault> {
    let mut last_dx = f64::INFINITY;
    let mut r_norm = f64::NAN;
    for _ in 0..MAX_NEWTON {
        let res = residual(x, stats)?;
        r_norm = inf_norm(&res.r);
        if r_norm <= 8.0 * f64::EPSILON * res.scale || last_dx <= 4.0 * f64::EPSILON * res.x_scale {
            return Ok(res.data);
        }
        let dx = correction(x, &res, r_norm, stats)?;
        last_dx = corrected(x, &dx, &mut [], &[], stats);
    }
    Err(Fault::Newton {
        iterations: MAX_NEWTON,
        residual: r_norm,
        reason,
    })
}
