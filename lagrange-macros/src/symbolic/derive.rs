//! Derive the equations: M, f_L, the applied forces Q − ∂D/∂q̇, the right-hand side, the
//! momenta, the energy and the power as DAG nodes, by forward-mode tangents over the lowered
//! bodies, and the decoupled 2×2 blocks of M.
// Index loops mirror the textbook formulas; iterator forms would obscure them.
#![allow(clippy::needless_range_loop)]

use proc_macro2::TokenStream;

use super::codegen;
use super::dag::{Dag, Fun, Id, Node, VarSet};
use super::{lower, poly};
use crate::errors::Errors;
use crate::model::Decl;

/// The derivatives of L as DAG nodes.
pub struct Derivation {
    /// The expression DAG holding every node below.
    pub dag: Dag,
    /// The `self` fields and free names the body reads.
    pub fields: Vec<lower::Field>,
    /// Conditions of constant `if`s (`Node::Select`).
    pub conds: Vec<lower::Cond>,
    /// L itself.
    #[cfg_attr(not(test), allow(dead_code))]
    pub lagrangian: Id,
    /// ∂L/∂q̇ᵢ.
    pub momenta: Vec<Id>,
    /// Mᵢₖ = ∂²L/∂q̇ᵢ∂q̇ₖ, upper triangle (`m[i][k]`, k ≥ i; zeros below).
    pub mass: Vec<Vec<Id>>,
    /// fᵢ = ∂L/∂qᵢ − Σₖ (∂²L/∂q̇ᵢ∂qₖ) q̇ₖ − ∂²L/∂q̇ᵢ∂t (the Lagrangian part f_L).
    pub force: Vec<Id>,
    /// Qᵢ, the generalized forces of `fn forces` (zeros without one).
    pub generalized: Vec<Id>,
    /// −∂D/∂q̇ᵢ, the dissipative forces of `fn dissipation` (zeros without one).
    pub dissipative: Vec<Id>,
    /// The applied forces Qᵢ − ∂D/∂q̇ᵢ.
    pub applied: Vec<Id>,
    /// The right-hand side of M q̈ = rhs: fᵢ + Qᵢ − ∂D/∂q̇ᵢ, formed once (the straight-line solve
    /// and the fallback both read it; the same nodes as `force` without forces).
    pub rhs: Vec<Id>,
    /// The power (Q − ∂D/∂q̇)·q̇ − ∂L/∂t.
    pub power: Id,
    /// h = Σ q̇ᵢ pᵢ − L.
    pub energy: Id,
    /// The 2×2 diagonal blocks of M coupled to nothing else, (i, k, det), i < k: solved by
    /// Cramer's rule with the determinant expanded and cancelled (see `poly::det2`).
    /// The flag: the determinant cancelled to one monomial (accurate however small).
    pub pairs: Vec<(usize, usize, Id, bool)>,
    /// The conservation flags read from the derived expressions.
    pub symmetry: Symmetry,
}

/// The flags of the `Lagrangian` trait decided from the expressions (∂L/∂qᵢ ≡ 0 after expansion
/// and sin² + cos² = 1), not from the names a body mentions: a coordinate that cancels only
/// through an identity (a heavy top written from its rotation matrix, where ψ leaves through
/// sin²ψ + cos²ψ) is cyclic. Each is true only when the expression it rests on vanishes
/// identically (see [`vanishes`]); the macro ORs them with the rule by names, which never says
/// true where these say false.
#[derive(Clone, Debug)]
pub struct Symmetry {
    /// ∂L/∂qᵢ, ∂D/∂qᵢ and every ∂Qⱼ/∂qᵢ vanish: q̈ does not depend on qᵢ.
    pub cyclic: Vec<bool>,
    /// ∂L/∂t vanishes.
    pub autonomous: bool,
    /// Cyclic, and Qᵢ − ∂D/∂q̇ᵢ vanishes: pᵢ is conserved.
    pub momentum_conserved: Vec<bool>,
    /// Autonomous, and every Qᵢ − ∂D/∂q̇ᵢ vanishes: the energy h = q̇·p − L is conserved.
    pub energy_conserved: bool,
}

