//! The Taylor method over the motion and its variations: at each node the generated series of
//! the motion (`Lagrangian::series_in`) evaluated in [`Tangent`]s whose slopes at order 0 are the
//! columns of Φ (and of the parameters' sensitivities) at the node. The slopes of the k-th
//! coefficients are then the k-th coefficients of the variations: the Taylor series of the
//! variational equations, from the same generated code, to the same order. The step is the
//! motion's (Jorba–Zou from its last two coefficients, as [`Taylor`](super::super::taylor));
//! the variations' series are summed at it, and are their dense output.
//!
//! [`CHUNK`] columns per evaluation (`Tangent<CHUNK>`): Φ's 2N columns and the parameters' P in
//! ⌈(2N + P)/CHUNK⌉ evaluations. A parameter's explicit part ∂(x_k)/∂p comes from the same
//! evaluation where it has a direction in the kernels' parameters (a field: those slots are
//! seeded with the column's), exact; otherwise from a fourth-order central difference of the
//! series of the systems its closure builds at p ± h, p ± 2h (as the explicit methods take
//! ∂q̈/∂p).

use core::cell::RefCell;

use crate::error::DynamicsError;
use crate::lagrangian::Lagrangian;
use crate::tangent::Tangent;
use crate::taylor::{SeriesBuf, TaylorBuf};

use super::super::state::{Fault, Stats, Y};
use super::super::stepper::Stepper;
use super::super::taylor::{Carried, Taylor};
use super::variation::{Variation, central};
use super::{CHUNK, Log};

/// A parameter's four neighbouring systems' kernel parameters and series (scratch kept between
/// steps).
#[derive(Default)]
struct Neighbours<const N: usize> {
    params: [Vec<f64>; 4],
    series: [Vec<Y<N>>; 4],
}

/// What a Taylor sensitivity run carries with the motion: the columns and their series (the
/// Taylor stepper steps it as it steps a plain run, see [`Carried`]).
pub(crate) struct VarSeries<'s, 'l, L, const N: usize> {
    var: Variation<'s, L, N>,
    /// The columns at the current node (each 2N: δq then δq̇).
    cols: Vec<f64>,
    /// The columns' series at the current node (order k: every column's k-th coefficients).
    series: Vec<Vec<f64>>,
    /// The columns' series of the last step, from its start.
    old: Vec<Vec<f64>>,
    /// The series in tangents (scratch) and the kernels' parameters in tangents.
    out: Vec<[[Tangent<CHUNK>; N]; 2]>,
    buf: SeriesBuf<Tangent<CHUNK>>,
    params: Vec<Tangent<CHUNK>>,
    neighbours: Vec<Neighbours<N>>,
    /// The neighbours' series buffer.
    fbuf: TaylorBuf,
    log: Option<&'l RefCell<Log>>,
}

/// The Taylor stepper of a sensitivity run.
pub(crate) type VarTaylor<'s, 'l, L, const N: usize> = Taylor<'s, L, N, VarSeries<'s, 'l, L, N>>;

impl<'s, 'l, L: Lagrangian<N>, const N: usize> VarSeries<'s, 'l, L, N> {
    /// The Taylor stepper of the motion from (t0, y0) carrying the columns `cols0`.
    pub(crate) fn stepper(
        var: Variation<'s, L, N>,
        t0: f64,
        y0: Y<N>,
        cols0: &[f64],
        tol: f64,
        hmax: f64,
        log: Option<&'l RefCell<Log>>,
    ) -> VarTaylor<'s, 'l, L, N> {
        let neighbours = var.params.iter().map(|_| Neighbours::default()).collect();
        let sys = var.sys;
        let carried = VarSeries {
            var,
            cols: cols0.to_vec(),
            series: Vec::new(),
            old: Vec::new(),
            out: Vec::new(),
            buf: SeriesBuf::new(),
            params: Vec::new(),
            neighbours,
            fbuf: TaylorBuf::new(),
            log,
        };
        Taylor::carrying(sys, t0, y0, tol, hmax, carried)
    }

