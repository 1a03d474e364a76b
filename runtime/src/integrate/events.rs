//! Events: zero crossings of a user function g(t, q, q̇), located by Brent's method on the
//! method's interpolant.

use core::fmt;

use crate::error::DynamicsError;

/// Which sign changes of g count as an event.
///
/// ```
/// use lagrange_runtime::{Direction, Event};
/// let e = Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).falling();
/// assert_eq!(e.direction(), Direction::Falling);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// g goes from negative to non-negative.
    Rising,
    /// g goes from positive to non-positive.
    Falling,
    /// Either.
    Any,
}

/// The event function's type: g(t, q, q̇).
type EventFn<'a, const N: usize> = Box<dyn Fn(f64, &[f64; N], &[f64; N]) -> f64 + 'a>;

/// A reset map's type: (q⁺, q̇⁺) from (t, q⁻, q̇⁻), or why there is none (an impact law
/// without a solution).
type ResetFn<'a, const N: usize> =
    Box<dyn Fn(f64, &[f64; N], &[f64; N]) -> Result<[[f64; N]; 2], DynamicsError> + 'a>;

/// A zero crossing to detect during a run: g(t, q, q̇) = 0, with a direction filter and an
/// optional terminal flag (the run stops at the first terminal hit).
///
/// ```
/// use lagrange_runtime::{Direction, Event};
/// let e = Event::zero_crossing("apex", |_t, _q, v: &[f64; 2]| v[1]).rising().terminal();
/// assert_eq!((e.name(), e.direction(), e.is_terminal()), ("apex", Direction::Rising, true));
/// ```
pub struct Event<'a, const N: usize> {
    name: String,
    g: EventFn<'a, N>,
    direction: Direction,
    terminal: bool,
    reset: Option<ResetFn<'a, N>>,
    /// Where the hits accumulate (Zeno), the state the run goes on from (a contact closed at
    /// rest); without it a Zeno run ends there.
    rest: Option<ResetFn<'a, N>>,
    /// For an event whose reset changes a mode the flow depends on (a contact's: which contacts
    /// are closed): puts that mode on one side of the last jump, for the jump's saltation
    /// matrix ([`Side`]).
    sides: Option<SidesFn<'a>>,
}

/// Which side of its last jump a modal event's mode is put on ([`Event::side`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// The mode before the jump; resets are then evaluated and undone (differences of the
    /// reset map).
    Before,
    /// The mode after the jump, as the run goes on.
    After,
}

/// See [`Event::side`]: `Err` says why the last jump has no saltation matrix.
type SidesFn<'a> = Box<dyn Fn(Side) -> Result<(), String> + 'a>;

impl<'a, const N: usize> Event<'a, N> {
    /// An event at the zeros of g(t, q, q̇), in either direction, not terminal.
    ///
    /// ```
    /// use lagrange_runtime::Event;
    /// let e = Event::zero_crossing("turning point", |_t, _q, v: &[f64; 1]| v[0]);
    /// assert_eq!(e.value(0.0, &[1.0], &[-2.0]), -2.0);
    /// ```
    pub fn zero_crossing<F>(name: impl Into<String>, g: F) -> Self
    where
        F: Fn(f64, &[f64; N], &[f64; N]) -> f64 + 'a,
    {
        Event {
            name: name.into(),
            g: Box::new(g),
            direction: Direction::Any,
            terminal: false,
            reset: None,
            rest: None,
            sides: None,
        }
    }

    /// Only crossings with this direction count.
    ///
    /// ```
    /// use lagrange_runtime::{Direction, Event};
    /// let e = Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).direction_filter(Direction::Rising);
    /// assert_eq!(e.direction(), Direction::Rising);
    /// ```
    pub fn direction_filter(mut self, direction: Direction) -> Self {
        self.direction = direction;
        self
    }

    /// Only crossings where g increases (− to +) count.
    ///
    /// ```
    /// use lagrange_runtime::{Direction, Event};
    /// assert_eq!(Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).rising().direction(), Direction::Rising);
    /// ```
    pub fn rising(self) -> Self {
        self.direction_filter(Direction::Rising)
    }

