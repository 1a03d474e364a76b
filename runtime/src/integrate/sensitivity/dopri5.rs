//! Dormand–Prince 5(4) over the augmented state (the motion and its variations): the tableau, the
//! error estimate, the step-size control and the 4th-order continuous extension of
//! [`dopri5`](super::super::dopri5), on a state whose length is known at run time. As for DOP853
//! ([`dop853`](super::dop853)): the variations are the method applied to the variational
//! equations with the motion's steps, the error norm the larger of the motion's and the
//! variations' (a column weighted by its own size), the constant columns not stepped.

use core::cell::RefCell;

use crate::lagrangian::Lagrangian;

use super::super::control::{Controller, StepControl, effective_atol, initial_step};
use super::super::dopri5::{A, C, D, E};
use super::super::state::{Fault, Stats, Y};
use super::super::stepper::Stepper;
use super::Log;
use super::arith::{combine_into, inverse_weights, moving, sum_sq, weighted_into, y_of};
use super::variation::Variation;

/// The Dormand–Prince stepper of the augmented state.
pub(crate) struct VarDopri5<'s, 'l, L, const N: usize> {
    var: Variation<'s, L, N>,
    rtol: f64,
    atol: f64,
    t: f64,
    z: Vec<f64>,
    t_old: f64,
    h_old: f64,
    /// The stages; `k[0]` = F at the current node, `k[6]` = F at the trial point (FSAL).
    k: Vec<Vec<f64>>,
    /// A stage's argument, the trial y₁, the error estimate and the inverse weights (scratch).
    arg: Vec<f64>,
    z1: Vec<f64>,
    err: Vec<f64>,
    inv: Vec<f64>,
    /// The continuous extension of the last step (5 rows).
    r: Vec<Vec<f64>>,
    moving: Vec<(usize, usize)>,
    sc: StepControl,
    log: Option<&'l RefCell<Log>>,
}

impl<'s, 'l, L: Lagrangian<N>, const N: usize> VarDopri5<'s, 'l, L, N> {
    /// Starts at (t0, z0) (z0 the augmented state: y0 then the columns); the first step as for the
    /// motion alone (the controller shrinks it if the variations need).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        var: Variation<'s, L, N>,
        t0: f64,
        z0: Vec<f64>,
        rtol: f64,
        atol: f64,
        hmax: f64,
        log: Option<&'l RefCell<Log>>,
        stats: &mut Stats,
    ) -> Result<Self, Fault> {
        let n = var.len();
        let atol = effective_atol(atol);
        let mut k = vec![vec![0.0; n]; 7];
        var.eval(t0, &z0, &mut k[0], stats)?;
        let h = initial_step(
            var.sys,
            t0,
            &y_of::<N>(&z0),
            &y_of::<N>(&k[0]),
            5,
            rtol,
            atol,
            hmax,
            stats,
        )?;
        Ok(VarDopri5 {
            moving: moving(&var),
            var,
            rtol,
            atol,
            t: t0,
            t_old: t0,
            h_old: 0.0,
            k,
            // The scratch states start as z0: a constant column is never written again.
            arg: z0.clone(),
            z1: z0.clone(),
            err: vec![0.0; n],
            inv: vec![0.0; n],
            r: vec![
                z0.clone(),
                vec![0.0; n],
                vec![0.0; n],
                vec![0.0; n],
                vec![0.0; n],
            ],
            z: z0,
            // Hairer's defaults for dopri5, as the plain stepper.
            sc: StepControl::new(h, hmax, Controller::new(0.2 - 0.04 * 0.75, 0.04, 0.2, 10.0)),
            log,
        })
    }

    /// One attempt of size h: the stages, y₁ into `z1`, F there into `k[6]`, ln err.
    fn attempt(&mut self, h: f64, stats: &mut Stats) -> Result<f64, Fault> {
        for s in 1..6 {
            combine_into(&mut self.arg, &self.z, h, &A[s][..s], &self.k, &self.moving);
            self.var
                .eval(self.t + C[s] * h, &self.arg, &mut self.k[s], stats)?;
        }
        combine_into(&mut self.z1, &self.z, h, &A[6], &self.k, &self.moving);
        if !self.z1.iter().all(|x| x.is_finite()) {
            return Err(Fault::NonFinite);
        }
        self.var.eval(self.t + h, &self.z1, &mut self.k[6], stats)?;
        weighted_into(&mut self.err, &E, &self.k, &self.moving);
        let n2 = 2 * N;
        let n = self.z.len();
        inverse_weights(&self.z, &self.z1, n2, self.rtol, self.atol, &mut self.inv);
        // dopri5's norm √(Σ (h e/w)² / count), over the motion and over the variations.
        let ln = |lo: usize, hi: usize| {
            0.5 * (h * h * sum_sq(&self.err, &self.inv, lo, hi) / (hi - lo) as f64).ln()
        };
        Ok(if n > n2 {
            ln(0, n2).max(ln(n2, n))
        } else {
            ln(0, n2)
        })
    }

    /// Components `lo..hi` at t in [t_prev, t] (the continuous extension).
    fn part_at(&self, t: f64, lo: usize, hi: usize) -> Vec<f64> {
        if t >= self.t || self.h_old == 0.0 {
            return self.z[lo..hi].to_vec();
        }
        let (th, t1) = {
            let th = (t - self.t_old) / self.h_old;
            (th, 1.0 - th)
        };
        let r = &self.r;
        (lo..hi)
            .map(|i| r[0][i] + th * (r[1][i] + t1 * (r[2][i] + th * (r[3][i] + t1 * r[4][i]))))
            .collect()
    }
}

impl<L: Lagrangian<N>, const N: usize> Stepper<N> for VarDopri5<'_, '_, L, N> {
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
        self.k[0][..N].copy_from_slice(&y[1]);
        Ok(())
    }
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        loop {
            let (h, last) = self.sc.trial(self.t, t_end)?;
            match self.attempt(h, stats) {
                Ok(ln_err) if ln_err <= 0.0 => {
                    self.sc.accept(h, ln_err, stats);
                    // The continuous extension (rcont of dopri5.f) over every component.
                    weighted_into(&mut self.r[4], &D, &self.k, &[(0, self.z.len())]);
                    for i in 0..self.z.len() {
                        let ydiff = self.z1[i] - self.z[i];
                        let bspl = h * self.k[0][i] - ydiff;
                        self.r[0][i] = self.z[i];
                        self.r[1][i] = ydiff;
                        self.r[2][i] = bspl;
                        self.r[3][i] = ydiff - h * self.k[6][i] - bspl;
                        self.r[4][i] *= h;
                    }
                    self.t_old = self.t;
                    self.h_old = h;
                    self.t = if last { t_end } else { self.t + h };
                    core::mem::swap(&mut self.z, &mut self.z1);
                    self.k.swap(0, 6);
                    return Ok(());
                }
                Ok(ln_err) => self.sc.reject(h, ln_err, stats),
                Err(f) => self.sc.shrink(h, f, stats),
            }
        }
    }
    fn interp(&mut self, t: f64, _stats: &mut Stats) -> Result<Y<N>, Fault> {
        Ok(y_of::<N>(&self.part_at(t, 0, 2 * N)))
    }
    /// The 5 rows of the continuous extension of the motion, scaled by h.
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, _stats: &mut Stats) -> Result<f64, Fault> {
        rows.extend(self.r.iter().map(|row| y_of::<N>(row)));
        Ok(self.h_old)
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
