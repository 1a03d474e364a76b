//! Stiffness diagnosis: when an explicit method runs out of steps or blows up, whether a fast
//! mode of the system is the reason, from the eigenvalues of the linearization at the last good
//! state. The error then says so, with the mode's frequency, the step it forced, and what helps
//! (an implicit method: Radau5 first), instead of advising looser tolerances, which do not move a step that
//! stability bounds.

use core::fmt;

use super::method::Method;
use super::state::Y;

/// The spread of the spectrum above which the system counts as stiff: the fastest mode at least
/// this many times faster than the slowest non-static one.
pub const STIFF_RATIO: f64 = 100.0;

/// What a run that ran out of steps or blew up learned about the system's fastest motion, from
/// the eigenvalues λ of its linearization at the last good state.
///
/// ```
/// use lagrange_runtime::integrate::Stiffness;
/// let s = Stiffness { omega_max: 1.0e4, omega_min: Some(0.7), h: 7.0e-5, limit: None };
/// let m = s.to_string();
/// // The adaptive implicit method first, the variational one second.
/// let (radau, variational) = (m.find("Method::Radau5").unwrap(), m.find("VariationalMidpoint").unwrap());
/// assert!(radau < variational);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Stiffness {
    /// The largest |λ| (rad per unit time): the fastest mode.
    pub omega_max: f64,
    /// The smallest |λ| above 1e-9 ω_max, where there is one: the slowest mode.
    pub omega_min: Option<f64>,
    /// The step: `dt` of a fixed-step method, the average accepted step of an adaptive run.
    pub h: f64,
    /// The method's stability limit on h·ω_max, for a fixed step that exceeded it (RK4: 2√2).
    pub limit: Option<f64>,
}

impl fmt::Display for Stiffness {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let w = self.omega_max;
        let implicit = "Method::Radau5 { rtol, atol } (implicit, L-stable and adaptive: its \
                        steps follow the slow motion while the fast mode is damped out, not \
                        resolved), or Method::VariationalMidpoint { dt } (implicit and A-stable: \
                        stable at any dt, with dt chosen for the slow motion; the fast mode is then \
                        not resolved)";
        match self.limit {
            Some(limit) => write!(
                f,
                "The fixed step dt = {h:.3e} is above the stability limit of the method for the \
                 fastest mode of the system (ω_max = {w:.4e} rad per unit time, from the \
                 linearization at the run's start): dt·ω_max = {hw:.3} > {limit:.3}, so each step \
                 amplifies that mode until it overflows. Try: dt < {max:.3e}, or {implicit}.",
                h = self.h,
                hw = self.h * w,
                max = limit / w,
            ),
            None => {
                let slow = self.omega_min.map_or(String::new(), |m| {
                    format!(" while the slowest is {m:.4e} ({:.0}× slower)", w / m)
                });
                write!(
                    f,
                    "The system is stiff: its fastest mode has ω_max = {w:.4e} rad per unit time \
                     (period {p:.3e}){slow}, and the average step h = {h:.3e} (h·ω_max = {hw:.3}) \
                     is set by that mode, not by the tolerances: loosening them does not make an \
                     explicit method take longer steps. Try: {implicit}, or raise .max_steps() \
                     (this rate takes about {per:.0} steps per unit time).",
                    p = 2.0 * core::f64::consts::PI / w,
                    h = self.h,
                    hw = self.h * w,
                    per = 1.0 / self.h,
                )
            }
        }
    }
}

/// Why an explicit run stopped, where a fast mode explains it: `blew_up` for a run whose state
/// or dynamics went non-finite (a fixed step above RK4's limit; `(t, y)` is then the run's first
/// state), else a run out of steps at `(t, y)` (an adaptive run on a stiff system), `steps`
/// accepted steps after `t0`. `None` for the implicit method, a
/// constrained run, or where the linearization fails.
#[allow(clippy::too_many_arguments)]
pub(crate) fn diagnose<const N: usize>(
    sys: &dyn super::system::System<N>,
    method: Method,
    constrained: bool,
    t0: f64,
    t: f64,
    y: &Y<N>,
    steps: usize,
    blew_up: bool,
) -> Option<Stiffness> {
    if constrained || !y.iter().flatten().all(|x| x.is_finite()) {
        return None;
    }
    // The explicit methods' steps are bounded by the fastest mode; an implicit one's are not.
    let spec = method.spec();
    if !spec.explicit {
        return None;
    }
    let (fixed, limit) = (spec.fixed_dt, spec.stability_limit);
    let sizes = sys.mode_sizes(&y[0], &y[1], t)?;
    let omega_max = sizes.iter().copied().fold(0.0, f64::max);
    if !(omega_max.is_finite() && omega_max > 0.0) {
        return None;
    }
    let omega_min = sizes
        .iter()
        .copied()
        .filter(|&m| m > 1e-9 * omega_max)
        .fold(None, |a: Option<f64>, m| Some(a.map_or(m, |a| a.min(m))));
    match (blew_up, fixed, limit) {
        // A fixed step above the limit blew the state up.
        (true, Some(dt), Some(limit)) if dt * omega_max > limit => Some(Stiffness {
            omega_max,
            omega_min,
            h: dt,
            limit: Some(limit),
        }),
        // An adaptive run out of steps whose steps resolve a mode far faster than the slowest.
        (false, None, _) => {
            let h = (t - t0) / steps.max(1) as f64;
            let stiff = omega_min.is_some_and(|m| omega_max >= STIFF_RATIO * m);
            (stiff && h * omega_max >= 0.05).then_some(Stiffness {
                omega_max,
                omega_min,
                h,
                limit: None,
            })
        }
        _ => None,
    }
}
