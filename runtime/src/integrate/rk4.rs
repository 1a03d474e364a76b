//! The classical 4th-order Runge–Kutta method with a fixed step, and cubic Hermite interpolation
//! between steps (from y and f = ẏ at both ends) for locating events.

use crate::lagrangian::Lagrangian;

use super::state::Stats;
use super::state::{Fault, Y, combine, finite, rhs};
use super::stepper::{FixedGrid, Stepper};

/// One classical RK4 step of size h from (t, y) with k₁ = f(t, y).
pub(crate) fn step<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    t: f64,
    y: &Y<N>,
    f0: &Y<N>,
    h: f64,
    stats: &mut Stats,
) -> Result<Y<N>, Fault> {
    let k1 = *f0;
    let k2 = rhs(
        sys,
        t + 0.5 * h,
        &combine::<1, _, _, _, _>(y, h, &[0.5], &[k1]),
        stats,
    )?;
    let k3 = rhs(
        sys,
        t + 0.5 * h,
        &combine::<1, _, _, _, _>(y, h, &[0.5], &[k2]),
        stats,
    )?;
    let k4 = rhs(
        sys,
        t + h,
        &combine::<1, _, _, _, _>(y, h, &[1.0], &[k3]),
        stats,
    )?;
    let y1 = combine::<4, _, _, _, _>(
        y,
        h,
        &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
        &[k1, k2, k3, k4],
    );
    if finite(&y1) {
        Ok(y1)
    } else {
        Err(Fault::NonFinite)
    }
}

/// Cubic Hermite interpolation of y on [t0, t0 + h] from y and ẏ at both ends (3rd order).
pub(crate) fn hermite<const N: usize>(
    y0: &Y<N>,
    f0: &Y<N>,
    y1: &Y<N>,
    f1: &Y<N>,
    h: f64,
    s: f64,
) -> Y<N> {
    let h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
    let h10 = s * (1.0 - s) * (1.0 - s);
    let h01 = s * s * (3.0 - 2.0 * s);
    let h11 = s * s * (s - 1.0);
    let mut out = [[0.0; N]; 2];
    for c in 0..2 {
        for i in 0..N {
            out[c][i] = h00 * y0[c][i] + h10 * h * f0[c][i] + h01 * y1[c][i] + h11 * h * f1[c][i];
        }
    }
    out
}

/// The fixed-step RK4 stepper.
pub(crate) struct Rk4<'a, L, const N: usize> {
    sys: &'a L,
    grid: FixedGrid,
    k: u64,
    t: f64,
    y: Y<N>,
    f: Y<N>,
    t_old: f64,
    y_old: Y<N>,
    f_old: Y<N>,
}

impl<'a, L: Lagrangian<N>, const N: usize> Rk4<'a, L, N> {
    /// Starts at (t0, y0) on the given step grid.
    pub(crate) fn new(
        sys: &'a L,
        grid: FixedGrid,
        y0: Y<N>,
        stats: &mut Stats,
    ) -> Result<Self, Fault> {
        let f = rhs(sys, grid.t0, &y0, stats)?;
        Ok(Rk4 {
            sys,
            grid,
            k: 0,
            t: grid.t0,
            y: y0,
            f,
            t_old: grid.t0,
            y_old: y0,
            f_old: f,
        })
    }
}

impl<L: Lagrangian<N>, const N: usize> Stepper<N> for Rk4<'_, L, N> {
    fn t(&self) -> f64 {
        self.t
    }
    fn t_prev(&self) -> f64 {
        self.t_old
    }
    fn last_state(&self) -> Y<N> {
        self.y
    }
    fn set_node(&mut self, y: Y<N>, _stats: &mut Stats) -> Result<(), Fault> {
        // The next step's k₁ as `Stepper::set_node` says: q̇ from y, q̈ kept.
        self.f[0] = y[1];
        self.y = y;
        Ok(())
    }
    fn advance(&mut self, _t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        let t1 = self.grid.time(self.k + 1);
        let h = t1 - self.t;
        let y1 = step(self.sys, self.t, &self.y, &self.f, h, stats)?;
        // f at the new node: the next step's k₁ and the Hermite interpolant's right slope.
        let f1 = rhs(self.sys, t1, &y1, stats)?;
        stats.steps += 1;
        self.k += 1;
        self.t_old = self.t;
        self.y_old = self.y;
        self.f_old = self.f;
        self.t = t1;
        self.y = y1;
        self.f = f1;
        Ok(())
    }
    fn interp(&mut self, t: f64, _stats: &mut Stats) -> Result<Y<N>, Fault> {
        if t >= self.t {
            return Ok(self.y);
        }
        let h = self.t - self.t_old;
        let s = (t - self.t_old) / h;
        Ok(hermite(&self.y_old, &self.f_old, &self.y, &self.f, h, s))
    }
    /// The cubic Hermite interpolant's rows: y and f = ẏ at both nodes (`hermite`'s order).
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, _stats: &mut Stats) -> Result<f64, Fault> {
        rows.extend_from_slice(&[self.y_old, self.f_old, self.y, self.f]);
        Ok(self.t - self.t_old)
    }
}
