//! The constrained variational midpoint step (RATTLE for the midpoint discrete Lagrangian):
//! the variational method of a constrained run, whose nodes satisfy g(q, t) = 0 and
//! G q̇ + ∂g/∂t = 0 to Newton's tolerance.
//!
//! One step from (q_k, p_k) at t_k (G_k = ∂g/∂q at q_k, ν and σ the scaled multipliers):
//!
//! ```text
//! p_k + (h/2)(∂L/∂q + F) − ∂L/∂q̇ + G_kᵀ ν / h = 0,   g(q_{k+1}, t_{k+1}) = 0        (q_{k+1}, ν)
//! p* = p_k + h (∂L/∂q + F) + G_kᵀ ν / h                                                    (L, F at the midpoint)
//! ∂L/∂q̇(q_{k+1}, q̇_{k+1}, t_{k+1}) = p* + G_{k+1}ᵀ σ,   G_{k+1} q̇_{k+1} + ∂g/∂t = 0      (q̇_{k+1}, σ)
//! p_{k+1} = p* + G_{k+1}ᵀ σ
//! ```
//!
//! The first line is the midpoint rule's discrete Euler–Lagrange equation
//! (see [`variational`](super::variational)) with the constraint force (h/2)G_kᵀμ, ν = (h²/2)μ,
//! and the position constraint at the new node; the third line puts the momentum on the
//! cotangent space of the constraints (the velocity constraint), with the force (h/2)G_{k+1}ᵀμ'.
//! Together they are the symmetric, symplectic RATTLE scheme for this discrete Lagrangian
//! (Marsden & West 2001, §3.5; Hairer, Lubich & Wanner, VII.1). Both solves are Newton's method
//! on an (N + K)-square system with the exact Jacobian ([M̃ −Gᵀ; G 0] blocks), which is regular
//! when the constrained system is, also where M alone is singular. A coordinate that neither L,
//! a force nor a constraint depends on keeps its momentum bit for bit.

use crate::linalg::{RANK_TOL, lu_solve_dyn};

use super::manifold::Manifold;
use super::newton::{MAX_NEWTON, corrected, inf_norm};
use super::state::Stats;
use super::state::{Fault, Y};
use super::stepper::{FixedGrid, Stepper};
use super::system::System;
use super::variational::{Midpoint, SINGULAR_STEP, between_nodes};

/// The RATTLE stepper; its state is (t_k, q_k, p_k, q̇_k), every node on the constraints.
pub(crate) struct Rattle<'a, const N: usize> {
    sys: &'a dyn System<N>,
    m: &'a dyn Manifold<N>,
    grid: FixedGrid,
    k: u64,
    t: f64,
    q: [f64; N],
    p: [f64; N],
    v: [f64; N],
    /// The last position multiplier (the next step's first guess).
    nu: Vec<f64>,
    t_old: f64,
    q_old: [f64; N],
    v_old: [f64; N],
}

/// The (N + K)-square Newton system [A −Gᵀ; G 0] [Δx; Δm] = [a; c], solved in place.
fn solve_bordered<const N: usize>(
    a: &[[f64; N]; N],
    gt_rows: &[[f64; N]],
    g_rows: &[[f64; N]],
    rhs_a: &[f64; N],
    rhs_c: &[f64],
) -> Result<([f64; N], Vec<f64>), ()> {
    let k = g_rows.len();
    let n = N + k;
    let bordered = || {
        let mut mat = vec![0.0; n * n];
        for i in 0..N {
            mat[i * n..i * n + N].copy_from_slice(&a[i]);
            for (j, row) in gt_rows.iter().enumerate() {
                mat[i * n + N + j] = -row[i];
            }
        }
        for (j, row) in g_rows.iter().enumerate() {
            mat[(N + j) * n..(N + j) * n + N].copy_from_slice(row);
        }
        mat
    };
    let scale = a
        .iter()
        .chain(gt_rows)
        .chain(g_rows)
        .fold(0.0_f64, |m, row| m.max(inf_norm(row)));
    let mut x: Vec<f64> = rhs_a.iter().chain(rhs_c).copied().collect();
    if lu_solve_dyn(&mut bordered(), &mut x, scale).is_err() {
        // The LU worked in place: the matrix again for the least-squares solve (redundant rows
        // only, so no copy on every iteration).
        x = least_squares(n, bordered(), rhs_a.iter().chain(rhs_c).copied().collect())?;
    }
    let mut dx = [0.0; N];
    dx.copy_from_slice(&x[..N]);
    Ok((dx, x[N..].to_vec()))
}

