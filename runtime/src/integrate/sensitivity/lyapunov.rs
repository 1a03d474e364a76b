//! Lyapunov exponents of a motion by QR re-orthonormalization of the state transition matrix
//! (Benettin et al. 1980; Shimada & Nagashima 1979).
//!
//! k orthonormal directions Q₀ in general position (a fixed quasi-random basis: unit vectors
//! would stay in the invariant subspaces of a decoupled system and never find the largest
//! exponents) are carried by the variational equations, Φ(t) Q, together with the motion
//! (DOP853 over the augmented state). Every interval Δ — and sooner, after any step where the
//! directions' lengths have separated by more than a factor 100, so that their orthogonal parts
//! are not lost — the carried directions are factored W = Q R (modified Gram–Schmidt), the
//! logarithms ln R_ii are summed and the run goes on from Q. After time t the i-th exponent is
//! λ_i ≈ (1/t) Σ ln R_ii; the first k exponents, largest first, come out (k = 2N: the whole
//! spectrum, whose sum is the mean of tr J, −⟨tr M⁻¹C⟩: −b/(m l²) for a pendulum with friction b).

use crate::lagrangian::Lagrangian;

use super::super::dop853::Dop853;
use super::super::error::SimulationError;
use super::super::explicit::ExplicitRk;
use super::super::simulation::Simulation;
use super::super::state::{Fault, Stats};
use super::super::stepper::Stepper;
use super::augmented::Variational;
use super::variation::Variation;

/// The Lyapunov spectrum of a motion and how it converged ([`Lyapunov::compute`]).
///
/// ```
/// use lagrange_runtime::sensitivity::Spectrum;
/// let s = Spectrum { exponents: vec![0.1, -0.6], history: vec![(10.0, vec![0.1, -0.6])], duration: 10.0, renormalizations: 10 };
/// assert!((s.sum() + 0.5).abs() < 1e-15);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Spectrum {
    /// The exponents λ₁ ≥ λ₂ ≥ … (per unit time), as many as the directions followed.
    pub exponents: Vec<f64>,
    /// The running estimates (t − t_start, exponents) after each re-orthonormalization, thinned
    /// to at most about 1000 entries (the convergence as the run goes).
    pub history: Vec<(f64, Vec<f64>)>,
    /// The time averaged over (after the transient).
    pub duration: f64,
    /// How many re-orthonormalizations were made.
    pub renormalizations: usize,
}

impl Spectrum {
    /// Σ λ_i: for the whole spectrum, the mean rate of phase-space contraction ⟨tr J⟩.
    ///
    /// ```
    /// use lagrange_runtime::sensitivity::Spectrum;
    /// let s = Spectrum { exponents: vec![0.5, -0.5], history: vec![], duration: 1.0, renormalizations: 1 };
    /// assert_eq!(s.sum(), 0.0);
    /// ```
    pub fn sum(&self) -> f64 {
        self.exponents.iter().sum()
    }
}

/// The Lyapunov exponents of the motion from (q₀, q̇₀): configure, then
/// [`compute`](Lyapunov::compute).
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar};
/// use lagrange_runtime::sensitivity::Lyapunov;
/// /// ẍ = x: the exponents are +1 and −1.
/// struct Saddle;
/// impl Lagrangian<1> for Saddle {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] + q[0] * q[0]) * 0.5 }
/// }
/// // Along the motion x = 0 (an equilibrium), J is constant.
/// let s = Lyapunov::new(&Saddle, [0.0], [0.0]).duration(40.0).compute().unwrap();
/// assert!((s.exponents[0] - 1.0).abs() < 0.03 && (s.exponents[1] + 1.0).abs() < 0.03);
/// assert!(s.sum().abs() < 1e-9);
/// ```
pub struct Lyapunov<'a, L, const N: usize> {
    sys: &'a L,
    q0: [f64; N],
    qdot0: [f64; N],
    t0: f64,
    transient: f64,
    duration: f64,
    every: f64,
    directions: usize,
    rtol: f64,
    atol: f64,
}

