//! q̈ as explicit expressions, for the Taylor series: where the mass matrix is block diagonal in
//! 1×1 blocks and decoupled 2×2 blocks (`Derivation::pairs`), q̈ᵢ = fᵢ / mᵢᵢ and, for a pair
//! {i, k}, Cramer's rule over the pair's simplified determinant, the other acceleration by back
//! substitution when its diagonal entry is constant in time. The series of these nodes needs no
//! series of M and no solve per order (`taylor.rs`); a quotient by a determinant that is one
//! monomial (I⊥ I∥ sin²θ for the heavy top) has the atoms it shares with its numerator cancelled
//! and the numerator's remaining common factor taken out ([`quotient`]): the heavy top's
//! φ̈ = θ̇ ((I∥ − 2 I⊥) φ̇ cos θ + I∥ ψ̇) / (I⊥ sin θ), the closed form people write by hand.
//!
//! A system with a larger coupled block has none (`None`): its series solves M₀ a_k = f_k −
//! Σ M_j a_{k−j} order by order.

use std::collections::BTreeMap;

use super::dag::{Dag, Id};
use super::derive::Derivation;
use super::poly::{self, Mono, Poly};

/// The accelerations as nodes and what must hold at order 0 for them to be the solution.
pub struct Explicit {
    /// q̈ᵢ.
    pub accel: Vec<Id>,
    /// The divisors (a 1×1 block's entry, a pair's determinant, the diagonal entry a pair's back
    /// substitution divides by) whose order-0 values must be finite and not zero: where one is
    /// not, M₀ is singular (the determinants are exact) or not finite.
    pub tests: Vec<Id>,
}

/// The explicit accelerations of `d` in `dag` (a copy of the derivation's DAG that may grow), or
/// `None` where a coordinate sits in a coupled block of three or more, or a pair's determinant
/// did not cancel to one monomial (its Cramer solve would need the elimination's accuracy test
/// and, where that fails, the elimination).
pub fn accelerations(dag: &mut Dag, d: &Derivation) -> Option<Explicit> {
    let n = d.mass.len();
    let entry = |i: usize, k: usize| {
        let (a, b) = if i <= k { (i, k) } else { (k, i) };
        d.mass[a][b]
    };
    let mut accel = vec![Dag::ZERO; n];
    let mut done = vec![false; n];
    let mut tests = Vec::new();
    for &(i, k, det, exact) in &d.pairs {
        if !exact {
            return None;
        }
        let (mii, mkk, mik) = (entry(i, i), entry(k, k), entry(i, k));
        // Cramer for the coordinate whose partner's diagonal is constant, back substitution for
        // the partner (one quotient by the determinant instead of two).
        let (a, b, maa, mbb) = if dag.is_state_free(mii) && !dag.is_state_free(mkk) {
            (k, i, mkk, mii)
        } else {
            (i, k, mii, mkk)
        };
        let (fa, fb) = (d.rhs[a], d.rhs[b]);
        let (x, y) = (dag.mul(mbb, fa), dag.mul(mik, fb));
        let num = dag.sub(x, y);
        let qa = quotient(dag, num, det);
        let qb = if dag.is_state_free(mbb) {
            let m = dag.mul(mik, qa);
            let r = dag.sub(fb, m);
            tests.push(mbb);
            quotient(dag, r, mbb)
        } else {
            let (x, y) = (dag.mul(maa, fb), dag.mul(mik, fa));
            let num = dag.sub(x, y);
            quotient(dag, num, det)
        };
        accel[a] = qa;
        accel[b] = qb;
        done[a] = true;
        done[b] = true;
        tests.push(det);
    }
    for i in 0..n {
        if done[i] {
            continue;
        }
        if (0..n).any(|k| k != i && entry(i, k) != Dag::ZERO) {
            return None;
        }
        let m = entry(i, i);
        if m == Dag::ZERO {
            return None;
        }
        accel[i] = quotient(dag, d.rhs[i], m);
        tests.push(m);
    }
    Some(Explicit { accel, tests })
}

