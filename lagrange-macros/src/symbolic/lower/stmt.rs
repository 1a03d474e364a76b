//! Statements and bindings: blocks, `let` (tuple and array patterns), assignments and compound
//! assignments to locals, elements and fields of locals, in the scopes of [`Lower`].

use super::*;

impl Lower {
    /// The body of `fn forces`: statements, then an array literal of `n` values (`None`, with an
    /// error, for any other tail).
    pub(super) fn array_block(&mut self, b: &syn::Block, n: usize) -> R<Option<Vec<Val>>> {
        let depth = self.scopes.mark();
        let (init, tail) = match b.stmts.split_last() {
            Some((Stmt::Expr(e, None), init)) => (init, Some(e)),
            _ => (&b.stmts[..], None),
        };
        self.stmts(init)?;
        let result = match tail.map(paren_less) {
            Some(Expr::Array(a)) if a.elems.len() == n => {
                let mut vals = Vec::with_capacity(n);
                for e in &a.elems {
                    vals.push(self.expr(e)?);
                }
                Some(vals)
            }
            Some(Expr::Array(a)) => {
                self.errors.push(syn::Error::new(
                    a.span(),
                    format!(
                        "`fn forces` returns one generalized force per coordinate slot: {n} here, and this array has {}",
                        a.elems.len()
                    ),
                ));
                None
            }
            _ => {
                self.errors.push(unsupported(
                    body_tail_span(b),
                    "a body of `fn forces` that does not end in an array literal (`[f_x, f_y]`, \
                     one force per coordinate slot)",
                ));
                None
            }
        };
        self.scopes.truncate(depth);
        Ok(result)
    }

    pub(super) fn block(&mut self, b: &syn::Block) -> R<Val> {
        let depth = self.scopes.mark();
        let result = self.stmts(&b.stmts)?;
        self.scopes.truncate(depth);
        Ok(result)
    }

    /// Lowers statements in the current scope; the value of the last one if it is a tail
    /// expression, `()` otherwise.
    pub(super) fn stmts(&mut self, stmts: &[Stmt]) -> R<Val> {
        let mut result = Val::Tuple(Vec::new());
        let n = stmts.len();
        // Nested `fn` items are visible in the whole block.
        for stmt in stmts {
            if let Stmt::Item(syn::Item::Fn(f)) = stmt {
                let callable = Callable::item(std::rc::Rc::new(crate::front::callables::nested(f)));
                self.scopes
                    .push(unraw(&f.sig.ident), Val::F(std::rc::Rc::new(callable)));
            }
        }
        for (k, stmt) in stmts.iter().enumerate() {
            let last = k + 1 == n;
            match stmt {
                Stmt::Local(local) => {
                    let Some(init) = &local.init else {
                        self.unsupported(local.span(), "a `let` without a value");
                        continue;
                    };
                    if let Some((else_tok, _)) = &init.diverge {
                        self.unsupported(else_tok.span, "`let ... else`");
                        continue;
                    }
                    let v = self.expr(&init.expr)?;
                    self.bind(&local.pat, v);
                }
                Stmt::Expr(e, semi) => {
                    let v = self.expr(e)?;
                    if last && semi.is_none() {
                        result = v;
                    }
                }
                Stmt::Item(syn::Item::Fn(_)) => {}
                // `const K: f64 = 2.0;`: its value, if it does not depend on the state.
                Stmt::Item(syn::Item::Const(c)) => {
                    let v = self.expr(&c.expr)?;
                    self.scopes.push(unraw(&c.ident), v);
                }
                Stmt::Item(item) => {
                    self.unsupported(
                        item.span(),
                        "an item other than `fn` or `const` inside the body",
                    );
                }
                Stmt::Macro(m) => {
                    self.unsupported(m.span(), "a macro call");
                }
            }
        }
        Ok(result)
    }

    /// Binds `pat` to `v` with the front end's binder (the patterns the symbolic mode takes:
    /// names, `_`, tuples, references, parentheses and typed patterns).
    pub(super) fn bind(&mut self, pat: &Pat, v: Val) {
        crate::front::scope::bind(&mut self.scopes, pat, v, &mut self.errors);
    }

    pub(super) fn store(&mut self, target: &Expr, v: Val) {
        // `a`, `a[i]`, `a[i][j]`: the root binding and the indices, outermost last.
        let mut indices = Vec::new();
        let mut root = paren_less(target);
        while let Expr::Index(ix) = root {
            indices.push(&*ix.index);
            root = paren_less(&ix.expr);
        }
        indices.reverse();
        if let Expr::Path(p) = root {
            if let Some(id) = p.path.get_ident() {
                let name = unraw(id);
                if self.depth > 0
                    && self
                        .scopes
                        .position(&name)
                        .is_some_and(|k| k < self.frame_base)
                {
                    self.unsupported(
                        target.span(),
                        "a closure that assigns to a binding it captures",
                    );
                    return;
                }
                if indices.is_empty() {
                    if self.assign(&name, v) {
                        return;
                    }
                } else if let Some(mut whole) = self.lookup(&name) {
                    let mut ks = Vec::new();
                    for e in &indices {
                        match self.const_int(e) {
                            Some(k) => ks.push(k),
                            None => {
                                self.unsupported(
                                    e.span(),
                                    "an index that is not known when the macro expands (it may \
                                     be a literal, a loop variable, or an integer `const` of this \
                                     impl block, `Self::N`)",
                                );
                                return;
                            }
                        }
                    }
                    match set_element(&mut whole, &ks, v) {
                        Ok(()) => {
                            self.assign(&name, whole);
                        }
                        Err(msg) => {
                            self.err(syn::Error::new(target.span(), msg));
                        }
                    }
                    return;
                }
            }
        }
        self.unsupported(
            target.span(),
            "assigning to anything but a local binding or an element of a local array",
        );
    }
}
