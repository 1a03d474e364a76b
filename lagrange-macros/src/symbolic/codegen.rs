//! Emission of straight-line Rust from the DAG: each reachable node once, in id (topological)
//! order, as `let <xN> = ...;` (locals named by `names::node`); leaves (constants, `q[i]`,
//! `qdot[i]`, `t`, parameters) inline.

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{quote, quote_spanned};

use super::dag::{Dag, Fun, Id, Node};
use super::lower::{Cond, Field};
use crate::names;

/// Above this many levels the straight-line code is emitted in chunks (see [`emit_as`]).
const CHUNK_ABOVE: usize = 256;

/// Straight-line code computing a set of DAG nodes.
pub struct Code {
    /// The parameter loads and conditions.
    pub loads: TokenStream,
    /// The values, after the loads.
    pub values: TokenStream,
    /// The locals `loads` binds, with their types, in order: the inputs of `values`.
    pub inputs: Vec<(Ident, TokenStream)>,
    /// Per input, the name of the field it loads (`g` for `self.g`), or `None` where it is not
    /// a field of `self` (a free constant, parameter-only code, a condition).
    pub fields: Vec<Option<String>>,
    /// How many `let` statements were emitted for DAG nodes.
    pub lets: usize,
}

fn field_local(f: &Field) -> Ident {
    match &f.opaque {
        Some((k, _)) => names::opaque(*k),
        None => names::field(&f.name, f.free),
    }
}

