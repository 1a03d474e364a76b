//! Geometry: `velocity(x)` (the graph's tangent along (q̇, 1)), rotations (nine entries) with
//! composition, `r * v` and `transpose`, and the angular velocities Ṙ Rᵀ and Rᵀ Ṙ, each
//! component with its sin² + cos² pairs merged (so an angle that leaves ω leaves it in the
//! graph, and the L-level merge of `derive` can finish the job).

use super::*;
use crate::symbolic::dag::VarSet;
use crate::symbolic::poly;

/// R₁ R₂, row-major entries.
pub(super) fn compose(d: &mut Dag, a: &[Id; 9], b: &[Id; 9]) -> [Id; 9] {
    std::array::from_fn(|ij| {
        let (i, j) = (ij / 3, ij % 3);
        let mut s = Dag::ZERO;
        for k in 0..3 {
            let p = d.mul(a[3 * i + k], b[3 * k + j]);
            s = d.add(s, p);
        }
        s
    })
}

/// R v.
pub(super) fn apply(d: &mut Dag, a: &[Id; 9], v: &[Id; 3]) -> [Id; 3] {
    std::array::from_fn(|i| {
        let mut s = Dag::ZERO;
        for k in 0..3 {
            let p = d.mul(a[3 * i + k], v[k]);
            s = d.add(s, p);
        }
        s
    })
}

/// Rᵀ.
pub(super) fn transpose(a: &[Id; 9]) -> [Id; 9] {
    std::array::from_fn(|ij| a[3 * (ij % 3) + ij / 3])
}

impl Lower {
    /// A call of the geometry vocabulary (`Rotation::about_z(a)`, `velocity(x)`, …): `None` when
    /// `segs` names none of it.
    pub(super) fn geometry_call(&mut self, segs: &[String], c: &syn::ExprCall) -> R<Option<Val>> {
        let name = match segs {
            [ty, f] if ty == "Rotation" => format!("Rotation::{f}"),
            [ty, f] if ty == "Vector3" && matches!(f.as_str(), "x" | "y" | "z") => {
                format!("Vector3::{f}")
            }
            [f] if crate::front::timed::RATE_FUNCTIONS.contains(&f.as_str()) => f.clone(),
            _ => return Ok(None),
        };
        let arity = match name.as_str() {
            "Rotation::about_x" | "Rotation::about_y" | "Rotation::about_z" => 1,
            "Rotation::from_quaternion" => 4,
            "Rotation::identity" | "Vector3::x" | "Vector3::y" | "Vector3::z" => 0,
            "velocity" | "angular_velocity" | "body_angular_velocity" => 1,
            _ => return Ok(Some(self.unsupported(c.func.span(), &format!("`{name}`")))),
        };
        if c.args.len() != arity {
            return Ok(Some(self.err(syn::Error::new_spanned(
                c,
                format!("`{name}` takes {arity} argument(s)"),
            ))));
        }
        let mut args = Vec::with_capacity(arity);
        for a in &c.args {
            args.push(self.expr(a)?);
        }
        let (o, z) = (Dag::ONE, Dag::ZERO);
        Ok(Some(match name.as_str() {
            "Vector3::x" => Val::V([o, z, z]),
            "Vector3::y" => Val::V([z, o, z]),
            "Vector3::z" => Val::V([z, z, o]),
            "Rotation::identity" => Val::R([o, z, z, z, o, z, z, z, o]),
            "Rotation::about_x" | "Rotation::about_y" | "Rotation::about_z" => {
                let Some(a) = self.scalar(args.remove(0), &c.args[0], "the angle") else {
                    return Ok(Some(Val::Poison));
                };
                let s = self.dag.un(Fun::Sin, a);
                let cs = self.dag.un(Fun::Cos, a);
                let ns = self.dag.neg(s);
                Val::R(match name.as_str() {
                    "Rotation::about_x" => [o, z, z, z, cs, ns, z, s, cs],
                    "Rotation::about_y" => [cs, z, s, z, o, z, ns, z, cs],
                    _ => [cs, ns, z, s, cs, z, z, z, o],
                })
            }
            "Rotation::from_quaternion" => {
                let mut q = [Dag::ZERO; 4];
                for (k, v) in args.into_iter().enumerate() {
                    match self.scalar(v, &c.args[k], "a quaternion component") {
                        Some(id) => q[k] = id,
                        None => return Ok(Some(Val::Poison)),
                    }
                }
                Val::R(self.quaternion(q))
            }
            "velocity" => {
                let arg = &c.args[0];
                match args.remove(0) {
                    Val::S(id) => match self.rates(&[id], arg, "`velocity`") {
                        Some(r) => Val::S(r[0]),
                        None => Val::Poison,
                    },
                    Val::I(_) => Val::S(Dag::ZERO),
                    Val::V(v) => match self.rates(&v, arg, "`velocity`") {
                        Some(r) => Val::V([r[0], r[1], r[2]]),
                        None => Val::Poison,
                    },
                    Val::Poison => Val::Poison,
                    Val::R(_) => self.err(syn::Error::new(
                        arg.span(),
                        "`velocity` takes a `Scalar` or a `Vector3<Scalar>`, not a `Rotation`: \
                         for a rotation, use `angular_velocity(&r)` (space axes) or \
                         `body_angular_velocity(&r)` (body axes)",
                    )),
                    other => {
                        let kind = other.kind();
                        self.err(syn::Error::new(
                            arg.span(),
                            format!(
                                "`velocity` takes a `Scalar` or a `Vector3<Scalar>`, and this is {kind}"
                            ),
                        ))
                    }
                }
            }
            _ => {
                let arg = &c.args[0];
                let r = match args.remove(0) {
                    Val::R(r) => r,
                    Val::Poison => return Ok(Some(Val::Poison)),
                    other => {
                        let kind = other.kind();
                        return Ok(Some(self.err(syn::Error::new(
                            arg.span(),
                            format!("`{name}` takes a `Rotation`, and this is {kind}"),
                        ))));
                    }
                };
                let what = format!("`{name}`");
                let Some(rate) = self.rates(&r, arg, &what) else {
                    return Ok(Some(Val::Poison));
                };
                let rate: [Id; 9] = std::array::from_fn(|k| rate[k]);
                // ω̂ = Ṙ Rᵀ (space) or Rᵀ Ṙ (body); ω = (ω̂₂₁, ω̂₀₂, ω̂₁₀).
                let w = if name == "angular_velocity" {
                    compose(&mut self.dag, &rate, &transpose(&r))
                } else {
                    compose(&mut self.dag, &transpose(&r), &rate)
                };
                let merged = [w[7], w[2], w[3]].map(|id| {
                    crate::symbolic::derive::pythagorean(&mut self.dag, id, &poly::SYMMETRY)
                });
                Val::V(merged)
            }
        }))
    }

