//! The variational midpoint integrator: the discrete Lagrangian
//! L_d(q_k, q_{k+1}) = h · L((q_k + q_{k+1})/2, (q_{k+1} − q_k)/h, t_k + h/2) in position–momentum
//! form, p_k = −D₁L_d(q_k, q_{k+1}), p_{k+1} = D₂L_d(q_k, q_{k+1}), solved by Newton's method with
//! the exact Jacobian from the Hessian jet.
//!
//! Written out, the implicit equation for q_{k+1} is
//! R(q_{k+1}) = p_k + (h/2) ∂L/∂q − ∂L/∂q̇ = 0 (L and its derivatives at the midpoint), and then
//! p_{k+1} = (h/2) ∂L/∂q + ∂L/∂q̇ = p_k + h ∂L/∂q − R. At the converged solution (R at round-off)
//! we use p_{k+1} = p_k + h ∂L/∂q: for a cyclic coordinate ∂L/∂q is exactly zero, so its
//! momentum is carried over bit for bit.
//!
//! Generalized forces and dissipation enter by the discrete Lagrange–d'Alembert principle
//! (forced variational integrators, Marsden and West 2001, §3.2): the applied force
//! F = Q − ∂D/∂q̇ at the midpoint, (h/2)·F, is added to both discrete momenta, so
//! R = p_k + (h/2)(∂L/∂q + F) − ∂L/∂q̇ and p_{k+1} = p_k + h (∂L/∂q + F). A cyclic coordinate on
//! which no force acts still keeps its momentum bit for bit while the others are damped or
//! driven.
//!
//! Velocities at the nodes are *not* the secant (q_{k+1} − q_k)/h: the integrator reports
//! q̇_k = (∂L/∂q̇)⁻¹(q_k, p_k, t_k), the velocity whose Legendre transform is the discrete momentum
//! (solved by Newton with the mass matrix). So (q_k, q̇_k) is a consistent state: the momenta
//! computed from it are the conserved p_k, and the energy from it is the integrator's energy.

use nalgebra::DMatrix;

use crate::eom::solve_mass_matrix;
use crate::jet::HessianJet;
use crate::lagrangian::AppliedJacobian;
use crate::linalg::lu_solve;

use super::newton::{self, Residual, inf_norm};
use super::state::Stats;
use super::state::{Fault, Y};
use super::stepper::{FixedGrid, Stepper};
use super::system::System;

/// The variational midpoint stepper; its own state is (t_k, q_k, p_k).
pub(crate) struct VariationalMidpoint<'a, const N: usize> {
    sys: &'a dyn System<N>,
    grid: FixedGrid,
    k: u64,
    t: f64,
    q: [f64; N],
    p: [f64; N],
    /// q̇ at the node, once the Legendre map has been inverted there.
    v: Option<[f64; N]>,
    /// The best velocity guess at the node (the last secant velocity).
    v_guess: [f64; N],
    t_old: f64,
    q_old: [f64; N],
    v_old: [f64; N],
    /// A sensitivity run's variations, carried through the steps.
    var: Option<Variations<'a, N>>,
}

/// A parameter's difference step h and the systems at p + h, p − h, p + 2h, p − 2h.
pub(crate) type Neighbours<'a, const N: usize> = (f64, [&'a dyn System<N>; 4]);

/// ∂/∂p of the rows x(sys) by the fourth-order central difference over a parameter's
/// neighbours (each neighbour evaluated once for all its rows).
fn by_parameter<const N: usize, const M: usize>(
    (h, systems): &Neighbours<'_, N>,
    x: impl Fn(&dyn System<N>) -> [[f64; N]; M],
) -> [[f64; N]; M] {
    let [a, b, c, d] = systems.map(x);
    core::array::from_fn(|r| {
        core::array::from_fn(|i| {
            super::sensitivity::central(*h, [a[r][i], b[r][i], c[r][i], d[r][i]])
        })
    })
}