/// Whether `id` is identically zero: structurally, or its polynomial expansion over the DAG's
/// atoms (under [`poly::SYMMETRY`]'s caps) reduces to no term modulo sin²x + cos²x = 1
/// ([`poly::reduce_pythagorean`], exact: coefficients cancel only when they are equal). An
/// expansion past the caps does not vanish: the answer is never "zero" for an expression that
/// is not.
pub fn vanishes(dag: &Dag, id: Id) -> bool {
    if id == Dag::ZERO {
        return true;
    }
    let Some(mut p) = poly::expand_under(dag, id, &poly::SYMMETRY) else {
        return false;
    };
    let sin_of = |a: Id| match dag.node(a) {
        Node::Un(Fun::Cos, x) => dag.find(Node::Un(Fun::Sin, x)),
        _ => None,
    };
    poly::reduce_pythagorean(&mut p, &sin_of, &poly::SYMMETRY) && p.0.is_empty()
}

/// The 2×2 blocks {i, k} of M (upper triangle) that no other coordinate couples to.
fn decoupled_pairs(mass: &[Vec<Id>]) -> Vec<(usize, usize)> {
    let n = mass.len();
    let coupled = |i: usize, k: usize| {
        let (a, b) = if i < k { (i, k) } else { (k, i) };
        mass[a][b] != Dag::ZERO
    };
    let mut pairs = Vec::new();
    for i in 0..n {
        for k in i + 1..n {
            if coupled(i, k)
                && (0..n)
                    .filter(|&j| j != i && j != k)
                    .all(|j| !coupled(i, j) && !coupled(k, j))
            {
                pairs.push((i, k));
            }
        }
    }
    pairs
}

/// `id` with its sin² + cos² pairs merged (see [`poly::merge_pythagorean`]) where it expands
/// within `rules`' caps and something merges; as it is otherwise (merging only removes terms).
pub(crate) fn pythagorean(dag: &mut Dag, id: Id, rules: &poly::Rules) -> Id {
    let Some(mut p) = poly::expand_under(dag, id, rules) else {
        return id;
    };
    let cos_of = |a: Id| match dag.node(a) {
        Node::Un(Fun::Sin, x) => dag.find(Node::Un(Fun::Cos, x)),
        _ => None,
    };
    let mut merged = false;
    while poly::merge_pythagorean(&mut p, &cos_of) {
        merged = true;
    }
    if merged {
        poly::build(dag, &p)
    } else {
        id
    }
}

/// L with its sin² + cos² pairs merged where that removes a coordinate (or t) from it: a heavy
/// top written from its rotation matrix (ω_body of R_z(φ) R_x(θ) R_z(ψ)) has ψ in L only through
/// sin²ψ + cos²ψ, and after the merge every derivative (M, f, the momenta, the energy, the
/// printed equations) is free of it. Otherwise L keeps its factored form: the expanded sum of
/// monomials of a pendulum chain's L made its q̈ 12–17 % slower (N = 2, 4) although pairs merged.
fn without_hidden_coordinates(dag: &mut Dag, l: Id, n: usize) -> Id {
    let merged = pythagorean(dag, l, &poly::SYMMETRY);
    if merged == l {
        return l;
    }
    let vars = dag.vars;
    let gone = (0..n).map(|i| vars.q(i)).chain([vars.t()]).any(|var| {
        let mut set = VarSet::new(vars);
        set.insert(var);
        dag.depends_on(l, &set) && !dag.depends_on(merged, &set)
    });
    if gone {
        merged
    } else {
        l
    }
}

