//! Polynomials over atoms (sums of monomials with `f64` coefficients), the one expander of the
//! symbolic path, with its caps in one place ([`Rules`]: [`DETERMINANT`], [`PRINTING`]).
//!
//! Two walks of the DAG use it. Here, a determinant like (I⊥ s² + I∥ c²)·I∥ − (I∥ c)² is
//! expanded so it cancels to the monomial I⊥ I∥ s² instead of being evaluated as a difference
//! of nearly equal numbers; its atoms are the nodes that are not `+ − ×`, negation, small
//! integer powers or constants (parameters, coordinates, `sin θ`, divisions, …), and it gives up
//! (`None`) past its caps, so it never blows up; callers then keep the unexpanded expression.
//! `print.rs` expands the equations for people over finer atoms (a division by a monomial is a
//! negative power; what exceeds the caps stays in parentheses).

use std::collections::BTreeMap;

use super::dag::{Dag, Id, Node};

/// How far an expansion may go and when a coefficient counts as cancelled: the caps of both
/// expanders, stated here.
pub struct Rules {
    /// A product with more terms than this is abandoned (`None`); so is a sum, where the
    /// walk asks for it ([`Poly::capped`]: the determinant does, printing keeps every sum).
    pub max_terms: usize,
    /// A product is not even formed when its operands' term counts multiply to more than this.
    pub max_product: usize,
    /// A merged coefficient is dropped when |c| ≤ `cancel` · max(|before|, |added|): 0 keeps
    /// exactly what cancels exactly.
    pub cancel: f64,
}

/// The determinants of decoupled 2×2 blocks (`det2`): small, exact.
pub const DETERMINANT: Rules = Rules {
    max_terms: 32,
    max_product: 32 * 32,
    cancel: 0.0,
};

/// The printed equations (`print.rs`): large, and rounding residue of cancelled terms dropped.
pub const PRINTING: Rules = Rules {
    max_terms: 600,
    max_product: 600 * 8,
    cancel: 1e-14,
};

/// Whether a derivative vanishes identically (`derive::vanishes`, the flags CYCLIC and
/// AUTONOMOUS): larger than the determinant's caps (a heavy top written from its rotation
/// matrix needs ~40 terms), exact.
pub const SYMMETRY: Rules = Rules {
    max_terms: 256,
    max_product: 256 * 32,
    cancel: 0.0,
};

/// Expression depth beyond which the determinant expansion gives up (bounds the recursion).
pub const MAX_DEPTH: usize = 64;

/// A monomial: its atoms and their (nonzero) exponents, sorted by atom.
pub type Mono<A> = Vec<(A, i32)>;

/// A polynomial over atoms: monomial → coefficient, like terms merged, no zero coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct Poly<A: Ord>(pub BTreeMap<Mono<A>, f64>);

impl<A: Ord> Default for Poly<A> {
    fn default() -> Self {
        Poly(BTreeMap::new())
    }
}

/// The product of two monomials, with the exponents of `b` times `sign` (−1 divides); `None`
/// when an exponent would overflow `i32` (`x.powi(i32::MIN) / x`): the caller keeps the factors
/// apart.
pub fn mono_mul<A: Ord + Copy>(a: &Mono<A>, b: &Mono<A>, sign: i32) -> Option<Mono<A>> {
    let mut r: BTreeMap<A, i32> = a.iter().copied().collect();
    for &(x, e) in b {
        let slot = r.entry(x).or_insert(0);
        *slot = slot.checked_add(sign.checked_mul(e)?)?;
    }
    Some(r.into_iter().filter(|(_, e)| *e != 0).collect())
}

impl<A: Ord + Copy> Poly<A> {
    /// The constant `c` (no term for 0).
    pub fn constant(c: f64) -> Self {
        let mut p = Poly::default();
        if c != 0.0 {
            p.0.insert(Vec::new(), c);
        }
        p
    }

    /// The atom `a` to the power `e`.
    pub fn atom(a: A, e: i32) -> Self {
        let mut p = Poly::default();
        p.0.insert(vec![(a, e)], 1.0);
        p
    }

    /// The number of terms.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// The only term, if there is exactly one.
    pub fn single(&self) -> Option<(&Mono<A>, f64)> {
        if self.0.len() == 1 {
            self.0.iter().next().map(|(m, c)| (m, *c))
        } else {
            None
        }
    }

    /// Every coefficient times `k`.
    pub fn scale(&self, k: f64) -> Self {
        if k == 0.0 {
            return Poly::default();
        }
        Poly(self.0.iter().map(|(m, c)| (m.clone(), c * k)).collect())
    }