/// The variations a sensitivity run carries through the variational method: the derivative of
/// its discrete map (q_k, p_k) ↦ (q_{k+1}, p_{k+1}). Kept in (q, p) as Ψ = ∂(q, p)/∂y₀; Φ in
/// (q, q̇) at a node from the Legendre map's derivative there, dq̇ = L_q̇q̇⁻¹ (dp − L_q̇q dq).
struct Variations<'l, const N: usize> {
    /// Columns (2N rows each, column-major).
    cols: usize,
    /// The parameters' neighbouring systems (at p + h, p − h, p + 2h, p − 2h) and h, one per
    /// column after the first `cols − params.len()`: the discrete map's dependence on each by
    /// fourth-order differences of ∂L/∂q, ∂L/∂q̇ and F.
    params: Vec<Neighbours<'l, N>>,
    /// Ψ at the node.
    psi: DMatrix<f64>,
    /// Φ at the last node and at the one before it (None until asked).
    phi: Option<DMatrix<f64>>,
    phi_old: DMatrix<f64>,
    log: &'l core::cell::RefCell<super::sensitivity::Log>,
}

impl<'a, const N: usize> VariationalMidpoint<'a, N> {
    /// Starts at (t0, q0, q̇0) with p0 = ∂L/∂q̇(q0, q̇0, t0).
    pub(crate) fn new(sys: &'a dyn System<N>, grid: FixedGrid, q0: [f64; N], v0: [f64; N]) -> Self {
        let p = sys.momenta(&q0, &v0, grid.t0);
        VariationalMidpoint {
            sys,
            grid,
            k: 0,
            t: grid.t0,
            q: q0,
            p,
            v: Some(v0),
            v_guess: v0,
            t_old: grid.t0,
            q_old: q0,
            v_old: v0,
            var: None,
        }
    }

    /// Carries the variations `phi` (column-major, 2N rows, of (q, q̇) at the start) through
    /// the run, recording them in `log` at the samples and event hits.
    // Out of line: a sensitivity run's large locals (Hessians of 64 coordinates) stay off
    // the plain step's frame.
    #[inline(never)]
    pub(crate) fn with_variations(
        mut self,
        phi: Vec<f64>,
        params: Vec<Neighbours<'a, N>>,
        log: &'a core::cell::RefCell<super::sensitivity::Log>,
    ) -> Self {
        let n = 2 * N;
        let cols = phi.len() / n;
        let phi = DMatrix::from_column_slice(n, cols, &phi);
        let v = self.v.unwrap_or(self.v_guess);
        let jet = self.sys.hessian_jet(&self.q, &v, self.t);
        // dp = L_q̇q dq + L_q̇q̇ dq̇ at the start, + ∂L_q̇/∂p for a parameter's column (the start
        // is given in (q, q̇): its momentum moves with p).
        let (hqv, hvv) = (jet.hess_qqdot(), jet.hess_qdotqdot());
        let mut psi = phi.clone();
        let first_param = cols - params.len();
        for c in 0..cols {
            let dp = match c.checked_sub(first_param).and_then(|k| params.get(k)) {
                Some(nb) => by_parameter(nb, |s| [s.momenta(&self.q, &v, self.t)])[0],
                None => [0.0; N],
            };
            for i in 0..N {
                psi[(N + i, c)] = (0..N)
                    .map(|k| hqv[k][i] * phi[(k, c)] + hvv[i][k] * phi[(N + k, c)])
                    .sum::<f64>()
                    + dp[i];
            }
        }
        self.var = Some(Variations {
            cols,
            params,
            psi,
            phi: Some(phi.clone()),
            phi_old: phi,
            log,
        });
        self
    }