/// Lowers the body of `decl` and differentiates it; `None` (with the reasons pushed to
/// `errors`) when the body cannot be lowered.
pub fn derive(
    decl: &Decl,
    front: &crate::front::Front<'_>,
    errors: &mut Errors,
) -> Option<Derivation> {
    let lowered = lower::lower(decl, front, errors)?;
    let mut dag = lowered.dag;
    let l = without_hidden_coordinates(&mut dag, lowered.lagrangian, decl.n());
    let n = decl.n();
    let vars = dag.vars;
    let unit = |var: usize| {
        let mut s = VarSet::new(vars);
        s.insert(var);
        s
    };
    let mut momenta = Vec::with_capacity(n);
    for i in 0..n {
        let p = dag.tangents(&[l], &unit(vars.v(i)), &|_, node| {
            (node == Node::V(i as u32)).then_some(Dag::ONE)
        });
        momenta.push(p[0]);
    }
    let mut mass = vec![vec![Dag::ZERO; n]; n];
    for k in 0..n {
        let col = dag.tangents(&momenta[..=k], &unit(vars.v(k)), &|_, node| {
            (node == Node::V(k as u32)).then_some(Dag::ONE)
        });
        for (i, m) in col.into_iter().enumerate() {
            mass[i][k] = m;
        }
    }
    // sin² + cos² = 1 in the entries of M (an N-link chain's Σ m l² (sin² θ + cos² θ)): the
    // code computes fewer operations, and a pair that only cancelled through the identity is a
    // structural zero or a constant.
    for i in 0..n {
        for k in i..n {
            mass[i][k] = pythagorean(&mut dag, mass[i][k], &poly::DETERMINANT);
            mass[k][i] = mass[i][k];
        }
    }
    // The total time derivative of the momenta at fixed q̇: Σₖ q̇ₖ ∂/∂qₖ + ∂/∂t.
    let mut along = VarSet::new(vars);
    for k in 0..n {
        along.insert(vars.q(k));
    }
    along.insert(vars.t());
    let dp = dag.tangents(&momenta, &along, &|dag, node| match node {
        Node::Q(k) => Some(dag.v(k as usize)),
        Node::T => Some(Dag::ONE),
        _ => None,
    });
    let mut force = Vec::with_capacity(n);
    let mut dl_dq = Vec::with_capacity(n);
    for (i, dpi) in dp.into_iter().enumerate() {
        let g = dag.tangents(&[l], &unit(vars.q(i)), &|_, node| {
            (node == Node::Q(i as u32)).then_some(Dag::ONE)
        });
        dl_dq.push(g[0]);
        let f = dag.sub(g[0], dpi);
        force.push(dag.collect_terms(f));
    }
    let mut energy = dag.neg(l);
    for (i, &p) in momenta.iter().enumerate() {
        let v = dag.v(i);
        let vp = dag.mul(v, p);
        energy = dag.add(energy, vp);
    }
    // Applied forces and the right-hand side (formed once), then the power.
    let has_forces = lowered.forces.is_some();
    let generalized = lowered.forces.unwrap_or_else(|| vec![Dag::ZERO; n]);
    let mut dissipative = vec![Dag::ZERO; n];
    if let Some(dd) = lowered.dissipation {
        for (i, slot) in dissipative.iter_mut().enumerate() {
            let g = dag.tangents(&[dd], &unit(vars.v(i)), &|_, node| {
                (node == Node::V(i as u32)).then_some(Dag::ONE)
            });
            *slot = dag.neg(g[0]);
        }
    }
    let applied: Vec<Id> = (0..n)
        .map(|i| dag.add(generalized[i], dissipative[i]))
        .collect();
    let rhs: Vec<Id> = (0..n).map(|i| dag.add(force[i], applied[i])).collect();
    let pairs = decoupled_pairs(&mass)
        .into_iter()
        .map(|(i, k)| {
            let (det, exact) = poly::det2(&mut dag, mass[i][i], mass[k][k], mass[i][k]);
            (i, k, det, exact)
        })
        .collect();
    let dldt = dag.tangents(&[l], &unit(vars.t()), &|_, node| {
        (node == Node::T).then_some(Dag::ONE)
    })[0];
    let mut power = dag.neg(dldt);
    for (i, &a) in applied.iter().enumerate() {
        let v = dag.v(i);
        let av = dag.mul(a, v);
        power = dag.add(power, av);
    }
    let symmetry = symmetry(
        &mut dag,
        &dl_dq,
        lowered.dissipation,
        has_forces.then_some(&generalized[..]),
        &applied,
        dldt,
    );
    Some(Derivation {
        symmetry,
        pairs,
        generalized,
        dissipative,
        applied,
        rhs,
        power,
        dag,
        fields: lowered.fields,
        conds: lowered.conds,
        lagrangian: l,
        momenta,
        mass,
        force,
        energy,
    })
}

