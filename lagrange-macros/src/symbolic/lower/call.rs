//! Calls: the function table (methods of `Scalar` and `Vector3`), helpers of the impl block and
//! closures, inlined.

use super::*;

impl Lower {
    /// Inlines a call of `f` (a closure, a nested `fn`, a helper method) with `args`.
    pub(super) fn call_fn(&mut self, f: &Callable, args: Vec<Val>, at: &dyn At) -> R<Val> {
        let (what, params) = (&f.f.what, &f.f.params);
        if !self.spend(at, &format!("this call of {what}")) {
            return Ok(Val::Poison);
        }
        if self.depth >= MAX_CALL_DEPTH {
            return Ok(self.err(syn::Error::new(
                at.at(),
                format!(
                    "{what} is called {MAX_CALL_DEPTH} calls deep: the symbolic mode inlines every \
                     call, so it cannot follow recursion; use `#[lagrangian(mode = \"jets\")]` on \
                     this impl block"
                ),
            )));
        }
        if args.len() != params.len() {
            return Ok(self.err(syn::Error::new(
                at.at(),
                format!(
                    "{what} takes {} argument(s), and this call gives {}",
                    params.len(),
                    args.len()
                ),
            )));
        }
        // A nested `fn` sees the other `fn` items of the scope it is called from.
        let env: Scopes<Val> = if f.f.item {
            self.scopes
                .iter()
                .filter(|(_, v)| matches!(v, Val::F(c) if c.f.item))
                .cloned()
                .collect()
        } else {
            f.env.clone()
        };
        let base = env.mark();
        let saved = self.scopes.replace(env);
        let saved_base = std::mem::replace(&mut self.frame_base, base);
        self.depth += 1;
        for (p, a) in f.f.params.iter().zip(args) {
            self.bind(p, a);
        }
        let result = match &f.f.body {
            FnBody::Expr(e) => self.expr(e),
            FnBody::Block(b) => self.block(b),
        };
        self.depth -= 1;
        self.scopes = saved;
        self.frame_base = saved_base;
        result
    }

    pub(super) fn call(&mut self, c: &syn::ExprCall) -> R<Val> {
        let Expr::Path(p) = paren_less(&c.func) else {
            return Ok(self.unsupported(c.func.span(), "calling this"));
        };
        // A closure or a nested `fn` of the body, or `Self::kinetic(self, v)`: inlined.
        let callee = match p.path.get_ident() {
            Some(id) => match self.lookup(&unraw(id)) {
                Some(Val::F(f)) => Some((f, 0)),
                _ => None,
            },
            None => match segment_names(&p.path).as_slice() {
                [s, name] if s == "Self" && p.qself.is_none() => {
                    self.helpers.get(name).cloned().map(|f| (f, 1))
                }
                _ => None,
            },
        };
        if let Some((f, skip)) = callee {
            let mut args = Vec::with_capacity(c.args.len());
            for a in c.args.iter().skip(skip) {
                args.push(self.expr(a)?);
            }
            return self.call_fn(&f, args, c);
        }
        let segs = segment_names(&p.path);
        let n = segs.len();
        // `Scalar::constant(c)`, `Scalar::from(c)`, `<Scalar as From<f64>>::from(c)`: the
        // identity on a constant.
        let scalar_self = match &p.qself {
            Some(q) => {
                matches!(&*q.ty, syn::Type::Path(t) if t.qself.is_none() && t.path.is_ident("Scalar"))
            }
            None => false,
        };
        let is_constant_ctor = c.args.len() == 1
            && match (&p.qself, segs.as_slice()) {
                (None, [s, m]) => s == "Scalar" && (m == "constant" || m == "from"),
                (Some(_), [t, m]) => scalar_self && t == "From" && m == "from",
                _ => false,
            };
        if is_constant_ctor {
            let arg = &c.args[0];
            let v = self.expr(arg)?;
            let Some(id) = self.scalar(v, arg, "the argument of this conversion") else {
                return Ok(Val::Poison);
            };
            if !self.dag.is_state_free(id) {
                return Ok(self.err(syn::Error::new(
                    arg.span(),
                    "this converts an f64 constant into a Scalar, but the argument depends on \
                     the coordinates, velocities or time; it is already a Scalar, so write it \
                     without the conversion",
                )));
            }
            return Ok(Val::S(id));
        }
        if let Some(v) = self.geometry_call(&segs[n.saturating_sub(2)..], c)? {
            return Ok(v);
        }
        if let Some(v) = self.geometry_call(&segs[n.saturating_sub(1)..], c)? {
            return Ok(v);
        }
        if n >= 2 && segs[n - 2] == "Vector3" {
            match segs[n - 1].as_str() {
                "new" if c.args.len() == 3 => {
                    let mut comps = [Dag::ZERO; 3];
                    let mut poison = false;
                    for (k, a) in c.args.iter().enumerate() {
                        let v = self.expr(a)?;
                        match self.scalar(v, a, "a component of `Vector3::new`") {
                            Some(id) => comps[k] = id,
                            None => poison = true,
                        }
                    }
                    return Ok(if poison { Val::Poison } else { Val::V(comps) });
                }
                "zeros" if c.args.is_empty() => return Ok(Val::V([Dag::ZERO; 3])),
                _ => {}
            }
        }
        // `f64::sin(x)`, `Scalar::powi(x, 2)`: method calls in function form.
        if n == 2 && matches!(segs[0].as_str(), "f64" | "Scalar") && !c.args.is_empty() {
            let mut args = c.args.iter();
            if let Some(recv_e) = args.next() {
                let rest: Vec<&Expr> = args.collect();
                let method = &p.path.segments[1].ident;
                let recv = self.expr(recv_e)?;
                return self.apply_method(recv, recv_e, method, &rest, c);
            }
        }
        // A function of parameters only (the user's own `fn`, `f64::max(self.a, self.b)`):
        // evaluated once per call, as written.
        if let Some(v) = self.opaque(&Expr::Call(c.clone())) {
            return Ok(v);
        }
        let name = segs.join("::");
        Ok(self.unsupported(c.func.span(), &format!("a call to the function `{name}`")))
    }

