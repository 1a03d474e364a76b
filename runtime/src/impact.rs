//! The impact map of unilateral contacts: from the velocities before a collision to those after
//! it, derived from the mass matrix and the contacts' gradients alone.
//!
//! With the candidate contacts j (the colliding one, the closed ones, any other at zero gap),
//! their gap gradients n_j, rates before the impact v⁻_j = n_j·q̇⁻ + ∂g_j/∂t and restitution
//! coefficients e_j, the impulses Λ_j and the jump Δq̇ satisfy
//!
//! ```text
//! M Δq̇ = Σ_j n_j Λ_j (+ τ_j Λ_j^t for a sticking contact),
//! v⁺_j − b_j ≥ 0,  Λ_j ≥ 0,  (v⁺_j − b_j) Λ_j = 0,    b_j = −e_j min(v⁻_j, 0),
//! τ_j·q̇⁺ + ∂s_j/∂t = 0 where Λ_j > 0 (a sticking contact stops its contact point),
//! ```
//!
//! Newton's law on the rows that take an impulse, separation on the others: a linear
//! complementarity problem. For the few contacts that meet at once it is solved exactly, by
//! trying each set of impulse-taking contacts (smallest first) and keeping the first whose
//! solution satisfies every sign condition.
//!
//! ```
//! use lagrange_runtime::impact::{resolve, Candidate};
//! // A unit point mass in the plane hits the floor y = 0 at (ẋ, ẏ) = (1, −2) with e = 0.5.
//! let floor = Candidate { normal: [0.0, 1.0], rate: -2.0, restitution: 0.5, tangent: None };
//! let out = resolve(&[[1.0, 0.0], [0.0, 1.0]], &[1.0, -2.0], &[floor]).unwrap();
//! assert_eq!(out.qdot, [1.0, 1.0]);
//! assert_eq!((out.active, out.impulse), (vec![true], vec![(3.0, 0.0)]));
//! ```

use crate::linalg::lu_solve_dyn;

/// A contact that may take an impulse at an impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate<const N: usize> {
    /// ∂g/∂q.
    pub normal: [f64; N],
    /// ġ before the impact (with ∂g/∂t).
    pub rate: f64,
    /// Newton's restitution coefficient.
    pub restitution: f64,
    /// A sticking contact's ∂s/∂q and ṡ before the impact.
    pub tangent: Option<([f64; N], f64)>,
}

/// The outcome of an impact: the velocities after it, which candidates took an impulse, and
/// the impulses (normal, tangential) in the units of M q̇.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome<const N: usize> {
    /// q̇⁺.
    pub qdot: [f64; N],
    /// Whether candidate j took an impulse.
    pub active: Vec<bool>,
    /// (Λ_j, Λ_j^t), zero for a candidate that took none.
    pub impulse: Vec<(f64, f64)>,
}

/// Why an impact has no solution.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// No set of impulse-taking contacts satisfies the sign conditions (or every such set's
    /// system is singular: the contacts' gradients are dependent where they act together).
    NoSolution,
    /// Too many candidates for the exact enumeration (the limit is [`MAX_CANDIDATES`]).
    TooMany(usize),
    /// A value was not finite.
    NonFinite,
}

/// The most contacts one impact enumerates (2^12 sets).
pub const MAX_CANDIDATES: usize = 12;

/// The impact map: q̇⁺ from q̇⁻ under the mass matrix `mass` (full, symmetric) and the
/// candidate contacts (see the [module documentation](crate::impact)).
///
/// ```
/// use lagrange_runtime::impact::{resolve, Candidate, Failure};
/// // Two unit masses on a line, the first at a wall (g = x₁ ≥ 0, plastic), the second resting
/// // against it (g = x₂ − x₁ ≥ 0, elastic): both arrive at −1 and stop together.
/// let wall = Candidate { normal: [1.0, 0.0], rate: -1.0, restitution: 0.0, tangent: None };
/// let pair = Candidate { normal: [-1.0, 1.0], rate: 0.0, restitution: 1.0, tangent: None };
/// let out = resolve(&[[1.0, 0.0], [0.0, 1.0]], &[-1.0, -1.0], &[wall, pair]).unwrap();
/// assert_eq!(out.qdot, [0.0, 0.0]);
/// // A contact whose gradient vanishes cannot stop anything.
/// let none = Candidate { normal: [0.0, 0.0], rate: -1.0, restitution: 0.0, tangent: None };
/// assert_eq!(resolve(&[[1.0, 0.0], [0.0, 1.0]], &[-1.0, 0.0], &[none]), Err(Failure::NoSolution));
/// ```
pub fn resolve<const N: usize>(
    mass: &[[f64; N]; N],
    qdot: &[f64; N],
    candidates: &[Candidate<N>],
) -> Result<Outcome<N>, Failure> {
    resolve_constrained(mass, qdot, candidates, &[])
}

/// An equality constraint that holds through an impact: its row (∂g/∂q, or A of a velocity
/// constraint A q̇ + b = 0) and its rate before the impact (ġ⁻, or A q̇⁻ + b). After the impact
/// the rate is zero; its impulse may have either sign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Equality<const N: usize> {
    /// ∂g/∂q (or A).
    pub row: [f64; N],
    /// ġ before the impact (with ∂g/∂t).
    pub rate: f64,
}