/// The flags from the expressions: ∂L/∂qᵢ (`dl_dq`), D and Q (if declared) differentiated by
/// each qᵢ, the applied forces Qᵢ − ∂D/∂q̇ᵢ and ∂L/∂t.
fn symmetry(
    dag: &mut Dag,
    dl_dq: &[Id],
    dissipation: Option<Id>,
    forces: Option<&[Id]>,
    applied: &[Id],
    dldt: Id,
) -> Symmetry {
    let vars = dag.vars;
    let n = dl_dq.len();
    let mut cyclic = Vec::with_capacity(n);
    for (i, &g) in dl_dq.iter().enumerate() {
        let mut along = VarSet::new(vars);
        along.insert(vars.q(i));
        let seed = |_: &mut Dag, node: Node| (node == Node::Q(i as u32)).then_some(Dag::ONE);
        let mut absent = vanishes(dag, g);
        if absent {
            if let Some(d) = dissipation {
                let dd = dag.tangents(&[d], &along, &seed)[0];
                absent = vanishes(dag, dd);
            }
        }
        if absent {
            if let Some(q) = forces {
                let dq = dag.tangents(q, &along, &seed);
                absent = dq.iter().all(|&x| vanishes(dag, x));
            }
        }
        cyclic.push(absent);
    }
    let still: Vec<bool> = applied.iter().map(|&a| vanishes(dag, a)).collect();
    let autonomous = vanishes(dag, dldt);
    Symmetry {
        momentum_conserved: (0..n).map(|i| cyclic[i] && still[i]).collect(),
        energy_conserved: autonomous && still.iter().all(|s| *s),
        cyclic,
        autonomous,
    }
}

/// M q̈ = rhs as operands of the generated code (`None`: a structural zero), formed once from a
/// [`Derivation`] and read by both the straight-line solve and the fallback's arrays.
pub struct Equations {
    /// Mᵢₖ, upper triangle (`mass[i][k]`, k ≥ i; `None` below the diagonal).
    pub mass: Vec<Vec<Option<TokenStream>>>,
    /// fᵢ + Qᵢ − ∂D/∂q̇ᵢ, the right-hand side.
    pub rhs: Vec<Option<TokenStream>>,
}

impl Equations {
    /// The operands of `d.mass` and `d.rhs` (each an inline leaf or the local of its node) in
    /// the generic kernel over `r` (a constant is an `R`).
    pub fn of(d: &Derivation, r: &TokenStream) -> Equations {
        let op =
            |id: Id| (id != Dag::ZERO).then(|| codegen::operand_as(&d.dag, &d.fields, id, Some(r)));
        Equations {
            mass: d
                .mass
                .iter()
                .enumerate()
                .map(|(i, row)| {
                    row.iter()
                        .enumerate()
                        .map(|(k, &m)| if k < i { None } else { op(m) })
                        .collect()
                })
                .collect(),
            rhs: d.rhs.iter().map(|&x| op(x)).collect(),
        }
    }
}