    /// Ψ over the step just taken from (q₀, p₀) to q₁ with `m` the converged midpoint: with
    /// K₁ = −h ∂R/∂q₁ (the Newton matrix) and K₀ = −h ∂R/∂q₀,
    /// dq₁ = K₁⁻¹ (h dp₀ − K₀ dq₀), dp₁ = dp₀ + h (L_qq + F_q)(dq₀ + dq₁)/2 + (L_qq̇ + F_q̇)(dq₁ − dq₀).
    // Out of line: a sensitivity run's large locals (Hessians of 64 coordinates) stay off
    // the plain step's frame.
    #[inline(never)]
    fn vary(&mut self, m: &Midpoint<N>, h: f64) -> Result<(), Fault> {
        let Some(var) = self.var.as_mut() else {
            return Ok(());
        };
        let (jet, forced) = (&m.jet, &m.forced);
        let (hqq, hqv, hvv) = (jet.hess_qq(), jet.hess_qqdot(), jet.hess_qdotqdot());
        let (k1, _) = m.jacobian(h);
        let k1 = DMatrix::from_fn(N, N, |i, k| k1[i][k]);
        let k0 = DMatrix::from_fn(N, N, |i, k| {
            -hvv[i][k] - 0.25 * h * h * (hqq[i][k] + forced.d_q[i][k])
                + 0.5 * h * (hqv[k][i] + hqv[i][k])
                + 0.5 * h * forced.d_qdot[i][k]
        });
        let a = DMatrix::from_fn(N, N, |i, k| hqq[i][k] + forced.d_q[i][k]);
        let b = DMatrix::from_fn(N, N, |i, k| hqv[i][k] + forced.d_qdot[i][k]);
        let dq0 = var.psi.rows(0, N).into_owned();
        let dp0 = var.psi.rows(N, N).into_owned();
        let mut rhs = &dp0 * h - &k0 * &dq0;
        // A parameter's column: R and p_{k+1} − p_k = h (L_q + F) at the midpoint move with it,
        // K₁ dq₁ = h dp₀ − K₀ dq₀ + h ∂R/∂p and dp₁ += h ∂(L_q + F)/∂p.
        let first_param = var.cols - var.params.len();
        let mut dg = Vec::with_capacity(var.params.len());
        if !var.params.is_empty() {
            let (tm, qm): (f64, [f64; N]) = (
                self.t + 0.5 * h,
                core::array::from_fn(|i| self.q[i] + 0.5 * h * m.v[i]),
            );
            for (k, nb) in var.params.iter().enumerate() {
                let [d_lq, d_lv, d_f] = by_parameter(nb, |s| {
                    let jet = s.hessian_jet(&qm, &m.v, tm);
                    let f = s.applied_jacobian(&qm, &m.v, tm).value;
                    [jet.grad_q(), jet.grad_qdot(), f]
                });
                for i in 0..N {
                    let d_r = 0.5 * h * (d_lq[i] + d_f[i]) - d_lv[i];
                    rhs[(i, first_param + k)] += h * d_r;
                }
                dg.push(core::array::from_fn::<f64, N, _>(|i| d_lq[i] + d_f[i]));
            }
        }
        let dq1 = k1.lu().solve(&rhs).ok_or(Fault::Newton {
            iterations: 0,
            residual: f64::NAN,
            reason: SINGULAR_STEP,
        })?;
        let mut dp1 = &dp0 + (&a * (&dq0 + &dq1)) * (0.5 * h) + &b * (&dq1 - &dq0);
        for (k, g) in dg.iter().enumerate() {
            for i in 0..N {
                dp1[(i, first_param + k)] += h * g[i];
            }
        }
        var.psi.rows_mut(0, N).copy_from(&dq1);
        var.psi.rows_mut(N, N).copy_from(&dp1);
        if let Some(phi) = var.phi.take() {
            var.phi_old = phi;
        }
        Ok(())
    }

