//! The iterator vocabulary of the body language, once: which methods are iterator methods, how
//! many arguments each takes and what a closure argument receives. Both back ends dispatch on
//! [`Iter`] (the jets' kinds match on it exhaustively, so a new word is a variant here and an arm
//! there that the compiler asks for; the symbolic mode lowers the words it unrolls).

/// An iterator method of the body language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Iter {
    /// `iter`, `into_iter`, `copied`, `cloned`, `by_ref`: the elements as they are.
    Elements,
    /// `len`: the number of elements.
    Len,
    /// `count`: the number of elements.
    Count,
    /// `enumerate`: (index, element) pairs.
    Enumerate,
    /// `rev`: the elements backwards.
    Rev,
    /// `skip(k)`.
    Skip,
    /// `take(k)`.
    Take,
    /// `step_by(k)`.
    StepBy,
    /// `zip(other)`: (element, other's element) pairs, as long as the shorter side.
    Zip,
    /// `map(f)`: f of each element.
    Map,
    /// `fold(init, f)`: f(acc, element) from init.
    Fold,
    /// `sum()`.
    Sum,
    /// `product()`.
    Product,
    /// `for_each(f)`, run for its effects (the jets only: the symbolic mode has no effects).
    ForEach,
    /// `filter(p)` (the jets only: which elements pass depends on the values).
    Filter,
    /// `any(p)` (the jets only).
    Any,
    /// `all(p)` (the jets only).
    All,
}

/// What a closure argument of an iterator method receives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClosureParams {
    /// One element (`map`, `for_each`, `filter`, `any`, `all`).
    Element,
    /// The accumulator (the method's first argument) and one element (`fold`).
    AccumulatorAndElement,
}

impl Iter {
    /// The iterator method called `name`, if it is one.
    pub fn of(name: &str) -> Option<Iter> {
        Some(match name {
            "iter" | "into_iter" | "copied" | "cloned" | "by_ref" => Iter::Elements,
            "len" => Iter::Len,
            "count" => Iter::Count,
            "enumerate" => Iter::Enumerate,
            "rev" => Iter::Rev,
            "skip" => Iter::Skip,
            "take" => Iter::Take,
            "step_by" => Iter::StepBy,
            "zip" => Iter::Zip,
            "map" => Iter::Map,
            "fold" => Iter::Fold,
            "sum" => Iter::Sum,
            "product" => Iter::Product,
            "for_each" => Iter::ForEach,
            "filter" => Iter::Filter,
            "any" => Iter::Any,
            "all" => Iter::All,
            _ => return None,
        })
    }

    /// What the closure passed as argument `arg` receives, if that argument is a closure.
    pub fn closure_params(self, arg: usize) -> Option<ClosureParams> {
        match (self, arg) {
            (Iter::Map | Iter::ForEach | Iter::Filter | Iter::Any | Iter::All, 0) => {
                Some(ClosureParams::Element)
            }
            (Iter::Fold, 1) => Some(ClosureParams::AccumulatorAndElement),
            _ => None,
        }
    }

    /// A word only the jets take (the symbolic mode unrolls iterators into values, and these
    /// depend on the values or run for effects).
    pub fn jets_only(self) -> bool {
        matches!(self, Iter::ForEach | Iter::Filter | Iter::Any | Iter::All)
    }

    /// An adaptor: it makes another iterator (a consumer makes a value).
    pub fn is_adaptor(self) -> bool {
        matches!(
            self,
            Iter::Elements
                | Iter::Enumerate
                | Iter::Rev
                | Iter::Skip
                | Iter::Take
                | Iter::StepBy
                | Iter::Zip
                | Iter::Map
                | Iter::Filter
        )
    }
}

/// A contact's builder methods whose arguments are taken as written, not as numbers of the
/// motion (`Contact::gap(y).restitution(self.e).named("floor")`).
pub fn takes_arguments_as_written(method: &str) -> bool {
    matches!(method, "restitution" | "named")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_words_and_their_closures() {
        let words = [
            ("iter", Iter::Elements),
            ("by_ref", Iter::Elements),
            ("len", Iter::Len),
            ("skip", Iter::Skip),
            ("zip", Iter::Zip),
            ("fold", Iter::Fold),
            ("any", Iter::Any),
        ];
        for (w, it) in words {
            assert_eq!(Iter::of(w), Some(it), "{w}");
        }
        assert_eq!(Iter::of("sin"), None);
        assert_eq!(
            Iter::Fold.closure_params(1),
            Some(ClosureParams::AccumulatorAndElement)
        );
        assert_eq!(Iter::Fold.closure_params(0), None);
        assert!(Iter::Zip.is_adaptor() && !Iter::Sum.is_adaptor());
        assert!(Iter::Filter.jets_only() && !Iter::Map.jets_only());
    }
}
