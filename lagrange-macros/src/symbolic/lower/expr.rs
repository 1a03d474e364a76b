//! Expressions: paths, fields, indexing, ranges, `if` (on parameters: a select), unary and binary
//! arithmetic over scalars and vectors.

use super::*;

impl Lower {
    pub(super) fn expr(&mut self, e: &Expr) -> R<Val> {
        Ok(match e {
            Expr::Paren(p) => self.expr(&p.expr)?,
            Expr::Group(g) => self.expr(&g.expr)?,
            Expr::Reference(r) => self.expr(&r.expr)?,
            Expr::Unary(u) => match u.op {
                UnOp::Deref(_) => self.expr(&u.expr)?,
                UnOp::Neg(_) => {
                    let v = self.expr(&u.expr)?;
                    self.neg(v)
                }
                _ => self.unsupported(u.span(), "this operator"),
            },
            Expr::Lit(l) => match &l.lit {
                Lit::Float(f) => match f.base10_parse::<f64>() {
                    Ok(x) => Val::S(self.dag.constant(x)),
                    Err(e) => self.err(e),
                },
                Lit::Int(i) => match (i.suffix(), i.base10_parse::<i64>()) {
                    (
                        "" | "i8" | "i16" | "i32" | "i64" | "isize" | "u8" | "u16" | "u32" | "u64"
                        | "usize",
                        Ok(k),
                    ) => Val::I(k),
                    _ => match i.base10_parse::<f64>() {
                        Ok(x) => Val::S(self.dag.constant(x)),
                        Err(e) => self.err(e),
                    },
                },
                other => self.unsupported(other.span(), "this literal"),
            },
            Expr::Path(p) => self.path(p),
            Expr::Tuple(t) => {
                let mut items = Vec::new();
                for e in &t.elems {
                    items.push(self.expr(e)?);
                }
                Val::Tuple(items)
            }
            Expr::Block(b) if b.label.is_none() => self.block(&b.block)?,
            Expr::Field(f) => self.field_access(f)?,
            Expr::Index(ix) => {
                // `self.k[i]`, `self.g[2]`: parameter-only, read as written (a loop variable
                // in the index by its value).
                if let Some(v) = self.opaque(e) {
                    return Ok(v);
                }
                let base = self.expr(&ix.expr)?;
                let index = self.expr(&ix.index)?;
                self.index(base, index, ix)?
            }
            Expr::Array(a) => {
                let mut items = Vec::with_capacity(a.elems.len());
                for e in &a.elems {
                    items.push(self.expr(e)?);
                }
                Val::A(items)
            }
            Expr::Repeat(r) => {
                let v = self.expr(&r.expr)?;
                match self.expr(&r.len)? {
                    Val::I(k) if (0..=MAX_UNROLL).contains(&k) => Val::A(vec![v; k as usize]),
                    Val::Poison => Val::Poison,
                    _ => self.unsupported(r.len.span(), "an array length that is not an integer known when the macro expands (a literal or a `const` of this impl block, `Self::N`)"),
                }
            }
            Expr::Range(r) => self.range(r)?,
            Expr::ForLoop(f) => self.for_loop(f)?,
            Expr::Closure(c) => Val::F(std::rc::Rc::new(Callable {
                f: std::rc::Rc::new(crate::front::callables::closure(c)),
                env: self.scopes.clone(),
            })),
            Expr::Binary(b) => self.binary(b)?,
            Expr::Assign(a) => {
                let v = self.expr(&a.right)?;
                self.store(&a.left, v);
                Val::Tuple(Vec::new())
            }
            Expr::MethodCall(m) => self.method(m)?,
            Expr::Call(c) => self.call(c)?,
            Expr::If(i) => self.if_expr(i)?,
            Expr::Cast(c) => match self.const_int(&c.expr) {
                // `i as f64` of a loop variable: its value.
                Some(k) if is_float_type(&c.ty) => Val::S(self.dag.constant(k as f64)),
                Some(k) => Val::I(k),
                None => match self.opaque(e) {
                    Some(v) => v,
                    None => self.unsupported(e.span(), expr_kind(e)),
                },
            },
            Expr::Match(_) => match self.opaque(e) {
                Some(v) => v,
                None => self.unsupported(e.span(), expr_kind(e)),
            },
            other => {
                let kind = expr_kind(other);
                self.unsupported(other.span(), kind)
            }
        })
    }

