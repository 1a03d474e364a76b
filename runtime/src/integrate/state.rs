//! What every method shares: the first-order state y = (q, q̇), the faults a stepper reports, the
//! right-hand side, and the linear combinations of stages of the explicit Runge–Kutta methods
//! (`combine`, `weighted`).

use crate::error::DynamicsError;

/// The first-order state y = (q, q̇): `y[0]` = q, `y[1]` = q̇.
pub(crate) type Y<const N: usize> = [[f64; N]; 2];

/// The state of several members side by side (`Y` over [`Lanes`](crate::lanes::Lanes)), or `Y`
/// itself for T = f64.
pub(crate) type YOf<T, const N: usize> = [[T; N]; 2];

/// The numbers the stage combinations run on: `f64`, and [`Lanes`](crate::lanes::Lanes) for
/// ensembles (every operation lane by lane, so each lane is the scalar computation bit for bit) —
/// the number trait of every compiled kernel.
pub(crate) use crate::real::Real;

/// Counters of a run.
///
/// For the explicit methods `rhs_evals` counts evaluations of the accelerations; for the
/// variational midpoint it counts evaluations of L in the Hessian jet (Newton residual and
/// Jacobian, and the inverse Legendre map at reported nodes); Radau5 counts the accelerations (3
/// per Newton iteration, 1 per accepted step, 1 more for a filtered error estimate).
///
/// ```
/// let s = lagrange_runtime::Stats::default();
/// assert_eq!((s.steps, s.rejected, s.rhs_evals, s.newton_iterations), (0, 0, 0, 0));
/// assert_eq!((s.jacobians, s.decompositions, s.newton_failures), (0, 0, 0));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected step attempts (adaptive methods).
    pub rejected: usize,
    /// Of the rejected attempts, those whose Newton iteration on the stage equations failed
    /// (Radau5: diverging, converging too slowly, or a singular Newton matrix) rather than the
    /// error test: where they dominate, the step is bounded by the problem's nonlinearity over
    /// a step, not by the accuracy asked.
    pub newton_failures: usize,
    /// Right-hand-side evaluations (see the type's documentation).
    pub rhs_evals: usize,
    /// Newton iterations (the implicit methods: variational midpoint, Radau5).
    pub newton_iterations: usize,
    /// Jacobians formed (the implicit methods: Radau5 forms one when Newton slows down or after
    /// a rejection; the variational methods one per Newton iteration).
    pub jacobians: usize,
    /// LU decompositions of the Newton matrix (Radau5: one per new step size or Jacobian, its
    /// two matrices I − hA⊗J and I − γhJ counted as one, as `radau5.f`'s NDEC; the variational
    /// methods one per Newton iteration).
    pub decompositions: usize,
}

/// Why a stepper could not go on (the driver adds t, the state and the partial trajectory).
#[derive(Debug)]
pub(crate) enum Fault {
    /// The dynamics failed at an accepted state (or every retry failed).
    Dynamics(DynamicsError),
    /// The adaptive step fell below the round-off limit.
    Underflow { h: f64 },
    /// The state became NaN or infinite.
    NonFinite,
    /// The step budget is used up.
    MaxSteps(usize),
    /// The stored samples reached `max_samples`.
    MaxSamples(usize),
    /// The implicit step (or the inverse Legendre map) did not converge.
    Newton {
        iterations: usize,
        residual: f64,
        reason: &'static str,
    },
}

impl From<DynamicsError> for Fault {
    fn from(e: DynamicsError) -> Self {
        Fault::Dynamics(e)
    }
}

/// f(t, y) = (q̇, q̈(q, q̇, t)), counted in `stats`.
#[inline(always)]
pub(crate) fn rhs<L: super::system::System<N> + ?Sized, const N: usize>(
    sys: &L,
    t: f64,
    y: &Y<N>,
    stats: &mut Stats,
) -> Result<Y<N>, DynamicsError> {
    stats.rhs_evals += 1;
    let a = sys.accelerations(&y[0], &y[1], t)?;
    Ok([y[1], a])
}

/// y + h Σ_{j<S} a_j k_j. `S` is a constant, so the loops unroll and the 2N components
/// vectorise; the rows of a tableau can be longer than S (padded with the later stages'
/// coefficients or zeros).
///
/// The newest stage (the last non-zero a_j) is added last, as (h a_j) k_j, to y + h Σ of the
/// others: every stage waits for the one before it, and this way only a multiplication and an
/// addition stand between k_j and the next right-hand side (the sum-first order of `dop853.f`
/// put four there).
///
/// Zero coefficients are skipped (a test decided at compile time: the tableaux are constants).
#[inline(always)]
pub(crate) fn combine<const S: usize, const N: usize, const R: usize, const K: usize, T: Real>(
    y: &YOf<T, N>,
    h: T,
    a: &[f64; R],
    k: &[YOf<T, N>; K],
) -> YOf<T, N> {
    const { assert!(S >= 1 && S <= R && S <= K) };
    combine_by(S, y, h, a, |j| &k[j])
}

