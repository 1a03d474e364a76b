//! The classical RK4 over the augmented state (the motion and its variations) on the fixed step
//! grid of [`rk4`](super::super::rk4), with cubic Hermite interpolation between nodes from the
//! augmented slopes at both ends: the variations are RK4 applied to the variational equations
//! with the motion's steps, the exact derivative of the discrete flow.

use core::cell::RefCell;

use crate::lagrangian::Lagrangian;

use super::super::state::{Fault, Stats, Y};
use super::super::stepper::{FixedGrid, Stepper};
use super::Log;
use super::arith::y_of;
use super::variation::Variation;

/// The RK4 stepper of the augmented state.
pub(crate) struct VarRk4<'s, 'l, L, const N: usize> {
    var: Variation<'s, L, N>,
    grid: FixedGrid,
    k: u64,
    t: f64,
    z: Vec<f64>,
    f: Vec<f64>,
    t_old: f64,
    z_old: Vec<f64>,
    f_old: Vec<f64>,
    log: Option<&'l RefCell<Log>>,
}

impl<'s, 'l, L: Lagrangian<N>, const N: usize> VarRk4<'s, 'l, L, N> {
    /// Starts at (t0, z0) on the given grid.
    pub(crate) fn new(
        var: Variation<'s, L, N>,
        grid: FixedGrid,
        z0: Vec<f64>,
        log: Option<&'l RefCell<Log>>,
        stats: &mut Stats,
    ) -> Result<Self, Fault> {
        let mut f = vec![0.0; z0.len()];
        var.eval(grid.t0, &z0, &mut f, stats)?;
        Ok(VarRk4 {
            var,
            grid,
            k: 0,
            t: grid.t0,
            z_old: z0.clone(),
            f_old: f.clone(),
            z: z0,
            f,
            t_old: grid.t0,
            log,
        })
    }

    /// Components `lo..hi` at t in [t_prev, t] (cubic Hermite).
    fn part_at(&self, t: f64, lo: usize, hi: usize) -> Vec<f64> {
        let h = self.t - self.t_old;
        if t >= self.t || h == 0.0 {
            return self.z[lo..hi].to_vec();
        }
        let s = (t - self.t_old) / h;
        let h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
        let h10 = s * (1.0 - s) * (1.0 - s);
        let h01 = s * s * (3.0 - 2.0 * s);
        let h11 = s * s * (s - 1.0);
        (lo..hi)
            .map(|i| {
                h00 * self.z_old[i]
                    + h10 * h * self.f_old[i]
                    + h01 * self.z[i]
                    + h11 * h * self.f[i]
            })
            .collect()
    }
}

impl<L: Lagrangian<N>, const N: usize> Stepper<N> for VarRk4<'_, '_, L, N> {
    fn t(&self) -> f64 {
        self.t
    }
    fn t_prev(&self) -> f64 {
        self.t_old
    }
    fn last_state(&self) -> Y<N> {
        y_of::<N>(&self.z)
    }
    fn set_node(&mut self, y: Y<N>, _stats: &mut Stats) -> Result<(), Fault> {
        // Not reached: sensitivity runs refuse constraints, whose projection calls this.
        self.z[..N].copy_from_slice(&y[0]);
        self.z[N..2 * N].copy_from_slice(&y[1]);
        self.f[..N].copy_from_slice(&y[1]);
        Ok(())
    }
    fn advance(&mut self, _t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        let t1 = self.grid.time(self.k + 1);
        let h = t1 - self.t;
        let n = self.z.len();
        let at = |base: &[f64], c: f64, k: &[f64]| -> Vec<f64> {
            base.iter().zip(k).map(|(b, k)| b + c * h * k).collect()
        };
        let mut k2 = vec![0.0; n];
        let mut k3 = vec![0.0; n];
        let mut k4 = vec![0.0; n];
        self.var
            .eval(self.t + 0.5 * h, &at(&self.z, 0.5, &self.f), &mut k2, stats)?;
        self.var
            .eval(self.t + 0.5 * h, &at(&self.z, 0.5, &k2), &mut k3, stats)?;
        self.var.eval(t1, &at(&self.z, 1.0, &k3), &mut k4, stats)?;
        let z1: Vec<f64> = (0..n)
            .map(|i| self.z[i] + h * (self.f[i] + 2.0 * (k2[i] + k3[i]) + k4[i]) / 6.0)
            .collect();
        if !z1.iter().all(|x| x.is_finite()) {
            return Err(Fault::NonFinite);
        }
        let mut f1 = vec![0.0; n];
        self.var.eval(t1, &z1, &mut f1, stats)?;
        stats.steps += 1;
        self.k += 1;
        self.t_old = self.t;
        self.z_old = core::mem::replace(&mut self.z, z1);
        self.f_old = core::mem::replace(&mut self.f, f1);
        self.t = t1;
        Ok(())
    }
    fn interp(&mut self, t: f64, _stats: &mut Stats) -> Result<Y<N>, Fault> {
        Ok(y_of::<N>(&self.part_at(t, 0, 2 * N)))
    }
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, _stats: &mut Stats) -> Result<f64, Fault> {
        rows.extend_from_slice(&[
            y_of::<N>(&self.z_old),
            y_of::<N>(&self.f_old),
            y_of::<N>(&self.z),
            y_of::<N>(&self.f),
        ]);
        Ok(self.t - self.t_old)
    }
    fn recorded(&mut self, t: f64, at: f64, _stats: &mut Stats) -> Result<(), Fault> {
        if let Some(log) = self.log {
            let cols = self.part_at(at, 2 * N, self.z.len());
            log.borrow_mut().samples.push((t, cols));
        }
        Ok(())
    }
    fn event_located(&mut self, t: f64, event: usize, _stats: &mut Stats) -> Result<(), Fault> {
        if let Some(log) = self.log {
            let cols = self.part_at(t, 2 * N, self.z.len());
            log.borrow_mut().events.push((t, event, cols));
        }
        Ok(())
    }
}
