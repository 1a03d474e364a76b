//! Shared machinery of the explicit Runge–Kutta methods: the first-order state y = (q, q̇), the
//! right-hand side, linear combinations of stages, the weighted error norm, Hairer's initial step
//! and the PI step-size controller.

use crate::error::DynamicsError;
use crate::lagrangian::Lagrangian;

use super::trajectory::Stats;

/// The first-order state y = (q, q̇): `y[0]` = q, `y[1]` = q̇.
pub(crate) type Y<const N: usize> = [[f64; N]; 2];

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
pub(crate) fn rhs<L: Lagrangian<N> + ?Sized, const N: usize>(
    sys: &L,
    t: f64,
    y: &Y<N>,
    stats: &mut Stats,
) -> Result<Y<N>, DynamicsError> {
    stats.rhs_evals += 1;
    let a = sys.accelerations(&y[0], &y[1], t)?;
    Ok([y[1], a])
}

/// Evaluates the listed stages of the tableau `(A, C)` into `k`, unrolled so that each stage's
/// sum has a constant length: `k[s] = f(t + C[s] h, y + h Σ_{j<s} A[s][j] k[j])`, returning the
/// fault of a failing right-hand side from the enclosing function.
///
/// The stage positions of cyclic coordinates are not formed (see [`hold_cyclic`]).
macro_rules! stages {
    (($a:ident, $c:ident), $sys:ident, $t:ident, $y:ident, $h:ident, $k:ident, $stats:ident;
     $($s:literal)*) => {$(
        let mut ys = $crate::integrate::tableau::combine::<$s, _, _, _>($y, $h, &$a[$s], $k);
        $crate::integrate::tableau::hold_cyclic($sys, $y, &mut ys);
        $k[$s] = $crate::integrate::tableau::rhs($sys, $t + $c[$s] * $h, &ys, $stats)?;
    )*};
}
pub(crate) use stages;

