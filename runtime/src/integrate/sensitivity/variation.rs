//! The variational equations as one right-hand side: the motion y = (q, q̇) with ẏ = f(t, y),
//! and its columns of first-order variations, each 2N long, with ẋ = J(t, y) x (+ ∂f/∂p for a
//! parameter's column), J = [[0, I], [∂q̈/∂q, ∂q̈/∂q̇]] exact: where the system has a compiled
//! q̈ (the symbolic mode), that kernel evaluated in [`Tangent`]s along q and q̇ (the derivative
//! of the generated code, [`CHUNK`] directions per evaluation, the cyclic coordinates' left out);
//! otherwise, or where
//! that kernel declines (a pivot test), from the jets ([`jet_linearize`]: third derivatives of L,
//! −M⁻¹K and −M⁻¹C). Forces, dissipation and explicit time are included either way.

use core::cell::RefCell;

use nalgebra::SMatrix;

use crate::error::DynamicsError;
use crate::lagrangian::Lagrangian;
use crate::tangent::Tangent;

use super::super::jacobian::{Fields, Jacobian, compiled_along, jacobian};
use super::super::state::{Fault, Stats, Y};
use super::CHUNK;

/// A parameter the run differentiates the motion with respect to: its name, its value in the
/// system of the run, and how ∂q̈/∂p is taken: exactly, along a direction of the compiled
/// kernels' parameters (the fields: `slots`, ∂slot/∂p per slot), and/or by the fourth-order
/// central difference ([`central`]) of the systems its closure builds at p + h, p − h, p + 2h,
/// p − 2h (built once, at [`Parameter::new`]), with the step h of [`difference_step`].
pub(crate) struct Parameter<L> {
    pub(crate) name: String,
    pub(crate) value: f64,
    /// ∂slot/∂p of every slot of the compiled kernels' parameters, where p moves them affinely
    /// (a field set to p; checked when the parameter is given): ∂q̈/∂p is then the kernel's
    /// derivative along it, exact.
    pub(crate) slots: Option<Vec<f64>>,
    /// The difference step h and the systems at p + h, p − h, p + 2h, p − 2h (a parameter given
    /// by its closure; a field has none).
    pub(crate) difference: Option<(f64, [L; 4])>,
}

impl<L> Parameter<L> {
    /// The parameter `name` at `value` with the difference step h, its neighbouring systems
    /// from `build`, and its direction in the kernels' parameters where it has one.
    pub(crate) fn new(
        name: String,
        value: f64,
        h: f64,
        build: impl Fn(f64) -> L,
        slots: Option<Vec<f64>>,
    ) -> Self {
        Parameter {
            name,
            value,
            slots,
            difference: Some((h, [h, -h, 2.0 * h, -2.0 * h].map(|dp| build(value + dp)))),
        }
    }

    /// The field of the kernels' parameters at slot `slot`, whose value is `value`: exact only.
    pub(crate) fn field(name: String, value: f64, slot: usize, count: usize) -> Self {
        let mut slots = vec![0.0; count];
        slots[slot] = 1.0;
        Parameter {
            name,
            value,
            slots: Some(slots),
            difference: None,
        }
    }
}

/// The directions of the parameters that have one ([`Parameter::slots`]), in order.
pub(crate) fn exact_dirs<L>(params: &[Parameter<L>]) -> Vec<&[f64]> {
    params.iter().filter_map(|p| p.slots.as_deref()).collect()
}

/// How `build(p)` moves the compiled kernels' parameters of `sys` near p = `value`: ∂slot/∂p per
/// slot where every slot is affine in p (a field set to p, 2p or p + c; conditions that do not
/// flip), at least one moves, and `build(value)` loads the slots `sys` loads (the closure
/// describes the system of the run). Checked at three points p, p + s, p + 2s (s a quarter of
/// p's binade [2^e, 2^(e+1)), towards its larger room: a field set to p moves by s exactly, and
/// its derivative comes out 1 exactly; one set to 3p by s to half an ulp of 3p, so ∂slot/∂p is
/// 3 to 2⁻⁴⁹ — an affine map does not need a small step). `None` otherwise, or where `sys` has no compiled kernel: the
/// parameter then takes the central difference.
pub(crate) fn affine_slots<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    value: f64,
    build: impl Fn(f64) -> L,
) -> Option<Vec<f64>> {
    use super::super::jacobian::kernel_slots;
    let base = kernel_slots(sys)?;
    if kernel_slots(&build(value))? != base || !value.is_finite() {
        return None;
    }
    // s = 2^(e−2), towards the binade's larger room (at least 2^(e−1) = 2s: p + 2s stays in it).
    let s = if value == 0.0 {
        0.25
    } else {
        let e = value.abs().log2().floor() as i32;
        let room_up = 2f64.powi(e + 1) - value.abs() > value.abs() - 2f64.powi(e);
        2f64.powi(e - 2) * if room_up == (value > 0.0) { 1.0 } else { -1.0 }
    };
    let one = kernel_slots(&build(value + s))?;
    let two = kernel_slots(&build(value + 2.0 * s))?;
    if one.len() != base.len() || two.len() != base.len() {
        return None;
    }
    let mut moved = false;
    let mut dirs = Vec::with_capacity(base.len());
    for ((&b, &x1), &x2) in base.iter().zip(&one).zip(&two) {
        let c = (x1 - b) / s;
        let scale = b.abs().max(x1.abs()).max(x2.abs());
        if !c.is_finite() || (x2 - b - 2.0 * c * s).abs() > 8.0 * f64::EPSILON * scale {
            return None;
        }
        moved |= c != 0.0;
        dirs.push(c);
    }
    moved.then_some(dirs)
}