impl<'a, L: Lagrangian<N>, const N: usize> Lyapunov<'a, L, N> {
    /// The exponents of the motion from (q₀, q̇₀) at t₀ = 0: the whole spectrum (2N), no
    /// transient, over a duration of 1000, re-orthonormalized every 1, DOP853 at
    /// rtol = atol = 1e-10.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Lyapunov;
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let s = Lyapunov::new(&Free, [0.0], [1.0]).duration(100.0).compute().unwrap();
    /// assert!(s.exponents.iter().all(|l| l.abs() < 0.1)); // polynomial growth: exponents → 0
    /// ```
    pub fn new(sys: &'a L, q0: [f64; N], qdot0: [f64; N]) -> Self {
        Lyapunov {
            sys,
            q0,
            qdot0,
            t0: 0.0,
            transient: 0.0,
            duration: 1000.0,
            every: 1.0,
            directions: 2 * N,
            rtol: 1e-10,
            atol: 1e-10,
        }
    }

    /// The start time t₀ (default 0).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Lyapunov;
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let s = Lyapunov::new(&Free, [0.0], [1.0]).start_time(5.0).duration(10.0).compute().unwrap();
    /// assert_eq!(s.duration, 10.0);
    /// ```
    pub fn start_time(mut self, t0: f64) -> Self {
        self.t0 = t0;
        self
    }

    /// Integrate this long first without averaging (to reach the attractor; default 0).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Lyapunov;
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let s = Lyapunov::new(&Free, [0.0], [1.0]).transient(50.0).duration(10.0).compute().unwrap();
    /// assert_eq!(s.renormalizations, 10);
    /// ```
    pub fn transient(mut self, t: f64) -> Self {
        self.transient = t;
        self
    }

    /// The time averaged over after the transient (default 1000).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Lyapunov;
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let s = Lyapunov::new(&Free, [0.0], [1.0]).duration(20.0).compute().unwrap();
    /// assert_eq!(s.duration, 20.0);
    /// ```
    pub fn duration(mut self, t: f64) -> Self {
        self.duration = t;
        self
    }

    /// Re-orthonormalize at least every `dt` (default 1), and sooner, after any step where the
    /// directions' lengths have separated by more than a factor 100 (fast growth: e^{(λ₁ − λ_k) dt}
    /// large), so they never collapse onto the fastest one in between.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Lyapunov;
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let s = Lyapunov::new(&Free, [0.0], [1.0]).duration(10.0).renormalize_every(0.5).compute().unwrap();
    /// assert_eq!(s.renormalizations, 20);
    /// ```
    pub fn renormalize_every(mut self, dt: f64) -> Self {
        self.every = dt;
        self
    }

    /// Follow only the first `k` directions (1 ≤ k ≤ 2N; default 2N): the k largest exponents.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Lyapunov;
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let s = Lyapunov::new(&Free, [0.0], [1.0]).duration(10.0).directions(1).compute().unwrap();
    /// assert_eq!(s.exponents.len(), 1);
    /// ```
    pub fn directions(mut self, k: usize) -> Self {
        self.directions = k;
        self
    }

    /// DOP853's tolerances for the motion and the directions (default 1e-10, 1e-10).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # use lagrange_runtime::sensitivity::Lyapunov;
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let s = Lyapunov::new(&Free, [0.0], [1.0]).duration(10.0).tolerances(1e-12, 1e-12).compute().unwrap();
    /// assert_eq!(s.exponents.len(), 2);
    /// ```
    pub fn tolerances(mut self, rtol: f64, atol: f64) -> Self {
        self.rtol = rtol;
        self.atol = atol;
        self
    }