    /// `if cond { .. } else { .. }` on a constant condition: both branches are lowered, and every
    /// value that differs between them (the result and any binding assigned in a branch) becomes
    /// a `Select` on the condition.
    pub(super) fn if_expr(&mut self, i: &syn::ExprIf) -> R<Val> {
        // A condition known when the macro expands (`if i > 0` in an unrolled loop): only the
        // branch taken is lowered.
        if let Some(b) = self.const_bool(&i.cond) {
            return match (b, &i.else_branch) {
                (true, _) => self.block(&i.then_branch),
                (false, Some((_, e))) => self.expr(e),
                (false, None) => Ok(Val::Tuple(Vec::new())),
            };
        }
        let cond = self.condition(&i.cond);
        let before = self.scopes.clone();
        let a = self.block(&i.then_branch)?;
        let after_a = self.scopes.replace(before.clone());
        let b = match &i.else_branch {
            Some((_, e)) => self.expr(e)?,
            None => Val::Tuple(Vec::new()),
        };
        let after_b = self.scopes.replace(before);
        let Some(c) = cond else {
            return Ok(Val::Poison);
        };
        let span = i.if_token.span;
        for (k, ((_, va), (_, vb))) in after_a.into_iter().zip(after_b).enumerate() {
            let v = self.merge(c, va, vb, span);
            self.scopes.set(k, v);
        }
        Ok(self.merge(c, a, b, span))
    }

