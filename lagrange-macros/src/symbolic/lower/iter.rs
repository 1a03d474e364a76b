//! `for` loops and the iterator vocabulary (`iter`, `enumerate`, `zip`, `rev`, `skip`, `take`,
//! `step_by`, `map`, `sum`, `product`, `fold`, …), unrolled where the macro knows the lengths.

use super::*;

impl Lower {
    /// `for pat in iterable { body }`, unrolled: the body lowered once per element.
    pub(super) fn for_loop(&mut self, f: &syn::ExprForLoop) -> R<Val> {
        if let Some(label) = &f.label {
            return Ok(self.unsupported(label.span(), "a loop label"));
        }
        if self.over_budget {
            return Ok(Val::Poison);
        }
        let items = match self.seq_or_expr(&f.expr)? {
            Val::A(items) => items.into_iter().map(|v| (v, Guard::new())).collect(),
            Val::Z(z) => z.items,
            Val::Poison => return Ok(Val::Poison),
            Val::Seq(b) => {
                return Ok(self.err(syn::Error::new(
                    f.expr.span(),
                    format!(
                        "the length of `{}` is not known when the macro expands: loop over a range \
                         (`for i in 0..K`) and index it, or zip it with a coordinate array \
                         (`q.iter().zip({}.iter())`)",
                        cond_text(&quote::ToTokens::to_token_stream(&b)),
                        quote::ToTokens::to_token_stream(&b),
                    ),
                )))
            }
            other => {
                let kind = other.kind();
                return Ok(self.err(syn::Error::new(
                    f.expr.span(),
                    format!("a `for` loop over {kind}: the symbolic mode unrolls loops over arrays, ranges with known bounds and their iterators (`.iter()`, `.enumerate()`, `.zip(..)`, `.rev()`)"),
                )));
            }
        };
        let head = LoopHead(f);
        for (item, guard) in items {
            if !self.spend(&head, "this loop") {
                return Ok(Val::Poison);
            }
            let depth = self.scopes.mark();
            let span = f.for_token.span;
            let before = self
                .guard_cond(&guard, span)
                .map(|c| (c, self.scopes.clone()));
            self.bind(&f.pat, item);
            self.block(&f.body)?;
            self.scopes.truncate(depth);
            // An element of a zip that may not exist: what the body assigned, under its guard.
            if let Some((c, before)) = before {
                let after = self.scopes.replace(before.clone());
                for (k, ((_, va), (_, vb))) in after.into_iter().zip(before).enumerate() {
                    let v = self.merge(c, va, vb, span);
                    self.scopes.set(k, v);
                }
            }
        }
        Ok(Val::Tuple(Vec::new()))
    }