    /// Runs the transient (a plain run), then the motion with its k directions, and returns
    /// the exponents with their convergence. Bad options are
    /// [`SimulationError::InvalidOptions`]; a failing run is its error (time, state).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, SimulationError};
    /// # use lagrange_runtime::sensitivity::Lyapunov;
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let err = Lyapunov::new(&Free, [0.0], [1.0]).directions(3).compute().unwrap_err();
    /// assert!(matches!(err, SimulationError::InvalidOptions { .. }));
    /// ```
    pub fn compute(self) -> Result<Spectrum, SimulationError> {
        let n2 = 2 * N;
        let method = self.checked()?;
        // The transient: a plain run.
        let (mut q, mut v, mut t) = (self.q0, self.qdot0, self.t0);
        if self.transient > 0.0 {
            let tr = Simulation::new(self.sys, q, v)
                .method(method)
                .start_time(t)
                .until(t + self.transient)
                .keep_samples(false)
                .run()?;
            if let (Some(qe), Some(ve)) = (tr.q.last(), tr.qdot.last()) {
                (q, v) = (*qe, *ve);
            }
            t += self.transient;
        }
        // Check the options the way a run does (finite state, tolerances) before stepping.
        Simulation::new(self.sys, q, v)
            .method(method)
            .start_time(t)
            .until(t + self.every.min(self.duration))
            .prepare()?;
        let k = self.directions;
        let var = Variation {
            sys: self.sys,
            params: &[],
            phi_cols: k,
            phi_unit: false,
            kernel: Default::default(),
            fields: None,
        };
        // The directions take part in the error control: at an equilibrium the motion alone
        // would allow any step.
        let problem = Variational {
            var,
            log: None,
            control: true,
        };
        let x0 = problem.state([q, v], generic_directions(n2, k));
        let mut stats = Stats::default();
        let t_start = t;
        let t_stop = t_start + self.duration;
        // The node's motion then its columns, as the errors report them.
        let flat = |s: &ExplicitRk<Variational<'_, '_, L, N>, Dop853, N>| -> Vec<f64> {
            let x = s.node().1;
            x.y.iter().flatten().chain(&x.cols).copied().collect()
        };
        let fail = |f: Fault, s: &ExplicitRk<Variational<'_, '_, L, N>, Dop853, N>| {
            fault_error::<N>(f, s.t(), &flat(s))
        };
        let mut s = ExplicitRk::<_, Dop853, N>::new(
            problem,
            t,
            x0,
            (self.rtol, self.atol),
            0.0,
            t_stop,
            self.every,
            &mut stats,
        )
        .map_err(|f| SimulationError::InvalidOptions {
            message: format!("the Lyapunov run could not start at t = {t}: {f:?}"),
        })?;
        let mut sums = vec![0.0; k];
        let mut history = Vec::new();
        let total = (self.duration / self.every).ceil().max(1.0) as usize;
        let thin = total.div_ceil(1000).max(1);
        // Orthonormalizations made, and intervals of `every` done (the grid the history is on).
        let (mut count, mut intervals) = (0, 0);
        while s.t() < t_stop {
            let target = (t_start + (intervals + 1) as f64 * self.every).min(t_stop);
            let target = if t_stop - target < 1e-9 * self.every {
                t_stop
            } else {
                target
            };
            loop {
                s.advance(target, &mut stats).map_err(|f| fail(f, &s))?;
                let at_target = s.t() >= target;
                // The directions as they stand: orthonormalized at the interval's end, or
                // sooner where they separate by more than SEPARATION (their orthogonal parts
                // would be lost to round-off and to the error control, which is relative to
                // the aligned part: at λ = ±20 and an interval of 1, by e⁴⁰).
                // And sooner where they grow by more than GROWTH (one fast direction, or several
                // growing alike, have no spread; past e^709 their entries overflow).
                let mut cols = s.node().1.cols.clone();
                let ln_r = orthonormalize(&mut cols, n2);
                let spread = separation(&ln_r);
                if spread.is_nan() || spread > MAX_SEPARATION {
                    let y = s.node().1.y;
                    return Err(separated(s.t(), &y[0], &y[1], spread));
                }
                let grown = ln_r.iter().any(|&l| l > GROWTH);
                if at_target || spread > SEPARATION || grown {
                    for (sum, ln) in sums.iter_mut().zip(&ln_r) {
                        *sum += ln;
                    }
                    let mut x = s.node().1.clone();
                    x.cols = cols;
                    s.replace_node(x, &mut stats).map_err(|f| fail(f, &s))?;
                    count += 1;
                }
                if at_target {
                    break;
                }
            }
            let elapsed = s.t() - t_start;
            intervals += 1;
            if intervals % thin == 0 || s.t() >= t_stop {
                history.push((elapsed, sums.iter().map(|x| x / elapsed).collect()));
            }
        }
        // Largest first: the directions start generic, so the orthonormalization orders them
        // as the run converges; the sort makes the order hold for a run too short for that.
        let exponents: Vec<f64> = descending(sums.iter().map(|x| x / self.duration).collect());
        for (_, h) in history.iter_mut() {
            *h = descending(core::mem::take(h));
        }
        if exponents.iter().any(|x| !x.is_finite()) {
            let y = s.node().1.y;
            return Err(SimulationError::NonFinite {
                t: s.t(),
                q: y[0].to_vec(),
                qdot: y[1].to_vec(),
                partial: super::super::error::PartialTrajectory::none(),
            });
        }
        Ok(Spectrum {
            exponents,
            history,
            duration: self.duration,
            renormalizations: count,
        })
    }

