//! A sensitivity run as a [`Problem`]: the motion y = (q, q̇) and its columns of variations as
//! one state ([`Aug`]), with the variational equations as its right-hand side ([`Variational`]).
//! Any explicit Runge–Kutta tableau steps it (`explicit::ExplicitRk`), so the variations are
//! the method applied to the variational equations with the motion's steps: Φ is the exact
//! derivative of the discrete flow with respect to the initial state.
//!
//! **Error control** takes the columns too by default (the larger of the tableau's norm over the
//! motion and over the columns decides the step, as heyoka's variational systems are stepped as
//! one): at an equilibrium, where the motion alone would allow any step, Φ is still accurate.
//! With [`Sensitivity::motion_steps`](super::Sensitivity::motion_steps) the steps are the
//! motion's alone, so the motion is the plain run's bit for bit and Φ the exact derivative of
//! that run's discrete flow.

use core::cell::RefCell;
use std::rc::Rc;

use crate::lagrangian::Lagrangian;

use super::super::explicit::Counted;
use super::super::problem::{Estimate, Problem, Space};
use super::super::state::{Fault, Stats, Y, combine_by, weighted_by};
use super::Log;
use super::variation::Variation;

/// The motion and its columns (each 2N: δq then δq̇), with the ranges of the columns that move
/// (a cyclic coordinate's column of Φ is constant and is never written).
#[derive(Clone, Debug)]
pub(crate) struct Aug<const N: usize> {
    pub(crate) y: Y<N>,
    pub(crate) cols: Vec<f64>,
    shape: Rc<Shape>,
}

/// What the states of a run share: the ranges of the columns that move, and whether the
/// columns take part in the error control.
#[derive(Debug)]
struct Shape {
    moving: Vec<(usize, usize)>,
    control: bool,
}

impl Shape {
    /// The ranges of the `len` column entries that do not move (the gaps of `moving`).
    fn still(&self, len: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        let ends = self.moving.iter().map(|r| r.0).chain([len]);
        let starts = [0].into_iter().chain(self.moving.iter().map(|r| r.1));
        starts.zip(ends).filter(|(lo, hi)| lo < hi)
    }
}

impl<const N: usize> Aug<N> {
    /// The motion y with the columns `cols`, of which those `frozen` says are constant; the
    /// columns take part in the error control where `control`.
    pub(crate) fn new(
        y: Y<N>,
        cols: Vec<f64>,
        frozen: impl Fn(usize) -> bool,
        control: bool,
    ) -> Self {
        let n2 = 2 * N;
        let mut moving: Vec<(usize, usize)> = Vec::new();
        for c in (0..cols.len() / n2).filter(|&c| !frozen(c)) {
            let (lo, hi) = (c * n2, (c + 1) * n2);
            match moving.last_mut() {
                Some(last) if last.1 == lo => last.1 = hi,
                _ => moving.push((lo, hi)),
            }
        }
        Aug {
            y,
            cols,
            shape: Rc::new(Shape { moving, control }),
        }
    }
}

