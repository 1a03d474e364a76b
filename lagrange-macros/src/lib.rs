mod model;
mod symbolic;
use proc_macro::TokenStream;
#[proc_macro_attribute]
pub fn lagrangian(_a: TokenStream, i: TokenStream) -> TokenStream {
    i
}