    /// Φ at the node (q, q̇), from Ψ by the Legendre map's derivative there.
    // Out of line: a sensitivity run's large locals (Hessians of 64 coordinates) stay off
    // the plain step's frame.
    #[inline(never)]
    fn phi_node(&mut self, stats: &mut Stats) -> Result<Option<DMatrix<f64>>, Fault> {
        if self.var.as_ref().is_none_or(|v| v.phi.is_some()) {
            return Ok(self.var.as_ref().and_then(|v| v.phi.clone()));
        }
        let [q, v] = self.node(stats)?;
        let jet = self.sys.hessian_jet(&q, &v, self.t);
        let (hqv, hvv) = (jet.hess_qqdot(), jet.hess_qdotqdot());
        let Some(var) = self.var.as_mut() else {
            return Ok(None);
        };
        let m = DMatrix::from_fn(N, N, |i, k| hvv[i][k]);
        let lvq = DMatrix::from_fn(N, N, |i, k| hqv[k][i]);
        let dq = var.psi.rows(0, N).into_owned();
        let mut rhs = var.psi.rows(N, N) - &lvq * &dq;
        // dq̇ = L_q̇q̇⁻¹ (dp − L_q̇q dq − ∂L_q̇/∂p) for a parameter's column.
        let first_param = var.cols - var.params.len();
        for (k, nb) in var.params.iter().enumerate() {
            let [d] = by_parameter(nb, |s| [s.momenta(&q, &v, self.t)]);
            for i in 0..N {
                rhs[(i, first_param + k)] -= d[i];
            }
        }
        let dv = m.lu().solve(&rhs).ok_or(Fault::NonFinite)?;
        let mut phi = var.psi.clone();
        phi.rows_mut(N, N).copy_from(&dv);
        var.phi = Some(phi.clone());
        Ok(Some(phi))
    }

    /// Φ at t in the last step: the interpolant's derivative (Hermite in q, linear in q̇) over
    /// Φ at both nodes.
    // Out of line: a sensitivity run's large locals (Hessians of 64 coordinates) stay off
    // the plain step's frame.
    #[inline(never)]
    fn phi_at(&mut self, t: f64, stats: &mut Stats) -> Result<Option<Vec<f64>>, Fault> {
        let Some(phi1) = self.phi_node(stats)? else {
            return Ok(None);
        };
        let Some(var) = self.var.as_ref() else {
            return Ok(None);
        };
        if t >= self.t || self.t == self.t_old {
            return Ok(Some(phi1.as_slice().to_vec()));
        }
        let h = self.t - self.t_old;
        let mut out = Vec::with_capacity(2 * N * var.cols);
        for c in 0..var.cols {
            let col = |m: &DMatrix<f64>| -> Y<N> {
                [
                    core::array::from_fn(|k| m[(k, c)]),
                    core::array::from_fn(|k| m[(N + k, c)]),
                ]
            };
            let y = across_step(self.t_old, h, &col(&var.phi_old), &col(&phi1), t);
            out.extend(y.iter().flatten());
        }
        Ok(Some(out))
    }

    /// Solves ∂L/∂q̇(q, v, t) = p for v by Newton's method with the mass matrix.
    fn legendre_inverse(&self, stats: &mut Stats) -> Result<[f64; N], Fault> {
        let mut v = self.v_guess;
        newton::solve(
            &mut v,
            stats,
            "the inverse Legendre map (solving ∂L/∂q̇ = p for q̇) did not converge",
            |v, stats| {
                let jet = self.sys.hessian_jet(&self.q, v, self.t);
                stats.rhs_evals += 1;
                let lv = jet.grad_qdot();
                let mut r = [0.0; N];
                for i in 0..N {
                    r[i] = self.p[i] - lv[i];
                }
                let scale = inf_norm(&self.p).max(inf_norm(&lv));
                if !r.iter().all(|x| x.is_finite()) {
                    return Err(Fault::NonFinite);
                }
                Ok(Residual {
                    r,
                    scale,
                    x_scale: inf_norm(v),
                    data: jet,
                })
            },
            |v, res, _r_norm, _stats| {
                let m = res.data.hess_qdotqdot();
                solve_mass_matrix(&m, &res.r, self.sys.flags().coordinates, &self.q, v, self.t)
                    .map_err(Fault::from)
            },
        )?;
        Ok(v)
    }
}