    /// A chain of method calls `x.sin().cos()…`: walked along its receivers with a loop, so a
    /// 2000-deep chain does not overflow the compiler's stack; innermost call first.
    pub(super) fn method(&mut self, m: &syn::ExprMethodCall) -> R<Val> {
        // `self.kinetic(v)`: a helper method of the impl block, inlined.
        if let Some(h) = self.helper_called(m) {
            let mut args = Vec::with_capacity(m.args.len());
            for a in &m.args {
                args.push(self.expr(a)?);
            }
            return self.call_fn(&h, args, m);
        }
        // A method the symbolic mode does not know, on parameters only (`self.n.count_ones()`,
        // `self.table.len()`): evaluated once per call, as written.
        let name = m.method.to_string();
        let adaptor = Iter::of(&name).is_some_and(|w| w.is_adaptor() && !w.jets_only());
        if Fun::from_method(&name).is_none() && !KNOWN_METHODS.contains(&name.as_str()) && !adaptor
        {
            if let Some(v) = self.opaque(&Expr::MethodCall(m.clone())) {
                return Ok(v);
            }
        }
        let mut spine = vec![m];
        while let Expr::MethodCall(inner) = &*spine[spine.len() - 1].receiver {
            if self.helper_called(inner).is_some() {
                break;
            }
            spine.push(inner);
        }
        let Some(innermost) = spine.last() else {
            return Ok(Val::Poison);
        };
        // `self.m.iter()`: an array field, whose length the macro does not know.
        let seq = matches!(innermost.method.to_string().as_str(), "iter" | "into_iter")
            .then(|| self_field_seq(&innermost.receiver))
            .flatten();
        let mut recv = match seq {
            Some(b) => Val::Seq(Box::new(b)),
            None => self.expr(&innermost.receiver)?,
        };
        while let Some(m) = spine.pop() {
            let args: Vec<&Expr> = m.args.iter().collect();
            recv = self.apply_method(recv, &m.receiver, &m.method, &args, m)?;
        }
        Ok(recv)
    }

    /// The helper method `m` calls (`self.kinetic(v)`), if it calls one.
    pub(super) fn helper_called(&self, m: &syn::ExprMethodCall) -> Option<std::rc::Rc<Callable>> {
        if !matches!(paren_less(&m.receiver), Expr::Path(p) if p.path.is_ident("self")) {
            return None;
        }
        self.helpers.get(&unraw(&m.method)).cloned()
    }
}