    /// Only crossings where g decreases (+ to −) count.
    ///
    /// ```
    /// use lagrange_runtime::{Direction, Event};
    /// assert_eq!(Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).falling().direction(), Direction::Falling);
    /// ```
    pub fn falling(self) -> Self {
        self.direction_filter(Direction::Falling)
    }

    /// Stop the run at the first hit of this event (the trajectory ends at the event).
    ///
    /// ```
    /// use lagrange_runtime::Event;
    /// assert!(Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).terminal().is_terminal());
    /// ```
    pub fn terminal(mut self) -> Self {
        self.terminal = true;
        self
    }

    /// The same event at the level g = `level` (a Poincaré section through a start that is not
    /// quite on it: the start is then on the section, g − level = 0, which is not a crossing),
    /// named `name`; `None` for an event that resets or rests (a section only observes).
    pub(crate) fn at_level(self, level: f64, name: String) -> Option<Self> {
        if self.reset.is_some() || self.rest.is_some() || self.sides.is_some() {
            return None;
        }
        let g = self.g;
        Some(Event {
            name,
            g: Box::new(move |t, q, v| g(t, q, v) - level),
            ..self
        })
    }

    /// At each hit the state jumps to `reset(t, q⁻, q̇⁻) = (q⁺, q̇⁺)` and the run goes on from it,
    /// the method started afresh (an impact, a switch): the jump is recorded in
    /// [`Trajectory::jumps`](crate::Trajectory::jumps), its energy change enters the work column
    /// (so the energy balance h − h₀ − W holds across it), and an accumulation of hits (impact
    /// times converging geometrically: a Zeno run) ends the run at the last one with
    /// [`Trajectory::zeno`](crate::Trajectory::zeno) saying when the hits would accumulate.
    /// The trajectory's sample at the hit is the state before the jump.
    ///
    /// ```
    /// use lagrange_runtime::Event;
    /// // a ball on the floor x = 0 with restitution 0.8
    /// let e = Event::zero_crossing("floor", |_t, q: &[f64; 1], _v| q[0])
    ///     .falling()
    ///     .reset(|_t, q, v| (*q, [-0.8 * v[0]]));
    /// assert!(e.is_reset());
    /// assert_eq!(e.apply_reset(0.0, &[0.0], &[-5.0]), Some(([0.0], [4.0])));
    /// ```
    pub fn reset<F>(mut self, reset: F) -> Self
    where
        F: Fn(f64, &[f64; N], &[f64; N]) -> ([f64; N], [f64; N]) + 'a,
    {
        self.reset = Some(Box::new(move |t, q, v| {
            let (q, v) = reset(t, q, v);
            Ok([q, v])
        }));
        self
    }

    /// A reset map that may fail ([`reset`](Self::reset) whose map returns `Err` where it has
    /// no answer: an impact law without a solution, a singular matrix): the run stops there
    /// with that error, as a failing step would.
    ///
    /// ```
    /// use lagrange_runtime::{DynamicsError, Event};
    /// let e = Event::zero_crossing("floor", |_t, q: &[f64; 1], _v| q[0])
    ///     .falling()
    ///     .reset_fallible(|t, q, v| {
    ///         if v[0] < -100.0 {
    ///             Err(DynamicsError::Impact {
    ///                 t, q: q.to_vec(), qdot: v.to_vec(),
    ///                 message: "too fast for the impact law".into(),
    ///             })
    ///         } else {
    ///             Ok([*q, [-0.5 * v[0]]])
    ///         }
    ///     });
    /// assert_eq!(e.apply_reset(0.0, &[0.0], &[-2.0]), Some(([0.0], [1.0])));
    /// assert_eq!(e.apply_reset(0.0, &[0.0], &[-200.0]), None);
    /// ```
    pub fn reset_fallible<F>(mut self, reset: F) -> Self
    where
        F: Fn(f64, &[f64; N], &[f64; N]) -> Result<[[f64; N]; 2], DynamicsError> + 'a,
    {
        self.reset = Some(Box::new(reset));
        self
    }