    /// The rotation of the quaternion (w, x, y, z), homogeneous form (|q|² times a rotation).
    fn quaternion(&mut self, q: [Id; 4]) -> [Id; 9] {
        let d = &mut self.dag;
        let [w, x, y, z] = q;
        let sq = |d: &mut Dag, a: Id| d.mul(a, a);
        let (ww, xx, yy, zz) = (sq(d, w), sq(d, x), sq(d, y), sq(d, z));
        let two = d.constant(2.0);
        let twice = |d: &mut Dag, a: Id, b: Id, c: Id, e: Id, plus: bool| {
            let p = d.mul(a, b);
            let r = d.mul(c, e);
            let s = if plus { d.add(p, r) } else { d.sub(p, r) };
            d.mul(two, s)
        };
        let diag = |d: &mut Dag, a: Id, b: Id, c: Id, e: Id| {
            // a + b − c − e
            let s = d.add(a, b);
            let s = d.sub(s, c);
            d.sub(s, e)
        };
        [
            diag(d, ww, xx, yy, zz),
            twice(d, x, y, z, w, false),
            twice(d, x, z, y, w, true),
            twice(d, x, y, z, w, true),
            diag(d, ww, yy, xx, zz),
            twice(d, y, z, x, w, false),
            twice(d, x, z, y, w, false),
            twice(d, y, z, x, w, true),
            diag(d, ww, zz, xx, yy),
        ]
    }

    /// The total time derivatives Σ ∂x/∂qᵢ q̇ᵢ + ∂x/∂t of `ids`; `None` (with an error at `at`)
    /// when one of them depends on the velocities.
    fn rates(&mut self, ids: &[Id], at: &Expr, what: &str) -> Option<Vec<Id>> {
        let vars = self.dag.vars;
        let mut velocities = VarSet::new(vars);
        let mut support = VarSet::new(vars);
        for i in 0..vars.n {
            velocities.insert(vars.v(i));
            support.insert(vars.q(i));
        }
        support.insert(vars.t());
        if ids.iter().any(|&id| self.dag.depends_on(id, &velocities)) {
            self.errors.push(syn::Error::new(
                at.span(),
                format!(
                    "{what} of a value that depends on the velocities: {what} takes a position (a \
                     function of the coordinates and `t`) and returns its time derivative; a \
                     velocity's rate would need the accelerations"
                ),
            ));
            return None;
        }
        Some(self.dag.tangents(ids, &support, &|d, node| match node {
            Node::Q(i) => Some(d.v(i as usize)),
            Node::T => Some(Dag::ONE),
            _ => None,
        }))
    }
}
