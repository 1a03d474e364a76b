//! Scopes and bindings: the names a body binds and what each holds, for either back end (the
//! jets back end holds whether a value carries the motion, the symbolic one its graph nodes),
//! and the one pattern binder (`let`, `for`, closure and function parameters, `match` arms).

use syn::spanned::Spanned;
use syn::Pat;

use crate::model::unraw;

/// The bindings in scope, innermost last: a block, a loop body or an inlined call takes a
/// [`Scopes::mark`] on entry and [`Scopes::truncate`]s back to it on exit, so a later binding of
/// a name shadows an earlier one exactly as in Rust.
#[derive(Clone, Debug)]
pub struct Scopes<V> {
    items: Vec<(String, V)>,
}

impl<V> Default for Scopes<V> {
    fn default() -> Self {
        Scopes { items: Vec::new() }
    }
}

impl<V: Clone> Scopes<V> {
    /// The scopes holding `items`, innermost last.
    pub fn of(items: Vec<(String, V)>) -> Self {
        Scopes { items }
    }

    /// Binds `name` to `v`, shadowing any earlier binding of it.
    pub fn push(&mut self, name: String, v: V) {
        self.items.push((name, v));
    }

    /// What `name` holds in the innermost binding of it.
    pub fn lookup(&self, name: &str) -> Option<V> {
        self.items
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.clone())
    }

    /// Where the innermost binding of `name` is (compare with a [`Scopes::mark`]).
    pub fn position(&self, name: &str) -> Option<usize> {
        self.items.iter().rposition(|(n, _)| n == name)
    }

    /// Sets the binding at `k` (a [`Scopes::position`]) to `v`.
    pub fn set(&mut self, k: usize, v: V) {
        self.items[k].1 = v;
    }

    /// How many bindings there are: a scope's start, to [`Scopes::truncate`] back to.
    pub fn mark(&self) -> usize {
        self.items.len()
    }

    /// Drops every binding made after `mark`.
    pub fn truncate(&mut self, mark: usize) {
        self.items.truncate(mark);
    }

    /// Every binding, outermost first.
    pub fn iter(&self) -> impl Iterator<Item = &(String, V)> {
        self.items.iter()
    }

    /// Replaces every binding by `items` (an inlined call's own scope), returning the old ones.
    pub fn replace(&mut self, items: Scopes<V>) -> Scopes<V> {
        std::mem::replace(self, items)
    }

    /// Removes every binding, returning them.
    pub fn take(&mut self) -> Scopes<V> {
        std::mem::take(self)
    }
}

/// What a back end binds: how a value splits over a tuple pattern and which patterns it takes.
pub trait Bindable: Clone {
    /// The parts of the value for a tuple pattern of `n` elements (`Err` with the value each
    /// element then gets, when the value does not have that shape and the back end says so).
    fn parts(self, n: usize) -> Result<Vec<Self>, Self>;
    /// The value a typed pattern `p: T` binds.
    fn typed(self, _ty: &syn::Type) -> Self {
        self
    }
    /// The error for a pattern the back end does not take (`ref x`, `x @ ..`, slices, structs,
    /// or-patterns): `None` where it binds every part of it to the whole value (rustc then
    /// checks the pattern against the value as written).
    fn refuse(_pat: &Pat) -> Option<syn::Error> {
        None
    }
}

/// Binds the names of `pat` to (the parts of) `v`; errors into `errors`.
pub fn bind<V: Bindable>(scopes: &mut Scopes<V>, pat: &Pat, v: V, errors: &mut Vec<syn::Error>) {
    match pat {
        Pat::Ident(p) if p.by_ref.is_none() && p.subpat.is_none() => {
            scopes.push(unraw(&p.ident), v);
        }
        Pat::Wild(_) => {}
        Pat::Type(t) => {
            let v = v.typed(&t.ty);
            bind(scopes, &t.pat, v, errors)
        }
        Pat::Paren(p) => bind(scopes, &p.pat, v, errors),
        Pat::Reference(r) => bind(scopes, &r.pat, v, errors),
        Pat::Tuple(t) => {
            let parts = v.parts(t.elems.len()).unwrap_or_else(|each| {
                errors.push(syn::Error::new(
                    t.span(),
                    "this tuple pattern does not match the value's shape",
                ));
                vec![each; t.elems.len()]
            });
            for (p, part) in t.elems.iter().zip(parts) {
                bind(scopes, p, part, errors);
            }
        }
        other => match V::refuse(other) {
            Some(e) => errors.push(e),
            None => bind_whole(scopes, other, v, errors),
        },
    }
}

