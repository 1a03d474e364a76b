//! Hygiene of the generated code: constants in the user's module named like the parameters and
//! locals the macro generates (`q`, `t`, `scale`, `tol`, `x3`, ...) break neither mode. These are
//! compile-pass cases run as ordinary tests (a trybuild pass case would build every
//! dev-dependency once more).

mod jets;
mod symbolic;