/// The least-norm least-squares solution of the n-square system `mat` x = b (row-major) where
/// LU found it singular: redundant constraints, whose rows of G depend on the others, leave the
/// multipliers undetermined while Δx is not; the singular values at or below √ε of the largest
/// are dropped, so the multipliers are the least-norm ones.
#[inline(never)]
fn least_squares(n: usize, mat: Vec<f64>, b: Vec<f64>) -> Result<Vec<f64>, ()> {
    let a = nalgebra::DMatrix::from_row_slice(n, n, &mat);
    if !a.iter().chain(&b).all(|x| x.is_finite()) {
        return Err(());
    }
    let svd = a.svd(true, true);
    let big = svd.singular_values.max();
    if big <= 0.0 {
        return Err(());
    }
    let x = svd
        .solve(&nalgebra::DVector::from_vec(b), RANK_TOL * big)
        .map_err(|_| ())?;
    Ok(x.iter().copied().collect())
}

impl<'a, const N: usize> Rattle<'a, N> {
    /// Starts at (t0, q0, q̇0), a state on the constraints, with p0 = ∂L/∂q̇(q0, q̇0, t0).
    pub(crate) fn new(
        sys: &'a dyn System<N>,
        m: &'a dyn Manifold<N>,
        grid: FixedGrid,
        q0: [f64; N],
        v0: [f64; N],
    ) -> Result<Self, Fault> {
        let p = sys.momenta(&q0, &v0, grid.t0);
        if !p.iter().all(|x| x.is_finite()) {
            return Err(Fault::NonFinite);
        }
        Ok(Rattle {
            sys,
            m,
            grid,
            k: 0,
            t: grid.t0,
            q: q0,
            p,
            v: v0,
            nu: vec![0.0; m.count()],
            t_old: grid.t0,
            q_old: q0,
            v_old: v0,
        })
    }

