//! The Jacobian of the accelerations, ∂q̈/∂(q, q̇), where every method that needs it takes it
//! (the sensitivity runs' variational equations, Radau5's Newton matrix): the compiled q̈
//! evaluated in [`Tangent`]s where the system has one (the derivative of the generated code), the
//! jets otherwise (third derivatives of L: −M⁻¹K and −M⁻¹C).

use nalgebra::SMatrix;

use crate::error::DynamicsError;
use crate::lagrangian::Lagrangian;
use crate::linalg::{Ldlt, solve_symmetric};
use crate::linearize::jet_linearize;
use crate::tangent::Tangent;

/// How many directions one evaluation of the compiled kernels in [`Tangent`]s carries (the
/// Jacobian's, the Taylor method's columns). Φ's column of a cyclic coordinate is constant and
/// q̈ does not depend on that coordinate, so the heavy top (two of three cyclic) needs 4
/// directions: one evaluation of 4 slopes per stage (6.0× a plain DOP853 run with Φ, 4.6× the
/// Taylor method) against one of 8 (7.2×, 6.6×) or two of 3 (7.0×, 7.4×; BENCHMARKS.md).
pub(crate) const CHUNK: usize = 4;

/// The Jacobian blocks of q̈ at a state: ∂q̈/∂q = −M⁻¹K and ∂q̈/∂q̇ = −M⁻¹C.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Jacobian<const N: usize> {
    pub(crate) d_q: SMatrix<f64, N, N>,
    pub(crate) d_qdot: SMatrix<f64, N, N>,
}

impl<const N: usize> Jacobian<N> {
    /// ẋ = J x for one column x = (δq, δq̇) of 2N entries, into `out`.
    #[inline]
    pub(crate) fn apply(&self, x: &[f64], out: &mut [f64]) {
        let (Some(dq), Some(dv)) = (x.first_chunk::<N>(), x[N..].first_chunk::<N>()) else {
            return;
        };
        let (top, bottom) = out.split_at_mut(N);
        top.copy_from_slice(dv);
        for (i, o) in bottom.iter_mut().take(N).enumerate() {
            let mut s = 0.0;
            for j in 0..N {
                s += self.d_q[(i, j)] * dq[j] + self.d_qdot[(i, j)] * dv[j];
            }
            *o = s;
        }
    }
}

/// q̈ and its Jacobian from the compiled kernel in tangents: the directions q_i of the
/// coordinates that are not cyclic (q̈ does not depend on a cyclic one: its column is 0, and the
/// run has checked the declaration), then every q̇_i, [`CHUNK`] per evaluation (one evaluation
/// for the heavy top: θ, θ̇, φ̇, ψ̇). q̈ is the value of any evaluation. `None` where the system has
/// no compiled kernel, or where it declines at this state (a pivot test failed, a value or slope
/// not finite): the caller takes the jets.
pub(crate) fn compiled<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    params: &mut Vec<Tangent<CHUNK>>,
    q: &[f64; N],
    v: &[f64; N],
    t: f64,
) -> Option<([f64; N], Jacobian<N>)> {
    compiled_along::<L, N, false>(sys, params, None, true, q, v, t).map(|(a, jac, _)| (a, jac))
}

/// Directions in the compiled kernels' parameters (the fields): the slots' values `base` and,
/// per direction, ∂slot/∂p of every slot (see `Lagrangian::KERNEL_FIELDS`).
#[derive(Clone, Copy)]
pub(crate) struct Fields<'a> {
    pub(crate) base: &'a [f64],
    pub(crate) dirs: &'a [&'a [f64]],
}

impl Fields<'_> {
    /// The kernels' parameters in tangents: slot j's slope k is ∂slot_j/∂p of the direction
    /// `dir(k)` carries in slot k (0 where it carries none). Out of line: the plain evaluations'
    /// loops stay as they were.
    #[inline(never)]
    pub(crate) fn seed<'d>(
        &self,
        params: &mut Vec<Tangent<CHUNK>>,
        dir: impl Fn(usize) -> Option<&'d [f64]>,
    ) {
        let dirs: [Option<&[f64]>; CHUNK] = core::array::from_fn(dir);
        params.clear();
        params.extend(self.base.iter().enumerate().map(|(j, &x)| {
            Tangent::new(x, core::array::from_fn(|k| dirs[k].map_or(0.0, |d| d[j])))
        }));
    }
}

