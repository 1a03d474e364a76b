//! The sensitivity of an event's time: at g(t*, x(t*)) = 0 the implicit function theorem gives
//! dt*/dx₀ = −(∂g/∂x · Φ(t*)) / ġ, with ġ = ∂g/∂t + ∂g/∂x · f the rate g crosses zero at.

use nalgebra::DMatrix;

use crate::lagrangian::Lagrangian;

use super::super::events::Event;
use super::result::EventSensitivity;

/// ∂g/∂(t, q, q̇) at (t, q, q̇) by the fourth-order central difference with steps
/// h = ε^(1/5) max(|x|, 1) per variable (truncation O(h⁴), round-off O(ε/h): about 1e-13
/// relative for a smooth g; exact to round-off for a g linear in the variable). Returns
/// (∂g/∂t, ∂g/∂(q, q̇)).
pub(super) fn gradient<const N: usize>(
    ev: &Event<'_, N>,
    t: f64,
    q: &[f64; N],
    v: &[f64; N],
) -> (f64, Vec<f64>) {
    let step = |x: f64| f64::EPSILON.powf(0.2) * x.abs().max(1.0);
    let d = |g: &dyn Fn(f64) -> f64, h: f64| {
        (8.0 * (g(h) - g(-h)) - (g(2.0 * h) - g(-2.0 * h))) / (12.0 * h)
    };
    let gt = d(&|dt| ev.value(t + dt, q, v), step(t));
    let mut grad = Vec::with_capacity(2 * N);
    for i in 0..N {
        grad.push(d(
            &|dx| {
                let mut qq = *q;
                qq[i] += dx;
                ev.value(t, &qq, v)
            },
            step(q[i]),
        ));
    }
    for i in 0..N {
        grad.push(d(
            &|dx| {
                let mut vv = *v;
                vv[i] += dx;
                ev.value(t, q, &vv)
            },
            step(v[i]),
        ));
    }
    (gt, grad)
}

/// The sensitivities at a hit of `ev` at t* with state (q, q̇) and variations `cols` (Φ's 2N
/// columns, then P parameter columns, each 2N long).
#[allow(clippy::too_many_arguments)]
pub(super) fn at_event<L: Lagrangian<N>, const N: usize>(
    sys: &L,
    ev: &Event<'_, N>,
    t: f64,
    q: &[f64; N],
    v: &[f64; N],
    cols: &[f64],
    params: usize,
    located_rate: Option<&[f64]>,
) -> EventSensitivity {
    let n2 = 2 * N;
    let phi = DMatrix::from_column_slice(n2, n2, &cols[..n2 * n2]);
    let dparams = DMatrix::from_column_slice(n2, params, &cols[n2 * n2..n2 * (n2 + params)]);
    let (gt, grad) = gradient(ev, t, q, v);
    // f = (q̇, q̈) at the hit; where the accelerations fail there (they did not a moment ago,
    // on the same state) the rate is unknown and the hit is treated as grazing.
    // Where the hit was located on a curve whose rate is not f (`Log::rates`), that rate.
    let f: Option<Vec<f64>> = match located_rate {
        Some(r) => Some(r.to_vec()),
        None => sys
            .accelerations(q, v, t)
            .ok()
            .map(|a| v.iter().chain(a.iter()).copied().collect()),
    };
    let (rate, scale) = match &f {
        Some(f) => {
            let terms = grad.iter().zip(f).map(|(g, f)| g * f);
            let rate = gt + terms.clone().sum::<f64>();
            let scale = gt.abs() + terms.map(f64::abs).sum::<f64>();
            (rate, scale)
        }
        None => (f64::NAN, f64::NAN),
    };
    // Grazing: ġ vanishes to round-off against the size of its terms.
    let transversal = rate.is_finite() && rate.abs() > 1e-12 * scale && rate != 0.0;
    let row = |m: &DMatrix<f64>| -> Vec<f64> {
        (0..m.ncols())
            .map(|j| -(0..n2).map(|i| grad[i] * m[(i, j)]).sum::<f64>() / rate)
            .collect()
    };
    let (dt_dx0, dt_dp, dstate_dx0) = match (&f, transversal) {
        (Some(f), true) => {
            let dt = row(&phi);
            let total = DMatrix::from_fn(n2, n2, |i, j| phi[(i, j)] + f[i] * dt[j]);
            (Some(dt), Some(row(&dparams)), Some(total))
        }
        _ => (None, None, None),
    };
    EventSensitivity {
        name: ev.name().to_string(),
        t,
        phi,
        dparams,
        gradient: grad,
        rate,
        dt_dx0,
        dt_dp,
        dstate_dx0,
    }
}
