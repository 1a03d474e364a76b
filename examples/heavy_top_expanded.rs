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
//!
//! What to look for:
//! - `lagrangian<Scalar>` is the body as written, generic over the number type, with the constants
//!   routed through `ConstMul` (an `f64` times a jet is a scale, not a jet product); `phi` is not
//!   bound because it is cyclic. The run-time jets use it, and so can you.
//! - `accelerations`, `mass_matrix`, `momenta` and `energy` are the symbolic mode (the default):
//!   the derivatives of L were taken at compile time, common subexpressions are computed once,
//!   entries of M that are structurally zero are skipped, and M q̈ = f is solved by a
//!   straight-line LDLᵀ that falls back to the runtime's pivoting solve (and its typed error) if a
//!   pivot is not clearly positive.
//! - `HeavyTop::EQUATIONS` / `EQUATIONS_LATEX`: the Euler–Lagrange equations for people.
//! - Every runtime path goes through `::lagrange::__private`.
//!
//! Run it: `cargo run --example heavy_top_expanded`.

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
    #[allow(
        unused_variables,
        unused_parens,
        non_snake_case,
        clippy::all,
        clippy::pedantic,
        clippy::nursery
    )]
    #[inline(always)]
    fn accelerations(
        &self,
        q: &[f64; 3],
        qdot: &[f64; 3],
        t: f64,
    ) -> ::core::result::Result<[f64; 3], ::lagrange::__private::DynamicsError> {
        let _ = (q, qdot, t);
        let p_i_perp: f64 = self.i_perp;
        let p_i_par: f64 = self.i_par;
        let p_m: f64 = self.m;
        let p_g: f64 = self.g;
        let p_l: f64 = self.l;
        let ((x8, x9), x31): ((f64, f64), f64) = (q[0].sin_cos(), p_m * p_g);
        let (x15, x22, x33, x53, x55, x58, x59, x60): (f64, f64, f64, f64, f64, f64, f64, f64) = (
            qdot[1] * x8,
            qdot[1] * x9,
            x31 * p_l,
            x8 * x8,
            x9 * x9,
            x9 * p_i_par,
            qdot[0] * x9,
            qdot[0] * x8,
        );
        let (x23, x54, x56, x63, x65, x80, x93): (f64, f64, f64, f64, f64, f64, f64) = (
            qdot[2] + x22,
            p_i_perp * x53,
            p_i_par * x55,
            qdot[1] * x60,
            x15 * x59,
            x15 * x22,
            x8 * x33,
        );
        let (x57, x67, x69, x77, x82, x85, x104): (f64, f64, f64, f64, f64, f64, f64) = (
            x54 + x56,
            p_i_perp * x65,
            x23 * x60,
            p_i_par * x63,
            p_i_perp * x80,
            x15 * x23,
            p_i_par * x54,
        );
        let (x68, x72, x89): (f64, f64, f64) = (2.0 * x67, x65 + x69, p_i_par * x85);
        let (x74, x91): (f64, f64) = (p_i_par * x72, x82 - x89);
        let (x95, x96): (f64, f64) = (x91 + x93, x74 - x68);
        let fast: ::core::option::Option<[f64; 3]> = 'fast: {
            let __lagrange_max = |s: f64, a: f64| if a > s { a } else { s };
            let scale: f64 = __lagrange_max(
                __lagrange_max(__lagrange_max(0.0_f64, f64::abs(p_i_perp)), f64::abs(x57)),
                f64::abs(p_i_par),
            );
            let tol = ::lagrange::__private::linalg::SINGULAR_RELATIVE_PIVOT * scale;
            if !(x57 > tol) {
                break 'fast ::core::option::Option::None;
            }
            let det_1_2: f64 = x104;
            if !(det_1_2 > tol * x57) {
                break 'fast ::core::option::Option::None;
            }
            let y_1: f64 = (p_i_par * x96 - x58 * x77) / det_1_2;
            let y_2: f64 = (x57 * x77 - x58 * x96) / det_1_2;
            let d_0: f64 = p_i_perp;
            if !(d_0 > tol) {
                break 'fast ::core::option::Option::None;
            }
            let y_0: f64 = x95;
            let y_0: f64 = y_0 / d_0;
            let x = [y_0, y_1, y_2];
            if (y_0 + y_1 + y_2).is_finite() {
                ::core::option::Option::Some(x)
            } else {
                ::core::option::Option::None
            }
        };
        match fast {
            ::core::option::Option::Some(x) => ::core::result::Result::Ok(x),
            ::core::option::Option::None => ::lagrange::__private::solve_mass_matrix(
                &[[p_i_perp, 0.0, 0.0], [0.0, x57, x58], [0.0, 0.0, p_i_par]],
                &[x95, x96, x77],
                <Self as ::lagrange::__private::Lagrangian<3>>::COORDINATES,
                q,
                qdot,
                t,
            ),
        }
    }
    #[allow(
        unused_variables,
        unused_parens,
        non_snake_case,
        clippy::all,
        clippy::pedantic,
        clippy::nursery
    )]
    #[inline]
    fn mass_matrix(
        &self,
        q: &[f64; 3],
        qdot: &[f64; 3],
        t: f64,
    ) -> ::lagrange::__private::SMatrix<f64, 3, 3> {
        let _ = (q, qdot, t);
        let p_i_perp: f64 = self.i_perp;
        let p_i_par: f64 = self.i_par;
        let (x8, x9): (f64, f64) = q[0].sin_cos();
        let (x53, x55, x58): (f64, f64, f64) = (x8 * x8, x9 * x9, x9 * p_i_par);
        let (x54, x56): (f64, f64) = (p_i_perp * x53, p_i_par * x55);
        let x57: f64 = x54 + x56;
        ::lagrange::__private::SMatrix::<f64, 3, 3>::from_row_slice(&[
            p_i_perp, 0.0, 0.0, 0.0, x57, x58, 0.0, x58, p_i_par,
        ])
    }
    #[allow(
        unused_variables,
        unused_parens,
        non_snake_case,
        clippy::all,
        clippy::pedantic,
        clippy::nursery
    )]
    #[inline]
    fn momenta(&self, q: &[f64; 3], qdot: &[f64; 3], t: f64) -> [f64; 3] {
        let _ = (q, qdot, t);
        let p_i_perp: f64 = self.i_perp;
        let p_i_par: f64 = self.i_par;
        let ((x8, x9), x37): ((f64, f64), f64) = (q[0].sin_cos(), qdot[0] * p_i_perp);
        let (x15, x22): (f64, f64) = (qdot[1] * x8, qdot[1] * x9);
        let (x23, x40): (f64, f64) = (qdot[2] + x22, x8 * x15);
        let (x42, x45, x51): (f64, f64, f64) = (p_i_perp * x40, x9 * x23, p_i_par * x23);
        let x47: f64 = p_i_par * x45;
        let x49: f64 = x42 + x47;
        [x37, x49, x51]
    }
    #[allow(
        unused_variables,
        unused_parens,
        non_snake_case,
        clippy::all,
        clippy::pedantic,
        clippy::nursery
    )]
    #[inline]
    fn energy(&self, q: &[f64; 3], qdot: &[f64; 3], t: f64) -> f64 {
        let _ = (q, qdot, t);
        let p_i_perp: f64 = self.i_perp;
        let p_i_par: f64 = self.i_par;
        let p_m: f64 = self.m;
        let p_g: f64 = self.g;
        let p_l: f64 = self.l;
        let ((x8, x9), x14, x31, x37): ((f64, f64), f64, f64, f64) = (
            q[0].sin_cos(),
            qdot[0] * qdot[0],
            p_m * p_g,
            qdot[0] * p_i_perp,
        );
        let (x15, x22, x33, x98): (f64, f64, f64, f64) =
            (qdot[1] * x8, qdot[1] * x9, x31 * p_l, qdot[0] * x37);
        let (x16, x23, x34, x40): (f64, f64, f64, f64) =
            (x15 * x15, qdot[2] + x22, x9 * x33, x8 * x15);
        let (x17, x24, x42, x45, x51): (f64, f64, f64, f64, f64) = (
            x14 + x16,
            x23 * x23,
            p_i_perp * x40,
            x9 * x23,
            p_i_par * x23,
        );
        let (x18, x25, x47, x102): (f64, f64, f64, f64) =
            (p_i_perp * x17, p_i_par * x24, p_i_par * x45, qdot[2] * x51);
        let (x27, x49): (f64, f64) = (x18 + x25, x42 + x47);
        let (x28, x100): (f64, f64) = (0.5 * x27, qdot[1] * x49);
        let x97: f64 = x34 - x28;
        let x99: f64 = x97 + x98;
        let x101: f64 = x99 + x100;
        let x103: f64 = x101 + x102;
        x103
    }
    #[allow(
        unused_variables,
        unused_parens,
        non_snake_case,
        clippy::all,
        clippy::pedantic,
        clippy::nursery
    )]
    #[inline]
    fn energy_and_momenta(&self, q: &[f64; 3], qdot: &[f64; 3], t: f64) -> (f64, [f64; 3]) {
        let _ = (q, qdot, t);
        let p_i_perp: f64 = self.i_perp;
        let p_i_par: f64 = self.i_par;
        let p_m: f64 = self.m;
        let p_g: f64 = self.g;
        let p_l: f64 = self.l;
        let ((x8, x9), x14, x31, x37): ((f64, f64), f64, f64, f64) = (
            q[0].sin_cos(),
            qdot[0] * qdot[0],
            p_m * p_g,
            qdot[0] * p_i_perp,
        );
        let (x15, x22, x33, x98): (f64, f64, f64, f64) =
            (qdot[1] * x8, qdot[1] * x9, x31 * p_l, qdot[0] * x37);
        let (x16, x23, x34, x40): (f64, f64, f64, f64) =
            (x15 * x15, qdot[2] + x22, x9 * x33, x8 * x15);
        let (x17, x24, x42, x45, x51): (f64, f64, f64, f64, f64) = (
            x14 + x16,
            x23 * x23,
            p_i_perp * x40,
            x9 * x23,
            p_i_par * x23,
        );
        let (x18, x25, x47, x102): (f64, f64, f64, f64) =
            (p_i_perp * x17, p_i_par * x24, p_i_par * x45, qdot[2] * x51);
        let (x27, x49): (f64, f64) = (x18 + x25, x42 + x47);
        let (x28, x100): (f64, f64) = (0.5 * x27, qdot[1] * x49);
        let x97: f64 = x34 - x28;
        let x99: f64 = x97 + x98;
        let x101: f64 = x99 + x100;
        let x103: f64 = x101 + x102;
        (x103, [x37, x49, x51])
    }
}
#[doc = "# Equations of motion\n\nDerived at compile time by `#[lagrangian]` (d/dt ∂L/∂q\u{307} = ∂L/∂q, one line per coordinate):\n\n```text\ntheta: i_perp θ\u{308} = −i_par φ\u{307} ψ\u{307} sin(θ) + (i_perp − i_par) φ\u{307}² sin(θ) cos(θ) + m g l sin(θ)\nphi: i_perp φ\u{308} sin²(θ) + i_par φ\u{308} cos²(θ) + i_par ψ\u{308} cos(θ) = 2 (i_par − i_perp) θ\u{307} φ\u{307} sin(θ) cos(θ) + i_par θ\u{307} ψ\u{307} sin(θ)\npsi: i_par φ\u{308} cos(θ) + i_par ψ\u{308} = i_par θ\u{307} φ\u{307} sin(θ)\n```\n"]
impl HeavyTop {
    #[doc = "The Euler–Lagrange equations, derived at compile time by `#[lagrangian]`: one line per coordinate, `Σₖ Mᵢₖ q\u{308}ₖ = fᵢ` (accelerations on the left).\n\n```text\ntheta: i_perp θ\u{308} = −i_par φ\u{307} ψ\u{307} sin(θ) + (i_perp − i_par) φ\u{307}² sin(θ) cos(θ) + m g l sin(θ)\nphi: i_perp φ\u{308} sin²(θ) + i_par φ\u{308} cos²(θ) + i_par ψ\u{308} cos(θ) = 2 (i_par − i_perp) θ\u{307} φ\u{307} sin(θ) cos(θ) + i_par θ\u{307} ψ\u{307} sin(θ)\npsi: i_par φ\u{308} cos(θ) + i_par ψ\u{308} = i_par θ\u{307} φ\u{307} sin(θ)\n```"]
    pub const EQUATIONS : & 'static str = "theta: i_perp θ\u{308} = −i_par φ\u{307} ψ\u{307} sin(θ) + (i_perp − i_par) φ\u{307}² sin(θ) cos(θ) + m g l sin(θ)\nphi: i_perp φ\u{308} sin²(θ) + i_par φ\u{308} cos²(θ) + i_par ψ\u{308} cos(θ) = 2 (i_par − i_perp) θ\u{307} φ\u{307} sin(θ) cos(θ) + i_par θ\u{307} ψ\u{307} sin(θ)\npsi: i_par φ\u{308} cos(θ) + i_par ψ\u{308} = i_par θ\u{307} φ\u{307} sin(θ)" ;
    #[doc = "The Euler–Lagrange equations in LaTeX, one line per coordinate (the same equations as `EQUATIONS`)."]
    pub const EQUATIONS_LATEX : & 'static str = "i_{\\mathrm{perp}} \\ddot{\\theta} = -i_{\\mathrm{par}} \\dot{\\phi} \\dot{\\psi} \\sin\\left(\\theta\\right) + \\left(i_{\\mathrm{perp}} - i_{\\mathrm{par}}\\right) \\dot{\\phi}^{2} \\sin\\left(\\theta\\right) \\cos\\left(\\theta\\right) + m g l \\sin\\left(\\theta\\right)\ni_{\\mathrm{perp}} \\ddot{\\phi} \\sin^{2}\\left(\\theta\\right) + i_{\\mathrm{par}} \\ddot{\\phi} \\cos^{2}\\left(\\theta\\right) + i_{\\mathrm{par}} \\ddot{\\psi} \\cos\\left(\\theta\\right) = 2 \\left(i_{\\mathrm{par}} - i_{\\mathrm{perp}}\\right) \\dot{\\theta} \\dot{\\phi} \\sin\\left(\\theta\\right) \\cos\\left(\\theta\\right) + i_{\\mathrm{par}} \\dot{\\theta} \\dot{\\psi} \\sin\\left(\\theta\\right)\ni_{\\mathrm{par}} \\ddot{\\phi} \\cos\\left(\\theta\\right) + i_{\\mathrm{par}} \\ddot{\\psi} = i_{\\mathrm{par}} \\dot{\\theta} \\dot{\\phi} \\sin\\left(\\theta\\right)" ;
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
    println!("EQUATIONS:\n{}", HeavyTop::EQUATIONS);
    match top.accelerations(&q, &qdot, 0.0) {
        Ok(a) => println!("q̈ at θ = 1, φ̇ = −0.5, ψ̇ = 8: {a:?}"),
        Err(e) => println!("error: {e}"),
    }
}
