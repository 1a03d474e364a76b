//! The flags of the generated impl, read from the front end's bodies (which names each body
//! mentions): CYCLIC, AUTONOMOUS, MOMENTUM_CONSERVED, ENERGY_CONSERVED, and for
//! `fn constraints` CONSTRAINED_COORDINATES and SCLERONOMIC. One syntactic rule for both modes,
//! so the modes agree; the symbolic mode may then [`Analysis::refine`] them from the derived
//! expressions.

use syn::{Block, Expr, Stmt};

use crate::front::{paren_less, Body, Front, Seed};
use crate::model::{Decl, FuncKind};

/// What the analysis found.
pub struct Analysis {
    /// CONSTRAINED_COORDINATES, one per slot: q_i appears in the body of `fn constraints` (a
    /// `Coord3` marks its three slots), or q_i or q̇_i in `fn velocity_constraints`. Empty
    /// without either.
    pub constrained: Vec<bool>,
    /// SCLERONOMIC: `fn constraints` has no `t: Time`, or does not use it, and the velocity
    /// constraints have no velocity-free term.
    pub scleronomic: bool,
    /// `Unilateral::SCLERONOMIC`: `fn contacts` has no `t: Time`, or does not use it.
    pub contacts_scleronomic: bool,
    /// CYCLIC, one per slot: q_i appears in none of L, D and Q.
    pub cyclic: Vec<bool>,
    /// AUTONOMOUS: L has no explicit t.
    pub autonomous: bool,
    /// MOMENTUM_CONSERVED, one per slot: cyclic, q̇_i absent from D, and Q's i-th entry a
    /// literal zero in the array `fn forces` ends with.
    pub momentum_conserved: Vec<bool>,
    /// ENERGY_CONSERVED: autonomous, no D, and no Q (or every entry of Q a literal zero).
    pub energy_conserved: bool,
}

/// CYCLIC, AUTONOMOUS, MOMENTUM_CONSERVED, ENERGY_CONSERVED and the constraints' flags, from the
/// names the front end's bodies mention.
pub fn analyze(decl: &Decl, front: &Front<'_>) -> Analysis {
    let func = |kind| front.func(kind);
    // Whether the body of the function of kind `kind` (if any) reads `seed`.
    let reads = |kind, seed| func(kind).is_some_and(|b: &Body<'_>| b.reads(seed));
    // Q's entries that are a literal zero (all false when the tail is not an array literal).
    let n = decl.n();
    let zero_force: Vec<bool> = match &decl.forces {
        None => vec![true; n],
        Some(f) => match tail_array(&f.body) {
            Some(elems) if elems.len() == n => elems.iter().map(|e| is_literal_zero(e)).collect(),
            _ => vec![false; n],
        },
    };
    // A coordinate is constrained when g mentions it, or a velocity constraint mentions it or
    // its velocity.
    let constrained: Vec<bool> =
        if decl.constraints.is_none() && decl.velocity_constraints.is_none() {
            Vec::new()
        } else {
            decl.coords
                .iter()
                .enumerate()
                .flat_map(|(p, c)| {
                    let used = reads(FuncKind::Constraints, Seed::Coord(p))
                        || reads(FuncKind::VelocityConstraints, Seed::Coord(p))
                        || reads(FuncKind::VelocityConstraints, Seed::Velocity(p));
                    std::iter::repeat_n(used, c.width())
                })
                .collect()
        };
    // Velocity constraints with a velocity-free term b(q, t) do work on the motion, as moving
    // constraints do.
    let scleronomic = !reads(FuncKind::Constraints, Seed::Time)
        && decl.velocity_constraints.as_ref().is_none_or(|f| !f.affine);
    let contacts_scleronomic = !reads(FuncKind::Contacts, Seed::Time);
    let mut cyclic = Vec::with_capacity(n);
    let mut momentum_conserved = Vec::with_capacity(n);
    for (p, c) in decl.coords.iter().enumerate() {
        let absent = !front.lagrangian.reads(Seed::Coord(p))
            && !reads(FuncKind::Dissipation, Seed::Coord(p))
            && !reads(FuncKind::Forces, Seed::Coord(p));
        let undamped = !reads(FuncKind::Dissipation, Seed::Velocity(p));
        for &zero in &zero_force[c.first_index..c.first_index + c.width()] {
            cyclic.push(absent);
            momentum_conserved.push(absent && undamped && zero);
        }
    }
    let autonomous = !front.lagrangian.reads(Seed::Time);
    // A moving constraint (g depends on t) does work on the system.
    let energy_conserved =
        autonomous && decl.dissipation.is_none() && zero_force.iter().all(|z| *z) && scleronomic;
    Analysis {
        constrained,
        scleronomic,
        contacts_scleronomic,
        cyclic,
        autonomous,
        momentum_conserved,
        energy_conserved,
    }
}

/// The elements of the array literal a body ends with (`[a, b, c]` as its tail expression).
pub fn tail_array(body: &Block) -> Option<Vec<&Expr>> {
    match body.stmts.last() {
        Some(Stmt::Expr(e, None)) => match paren_less(e) {
            Expr::Array(a) => Some(a.elems.iter().collect()),
            _ => None,
        },
        _ => None,
    }
}

/// A number literal equal to zero (`0.0`, `0`, `-0.0`, `0.0_f64`), possibly in parentheses.
fn is_literal_zero(e: &Expr) -> bool {
    match paren_less(e) {
        Expr::Lit(l) => match &l.lit {
            syn::Lit::Float(f) => f.base10_parse::<f64>().is_ok_and(|x| x == 0.0),
            syn::Lit::Int(i) => i.base10_parse::<u64>().is_ok_and(|x| x == 0),
            _ => false,
        },
        Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => is_literal_zero(&u.expr),
        _ => false,
    }
}

impl Analysis {
    /// The flags of the constrained motion: a coordinate the constraints read (holonomic or
    /// velocity: the constraint forces Gᵀλ, Aᵀλ act along it, and the constrained
    /// accelerations change with it) is neither cyclic nor has a conserved momentum, whatever
    /// L says (a sleigh's x, y and heading, all absent from its L). Applied last, after
    /// [`Analysis::refine`].
    pub fn constrain(&mut self) {
        for (i, &c) in self.constrained.iter().enumerate() {
            if c {
                self.cyclic[i] = false;
                self.momentum_conserved[i] = false;
            }
        }
    }

    /// The flags ORed with those the symbolic mode read from the derived expressions (a
    /// coordinate that leaves L only through an identity is cyclic there): both rules only say
    /// true where it holds.
    pub fn refine(&mut self, s: &crate::symbolic::Symmetry) {
        for (c, &e) in self.cyclic.iter_mut().zip(&s.cyclic) {
            *c |= e;
        }
        for (m, &e) in self
            .momentum_conserved
            .iter_mut()
            .zip(&s.momentum_conserved)
        {
            *m |= e;
        }
        self.autonomous |= s.autonomous;
        // A moving constraint does work: the expressions of L, D and Q do not see it.
        self.energy_conserved |= s.energy_conserved && self.scleronomic;
    }
}