impl<const N: usize> Stepper<N> for VariationalMidpoint<'_, N> {
    fn t(&self) -> f64 {
        self.t
    }
    fn t_prev(&self) -> f64 {
        self.t_old
    }
    fn last_state(&self) -> Y<N> {
        [self.q, self.v.unwrap_or(self.v_guess)]
    }
    fn node(&mut self, stats: &mut Stats) -> Result<Y<N>, Fault> {
        if let Some(v) = self.v {
            return Ok([self.q, v]);
        }
        let v = self.legendre_inverse(stats)?;
        self.v = Some(v);
        Ok([self.q, v])
    }
    /// Never called: a constrained run steps the variational method with its own constrained
    /// step (RATTLE), whose nodes are on the constraints. Taken as given: q and p = ∂L/∂q̇.
    fn set_node(&mut self, y: Y<N>, _stats: &mut Stats) -> Result<(), Fault> {
        self.p = self.sys.momenta(&y[0], &y[1], self.t);
        self.q = y[0];
        self.v = Some(y[1]);
        Ok(())
    }
    fn advance(&mut self, _t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        // The left node's velocity is needed by the interpolant (events); compute it lazily there
        // — but for a sensitivity run now, with Φ there (the interpolant's left end).
        if self.var.is_some() {
            self.phi_node(stats)?;
        }
        let t1 = self.grid.time(self.k + 1);
        let h = t1 - self.t;
        let tm = self.t + 0.5 * h;
        let q0 = self.q;
        // Predictor: the last secant velocity (exact for uniform motion).
        let mut q1 = [0.0; N];
        for i in 0..N {
            q1[i] = q0[i] + h * self.v_guess[i];
        }
        let p0 = self.p;
        let solved = newton::solve(
            &mut q1,
            stats,
            "Newton's method on the implicit midpoint step did not converge",
            |q1, stats| {
                let m = Midpoint::at(self.sys, &q0, q1, &p0, h, tm, stats)?;
                Ok(Residual {
                    r: m.r,
                    scale: m.scale,
                    x_scale: m.x_scale,
                    data: m,
                })
            },
            |_q1, res, residual, stats| {
                // R + J Δq = 0 with J = −(1/h)·jac ⇒ jac · Δq = h R.
                let (jac, jscale) = res.data.jacobian(h);
                let mut rhs = [0.0; N];
                for i in 0..N {
                    rhs[i] = h * res.r[i];
                }
                lu_solve(&jac, &rhs, jscale).map_err(|_| Fault::Newton {
                    iterations: stats.newton_iterations,
                    residual,
                    reason: SINGULAR_STEP,
                })
            },
        );
        // Read in place: a moved copy of the converged midpoint (its Hessian jet) would double
        // the step's frame, which a 64-coordinate system's run on a 2 MiB thread cannot take.
        let (lq, f, v_secant) = match &solved {
            Ok(m) => {
                self.vary(m, h)?;
                (m.lq, m.forced.value, m.v)
            }
            Err(_) => return solved.map(|_| ()),
        };
        // p_{k+1} = p_k + h (∂L/∂q + F): a coordinate on which neither L nor a force depends
        // keeps its momentum bit for bit.
        let mut p1 = self.p;
        for i in 0..N {
            p1[i] += h * (lq[i] + f[i]);
        }
        stats.steps += 1;
        self.k += 1;
        self.t_old = self.t;
        self.q_old = self.q;
        self.v_old = self.v.unwrap_or(v_secant);
        self.t = t1;
        self.q = q1;
        self.p = p1;
        self.v = None;
        self.v_guess = v_secant;
        Ok(())
    }
    fn interp(&mut self, t: f64, stats: &mut Stats) -> Result<Y<N>, Fault> {
        let [q1, v1] = self.node(stats)?;
        if t >= self.t {
            return Ok([q1, v1]);
        }
        Ok(between_nodes(
            (self.t_old, &self.q_old, &self.v_old),
            (self.t, &q1, &v1),
            t,
        ))
    }
    /// (q, q̇) at both nodes (`between_nodes`'), the right one's q̇ from the Legendre map.
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, stats: &mut Stats) -> Result<f64, Fault> {
        let y1 = self.node(stats)?;
        rows.extend_from_slice(&[[self.q_old, self.v_old], y1]);
        Ok(self.t - self.t_old)
    }
    fn recorded(&mut self, t: f64, at: f64, stats: &mut Stats) -> Result<(), Fault> {
        if let Some(cols) = self.phi_at(at, stats)?
            && let Some(var) = self.var.as_ref()
        {
            var.log.borrow_mut().samples.push((t, cols));
        }
        Ok(())
    }
    fn event_located(&mut self, t: f64, event: usize, stats: &mut Stats) -> Result<(), Fault> {
        let Some(cols) = self.phi_at(t, stats)? else {
            return Ok(());
        };
        let y = self.interp(t, stats)?;
        // The hit is located on the interpolant, whose q̇ is linear between the nodes: its rate
        // there, not f, moves the hit's time.
        let [q1, v1] = self.node(stats)?;
        let rate = across_step_rate(
            self.t_old,
            self.t - self.t_old,
            &[self.q_old, self.v_old],
            &[q1, v1],
            t,
        );
        if let Some(var) = self.var.as_ref() {
            let rate = rate.iter().flatten().copied().collect();
            var.log.borrow_mut().event(t, event, cols, &y, Some(rate));
        }
        Ok(())
    }
}