/// The step h = ε^(1/5) s of a fourth-order central difference of `f` (a vector function of one
/// parameter, `None` where it fails) at p: truncation O(h⁴) and round-off O(ε/h) both near
/// 1e-13 relative when s is the scale on which f varies with p. That scale is not always |p|:
/// a mass of 1e-6 varies on 1e-6 (a step of 7e-4 would evaluate a negative mass), an offset
/// x₀ = 1000 in cos(x − x₀) on 1 (a step of 0.74 was 1 % off), a stiffness of 10⁸ on 10⁸ (a step
/// of 7e-4 is round-off). So both s = |p| and s = 1 are tried at the state given, each with its
/// Richardson error estimate |D(h) − D(h/2)|, and the one with the clearly smaller estimate is
/// taken; on a tie (both exact, or a dependence that vanishes at this state) the smaller step.
pub(crate) fn difference_step(p: f64, f: impl Fn(f64) -> Option<Vec<f64>>) -> f64 {
    let root = f64::EPSILON.powf(0.2);
    // |p|, or 1 at p = 0 (no scale to keep).
    let mut scales = [p.abs(), 1.0];
    if !(scales[0] > 0.0 && scales[0].is_finite()) {
        scales[0] = 1.0;
    }
    scales.sort_by(f64::total_cmp);
    // The fourth-order difference at step h, or None where an evaluation failed.
    let d4 = |h: f64| -> Option<Vec<f64>> {
        let v = [h, -h, 2.0 * h, -2.0 * h].map(|dp| f(p + dp));
        let [Some(a), Some(b), Some(c), Some(d)] = v else {
            return None;
        };
        let d: Vec<f64> = (0..a.len())
            .map(|i| central(h, [a[i], b[i], c[i], d[i]]))
            .collect();
        d.iter().all(|x| x.is_finite()).then_some(d)
    };
    let estimate = |h: f64| -> f64 {
        match (d4(h), d4(0.5 * h)) {
            (Some(a), Some(b)) => a
                .iter()
                .zip(&b)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs())),
            _ => f64::INFINITY,
        }
    };
    let mut best = (root * scales[0], estimate(root * scales[0]));
    if scales[1] != scales[0] {
        let h = root * scales[1];
        let e = estimate(h);
        if e < 0.5 * best.1 {
            best = (h, e);
        }
    }
    best.0
}

/// The fourth-order central difference from the values at p + h, p − h, p + 2h, p − 2h.
#[inline]
pub(crate) fn central(h: f64, [p1, m1, p2, m2]: [f64; 4]) -> f64 {
    (8.0 * (p1 - m1) - (p2 - m2)) / (12.0 * h)
}

/// The augmented right-hand side: y, then `2N + P` columns of 2N entries (the columns of Φ,
/// then one per parameter), stored one after the other.
pub(crate) struct Variation<'s, L, const N: usize> {
    pub(crate) sys: &'s L,
    pub(crate) params: &'s [Parameter<L>],
    /// How many columns of Φ (2N for the state transition matrix; any number k of directions
    /// for a Lyapunov run that follows k of them).
    pub(crate) phi_cols: usize,
    /// Whether the first columns are Φ's (unit vectors at the start): the column of a cyclic
    /// coordinate is then constant (shifting q_i shifts the motion: Φ e_i = e_i, J e_i = 0), and
    /// is not integrated.
    pub(crate) phi_unit: bool,
    /// The compiled kernels' parameters in tangents (loaded at the first call; seeded along the
    /// parameters' directions at every call where `fields` is given).
    pub(crate) kernel: RefCell<Vec<Tangent<CHUNK>>>,
    /// The kernels' parameter slots and the directions of the parameters that have one
    /// ([`exact_dirs`]): their ∂q̈/∂p from the kernel's tangents, exact. `None` without such a
    /// parameter.
    pub(crate) fields: Option<Fields<'s>>,
}

