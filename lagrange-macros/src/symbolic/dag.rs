//! The hash-consed scalar expression DAG with constant folding, numeric evaluation and
//! forward-mode (tangent) differentiation.
//!
//! Node ids are handed out in creation order and every node's operands are created before it, so
//! id order is a topological order: emission and differentiation walk ids upwards.

use std::collections::HashMap;

use super::functions::{Build, Rule};
pub use super::functions::{Fun, Id};

/// One node of the DAG.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// An `f64` constant, stored as its bits (normalized: no `-0.0`, one NaN).
    Const(u64),
    /// `self.<field>`: field index, component (0 for an `f64` field, 1..=3 for x, y, z).
    Param(u32, u8),
    /// Generalized coordinate `q[i]`.
    Q(u32),
    /// Generalized velocity `qdot[i]`.
    V(u32),
    /// Time.
    T,
    Add(Id, Id),
    Sub(Id, Id),
    Mul(Id, Id),
    Div(Id, Id),
    Neg(Id),
    Powi(Id, i32),
    Powf(Id, Id),
    Atan2(Id, Id),
    Un(Fun, Id),
    /// `if b { a } else { c }` on a condition that depends on constants only (the index of a
    /// run-time `bool` evaluated once per call, see `lower::Cond`).
    Select(u32, Id, Id),
}

impl Node {
    /// The operands of this node.
    pub fn children(&self) -> impl Iterator<Item = Id> {
        let (a, b) = match *self {
            Node::Const(_) | Node::Param(..) | Node::Q(_) | Node::V(_) | Node::T => (None, None),
            Node::Add(a, b)
            | Node::Sub(a, b)
            | Node::Mul(a, b)
            | Node::Div(a, b)
            | Node::Powf(a, b)
            | Node::Atan2(a, b)
            | Node::Select(_, a, b) => (Some(a), Some(b)),
            Node::Neg(a) | Node::Powi(a, _) | Node::Un(_, a) => (Some(a), None),
        };
        a.into_iter().chain(b)
    }

    /// Whether this node is a leaf (constant, parameter, coordinate, velocity or time).
    pub fn is_leaf(&self) -> bool {
        matches!(
            self,
            Node::Const(_) | Node::Param(..) | Node::Q(_) | Node::V(_) | Node::T
        )
    }
}

fn bits(c: f64) -> u64 {
    if c.is_nan() {
        f64::NAN.to_bits()
    } else if c == 0.0 {
        0.0_f64.to_bits()
    } else {
        c.to_bits()
    }
}

/// The variable numbering used for dependency sets: q[i] → i, qdot[i] → n + i, t → 2n.
#[derive(Clone, Copy, Debug)]
pub struct Vars {
    pub n: usize,
}

impl Vars {
    pub fn q(self, i: usize) -> usize {
        i
    }
    pub fn v(self, i: usize) -> usize {
        self.n + i
    }
    pub fn t(self) -> usize {
        2 * self.n
    }
    pub fn count(self) -> usize {
        2 * self.n + 1
    }
    fn words(self) -> usize {
        self.count().div_ceil(64)
    }
}

/// The hash-consed expression DAG.
#[derive(Clone)]
pub struct Dag {
    nodes: Vec<Node>,
    index: HashMap<Node, Id>,
    /// Dependency bit sets, `words` u64s per node.
    deps: Vec<u64>,
    words: usize,
    pub vars: Vars,
    /// Products by their sorted factors (hash-consing modulo associativity and commutativity of
    /// `*`): `(a b) c` and `a (c b)` are one node, so like terms meet (`x + x = 2 x`).
    monomials: HashMap<Vec<Id>, Id>,
}

/// [`Dag::collect_terms`] gives up on sums of more nodes than this (bounds its work).
const COLLECT_MAX_VISITS: usize = 1 << 16;

/// Products with more factors than this are not canonicalized (bounds the work per `mul`).
const MONOMIAL_MAX_FACTORS: usize = 16;

/// A variable set, as a bit set over [`Vars`] numbering.
#[derive(Clone, Debug)]
pub struct VarSet(Vec<u64>);