fn const_tokens(c: f64) -> TokenStream {
    if c.is_nan() {
        quote!(f64::NAN)
    } else if c == f64::INFINITY {
        quote!(f64::INFINITY)
    } else if c == f64::NEG_INFINITY {
        quote!(f64::NEG_INFINITY)
    } else if c < 0.0 {
        let l = Literal::f64_unsuffixed(-c);
        quote!(-#l)
    } else {
        let l = Literal::f64_unsuffixed(c);
        quote!(#l)
    }
}

/// The tokens of an operand in code over `num` (`None`: `f64`; `Some(R)`: a generic kernel,
/// where a constant becomes an `R`, so every operand has the kernel's type).
pub fn operand_as(dag: &Dag, fields: &[Field], id: Id, num: Option<&TokenStream>) -> TokenStream {
    match (num, dag.as_const(id)) {
        (Some(r), Some(_)) => real_const(r, &operand(dag, fields, id)),
        _ => operand(dag, fields, id),
    }
}

/// The `f64` constant `c` as an `R` of a generic kernel.
pub fn real_const(r: &TokenStream, c: &TokenStream) -> TokenStream {
    quote!(<#r as ::core::convert::From<f64>>::from(#c))
}

/// The tokens of an operand: a leaf inline, an inner node by its local name.
pub fn operand(dag: &Dag, fields: &[Field], id: Id) -> TokenStream {
    let names::Params { q, qdot, t } = names::Params::symbolic();
    match dag.node(id) {
        Node::Const(b) => const_tokens(f64::from_bits(b)),
        Node::Q(i) => {
            let i = Literal::usize_unsuffixed(i as usize);
            quote!(#q[#i])
        }
        Node::V(i) => {
            let i = Literal::usize_unsuffixed(i as usize);
            quote!(#qdot[#i])
        }
        Node::T => quote!(#t),
        Node::Param(f, c) => {
            let local = field_local(&fields[f as usize]);
            match c {
                1 => quote!(#local.x),
                2 => quote!(#local.y),
                3 => quote!(#local.z),
                _ => quote!(#local),
            }
        }
        _ => {
            let x = names::node(id);
            quote!(#x)
        }
    }
}

/// An operand in method-receiver position (a constant needs its type and, if negative, parens;
/// in a generic kernel it is an `R`).
fn receiver(dag: &Dag, fields: &[Field], id: Id, num: Option<&TokenStream>) -> TokenStream {
    match dag.as_const(id) {
        Some(_) if num.is_some() => operand_as(dag, fields, id, num),
        Some(c) if c.is_finite() => {
            let l = Literal::f64_suffixed(c.abs());
            if c < 0.0 {
                quote!((-#l))
            } else {
                quote!(#l)
            }
        }
        _ => operand(dag, fields, id),
    }
}

/// 1 + the deepest level of the inner (non-leaf) operands of `node`; 0 if it has none.
fn node_level(dag: &Dag, level: &[usize], node: Node) -> usize {
    node.children()
        .filter(|&c| !dag.node(c).is_leaf())
        .map(|c| level[c as usize] + 1)
        .max()
        .unwrap_or(0)
}

/// Emits the code computing `outputs` (and everything they need).
pub fn emit(dag: &Dag, fields: &[Field], conds: &[Cond], outputs: &[Id]) -> Code {
    emit_as(dag, fields, conds, outputs, None)
}

/// The number type of the generic kernels: `R`, bound to `::lagrange::__private::Real`.
pub fn real_type() -> TokenStream {
    let r = names::real();
    quote!(#r)
}

/// Emits the code computing `outputs` over `num` (`None`: `f64`; `Some(R)`: the body of a
/// kernel generic over `Real`, whose `f64` instance is the scalar code and whose lanes
/// instance computes each lane's scalar value): the same operations in the same order. In a
/// generic kernel the loads are the scalar ones (for the parameter array); the values read the
/// locals [`param_binds`] binds.
pub fn emit_as(
    dag: &Dag,
    fields: &[Field],
    conds: &[Cond],
    outputs: &[Id],
    lanes: Option<&TokenStream>,
) -> Code {
    let num = match lanes {
        Some(l) => l.clone(),
        None => quote!(f64),
    };
    let rt = quote!(::lagrange::__private::Real);
    let mut need = vec![false; dag.len()];
    let mut stack: Vec<Id> = outputs.to_vec();
    while let Some(id) = stack.pop() {
        if need[id as usize] {
            continue;
        }
        need[id as usize] = true;
        stack.extend(dag.node(id).children());
    }
    // Parameter loads, typed, spanned at the field's first use.
    let mut stmts = TokenStream::new();
    let mut inputs = Vec::new();
    let mut input_fields = Vec::new();
    let mut loaded = vec![false; fields.len()];
    for (id, needed) in need.iter().enumerate() {
        if let (true, Node::Param(f, _)) = (*needed, dag.node(id as Id)) {
            loaded[f as usize] = true;
        }
    }
    for (f, field) in fields.iter().enumerate() {
        if !loaded[f] {
            continue;
        }
        let local = field_local(field);
        let member = &field.member;
        let ty = if field.vector {
            quote!(::lagrange::__private::Vector3<f64>)
        } else {
            quote!(f64)
        };
        // `self` must resolve like the receiver of the generated method (call-site hygiene),
        // while errors point at the user's field.
        let this = Ident::new("self", Span::call_site().located_at(field.span));
        inputs.push((local.clone(), ty.clone()));
        input_fields.push((field.opaque.is_none() && !field.free).then(|| field.name.clone()));
        if let Some((_, tokens)) = &field.opaque {
            stmts.extend(quote_spanned!(field.span=> let #local: #ty = #tokens;));
        } else if field.free {
            stmts.extend(quote_spanned!(field.span=> let #local: #ty = #member;));
        } else {
            stmts.extend(quote_spanned!(field.span=> let #local: #ty = #this.#member;));
        }
    }
    // Conditions of constant `if`s: one `bool` each, evaluated as written (spanned at the user's
    // condition, `self` resolved like the field loads).
    let mut used = vec![false; conds.len()];
    for (id, needed) in need.iter().enumerate() {
        if let (true, Node::Select(c, _, _)) = (*needed, dag.node(id as Id)) {
            used[c as usize] = true;
        }
    }
    for (k, cond) in conds.iter().enumerate() {
        if used[k] {
            let b = names::cond(k as u32);
            let tokens = &cond.tokens;
            stmts.extend(quote_spanned!(cond.span=> let #b: bool = #tokens;));
            inputs.push((b, quote!(bool)));
            input_fields.push(None);
        }
    }
    let loads = std::mem::take(&mut stmts);
    let fused = multiply_adds(dag, &need, outputs, lanes.is_some());
    // Every `let` opens a lexical scope, and debug info nests them: thousands of sequential
    // `let`s overflow LLVM's stack. Nodes are grouped by level (1 + the deepest inner operand)
    // into one tuple `let` per level, so the nesting depth is the depth of the DAG.
    let mut level = vec![0usize; dag.len()];
    // (pattern, type, value) per level.
    let mut by_level: Vec<Vec<(TokenStream, TokenStream, TokenStream)>> = Vec::new();
    let mut lets = 0;
    for (id, needed) in need.iter().enumerate() {
        let id = id as Id;
        let node = dag.node(id);
        if !*needed || node.is_leaf() {
            continue;
        }
        if fused.absorbed[id as usize] {
            // Computed inside the sum that uses it (see `multiply_adds`).
            level[id as usize] = node_level(dag, &level, node);
            continue;
        }
        // A needed sin(a) and cos(a) become one `a.sin_cos()` (emitted with the sin).
        let partner = match node {
            Node::Un(Fun::Sin, a) => dag
                .find(Node::Un(Fun::Cos, a))
                .filter(|&c| need[c as usize])
                .map(|c| (id, c)),
            Node::Un(Fun::Cos, a) => {
                if dag
                    .find(Node::Un(Fun::Sin, a))
                    .is_some_and(|s| need[s as usize])
                {
                    // Emitted with the sin.
                    level[id as usize] = node_level(dag, &level, node);
                    continue;
                }
                None
            }
            _ => None,
        };
        let o = |i: Id| operand_as(dag, fields, i, lanes);
        let receiver = |i: Id| receiver(dag, fields, i, lanes);
        // A sum that computes its product (see `multiply_adds`): x·y + c, x·y − c as x·y + (−c),
        // c − x·y as (−x)·y + c — the values of the unfused expression, bit for bit, where `madd`
        // rounds twice.
        let fuse = fused.with[id as usize].and_then(|(m, at_a)| match dag.node(m) {
            Node::Mul(x, y) => Some((o(x), o(y), at_a)),
            _ => None,
        });
        let madd = |x: TokenStream, y: TokenStream, c: TokenStream| quote!(<#num as #rt>::madd(#x, #y, #c));
        let rhs = match (node, fuse) {
            (Node::Add(_, c), Some((x, y, true))) => madd(x, y, o(c)),
            (Node::Add(c, _), Some((x, y, false))) => madd(x, y, o(c)),
            (Node::Sub(_, c), Some((x, y, true))) => {
                let c = o(c);
                madd(x, y, quote!(-#c))
            }
            (Node::Sub(c, _), Some((x, y, false))) => madd(quote!(-#x), y, o(c)),
            _ => match node {
                Node::Un(_, a) if partner.is_some() => {
                    let a = receiver(a);
                    quote!(#a.sin_cos())
                }
                Node::Add(a, b) => {
                    let (a, b) = (o(a), o(b));
                    quote!(#a + #b)
                }
                Node::Sub(a, b) => {
                    let (a, b) = (o(a), o(b));
                    quote!(#a - #b)
                }
                Node::Mul(a, b) => {
                    let (a, b) = (o(a), o(b));
                    quote!(#a * #b)
                }
                Node::Div(a, b) => {
                    let (a, b) = (o(a), o(b));
                    quote!(#a / #b)
                }
                Node::Neg(a) => {
                    let a = o(a);
                    quote!(-#a)
                }
                Node::Powi(a, 2) => {
                    let a = o(a);
                    quote!(#a * #a)
                }
                Node::Powi(a, n) => {
                    let a = receiver(a);
                    let n = Literal::i32_unsuffixed(n);
                    quote!(#a.powi(#n))
                }
                Node::Powf(a, b) => {
                    let (a, b) = (receiver(a), o(b));
                    quote!(#a.powf(#b))
                }
                Node::Select(c, a, b) => {
                    let (a, b) = (o(a), o(b));
                    let c = names::cond(c);
                    match lanes {
                        Some(l) => quote!(<#l as #rt>::select(#c, #a, #b)),
                        None => quote!(if #c { #a } else { #b }),
                    }
                }
                Node::Atan2(y, x) => {
                    let (y, x) = (receiver(y), o(x));
                    quote!(#y.atan2(#x))
                }
                Node::Un(Fun::Step, a) => {
                    let a = o(a);
                    match lanes {
                        Some(l) => quote!(<#l as #rt>::step(#a)),
                        None => quote!(if #a >= 0.0 { 1.0_f64 } else { 0.0_f64 }),
                    }
                }
                Node::Un(f, a) => {
                    let a = receiver(a);
                    let m = Ident::new(f.method(), Span::call_site());
                    quote!(#a.#m())
                }
                Node::Const(_) | Node::Param(..) | Node::Q(_) | Node::V(_) | Node::T => continue,
            },
        };
        let lv = node_level(dag, &level, node);
        level[id as usize] = lv;
        if by_level.len() <= lv {
            by_level.resize_with(lv + 1, Vec::new);
        }
        let (pat, ty) = match partner {
            Some((s, c)) => {
                let (s, c) = (names::node(s), names::node(c));
                lets += 1;
                (quote!((#s, #c)), quote!((#num, #num)))
            }
            None => {
                let x = names::node(id);
                (quote!(#x), quote!(#num))
            }
        };
        by_level[lv].push((pat, ty, rhs));
        lets += 1;
    }
    // A DAG deeper than CHUNK_ABOVE levels (a body of 1500 chained `let`s: some 5000) still
    // nested too deep for a debug build: its levels are emitted in chunks of √levels, each a
    // block whose value is the tuple of what it binds, so the nesting is about 2√levels.
    let level_lets = |groups: &[Vec<(TokenStream, TokenStream, TokenStream)>]| {
        let mut out = TokenStream::new();
        for group in groups {
            if let [(x, ty, rhs)] = group.as_slice() {
                out.extend(quote!(let #x: #ty = #rhs;));
            } else if !group.is_empty() {
                let xs = group.iter().map(|(x, _, _)| x);
                let tys = group.iter().map(|(_, t, _)| t);
                let rhss = group.iter().map(|(_, _, r)| r);
                out.extend(quote!(let (#(#xs,)*): (#(#tys,)*) = (#(#rhss,)*);));
            }
        }
        out
    };
    if by_level.len() <= CHUNK_ABOVE {
        stmts.extend(level_lets(&by_level));
    } else {
        let k = by_level.len().isqrt() + 1;
        for chunk in by_level.chunks(k) {
            let inner = level_lets(chunk);
            let xs: Vec<&TokenStream> = chunk.iter().flatten().map(|(x, _, _)| x).collect();
            let tys = chunk.iter().flatten().map(|(_, t, _)| t);
            stmts.extend(quote!(let (#(#xs,)*): (#(#tys,)*) = { #inner (#(#xs,)*) };));
        }
    }
    Code {
        loads,
        values: stmts,
        inputs,
        fields: input_fields,
        lets,
    }
}

/// Which products a generic kernel computes inside the sum that uses them.
struct MultiplyAdds {
    /// The product is computed by its user's `madd` (not bound on its own).
    absorbed: Vec<bool>,
    /// For a sum or difference: the product it fuses and whether it is the left operand.
    with: Vec<Option<(Id, bool)>>,
}

/// The multiply-adds of a generic kernel (`generic`; none in `f64` code): every product that is
/// needed once, by a sum or a difference, and is not an output, is computed in that sum as
/// `Real::madd(x, y, c)` — rounded twice for `f64` and the exact lanes (the same values as
/// `x * y + c`, bit for bit), once in the fused lanes (a fused multiply-add: one rounding, and
/// half the latency on the dependency chains that bound a right-hand side). Where both operands
/// are such products, the deeper one is fused (the other is computed alongside).
fn multiply_adds(dag: &Dag, need: &[bool], outputs: &[Id], generic: bool) -> MultiplyAdds {
    let n = dag.len();
    let mut out = MultiplyAdds {
        absorbed: vec![false; n],
        with: vec![None; n],
    };
    if !generic {
        return out;
    }
    let mut uses = vec![0u32; n];
    let mut depth = vec![0usize; n];
    for (id, _) in need.iter().enumerate().filter(|(_, &needed)| needed) {
        let node = dag.node(id as Id);
        for c in node.children() {
            uses[c as usize] += 1;
            depth[id] = depth[id].max(depth[c as usize] + 1);
        }
    }
    for &o in outputs {
        uses[o as usize] += 2;
    }
    let single_product = |x: Id| uses[x as usize] == 1 && matches!(dag.node(x), Node::Mul(..));
    for (id, _) in need.iter().enumerate().filter(|(_, &needed)| needed) {
        let (a, b) = match dag.node(id as Id) {
            Node::Add(a, b) | Node::Sub(a, b) if a != b => (a, b),
            _ => continue,
        };
        let pick = match (single_product(a), single_product(b)) {
            (true, true) if depth[b as usize] > depth[a as usize] => Some((b, false)),
            (true, _) => Some((a, true)),
            (false, true) => Some((b, false)),
            (false, false) => None,
        };
        if let Some((m, at_a)) = pick {
            out.absorbed[m as usize] = true;
            out.with[id] = Some((m, at_a));
        }
    }
    out
}

/// The parameters of the generic kernels: every field and condition the body reads, in one
/// `[f64; P]` per member (a field of type `Vector3<f64>` takes three slots, a condition one: 1
/// or 0). The statements binding them inside a kernel from `params: &[R; P]`
/// ([`KernelParams::binds`]) and the body of the inherent `__lagrange_params(&self)` that loads
/// them from `self` (spanned at the user's fields).
pub struct KernelParams {
    /// Binds every input as an `R` (a condition as `R::Mask`, a vector as `Vector3<R>`).
    pub binds: TokenStream,
    /// The loads from `self`, then the array of their values.
    pub load: TokenStream,
    /// P.
    pub count: usize,
    /// Per slot, the field it holds (`g`; a vector field's components `r.x`, `r.y`, `r.z`), or
    /// `""` where the slot is not a field of `self` (a free constant, parameter-only code, a
    /// condition): the names `Lagrangian::KERNEL_FIELDS` exposes for exact parameter
    /// derivatives.
    pub names: Vec<String>,
}

/// [`KernelParams`] of the derivation's fields and conditions (all of them, whatever a kernel
/// reads: one array serves q̈ and the Taylor series).
pub fn kernel_params(dag: &Dag, fields: &[Field], conds: &[Cond], params: &Ident) -> KernelParams {
    let inputs: Vec<Id> = (0..dag.len() as Id)
        .filter(|&id| matches!(dag.node(id), Node::Param(..) | Node::Select(..)))
        .collect();
    let code = emit(dag, fields, conds, &inputs);
    let r = real_type();
    let rt = quote!(::lagrange::__private::Real);
    let mut binds = TokenStream::new();
    let mut values = Vec::new();
    let mut names = Vec::new();
    let mut k = 0usize;
    for ((x, ty), field) in code.inputs.iter().zip(&code.fields) {
        let field = field.as_deref().unwrap_or("");
        let ty = ty.to_string();
        let i = Literal::usize_unsuffixed(k);
        if ty == "bool" {
            binds.extend(quote!(let #x: <#r as #rt>::Mask = <#r as #rt>::nonzero(#params[#i]);));
            values.push(quote!(if #x { 1.0 } else { 0.0 }));
            names.push(String::new());
            k += 1;
        } else if ty.contains("Vector3") {
            let (j, m) = (
                Literal::usize_unsuffixed(k + 1),
                Literal::usize_unsuffixed(k + 2),
            );
            binds.extend(quote! {
                let #x: ::lagrange::__private::Vector3<#r> =
                    ::lagrange::__private::Vector3::new(#params[#i], #params[#j], #params[#m]);
            });
            values.extend([quote!(#x.x), quote!(#x.y), quote!(#x.z)]);
            names.extend(["x", "y", "z"].map(|c| {
                if field.is_empty() {
                    String::new()
                } else {
                    format!("{field}.{c}")
                }
            }));
            k += 3;
        } else {
            binds.extend(quote!(let #x: #r = #params[#i];));
            values.push(quote!(#x));
            names.push(field.to_string());
            k += 1;
        }
    }
    let loads = &code.loads;
    KernelParams {
        binds,
        load: quote!(#loads [#(#values),*]),
        count: k,
        names,
    }
}

impl Code {
    /// All the `let` statements: the loads, then the values.
    pub fn stmts(&self) -> TokenStream {
        let mut all = self.loads.clone();
        all.extend(self.values.clone());
        all
    }
}
