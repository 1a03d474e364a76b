//! DOP853 over the augmented state (the motion and its variations): the tableau, error
//! estimate, step-size control and 7th-order dense output of [`dop853`](super::super::dop853),
//! on a state whose length is known at run time (2N + 2N·columns: Rust's stable const generics
//! cannot size it from N).
//!
//! Every stage evaluates the motion and the variations together, so the variations are the
//! same Runge–Kutta method applied to the variational equations with the motion's steps: Φ is
//! the exact derivative of the discrete flow with respect to the initial state. The error norm is
//! the larger of DOP853's norm over the motion and its norm over the variations (each an RMS over
//! its own components), so both are held to the tolerance, as heyoka's `var_ode_sys` does by
//! integrating the augmented system as one. A variation's component is weighted by the size of
//! its column ([`inverse_weights`]), not by its own: a column is a direction, held to rtol
//! relative to its length, and a component passing near zero does not force steps at atol
//! (per-component weights took 22–26 % more steps than the motion alone on the heavy top, these
//! 12–13 %; BENCHMARKS.md).

use core::cell::RefCell;

use crate::lagrangian::Lagrangian;

use super::super::control::{Controller, StepControl, effective_atol, initial_step};
use super::super::dop853_coefficients::{A, C, D, E3, E5};
use super::super::state::{Fault, Stats, Y};
use super::super::stepper::Stepper;
use super::Log;
use super::arith::{combine_into, inverse_weights, moving, sum_sq, weighted_into, y_of};
use super::variation::{Jacobian, Variation};

/// The DOP853 stepper of the augmented state.
pub(crate) struct VarDop853<'s, 'l, L, const N: usize> {
    var: Variation<'s, L, N>,
    rtol: f64,
    atol: f64,
    t: f64,
    z: Vec<f64>,
    t_old: f64,
    z_old: Vec<f64>,
    h_old: f64,
    /// Stages; `k[12]` = F at the current node.
    k: Vec<Vec<f64>>,
    /// The Jacobian at the current node (a column replacement re-derives k[12] from it).
    jac: Jacobian<N>,
    /// A stage's argument (scratch).
    arg: Vec<f64>,
    /// The trial y₁ (scratch).
    z1: Vec<f64>,
    /// The components that move, as ranges: all but the constant columns of cyclic coordinates
    /// (which every stage argument, y₁ and node keep as they were set at the start).
    moving: Vec<(usize, usize)>,
    /// The two error estimates Σ E5_j k_j and Σ E3_j k_j, and the inverse error weights
    /// (scratch).
    e5: Vec<f64>,
    e3: Vec<f64>,
    inv: Vec<f64>,
    /// Dense-output rows of the last step once evaluated (8 × len).
    r: Option<Vec<Vec<f64>>>,
    sc: StepControl,
    log: Option<&'l RefCell<Log>>,
}