impl<const N: usize> Space<N> for Aug<N> {
    type R = f64;
    #[inline(always)]
    fn motion(&self) -> &Y<N> {
        &self.y
    }
    #[inline(always)]
    fn motion_mut(&mut self) -> &mut Y<N> {
        &mut self.y
    }
    /// The motion as a plain run's ([`combine_by`]); the columns that move as
    /// x + Σ (h a_j) k_j, zeros skipped.
    fn combine<const S: usize>(
        out: &mut Self,
        x: &Self,
        h: f64,
        a: &[f64; 16],
        k: &[Self; 16],
        hold: Option<&[bool; N]>,
    ) {
        out.y = combine_by(S, &x.y, h, a, |j| &k[j].y);
        if let Some(cyclic) = hold {
            for i in 0..N {
                if cyclic[i] {
                    out.y[0][i] = x.y[0][i];
                }
            }
        }
        // A constant column is the same in every state of the run (they all start as copies of
        // the first): it is not written.
        combine_columns(&mut out.cols, &x.cols, h, &a[..S], k, &x.shape.moving);
    }
    fn weighted<const S: usize>(out: &mut Self, a: &[f64; 16], k: &[Self; 16]) {
        out.y = weighted_by(S, a, |j| &k[j].y);
        // A constant column's slopes are zero: so is its sum.
        for (lo, hi) in k[0].shape.still(out.cols.len()) {
            out.cols[lo..hi].fill(0.0);
        }
        for &(lo, hi) in &k[0].shape.moving {
            let o = &mut out.cols[lo..hi];
            o.fill(0.0);
            for (&aj, kj) in a[..S].iter().zip(k) {
                if aj == 0.0 {
                    continue;
                }
                for (o, k) in o.iter_mut().zip(&kj.cols[lo..hi]) {
                    *o += aj * k;
                }
            }
        }
    }
    fn map<const I: usize, const O: usize>(
        ins: [&Self; I],
        outs: [&mut Self; O],
        f: impl Fn([f64; I]) -> [f64; O],
    ) {
        let mut outs = outs;
        for c in 0..2 {
            for i in 0..N {
                let v = f(core::array::from_fn(|j| ins[j].y[c][i]));
                for (o, v) in outs.iter_mut().zip(v) {
                    o.y[c][i] = v;
                }
            }
        }
        for i in 0..ins[0].cols.len() {
            let v = f(core::array::from_fn(|j| ins[j].cols[i]));
            for (o, v) in outs.iter_mut().zip(v) {
                o.cols[i] = v;
            }
        }
    }
    /// The tableau's estimate over the columns, each column's components weighted by the
    /// column's size (its largest component at either end of the step): a column is a
    /// direction, held to rtol relative to its length, and a component passing near zero does
    /// not force steps at atol (per-component weights took 22–26 % more steps than the motion
    /// alone on the heavy top, these 12–13 %; BENCHMARKS.md).
    fn parts_ln_err(
        (x, x1, k): (&Self, &Self, &[Self; 16]),
        h: f64,
        (rtol, atol): (f64, f64),
        (rows, ln_err_of): Estimate<'_>,
    ) -> Option<f64> {
        if !x.shape.control || x.cols.is_empty() {
            return None;
        }
        let n2 = 2 * N;
        let mut sums = [0.0; 2];
        // Each estimate Σ_j E_j k_j over a column, stage by stage (as the stage sums go).
        let mut e = vec![0.0; n2];
        for &(lo, hi) in &x.shape.moving {
            for col in (lo..hi).step_by(n2) {
                let r = col..col + n2;
                let largest = |c: &[f64]| c.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                let scale = largest(&x.cols[r.clone()]).max(largest(&x1.cols[r.clone()]));
                let inv = 1.0 / (atol + rtol * scale);
                for (est, sum) in rows.iter().zip(&mut sums) {
                    e.fill(0.0);
                    for (&c, kj) in est.iter().zip(k) {
                        if c != 0.0 {
                            for (e, k) in e.iter_mut().zip(&kj.cols[r.clone()]) {
                                *e += c * k;
                            }
                        }
                    }
                    *sum += e.iter().map(|e| (e * inv) * (e * inv)).sum::<f64>();
                }
            }
        }
        Some(ln_err_of(sums, h, x.cols.len()))
    }
    fn assign(&mut self, from: &Self) {
        self.y = from.y;
        self.cols.copy_from_slice(&from.cols);
    }
    fn finite(&self) -> bool {
        self.y
            .iter()
            .flatten()
            .chain(&self.cols)
            .all(|x| x.is_finite())
    }
}

/// out = x + Σ_j (h a_j) k_j over the ranges of the columns that move, zeros skipped.
fn combine_columns<const N: usize>(
    out: &mut [f64],
    x: &[f64],
    h: f64,
    a: &[f64],
    k: &[Aug<N>; 16],
    moving: &[(usize, usize)],
) {
    for &(lo, hi) in moving {
        let o = &mut out[lo..hi];
        o.copy_from_slice(&x[lo..hi]);
        for (j, &aj) in a.iter().enumerate() {
            if aj == 0.0 {
                continue;
            }
            let ha = h * aj;
            for (o, kj) in o.iter_mut().zip(&k[j].cols[lo..hi]) {
                *o += ha * kj;
            }
        }
    }
}

/// The variational equations as a problem, logging the columns where the driver records a
/// sample or locates an event.
pub(crate) struct Variational<'s, 'l, L, const N: usize> {
    pub(crate) var: Variation<'s, L, N>,
    pub(crate) log: Option<&'l RefCell<Log>>,
    /// Whether the columns take part in the error control; else the steps are the motion's and
    /// its q̈ the plain kernel's, so the motion is the plain run's bit for bit.
    pub(crate) control: bool,
}

impl<L: Lagrangian<N>, const N: usize> Variational<'_, '_, L, N> {
    /// The state y with the columns `cols` (Φ's first, then the parameters').
    pub(crate) fn state(&self, y: Y<N>, cols: Vec<f64>) -> Aug<N> {
        Aug::new(y, cols, |c| self.var.frozen(c), self.control)
    }
}

impl<L: Lagrangian<N>, const N: usize> Problem<N> for Variational<'_, '_, L, N> {
    type Sys = L;
    type State = Aug<N>;
    const OBSERVES: bool = true;
    type Slopes<'a>
        = Counted<'a, Self>
    where
        Self: 'a;
    fn slopes<'a>(&'a self, _sys: &'a L, stats: &'a mut Stats) -> Counted<'a, Self> {
        Counted { p: self, stats }
    }
    fn sys(&self) -> &L {
        self.var.sys
    }
    fn slope(&self, t: f64, x: &Aug<N>, out: &mut Aug<N>, stats: &mut Stats) -> Result<(), Fault> {
        self.var.eval(
            t,
            (&x.y, &x.cols),
            (&mut out.y, &mut out.cols),
            !self.control,
            stats,
        )
    }
    fn recorded(&self, t: f64, x: &Aug<N>) {
        if let Some(log) = self.log {
            log.borrow_mut().samples.push((t, x.cols.clone()));
        }
    }
    fn event_located(&self, t: f64, event: usize, x: &Aug<N>) {
        if let Some(log) = self.log {
            log.borrow_mut().event(t, event, x.cols.clone(), &x.y, None);
        }
    }
}