    /// An iterator method (`iter`, `enumerate`, `zip`, `map`, `sum`, `fold`, ...) on an array
    /// (or an array field of unknown length): `None` when `name` is not one or `recv` is not
    /// an array.
    pub(super) fn iterator_method(
        &mut self,
        recv: &Val,
        recv_e: &Expr,
        name: &str,
        args: &[&Expr],
        whole: &dyn At,
    ) -> R<Option<Val>> {
        let nargs = args.len();
        let Some(word) = Iter::of(name) else {
            return Ok(None);
        };
        let items = match recv {
            Val::A(items) => items.clone(),
            Val::Seq(b) => {
                return Ok(match (word, nargs) {
                    (Iter::Elements, 0) => Some(Val::Seq(b.clone())),
                    (Iter::Zip, 1) => {
                        let other = self.seq_or_expr(args[0])?;
                        match other {
                            Val::A(ys) => {
                                let xs = self.guarded_elements(b, ys.len(), whole);
                                let ys = ys.into_iter().map(|y| (y, Guard::new())).collect();
                                Some(zip_guarded(xs, ys))
                            }
                            Val::Z(z) if z.forward => {
                                let xs = self.guarded_elements(b, z.items.len(), whole);
                                Some(zip_guarded(xs, z.items))
                            }
                            Val::Z(_) => Some(self.after_rev("zip", whole)),
                            Val::Poison => Some(Val::Poison),
                            _ => Some(self.unknown_length(b, whole)),
                        }
                    }
                    (
                        Iter::Enumerate
                        | Iter::Map
                        | Iter::Sum
                        | Iter::Product
                        | Iter::Fold
                        | Iter::Rev
                        | Iter::Len
                        | Iter::Skip
                        | Iter::Take,
                        _,
                    ) => Some(self.unknown_length(b, whole)),
                    _ => None,
                });
            }
            Val::Z(z) => return self.zipped_method((**z).clone(), recv_e, name, args, whole),
            _ => return Ok(None),
        };
        Ok(Some(match (word, nargs) {
            (Iter::Elements, 0) => Val::A(items),
            (Iter::Len | Iter::Count, 0) => Val::I(items.len() as i64),
            (Iter::Enumerate, 0) => Val::A(
                items
                    .into_iter()
                    .enumerate()
                    .map(|(k, x)| Val::Tuple(vec![Val::I(k as i64), x]))
                    .collect(),
            ),
            (Iter::Rev, 0) => Val::A(items.into_iter().rev().collect()),
            (Iter::Skip | Iter::Take | Iter::StepBy, 1) => match self.int_arg(name, args[0])? {
                Ok(k) => Val::A(match word {
                    Iter::Skip => items.into_iter().skip(k).collect(),
                    Iter::Take => items.into_iter().take(k).collect(),
                    _ => items.into_iter().step_by(k).collect(),
                }),
                Err(v) => v,
            },
            (Iter::Zip, 1) => match self.seq_or_expr(args[0])? {
                Val::A(ys) => Val::A(
                    items
                        .into_iter()
                        .zip(ys)
                        .map(|(x, y)| Val::Tuple(vec![x, y]))
                        .collect(),
                ),
                Val::Seq(b) => {
                    let ys = self.guarded_elements(&b, items.len(), whole);
                    let xs = items.into_iter().map(|x| (x, Guard::new())).collect();
                    zip_guarded(xs, ys)
                }
                Val::Z(z) if z.forward => {
                    let xs = items.into_iter().map(|x| (x, Guard::new())).collect();
                    zip_guarded(xs, z.items)
                }
                Val::Z(_) => self.after_rev("zip", whole),
                Val::Poison => Val::Poison,
                other => {
                    let kind = other.kind();
                    self.err(syn::Error::new(
                        args[0].span(),
                        format!("`.zip()` over {kind}: it zips arrays and their iterators"),
                    ))
                }
            },
            (Iter::Map, 1) => {
                let f = self.expr(args[0])?;
                let Val::F(f) = f else {
                    return Ok(Some(self.unsupported(
                        args[0].span(),
                        "a `.map()` argument that is not a closure or a function of the body",
                    )));
                };
                let mut out = Vec::with_capacity(items.len());
                for x in items {
                    out.push(self.call_fn(&f, vec![x], args[0])?);
                }
                Val::A(out)
            }
            (Iter::Fold, 2) => {
                let mut acc = self.expr(args[0])?;
                let Val::F(f) = self.expr(args[1])? else {
                    return Ok(Some(self.unsupported(
                        args[1].span(),
                        "a `.fold()` argument that is not a closure or a function of the body",
                    )));
                };
                for x in items {
                    acc = self.call_fn(&f, vec![acc, x], args[1])?;
                }
                acc
            }
            (Iter::Sum | Iter::Product, 0) => {
                let op = if word == Iter::Sum { '+' } else { '*' };
                let mut it = items.into_iter();
                match it.next() {
                    None => Val::S(if op == '+' { Dag::ZERO } else { Dag::ONE }),
                    Some(first) => {
                        let mut acc = first;
                        for x in it {
                            if !self.spend(whole, &format!("this `.{name}()`")) {
                                return Ok(Some(Val::Poison));
                            }
                            acc = self.arith(op, acc, x, recv_e, recv_e)?;
                        }
                        acc
                    }
                }
            }
            _ => return Ok(None),
        }))
    }

