//! The saltation matrix of a jump: how a variation δy⁻ of the state just before a resetting
//! event fires becomes the variation δy⁺ after it.
//!
//! With the event's function h(t, y) crossing zero at t* and the reset y⁺ = R(t*, y⁻), a
//! variation δy⁻ moves the crossing by δt* = −(∂h/∂y δy⁻)/ḣ, ḣ = ∂h/∂t + ∂h/∂y f⁻, and the
//! state after it is R(t* + δt*, y⁻ + δy⁻ + f⁻ δt*) flowed back over −δt* with f⁺, so
//!
//! ```text
//! δy⁺ = S δy⁻,   S = ∂R/∂y + (f⁺ − ∂R/∂y f⁻ − ∂R/∂t) (∂h/∂y) / ḣ,
//! ```
//!
//! f∓ = (q̇, q̈) before and after the jump (Aizerman & Gantmacher, 1958; the form of Leine &
//! van Campen's "Discontinuous bifurcations", 2006). Φ after the jump is S Φ before it.
//! ∂R/∂(t, y) and ∂h/∂(t, y) come from fourth-order central differences (steps ε^(1/5) of each
//! variable's size: about 1e-13 relative for smooth maps, exact for maps linear in a variable,
//! as a bounce's is in the velocities).

use nalgebra::DMatrix;

use crate::error::DynamicsError;
use crate::lagrangian::Lagrangian;

use super::super::events::{Event, Side};
use super::super::state::{Fault, Y};
use super::central;
use super::event_time::gradient;

/// S at the jump of `ev` at t from `before` to `after` (a 2N × 2N matrix, y = (q, q̇)).
pub(super) fn saltation<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    ev: &Event<'_, N>,
    t: f64,
    before: &Y<N>,
    after: &Y<N>,
) -> Result<DMatrix<f64>, Fault> {
    // A modal event (a contact's) is evaluated in the mode before the jump (f⁻, h and the
    // reset's differences, each reset undone), then in the mode after it (f⁺).
    let side = |s: Side| {
        ev.side(s).map_err(|message| {
            Fault::Dynamics(DynamicsError::NonFinite {
                t,
                q: before[0].to_vec(),
                qdot: before[1].to_vec(),
                message,
            })
        })
    };
    side(Side::Before)?;
    let jump = reset_derivatives(sys, ev, t, before);
    side(Side::After)?;
    let (f_minus, rate, hy, rt, ry) = jump?;
    let a = sys.accelerations(&after[0], &after[1], t)?;
    let f_plus: Vec<f64> = after[1].iter().chain(a.iter()).copied().collect();
    // S = R_y + (f⁺ − R_y f⁻ − R_t) h_yᵀ / ḣ.
    let n2 = 2 * N;
    let mut s = ry.clone();
    for i in 0..n2 {
        let ry_f: f64 = (0..n2).map(|k| ry[(i, k)] * f_minus[k]).sum();
        let w = (f_plus[i] - ry_f - rt[i]) / rate;
        for k in 0..n2 {
            s[(i, k)] += w * hy[k];
        }
    }
    if s.iter().all(|x| x.is_finite()) {
        Ok(s)
    } else {
        Err(Fault::NonFinite)
    }
}

/// What the saltation matrix takes from the side before the jump: f⁻, the event's rate ḣ and
/// ∂h/∂y, and the reset's ∂R/∂t and ∂R/∂y.
type BeforeJump = (Vec<f64>, f64, Vec<f64>, Vec<f64>, DMatrix<f64>);

/// [`BeforeJump`] at the jump of `ev` at t from `before`.
fn reset_derivatives<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    ev: &Event<'_, N>,
    t: f64,
    before: &Y<N>,
) -> Result<BeforeJump, Fault> {
    let n2 = 2 * N;
    let a = sys.accelerations(&before[0], &before[1], t)?;
    let f_minus: Vec<f64> = before[1].iter().chain(a.iter()).copied().collect();
    let (ht, hy) = gradient(ev, t, &before[0], &before[1]);
    let rate = ht + (0..n2).map(|k| hy[k] * f_minus[k]).sum::<f64>();
    let scale = (0..n2).map(|k| (hy[k] * f_minus[k]).abs()).sum::<f64>() + ht.abs();
    if rate.is_nan() || rate.abs() <= 1e-9 * scale {
        return Err(Fault::Dynamics(DynamicsError::NonFinite {
            t,
            q: before[0].to_vec(),
            qdot: before[1].to_vec(),
            message: format!(
                "event \"{}\" fires grazing (its function crosses zero at the rate {rate:e}): \
                 the derivative of the jump's time, and of the flow through the jump, is not \
                 defined there; start the sensitivity run where the crossing is transversal",
                ev.name()
            ),
        }));
    }
    // R at a perturbed (t, y⁻), flattened.
    let reset = |dt: f64, k: Option<(usize, f64)>| -> Result<Vec<f64>, Fault> {
        let mut y = *before;
        if let Some((k, dx)) = k {
            y[k / N][k % N] += dx;
        }
        match ev.try_reset(t + dt, &y[0], &y[1]) {
            Some(r) => Ok(r?.iter().flatten().copied().collect()),
            None => Err(Fault::NonFinite),
        }
    };
    let d = |at: &dyn Fn(f64) -> Result<Vec<f64>, Fault>, h: f64| -> Result<Vec<f64>, Fault> {
        let (p1, m1, p2, m2) = (at(h)?, at(-h)?, at(2.0 * h)?, at(-2.0 * h)?);
        Ok((0..n2)
            .map(|i| central(h, [p1[i], m1[i], p2[i], m2[i]]))
            .collect())
    };
    let step = |x: f64| f64::EPSILON.powf(0.2) * x.abs().max(1.0);
    let rt = d(&|dt| reset(dt, None), step(t))?;
    let mut ry = DMatrix::zeros(n2, n2);
    for k in 0..n2 {
        let col = d(&|dx| reset(0.0, Some((k, dx))), step(before[k / N][k % N]))?;
        for i in 0..n2 {
            ry[(i, k)] = col[i];
        }
    }
    Ok((f_minus, rate, hy, rt, ry))
}
