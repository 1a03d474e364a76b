//! The problem side of a run, apart from the methods that solve it (as diffsol separates its
//! equations from its solvers): a [`Problem`] is a right-hand side over a [`Space`] of states,
//! with hooks where the driver records a sample or locates an event. A plain run ([`Plain`]: the
//! motion y = (q, q̇)) and a sensitivity run (the motion with its columns of variations, in
//! `sensitivity`) are problems; the explicit Runge–Kutta methods and the Taylor method are
//! written once over them.

use super::state::{Fault, Real, Stats, Y, YOf, combine, rhs, weighted};
use crate::lagrangian::Lagrangian;

/// The states a method steps, with the arithmetic of its stages: the motion y = (q, q̇) (`Y`,
/// also at the width of SIMD lanes) or the motion with its variations.
pub(crate) trait Space<const N: usize>: Clone {
    /// The numbers: `f64`, or lanes of several members.
    type R: Real;
    /// Whether a copy is cheap (a fixed array, no allocation): a stage's argument is then a
    /// local of its own rather than one scratch state.
    const COPY: bool = false;
    /// The motion's part.
    fn motion(&self) -> &YOf<Self::R, N>;
    /// The motion's part, to be written.
    fn motion_mut(&mut self) -> &mut YOf<Self::R, N>;
    /// out = x + h Σ_{j<S} a_j k_j (the order of [`combine`]); for a stage's argument (`hold`
    /// given) the positions of the coordinates it marks (the cyclic ones) are held at x's.
    ///
    /// q̈ does not depend on a coordinate absent from L, and a stage's position enters nothing
    /// but the right-hand side (its slope in q is the stage velocity, formed in full), so these
    /// positions need not be formed: after inlining, their sums are dead code (a measurable
    /// saving on a heavy-top DOP853 run, where 2 of 3 coordinates are cyclic). x₁ and the error
    /// estimate still integrate every position. `Simulation::run` checks the declaration before
    /// the first step.
    fn combine<const S: usize>(
        out: &mut Self,
        x: &Self,
        h: Self::R,
        a: &[f64; 16],
        k: &[Self; 16],
        hold: Option<&[bool; N]>,
    );
    /// out = Σ_{j<S} a_j k_j (the order of [`weighted`]).
    fn weighted<const S: usize>(out: &mut Self, a: &[f64; 16], k: &[Self; 16]);
    /// Component by component, the outputs from the inputs (the dense-output rules).
    fn map<const I: usize, const O: usize>(
        ins: [&Self; I],
        outs: [&mut Self; O],
        f: impl Fn([Self::R; I]) -> [Self::R; O],
    );
    /// ln of the error norm over the parts of the state other than the motion that take part in
    /// the error control (a sensitivity run's columns), by a tableau's estimate: its rows of
    /// error weights and its norm of their sums (`explicit::Tableau`'s `ERROR_ROWS` and
    /// `ln_err_of`); `None` where only the motion does.
    #[inline(always)]
    fn parts_ln_err(
        _steps: (&Self, &Self, &[Self; 16]),
        _h: Self::R,
        _tol: (Self::R, Self::R),
        _estimate: Estimate<'_>,
    ) -> Option<Self::R> {
        None
    }
    /// Copies `from` into self (no allocation).
    fn assign(&mut self, from: &Self);
    /// Whether every component is finite (always true for lanes, which test theirs lane by
    /// lane).
    fn finite(&self) -> bool;
}

impl<R: Real, const N: usize> Space<N> for YOf<R, N> {
    type R = R;
    const COPY: bool = true;
    #[inline(always)]
    fn motion(&self) -> &YOf<R, N> {
        self
    }
    #[inline(always)]
    fn motion_mut(&mut self) -> &mut YOf<R, N> {
        self
    }
    #[inline(always)]
    fn combine<const S: usize>(
        out: &mut Self,
        x: &Self,
        h: R,
        a: &[f64; 16],
        k: &[Self; 16],
        hold: Option<&[bool; N]>,
    ) {
        let mut ys = combine::<S, N, 16, 16, R>(x, h, a, k);
        if let Some(cyclic) = hold {
            // The same values either way; LLVM keeps the fewest instructions with the whole row
            // rebuilt at width 1 (−1.0 % for a run) and with single stores in lanes (−4.6 %).
            if R::WIDTH == 1 {
                let held: [R; N] =
                    core::array::from_fn(|i| if cyclic[i] { x[0][i] } else { ys[0][i] });
                ys[0] = held;
            } else {
                for i in 0..N {
                    if cyclic[i] {
                        ys[0][i] = x[0][i];
                    }
                }
            }
        }
        *out = ys;
    }
    #[inline(always)]
    fn weighted<const S: usize>(out: &mut Self, a: &[f64; 16], k: &[Self; 16]) {
        *out = weighted::<S, N, 16, 16, R>(a, k);
    }
    #[inline(always)]
    fn map<const I: usize, const O: usize>(
        ins: [&Self; I],
        mut outs: [&mut Self; O],
        f: impl Fn([R; I]) -> [R; O],
    ) {
        for c in 0..2 {
            for i in 0..N {
                let v = f(core::array::from_fn(|j| ins[j][c][i]));
                for (o, v) in outs.iter_mut().zip(v) {
                    o[c][i] = v;
                }
            }
        }
    }
    #[inline(always)]
    fn assign(&mut self, from: &Self) {
        *self = *from;
    }
    #[inline(always)]
    fn finite(&self) -> bool {
        R::WIDTH > 1 || self.iter().flatten().all(|x| R::all(x.finite()))
    }
}