    /// Adds `c` to the coefficient of `m`; true when that cancelled it (see [`Rules::cancel`]).
    fn accumulate(&mut self, m: &Mono<A>, c: f64, rules: &Rules) -> bool {
        let e = self.0.entry(m.clone()).or_insert(0.0);
        let before = *e;
        *e += c;
        if e.abs() <= rules.cancel * before.abs().max(c.abs()) {
            self.0.remove(m);
            return true;
        }
        false
    }

    /// `self + sign·other` and the number of terms that cancelled.
    pub fn add(&self, other: &Self, sign: f64, rules: &Rules) -> (Self, usize) {
        let mut r = self.clone();
        let mut cancelled = 0;
        for (m, c) in &other.0 {
            cancelled += usize::from(r.accumulate(m, sign * c, rules));
        }
        (r, cancelled)
    }

    /// `self`, unless it has more than `rules.max_terms` terms.
    pub fn capped(self, rules: &Rules) -> Option<Self> {
        (self.len() <= rules.max_terms).then_some(self)
    }

    /// `self · other`; `None` past the caps.
    pub fn mul(&self, other: &Self, rules: &Rules) -> Option<Self> {
        if self.len() * other.len() > rules.max_product {
            return None;
        }
        let mut r = Poly::default();
        for (m1, c1) in &self.0 {
            for (m2, c2) in &other.0 {
                r.accumulate(&mono_mul(m1, m2, 1)?, c1 * c2, rules);
            }
        }
        r.capped(rules)
    }
}

/// Expands `id` into a polynomial over its atoms (DAG nodes), under [`DETERMINANT`]: `None`
/// when it has more than its `max_terms` terms (at any step) or is nested deeper than
/// [`MAX_DEPTH`].
pub fn expand(dag: &Dag, id: Id) -> Option<Poly<Id>> {
    expand_within(dag, id, MAX_DEPTH, &DETERMINANT)
}

/// [`expand`] under other caps.
pub fn expand_under(dag: &Dag, id: Id, rules: &Rules) -> Option<Poly<Id>> {
    expand_within(dag, id, MAX_DEPTH, rules)
}

fn expand_within(dag: &Dag, id: Id, depth: usize, rules: &Rules) -> Option<Poly<Id>> {
    if let Some(c) = dag.as_const(id) {
        return Some(Poly::constant(c));
    }
    let depth = depth.checked_sub(1)?;
    let ex = |x: Id| expand_within(dag, x, depth, rules);
    let sum = |a: Poly<Id>, b: Poly<Id>, sign: f64| a.add(&b, sign, rules).0.capped(rules);
    match dag.node(id) {
        Node::Add(a, b) => sum(ex(a)?, ex(b)?, 1.0),
        Node::Sub(a, b) => sum(ex(a)?, ex(b)?, -1.0),
        Node::Neg(a) => sum(Poly::constant(0.0), ex(a)?, -1.0),
        Node::Mul(a, b) => ex(a)?.mul(&ex(b)?, rules),
        Node::Powi(a, n @ 2..=4) => {
            let base = ex(a)?;
            let mut p = base.clone();
            for _ in 1..n {
                p = p.mul(&base, rules)?;
            }
            Some(p)
        }
        _ => Some(Poly::atom(id, 1)),
    }
}

/// The monomial `m` with the exponent of `atom` changed by `delta` (dropped at 0, inserted in
/// order where absent).
pub fn shifted<A: Ord + Copy>(m: &Mono<A>, atom: A, delta: i32) -> Mono<A> {
    let mut out: Mono<A> = m.clone();
    match out.iter().position(|(a, _)| *a == atom) {
        Some(i) => {
            out[i].1 += delta;
            if out[i].1 == 0 {
                out.remove(i);
            }
        }
        None => {
            let at = out.partition_point(|(a, _)| *a < atom);
            out.insert(at, (atom, delta));
        }
    }
    out
}

/// Adds `c` to the coefficient of `m` (dropping it at exactly 0).
pub fn accumulate<A: Ord>(p: &mut Poly<A>, m: Mono<A>, c: f64) {
    let sum = p.0.get(&m).copied().unwrap_or(0.0) + c;
    if sum == 0.0 {
        p.0.remove(&m);
    } else {
        p.0.insert(m, sum);
    }
}