/// The impact map with equality constraints holding through it: as [`resolve`], with
/// M Δq̇ = Σ_j n_j Λ_j + Σ_i G_iᵀ μ_i and every equality's rate zero after the impact (its
/// impulse μ_i free in sign). The equalities' rows must be independent of each other.
///
/// ```
/// use lagrange_runtime::impact::{resolve_constrained, Candidate, Equality};
/// // A pendulum of length 1 in x, y at the bottom (0, −1) moving left at 2, striking a wall
/// // x ≥ 0 there (e = 1): the rod keeps ẏ = 0, and ẋ reverses.
/// let wall = Candidate { normal: [1.0, 0.0], rate: -2.0, restitution: 1.0, tangent: None };
/// let rod = Equality { row: [0.0, -2.0], rate: 0.0 };
/// let out = resolve_constrained(&[[1.0, 0.0], [0.0, 1.0]], &[-2.0, 0.0], &[wall], &[rod]).unwrap();
/// assert_eq!(out.qdot, [2.0, 0.0]);
/// assert_eq!(out.impulse, vec![(4.0, 0.0)]);
/// ```
pub fn resolve_constrained<const N: usize>(
    mass: &[[f64; N]; N],
    qdot: &[f64; N],
    candidates: &[Candidate<N>],
    equalities: &[Equality<N>],
) -> Result<Outcome<N>, Failure> {
    let k = candidates.len();
    if k > MAX_CANDIDATES {
        return Err(Failure::TooMany(k));
    }
    let finite = mass
        .iter()
        .flatten()
        .chain(qdot.iter())
        .all(|x| x.is_finite())
        && equalities
            .iter()
            .all(|e| e.rate.is_finite() && e.row.iter().all(|x| x.is_finite()))
        && candidates.iter().all(|c| {
            c.normal.iter().all(|x| x.is_finite())
                && c.rate.is_finite()
                && c.restitution.is_finite()
                && c.tangent
                    .is_none_or(|(t, r)| r.is_finite() && t.iter().all(|x| x.is_finite()))
        });
    if !finite {
        return Err(Failure::NonFinite);
    }
    // The scales the sign tests are measured against: the largest approach speed, the largest
    // momentum change it could take.
    let vscale = candidates
        .iter()
        .map(|c| c.rate.abs())
        .fold(f64::MIN_POSITIVE, f64::max);
    let mscale = mass
        .iter()
        .flatten()
        .fold(0.0_f64, |m, x| m.max(x.abs()))
        .max(f64::MIN_POSITIVE);
    let target = |c: &Candidate<N>| -c.restitution * c.rate.min(0.0);
    // Sets of impulse-taking contacts, fewest first (none at all first of all) (then in order of the bit pattern).
    let mut sets: Vec<u32> = (0..(1u32 << k)).collect();
    sets.sort_by_key(|s| (s.count_ones(), *s));
    for set in sets {
        // The rows of this set: (gradient, required change of its rate, candidate, tangential?).
        // The equalities first (index `k`: no candidate), their rates brought to zero.
        let mut rows: Vec<(&[f64; N], f64, usize, bool)> = equalities
            .iter()
            .map(|e| (&e.row, -e.rate, k, false))
            .collect();
        for (j, c) in candidates.iter().enumerate() {
            if set & (1 << j) == 0 {
                continue;
            }
            rows.push((&c.normal, target(c) - c.rate, j, false));
            if let Some((t, rate)) = &c.tangent {
                rows.push((t, -rate, j, true));
            }
        }
        let r = rows.len();
        let n = N + r;
        // [M −Gᵀ; G 0] (Δq̇, Λ) = (0, Δv), each row of G scaled to unit largest entry.
        let mut a = vec![0.0; n * n];
        let mut x = vec![0.0; n];
        let mut scale_rows = vec![1.0; r];
        for i in 0..N {
            for c in 0..N {
                a[i * n + c] = mass[i][c] / mscale;
            }
        }
        for (m, (g, dv, _, _)) in rows.iter().enumerate() {
            let s = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            if s == 0.0 {
                // A vanishing gradient: this set cannot be solved.
                a.clear();
                break;
            }
            scale_rows[m] = 1.0 / s;
            for i in 0..N {
                a[i * n + N + m] = -g[i] / s;
                a[(N + m) * n + i] = g[i] / s;
            }
            x[N + m] = dv / s;
        }
        // No impulse: no jump (M may be singular, so no solve).
        if r == 0 {
            x.iter_mut().for_each(|v| *v = 0.0);
        } else if a.is_empty() || lu_solve_dyn(&mut a, &mut x, 1.0).is_err() {
            continue;
        }
        // Λ in the units of M q̇: the scaled solve's multipliers times mscale, unscaled per row.
        let lambda: Vec<f64> = (0..r).map(|m| x[N + m] * mscale * scale_rows[m]).collect();
        let dq: [f64; N] = core::array::from_fn(|i| x[i]);
        let lscale = lambda.iter().fold(f64::MIN_POSITIVE, |m, l| m.max(l.abs()));
        let mut ok = true;
        let mut impulse = vec![(0.0, 0.0); k];
        for (m, &(_, _, j, tangential)) in rows.iter().enumerate() {
            if j == k {
                // An equality's impulse: either sign.
            } else if tangential {
                impulse[j].1 = lambda[m];
            } else {
                impulse[j].0 = lambda[m];
                ok &= lambda[m] >= -1e-10 * lscale;
            }
        }
        for (j, c) in candidates.iter().enumerate() {
            if set & (1 << j) == 0 {
                let after = c.rate + (0..N).map(|i| c.normal[i] * dq[i]).sum::<f64>();
                ok &= after - target(c) >= -1e-10 * vscale;
            }
        }
        if ok {
            return Ok(Outcome {
                qdot: core::array::from_fn(|i| qdot[i] + dq[i]),
                active: (0..k).map(|j| set & (1 << j) != 0).collect(),
                impulse,
            });
        }
    }
    Err(Failure::NoSolution)
}