    /// The position step: (q_{k+1}, ν) from the discrete Euler–Lagrange equation with the
    /// constraint force and g(q_{k+1}) = 0; returns q_{k+1}, p* and the secant velocity.
    #[allow(clippy::type_complexity)]
    fn position(
        &mut self,
        t1: f64,
        stats: &mut Stats,
    ) -> Result<([f64; N], [f64; N], [f64; N]), Fault> {
        let h = t1 - self.t;
        let tm = self.t + 0.5 * h;
        let (q0, p0) = (self.q, self.p);
        let g0 = self.m.rows(&q0, &[0.0; N], self.t).jacobian;
        let mut q1 = [0.0; N];
        for i in 0..N {
            q1[i] = q0[i] + h * self.v[i];
        }
        let mut nu = self.nu.clone();
        let mut last_dx = f64::INFINITY;
        let mut r_norm = f64::NAN;
        for _ in 0..MAX_NEWTON {
            let mid = Midpoint::at(self.sys, &q0, &q1, &p0, h, tm, stats)?;
            let rows1 = self.m.rows(&q1, &[0.0; N], t1);
            let mut r = mid.r;
            let mut scale = mid.scale;
            for (j, row) in g0.iter().enumerate() {
                for i in 0..N {
                    let term = row[i] * nu[j] / h;
                    r[i] += term;
                    scale = scale.max(term.abs());
                }
            }
            // Each constraint against the size of the terms that cancel in it, at least its
            // gradient times max(|q|, 1) (the projection's floor: near q = 0 a loop's closure
            // j₅ − (0, 0, 1) still carries the rounding of its O(1) terms).
            // Within `k` roundings of the terms: k = 8 converged, k = 8000 converged if Newton
            // no longer gains (redundant rows: the least-squares step's own rounding, up to
            // 1/√ε of ε in the directions it keeps, is a floor above 8 ε).
            let q_size = inf_norm(&q1).max(1.0);
            let within = |k: f64| {
                inf_norm(&r) <= k * f64::EPSILON * scale
                    && rows1.jacobian.iter().enumerate().all(|(j, row)| {
                        let cs: f64 = (0..N).map(|i| (row[i] * q1[i]).abs()).sum();
                        let floor = inf_norm(row) * q_size;
                        rows1.value[j].abs() <= k * f64::EPSILON * cs.max(floor)
                    })
            };
            let previous = r_norm;
            r_norm = inf_norm(&r).max(inf_norm_slice(&rows1.value));
            if !r_norm.is_finite() {
                return Err(Fault::NonFinite);
            }
            let stalled = r_norm > 0.5 * previous && within(8000.0);
            if within(8.0) || stalled || last_dx <= 4.0 * f64::EPSILON * mid.x_scale {
                self.nu = nu;
                let mut p_star = p0;
                for i in 0..N {
                    p_star[i] += h * (mid.lq[i] + mid.forced.value[i]);
                }
                for (j, row) in g0.iter().enumerate() {
                    for i in 0..N {
                        p_star[i] += row[i] * self.nu[j] / h;
                    }
                }
                return Ok((q1, p_star, mid.v));
            }
            // [jac −G0ᵀ; G1 0][Δq; Δν] = [h R; −g(q1)].
            let (jac, _) = mid.jacobian(h);
            let mut hr = [0.0; N];
            for i in 0..N {
                hr[i] = h * r[i];
            }
            let neg_g: Vec<f64> = rows1.value.iter().map(|g| -g).collect();
            let (dq, dnu) =
                solve_bordered(&jac, &g0, &rows1.jacobian, &hr, &neg_g).map_err(|()| {
                    Fault::Newton {
                        iterations: stats.newton_iterations,
                        residual: r_norm,
                        reason: SINGULAR_STEP,
                    }
                })?;
            last_dx = corrected(&mut q1, &dq, &mut nu, &dnu, stats);
        }
        Err(Fault::Newton {
            iterations: MAX_NEWTON,
            residual: r_norm,
            reason: "Newton's method on the constrained midpoint (RATTLE) step did not converge",
        })
    }