    /// The state a Zeno accumulation of this event's hits resolves to (the run goes on from it
    /// instead of ending).
    pub(crate) fn rest_at_accumulation<F>(mut self, rest: F) -> Self
    where
        F: Fn(f64, &[f64; N], &[f64; N]) -> Result<[[f64; N]; 2], DynamicsError> + 'a,
    {
        self.rest = Some(Box::new(rest));
        self
    }

    /// Makes the event modal ([`side`](Self::side)).
    pub(crate) fn with_sides<F>(mut self, sides: F) -> Self
    where
        F: Fn(Side) -> Result<(), String> + 'a,
    {
        self.sides = Some(Box::new(sides));
        self
    }

    /// Puts the mode of a modal event (a contact's) on `side` of its last jump; nothing for an
    /// event without modes. `Err` where that jump has no saltation matrix (a Zeno completion).
    pub(crate) fn side(&self, side: Side) -> Result<(), String> {
        self.sides.as_ref().map_or(Ok(()), |f| f(side))
    }

    /// The reset map at (t, q, q̇), for an event that resets.
    pub(crate) fn try_reset(
        &self,
        t: f64,
        q: &[f64; N],
        qdot: &[f64; N],
    ) -> Option<Result<[[f64; N]; 2], DynamicsError>> {
        self.reset.as_ref().map(|r| r(t, q, qdot))
    }

    /// Whether the event is a contact's (it has a resting state): its function changes meaning
    /// at each transition (the gap while open, the normal force while closed).
    pub(crate) fn is_contact(&self) -> bool {
        self.rest.is_some()
    }

    /// The resting state at an accumulation of hits, for an event that has one.
    pub(crate) fn try_rest(
        &self,
        t: f64,
        q: &[f64; N],
        qdot: &[f64; N],
    ) -> Option<Result<[[f64; N]; 2], DynamicsError>> {
        self.rest.as_ref().map(|r| r(t, q, qdot))
    }

    /// Whether the state jumps at this event.
    ///
    /// ```
    /// use lagrange_runtime::Event;
    /// assert!(!Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).is_reset());
    /// ```
    pub fn is_reset(&self) -> bool {
        self.reset.is_some()
    }

    /// The state after the jump at (t, q, q̇), for an event that resets (`None` also where its
    /// map fails there).
    ///
    /// ```
    /// use lagrange_runtime::Event;
    /// let e = Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).reset(|_t, q, v| (*q, [-v[0]]));
    /// assert_eq!(e.apply_reset(1.0, &[0.0], &[2.0]), Some(([0.0], [-2.0])));
    /// ```
    pub fn apply_reset(
        &self,
        t: f64,
        q: &[f64; N],
        qdot: &[f64; N],
    ) -> Option<([f64; N], [f64; N])> {
        self.reset
            .as_ref()
            .and_then(|r| r(t, q, qdot).ok())
            .map(|[q, v]| (q, v))
    }

    /// The event's name.
    ///
    /// ```
    /// use lagrange_runtime::Event;
    /// assert_eq!(Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).name(), "x");
    /// ```
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The direction filter.
    ///
    /// ```
    /// use lagrange_runtime::{Direction, Event};
    /// assert_eq!(Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).direction(), Direction::Any);
    /// ```
    pub fn direction(&self) -> Direction {
        self.direction
    }

    /// Whether the run stops at this event.
    ///
    /// ```
    /// use lagrange_runtime::Event;
    /// assert!(!Event::zero_crossing("x", |_t, q: &[f64; 1], _v| q[0]).is_terminal());
    /// ```
    pub fn is_terminal(&self) -> bool {
        self.terminal
    }