/// `num / den`, simplified where `den` expands to one monomial: the state-dependent atoms it
/// shares with every term of `num` cancel, and what `num`'s terms still share is taken out as
/// one product (each term's remaining state-dependent part built once, its state-free
/// coefficients summed: constants of the series). As written where nothing cancels.
fn quotient(dag: &mut Dag, num: Id, den: Id) -> Id {
    let plain = dag.div(num, den);
    if num == Dag::ZERO || dag.is_state_free(den) {
        return plain;
    }
    let Some(dp) = poly::expand(dag, den) else {
        return plain;
    };
    let Some((dmono, dcoef)) = dp.single() else {
        return plain;
    };
    let (dmono, dcoef) = (dmono.clone(), dcoef);
    let Some(np) = poly::expand_under(dag, num, &poly::SYMMETRY) else {
        return plain;
    };
    let state = |dag: &Dag, a: Id| !dag.is_state_free(a);
    // The state-dependent atoms every term has, at their least exponent.
    let mut common: Option<BTreeMap<Id, i32>> = None;
    for m in np.0.keys() {
        let here: BTreeMap<Id, i32> = m
            .iter()
            .filter(|&&(a, e)| e > 0 && state(dag, a))
            .copied()
            .collect();
        common = Some(match common {
            None => here,
            Some(c) => c
                .into_iter()
                .filter_map(|(a, e)| here.get(&a).map(|&h| (a, e.min(h))))
                .collect(),
        });
    }
    let Some(common) = common else {
        return plain;
    };
    // Cancel against the denominator's state-dependent atoms.
    let mut dmono: Mono<Id> = dmono;
    let mut cancel: BTreeMap<Id, i32> = BTreeMap::new();
    for (a, e) in dmono.iter_mut() {
        if *e <= 0 || !state(dag, *a) {
            continue;
        }
        if let Some(&c) = common.get(a) {
            let x = c.min(*e);
            if x > 0 {
                cancel.insert(*a, x);
                *e -= x;
            }
        }
    }
    if cancel.is_empty() {
        return plain;
    }
    dmono.retain(|&(_, e)| e != 0);
    // What the numerator's terms still share is the factor g; the rest, grouped by each term's
    // state-dependent part, is Σ (state-free coefficient) · (state-dependent product).
    let mut groups: BTreeMap<Vec<Id>, Poly<Id>> = BTreeMap::new();
    for (m, &c) in &np.0 {
        let mut state_part: Vec<Id> = Vec::new();
        let mut free_part: Mono<Id> = Vec::new();
        for &(a, e) in m {
            if state(dag, a) {
                let left = e - common.get(&a).copied().unwrap_or(0);
                state_part.extend(std::iter::repeat_n(a, usize::try_from(left).unwrap_or(0)));
            } else {
                free_part.push((a, e));
            }
        }
        poly::accumulate(groups.entry(state_part).or_default(), free_part, c);
    }
    let mut sum = Dag::ZERO;
    for (atoms, coef) in &groups {
        if coef.0.is_empty() {
            continue;
        }
        let k = poly::build(dag, coef);
        let p = dag.product(atoms);
        let term = dag.mul(k, p);
        sum = dag.add(sum, term);
    }
    let g: Vec<Id> = common
        .iter()
        .flat_map(|(&a, &e)| {
            let left = e - cancel.get(&a).copied().unwrap_or(0);
            std::iter::repeat_n(a, usize::try_from(left).unwrap_or(0))
        })
        .collect();
    let g = dag.product(&g);
    let top = dag.mul(g, sum);
    let mut den_free: Poly<Id> = Poly::default();
    let mut den_state: Vec<Id> = Vec::new();
    let mut free_mono: Mono<Id> = Vec::new();
    for &(a, e) in &dmono {
        if state(dag, a) {
            den_state.extend(std::iter::repeat_n(a, usize::try_from(e).unwrap_or(0)));
        } else {
            free_mono.push((a, e));
        }
    }
    poly::accumulate(&mut den_free, free_mono, dcoef);
    let kd = poly::build(dag, &den_free);
    let pd = dag.product(&den_state);
    let bottom = dag.mul(kd, pd);
    dag.div(top, bottom)
}