/// A pattern whose every name gets the whole value.
fn bind_whole<V: Bindable>(scopes: &mut Scopes<V>, pat: &Pat, v: V, errors: &mut Vec<syn::Error>) {
    let subs: Vec<&Pat> = match pat {
        Pat::Ident(p) => {
            scopes.push(unraw(&p.ident), v.clone());
            p.subpat.iter().map(|(_, s)| &**s).collect()
        }
        Pat::Slice(s) => s.elems.iter().collect(),
        Pat::TupleStruct(ts) => ts.elems.iter().collect(),
        Pat::Struct(ps) => ps.fields.iter().map(|f| &*f.pat).collect(),
        Pat::Or(o) => o.cases.iter().collect(),
        _ => Vec::new(),
    };
    for s in subs {
        bind(scopes, s, v.clone(), errors);
    }
}

impl<V> IntoIterator for Scopes<V> {
    type Item = (String, V);
    type IntoIter = std::vec::IntoIter<(String, V)>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.into_iter()
    }
}

impl<V> FromIterator<(String, V)> for Scopes<V> {
    fn from_iter<I: IntoIterator<Item = (String, V)>>(iter: I) -> Self {
        Scopes {
            items: iter.into_iter().collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value that is a number or a tuple of values; a tuple pattern of another length is an
    /// error.
    #[derive(Clone, Debug, PartialEq)]
    enum V {
        N(i32),
        T(Vec<V>),
    }

    impl Bindable for V {
        fn parts(self, n: usize) -> Result<Vec<V>, V> {
            match self {
                V::T(items) if items.len() == n => Ok(items),
                _ => Err(V::N(-1)),
            }
        }
        fn refuse(pat: &Pat) -> Option<syn::Error> {
            Some(syn::Error::new(pat.span(), "refused"))
        }
    }

    #[test]
    fn binds_destructures_shadows_and_refuses() {
        let mut s = Scopes::default();
        let mut errors = Vec::new();
        let pat: Pat = syn::parse_quote!((a, (b, _), c));
        let v = V::T(vec![V::N(1), V::T(vec![V::N(2), V::N(3)]), V::N(4)]);
        let mark = s.mark();
        bind(&mut s, &pat, v, &mut errors);
        assert!(errors.is_empty());
        assert_eq!(s.lookup("a"), Some(V::N(1)));
        assert_eq!(s.lookup("b"), Some(V::N(2)));
        assert_eq!(s.lookup("c"), Some(V::N(4)));
        let syn::Stmt::Local(local) = syn::parse_quote!(let a: f64 = 0.0;) else {
            unreachable!("a `let` statement")
        };
        let typed = local.pat;
        bind(&mut s, &typed, V::N(9), &mut errors);
        assert_eq!(s.lookup("a"), Some(V::N(9)));
        let wrong: Pat = syn::parse_quote!((x, y));
        bind(&mut s, &wrong, V::N(0), &mut errors);
        assert_eq!(errors.len(), 1);
        assert_eq!(s.lookup("y"), Some(V::N(-1)));
        let slice: Pat = syn::parse_quote!([p, q]);
        bind(&mut s, &slice, V::N(0), &mut errors);
        assert_eq!(errors.len(), 2);
        assert_eq!(s.lookup("p"), None);
        s.truncate(mark);
        assert_eq!(s.lookup("a"), None);
    }
}