impl<'s, 'l, L: Lagrangian<N>, const N: usize> VarDop853<'s, 'l, L, N> {
    /// Starts at (t0, z0) (z0 the augmented state: y0 then the columns); the first step as for
    /// the motion alone (Hairer's estimate; the controller shrinks it if the variations need).
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
        debug_assert_eq!(z0.len(), n);
        let atol = effective_atol(atol);
        // Stages 0..=15, and a spare (16) for F at a trial point.
        let mut k = vec![vec![0.0; n]; 17];
        let jac = var.eval(t0, &z0, &mut k[12], stats)?;
        let y0 = y_of::<N>(&z0);
        let f0 = y_of::<N>(&k[12]);
        let h = initial_step(var.sys, t0, &y0, &f0, 8, rtol, atol, hmax, stats)?;
        // The scratch states start as z0: a constant column is never written again.
        let scratch = z0.clone();
        Ok(VarDop853 {
            moving: moving(&var),
            var,
            rtol,
            atol,
            t: t0,
            z_old: z0.clone(),
            z: z0,
            t_old: t0,
            h_old: 0.0,
            k,
            jac,
            arg: scratch.clone(),
            z1: scratch,
            e5: vec![0.0; n],
            e3: vec![0.0; n],
            inv: vec![0.0; n],
            r: None,
            sc: StepControl::new(
                h,
                hmax,
                Controller::new(1.0 / 8.0 - 0.04 * 0.2, 0.04, 0.333, 6.0),
            ),
            log,
        })
    }

    /// The time of the current node.
    pub(crate) fn node_time(&self) -> f64 {
        self.t
    }

    /// The augmented state at the current node.
    pub(crate) fn state(&self) -> &[f64] {
        &self.z
    }

    /// Replaces the columns at the current node (y unchanged) and their slopes (FSAL), from the
    /// Jacobian known there: no new evaluation.
    pub(crate) fn set_columns(&mut self, cols: &[f64]) {
        let n2 = 2 * N;
        self.z[n2..n2 + cols.len()].copy_from_slice(cols);
        self.var
            .refresh_columns(&self.jac, &self.z, &mut self.k[12]);
        self.r = None;
    }

    /// One attempt of size h: the stages 1..=11, y₁ into `z1`, ln err.
    fn attempt(&mut self, h: f64, stats: &mut Stats) -> Result<f64, Fault> {
        let n = self.z.len();
        for s in 1..12 {
            combine_into(&mut self.arg, &self.z, h, &A[s][..s], &self.k, &self.moving);
            let (_, tail) = self.k.split_at_mut(s);
            self.var
                .eval(self.t + C[s] * h, &self.arg, &mut tail[0], stats)?;
        }
        combine_into(
            &mut self.z1,
            &self.z,
            h,
            &A[12][..12],
            &self.k,
            &self.moving,
        );
        if !self.z1.iter().all(|x| x.is_finite()) {
            return Err(Fault::NonFinite);
        }
        let n2 = 2 * N;
        weighted_into(&mut self.e5, &E5, &self.k, &self.moving);
        weighted_into(&mut self.e3, &E3, &self.k, &self.moving);
        inverse_weights(&self.z, &self.z1, n2, self.rtol, self.atol, &mut self.inv);
        // DOP853's norm, over the motion and over the variations; the larger decides.
        let ln = |lo: usize, hi: usize| {
            let err5 = sum_sq(&self.e5, &self.inv, lo, hi);
            let err3 = sum_sq(&self.e3, &self.inv, lo, hi);
            let deno = err5 + 0.01 * err3;
            let deno = if deno <= 0.0 { 1.0 } else { deno };
            (h * err5).ln() - (deno * (hi - lo) as f64).ln() * 0.5
        };
        let ln_err = if n > n2 {
            ln(0, n2).max(ln(n2, n))
        } else {
            ln(0, n2)
        };
        Ok(ln_err)
    }

    /// The dense-output rows of the last step (three more stages), evaluated on first use.
    fn dense_output(&mut self, stats: &mut Stats) -> Result<&Vec<Vec<f64>>, Fault> {
        if self.r.is_none() {
            let n = self.z.len();
            let h = self.h_old;
            for s in 13..16 {
                combine_into(
                    &mut self.arg,
                    &self.z_old,
                    h,
                    &A[s][..s],
                    &self.k,
                    &self.moving,
                );
                let (_, tail) = self.k.split_at_mut(s);
                self.var
                    .eval(self.t_old + C[s] * h, &self.arg, &mut tail[0], stats)?;
            }
            let mut r = vec![vec![0.0; n]; 8];
            for (j, dj) in D.iter().enumerate() {
                for i in 0..n {
                    let mut w = 0.0;
                    for (m, d) in dj.iter().enumerate() {
                        if *d != 0.0 {
                            w += d * self.k[m][i];
                        }
                    }
                    r[4 + j][i] = h * w;
                }
            }
            for i in 0..n {
                let ydiff = self.z[i] - self.z_old[i];
                let bspl = h * self.k[0][i] - ydiff;
                r[0][i] = self.z_old[i];
                r[1][i] = ydiff;
                r[2][i] = bspl;
                r[3][i] = ydiff - h * self.k[12][i] - bspl;
            }
            self.r = Some(r);
        }
        match &self.r {
            Some(r) => Ok(r),
            None => Err(Fault::NonFinite),
        }
    }

    /// The augmented state's components `lo..hi` at t in [t_prev, t].
    pub(crate) fn part_at(
        &mut self,
        t: f64,
        lo: usize,
        hi: usize,
        stats: &mut Stats,
    ) -> Result<Vec<f64>, Fault> {
        if t >= self.t || self.h_old == 0.0 {
            return Ok(self.z[lo..hi].to_vec());
        }
        let s = (t - self.t_old) / self.h_old;
        let r = self.dense_output(stats)?;
        Ok((lo..hi).map(|i| eval_dense(r, i, s)).collect())
    }

    /// Takes one accepted step, not beyond `t_end`.
    pub(crate) fn step(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        let (head, tail) = self.k.split_at_mut(12);
        head[0].copy_from_slice(&tail[0]);
        loop {
            let (h, last) = self.sc.trial(self.t, t_end)?;
            let attempt = self.attempt(h, stats).and_then(|ln_err| {
                if ln_err <= 0.0 {
                    // F at the new point (into the spare stage 16): the next step's first stage
                    // and the dense output.
                    let jac = self
                        .var
                        .eval(self.t + h, &self.z1, &mut self.k[16], stats)?;
                    Ok((ln_err, Some(jac)))
                } else {
                    Ok((ln_err, None))
                }
            });
            match attempt {
                Ok((ln_err, Some(jac))) => {
                    self.sc.accept(h, ln_err, stats);
                    self.k.swap(12, 16);
                    self.jac = jac;
                    self.r = None;
                    self.t_old = self.t;
                    core::mem::swap(&mut self.z_old, &mut self.z);
                    core::mem::swap(&mut self.z, &mut self.z1);
                    self.h_old = h;
                    self.t = if last { t_end } else { self.t + h };
                    return Ok(());
                }
                Ok((ln_err, None)) => self.sc.reject(h, ln_err, stats),
                Err(f) => self.sc.shrink(h, f, stats),
            }
        }
    }

    /// Logs the variations at `at` as the sample's recorded at `t`.
    fn log_sample(&mut self, t: f64, at: f64, stats: &mut Stats) -> Result<(), Fault> {
        if let Some(log) = self.log {
            let cols = self.part_at(at, 2 * N, self.z.len(), stats)?;
            log.borrow_mut().samples.push((t, cols));
        }
        Ok(())
    }
}