/// [`combine`] with the terms k_j taken from `k` (a state's motion), for 1 ≤ s ≤ R (a constant
/// after inlining).
#[inline(always)]
pub(crate) fn combine_by<'k, const N: usize, const R: usize, T: Real + 'k>(
    s: usize,
    y: &YOf<T, N>,
    h: T,
    a: &[f64; R],
    k: impl Fn(usize) -> &'k YOf<T, N>,
) -> YOf<T, N> {
    let mut last = s - 1;
    while last > 0 && a[last] == 0.0 {
        last -= 1;
    }
    let mut base = *y;
    // Leading zeros skipped too (RK4's rows): the sum then starts at the first term.
    if a[..last].iter().any(|&aj| aj != 0.0) {
        let w = weighted_by(last, a, &k);
        for r in 0..2 {
            for i in 0..N {
                base[r][i] = h.madd(w[r][i], base[r][i]);
            }
        }
    }
    let hl = h * T::from(a[last]);
    let kl = k(last);
    let mut out = [[T::from(0.0); N]; 2];
    for r in 0..2 {
        for i in 0..N {
            out[r][i] = hl.madd(kl[r][i], base[r][i]);
        }
    }
    out
}

/// Σ_{j<S} a_j k_j (no base, no h).
#[inline(always)]
pub(crate) fn weighted<const S: usize, const N: usize, const R: usize, const K: usize, T: Real>(
    a: &[f64; R],
    k: &[YOf<T, N>; K],
) -> YOf<T, N> {
    const { assert!(S >= 1 && S <= R && S <= K) };
    weighted_to(S, a, k)
}

/// Σ_{j<s} a_j k_j for 1 ≤ s ≤ min(R, K); `s` is a constant after inlining.
#[inline(always)]
fn weighted_to<const N: usize, const R: usize, const K: usize, T: Real>(
    s: usize,
    a: &[f64; R],
    k: &[YOf<T, N>; K],
) -> YOf<T, N> {
    weighted_by(s, a, |j| &k[j])
}

/// Σ_{j<s} a_j k(j) for 1 ≤ s ≤ R, the terms taken from `k` (a state's motion: the tableaux'
/// error estimates over the motion of any state), from the first non-zero a_j on (a_0 k(0) if
/// every a_j is zero).
#[inline(always)]
pub(crate) fn weighted_by<'k, const N: usize, const R: usize, T: Real + 'k>(
    s: usize,
    a: &[f64; R],
    k: impl Fn(usize) -> &'k YOf<T, N>,
) -> YOf<T, N> {
    let mut first = 0;
    while first + 1 < s && a[first] == 0.0 {
        first += 1;
    }
    let mut w = [[T::from(0.0); N]; 2];
    let k0 = k(first);
    for r in 0..2 {
        for i in 0..N {
            w[r][i] = T::from(a[first]) * k0[r][i];
        }
    }
    for j in first + 1..s {
        // The tableaux are constants and s is too: after inlining this test is decided at
        // compile time, so the zeros of the tableau cost nothing.
        if a[j] == 0.0 {
            continue;
        }
        let kj = k(j);
        for r in 0..2 {
            for i in 0..N {
                w[r][i] = T::from(a[j]).madd(kj[r][i], w[r][i]);
            }
        }
    }
    w
}

/// Whether every component is finite.
#[inline(always)]
pub(crate) fn finite<const N: usize>(y: &Y<N>) -> bool {
    y.iter().flatten().all(|x| x.is_finite())
}

#[cfg(test)]
mod combine_tests {
    use super::*;

    /// y + h Σ a_j k_j written out, for comparison.
    fn naive<const N: usize>(y: &Y<N>, h: f64, a: &[f64], k: &[Y<N>]) -> Y<N> {
        let mut out = *y;
        for r in 0..2 {
            for i in 0..N {
                let s: f64 = a.iter().zip(k).map(|(aj, kj)| aj * kj[r][i]).sum();
                out[r][i] += h * s;
            }
        }
        out
    }

    /// The newest-stage-last order and the skipped zeros (inside the row, at its end, all but the
    /// first) agree with the plain sum to round-off.
    #[test]
    fn combine_agrees_with_the_plain_sum() {
        let k: [Y<2>; 4] = [
            [[1.0, -2.0], [0.5, 3.0]],
            [[0.25, 4.0], [-1.5, 2.0]],
            [[7.0, 0.125], [1.0, -0.75]],
            [[-3.0, 1.0], [2.5, 0.5]],
        ];
        let y = [[0.3, -0.7], [1.1, 2.2]];
        let h = 0.037;
        let rows: [[f64; 4]; 4] = [
            [0.2, 0.3, 0.5, -0.4],
            [0.2, 0.0, 0.5, 0.0],
            [0.2, 0.0, 0.0, 0.0],
            [0.0, 0.6, 0.0, 0.0],
        ];
        let close = |got: Y<2>, want: Y<2>| {
            got.iter()
                .flatten()
                .zip(want.iter().flatten())
                .all(|(g, w)| (g - w).abs() <= 4.0 * f64::EPSILON * w.abs().max(1.0))
        };
        for a in &rows {
            let got = combine::<4, _, _, _, _>(&y, h, a, &k);
            assert!(close(got, naive(&y, h, a, &k)), "row {a:?}: {got:?}");
        }
        // S shorter than the row: the later coefficients are ignored.
        let got = combine::<2, _, _, _, _>(&y, h, &rows[0], &k);
        assert!(close(got, naive(&y, h, &rows[0][..2], &k[..2])));
    }
}