    /// g(t, q, q̇).
    ///
    /// ```
    /// use lagrange_runtime::Event;
    /// let e = Event::zero_crossing("x", |t, q: &[f64; 1], _v| q[0] - t);
    /// assert_eq!(e.value(1.0, &[3.0], &[0.0]), 2.0);
    /// ```
    pub fn value(&self, t: f64, q: &[f64; N], qdot: &[f64; N]) -> f64 {
        (self.g)(t, q, qdot)
    }

    /// Whether a change of g from `g0` to `g1` over a step is a crossing this event reports.
    pub(crate) fn crosses(&self, g0: f64, g1: f64) -> Option<Direction> {
        let rising = g0 < 0.0 && g1 >= 0.0;
        let falling = g0 > 0.0 && g1 <= 0.0;
        match self.direction {
            Direction::Rising if rising => Some(Direction::Rising),
            Direction::Falling if falling => Some(Direction::Falling),
            Direction::Any if rising => Some(Direction::Rising),
            Direction::Any if falling => Some(Direction::Falling),
            _ => None,
        }
    }
}

impl<const N: usize> fmt::Debug for Event<'_, N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Event")
            .field("name", &self.name)
            .field("direction", &self.direction)
            .field("terminal", &self.terminal)
            .field("reset", &self.reset.is_some())
            .finish_non_exhaustive()
    }
}

/// One located event: which event, when, the state there and the direction of the crossing.
///
/// ```
/// use lagrange_runtime::{Direction, EventHit};
/// let hit = EventHit { name: "x".to_string(), t: 1.0, q: [0.0], qdot: [1.0], direction: Direction::Rising };
/// assert_eq!(hit.t, 1.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct EventHit<const N: usize> {
    /// The event's name.
    pub name: String,
    /// Time of the zero (to 1e-12 on the interpolant).
    pub t: f64,
    /// Coordinates at the zero.
    pub q: [f64; N],
    /// Velocities at the zero.
    pub qdot: [f64; N],
    /// Whether g was rising or falling through zero.
    pub direction: Direction,
}

/// A jump of the state at a resetting event ([`Event::reset`]).
///
/// ```
/// use lagrange_runtime::Jump;
/// let j = Jump { event: "floor".into(), t: 0.45, before: ([0.0], [-4.4]), after: ([0.0], [3.5]), energy_change: -3.5 };
/// assert!(j.energy_change < 0.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Jump<const N: usize> {
    /// The event's name.
    pub event: String,
    /// When.
    pub t: f64,
    /// (q, q̇) before the jump.
    pub before: ([f64; N], [f64; N]),
    /// (q, q̇) after the jump.
    pub after: ([f64; N], [f64; N]),
    /// The energy after minus the energy before (the Jacobi integral h; negative for an impact
    /// that dissipates): the work column carries it.
    pub energy_change: f64,
}

/// An accumulation of a resetting event's hits (a Zeno run: a ball bouncing ever lower): the
/// hit intervals shrank by one ratio, so the hits accumulate at a finite time, where the run
/// stopped instead of integrating them one by one.
///
/// ```
/// use lagrange_runtime::Zeno;
/// let z = Zeno { event: "floor".into(), ratio: 0.8, t_last: 4.0, t_accumulation: 4.1, hits: 12, resting: false };
/// assert!(z.to_string().contains("4.1"));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Zeno {
    /// The event's name.
    pub event: String,
    /// The ratio of successive intervals between hits.
    pub ratio: f64,
    /// The last hit integrated (where the run stopped).
    pub t_last: f64,
    /// Where the hits accumulate: t_last + Δ r/(1 − r), Δ the last interval.
    pub t_accumulation: f64,
    /// The event's hits integrated.
    pub hits: usize,
    /// Whether the run went on in resting contact from the last hit (a contact of
    /// [`Simulation::contacts`](crate::Simulation::contacts) closed there, plastically) rather
    /// than stopping there (a plain resetting event).
    pub resting: bool,
}