/// DOP853's dense output of component i at s ∈ [0, 1] (as `dop853::eval_dense`).
fn eval_dense(r: &[Vec<f64>], i: usize, s: f64) -> f64 {
    let s1 = 1.0 - s;
    let conpar = r[4][i] + s * (r[5][i] + s1 * (r[6][i] + s * r[7][i]));
    r[0][i] + s * (r[1][i] + s1 * (r[2][i] + s * (r[3][i] + s1 * conpar)))
}

impl<L: Lagrangian<N>, const N: usize> Stepper<N> for VarDop853<'_, '_, L, N> {
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
        self.k[12][..N].copy_from_slice(&y[1]);
        self.r = None;
        Ok(())
    }
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        self.step(t_end, stats)
    }
    fn interp(&mut self, t: f64, stats: &mut Stats) -> Result<Y<N>, Fault> {
        let y = self.part_at(t, 0, 2 * N, stats)?;
        Ok(y_of::<N>(&y))
    }
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, stats: &mut Stats) -> Result<f64, Fault> {
        let h = self.h_old;
        let r = self.dense_output(stats)?;
        rows.extend(r.iter().map(|row| y_of::<N>(row)));
        Ok(h)
    }
    fn recorded(&mut self, t: f64, at: f64, stats: &mut Stats) -> Result<(), Fault> {
        self.log_sample(t, at, stats)
    }
    fn event_located(&mut self, t: f64, event: usize, stats: &mut Stats) -> Result<(), Fault> {
        if let Some(log) = self.log {
            let cols = self.part_at(t, 2 * N, self.z.len(), stats)?;
            log.borrow_mut().events.push((t, event, cols));
        }
        Ok(())
    }
}