    /// The options checked: the method the run takes, or why they are refused.
    fn checked(&self) -> Result<super::super::method::Method, SimulationError> {
        let n2 = 2 * N;
        let bad = |message: String| Err(SimulationError::InvalidOptions { message });
        if self.directions == 0 || self.directions > n2 {
            return bad(format!(
                "directions({}): follow 1 to 2N = {n2} directions",
                self.directions
            ));
        }
        let positive = self.duration > 0.0 && self.every > 0.0 && self.transient >= 0.0;
        let finite =
            self.duration.is_finite() && self.every.is_finite() && self.transient.is_finite();
        if !positive || !finite {
            return bad(format!(
                "duration {}, renormalize_every {}, transient {}: give a positive finite \
                 duration and interval and a finite transient ≥ 0",
                self.duration, self.every, self.transient
            ));
        }
        if !(self.rtol > 0.0 && self.atol >= 0.0) {
            return bad(format!(
                "tolerances rtol = {}, atol = {}: give rtol > 0 and atol ≥ 0",
                self.rtol, self.atol
            ));
        }
        Ok(super::super::method::Method::Dop853 {
            rtol: self.rtol,
            atol: self.atol,
        })
    }
}

/// The error of a Lyapunov run that could not go on at (t, z).
fn fault_error<const N: usize>(f: Fault, t: f64, z: &[f64]) -> SimulationError {
    let (q, qdot) = (z[..N].to_vec(), z[N..2 * N].to_vec());
    let message = format!("{f:?}");
    SimulationError::Dynamics {
        source: Box::new(match f {
            Fault::Dynamics(e) => e,
            _ => crate::error::DynamicsError::NonFinite {
                t,
                q: q.clone(),
                qdot: qdot.clone(),
                message: format!(
                    "the Lyapunov run could not go on ({message}): tighten the \
                     tolerances or shorten the interval between re-orthonormalizations"
                ),
            },
        }),
        t,
        q,
        qdot,
        partial: super::super::error::PartialTrajectory::none(),
    }
}

/// Re-orthonormalize where the carried directions' lengths separate by more than this factor
/// (its logarithm) within an interval: their orthogonal parts then keep about
/// ε·e^SEPARATION / rtol·e^SEPARATION of their size (relative).
const SEPARATION: f64 = 4.605_170_185_988_091; // ln 100

/// A separation within one accepted step beyond this (ln 1e8) cannot be resolved by
/// re-orthonormalizing more often: the run is refused.
const MAX_SEPARATION: f64 = 18.420_680_743_952_367; // ln 1e8