impl fmt::Display for Zeno {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.resting {
            return write!(
                f,
                "the impacts of contact \"{}\" accumulate (Zeno): {} impacts, intervals \
                 shrinking by {:.6} each, accumulating at t = {}; the contact closed at the last \
                 one, t = {}, and the run went on in resting contact",
                self.event, self.hits, self.ratio, self.t_accumulation, self.t_last
            );
        }
        write!(
            f,
            "the hits of event \"{}\" accumulate (Zeno): {} hits, intervals shrinking by {:.6} \
             each, accumulating at t = {} (the run stopped at the last hit, t = {}); past it the \
             motion rests in contact, which a reset map cannot express: declare the contact \
             (`fn contacts`, run with Simulation::contacts), or stop the run with a terminal event",
            self.event, self.hits, self.ratio, self.t_accumulation, self.t_last
        )
    }
}

/// How many intervals between hits, shrinking by one ratio, make a Zeno run.
pub(crate) const ZENO_INTERVALS: usize = 6;

/// How closely an event's time is located near time t: 1e-12, or 4 ulp of t where that is more.
pub(crate) fn location_tol(t: f64) -> f64 {
    1e-12_f64.max(4.0 * f64::EPSILON * t.abs())
}

/// The accumulation of the hit times `ts` (oldest first), if the last [`ZENO_INTERVALS`]
/// intervals shrink by one ratio r < 0.999 (to 1e-3: a rocking body's intervals shrink by a
/// ratio that settles only as its amplitude does, and a miss leaves impacts too fast to resolve)
/// and that ratio is not drifting towards 1: (r, the accumulation time). Or, whatever the ratio,
/// if they shrink (by 1e-3 or more over the window) and the last is within 1000 location
/// tolerances ([`location_tol`]): hits that close are no longer resolved (their times carry
/// errors of 1e-3 of the interval, and the steps between them approach the time resolution), so
/// the motion between them is taken as over (a ball with restitution 0.9995: its intervals shrink
/// by 0.9995, a ratio no test of 6 intervals tells from 1, until the steps would underflow).
///
/// Ratios that agree to 1e-3 are not enough: intervals shrinking as a power of the hit count,
/// d_k ~ k^(−p), have ratios 1 − p/k that agree ever better while their sum may diverge (a ball
/// lifted by 0.1 each time it falls through a line: d_k ~ k^(−1/2), nothing accumulates). Their
/// ratio drifts up by p/k² a hit, (1 − r)²/p; a geometric law's does not drift. The law is taken
/// for geometric only where the drift per hit is below (1 − r)²/4 (so p > 4: the sum converges,
/// and the geometric prediction of where is close), tested on the same intervals.
pub(crate) fn zeno(ts: &[f64]) -> Option<(f64, f64)> {
    if ts.len() < ZENO_INTERVALS + 1 {
        return None;
    }
    let tail = &ts[ts.len() - ZENO_INTERVALS - 1..];
    let d: Vec<f64> = tail.windows(2).map(|w| w[1] - w[0]).collect();
    let ratios: Vec<f64> = d.windows(2).map(|w| w[1] / w[0]).collect();
    let (last, dl) = (tail[tail.len() - 1], d[d.len() - 1]);
    // Hits that the event location no longer resolves and that still shrink (beyond the
    // round-off of their times: by any law, geometric or a power of k) accumulate as far as the
    // run can tell.
    let shrinking = dl < 0.999 * d[0] || d[0] - dl > 16.0 * f64::EPSILON * last.abs();
    if dl > 0.0 && shrinking && dl <= 1e3 * location_tol(last) {
        // The mean ratio over the window.
        let r = (dl / d[0]).powf(1.0 / (d.len() - 1) as f64);
        return Some((r, last + dl * r / (1.0 - r)));
    }
    let r = ratios[ratios.len() - 1];
    let agree = ratios.iter().all(|&x| (x - r).abs() <= 1e-3 * r);
    if !(agree && r > 0.0 && r < 0.999) {
        return None;
    }
    // The ratio's drift per hit: the slope of a least-squares line through the ratios.
    let m = ratios.len() as f64;
    let mean_k = (m - 1.0) / 2.0;
    let mean_r = ratios.iter().sum::<f64>() / m;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (k, &x) in ratios.iter().enumerate() {
        let dk = k as f64 - mean_k;
        sxy += dk * (x - mean_r);
        sxx += dk * dk;
    }
    let drift = sxy / sxx;
    if drift > 0.25 * (1.0 - r) * (1.0 - r) {
        return None;
    }
    // Intervals d_k = d∞ + A r^k (a bouncing that settles into a steady cycle: a kick at each
    // hit) have ratios that agree while A r^k ≫ d∞, yet nothing accumulates. Their differences
    // are geometric whatever d∞: Δ_k = A r^k (r − 1), so d∞ = d_L − r Δ_{L−1} / (r − 1) from
    // the last two differences, zero for an accumulation up to the error of the hit times
    // (1e-9 of t plus the location's tolerance, amplified by 1 + 2r/(1 − r)).
    let n = d.len();
    let (d1, d2) = (d[n - 2] - d[n - 3], dl - d[n - 2]);
    let rd = d2 / d1;
    if rd > 0.0 && rd < 1.0 {
        let d_inf = dl - rd * d2 / (rd - 1.0);
        let noise = (1e-9 * last.abs() + 10.0 * location_tol(last)) * (1.0 + 2.0 * rd / (1.0 - rd));
        if d_inf > noise {
            return None;
        }
    }
    Some((r, last + dl * r / (1.0 - r)))
}