    /// The integer argument of `.skip(k)`, `.take(k)`, `.step_by(k)` (`Err`: the error's value).
    pub(super) fn int_arg(&mut self, name: &str, e: &Expr) -> R<Result<usize, Val>> {
        Ok(match self.expr(e)? {
            Val::I(k) => match usize::try_from(k) {
                Ok(0) if name == "step_by" => {
                    Err(self.err(syn::Error::new(
                        e.span(),
                        "`step_by(0)`: a step of 0 never advances (std's `step_by` panics on \
                         it); give `.step_by(k)` a step k ≥ 1",
                    )))
                }
                Ok(k) => Ok(k),
                Err(_) => Err(self.unsupported(
                    e.span(),
                    &format!("a `.{name}()` argument that is not an integer known when the macro expands"),
                )),
            },
            _ => Err(self.unsupported(
                e.span(),
                &format!("a `.{name}()` argument that is not an integer known when the macro expands"),
            )),
        })
    }

    /// The first `n` elements of the array field `b` that a zip may read, each a parameter
    /// guarded by `k < b.len()` and loaded without a bounds panic (`self.m.get(k)`; see
    /// [`Zipped`]), printed as `m[k]`.
    pub(super) fn guarded_elements(
        &mut self,
        b: &Expr,
        n: usize,
        whole: &dyn At,
    ) -> Vec<(Val, Guard)> {
        (0..n)
            .map(|k| {
                let lit = proc_macro2::Literal::usize_unsuffixed(k);
                // Paths, not methods: a user's trait in scope cannot change what they call.
                let e: Expr = syn::parse_quote_spanned!(whole.at()=>
                ::core::option::Option::<f64>::unwrap_or(
                    ::core::option::Option::<&f64>::copied(<[f64]>::get(&#b, #lit)),
                    0.0,
                ));
                let shown = cond_text(&quote::quote!(#b[#lit]));
                let v = self.opaque_shown(&e, Some(shown)).unwrap_or(Val::Poison);
                (v, vec![(b.clone(), k)])
            })
            .collect()
    }

    pub(super) fn after_rev(&mut self, name: &str, whole: &dyn At) -> Val {
        self.unsupported(
            whole.at(),
            &format!(
                "`.{name}()` after `.rev()` on a zip with an array field whose length the macro \
                 does not know (write `.{name}()` before `.rev()`)"
            ),
        )
    }

    /// An iterator method on a zip with an array field of unknown length (see [`Zipped`]).
    pub(super) fn zipped_method(
        &mut self,
        z: Zipped,
        recv_e: &Expr,
        name: &str,
        args: &[&Expr],
        whole: &dyn At,
    ) -> R<Option<Val>> {
        let Zipped { items, forward } = z;
        let span = whole.at();
        let z =
            |items: Vec<(Val, Guard)>, forward: bool| Val::Z(Box::new(Zipped { items, forward }));
        let Some(word) = Iter::of(name) else {
            return Ok(None);
        };
        Ok(Some(match (word, args.len()) {
            (Iter::Elements, 0) => z(items, forward),
            (Iter::Rev, 0) => z(items.into_iter().rev().collect(), !forward),
            (Iter::Enumerate | Iter::Skip | Iter::Take | Iter::StepBy | Iter::Zip, _)
                if !forward =>
            {
                self.after_rev(name, whole)
            }
            (Iter::Enumerate, 0) => z(
                items
                    .into_iter()
                    .enumerate()
                    .map(|(k, (x, g))| (Val::Tuple(vec![Val::I(k as i64), x]), g))
                    .collect(),
                true,
            ),
            (Iter::Skip | Iter::Take | Iter::StepBy, 1) => match self.int_arg(name, args[0])? {
                Ok(k) => z(
                    match word {
                        Iter::Skip => items.into_iter().skip(k).collect(),
                        Iter::Take => items.into_iter().take(k).collect(),
                        _ => items.into_iter().step_by(k).collect(),
                    },
                    true,
                ),
                Err(v) => v,
            },
            (Iter::Zip, 1) => match self.seq_or_expr(args[0])? {
                Val::A(ys) => {
                    zip_guarded(items, ys.into_iter().map(|y| (y, Guard::new())).collect())
                }
                Val::Seq(b) => {
                    let ys = self.guarded_elements(&b, items.len(), whole);
                    zip_guarded(items, ys)
                }
                Val::Z(o) if o.forward => zip_guarded(items, o.items),
                Val::Z(_) => self.after_rev(name, whole),
                Val::Poison => Val::Poison,
                other => {
                    let kind = other.kind();
                    self.err(syn::Error::new(
                        args[0].span(),
                        format!("`.zip()` over {kind}: it zips arrays and their iterators"),
                    ))
                }
            },
            (Iter::Map, 1) => {
                let Val::F(f) = self.expr(args[0])? else {
                    return Ok(Some(self.unsupported(
                        args[0].span(),
                        "a `.map()` argument that is not a closure or a function of the body",
                    )));
                };
                let mut out = Vec::with_capacity(items.len());
                for (x, g) in items {
                    out.push((self.call_fn(&f, vec![x], args[0])?, g));
                }
                z(out, forward)
            }
            (Iter::Fold, 2) => {
                let mut acc = self.expr(args[0])?;
                let Val::F(f) = self.expr(args[1])? else {
                    return Ok(Some(self.unsupported(
                        args[1].span(),
                        "a `.fold()` argument that is not a closure or a function of the body",
                    )));
                };
                for (x, g) in items {
                    let next = self.call_fn(&f, vec![acc.clone(), x], args[1])?;
                    acc = self.guarded(&g, next, acc, span);
                }
                acc
            }
            (Iter::Sum | Iter::Product, 0) => {
                let op = if word == Iter::Sum { '+' } else { '*' };
                let mut acc: Option<Val> = None;
                for (x, g) in items {
                    if !self.spend(whole, &format!("this `.{name}()`")) {
                        return Ok(Some(Val::Poison));
                    }
                    // An element that does not exist adds 0 (multiplies by 1).
                    let x = match x {
                        Val::V(_) if op == '+' => self.guarded(&g, x, Val::V([Dag::ZERO; 3]), span),
                        Val::S(_) | Val::I(_) | Val::V(_) => {
                            let unit = Val::S(if op == '+' { Dag::ZERO } else { Dag::ONE });
                            self.guarded(&g, x, unit, span)
                        }
                        other => other,
                    };
                    acc = Some(match acc {
                        None => x,
                        Some(a) => self.arith(op, a, x, recv_e, recv_e)?,
                    });
                }
                acc.unwrap_or(Val::S(if op == '+' { Dag::ZERO } else { Dag::ONE }))
            }
            (Iter::Len | Iter::Count, 0) => self.unsupported(
                span,
                &format!(
                    "`.{name}()` of a zip with an array field whose length the macro does not \
                     know (its length is known at run time only)"
                ),
            ),
            _ => return Ok(None),
        }))
    }

    pub(super) fn unknown_length(&mut self, b: &Expr, whole: &dyn At) -> Val {
        let text = cond_text(&quote::ToTokens::to_token_stream(b));
        self.err(syn::Error::new(
            whole.at(),
            format!(
                "the length of `{text}` is not known when the macro expands: zip it with a \
                 coordinate array (`q.iter().zip({}.iter())`), or loop over a range and index \
                 it (`for i in 0..K {{ .. self.{text}[i] .. }}`)",
                quote::ToTokens::to_token_stream(b)
            ),
        ))
    }

    /// `recv.method(args)`, the receiver `recv_e` already lowered to `recv`.
    pub(super) fn apply_method(
        &mut self,
        recv: Val,
        recv_e: &Expr,
        method: &syn::Ident,
        args: &[&Expr],
        whole: &dyn At,
    ) -> R<Val> {
        let name = method.to_string();
        let nargs = args.len();
        let bad_arity = |this: &mut Self, k: usize| -> Val {
            this.err(syn::Error::new(
                whole.at(),
                format!("`.{name}()` takes {k} argument(s) here"),
            ))
        };
        if let Some(v) = self.iterator_method(&recv, recv_e, &name, args, whole)? {
            return Ok(v);
        }
        if matches!(recv, Val::Poison) {
            return Ok(Val::Poison);
        }
        if let Val::R(r) = &recv {
            return Ok(match (name.as_str(), nargs) {
                ("transpose", 0) => Val::R(super::geometry::transpose(r)),
                ("clone", 0) => recv,
                ("transpose", _) => bad_arity(self, 0),
                _ => self.unsupported(
                    whole.at(),
                    &format!("`.{name}()` on a `Rotation` (the symbolic mode takes `transpose`, `r * r`, `r * v`)"),
                ),
            });
        }
        let fun = Fun::from_method(&name);
        if let Some(f) = fun {
            if nargs != 0 {
                return Ok(bad_arity(self, 0));
            }
            let Some(x) = self.scalar(recv, recv_e, &format!("the receiver of `.{name}()`")) else {
                return Ok(Val::Poison);
            };
            return Ok(Val::S(self.dag.un(f, x)));
        }
        match name.as_str() {
            "clone" | "to_owned" if nargs == 0 => return Ok(recv),
            "sin_cos" | "recip" | "powi" | "powf" | "atan2" | "hypot" | "mul_add" | "max"
            | "min" | "clamp" => {
                let want = match name.as_str() {
                    "sin_cos" | "recip" => 0,
                    "mul_add" | "clamp" => 2,
                    _ => 1,
                };
                if nargs != want {
                    return Ok(bad_arity(self, want));
                }
                let Some(x) = self.scalar(recv, recv_e, &format!("the receiver of `.{name}()`"))
                else {
                    return Ok(Val::Poison);
                };
                if name == "powi" {
                    return Ok(
                        match int_literal(args[0]).and_then(|k| i32::try_from(k).ok()) {
                            Some(k) => Val::S(self.dag.powi(x, k)),
                            None if matches!(paren_less(args[0]), Expr::Lit(l) if matches!(l.lit, Lit::Float(_))) => {
                                self.err(syn::Error::new(
                                    args[0].span(),
                                    "`powi` takes an integer exponent (`powi(2)`); for a real exponent use `powf`",
                                ))
                            }
                            // A constant exponent (`powi(N)`, `powi(Self::K)`): a parameter,
                            // x^N as x.powf(N as f64), exact for integers also at x < 0.
                            None => {
                                let e = args[0];
                                let cast: Expr = syn::parse_quote_spanned!(e.span()=> (#e) as f64);
                                let shown = cond_text(&quote::ToTokens::to_token_stream(e));
                                match self.opaque_shown(&cast, Some(shown)) {
                                    Some(Val::S(n)) => Val::S(self.dag.powf(x, n)),
                                    _ => self.unsupported(
                                        args[0].span(),
                                        "a `powi` exponent that depends on the state (it must be \
                                         a constant: a literal, a `const`, a parameter)",
                                    ),
                                }
                            }
                        },
                    );
                }
                let mut ys = Vec::new();
                for a in args {
                    let v = self.expr(a)?;
                    match self.scalar(v, *a, &format!("the argument of `.{name}()`")) {
                        Some(y) => ys.push(y),
                        None => return Ok(Val::Poison),
                    }
                }
                let d = &mut self.dag;
                return Ok(match name.as_str() {
                    "sin_cos" => {
                        Val::Tuple(vec![Val::S(d.un(Fun::Sin, x)), Val::S(d.un(Fun::Cos, x))])
                    }
                    "recip" => Val::S(d.div(Dag::ONE, x)),
                    "powf" => Val::S(d.powf(x, ys[0])),
                    "atan2" => Val::S(d.atan2(x, ys[0])),
                    "max" => Val::S(pick(d, x, ys[0], x, ys[0])),
                    "min" => Val::S(pick(d, x, ys[0], ys[0], x)),
                    "clamp" => {
                        let (lo, hi) = (ys[0], ys[1]);
                        let m = pick(d, x, lo, x, lo);
                        Val::S(pick(d, m, hi, hi, m))
                    }
                    "hypot" => {
                        let a = d.powi(x, 2);
                        let b = d.powi(ys[0], 2);
                        let s = d.add(a, b);
                        Val::S(d.un(Fun::Sqrt, s))
                    }
                    _ => {
                        let p = d.mul(x, ys[0]);
                        Val::S(d.add(p, ys[1]))
                    }
                });
            }
            "dot" | "cross" | "norm" | "norm_squared" | "magnitude" | "magnitude_squared"
            | "normalize" | "scale" | "component_mul" => {
                let want = match name.as_str() {
                    "dot" | "cross" | "scale" | "component_mul" => 1,
                    _ => 0,
                };
                if nargs != want {
                    return Ok(bad_arity(self, want));
                }
                let Some(a) = self.vector(recv, recv_e, &format!("the receiver of `.{name}()`"))?
                else {
                    return Ok(Val::Poison);
                };
                if name == "scale" {
                    let v = self.expr(args[0])?;
                    let Some(s) = self.scalar(v, args[0], "the argument of `.scale()`") else {
                        return Ok(Val::Poison);
                    };
                    return Ok(Val::V(a.map(|x| self.dag.mul(s, x))));
                }
                let b = if want == 1 {
                    let v = self.expr(args[0])?;
                    match self.vector(v, args[0], &format!("the argument of `.{name}()`"))? {
                        Some(b) => b,
                        None => return Ok(Val::Poison),
                    }
                } else {
                    a
                };
                let d = &mut self.dag;
                let dot = |d: &mut Dag| {
                    let x = d.mul(a[0], b[0]);
                    let y = d.mul(a[1], b[1]);
                    let z = d.mul(a[2], b[2]);
                    let s = d.add(x, y);
                    d.add(s, z)
                };
                let sq = |d: &mut Dag| {
                    let x = d.powi(a[0], 2);
                    let y = d.powi(a[1], 2);
                    let z = d.powi(a[2], 2);
                    let s = d.add(x, y);
                    d.add(s, z)
                };
                return Ok(match name.as_str() {
                    "dot" => Val::S(dot(d)),
                    "component_mul" => Val::V([0, 1, 2].map(|k| d.mul(a[k], b[k]))),
                    "cross" => {
                        let c = |d: &mut Dag, i: usize, j: usize| {
                            let p = d.mul(a[i], b[j]);
                            let q = d.mul(a[j], b[i]);
                            d.sub(p, q)
                        };
                        Val::V([c(d, 1, 2), c(d, 2, 0), c(d, 0, 1)])
                    }
                    "norm_squared" | "magnitude_squared" => Val::S(sq(d)),
                    "norm" | "magnitude" => {
                        let s = sq(d);
                        Val::S(d.un(Fun::Sqrt, s))
                    }
                    _ => {
                        let s = sq(d);
                        let n = d.un(Fun::Sqrt, s);
                        Val::V(a.map(|x| d.div(x, n)))
                    }
                });
            }
            _ => {}
        }
        Ok(self.unsupported(method.span(), &format!("the method `.{name}()`")))
    }
}