/// Re-orthonormalize where a direction has grown by more than this factor (its logarithm,
/// ln 1e40) since the last orthonormalization: far from f64's overflow at e^709 whatever one
/// step adds.
const GROWTH: f64 = 92.103_403_719_761_84; // ln 1e40

/// ln(max R_ii / min R_ii) from the logarithms ln R_ii: how far the directions separated since
/// the last orthonormalization (infinite, or NaN, where one collapsed or is not finite).
fn separation(ln_r: &[f64]) -> f64 {
    let (lo, hi) = ln_r
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if lo.is_nan() || hi.is_nan() {
        return f64::NAN;
    }
    hi - lo
}

/// The refusal of a run whose directions separate too fast for its steps.
fn separated(t: f64, q: &[f64], qdot: &[f64], spread: f64) -> SimulationError {
    SimulationError::InvalidOptions {
        message: format!(
            "the Lyapunov directions separate by a factor e^{spread:.1} within one step at t = \
             {t}: their orthogonal parts are lost to round-off before they can be \
             re-orthonormalized. Shorten the steps: .renormalize_every(Δ) with a smaller Δ (it \
             also bounds the step), or tighter tolerances (.tolerances(rtol, atol)); q = {q:?}, \
             q̇ = {qdot:?}"
        ),
    }
}

/// The values sorted largest first (NaN last).
fn descending(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(|a, b| b.total_cmp(a));
    v
}

/// k orthonormal directions in 2N dimensions in general position (none in an invariant
/// subspace of a decoupled system, as the unit vectors are), the same for every run: a fixed
/// quasi-random matrix (the additive recurrence of the plastic number), orthonormalized.
fn generic_directions(n2: usize, k: usize) -> Vec<f64> {
    const A1: f64 = 0.754_877_666_246_693; // 1/ρ, ρ the plastic number
    const A2: f64 = 0.569_840_290_998_053; // 1/ρ²
    let mut cols: Vec<f64> = (0..n2 * k)
        .map(|idx| {
            let (i, j) = ((idx % n2) as f64, (idx / n2) as f64);
            let u = (0.5 + A1 * (i + 1.0) + A2 * (j + 1.0) * (j + 2.0)).fract();
            // A dominant diagonal keeps the columns far from dependent.
            u - 0.5 + if idx % n2 == idx / n2 { 2.0 } else { 0.0 }
        })
        .collect();
    orthonormalize(&mut cols, n2);
    cols
}

/// The k columns of length n2 stored one after the other in `cols` (W) replaced by Q of W = Q R
/// (modified Gram–Schmidt, in place); returns the logarithms of R's diagonal (the lengths,
/// whose own values may exceed f64's range: a direction grown by e^800 in one interval).
fn orthonormalize(cols: &mut [f64], n2: usize) -> Vec<f64> {
    let k = cols.len() / n2;
    let mut ln_r = vec![0.0; k];
    for j in 0..k {
        let (done, rest) = cols.split_at_mut(j * n2);
        let cj = &mut rest[..n2];
        // Scaled to its largest entry first (exactly, by a power of two), so that neither the
        // projections nor the norm overflow for a direction grown beyond 1e154.
        let big = cj.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let scale = if big > 0.0 && big.is_finite() {
            crate::eom::power_of_two_ratio(1.0, big)
        } else {
            1.0
        };
        for x in cj.iter_mut() {
            *x *= scale;
        }
        for i in 0..j {
            let ci = &done[i * n2..(i + 1) * n2];
            let d: f64 = ci.iter().zip(cj.iter()).map(|(a, b)| a * b).sum();
            for (x, y) in cj.iter_mut().zip(ci) {
                *x -= d * y;
            }
        }
        let n = cj.iter().map(|x| x * x).sum::<f64>().sqrt();
        ln_r[j] = n.ln() - scale.ln();
        if n > 0.0 {
            for x in cj.iter_mut() {
                *x /= n;
            }
        }
    }
    ln_r
}
