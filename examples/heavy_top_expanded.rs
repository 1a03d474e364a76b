//! What `#[lagrangian]` writes for the heavy top (eq. 92 of the reference text).
//!
//! The user writes:
//!
//! ```ignore
//! #[lagrangian]
//! impl HeavyTop {
//!     /// Symmetric heavy top, eq. (92).
//!     fn lagrangian(&self, (theta, theta_dot): Coord, (phi, phi_dot): Coord, (psi, psi_dot): Coord) -> Scalar {
//!         let (s, c) = theta.sin_cos();
//!         self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
//!             + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
//!             - self.m * self.g * self.l * c
//!     }
//! }
//! ```
//!
//! and the macro emits the code between the markers below (kept in sync by a test in
//! `lagrange-macros`; regenerate with `UPDATE_EXPANDED=1 cargo test -p lagrange-macros expanded`).
//! Note how constants meet coordinate values through `ConstMul`/`MulConst` (the constant stays an
//! `f64`), `phi` is not bound (it is cyclic), and every runtime path goes through
//! `::lagrange::__private`. Run it: `cargo run --example heavy_top_expanded`.

use lagrange::prelude::*;

/// Symmetric heavy top.
#[derive(Debug, Clone)]
pub struct HeavyTop {
    /// Moment of inertia about a transverse axis through the fixed point.
    pub i_perp: f64,
    /// Moment of inertia about the symmetry axis.
    pub i_par: f64,
    /// Mass.
    pub m: f64,
    /// Gravitational acceleration.
    pub g: f64,
    /// Distance from the fixed point to the centre of mass.
    pub l: f64,
}

// ---- BEGIN GENERATED (do not edit) ----
#[automatically_derived]
impl ::lagrange::__private::Lagrangian<3> for HeavyTop {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    #[doc = " Symmetric heavy top, eq. (92)."]
    #[inline]
    #[allow(
        clippy::all,
        clippy::pedantic,
        clippy::nursery,
        unused_parens,
        unused_braces,
        non_snake_case
    )]
    fn lagrangian<Scalar: ::lagrange::__private::Scalar>(
        &self,
        __lagrange_q: &[Scalar; 3],
        __lagrange_qdot: &[Scalar; 3],
        _: Scalar,
    ) -> Scalar {
        let theta = __lagrange_q[0];
        let theta_dot = __lagrange_qdot[0];
        let phi_dot = __lagrange_qdot[1];
        let psi_dot = __lagrange_qdot[2];
        let (s, c) = theta.sin_cos();
        ::lagrange::__private::ConstMul::const_mul(
            self.i_perp / 2.0,
            (theta_dot.powi(2) + (phi_dot * s).powi(2)),
        ) + ::lagrange::__private::ConstMul::const_mul(
            self.i_par / 2.0,
            (psi_dot + phi_dot * c).powi(2),
        ) - ::lagrange::__private::ConstMul::const_mul(self.m * self.g * self.l, c)
    }
}
// ---- END GENERATED ----

fn main() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    let (q, qdot) = ([1.0, 0.0, 0.0], [0.0, -0.5, 8.0]);
    println!(
        "COORDINATES = {:?}",
        <HeavyTop as Lagrangian<3>>::COORDINATES
    );
    println!("CYCLIC      = {:?}", <HeavyTop as Lagrangian<3>>::CYCLIC);
    match top.accelerations(&q, &qdot, 0.0) {
        Ok(a) => println!("q̈ at θ = 1, φ̇ = −0.5, ψ̇ = 8: {a:?}"),
        Err(e) => println!("error: {e}"),
    }
}