/// Sets the stage positions of the cyclic coordinates back to the step's start.
///
/// q̈ does not depend on a coordinate absent from L, and a stage's position enters nothing but the
/// right-hand side (its slope in q is the stage velocity, formed in full), so these positions
/// need not be formed: after inlining, their sums are dead code (−3.5 % of a heavy-top DOP853 run,
/// where 2 of 3 coordinates are cyclic). y₁ and the error estimate still integrate every
/// position. `Simulation::run` checks the declaration before the first step.
#[inline(always)]
pub(crate) fn hold_cyclic<L: Lagrangian<N> + ?Sized, const N: usize>(
    _sys: &L,
    y: &Y<N>,
    ys: &mut Y<N>,
) {
    let cyclic: [bool; N] = const { L::CYCLIC };
    let held: [f64; N] = core::array::from_fn(|i| if cyclic[i] { y[0][i] } else { ys[0][i] });
    ys[0] = held;
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
pub(crate) fn combine<const S: usize, const N: usize, const R: usize, const K: usize>(
    y: &Y<N>,
    h: f64,
    a: &[f64; R],
    k: &[Y<N>; K],
) -> Y<N> {
    const { assert!(S >= 1 && S <= R && S <= K) };
    let mut last = S - 1;
    while last > 0 && a[last] == 0.0 {
        last -= 1;
    }
    let mut base = *y;
    if last > 0 {
        let w = weighted_to(last, a, k);
        for r in 0..2 {
            for i in 0..N {
                base[r][i] += h * w[r][i];
            }
        }
    }
    let hl = h * a[last];
    let mut out = [[0.0; N]; 2];
    for r in 0..2 {
        for i in 0..N {
            out[r][i] = base[r][i] + hl * k[last][r][i];
        }
    }
    out
}

/// Σ_{j<S} a_j k_j (no base, no h).
#[inline(always)]
pub(crate) fn weighted<const S: usize, const N: usize, const R: usize, const K: usize>(
    a: &[f64; R],
    k: &[Y<N>; K],
) -> Y<N> {
    const { assert!(S >= 1 && S <= R && S <= K) };
    weighted_to(S, a, k)
}

/// Σ_{j<s} a_j k_j for 1 ≤ s ≤ min(R, K); `s` is a constant after inlining.
#[inline(always)]
fn weighted_to<const N: usize, const R: usize, const K: usize>(
    s: usize,
    a: &[f64; R],
    k: &[Y<N>; K],
) -> Y<N> {
    let mut w = [[0.0; N]; 2];
    for r in 0..2 {
        for i in 0..N {
            w[r][i] = a[0] * k[0][r][i];
        }
    }
    for j in 1..s {
        // The tableaux are constants and s is too: after inlining this test is decided at
        // compile time, so the zeros of the tableau cost nothing.
        if a[j] == 0.0 {
            continue;
        }
        for r in 0..2 {
            for i in 0..N {
                w[r][i] += a[j] * k[j][r][i];
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

/// The error weights sk = atol + rtol · max(|y|, |y_new|), per component.
#[inline(always)]
pub(crate) fn scales<const N: usize>(rtol: f64, atol: f64, y: &Y<N>, y_new: &Y<N>) -> Y<N> {
    let mut s = [[0.0; N]; 2];
    for r in 0..2 {
        for i in 0..N {
            s[r][i] = atol + rtol * y[r][i].abs().max(y_new[r][i].abs());
        }
    }
    s
}

/// Σ (e_i / sk_i)² over all 2N components (the q and q̇ halves added pairwise first, so the
/// serial chain of additions is N long, not 2N: the sum is on the critical path between steps).
#[inline(always)]
pub(crate) fn sum_sq<const N: usize>(e: &Y<N>, sk: &Y<N>) -> f64 {
    let mut s = 0.0;
    for i in 0..N {
        let (a, b) = (e[0][i] / sk[0][i], e[1][i] / sk[1][i]);
        s += a * a + b * b;
    }
    s
}

/// Hairer's starting step (`hinit` of `dopri5.f`/`dop853.f`) for a method of order `order`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<L: Lagrangian<N> + ?Sized, const N: usize>(
    sys: &L,
    t: f64,
    y: &Y<N>,
    f0: &Y<N>,
    order: i32,
    rtol: f64,
    atol: f64,
    hmax: f64,
    stats: &mut Stats,
) -> Result<f64, DynamicsError> {
    let sk = scales(rtol, atol, y, y);
    let dnf = sum_sq(f0, &sk);
    let dny = sum_sq(y, &sk);
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(hmax);
    let y1 = combine::<1, _, _, _>(y, h, &[1.0], &[*f0]);
    let f1 = rhs(sys, t + h, &y1, stats)?;
    let mut d = [[0.0; N]; 2];
    for r in 0..2 {
        for i in 0..N {
            d[r][i] = f1[r][i] - f0[r][i];
        }
    }
    let der2 = sum_sq(&d, &sk).sqrt() / h;
    let der12 = der2.abs().max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(1.0 / f64::from(order))
    };
    Ok((100.0 * h).min(h1).min(hmax))
}

/// ln 10⁻⁴: the floor of err_old in the PI term (Hairer's `facold = max(err, 1e-4)`).
const LN_FACOLD_MIN: f64 = -9.210_340_371_976_182;

/// Hairer's PI step-size controller (Lund stabilisation, section IV.2 of Hairer & Wanner):
/// h_new = h · safe · err^(−expo1) · err_old^β, the factor h_new / h clamped to [fac_min, fac_max].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Controller {
    safe: f64,
    /// The smallest factor h_new / h.
    fac_min: f64,
    /// The largest factor h_new / h.
    fac_max: f64,
    expo1: f64,
    beta: f64,
    /// ln of the previous accepted error (floored at 10⁻⁴): the PI term needs err_old^β.
    ln_facold: f64,
}

impl Controller {
    /// A controller for an error estimate of order `q_err + 1` in h (expo1 = 1/(q_err+1) − β·γ).
    pub(crate) fn new(expo1: f64, beta: f64, fac_min: f64, fac_max: f64) -> Self {
        Controller {
            safe: 0.9,
            fac_min,
            fac_max,
            expo1,
            beta,
            ln_facold: LN_FACOLD_MIN,
        }
    }

    /// The next step after an accepted step with error norm err = exp(`ln_err`) ≤ 1.
    ///
    /// The controller works on ln err: the methods produce it from logarithms of their error
    /// sums, which keeps a division and a square root off the critical path between steps.
    pub(crate) fn accepted(&mut self, h: f64, ln_err: f64, rejected_last: bool) -> f64 {
        // h / clamp(err^expo1 / err_old^β / safe) as h · clamp(safe · exp(β ln err_old − expo1
        // ln err)): one exp (instead of two powf, which were 4 % of a DOP853 run) and a
        // multiplication instead of a division.
        let g = self.safe * (self.beta * self.ln_facold - self.expo1 * ln_err).exp();
        let g = self.fac_min.max(self.fac_max.min(g));
        self.ln_facold = ln_err.max(LN_FACOLD_MIN);
        let h_new = h * g;
        if rejected_last {
            h_new.min(h)
        } else {
            h_new
        }
    }

    /// The retry step after a rejected step with error norm err = exp(`ln_err`) > 1.
    pub(crate) fn rejected(&self, h: f64, ln_err: f64) -> f64 {
        h * self.fac_min.max(self.safe * (-self.expo1 * ln_err).exp())
    }
}

/// The smallest step the adaptive methods accept at time t (Hairer: 0.1|h| ≤ |t|·uround).
#[inline]
pub(crate) fn too_small(h: f64, t: f64) -> bool {
    0.1 * h.abs() <= t.abs() * 2.3e-16 || h < 1e-300
}

/// Step-size bookkeeping shared by the adaptive methods (dopri5, dop853): the proposed step, the
/// PI controller, whether the last attempt was rejected and why the latest retry was needed.
#[derive(Debug)]
pub(crate) struct StepControl {
    h: f64,
    hmax: f64,
    ctrl: Controller,
    rejected_last: bool,
    /// The fault behind the latest forced shrink since the last accepted step: reported instead
    /// of a bare underflow when the step then becomes too small.
    last_failure: Option<Fault>,
}

impl StepControl {
    /// Starts with the proposed first step `h`, never exceeding `hmax`.
    pub(crate) fn new(h: f64, hmax: f64, ctrl: Controller) -> Self {
        StepControl {
            h,
            hmax,
            ctrl,
            rejected_last: false,
            last_failure: None,
        }
    }

    /// The next trial step from `t` and whether it ends exactly at `t_end` (a step within 1 % of
    /// the end is stretched to it); the fault that ends the run when the step has underflowed.
    pub(crate) fn trial(&mut self, t: f64, t_end: f64) -> Result<(f64, bool), Fault> {
        let h = self.h.min(self.hmax);
        let (h, last) = if t + 1.01 * h >= t_end {
            (t_end - t, true)
        } else {
            (h, false)
        };
        if too_small(h, t) {
            return Err(self.last_failure.take().unwrap_or(Fault::Underflow { h }));
        }
        Ok((h, last))
    }

    /// Records the accepted step `h` with error norm exp(`ln_err`) ≤ 1 and proposes the next one.
    pub(crate) fn accept(&mut self, h: f64, ln_err: f64, stats: &mut Stats) {
        stats.steps += 1;
        self.h = self.ctrl.accepted(h, ln_err, self.rejected_last);
        self.rejected_last = false;
        self.last_failure = None;
    }

    /// Records the rejected step `h` with error norm exp(`ln_err`) > 1 and proposes the retry; a
    /// non-finite estimate (ln err = +∞ or NaN) is a fault and shrinks the step (see `shrink`).
    pub(crate) fn reject(&mut self, h: f64, ln_err: f64, stats: &mut Stats) {
        if ln_err.is_nan() || ln_err == f64::INFINITY {
            return self.shrink(h, Fault::NonFinite, stats);
        }
        stats.rejected += 1;
        self.rejected_last = true;
        self.h = self.ctrl.rejected(h, ln_err);
    }

    /// Records the step `h` that failed with `fault` (non-finite error, or a stage outside the
    /// domain of the dynamics) and retries with a quarter of it.
    pub(crate) fn shrink(&mut self, h: f64, fault: Fault, stats: &mut Stats) {
        stats.rejected += 1;
        self.rejected_last = true;
        self.h = 0.25 * h;
        self.last_failure = Some(fault);
    }
}

#[cfg(test)]
mod controller_tests {
    use super::*;

    #[test]
    fn ln_facold_floor_is_ln_of_1e_minus_4() {
        assert_eq!(LN_FACOLD_MIN, 1e-4_f64.ln());
    }

    /// The logarithmic form of the PI factor equals Hairer's powf form to round-off.
    #[test]
    fn accepted_step_matches_the_powf_form() {
        let (expo1, beta) = (1.0 / 8.0 - 0.04 * 0.2, 0.04);
        let mut c = Controller::new(expo1, beta, 0.333, 6.0);
        let mut facold: f64 = 1e-4;
        for err in [0.3_f64, 0.9, 1e-6, 0.0, 0.5] {
            let h = c.accepted(0.01, err.ln(), false);
            let fac = err.powf(expo1) / facold.powf(beta);
            let fac = (1.0 / 6.0_f64).max((1.0 / 0.333_f64).min(fac / 0.9));
            facold = err.max(1e-4);
            let want = 0.01 / fac;
            assert!(
                (h - want).abs() <= 4.0 * f64::EPSILON * want,
                "err {err}: {h} vs {want}"
            );
        }
    }

    /// The retry factor after a rejection equals Hairer's h / min(1/fac_min, err^expo1 / safe).
    #[test]
    fn rejected_step_matches_the_powf_form() {
        let expo1 = 1.0 / 8.0 - 0.04 * 0.2;
        let c = Controller::new(expo1, 0.04, 0.333, 6.0);
        for err in [1.5_f64, 3.0, 1e3, 1e12] {
            let h = c.rejected(0.01, err.ln());
            let want = 0.01 / (1.0 / 0.333_f64).min(err.powf(expo1) / 0.9);
            assert!(
                (h - want).abs() <= 4.0 * f64::EPSILON * want,
                "err {err}: {h} vs {want}"
            );
        }
    }
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
            let got = combine::<4, _, _, _>(&y, h, a, &k);
            assert!(close(got, naive(&y, h, a, &k)), "row {a:?}: {got:?}");
        }
        // S shorter than the row: the later coefficients are ignored.
        let got = combine::<2, _, _, _>(&y, h, &rows[0], &k);
        assert!(close(got, naive(&y, h, &rows[0][..2], &k[..2])));
    }
}
