//! Closed-form and quadrature theory of classic systems (the reference text's heavy top), which
//! lagrange's tests and examples check simulations against: physics derived independently of
//! the integrators, kept out of lagrange's API.
//!
//! - [`heavy_top`]: the symmetric heavy top of the reference text's section D (eqs. 92–102): its
//!   conserved quantities, the cubic of eq. 96 and its roots, the nutation period (eq. 97) and the
//!   mean precession rate over a nutation period.
//!
//! ```
//! use lagrange_theory::heavy_top::{Constants, Top};
//! let top = Top { i_perp: 1.0, i_par: 0.5, mgl: 1.0 };
//! let c = Constants::from_state(&top, &[1.0, 0.0, 0.0], &[0.0, 0.0, 20.0]).unwrap();
//! assert!((c.l_par - 10.0).abs() < 1e-15);
//! ```

#![forbid(unsafe_code)]

pub mod heavy_top;