/// [`compiled`], and with `fields` also ∂q̈/∂p along each of its directions, exact (the kernel's
/// parameter slots seeded in the same tangents, after the state's directions: a direction fills
/// a chunk's unused slot at no extra evaluation). `params` is then rewritten at each evaluation.
/// Without `state` only the fields' directions are seeded (the Jacobian returned is then 0).
/// `SEED` false compiles the plain evaluation (no fields: the loop as it was).
pub(crate) fn compiled_along<L: Lagrangian<N>, const N: usize, const SEED: bool>(
    sys: &L,
    params: &mut Vec<Tangent<CHUNK>>,
    fields: Option<Fields<'_>>,
    state: bool,
    q: &[f64; N],
    v: &[f64; N],
    t: f64,
) -> Option<([f64; N], Jacobian<N>, Vec<[f64; N]>)> {
    let t = Tangent::constant(t);
    let (mut d_q, mut d_qdot) = (SMatrix::zeros(), SMatrix::zeros());
    let mut a = [0.0; N];
    let fields = fields.filter(|_| SEED);
    let extra = fields.map_or(0, |f| f.dirs.len());
    let mut d_p = vec![[0.0; N]; extra];
    let end = 2 * N + extra;
    let first = if state { 0 } else { 2 * N };
    let mut dirs = (first..end).filter(|&d| d >= N || !L::CYCLIC[d]).peekable();
    while dirs.peek().is_some() {
        // This evaluation's directions (slot k: direction chunk[k]; `end` for an unused slot).
        let mut chunk = [end; CHUNK];
        for (slot, d) in chunk.iter_mut().zip(&mut dirs) {
            *slot = d;
        }
        let seed = |x: f64, dir: usize| {
            Tangent::new(
                x,
                core::array::from_fn(|k| f64::from(u8::from(chunk[k] == dir))),
            )
        };
        if let Some(f) = fields {
            f.seed(params, |k| {
                chunk[k]
                    .checked_sub(2 * N)
                    .and_then(|p| f.dirs.get(p).copied())
            });
        }
        let tq = core::array::from_fn(|i| seed(q[i], i));
        let tv = core::array::from_fn(|i| seed(v[i], N + i));
        let (acc, ok) = L::accelerations_in(&[sys], params, &tq, &tv, t)?;
        if !ok {
            return None;
        }
        for (k, &dir) in chunk.iter().enumerate() {
            for (i, x) in acc.iter().enumerate() {
                if dir < N {
                    d_q[(i, dir)] = x.slopes()[k];
                } else if dir < 2 * N {
                    d_qdot[(i, dir - N)] = x.slopes()[k];
                } else if dir < end {
                    d_p[dir - 2 * N][i] = x.slopes()[k];
                }
            }
        }
        a = acc.map(Tangent::value);
    }
    Some((a, Jacobian { d_q, d_qdot }, d_p))
}

/// The compiled kernels' parameters of `sys` (the slots `Lagrangian::KERNEL_FIELDS` names), as
/// its kernels load them; `None` where it has no compiled kernel.
pub(crate) fn kernel_slots<L: Lagrangian<N>, const N: usize>(sys: &L) -> Option<Vec<f64>> {
    let mut slots = Vec::new();
    let z = [0.0; N];
    if L::accelerations_in::<f64>(&[sys], &mut slots, &z, &z, 0.0).is_some() {
        return Some(slots);
    }
    // A system too large for the generic q̈ kernel may still have the Taylor series.
    slots.clear();
    let mut out = vec![[z; 2]; 2];
    let mut buf = crate::taylor::SeriesBuf::new();
    L::series_in::<f64>(&[sys], &mut slots, 0.0, &mut out, &mut buf).map(|_| slots)
}

/// J = ∂f/∂y = [[0, I], [∂q̈/∂q, ∂q̈/∂q̇]] of f = (q̇, q̈) at y, from the compiled q̈ in
/// tangents where the system has one (Radau5's Newton matrix); `None` where it has none or the kernel declines at this state (the caller
/// takes the jets).
pub(crate) fn compiled_state_jacobian<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    q: &[f64; N],
    v: &[f64; N],
    t: f64,
) -> Option<nalgebra::DMatrix<f64>> {
    let (_, jac) = compiled(sys, &mut Vec::new(), q, v, t)?;
    let mut j = nalgebra::DMatrix::zeros(2 * N, 2 * N);
    for i in 0..N {
        j[(i, N + i)] = 1.0;
        for k in 0..N {
            j[(N + i, k)] = jac.d_q[(i, k)];
            j[(N + i, N + k)] = jac.d_qdot[(i, k)];
        }
    }
    Some(j)
}

/// ∂q̈/∂q and ∂q̈/∂q̇ at (q, q̇, t): −M⁻¹K and −M⁻¹C of the linearization about the motion
/// through the state.
pub(crate) fn jacobian<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    q: &[f64; N],
    v: &[f64; N],
    t: f64,
) -> Result<Jacobian<N>, DynamicsError> {
    let lin = jet_linearize(sys, q, v, t)?;
    let m: [[f64; N]; N] = core::array::from_fn(|i| core::array::from_fn(|j| lin.m[(i, j)]));
    let ldlt = Ldlt::factor(&m).ok();
    let solve = |b: [f64; N]| match &ldlt {
        Some(f) => Ok(f.solve(&b)),
        None => solve_symmetric(&m, &b),
    };
    let mut d_q = SMatrix::<f64, N, N>::zeros();
    let mut d_qdot = SMatrix::<f64, N, N>::zeros();
    for j in 0..N {
        let kj = solve(core::array::from_fn(|i| lin.k[(i, j)]));
        let cj = solve(core::array::from_fn(|i| lin.c[(i, j)]));
        match (kj, cj) {
            (Ok(kj), Ok(cj)) if kj.iter().chain(cj.iter()).all(|x| x.is_finite()) => {
                for i in 0..N {
                    d_q[(i, j)] = -kj[i];
                    d_qdot[(i, j)] = -cj[i];
                }
            }
            _ => {
                return Err(DynamicsError::NonFinite {
                    t,
                    q: q.to_vec(),
                    qdot: v.to_vec(),
                    message: "the mass matrix of the linearized motion is singular here, so \
                              the variational equations have no Jacobian: choose coordinates \
                              regular along the motion (Euler angles away from sin θ = 0)"
                        .into(),
                });
            }
        }
    }
    Ok(Jacobian { d_q, d_qdot })
}