    /// `base[index]`: an element of an array, a component of a vector, an element of an array
    /// field; the index must be known when the macro expands.
    pub(super) fn index(&mut self, base: Val, index: Val, ix: &syn::ExprIndex) -> R<Val> {
        Ok(match (base, index) {
            (Val::Poison, _) | (_, Val::Poison) => Val::Poison,
            (Val::A(items), Val::I(k)) => {
                match usize::try_from(k).ok().and_then(|k| items.get(k)) {
                    Some(v) => v.clone(),
                    None => self.err(syn::Error::new(
                        ix.index.span(),
                        format!(
                            "index {k} is out of bounds: the array has {} elements",
                            items.len()
                        ),
                    )),
                }
            }
            (Val::Seq(b), Val::I(k)) => {
                let k = proc_macro2::Literal::i64_unsuffixed(k);
                let e: Expr = syn::parse_quote_spanned!(ix.index.span()=> #b[#k]);
                match self.opaque(&e) {
                    Some(v) => v,
                    None => self.unsupported(ix.span(), "this indexing"),
                }
            }
            (base @ (Val::S(_) | Val::V(_)), Val::I(k @ 0..=2)) => {
                match self.vector(base, &*ix.expr, "an indexed value")? {
                    Some(c) => Val::S(c[k as usize]),
                    None => Val::Poison,
                }
            }
            (_, Val::I(_)) | (Val::S(_) | Val::V(_), _) => self.unsupported(
                ix.span(),
                "indexing other than an array by a known integer or a Vector3 by 0, 1 or 2",
            ),
            (_, _) => self.unsupported(
                ix.index.span(),
                "an index that is not known when the macro expands (it may be a literal, a loop \
                 variable, or an integer `const` of this impl block, `Self::N`)",
            ),
        })
    }

    /// `a..b`, `a..=b` with bounds known when the macro expands: the array of its integers.
    pub(super) fn range(&mut self, r: &syn::ExprRange) -> R<Val> {
        let bound = |this: &mut Self, e: &Option<Box<Expr>>| -> R<Option<Val>> {
            match e {
                Some(e) => this.expr(e).map(Some),
                None => Ok(None),
            }
        };
        let lo = bound(self, &r.start)?;
        let hi = bound(self, &r.end)?;
        let inclusive = matches!(r.limits, syn::RangeLimits::Closed(_));
        Ok(match (lo, hi) {
            (Some(Val::Poison), _) | (_, Some(Val::Poison)) => Val::Poison,
            (Some(Val::I(a)), Some(Val::I(b))) => {
                let b = if inclusive { b.saturating_add(1) } else { b };
                if b.saturating_sub(a) > MAX_UNROLL {
                    return Ok(self.err(syn::Error::new(
                        r.span(),
                        format!("this range has {} elements: the symbolic mode unrolls at most {MAX_UNROLL}", b - a),
                    )));
                }
                Val::A((a..b).map(Val::I).collect())
            }
            _ => self.err(syn::Error::new(
                r.span(),
                "the symbolic mode unrolls loops, so a range's bounds must be known when the macro \
                 expands: integer literals, loop variables, `q.len()` of a coordinate array, or \
                 integer `const`s of this impl block (`const N: usize = 6;` written `Self::N`; a \
                 `const` declared elsewhere is not visible to the macro); or use \
                 `#[lagrangian(mode = \"jets\")]` on this impl block",
            )),
        })
    }

    /// `e`, or an array field of unknown length when `e` is `self.f` (`&self.f`,
    /// `self.f.iter()`): where an iterable is expected.
    pub(super) fn seq_or_expr(&mut self, e: &Expr) -> R<Val> {
        match self_field_seq(e) {
            Some(b) => Ok(Val::Seq(Box::new(b))),
            None => self.expr(e),
        }
    }

    pub(super) fn path(&mut self, p: &syn::ExprPath) -> Val {
        if p.qself.is_none() {
            if let Some(id) = p.path.get_ident() {
                if let Some(v) = self.lookup(&unraw(id)) {
                    return v;
                }
                // A name from the user's scope: an opaque constant, loaded once as written.
                return self.param(&Member::Named(id.clone()), id.span(), true);
            }
            let segs = segment_names(&p.path);
            let n = segs.len();
            if let [s, name] = segs.as_slice() {
                if s == "Self" {
                    if let Some(k) = self.int_consts.get(name) {
                        return Val::I(*k);
                    }
                }
            }
            if n >= 3 && segs[n - 3] == "f64" && segs[n - 2] == "consts" {
                if let Some(c) = f64_const(&segs[n - 1]) {
                    return Val::S(self.dag.constant(c));
                }
            }
        }
        let segs = segment_names(&p.path);
        if let [.., ty, name] = segs.as_slice() {
            if ty == "f64" {
                if let Some(c) = f64_assoc_const(name) {
                    return Val::S(self.dag.constant(c));
                }
            }
        }
        // `Self::K`, `crate::G`: a constant of the user's scope, read as written.
        let e = Expr::Path(p.clone());
        match self.opaque(&e) {
            Some(v) => v,
            None => self.unsupported(p.span(), "this path"),
        }
    }

    pub(super) fn field_access(&mut self, f: &syn::ExprField) -> R<Val> {
        if let Expr::Path(p) = paren_less(&f.base) {
            if p.path.is_ident("self") {
                return Ok(self.field(&f.member, f.span()));
            }
        }
        let base = self.expr(&f.base)?;
        Ok(match &f.member {
            Member::Named(name) => {
                let k = match name.to_string().as_str() {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    other => {
                        return Ok(self.unsupported(name.span(), &format!("the field `.{other}`")))
                    }
                };
                match self.vector(base, &*f.base, "the value of `.x`/`.y`/`.z`")? {
                    Some(c) => Val::S(c[k]),
                    None => Val::Poison,
                }
            }
            Member::Unnamed(i) => match base {
                Val::Tuple(items) if (i.index as usize) < items.len() => {
                    items[i.index as usize].clone()
                }
                Val::Poison => Val::Poison,
                _ => self.err(syn::Error::new(i.span, "no such tuple field")),
            },
        })
    }

    pub(super) fn neg(&mut self, v: Val) -> Val {
        match v {
            Val::S(a) => Val::S(self.dag.neg(a)),
            Val::V(c) => Val::V(c.map(|a| self.dag.neg(a))),
            Val::I(k) => Val::I(-k),
            Val::A(items) => Val::A(items.into_iter().map(|v| self.neg(v)).collect()),
            _ => Val::Poison,
        }
    }

    /// A chain of binary operators `a + b + c …` (left-nested): walked down its left operands
    /// with a loop, so a 2000-term sum does not overflow the compiler's stack.
    pub(super) fn binary(&mut self, b: &syn::ExprBinary) -> R<Val> {
        let mut spine = vec![b];
        while let Expr::Binary(inner) = &*spine[spine.len() - 1].left {
            spine.push(inner);
        }
        let mut acc: Option<Val> = None;
        while let Some(b) = spine.pop() {
            acc = Some(self.binary_one(b, acc)?);
        }
        Ok(acc.unwrap_or(Val::Poison))
    }

    /// One operator of a chain, with its left operand's value when the chain already has it.
    pub(super) fn binary_one(&mut self, b: &syn::ExprBinary, left: Option<Val>) -> R<Val> {
        let (op, assign) = match b.op {
            BinOp::Add(_) => ('+', false),
            BinOp::Sub(_) => ('-', false),
            BinOp::Mul(_) => ('*', false),
            BinOp::Div(_) => ('/', false),
            BinOp::Rem(_) => ('%', false),
            BinOp::RemAssign(_) => ('%', true),
            BinOp::AddAssign(_) => ('+', true),
            BinOp::SubAssign(_) => ('-', true),
            BinOp::MulAssign(_) => ('*', true),
            BinOp::DivAssign(_) => ('/', true),
            _ => return Ok(self.unsupported(b.span(), "this operator")),
        };
        let l = match left {
            Some(l) => l,
            None => self.expr(&b.left)?,
        };
        let r = self.expr(&b.right)?;
        let v = self.arith(op, l, r, &b.left, &b.right)?;
        if assign {
            self.store(&b.left, v);
            Ok(Val::Tuple(Vec::new()))
        } else {
            Ok(v)
        }
    }

    pub(super) fn arith(&mut self, op: char, l: Val, r: Val, le: &Expr, re: &Expr) -> R<Val> {
        // Integers known when the macro runs stay integers among themselves (`i + 1`), and
        // become constants where they meet a scalar.
        let (l, r) = match (l, r) {
            (Val::I(a), Val::I(b)) => {
                let v = match op {
                    '+' => a.checked_add(b),
                    '-' => a.checked_sub(b),
                    '*' => a.checked_mul(b),
                    '/' => a.checked_div(b),
                    _ => a.checked_rem(b),
                };
                return Ok(match v {
                    Some(v) => Val::I(v),
                    None => self.err(syn::Error::new(
                        le.span().join(re.span()).unwrap_or_else(|| re.span()),
                        "this integer arithmetic overflows or divides by zero",
                    )),
                });
            }
            (Val::I(a), r) => (Val::S(self.dag.constant(a as f64)), r),
            (l, Val::I(b)) => (l, Val::S(self.dag.constant(b as f64))),
            lr => lr,
        };
        if op == '%' {
            return Ok(match (l, r) {
                (Val::Poison, _) | (_, Val::Poison) => Val::Poison,
                _ => self.unsupported(
                    re.span(),
                    "`%` on values that are not integers known when the macro expands",
                ),
            });
        }
        let d = &mut self.dag;
        Ok(match (op, l, r) {
            (_, Val::Poison, _) | (_, _, Val::Poison) => Val::Poison,
            ('+', Val::S(a), Val::S(b)) => Val::S(d.add(a, b)),
            ('-', Val::S(a), Val::S(b)) => Val::S(d.sub(a, b)),
            ('*', Val::S(a), Val::S(b)) => Val::S(d.mul(a, b)),
            ('/', Val::S(a), Val::S(b)) => Val::S(d.div(a, b)),
            ('+', Val::V(a), Val::V(b)) => Val::V([0, 1, 2].map(|k| d.add(a[k], b[k]))),
            ('-', Val::V(a), Val::V(b)) => Val::V([0, 1, 2].map(|k| d.sub(a[k], b[k]))),
            ('*', Val::S(s), Val::V(v)) | ('*', Val::V(v), Val::S(s)) => {
                Val::V(v.map(|x| d.mul(s, x)))
            }
            ('/', Val::V(v), Val::S(s)) => Val::V(v.map(|x| d.div(x, s))),
            ('*', Val::R(a), Val::R(b)) => Val::R(geometry::compose(d, &a, &b)),
            ('*', Val::R(a), Val::V(v)) => Val::V(geometry::apply(d, &a, &v)),
            ('+' | '-', Val::S(s), Val::V(_)) => {
                let _ = self.vector(Val::S(s), le, "the left operand")?;
                Val::Poison
            }
            ('+' | '-', Val::V(_), Val::S(s)) => {
                let _ = self.vector(Val::S(s), re, "the right operand")?;
                Val::Poison
            }
            ('*', Val::V(_), Val::V(_)) => self.err(syn::Error::new(
                re.span(),
                "two Vector3 values cannot be multiplied with `*`; use `.dot(&v)` or `.cross(&v)`",
            )),
            ('/', _, Val::V(_)) => {
                self.err(syn::Error::new(re.span(), "cannot divide by a Vector3"))
            }
            _ => self.err(syn::Error::new(
                le.span().join(re.span()).unwrap_or_else(|| le.span()),
                "these operands cannot be combined (a tuple, an array, a function or a unit value \
                 is involved)",
            )),
        })
    }
}