impl VarSet {
    pub fn new(vars: Vars) -> Self {
        VarSet(vec![0; vars.words()])
    }
    pub fn insert(&mut self, var: usize) {
        self.0[var / 64] |= 1 << (var % 64);
    }
}

impl Dag {
    /// An empty DAG for `n` generalized coordinates.
    pub fn new(n: usize) -> Self {
        let vars = Vars { n };
        let mut dag = Dag {
            nodes: Vec::new(),
            index: HashMap::new(),
            deps: Vec::new(),
            words: vars.words(),
            vars,
            monomials: HashMap::new(),
        };
        // Ids 0 and 1 are the constants 0 and 1.
        dag.constant(0.0);
        dag.constant(1.0);
        dag
    }

    pub const ZERO: Id = super::functions::ZERO;
    pub const ONE: Id = super::functions::ONE;

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn node(&self, id: Id) -> Node {
        self.nodes[id as usize]
    }

    /// The constant value of a node, if it is a constant.
    pub fn as_const(&self, id: Id) -> Option<f64> {
        match self.node(id) {
            Node::Const(b) => Some(f64::from_bits(b)),
            _ => None,
        }
    }

    /// Whether the node depends on no coordinate, velocity or time (parameters and constants only).
    pub fn is_state_free(&self, id: Id) -> bool {
        let w = id as usize * self.words;
        self.deps[w..w + self.words].iter().all(|x| *x == 0)
    }

    /// Whether the node depends on any variable in `set`.
    pub fn depends_on(&self, id: Id, set: &VarSet) -> bool {
        let w = id as usize * self.words;
        self.deps[w..w + self.words]
            .iter()
            .zip(&set.0)
            .any(|(a, b)| a & b != 0)
    }

    /// The id of `node` if it is already in the DAG.
    pub fn find(&self, node: Node) -> Option<Id> {
        self.index.get(&node).copied()
    }

    fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.index.get(&node) {
            return id;
        }
        let id = self.nodes.len() as Id;
        let mut d = vec![0u64; self.words];
        match node {
            Node::Q(i) => d[self.vars.q(i as usize) / 64] |= 1 << (self.vars.q(i as usize) % 64),
            Node::V(i) => d[self.vars.v(i as usize) / 64] |= 1 << (self.vars.v(i as usize) % 64),
            Node::T => d[self.vars.t() / 64] |= 1 << (self.vars.t() % 64),
            _ => {
                for c in node.children() {
                    let w = c as usize * self.words;
                    for (k, x) in d.iter_mut().enumerate() {
                        *x |= self.deps[w + k];
                    }
                }
            }
        }
        self.deps.extend(d);
        self.nodes.push(node);
        self.index.insert(node, id);
        id
    }

    pub fn constant(&mut self, c: f64) -> Id {
        self.intern(Node::Const(bits(c)))
    }
    pub fn param(&mut self, field: u32, comp: u8) -> Id {
        self.intern(Node::Param(field, comp))
    }
    pub fn q(&mut self, i: usize) -> Id {
        self.intern(Node::Q(i as u32))
    }
    pub fn v(&mut self, i: usize) -> Id {
        self.intern(Node::V(i as u32))
    }
    pub fn t(&mut self) -> Id {
        self.intern(Node::T)
    }

    pub fn add(&mut self, a: Id, b: Id) -> Id {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x + y),
            (Some(0.0), None) => return b,
            (None, Some(0.0)) => return a,
            _ => {}
        }
        if let Node::Neg(nb) = self.node(b) {
            return self.sub(a, nb);
        }
        if let Node::Neg(na) = self.node(a) {
            return self.sub(b, na);
        }
        // Like terms: c₁ x + c₂ x = (c₁ + c₂) x.
        let ((ca, xa), (cb, xb)) = (self.split_coef(a), self.split_coef(b));
        if xa == xb {
            let c = self.constant(ca + cb);
            return self.mul(c, xa);
        }
        // A common constant factor goes outside: c x + c y = c (x + y), c x − c y = c (x − y)
        // (the 2 of d(v²) = 2v dv then meets the ½ of ½ m v² and both vanish).
        if ca != 1.0 && ca.abs() == cb.abs() {
            let s = if ca == cb {
                self.add(xa, xb)
            } else {
                self.sub(xa, xb)
            };
            let c = self.constant(ca);
            return self.mul(c, s);
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Add(a, b))
    }

    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x - y),
            (Some(0.0), None) => return self.neg(b),
            (None, Some(0.0)) => return a,
            _ => {}
        }
        if a == b {
            return Self::ZERO;
        }
        if let Node::Neg(nb) = self.node(b) {
            return self.add(a, nb);
        }
        if let Node::Neg(na) = self.node(a) {
            let s = self.add(na, b);
            return self.neg(s);
        }
        let ((ca, xa), (cb, xb)) = (self.split_coef(a), self.split_coef(b));
        if xa == xb {
            let c = self.constant(ca - cb);
            return self.mul(c, xa);
        }
        // c x − c y = c (x − y), c x − (−c) y = c (x + y).
        if ca != 1.0 && ca.abs() == cb.abs() {
            let s = if ca == cb {
                self.sub(xa, xb)
            } else {
                self.add(xa, xb)
            };
            let c = self.constant(ca);
            return self.mul(c, s);
        }
        self.intern(Node::Sub(a, b))
    }

    /// `id` with the like terms of its sum cancelled: the sum is flattened through `+`, `−`,
    /// negation, constant factors and a state-free factor of a sum (`p (a − b)` is `p a − p b`),
    /// terms equal up to their coefficient are merged, and the sum is rebuilt (grouped by
    /// state-free factor, in first-seen order) only when that removed a term and the rebuilt sum
    /// takes fewer new nodes than the sum visited. The Euler–Lagrange
    /// force fᵢ = ∂L/∂qᵢ − d/dt|_q̈ ∂L/∂q̇ᵢ is where this pays: the two halves share terms that
    /// cancel (a 64-link chain's f has ≈ 2 300 top-level terms, ≈ 1 400 after cancelling).
    pub fn collect_terms(&mut self, id: Id) -> Id {
        let mut terms = Vec::new();
        let mut budget = COLLECT_MAX_VISITS;
        if !self.linear_terms(id, Dag::ONE, 1.0, &mut terms, &mut budget) {
            return id;
        }
        let visited = COLLECT_MAX_VISITS - budget;
        let before = self.len();
        let mut index: HashMap<(Id, Id), usize> = HashMap::new();
        let mut merged: Vec<((Id, Id), f64)> = Vec::new();
        for &(factor, leaf, c) in &terms {
            match index.get(&(factor, leaf)) {
                Some(&k) => merged[k].1 += c,
                None => {
                    index.insert((factor, leaf), merged.len());
                    merged.push(((factor, leaf), c));
                }
            }
        }
        merged.retain(|&(_, c)| c != 0.0);
        if merged.len() == terms.len() {
            return id;
        }
        // Grouped by factor, in first-seen order.
        let mut groups: Vec<(Id, Id)> = Vec::new();
        for ((factor, leaf), c) in merged {
            let c = self.constant(c);
            let term = self.mul(c, leaf);
            match groups.iter_mut().find(|(f, _)| *f == factor) {
                Some((_, sum)) => *sum = self.add(*sum, term),
                None => groups.push((factor, term)),
            }
        }
        let mut total = Dag::ZERO;
        for (factor, sum) in groups {
            let term = self.mul(factor, sum);
            total = self.add(total, term);
        }
        // Only if the rebuilt sum is smaller than the one it replaces (the sum's nodes may be
        // shared with other outputs, which keep them; the new nodes are left unused).
        if self.len() - before < visited {
            total
        } else {
            id
        }
    }

    /// Appends the terms (state-free factor or 1, leaf, coefficient) of `coef · factor · id` to
    /// `out`; false when the sum visits more than `budget` nodes.
    fn linear_terms(
        &self,
        id: Id,
        factor: Id,
        coef: f64,
        out: &mut Vec<(Id, Id, f64)>,
        budget: &mut usize,
    ) -> bool {
        if *budget == 0 {
            return false;
        }
        *budget -= 1;
        let is_sum = |x: Id| matches!(self.node(x), Node::Add(..) | Node::Sub(..) | Node::Neg(_));
        match self.node(id) {
            Node::Add(a, b) => {
                self.linear_terms(a, factor, coef, out, budget)
                    && self.linear_terms(b, factor, coef, out, budget)
            }
            Node::Sub(a, b) => {
                self.linear_terms(a, factor, coef, out, budget)
                    && self.linear_terms(b, factor, -coef, out, budget)
            }
            Node::Neg(a) => self.linear_terms(a, factor, -coef, out, budget),
            Node::Mul(a, b) if self.as_const(a).is_some() => {
                let c = self.as_const(a).unwrap_or(1.0);
                self.linear_terms(b, factor, coef * c, out, budget)
            }
            // A product with one state-free factor p: p x, with x distributed over when a sum.
            Node::Mul(a, b)
                if factor == Dag::ONE && self.is_state_free(a) != self.is_state_free(b) =>
            {
                let (p, x) = if self.is_state_free(a) {
                    (a, b)
                } else {
                    (b, a)
                };
                if is_sum(x) {
                    self.linear_terms(x, p, coef, out, budget)
                } else {
                    out.push((p, x, coef));
                    true
                }
            }
            _ => {
                out.push((factor, id, coef));
                true
            }
        }
    }

    /// `c · x` as `(c, x)`; anything else as `(1, a)`.
    fn split_coef(&self, a: Id) -> (f64, Id) {
        if let Node::Mul(c, x) = self.node(a) {
            if let Some(c) = self.as_const(c) {
                return (c, x);
            }
        }
        (1.0, a)
    }

    pub fn neg(&mut self, a: Id) -> Id {
        match self.node(a) {
            Node::Const(b) => self.constant(-f64::from_bits(b)),
            Node::Neg(x) => x,
            Node::Sub(x, y) => self.sub(y, x),
            Node::Mul(x, y) if self.as_const(x).is_some() => {
                let c = -self.as_const(x).unwrap_or(0.0);
                let c = self.constant(c);
                self.mul(c, y)
            }
            _ => self.intern(Node::Neg(a)),
        }
    }

    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        // Constants go to the left.
        let (a, b) = if self.as_const(b).is_some() && self.as_const(a).is_none() {
            (b, a)
        } else {
            (a, b)
        };
        if let Some(x) = self.as_const(a) {
            if let Some(y) = self.as_const(b) {
                return self.constant(x * y);
            }
            if x == 0.0 {
                return Self::ZERO;
            }
            if x == 1.0 {
                return b;
            }
            if x == -1.0 {
                return self.neg(b);
            }
            match self.node(b) {
                // c1 * (c2 * y) = (c1 c2) * y
                Node::Mul(c, y) if self.as_const(c).is_some() => {
                    let k = x * self.as_const(c).unwrap_or(1.0);
                    let k = self.constant(k);
                    return self.mul(k, y);
                }
                Node::Neg(y) => {
                    let k = self.constant(-x);
                    return self.mul(k, y);
                }
                _ => {}
            }
            return self.intern(Node::Mul(a, b));
        }
        // Pull constant factors out: (c x) y = c (x y).
        if let Node::Mul(c, x) = self.node(a) {
            if self.as_const(c).is_some() {
                let p = self.mul(x, b);
                return self.mul(c, p);
            }
        }
        if let Node::Mul(c, y) = self.node(b) {
            if self.as_const(c).is_some() {
                let p = self.mul(a, y);
                return self.mul(c, p);
            }
        }
        match (self.node(a), self.node(b)) {
            (Node::Neg(x), Node::Neg(y)) => return self.mul(x, y),
            (Node::Neg(x), _) => {
                let p = self.mul(x, b);
                return self.neg(p);
            }
            (_, Node::Neg(y)) => {
                let p = self.mul(a, y);
                return self.neg(p);
            }
            _ => {}
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        let mut key = Vec::new();
        if self.factors(a, &mut key) && self.factors(b, &mut key) {
            key.sort_unstable();
            if let Some(&id) = self.monomials.get(&key) {
                return id;
            }
            let id = self.intern(Node::Mul(a, b));
            self.monomials.entry(key).or_insert(id);
            return id;
        }
        self.intern(Node::Mul(a, b))
    }

    /// The product of `factors` (1 for none), two at a time, each time a pair whose product is
    /// already a node where there is one: a new product reuses the DAG's (the Taylor series
    /// convolves once per product node that varies along the motion).
    pub fn product(&mut self, factors: &[Id]) -> Id {
        let mut parts: Vec<Id> = factors.to_vec();
        while parts.len() > 1 {
            let mut pick = (0, 1);
            'find: for i in 0..parts.len() {
                for j in i + 1..parts.len() {
                    if self.has_product(parts[i], parts[j]) {
                        pick = (i, j);
                        break 'find;
                    }
                }
            }
            let b = parts.remove(pick.1);
            let a = parts.remove(pick.0);
            let p = self.mul(a, b);
            parts.push(p);
        }
        parts.pop().unwrap_or(Self::ONE)
    }

    /// Whether a · b is already a node (as written or as the same monomial).
    fn has_product(&self, a: Id, b: Id) -> bool {
        let (x, y) = if a <= b { (a, b) } else { (b, a) };
        if self.index.contains_key(&Node::Mul(x, y)) {
            return true;
        }
        let mut key = Vec::new();
        self.factors(a, &mut key) && self.factors(b, &mut key) && {
            key.sort_unstable();
            self.monomials.contains_key(&key)
        }
    }

    /// Appends the factors of a product without constant factors (a non-product is its own
    /// factor); false when there are more than [`MONOMIAL_MAX_FACTORS`].
    fn factors(&self, id: Id, out: &mut Vec<Id>) -> bool {
        // Iterative (a long product must not deepen the macro's stack); stops at the bound.
        let mut todo = vec![id];
        while let Some(x) = todo.pop() {
            match self.node(x) {
                Node::Mul(a, b) if self.as_const(a).is_none() => todo.extend([b, a]),
                _ => {
                    out.push(x);
                    if out.len() > MONOMIAL_MAX_FACTORS {
                        return false;
                    }
                }
            }
        }
        true
    }

    pub fn div(&mut self, a: Id, b: Id) -> Id {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x / y),
            (Some(0.0), _) => return Self::ZERO,
            (_, Some(1.0)) => return a,
            (_, Some(-1.0)) => return self.neg(a),
            (_, Some(y)) if y != 0.0 && y.is_finite() => {
                // Multiplying by an exactly representable reciprocal is the same number.
                let r = 1.0 / y;
                if r.is_finite() && r * y == 1.0 && (r.to_bits() & ((1 << 52) - 1)) == 0 {
                    let r = self.constant(r);
                    return self.mul(r, a);
                }
            }
            _ => {}
        }
        if a == b {
            return Self::ONE;
        }
        self.intern(Node::Div(a, b))
    }

    pub fn powi(&mut self, a: Id, n: i32) -> Id {
        if n == 0 {
            return Self::ONE;
        }
        if n == 1 {
            return a;
        }
        if let Some(x) = self.as_const(a) {
            return self.constant(x.powi(n));
        }
        if let Node::Powi(x, m) = self.node(a) {
            if let Some(k) = m.checked_mul(n) {
                return self.powi(x, k);
            }
        }
        // √x to an even power is a power of x: `v.norm().powi(2)` is |v|², smooth at v = 0
        // (through the square root its derivative would be ∞·0 there).
        if let (Node::Un(Fun::Sqrt, x), 0) = (self.node(a), n % 2) {
            return self.powi(x, n / 2);
        }
        self.intern(Node::Powi(a, n))
    }

    pub fn powf(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.as_const(a), self.as_const(b)) {
            return self.constant(x.powf(y));
        }
        if let Some(y) = self.as_const(b) {
            if y == 0.0 {
                return Self::ONE;
            }
            if y == 1.0 {
                return a;
            }
        }
        self.intern(Node::Powf(a, b))
    }

    pub fn atan2(&mut self, y: Id, x: Id) -> Id {
        if let (Some(a), Some(b)) = (self.as_const(y), self.as_const(x)) {
            return self.constant(a.atan2(b));
        }
        self.intern(Node::Atan2(y, x))
    }

    pub fn un(&mut self, f: Fun, a: Id) -> Id {
        if let Some(x) = self.as_const(a) {
            return self.constant(f.eval(x));
        }
        match (f, self.node(a)) {
            (Fun::Abs, Node::Neg(x)) => return self.un(Fun::Abs, x),
            (Fun::Abs, Node::Un(Fun::Abs, _)) => return a,
            (Fun::Cos | Fun::Cosh, Node::Neg(x)) => return self.un(f, x),
            (Fun::Signum, Node::Un(Fun::Signum, _)) => return a,
            _ => {}
        }
        self.intern(Node::Un(f, a))
    }

    /// `if cond { a } else { b }`; equal branches fold, and a nested select on the same
    /// condition takes its own branch.
    pub fn select(&mut self, cond: u32, a: Id, b: Id) -> Id {
        let a = match self.node(a) {
            Node::Select(c, x, _) if c == cond => x,
            _ => a,
        };
        let b = match self.node(b) {
            Node::Select(c, _, y) if c == cond => y,
            _ => b,
        };
        if a == b {
            return a;
        }
        self.intern(Node::Select(cond, a, b))
    }

    /// Evaluates every node numerically (parameters flattened: `fields[f] = (start, vector)`;
    /// `conds[k]`: the value of condition k).
    #[cfg(test)]
    #[allow(clippy::too_many_arguments)]
    pub fn eval_all(
        &self,
        params: &[f64],
        fields: &[(usize, bool)],
        conds: &[bool],
        q: &[f64],
        v: &[f64],
        t: f64,
    ) -> Vec<f64> {
        let mut val = Vec::with_capacity(self.nodes.len());
        for node in &self.nodes {
            let g = |i: Id| val_at(&val, i);
            let x = match *node {
                Node::Const(b) => f64::from_bits(b),
                Node::Param(f, c) => {
                    let (start, vector) = fields[f as usize];
                    params[start + if vector { c as usize - 1 } else { 0 }]
                }
                Node::Q(i) => q[i as usize],
                Node::V(i) => v[i as usize],
                Node::T => t,
                Node::Add(a, b) => g(a) + g(b),
                Node::Sub(a, b) => g(a) - g(b),
                Node::Mul(a, b) => g(a) * g(b),
                Node::Div(a, b) => g(a) / g(b),
                Node::Neg(a) => -g(a),
                Node::Powi(a, n) => g(a).powi(n),
                Node::Powf(a, b) => g(a).powf(g(b)),
                Node::Atan2(a, b) => g(a).atan2(g(b)),
                Node::Un(f, a) => f.eval(g(a)),
                Node::Select(c, a, b) => {
                    if conds[c as usize] {
                        g(a)
                    } else {
                        g(b)
                    }
                }
            };
            val.push(x);
        }
        val
    }

    /// Forward-mode tangents of `targets` along the direction that gives each leaf the tangent
    /// `seed(leaf)` (`None`: zero). `support` is the set of variables with a nonzero seed:
    /// nodes that depend on none of them get the structural zero without being visited.
    pub fn tangents(
        &mut self,
        targets: &[Id],
        support: &VarSet,
        seed: &dyn Fn(&mut Dag, Node) -> Option<Id>,
    ) -> Vec<Id> {
        // Mark the nodes that need a tangent.
        let mut need = vec![false; self.nodes.len()];
        let mut stack: Vec<Id> = targets
            .iter()
            .copied()
            .filter(|&t| self.depends_on(t, support))
            .collect();
        while let Some(id) = stack.pop() {
            if need[id as usize] {
                continue;
            }
            need[id as usize] = true;
            for c in self.node(id).children() {
                if !need[c as usize] && self.depends_on(c, support) {
                    stack.push(c);
                }
            }
        }
        let mut tan: HashMap<Id, Id> = HashMap::new();
        for id in (0..need.len()).filter(|&i| need[i]) {
            let id = id as Id;
            let node = self.node(id);
            let d = |i: Id| tan.get(&i).copied().unwrap_or(Dag::ZERO);
            let t = match node {
                Node::Const(_) | Node::Param(..) => Dag::ZERO,
                Node::Q(_) | Node::V(_) | Node::T => seed(self, node).unwrap_or(Dag::ZERO),
                Node::Add(a, b) => {
                    let (da, db) = (d(a), d(b));
                    self.add(da, db)
                }
                Node::Sub(a, b) => {
                    let (da, db) = (d(a), d(b));
                    self.sub(da, db)
                }
                Node::Neg(a) => {
                    let da = d(a);
                    self.neg(da)
                }
                Node::Mul(a, b) => {
                    let (da, db) = (d(a), d(b));
                    let x = self.mul(da, b);
                    let y = self.mul(a, db);
                    self.add(x, y)
                }
                Node::Div(a, b) => {
                    // (a' − (a/b) b') / b
                    let (da, db) = (d(a), d(b));
                    let x = self.mul(id, db);
                    let y = self.sub(da, x);
                    self.div(y, b)
                }
                Node::Powi(a, n) => {
                    let da = d(a);
                    // a^(n−1), as a^n / a where n − 1 would overflow (n = i32::MIN)
                    let p = match n.checked_sub(1) {
                        Some(m) => self.powi(a, m),
                        None => {
                            let an = self.powi(a, n);
                            self.div(an, a)
                        }
                    };
                    let k = self.constant(f64::from(n));
                    let kp = self.mul(k, p);
                    self.mul(kp, da)
                }
                Node::Powf(a, b) => {
                    let (da, db) = (d(a), d(b));
                    // a^b (b' ln a + b a'/a)
                    let mut s = Dag::ZERO;
                    if da != Dag::ZERO {
                        let one = Dag::ONE;
                        let bm1 = self.sub(b, one);
                        let p = self.powf(a, bm1);
                        let bp = self.mul(b, p);
                        s = self.mul(bp, da);
                    }
                    if db != Dag::ZERO {
                        let ln = self.un(Fun::Ln, a);
                        let x = self.mul(id, ln);
                        let x = self.mul(x, db);
                        s = self.add(s, x);
                    }
                    s
                }
                Node::Select(c, a, b) => {
                    let (da, db) = (d(a), d(b));
                    self.select(c, da, db)
                }
                Node::Atan2(y, x) => {
                    let (dy, dx) = (d(y), d(x));
                    let a = self.mul(x, dy);
                    let b = self.mul(y, dx);
                    let num = self.sub(a, b);
                    let x2 = self.powi(x, 2);
                    let y2 = self.powi(y, 2);
                    let den = self.add(x2, y2);
                    self.div(num, den)
                }
                Node::Un(f, a) => {
                    let da = d(a);
                    f.derivative(self, id, a, da)
                }
            };
            if t != Dag::ZERO {
                tan.insert(id, t);
            }
        }
        targets
            .iter()
            .map(|t| tan.get(t).copied().unwrap_or(Dag::ZERO))
            .collect()
    }
}

#[cfg(test)]
fn val_at(v: &[f64], i: Id) -> f64 {
    v[i as usize]
}

impl Build for Dag {
    fn constant(&mut self, c: f64) -> Id {
        Dag::constant(self, c)
    }
    fn add(&mut self, a: Id, b: Id) -> Id {
        Dag::add(self, a, b)
    }
    fn sub(&mut self, a: Id, b: Id) -> Id {
        Dag::sub(self, a, b)
    }
    fn mul(&mut self, a: Id, b: Id) -> Id {
        Dag::mul(self, a, b)
    }
    fn div(&mut self, a: Id, b: Id) -> Id {
        Dag::div(self, a, b)
    }
    fn neg(&mut self, a: Id) -> Id {
        Dag::neg(self, a)
    }
    fn powi(&mut self, a: Id, n: i32) -> Id {
        Dag::powi(self, a, n)
    }
    fn un(&mut self, f: Fun, a: Id) -> Id {
        Dag::un(self, f, a)
    }
}