/// One merge of a pair k·r·sinᵃ⁺²(x)·cosᵇ(x) + k·r·sinᵃ(x)·cosᵇ⁺²(x) → k·r·sinᵃ(x)·cosᵇ(x)
/// (sin² + cos² = 1; the same k to 1e-14 and the same r), `cos_of(s)` the cosine atom of the
/// same argument where `s` is a sine atom; whether one was made. Only pairs merge, so a
/// polynomial never gets longer.
pub fn merge_pythagorean<A: Ord + Copy>(p: &mut Poly<A>, cos_of: &dyn Fn(A) -> Option<A>) -> bool {
    let mut found = None;
    'search: for (m, &c) in &p.0 {
        for &(atom, e) in m {
            let Some(cos) = cos_of(atom) else { continue };
            if e < 2 {
                continue;
            }
            let partner = shifted(&shifted(m, atom, -2), cos, 2);
            let Some(&c2) = p.0.get(&partner) else {
                continue;
            };
            if (c - c2).abs() > 1e-14 * c.abs().max(c2.abs()) {
                continue;
            }
            found = Some((m.clone(), partner, shifted(m, atom, -2), c));
            break 'search;
        }
    }
    let Some((m, partner, merged, c)) = found else {
        return false;
    };
    p.0.remove(&m);
    p.0.remove(&partner);
    accumulate(p, merged, c);
    true
}

/// Reduces `p` modulo sin²x + cos²x − 1 for every angle x whose sine and cosine are both
/// atoms (`sin_of(c)`: the sine atom of the argument of a cosine atom `c`): each cosᵉ with
/// e ≥ 2 becomes cosᵉ⁻²(1 − sin²) until every cosine has exponent 0 or 1. That is a normal form
/// of the quotient ring (basis sinᵏ·cos^{0,1}), so a polynomial that vanishes through the
/// identity reduces to no terms at all: exact, unlike the pairwise merge. `false` when the
/// reduction grows past `rules.max_terms` (`p` is then partly reduced).
pub fn reduce_pythagorean<A: Ord + Copy>(
    p: &mut Poly<A>,
    sin_of: &dyn Fn(A) -> Option<A>,
    rules: &Rules,
) -> bool {
    loop {
        let found = p.0.iter().find_map(|(m, &c)| {
            m.iter()
                .find_map(|&(atom, e)| (e >= 2).then(|| sin_of(atom).map(|s| (atom, s))).flatten())
                .map(|(cos, sin)| (m.clone(), c, cos, sin))
        });
        let Some((m, c, cos, sin)) = found else {
            return true;
        };
        p.0.remove(&m);
        let lower = shifted(&m, cos, -2);
        accumulate(p, shifted(&lower, sin, 2), -c);
        accumulate(p, lower, c);
        if p.len() > rules.max_terms {
            return false;
        }
    }
}

/// Builds the polynomial back as DAG nodes (sum of coefficient × product of atoms), the terms
/// in the order of their atoms written out with repetitions (a²b as a, a, b).
pub fn build(dag: &mut Dag, p: &Poly<Id>) -> Id {
    let mut terms: Vec<(Vec<Id>, f64)> =
        p.0.iter()
            .map(|(m, c)| {
                let atoms = m
                    .iter()
                    .flat_map(|&(a, e)| std::iter::repeat_n(a, usize::try_from(e).unwrap_or(0)))
                    .collect();
                (atoms, *c)
            })
            .collect();
    terms.sort_by(|a, b| a.0.cmp(&b.0));
    let mut sum = Dag::ZERO;
    for (atoms, c) in &terms {
        let mut term = Dag::ONE;
        for &a in atoms {
            term = dag.mul(term, a);
        }
        let c = dag.constant(*c);
        let term = dag.mul(c, term);
        sum = dag.add(sum, term);
    }
    sum
}

/// m₁₁ m₂₂ − m₁₂² as DAG nodes: expanded where terms of m₁₁m₂₂ and m₁₂² cancel exactly (and
/// the expansion stays small), as written otherwise (an expansion where nothing cancels only
/// costs operations and gains no accuracy).
pub fn det2(dag: &mut Dag, m11: Id, m22: Id, m12: Id) -> (Id, bool) {
    let rules = &DETERMINANT;
    let expanded = (|| {
        let (a, d, b) = (expand(dag, m11)?, expand(dag, m22)?, expand(dag, m12)?);
        let (ad, bb) = (a.mul(&d, rules)?, b.mul(&b, rules)?);
        let (det, cancelled) = ad.add(&bb, -1.0, rules);
        let det = det.capped(rules)?;
        (cancelled > 0).then_some(det)
    })();
    match expanded {
        // One monomial left: a product, evaluated to a few ulps however small it is.
        Some(p) => (build(dag, &p), p.len() == 1),
        None => {
            let ad = dag.mul(m11, m22);
            let bb = dag.mul(m12, m12);
            (dag.sub(ad, bb), false)
        }
    }
}