/// (q, q̇) at t between two nodes (t₀, q₀, q̇₀) and (t₁, q₁, q̇₁) of a variational method: cubic
/// Hermite in q, q̇ linear between the nodes.
pub(super) fn between_nodes<const N: usize>(
    (t0, q0, v0): (f64, &[f64; N], &[f64; N]),
    (t1, q1, v1): (f64, &[f64; N], &[f64; N]),
    t: f64,
) -> Y<N> {
    across_step(t0, t1 - t0, &[*q0, *v0], &[*q1, *v1], t)
}

/// [`between_nodes`] on the step [t₀, t₀ + h] from the states y₀ = (q₀, q̇₀) and y₁ at its nodes
/// (h as the step computed it: t₁ − t₀).
pub(super) fn across_step<const N: usize>(t0: f64, h: f64, y0: &Y<N>, y1: &Y<N>, t: f64) -> Y<N> {
    let ([q0, v0], [q1, v1]) = (y0, y1);
    let s = (t - t0) / h;
    let h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
    let h10 = s * (1.0 - s) * (1.0 - s);
    let h01 = s * s * (3.0 - 2.0 * s);
    let h11 = s * s * (s - 1.0);
    let mut out = [[0.0; N]; 2];
    for i in 0..N {
        out[0][i] = h00 * q0[i] + h10 * h * v0[i] + h01 * q1[i] + h11 * h * v1[i];
        out[1][i] = (1.0 - s) * v0[i] + s * v1[i];
    }
    out
}

/// The rate d/dt of [`across_step`]'s interpolant at t.
fn across_step_rate<const N: usize>(t0: f64, h: f64, y0: &Y<N>, y1: &Y<N>, t: f64) -> Y<N> {
    let ([q0, v0], [q1, v1]) = (y0, y1);
    let s = (t - t0) / h;
    let d00 = 6.0 * s * s - 6.0 * s;
    let d10 = 3.0 * s * s - 4.0 * s + 1.0;
    let d01 = -d00;
    let d11 = 3.0 * s * s - 2.0 * s;
    let mut out = [[0.0; N]; 2];
    for i in 0..N {
        out[0][i] = (d00 * q0[i] + d01 * q1[i]) / h + d10 * v0[i] + d11 * v1[i];
        out[1][i] = (v1[i] - v0[i]) / h;
    }
    out
}

/// Why the Newton Jacobian of an implicit step could not be solved.
pub(super) const SINGULAR_STEP: &str = "the Newton Jacobian of the implicit step is singular (the \
     mass matrix ∂²L/∂q̇∂q̇ is singular or nearly so at the midpoint)";

