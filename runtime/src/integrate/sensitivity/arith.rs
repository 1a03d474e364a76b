//! The augmented state's arithmetic that the explicit Runge–Kutta steppers over it share (DOP853,
//! Dormand–Prince): the stage sums over the components that move, the error weights, the motion's
//! part of a state.

use crate::lagrangian::Lagrangian;

use super::super::state::Y;
use super::variation::Variation;

/// out = z + h Σ_j a_j k_j over the given coefficients (zeros skipped), on the components in
/// `moving` (elsewhere out already equals z: constant columns).
pub(super) fn combine_into(
    out: &mut [f64],
    z: &[f64],
    h: f64,
    a: &[f64],
    k: &[Vec<f64>],
    moving: &[(usize, usize)],
) {
    for &(lo, hi) in moving {
        let out = &mut out[lo..hi];
        out.copy_from_slice(&z[lo..hi]);
        for (j, &aj) in a.iter().enumerate() {
            if aj == 0.0 {
                continue;
            }
            let ha = h * aj;
            for (o, kj) in out.iter_mut().zip(&k[j][lo..hi]) {
                *o += ha * kj;
            }
        }
    }
}

/// e = Σ_j c_j k_j over the components in `moving` (a constant column's stays 0), stage by stage
/// (in that order each component's sum is the method's).
pub(super) fn weighted_into(e: &mut [f64], c: &[f64], k: &[Vec<f64>], moving: &[(usize, usize)]) {
    for &(lo, hi) in moving {
        let e = &mut e[lo..hi];
        e.fill(0.0);
        for (&cj, kj) in c.iter().zip(k) {
            if cj == 0.0 {
                continue;
            }
            for (e, k) in e.iter_mut().zip(&kj[lo..hi]) {
                *e += cj * k;
            }
        }
    }
}

/// The ranges of the augmented state that move: the motion and every column but a constant one
/// (adjacent ranges merged).
pub(super) fn moving<L: Lagrangian<N>, const N: usize>(
    var: &Variation<'_, L, N>,
) -> Vec<(usize, usize)> {
    let n2 = 2 * N;
    let mut out: Vec<(usize, usize)> = Vec::new();
    for c in 0..var.len() / n2 {
        // Block 0 is the motion, block c + 1 column c.
        if c > 0 && var.frozen(c - 1) {
            continue;
        }
        let (lo, hi) = (c * n2, (c + 1) * n2);
        match out.last_mut() {
            Some(last) if last.1 == lo => last.1 = hi,
            _ => out.push((lo, hi)),
        }
    }
    out
}

/// The error weights 1/w of a step from z to z1, into `inv`: the motion's components by their own
/// size (w = atol + rtol max(|z_i|, |z1_i|), the methods' norm); a column of variations by the
/// column's size (its largest component at either end of the step). A column is a direction, held
/// to rtol relative to its length: its components that pass near zero do not force steps at atol.
pub(super) fn inverse_weights(
    z: &[f64],
    z1: &[f64],
    n2: usize,
    rtol: f64,
    atol: f64,
    inv: &mut [f64],
) {
    for i in 0..n2 {
        inv[i] = 1.0 / (atol + rtol * z[i].abs().max(z1[i].abs()));
    }
    for col in (n2..z.len()).step_by(n2) {
        let r = col..col + n2;
        let scale = z[r.clone()]
            .iter()
            .chain(&z1[r.clone()])
            .fold(0.0_f64, |m, x| m.max(x.abs()));
        inv[r].fill(1.0 / (atol + rtol * scale));
    }
}

/// Σ (e_i/w_i)² over `lo..hi`.
pub(super) fn sum_sq(e: &[f64], inv: &[f64], lo: usize, hi: usize) -> f64 {
    e[lo..hi]
        .iter()
        .zip(&inv[lo..hi])
        .map(|(e, w)| (e * w) * (e * w))
        .sum()
}

/// The motion's part of an augmented state.
pub(crate) fn y_of<const N: usize>(z: &[f64]) -> Y<N> {
    [
        core::array::from_fn(|i| z[i]),
        core::array::from_fn(|i| z[N + i]),
    ]
}
