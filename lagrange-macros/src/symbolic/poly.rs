//! Expansion of small DAG expressions into polynomials over their atoms (sums of monomials with
//! `f64` coefficients), so that a determinant like (I⊥ s² + I∥ c²)·I∥ − (I∥ c)² cancels to the
//! monomial I⊥ I∥ s² instead of being evaluated as a difference of nearly equal numbers.
//!
//! Atoms are the nodes that are not `+ − ×`, negation, small integer powers or constants
//! (parameters, coordinates, `sin θ`, divisions, …). Expansion gives up (`None`) beyond
//! [`MAX_TERMS`] terms, so it never blows up; callers then keep the unexpanded expression.

use super::dag::{Dag, Id, Node};

/// Expansions with more terms than this are abandoned.
pub const MAX_TERMS: usize = 32;

/// A monomial: coefficient and its atoms, sorted (repeated for powers).
type Term = (f64, Vec<Id>);

/// A polynomial over DAG atoms, terms sorted by atoms, like terms merged, no zero coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct Poly(Vec<Term>);

impl Poly {
    fn constant(c: f64) -> Poly {
        Poly::from_terms(vec![(c, Vec::new())])
    }

    fn atom(id: Id) -> Poly {
        Poly(vec![(1.0, vec![id])])
    }

    fn from_terms(terms: Vec<Term>) -> Poly {
        Poly::merge(terms).0
    }

    /// Sorts, merges like terms and drops those whose coefficients cancel to zero; also returns
    /// how many merged terms cancelled.
    fn merge(mut terms: Vec<Term>) -> (Poly, usize) {
        terms.sort_by(|a, b| a.1.cmp(&b.1));
        let mut out: Vec<Term> = Vec::with_capacity(terms.len());
        for (c, atoms) in terms {
            match out.last_mut() {
                Some(last) if last.1 == atoms => last.0 += c,
                _ => out.push((c, atoms)),
            }
        }
        let before = out.len();
        out.retain(|t| t.0 != 0.0);
        let cancelled = before - out.len();
        (Poly(out), cancelled)
    }

    fn add(&self, other: &Poly, sign: f64) -> Option<Poly> {
        self.add_counting(other, sign).map(|(p, _)| p)
    }

    /// `self + sign·other` and the number of terms that cancelled exactly.
    fn add_counting(&self, other: &Poly, sign: f64) -> Option<(Poly, usize)> {
        let terms = self
            .0
            .iter()
            .cloned()
            .chain(other.0.iter().map(|(c, a)| (sign * c, a.clone())))
            .collect();
        let (p, cancelled) = Poly::merge(terms);
        Some((p.capped()?, cancelled))
    }

    fn mul(&self, other: &Poly) -> Option<Poly> {
        if self.0.len() * other.0.len() > MAX_TERMS * MAX_TERMS {
            return None;
        }
        let mut terms = Vec::with_capacity(self.0.len() * other.0.len());
        for (ca, aa) in &self.0 {
            for (cb, ab) in &other.0 {
                let mut atoms = aa.clone();
                atoms.extend(ab);
                atoms.sort_unstable();
                terms.push((ca * cb, atoms));
            }
        }
        Poly::from_terms(terms).capped()
    }

    fn capped(self) -> Option<Poly> {
        (self.0.len() <= MAX_TERMS).then_some(self)
    }

    /// The number of terms.
    #[cfg_attr(not(test), allow(dead_code))]
    pub fn len(&self) -> usize {
        self.0.len()
    }
}

/// Expands `id` into a polynomial over its atoms, or `None` when it has more than
/// [`MAX_TERMS`] terms (at any step) or is nested deeper than [`MAX_DEPTH`].
pub fn expand(dag: &Dag, id: Id) -> Option<Poly> {
    expand_within(dag, id, MAX_DEPTH)
}

/// Expression depth beyond which expansion gives up (bounds the recursion).
pub const MAX_DEPTH: usize = 64;

fn expand_within(dag: &Dag, id: Id, depth: usize) -> Option<Poly> {
    if let Some(c) = dag.as_const(id) {
        return Some(Poly::constant(c));
    }
    let depth = depth.checked_sub(1)?;
    let ex = |x: Id| expand_within(dag, x, depth);
    match dag.node(id) {
        Node::Add(a, b) => ex(a)?.add(&ex(b)?, 1.0),
        Node::Sub(a, b) => ex(a)?.add(&ex(b)?, -1.0),
        Node::Neg(a) => Poly::constant(0.0).add(&ex(a)?, -1.0),
        Node::Mul(a, b) => ex(a)?.mul(&ex(b)?),
        Node::Powi(a, n @ 2..=4) => {
            let base = ex(a)?;
            let mut p = base.clone();
            for _ in 1..n {
                p = p.mul(&base)?;
            }
            Some(p)
        }
        _ => Some(Poly::atom(id)),
    }
}

/// Builds the polynomial back as DAG nodes (sum of coefficient × product of atoms).
pub fn build(dag: &mut Dag, p: &Poly) -> Id {
    let mut sum = Dag::ZERO;
    for (c, atoms) in &p.0 {
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
pub fn det2(dag: &mut Dag, m11: Id, m22: Id, m12: Id) -> Id {
    let expanded = (|| {
        let (a, d, b) = (expand(dag, m11)?, expand(dag, m22)?, expand(dag, m12)?);
        let (ad, bb) = (a.mul(&d)?, b.mul(&b)?);
        let (det, cancelled) = ad.add_counting(&bb, -1.0)?;
        (cancelled > 0).then_some(det)
    })();
    match expanded {
        Some(p) => build(dag, &p),
        None => {
            let ad = dag.mul(m11, m22);
            let bb = dag.mul(m12, m12);
            dag.sub(ad, bb)
        }
    }
}