/// The midpoint rule's discrete Euler–Lagrange residual at a trial q_{k+1}:
/// R = p_k + (h/2)(∂L/∂q + F) − ∂L/∂q̇ with L, its derivatives and the applied forces
/// F = Q − ∂D/∂q̇ at the midpoint ((q_k + q_{k+1})/2, (q_{k+1} − q_k)/h, t_k + h/2), and what the
/// Newton correction needs (shared by the unconstrained step and the constrained RATTLE step).
pub(super) struct Midpoint<const N: usize> {
    /// R.
    pub(super) r: [f64; N],
    /// The size of the terms of R.
    pub(super) scale: f64,
    /// The size of q_{k+1}.
    pub(super) x_scale: f64,
    /// ∂L/∂q at the midpoint.
    pub(super) lq: [f64; N],
    /// The secant velocity (q_{k+1} − q_k)/h.
    pub(super) v: [f64; N],
    /// L in the Hessian jet at the midpoint.
    pub(super) jet: HessianJet<N>,
    /// F and its Jacobians at the midpoint.
    pub(super) forced: AppliedJacobian<N>,
}

impl<const N: usize> Midpoint<N> {
    /// Evaluates R at q1 (one Hessian-jet evaluation of L, counted in `stats`).
    pub(super) fn at(
        sys: &dyn System<N>,
        q0: &[f64; N],
        q1: &[f64; N],
        p0: &[f64; N],
        h: f64,
        tm: f64,
        stats: &mut Stats,
    ) -> Result<Self, Fault> {
        let mut qm = [0.0; N];
        let mut v = [0.0; N];
        for i in 0..N {
            qm[i] = 0.5 * (q0[i] + q1[i]);
            v[i] = (q1[i] - q0[i]) / h;
        }
        let jet = sys.hessian_jet(&qm, &v, tm);
        // The applied forces F = Q − ∂D/∂q̇ at the midpoint (zero for a conservative system):
        // the discrete Lagrange–d'Alembert principle adds (h/2)·F to both discrete momenta.
        let forced = sys.applied_jacobian(&qm, &v, tm);
        stats.rhs_evals += 1;
        let lq = jet.grad_q();
        let lv = jet.grad_qdot();
        let f = forced.value;
        let mut r = [0.0; N];
        let mut scale = 0.0_f64;
        for i in 0..N {
            r[i] = p0[i] + 0.5 * h * lq[i] - lv[i] + 0.5 * h * f[i];
            scale = scale
                .max(p0[i].abs())
                .max(lv[i].abs())
                .max((0.5 * h * lq[i]).abs())
                .max((0.5 * h * f[i]).abs());
        }
        if !inf_norm(&r).is_finite() || !q1.iter().all(|x| x.is_finite()) {
            return Err(Fault::NonFinite);
        }
        Ok(Midpoint {
            r,
            scale,
            x_scale: inf_norm(q1).max(h * inf_norm(&v)),
            lq,
            v,
            jet,
            forced,
        })
    }

    /// −h·∂R/∂q_{k+1} = M − (h²/4) L_qq − (h/2)(L_qq̇ − L_qq̇ᵀ) − (h²/4) ∂F/∂q − (h/2) ∂F/∂q̇, and
    /// its largest entry.
    pub(super) fn jacobian(&self, h: f64) -> ([[f64; N]; N], f64) {
        let (jet, forced) = (&self.jet, &self.forced);
        let (hqq, hqv, hvv) = (jet.hess_qq(), jet.hess_qqdot(), jet.hess_qdotqdot());
        let mut jac = [[0.0; N]; N];
        let mut jscale = 0.0_f64;
        for i in 0..N {
            for kk in 0..N {
                jac[i][kk] = hvv[i][kk]
                    - 0.25 * h * h * hqq[i][kk]
                    - 0.5 * h * (hqv[i][kk] - hqv[kk][i])
                    - 0.25 * h * h * forced.d_q[i][kk]
                    - 0.5 * h * forced.d_qdot[i][kk];
                jscale = jscale.max(jac[i][kk].abs());
            }
        }
        (jac, jscale)
    }
}