    /// [`column_series`](Self::column_series), with the fields' seeding compiled in only where
    /// a parameter has a direction in the kernels' parameters.
    fn columns(
        &mut self,
        motion: &mut Taylor<'_, L, N, Self>,
        rows: usize,
        install: bool,
        stats: &mut Stats,
    ) -> Result<(), Fault> {
        if self.var.fields.is_some() {
            self.column_series::<true>(motion, rows, install, stats)
        } else {
            self.column_series::<false>(motion, rows, install, stats)
        }
    }

    /// The columns' series at the current node with `rows` orders; the first evaluation's
    /// values are the motion's series, handed to the motion's stepper where `install`.
    fn column_series<const SEED: bool>(
        &mut self,
        motion: &mut Taylor<'_, L, N, Self>,
        rows: usize,
        install: bool,
        stats: &mut Stats,
    ) -> Result<(), Fault> {
        let n2 = 2 * N;
        let (t, y) = motion.node_state();
        let ncols = self.cols.len() / n2;
        self.series.resize(rows, Vec::new());
        for row in &mut self.series {
            row.clear();
            row.resize(self.cols.len(), 0.0);
        }
        self.out.resize(rows, [[Tangent::constant(0.0); N]; 2]);
        // The columns that move (a cyclic coordinate's column of Φ is constant: its series is
        // the column itself, then zeros), CHUNK per evaluation.
        let mut active = (0..ncols).filter(|&c| !self.var.frozen(c)).peekable();
        let mut first_chunk = true;
        while active.peek().is_some() {
            // Slot k carries column chunk[k] (ncols: unused).
            let mut chunk = [ncols; CHUNK];
            for (slot, c) in chunk.iter_mut().zip(&mut active) {
                *slot = c;
            }
            let cols = &self.cols;
            let seed = |c: usize, i: usize| {
                Tangent::new(
                    y[c][i],
                    core::array::from_fn(|k| {
                        cols.get(chunk[k] * n2 + c * N + i).copied().unwrap_or(0.0)
                    }),
                )
            };
            self.out[0] = [
                core::array::from_fn(|i| seed(0, i)),
                core::array::from_fn(|i| seed(1, i)),
            ];
            // A parameter's column with a direction in the kernels' parameters seeds those too:
            // its explicit part ∂f/∂p comes out of the same evaluation, exact.
            if let Some(f) = self.var.fields.filter(|_| SEED) {
                let (phi_cols, params) = (self.var.phi_cols, self.var.params);
                f.seed(&mut self.params, |k| {
                    let p = chunk[k].checked_sub(phi_cols)?;
                    params.get(p)?.slots.as_deref()
                });
            }
            stats.rhs_evals += 1;
            let ok = match L::series_in(
                &[self.var.sys],
                &mut self.params,
                Tangent::constant(t),
                &mut self.out,
                &mut self.buf,
            ) {
                Some(Ok(ok)) => ok,
                Some(Err(e)) => return Err(Fault::Dynamics(e)),
                None => return Err(Fault::NonFinite),
            };
            if !ok {
                return Err(Fault::Dynamics(DynamicsError::NonFinite {
                    t,
                    q: y[0].to_vec(),
                    qdot: y[1].to_vec(),
                    message: "the mass matrix is not positive definite here (its LDLᵀ has a \
                              pivot below the accuracy bound), which the Taylor series of the \
                              variational equations needs: use Method::Dop853 for this run"
                        .into(),
                }));
            }
            if first_chunk && install {
                let values = self
                    .out
                    .iter()
                    .map(|row| row.map(|part| part.map(Tangent::value)));
                motion.install(values);
            }
            first_chunk = false;
            for (row, out) in self.series.iter_mut().zip(&self.out) {
                for (k, &col) in chunk.iter().enumerate().filter(|&(_, &c)| c < ncols) {
                    let col = &mut row[col * n2..(col + 1) * n2];
                    for c in 0..2 {
                        for i in 0..N {
                            col[c * N + i] = out[c][i].slopes()[k];
                        }
                    }
                }
            }
        }
        // The constant columns' order 0 (their higher orders are the zeros set above).
        for c in (0..ncols).filter(|&c| self.var.frozen(c)) {
            self.series[0][c * n2..(c + 1) * n2].copy_from_slice(&self.cols[c * n2..(c + 1) * n2]);
        }
        // The parameters' explicit parts, order by order (order 0 is the state: none).
        let phi_cols = self.var.phi_cols;
        for (p, (nb, par)) in self.neighbours.iter_mut().zip(self.var.params).enumerate() {
            // Exact above where the parameter has a direction in the kernels' parameters.
            let Some((h, neighbours)) = par.difference.as_ref().filter(|_| par.slots.is_none())
            else {
                continue;
            };
            for ((sys, params), series) in neighbours.iter().zip(&mut nb.params).zip(&mut nb.series)
            {
                series.clear();
                series.resize(rows, y);
                stats.rhs_evals += 1;
                match L::series_in(&[sys], params, t, series, &mut self.fbuf) {
                    Some(Ok(_)) => {}
                    Some(Err(e)) => return Err(Fault::Dynamics(e)),
                    None => return Err(Fault::NonFinite),
                }
            }
            let at = (phi_cols + p) * n2;
            let each = &nb.series;
            for (k, row) in self.series.iter_mut().enumerate().skip(1) {
                for c in 0..2 {
                    for i in 0..N {
                        row[at + c * N + i] +=
                            central(*h, core::array::from_fn(|j| each[j][k][c][i]));
                    }
                }
            }
        }
        if !self.series.iter().flatten().all(|x| x.is_finite()) {
            return Err(Fault::NonFinite);
        }
        Ok(())
    }