    /// The velocity step: q̇_{k+1} and p_{k+1} = p* + G_{k+1}ᵀσ with ∂L/∂q̇ = p_{k+1} and
    /// G_{k+1} q̇_{k+1} + ∂g/∂t = 0.
    fn velocity(
        &self,
        q1: &[f64; N],
        t1: f64,
        p_star: &[f64; N],
        v_guess: [f64; N],
        stats: &mut Stats,
    ) -> Result<([f64; N], [f64; N]), Fault> {
        let rows1 = self.m.rows(q1, &[0.0; N], t1);
        let g1 = &rows1.jacobian;
        let gt = &rows1.rate; // ∂g/∂t (q̇ = 0)
        let mut v = v_guess;
        let mut sigma = vec![0.0; g1.len()];
        let mut last_dv = f64::INFINITY;
        let mut r_norm = f64::NAN;
        for _ in 0..MAX_NEWTON {
            let jet = self.sys.hessian_jet(q1, &v, t1);
            stats.rhs_evals += 1;
            let lv = jet.grad_qdot();
            let mut p1 = *p_star;
            for (j, row) in g1.iter().enumerate() {
                for i in 0..N {
                    p1[i] += row[i] * sigma[j];
                }
            }
            let mut r = [0.0; N];
            let mut scale = 0.0_f64;
            for i in 0..N {
                r[i] = p1[i] - lv[i];
                scale = scale.max(p1[i].abs()).max(lv[i].abs());
            }
            let mut c = Vec::with_capacity(g1.len());
            let mut c_ok = true;
            for (j, row) in g1.iter().enumerate() {
                let cj: f64 = (0..N).map(|i| row[i] * v[i]).sum::<f64>() + gt[j];
                let cs: f64 = (0..N).map(|i| (row[i] * v[i]).abs()).sum::<f64>() + gt[j].abs();
                c_ok &= cj.abs() <= 8.0 * f64::EPSILON * cs.max(f64::MIN_POSITIVE);
                c.push(cj);
            }
            r_norm = inf_norm(&r).max(inf_norm_slice(&c));
            if !r_norm.is_finite() {
                return Err(Fault::NonFinite);
            }
            if (inf_norm(&r) <= 8.0 * f64::EPSILON * scale && c_ok)
                || last_dv <= 4.0 * f64::EPSILON * inf_norm(&v)
            {
                return Ok((v, p1));
            }
            // [M −G1ᵀ; G1 0][Δv; Δσ] = [R; −c].
            let neg_c: Vec<f64> = c.iter().map(|x| -x).collect();
            let (dv, ds) =
                solve_bordered(&jet.hess_qdotqdot(), g1, g1, &r, &neg_c).map_err(|()| {
                    Fault::Newton {
                        iterations: stats.newton_iterations,
                        residual: r_norm,
                        reason: "the constrained inverse Legendre map (∂L/∂q̇ = p with G q̇ + ∂g/∂t \
                             = 0) is singular: the constrained system [M Gᵀ; G 0] is singular",
                    }
                })?;
            last_dv = corrected(&mut v, &dv, &mut sigma, &ds, stats);
        }
        Err(Fault::Newton {
            iterations: MAX_NEWTON,
            residual: r_norm,
            reason: "the constrained inverse Legendre map (∂L/∂q̇ = p with G q̇ + ∂g/∂t = 0) did \
                     not converge",
        })
    }
}

/// The largest absolute component of a slice.
fn inf_norm_slice(x: &[f64]) -> f64 {
    x.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

impl<const N: usize> Stepper<N> for Rattle<'_, N> {
    fn t(&self) -> f64 {
        self.t
    }
    fn t_prev(&self) -> f64 {
        self.t_old
    }
    fn last_state(&self) -> Y<N> {
        [self.q, self.v]
    }
    /// Not called (RATTLE nodes are on the constraints); taken as given.
    fn set_node(&mut self, y: Y<N>, _stats: &mut Stats) -> Result<(), Fault> {
        self.p = self.sys.momenta(&y[0], &y[1], self.t);
        self.q = y[0];
        self.v = y[1];
        Ok(())
    }
    fn advance(&mut self, _t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        let t1 = self.grid.time(self.k + 1);
        let (q1, p_star, v_secant) = self.position(t1, stats)?;
        let (v1, p1) = self.velocity(&q1, t1, &p_star, v_secant, stats)?;
        stats.steps += 1;
        self.k += 1;
        self.t_old = self.t;
        self.q_old = self.q;
        self.v_old = self.v;
        self.t = t1;
        self.q = q1;
        self.p = p1;
        self.v = v1;
        Ok(())
    }
    fn interp(&mut self, t: f64, _stats: &mut Stats) -> Result<Y<N>, Fault> {
        if t >= self.t {
            return Ok([self.q, self.v]);
        }
        Ok(between_nodes(
            (self.t_old, &self.q_old, &self.v_old),
            (self.t, &self.q, &self.v),
            t,
        ))
    }
    /// (q, q̇) at both nodes (`between_nodes`').
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, _stats: &mut Stats) -> Result<f64, Fault> {
        rows.extend_from_slice(&[[self.q_old, self.v_old], [self.q, self.v]]);
        Ok(self.t - self.t_old)
    }
}
