//! Method chains and operators of the jets rewrite: the iterator vocabulary's kinds, helper
//! arguments, mixed constant–variable arithmetic, and the `^` and integer-literal mistakes.

use quote::quote_spanned;
use syn::spanned::Spanned;
use syn::{BinOp, Expr};

use super::*;
use crate::front::callables::ParamType;
use crate::front::vocab::{ClosureParams, Iter};
use crate::model::unraw;

impl Rewriter<'_> {
    /// A chain of method calls `x.sin().cos()…`, walked along its receivers with a loop (a
    /// 2000-deep chain must not overflow the compiler's stack), innermost call first.
    pub(super) fn method_chain(&mut self, e: &mut Expr) -> Kind {
        let mut spine = Vec::new();
        let mut cur = std::mem::replace(e, placeholder());
        while let Expr::MethodCall(mut m) = cur {
            cur = std::mem::replace(&mut *m.receiver, placeholder());
            spine.push(m);
        }
        let mut kr = self.expr(&mut cur);
        while let Some(mut m) = spine.pop() {
            *m.receiver = cur;
            // `q.iter()` of an array of the number type: by value, so the elements are
            // `Scalar`s (generic code has no arithmetic on `&Scalar`); `*v` on them is dropped.
            if kr.is_var() && m.method == "iter" && m.args.is_empty() {
                let recv = &m.receiver;
                let span = m.method.span();
                cur = Expr::Verbatim(
                    quote_spanned!(span=> ::core::iter::IntoIterator::into_iter(#recv)),
                );
                continue;
            }
            kr = self.method_one(&mut m, kr);
            cur = Expr::MethodCall(m);
        }
        *e = cur;
        kr
    }

    /// One call of a chain, its receiver's kind `kr` known.
    fn method_one(&mut self, m: &mut syn::ExprMethodCall, kr: Kind) -> Kind {
        norm_power_to_norm_squared(m);
        let name = m.method.to_string();
        let iter = Iter::of(&name);
        let mut kargs: Vec<Kind> = Vec::with_capacity(m.args.len());
        for (i, a) in m.args.iter_mut().enumerate() {
            // The kinds of the elements a closure argument of an iterator method receives.
            if matches!(a, Expr::Closure(_)) {
                self.closure_hint = match iter.and_then(|it| it.closure_params(i)) {
                    Some(ClosureParams::Element) => Some(vec![kr.clone()]),
                    Some(ClosureParams::AccumulatorAndElement) => Some(vec![
                        kargs.first().cloned().unwrap_or(Kind::Var),
                        kr.clone(),
                    ]),
                    None => None,
                };
            }
            kargs.push(self.expr(a));
            self.closure_hint = None;
        }
        if m.method == "powi" {
            return kr;
        }
        let any_var = kr.is_var() || kargs.iter().any(Kind::is_var);
        if !any_var {
            return Kind::Const;
        }
        // Iterator adaptors take what they are given (`q.iter().zip(self.m.iter())`); the
        // kind is their elements'.
        if let Some(iter) = iter {
            return match (iter, kargs.as_slice()) {
                (Iter::Zip, [k]) => Kind::Tuple(vec![kr, k.clone()]),
                (Iter::Enumerate, _) => Kind::Tuple(vec![Kind::Const, kr]),
                (Iter::Map, [k]) => k.clone(),
                (Iter::Fold, [a, b]) => Kind::join(a.clone(), b.clone()),
                (Iter::Sum | Iter::Product, _) => Kind::join(kr, Kind::Const),
                // A count, a truth value, or nothing (`for_each` runs for its effects).
                (Iter::Count | Iter::Len | Iter::Any | Iter::All | Iter::ForEach, _) => Kind::Const,
                (
                    Iter::Elements
                    | Iter::Rev
                    | Iter::Skip
                    | Iter::Take
                    | Iter::StepBy
                    | Iter::Filter
                    | Iter::Zip
                    | Iter::Map
                    | Iter::Fold,
                    _,
                ) => kr,
            };
        }
        // A method of the user's own type (`self.omega(t)`) takes its arguments as
        // declared: `self` is never lifted.
        if kr == Kind::Const && !is_self(&m.receiver) {
            lift_in_place(&mut m.receiver);
        }
        // A helper method takes a constant as it is where it declares an `f64`.
        let declared = if is_self(&m.receiver) {
            self.callables.helper(&unraw(&m.method)).cloned()
        } else {
            None
        };
        // A contact's restitution coefficient and name (`Contact::gap(y).restitution(self.e)`)
        // are an `f64` and a `&str`, not numbers of the motion.
        let as_written = crate::front::vocab::takes_arguments_as_written(&name);
        for (i, (a, k)) in m.args.iter_mut().zip(&kargs).enumerate() {
            let wants_scalar = !as_written
                && declared
                    .as_ref()
                    .is_none_or(|d| d.types.get(i) != Some(&ParamType::Other));
            if *k == Kind::Const && wants_scalar {
                lift_in_place(a);
            }
        }
        Kind::Var
    }

    /// A chain of binary operators `a + b + c …` (left-nested), walked down its left operands
    /// with a loop (a 2000-term sum must not overflow the compiler's stack), innermost first.
    pub(super) fn binary(&mut self, e: &mut Expr) -> Kind {
        let mut spine = Vec::new();
        let mut cur = std::mem::replace(e, placeholder());
        while let Expr::Binary(mut b) = cur {
            cur = std::mem::replace(&mut *b.left, placeholder());
            spine.push(b);
        }
        let mut kl = self.expr(&mut cur);
        while let Some(mut b) = spine.pop() {
            *b.left = cur;
            let mut node = Expr::Binary(b);
            kl = self.binary_one(&mut node, kl);
            cur = node;
        }
        *e = cur;
        kl
    }

    /// One operator of a chain, its left operand's kind `kl` known; may replace `e` by the
    /// mixed-operand call it needs.
    fn binary_one(&mut self, e: &mut Expr, kl: Kind) -> Kind {
        let Expr::Binary(b) = e else {
            return Kind::Const;
        };
        let kr = self.expr(&mut b.right);
        if matches!(b.op, BinOp::BitXor(_) | BinOp::BitXorAssign(_)) {
            self.errors.push(syn::Error::new(
                b.op.span(),
                "`^` is bitwise xor in Rust, not a power: write `x.powi(2)` for an integer power \
                 (`x.powf(p)` for a real one)",
            ));
        }
        if matches!(
            b.op,
            BinOp::Add(_)
                | BinOp::Sub(_)
                | BinOp::Mul(_)
                | BinOp::Div(_)
                | BinOp::AddAssign(_)
                | BinOp::SubAssign(_)
                | BinOp::MulAssign(_)
                | BinOp::DivAssign(_)
        ) {
            // An integer literal next to a value of the coordinates or a float: the number
            // type is f64, so `2` must be `2.0`.
            for (lit, other, ko) in [(&*b.left, &*b.right, &kr), (&*b.right, &*b.left, &kl)] {
                if let Some(i) = int_literal(lit) {
                    if ko.is_var() || is_float_literal(other) {
                        self.errors.push(syn::Error::new(
                            i.span(),
                            format!(
                                "an integer literal where a number of type f64 is needed: write `{}.0`",
                                i.base10_digits()
                            ),
                        ));
                    }
                }
            }
        }
        let mixed = |kl: &Kind, kr: &Kind| {
            (kl.is_var() && *kr == Kind::Const) || (*kl == Kind::Const && kr.is_var())
        };
        let arith = match b.op {
            BinOp::Add(_) => Some(("ConstAdd", "const_add", "AddConst", "add_const")),
            BinOp::Sub(_) => Some(("ConstSub", "const_sub", "SubConst", "sub_const")),
            BinOp::Mul(_) => Some(("ConstMul", "const_mul", "MulConst", "mul_const")),
            BinOp::Div(_) => Some(("ConstDiv", "const_div", "DivConst", "div_const")),
            _ => None,
        };
        if let Some((ct, cf, vt, vf)) = arith {
            if mixed(&kl, &kr) {
                let span = b.op.span();
                let (l, r) = (&b.left, &b.right);
                let (tr, f) = if kl == Kind::Const {
                    (ct, cf)
                } else {
                    (vt, vf)
                };
                let tr = syn::Ident::new(tr, span);
                let f = syn::Ident::new(f, span);
                *e = Expr::Verbatim(quote_spanned!(span=> ::lagrange::__private::#tr::#f(#l, #r)));
                return Kind::Var;
            }
            return Kind::join(kl, kr);
        }
        match b.op {
            BinOp::Rem(_) => {
                if mixed(&kl, &kr) {
                    if kl == Kind::Const {
                        lift_in_place(&mut b.left);
                    } else {
                        lift_in_place(&mut b.right);
                    }
                }
                Kind::join(kl, kr)
            }
            BinOp::Eq(_)
            | BinOp::Ne(_)
            | BinOp::Lt(_)
            | BinOp::Le(_)
            | BinOp::Gt(_)
            | BinOp::Ge(_) => {
                if mixed(&kl, &kr) {
                    if kl == Kind::Const {
                        lift_in_place(&mut b.left);
                    } else {
                        lift_in_place(&mut b.right);
                    }
                }
                Kind::Const
            }
            BinOp::AddAssign(_)
            | BinOp::SubAssign(_)
            | BinOp::MulAssign(_)
            | BinOp::DivAssign(_)
            | BinOp::RemAssign(_) => {
                if kl.is_var() && kr == Kind::Const {
                    lift_in_place(&mut b.right);
                }
                if kl == Kind::Const && kr.is_var() {
                    self.found.extend(assigned_root(&b.left));
                }
                Kind::Const
            }
            _ => Kind::join(kl, kr),
        }
    }
}

/// `v.norm().powi(2k)` → `v.norm_squared().powi(k)` (and `magnitude` alike): the same value,
/// but smooth at v = 0, where the jets of the square root are ∞·0 = NaN. The symbolic mode
/// folds √x to an even power the same way.
fn norm_power_to_norm_squared(m: &mut syn::ExprMethodCall) {
    if m.method != "powi" || m.args.len() != 1 {
        return;
    }
    let Some(Expr::Lit(syn::ExprLit {
        lit: syn::Lit::Int(n),
        ..
    })) = m.args.first()
    else {
        return;
    };
    let Ok(n) = n.base10_parse::<i32>() else {
        return;
    };
    let Expr::MethodCall(inner) = &mut *m.receiver else {
        return;
    };
    if n % 2 != 0
        || !inner.args.is_empty()
        || !(inner.method == "norm" || inner.method == "magnitude")
    {
        return;
    }
    let span = inner.method.span();
    inner.method = syn::Ident::new(&format!("{}_squared", inner.method), span);
    let half = proc_macro2::Literal::i32_unsuffixed(n / 2);
    m.args[0] = Expr::Verbatim(quote_spanned!(span=> #half));
}

/// The integer literal `e` is (through parentheses), if it is one without a float suffix.
fn int_literal(e: &Expr) -> Option<&syn::LitInt> {
    match paren_less(e) {
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Int(i),
            ..
        }) if i.suffix().is_empty() => Some(i),
        _ => None,
    }
}

fn is_float_literal(e: &Expr) -> bool {
    matches!(
        paren_less(e),
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Float(_),
            ..
        })
    )
}