/// Brent's method (Numerical Recipes `zbrent`) for a root of f in [a, b] where f(a), f(b) have
/// opposite signs (or one is zero), to `tol` in the argument.
pub(crate) fn brent<E>(
    f: &mut dyn FnMut(f64) -> Result<f64, E>,
    a: f64,
    b: f64,
    fa: f64,
    fb: f64,
    tol: f64,
) -> Result<f64, E> {
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    if fa == 0.0 {
        return Ok(a);
    }
    if fb == 0.0 {
        return Ok(b);
    }
    let (mut c, mut fc) = (b, fb);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if (fb > 0.0 && fc > 0.0) || (fb < 0.0 && fc < 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return Ok(b);
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q) = if a == c {
                (2.0 * xm * s, 1.0 - s)
            } else {
                let q = fa / fc;
                let r = fb / fc;
                (
                    s * (2.0 * xm * q * (q - r) - (b - a) * (r - 1.0)),
                    (q - 1.0) * (r - 1.0) * (s - 1.0),
                )
            };
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            let min1 = 3.0 * xm * q - (tol1 * q).abs();
            let min2 = (e * q).abs();
            if 2.0 * p < min1.min(min2) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b)?;
        if !fb.is_finite() {
            return Ok(b);
        }
    }
    Ok(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_cos_root_to_1e_12() {
        let r: Result<f64, ()> = brent(
            &mut |x| Ok(x.cos()),
            1.0,
            2.0,
            1f64.cos(),
            2f64.cos(),
            1e-12,
        );
        assert!((r.unwrap() - core::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    #[test]
    fn zeno_needs_one_shrinking_ratio() {
        let geometric: Vec<f64> = (0..8).map(|k| 1.0 - 0.5_f64.powi(k)).collect();
        let (r, t) = zeno(&geometric).unwrap();
        assert!((r - 0.5).abs() < 1e-15 && (t - 1.0).abs() < 1e-15);
        let periodic: Vec<f64> = (0..8).map(f64::from).collect();
        assert_eq!(zeno(&periodic), None);
        assert_eq!(zeno(&geometric[..6]), None);
        let mut broken = geometric.clone();
        broken[4] += 1e-3;
        assert_eq!(zeno(&broken), None);
    }

    /// Intervals d∞ + A r^k (a bouncing that settles into a steady cycle) are not Zeno, even
    /// while their ratios agree to 1e-3 (A r^k ≫ d∞); d∞ = 0 is.
    #[test]
    fn a_sequence_settling_into_a_cycle_is_not_zeno() {
        let times = |d_inf: f64| {
            let mut t = 45.0;
            let mut ts = vec![t];
            for k in 0..7 {
                t += d_inf + 90.0 * 0.8_f64.powi(k);
                ts.push(t);
            }
            ts
        };
        assert_eq!(zeno(&times(0.1)), None);
        let (r, _) = zeno(&times(0.0)).unwrap();
        assert!((r - 0.8).abs() < 1e-12);
    }

    /// A ball lifted by 0.1 each time it falls through y = 0.5 (dropped from y = 1, g = 9.81):
    /// its intervals shrink as k^(−1/2) and their ratios agree to 1e-3 from the 43rd hit on (at
    /// t = 0.99, where the geometric law would put an accumulation at t = 1.96), but nothing
    /// accumulates: the hits go on for ever, ever faster only as √k.
    #[test]
    fn zeno_is_not_a_power_law() {
        let g: f64 = 9.81;
        let mut t = (2.0 * 0.5 / g).sqrt();
        let mut v = g * t;
        let mut ts = vec![t];
        for _ in 0..200 {
            let d = ((v * v + 2.0 * g * 0.1).sqrt() - v) / g;
            t += d;
            v += g * d;
            ts.push(t);
        }
        for end in ZENO_INTERVALS + 1..=ts.len() {
            assert_eq!(zeno(&ts[..end]), None, "hit {end}, t = {}", ts[end - 1]);
        }
        // A geometric law with the same first ratio is still one.
        let r: f64 = 0.99;
        let geometric: Vec<f64> = (0..8).map(|k| (1.0 - r.powi(k)) / (1.0 - r)).collect();
        let (ratio, t_acc) = zeno(&geometric).unwrap();
        assert!(
            (ratio - r).abs() < 1e-12 && (t_acc - 100.0).abs() < 1e-9,
            "{ratio} {t_acc}"
        );
    }

    /// Intervals shrinking by 0.9995 (a ratio the 6-interval test cannot tell from 1) are an
    /// accumulation once they are within 1000 location tolerances (1e-9 near t = 1), not before;
    /// equal intervals that short (a fast oscillation) are not.
    #[test]
    fn unresolved_shrinking_hits_are_zeno() {
        let r: f64 = 0.9995;
        let hits = |d0: f64| -> Vec<f64> {
            let mut t = vec![1.0];
            for k in 0..7 {
                t.push(t[k] + d0 * r.powi(k as i32));
            }
            t
        };
        assert_eq!(zeno(&hits(2e-9)), None);
        // Hit times near t = 1 carry its round-off, 2.2e-16, 4e-7 of an interval: the mean
        // ratio to 1e-7 or so, and the remaining time d r/(1 − r) to its amplification of that,
        // δr/(1 − r) ≈ 4e-4 relative.
        let (ratio, t_acc) = zeno(&hits(5e-10)).unwrap();
        assert!((ratio - r).abs() < 1e-6, "{ratio}");
        let last = hits(5e-10)[7];
        let remaining = 5e-10 * r.powi(6) * r / (1.0 - r);
        assert!(
            (t_acc - (last + remaining)).abs() < 1e-2 * remaining,
            "{t_acc} vs {}",
            last + remaining
        );
        let even: Vec<f64> = (0..8).map(|k| 1.0 + 1e-10 * f64::from(k)).collect();
        assert_eq!(zeno(&even), None);
    }

    #[test]
    fn crossing_directions() {
        let any = Event::zero_crossing("g", |_t, q: &[f64; 1], _v| q[0]);
        assert_eq!(any.crosses(-1.0, 1.0), Some(Direction::Rising));
        assert_eq!(any.crosses(1.0, 0.0), Some(Direction::Falling));
        assert_eq!(any.crosses(0.0, 1.0), None);
        let up = Event::zero_crossing("g", |_t, q: &[f64; 1], _v| q[0]).rising();
        assert_eq!(up.crosses(1.0, -1.0), None);
        assert_eq!(up.crosses(-1.0, 2.0), Some(Direction::Rising));
    }
}
