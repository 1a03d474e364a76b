//! Step-size control of the adaptive methods (dopri5, dop853): the error weights and the weighted
//! error norm, Hairer's initial step, the PI controller and the per-run [`StepControl`].

use crate::error::DynamicsError;

use super::state::Stats;
use super::state::{Fault, Y, combine, rhs};

/// The absolute tolerance the error weights use: `atol`, or for `atol = 0` (pure relative
/// control) the smallest normal number, so that a component that is exactly zero with an exactly
/// zero error estimate (z ≡ 0 of a planar motion, φ = 0 at the start) weighs 0/tiny = 0 instead of
/// 0/0 = NaN, while a zero component with a non-zero error still counts as an infinite relative
/// error. Applied once when a run starts: the step itself is unchanged.
pub(crate) fn effective_atol(atol: f64) -> f64 {
    if atol == 0.0 { f64::MIN_POSITIVE } else { atol }
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

/// √(Σ (e_i / sk_i)²) over all 2N components without overflow or underflow of the squares: the
/// ratios are scaled by their largest magnitude first (a force of 1e150 over weights of 1e-10
/// would square to 1e320 = ∞).
fn scaled_norm<const N: usize>(e: &Y<N>, sk: &Y<N>) -> f64 {
    let mut m = 0.0_f64;
    for r in 0..2 {
        for i in 0..N {
            m = m.max((e[r][i] / sk[r][i]).abs());
        }
    }
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    let mut s = 0.0;
    for r in 0..2 {
        for i in 0..N {
            let x = e[r][i] / sk[r][i] / m;
            s += x * x;
        }
    }
    m * s.sqrt()
}

/// The starting step when the estimate is not a positive finite number (an overflowing or
/// non-finite norm): small, and the controller grows or shrinks it from there.
const FALLBACK_STEP: f64 = 1e-6;

/// Hairer's starting step (`hinit` of `dopri5.f`/`dop853.f`) for a method of order `order`,
/// with the norms computed scaled so that huge derivatives (a force of 1e150) give a tiny step,
/// not an overflow to a zero step; a step that still comes out zero or non-finite is
/// [`FALLBACK_STEP`] (at most `hmax`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<const N: usize>(
    sys: &dyn super::system::System<N>,
    t: f64,
    y: &Y<N>,
    f0: &Y<N>,
    order: i32,
    rtol: f64,
    atol: f64,
    hmax: f64,
    stats: &mut Stats,
) -> Result<f64, DynamicsError> {
    let mut sk = scales(rtol, atol, y, y);
    // Under a pure relative tolerance a component that starts at zero has no weight of its own:
    // for the starting step only, weigh it with the scale of the state (or 1).
    let floor = rtol
        * y.iter()
            .flatten()
            .fold(0.0_f64, |m, v| m.max(v.abs()))
            .max(1.0);
    for w in sk.iter_mut().flatten() {
        if *w < floor * f64::EPSILON {
            *w = floor;
        }
    }
    let usable = |h: f64| h > 0.0 && h.is_finite();
    // Hairer's sums of squares where they are finite (the same step, bit for bit, as before);
    // the scaled norms where a square overflowed.
    let norm = |e: &Y<N>| {
        let s = sum_sq(e, &sk);
        if s.is_finite() {
            s.sqrt()
        } else {
            scaled_norm(e, &sk)
        }
    };
    let (dnf2, dny2) = (sum_sq(f0, &sk), sum_sq(y, &sk));
    let dnf = norm(f0);
    let mut h = if dnf2.is_finite() && dny2.is_finite() {
        if dnf2 <= 1e-10 || dny2 <= 1e-10 {
            1e-6
        } else {
            (dny2 / dnf2).sqrt() * 0.01
        }
    } else {
        let dny = norm(y);
        if dnf <= 1e-5 || dny <= 1e-5 {
            1e-6
        } else {
            (dny / dnf) * 0.01
        }
    };
    if !usable(h) {
        h = FALLBACK_STEP;
    }
    h = h.min(hmax);
    let y1 = combine::<1, _, _, _, _>(y, h, &[1.0], &[*f0]);
    let f1 = rhs(sys, t + h, &y1, stats)?;
    let mut d = [[0.0; N]; 2];
    for r in 0..2 {
        for i in 0..N {
            d[r][i] = f1[r][i] - f0[r][i];
        }
    }
    let der2 = norm(&d) / h;
    let der12 = der2.abs().max(dnf);
    let h1 = if der12 <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(1.0 / f64::from(order))
    };
    // NaN compares false: a NaN h1 (an infinite der2) leaves 100 h.
    let h0 = (100.0 * h).min(h1).min(hmax);
    Ok(if usable(h0) { h0 } else { h.min(hmax) })
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
        // ln err)): one exp (instead of two powf, a visible share of a DOP853 run) and a
        // multiplication instead of a division.
        let g = self.safe * (self.beta * self.ln_facold - self.expo1 * ln_err).exp();
        let g = self.fac_min.max(self.fac_max.min(g));
        self.ln_facold = ln_err.max(LN_FACOLD_MIN);
        let h_new = h * g;
        if rejected_last { h_new.min(h) } else { h_new }
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