impl<'s, L: Lagrangian<N>, const N: usize> Variation<'s, L, N> {
    /// F(t, x) for the motion y and its columns (`cols`, 2N each) into `out_y` and `out_cols`.
    /// One evaluation counts once in `stats.rhs_evals`.
    /// With `plain_motion` the motion's q̈ comes from the plain kernel, so that a run on the
    /// plain run's steps moves as that run bit for bit (the tangent kernel orders its
    /// operations differently: the last bits differ).
    pub(crate) fn eval(
        &self,
        t: f64,
        (y, cols): (&Y<N>, &[f64]),
        (out_y, out_cols): (&mut Y<N>, &mut [f64]),
        plain_motion: bool,
        stats: &mut Stats,
    ) -> Result<(), Fault> {
        stats.rhs_evals += 1;
        let [q, v] = y;
        // A view whose accelerations are not L's own (a constrained run's) gives its Jacobian.
        let (a, jac, exact) = if let Some(own) = self.sys.first_order_jacobian(q, v, t) {
            let j = own?;
            let jac = Jacobian {
                d_q: SMatrix::from_fn(|i, k| j[(N + i, k)]),
                d_qdot: SMatrix::from_fn(|i, k| j[(N + i, N + k)]),
            };
            (self.sys.accelerations(q, v, t)?, jac, Vec::new())
        } else {
            let kernel = &mut self.kernel.borrow_mut();
            let both = if self.fields.is_some() {
                compiled_along::<L, N, true>(self.sys, kernel, self.fields, true, q, v, t)
            } else {
                compiled_along::<L, N, false>(self.sys, kernel, None, true, q, v, t)
            };
            match both {
                // q̈ from the plain kernel where the motion must be the plain run's bit for bit
                // (the tangent kernel orders its operations differently: the last bits differ).
                Some((_, jac, exact)) if plain_motion => {
                    (self.sys.accelerations(q, v, t)?, jac, exact)
                }
                Some(all) => all,
                None => (
                    self.sys.accelerations(q, v, t)?,
                    jacobian(self.sys, q, v, t)?,
                    Vec::new(),
                ),
            }
        };
        *out_y = [*v, a];
        let n2 = 2 * N;
        for c in 0..self.phi_cols {
            let at = n2 * c;
            if self.frozen(c) {
                out_cols[at..at + n2].fill(0.0);
            } else {
                jac.apply(&cols[at..at + n2], &mut out_cols[at..at + n2]);
            }
        }
        let mut exact = exact.iter();
        for (p, par) in self.params.iter().enumerate() {
            let at = n2 * (self.phi_cols + p);
            jac.apply(&cols[at..at + n2], &mut out_cols[at..at + n2]);
            // The kernel's exact ∂q̈/∂p where it gave them (in the order of the parameters that
            // have a direction), else the difference.
            let dp = match par.slots.as_ref().and_then(|_| exact.next()) {
                Some(d) => *d,
                None => par.difference_at(q, v, t)?,
            };
            for i in 0..N {
                out_cols[at + N + i] += dp[i];
            }
        }
        Ok(())
    }

    /// Whether column c is a cyclic coordinate's column of Φ, constant e_c.
    #[inline]
    pub(crate) fn frozen(&self, c: usize) -> bool {
        self.phi_unit && c < N && L::CYCLIC[c]
    }
}

impl<L> Parameter<L> {
    /// ∂q̈/∂p by the fourth-order central difference of the parameter's neighbouring systems'
    /// accelerations; for a field (no neighbours), the refusal: the compiled kernel declined
    /// here, and it is the field's only derivative.
    pub(crate) fn difference_at<const N: usize>(
        &self,
        q: &[f64; N],
        v: &[f64; N],
        t: f64,
    ) -> Result<[f64; N], DynamicsError>
    where
        L: Lagrangian<N>,
    {
        let Some((h, [p1, m1, p2, m2])) = &self.difference else {
            return Err(DynamicsError::NonFinite {
                t,
                q: q.to_vec(),
                qdot: v.to_vec(),
                message: format!(
                    "the compiled q̈ declines here (its LDLᵀ of M has a pivot below the accuracy \
                     bound, or a value is not finite), and the derivative with respect to field \
                     `{}` comes from it alone: give the parameter with its closure \
                     (`.parameter(name, value, build)`), whose differences stand in where the \
                     kernel declines",
                    self.name
                ),
            });
        };
        let (p1, m1, p2, m2) = (
            p1.accelerations(q, v, t)?,
            m1.accelerations(q, v, t)?,
            p2.accelerations(q, v, t)?,
            m2.accelerations(q, v, t)?,
        );
        Ok(core::array::from_fn(|i| {
            central(*h, [p1[i], m1[i], p2[i], m2[i]])
        }))
    }
}
