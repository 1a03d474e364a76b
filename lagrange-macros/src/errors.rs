//! An accumulator of spanned errors: every stage pushes, nothing is first-error-wins.

/// Collected `syn::Error`s.
#[derive(Default)]
pub struct Errors(Option<syn::Error>);

impl Errors {
    /// Adds one error.
    pub fn push(&mut self, e: syn::Error) {
        match &mut self.0 {
            Some(all) => all.combine(e),
            None => self.0 = Some(e),
        }
    }
    /// Adds an error spanned at `tokens`.
    pub fn at(&mut self, tokens: impl quote::ToTokens, msg: impl std::fmt::Display) {
        self.push(syn::Error::new_spanned(tokens, msg));
    }
    /// Adds every error of `other`.
    pub fn push_all(&mut self, other: Errors) {
        if let Some(e) = other.0 {
            self.push(e);
        }
    }
    /// Whether nothing was pushed.
    pub fn is_empty(&self) -> bool {
        self.0.is_none()
    }
    /// The errors one by one.
    #[cfg(test)]
    pub fn into_vec(self) -> Vec<syn::Error> {
        self.0.into_iter().flatten().collect()
    }
    /// All errors as `compile_error!` invocations.
    pub fn to_compile_errors(&self) -> proc_macro2::TokenStream {
        self.0
            .as_ref()
            .map(syn::Error::to_compile_error)
            .unwrap_or_default()
    }
}