/// The slopes F a stage evaluates: the problem's (a single run, a sensitivity run), or the
/// accelerations of W members at once (the lanes).
pub(crate) trait Slopes<S: Space<N>, const N: usize> {
    /// Why the evaluation failed.
    type Error;
    /// F(t, x) into `out`.
    fn slope(&mut self, t: S::R, x: &S, out: &mut S) -> Result<(), Self::Error>;
}

/// A tableau's error estimate for the parts of a state besides the motion: its rows of error
/// weights and its norm of their sums of squares, ln err(sums, h, count).
pub(crate) type Estimate<'a> = (&'a [[f64; 16]], fn([f64; 2], f64, usize) -> f64);

/// A right-hand side the methods step, with what the driver tells it.
pub(crate) trait Problem<const N: usize> {
    /// The system.
    type Sys: Lagrangian<N>;
    /// The states.
    type State: Space<N, R = f64>;
    /// Whether [`recorded`](Self::recorded) and [`event_located`](Self::event_located) want
    /// the state (the stepper then interpolates it there).
    const OBSERVES: bool = false;
    /// The system.
    fn sys(&self) -> &Self::Sys;
    /// F(t, x) into `out`, counted in `stats`.
    fn slope(
        &self,
        t: f64,
        x: &Self::State,
        out: &mut Self::State,
        stats: &mut Stats,
    ) -> Result<(), Fault>;
    /// The slopes a step evaluates, counted in the run's statistics.
    type Slopes<'a>: Slopes<Self::State, N, Error = Fault>
    where
        Self: 'a;
    /// The slopes of the steps, `sys` being [`sys`](Self::sys) handed in as an argument (see
    /// `explicit::attempt_at`): a plain run's hold that reference itself.
    fn slopes<'a>(&'a self, sys: &'a Self::Sys, stats: &'a mut Stats) -> Self::Slopes<'a>;
    /// The driver recorded a sample at time `t` whose state is `x`.
    fn recorded(&self, _t: f64, _x: &Self::State) {}
    /// The driver located a hit of event `event` at time `t`, in state `x`.
    fn event_located(&self, _t: f64, _event: usize, _x: &Self::State) {}
}

/// A plain run: the motion y = (q, q̇) of the system, ẏ = (q̇, q̈).
pub(crate) struct Plain<'a, L> {
    pub(crate) sys: &'a L,
}

impl<L: Lagrangian<N>, const N: usize> Problem<N> for Plain<'_, L> {
    type Sys = L;
    type State = Y<N>;
    type Slopes<'a>
        = Single<'a, L>
    where
        Self: 'a;
    #[inline(always)]
    fn slopes<'a>(&'a self, sys: &'a L, stats: &'a mut Stats) -> Single<'a, L> {
        Single { sys, stats }
    }
    #[inline(always)]
    fn sys(&self) -> &L {
        self.sys
    }
    #[inline(always)]
    fn slope(&self, t: f64, x: &Y<N>, out: &mut Y<N>, stats: &mut Stats) -> Result<(), Fault> {
        *out = rhs(self.sys, t, x, stats)?;
        Ok(())
    }
}

/// A plain run's slopes: the system's reference, copied out of the problem, and the run's
/// statistics.
pub(crate) struct Single<'a, L> {
    sys: &'a L,
    stats: &'a mut Stats,
}

impl<L: Lagrangian<N>, const N: usize> Slopes<Y<N>, N> for Single<'_, L> {
    type Error = Fault;
    #[inline(always)]
    fn slope(&mut self, t: f64, x: &Y<N>, out: &mut Y<N>) -> Result<(), Fault> {
        *out = rhs(self.sys, t, x, self.stats)?;
        Ok(())
    }
}