    /// The columns at t in [t_prev, t].
    fn cols_at(&self, motion: &Taylor<'_, L, N, Self>, t: f64) -> Vec<f64> {
        if t >= motion.t() || self.old.is_empty() {
            return self.cols.clone();
        }
        sum(&self.old, t - motion.t_prev())
    }
}

/// Σ_k x_k τ^k by Horner's rule, component by component.
fn sum(series: &[Vec<f64>], tau: f64) -> Vec<f64> {
    let mut y = series[series.len() - 1].clone();
    for x in series.iter().rev().skip(1) {
        for (y, x) in y.iter_mut().zip(x) {
            *y = *y * tau + x;
        }
    }
    y
}

impl<'s, 'l, L: Lagrangian<N>, const N: usize> Carried<L, N> for VarSeries<'s, 'l, L, N> {
    fn advance(
        &mut self,
        motion: &mut Taylor<'_, L, N, Self>,
        t_end: f64,
        stats: &mut Stats,
    ) -> Result<(), Fault> {
        // The variations' series first: its first evaluation's values are the motion's series
        // (so the motion's own is not computed); where the motion widens its series (its top
        // coefficients vanish), the variations' are taken again to its length.
        self.columns(motion, motion.order() + 1, true, stats)?;
        let (h, t1) = motion.plan(t_end, stats)?;
        let rows = motion.node_series().len();
        if rows != self.series.len() {
            self.columns(motion, rows, false, stats)?;
        }
        let cols = sum(&self.series, h);
        if !cols.iter().all(|x| x.is_finite()) {
            return Err(Fault::NonFinite);
        }
        motion.take(h, t1, stats)?;
        self.cols = cols;
        core::mem::swap(&mut self.old, &mut self.series);
        Ok(())
    }
    fn recorded(&mut self, motion: &Taylor<'_, L, N, Self>, t: f64, at: f64) {
        if let Some(log) = self.log {
            let cols = self.cols_at(motion, at);
            log.borrow_mut().samples.push((t, cols));
        }
    }
    fn event_located(&mut self, motion: &Taylor<'_, L, N, Self>, t: f64, event: usize) {
        if let Some(log) = self.log {
            let cols = self.cols_at(motion, t);
            let y = motion.motion_at(t);
            log.borrow_mut().event(t, event, cols, &y, None);
        }
    }
}
