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
#[allow(
    unused_parens,
    unused_braces,
    non_snake_case,
    clippy::all,
    clippy::pedantic,
    clippy::nursery
)]
impl ::lagrange::__private::Lagrangian<3> for HeavyTop {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    #[doc = " Symmetric heavy top, eq. (92)."]
    #[inline]
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
    #[inline(always)]
    fn accelerations(
        &self,
        __lagrange_q: &[f64; 3],
        __lagrange_qdot: &[f64; 3],
        __lagrange_t: f64,
    ) -> ::core::result::Result<[f64; 3], ::lagrange::__private::DynamicsError> {
        __lagrange_HeavyTop_67f09420_kernels::accelerations::<f64, _>(
            &Self::__lagrange_params(self),
            __lagrange_q,
            __lagrange_qdot,
            __lagrange_t,
            |__lagrange_qddot, __lagrange_ok| {
                __lagrange_ok.then_some(::core::result::Result::Ok(__lagrange_qddot))
            },
            |__lagrange_m, __lagrange_f| {
                ::lagrange::__private::solve_mass_matrix(
                    __lagrange_m,
                    __lagrange_f,
                    <Self as ::lagrange::__private::Lagrangian<3>>::COORDINATES,
                    __lagrange_q,
                    __lagrange_qdot,
                    __lagrange_t,
                )
            },
        )
    }
    #[inline(always)]
    fn pieces(
        &self,
        __lagrange_q: &[f64; 3],
        __lagrange_qdot: &[f64; 3],
        __lagrange_t: f64,
    ) -> ::lagrange::__private::eom::Pieces<3> {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_i_perp: f64 = self.i_perp;
        let __lagrange_p_i_par: f64 = self.i_par;
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_g: f64 = self.g;
        let __lagrange_p_l: f64 = self.l;
        let ((__lagrange_x8, __lagrange_x9), __lagrange_x31): ((f64, f64), f64) =
            (__lagrange_q[0].sin_cos(), __lagrange_p_m * __lagrange_p_g);
        let (
            __lagrange_x15,
            __lagrange_x22,
            __lagrange_x33,
            __lagrange_x53,
            __lagrange_x55,
            __lagrange_x58,
            __lagrange_x59,
            __lagrange_x60,
        ): (f64, f64, f64, f64, f64, f64, f64, f64) = (
            __lagrange_qdot[1] * __lagrange_x8,
            __lagrange_qdot[1] * __lagrange_x9,
            __lagrange_x31 * __lagrange_p_l,
            __lagrange_x8 * __lagrange_x8,
            __lagrange_x9 * __lagrange_x9,
            __lagrange_x9 * __lagrange_p_i_par,
            __lagrange_qdot[0] * __lagrange_x9,
            __lagrange_qdot[0] * __lagrange_x8,
        );
        let (
            __lagrange_x23,
            __lagrange_x54,
            __lagrange_x56,
            __lagrange_x63,
            __lagrange_x65,
            __lagrange_x80,
            __lagrange_x93,
        ): (f64, f64, f64, f64, f64, f64, f64) = (
            __lagrange_qdot[2] + __lagrange_x22,
            __lagrange_p_i_perp * __lagrange_x53,
            __lagrange_p_i_par * __lagrange_x55,
            __lagrange_qdot[1] * __lagrange_x60,
            __lagrange_x15 * __lagrange_x59,
            __lagrange_x15 * __lagrange_x22,
            __lagrange_x8 * __lagrange_x33,
        );
        let (
            __lagrange_x57,
            __lagrange_x67,
            __lagrange_x69,
            __lagrange_x77,
            __lagrange_x82,
            __lagrange_x85,
        ): (f64, f64, f64, f64, f64, f64) = (
            __lagrange_x54 + __lagrange_x56,
            __lagrange_p_i_perp * __lagrange_x65,
            __lagrange_x23 * __lagrange_x60,
            __lagrange_p_i_par * __lagrange_x63,
            __lagrange_p_i_perp * __lagrange_x80,
            __lagrange_x15 * __lagrange_x23,
        );
        let (__lagrange_x68, __lagrange_x72, __lagrange_x89): (f64, f64, f64) = (
            2.0 * __lagrange_x67,
            __lagrange_x65 + __lagrange_x69,
            __lagrange_p_i_par * __lagrange_x85,
        );
        let (__lagrange_x74, __lagrange_x91): (f64, f64) = (
            __lagrange_p_i_par * __lagrange_x72,
            __lagrange_x82 - __lagrange_x89,
        );
        let (__lagrange_x95, __lagrange_x96): (f64, f64) = (
            __lagrange_x91 + __lagrange_x93,
            __lagrange_x74 - __lagrange_x68,
        );
        ::lagrange::__private::eom::Pieces::new(
            [
                [__lagrange_p_i_perp, 0.0, 0.0],
                [0.0, __lagrange_x57, __lagrange_x58],
                [0.0, 0.0, __lagrange_p_i_par],
            ],
            [__lagrange_x95, __lagrange_x96, __lagrange_x77],
        )
    }
    #[inline]
    fn power(&self, __lagrange_q: &[f64; 3], __lagrange_qdot: &[f64; 3], __lagrange_t: f64) -> f64 {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        0.0
    }
    #[inline]
    fn mass_matrix(
        &self,
        __lagrange_q: &[f64; 3],
        __lagrange_qdot: &[f64; 3],
        __lagrange_t: f64,
    ) -> ::lagrange::__private::SMatrix<f64, 3, 3> {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_i_perp: f64 = self.i_perp;
        let __lagrange_p_i_par: f64 = self.i_par;
        let (__lagrange_x8, __lagrange_x9): (f64, f64) = __lagrange_q[0].sin_cos();
        let (__lagrange_x53, __lagrange_x55, __lagrange_x58): (f64, f64, f64) = (
            __lagrange_x8 * __lagrange_x8,
            __lagrange_x9 * __lagrange_x9,
            __lagrange_x9 * __lagrange_p_i_par,
        );
        let (__lagrange_x54, __lagrange_x56): (f64, f64) = (
            __lagrange_p_i_perp * __lagrange_x53,
            __lagrange_p_i_par * __lagrange_x55,
        );
        let __lagrange_x57: f64 = __lagrange_x54 + __lagrange_x56;
        ::lagrange::__private::SMatrix::<f64, 3, 3>::from_row_slice(&[
            __lagrange_p_i_perp,
            0.0,
            0.0,
            0.0,
            __lagrange_x57,
            __lagrange_x58,
            0.0,
            __lagrange_x58,
            __lagrange_p_i_par,
        ])
    }
    #[inline]
    fn momenta(
        &self,
        __lagrange_q: &[f64; 3],
        __lagrange_qdot: &[f64; 3],
        __lagrange_t: f64,
    ) -> [f64; 3] {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_i_perp: f64 = self.i_perp;
        let __lagrange_p_i_par: f64 = self.i_par;
        let ((__lagrange_x8, __lagrange_x9), __lagrange_x37): ((f64, f64), f64) = (
            __lagrange_q[0].sin_cos(),
            __lagrange_qdot[0] * __lagrange_p_i_perp,
        );
        let (__lagrange_x15, __lagrange_x22): (f64, f64) = (
            __lagrange_qdot[1] * __lagrange_x8,
            __lagrange_qdot[1] * __lagrange_x9,
        );
        let (__lagrange_x23, __lagrange_x40): (f64, f64) = (
            __lagrange_qdot[2] + __lagrange_x22,
            __lagrange_x8 * __lagrange_x15,
        );
        let (__lagrange_x42, __lagrange_x45, __lagrange_x51): (f64, f64, f64) = (
            __lagrange_p_i_perp * __lagrange_x40,
            __lagrange_x9 * __lagrange_x23,
            __lagrange_p_i_par * __lagrange_x23,
        );
        let __lagrange_x47: f64 = __lagrange_p_i_par * __lagrange_x45;
        let __lagrange_x49: f64 = __lagrange_x42 + __lagrange_x47;
        [__lagrange_x37, __lagrange_x49, __lagrange_x51]
    }
    #[inline]
    fn energy(
        &self,
        __lagrange_q: &[f64; 3],
        __lagrange_qdot: &[f64; 3],
        __lagrange_t: f64,
    ) -> f64 {
        <Self as ::lagrange::__private::Lagrangian<3>>::energy_and_momenta(
            self,
            __lagrange_q,
            __lagrange_qdot,
            __lagrange_t,
        )
        .0
    }
    #[inline]
    fn energy_and_momenta(
        &self,
        __lagrange_q: &[f64; 3],
        __lagrange_qdot: &[f64; 3],
        __lagrange_t: f64,
    ) -> (f64, [f64; 3]) {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_i_perp: f64 = self.i_perp;
        let __lagrange_p_i_par: f64 = self.i_par;
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_g: f64 = self.g;
        let __lagrange_p_l: f64 = self.l;
        let ((__lagrange_x8, __lagrange_x9), __lagrange_x14, __lagrange_x31, __lagrange_x37): (
            (f64, f64),
            f64,
            f64,
            f64,
        ) = (
            __lagrange_q[0].sin_cos(),
            __lagrange_qdot[0] * __lagrange_qdot[0],
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_qdot[0] * __lagrange_p_i_perp,
        );
        let (__lagrange_x15, __lagrange_x22, __lagrange_x33, __lagrange_x98): (f64, f64, f64, f64) = (
            __lagrange_qdot[1] * __lagrange_x8,
            __lagrange_qdot[1] * __lagrange_x9,
            __lagrange_x31 * __lagrange_p_l,
            __lagrange_qdot[0] * __lagrange_x37,
        );
        let (__lagrange_x16, __lagrange_x23, __lagrange_x34, __lagrange_x40): (f64, f64, f64, f64) = (
            __lagrange_x15 * __lagrange_x15,
            __lagrange_qdot[2] + __lagrange_x22,
            __lagrange_x9 * __lagrange_x33,
            __lagrange_x8 * __lagrange_x15,
        );
        let (__lagrange_x17, __lagrange_x24, __lagrange_x42, __lagrange_x45, __lagrange_x51): (
            f64,
            f64,
            f64,
            f64,
            f64,
        ) = (
            __lagrange_x14 + __lagrange_x16,
            __lagrange_x23 * __lagrange_x23,
            __lagrange_p_i_perp * __lagrange_x40,
            __lagrange_x9 * __lagrange_x23,
            __lagrange_p_i_par * __lagrange_x23,
        );
        let (__lagrange_x18, __lagrange_x25, __lagrange_x47, __lagrange_x102): (
            f64,
            f64,
            f64,
            f64,
        ) = (
            __lagrange_p_i_perp * __lagrange_x17,
            __lagrange_p_i_par * __lagrange_x24,
            __lagrange_p_i_par * __lagrange_x45,
            __lagrange_qdot[2] * __lagrange_x51,
        );
        let (__lagrange_x27, __lagrange_x49): (f64, f64) = (
            __lagrange_x18 + __lagrange_x25,
            __lagrange_x42 + __lagrange_x47,
        );
        let (__lagrange_x28, __lagrange_x100): (f64, f64) =
            (0.5 * __lagrange_x27, __lagrange_qdot[1] * __lagrange_x49);
        let __lagrange_x97: f64 = __lagrange_x34 - __lagrange_x28;
        let __lagrange_x99: f64 = __lagrange_x97 + __lagrange_x98;
        let __lagrange_x101: f64 = __lagrange_x99 + __lagrange_x100;
        let __lagrange_x103: f64 = __lagrange_x101 + __lagrange_x102;
        (
            __lagrange_x103,
            [__lagrange_x37, __lagrange_x49, __lagrange_x51],
        )
    }
    #[inline(always)]
    fn accelerations_in<R: ::lagrange::__private::Real>(
        __lagrange_members: &[&Self],
        __lagrange_params: &mut ::std::vec::Vec<R>,
        __lagrange_q: &[R; 3],
        __lagrange_qdot: &[R; 3],
        __lagrange_t: R,
    ) -> ::core::option::Option<([R; 3], <R as ::lagrange::__private::Real>::Mask)> {
        ::core::option::Option::Some(__lagrange_HeavyTop_67f09420_kernels::accelerations::<R, _>(
            ::lagrange::__private::kernel_params(
                __lagrange_members,
                __lagrange_params,
                Self::__lagrange_params,
            )?,
            __lagrange_q,
            __lagrange_qdot,
            __lagrange_t,
            |__lagrange_x, __lagrange_ok| {
                ::core::option::Option::Some((__lagrange_x, __lagrange_ok))
            },
            |_, _| {
                (
                    [<R as ::lagrange::__private::Real>::NAN; 3],
                    <R as ::lagrange::__private::Real>::finite(
                        <R as ::lagrange::__private::Real>::NAN,
                    ),
                )
            },
        ))
    }
    #[inline(always)]
    fn series_in<R: ::lagrange::__private::eom::SeriesReal>(
        __lagrange_members: &[&Self],
        __lagrange_params: &mut ::std::vec::Vec<R>,
        __lagrange_t: R,
        __lagrange_out: &mut [[[R; 3]; 2]],
        __lagrange_buf: &mut ::lagrange::__private::taylor::SeriesBuf<R>,
    ) -> ::core::option::Option<
        ::core::result::Result<
            <R as ::lagrange::__private::Real>::Mask,
            ::lagrange::__private::DynamicsError,
        >,
    > {
        ::core::option::Option::Some(__lagrange_HeavyTop_67f09420_kernels::series::<R>(
            ::lagrange::__private::kernel_params(
                __lagrange_members,
                __lagrange_params,
                Self::__lagrange_params,
            )?,
            <Self as ::lagrange::__private::Lagrangian<3>>::COORDINATES,
            __lagrange_t,
            __lagrange_out,
            __lagrange_buf,
        ))
    }
    const COMPILED: ::lagrange::__private::Compiled = ::lagrange::__private::Compiled {
        lanes: true,
        not_analytic: ::core::option::Option::None,
        constrained: false,
    };
    const KERNEL_FIELDS: &'static [&'static str] = &["i_perp", "i_par", "m", "g", "l"];
}
#[doc(hidden)]
#[allow(
    unused_parens,
    unused_braces,
    non_snake_case,
    clippy::all,
    clippy::pedantic,
    clippy::nursery
)]
#[allow(unused_variables)]
mod __lagrange_HeavyTop_67f09420_kernels {
    #[doc = r" How many numbers `__lagrange_params` loads (the kernels' parameters)."]
    pub(super) const PARAMS: usize = 5;
    #[doc = r" q̈ from M q̈ = f (the straight-line LDLᵀ) and the lanes where every pivot test"]
    #[doc = r" passed and every value is finite, handed to `done`; where that declines, M (upper"]
    #[doc = r" triangle) and f to `careful` (formed only on that path)."]
    #[inline(always)]
    pub(super) fn accelerations<R: ::lagrange::__private::Real, O>(
        __lagrange_params: &[R; PARAMS],
        __lagrange_q: &[R; 3],
        __lagrange_qdot: &[R; 3],
        __lagrange_t: R,
        done: impl FnOnce([R; 3], <R as ::lagrange::__private::Real>::Mask) -> ::core::option::Option<O>,
        careful: impl FnOnce(&[[R; 3]; 3], &[R; 3]) -> O,
    ) -> O {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_i_perp: R = __lagrange_params[0];
        let __lagrange_p_i_par: R = __lagrange_params[1];
        let __lagrange_p_m: R = __lagrange_params[2];
        let __lagrange_p_g: R = __lagrange_params[3];
        let __lagrange_p_l: R = __lagrange_params[4];
        let ((__lagrange_x8, __lagrange_x9), __lagrange_x31): ((R, R), R) =
            (__lagrange_q[0].sin_cos(), __lagrange_p_m * __lagrange_p_g);
        let (
            __lagrange_x15,
            __lagrange_x22,
            __lagrange_x33,
            __lagrange_x53,
            __lagrange_x55,
            __lagrange_x58,
            __lagrange_x59,
            __lagrange_x60,
        ): (R, R, R, R, R, R, R, R) = (
            __lagrange_qdot[1] * __lagrange_x8,
            __lagrange_qdot[1] * __lagrange_x9,
            __lagrange_x31 * __lagrange_p_l,
            __lagrange_x8 * __lagrange_x8,
            __lagrange_x9 * __lagrange_x9,
            __lagrange_x9 * __lagrange_p_i_par,
            __lagrange_qdot[0] * __lagrange_x9,
            __lagrange_qdot[0] * __lagrange_x8,
        );
        let (__lagrange_x23, __lagrange_x54, __lagrange_x63, __lagrange_x65, __lagrange_x80): (
            R,
            R,
            R,
            R,
            R,
        ) = (
            __lagrange_qdot[2] + __lagrange_x22,
            __lagrange_p_i_perp * __lagrange_x53,
            __lagrange_qdot[1] * __lagrange_x60,
            __lagrange_x15 * __lagrange_x59,
            __lagrange_x15 * __lagrange_x22,
        );
        let (
            __lagrange_x57,
            __lagrange_x67,
            __lagrange_x77,
            __lagrange_x82,
            __lagrange_x85,
            __lagrange_x104,
        ): (R, R, R, R, R, R) = (
            <R as ::lagrange::__private::Real>::madd(
                __lagrange_p_i_par,
                __lagrange_x55,
                __lagrange_x54,
            ),
            __lagrange_p_i_perp * __lagrange_x65,
            __lagrange_p_i_par * __lagrange_x63,
            __lagrange_p_i_perp * __lagrange_x80,
            __lagrange_x15 * __lagrange_x23,
            __lagrange_p_i_par * __lagrange_x54,
        );
        let (__lagrange_x68, __lagrange_x72): (R, R) = (
            <R as ::core::convert::From<f64>>::from(2.0) * __lagrange_x67,
            <R as ::lagrange::__private::Real>::madd(
                __lagrange_x23,
                __lagrange_x60,
                __lagrange_x65,
            ),
        );
        let __lagrange_x91: R = <R as ::lagrange::__private::Real>::madd(
            -__lagrange_p_i_par,
            __lagrange_x85,
            __lagrange_x82,
        );
        let (__lagrange_x95, __lagrange_x96): (R, R) = (
            <R as ::lagrange::__private::Real>::madd(__lagrange_x8, __lagrange_x33, __lagrange_x91),
            <R as ::lagrange::__private::Real>::madd(
                __lagrange_p_i_par,
                __lagrange_x72,
                -__lagrange_x68,
            ),
        );
        let (__lagrange_qddot, __lagrange_ok) = '__lagrange_fast: {
            let __lagrange_ok = <R as ::lagrange::__private::Real>::EVERY_LANE;
            let __lagrange_ok = __lagrange_ok
                & <R as ::lagrange::__private::Real>::greater(
                    __lagrange_x57,
                    <R as ::core::convert::From<f64>>::from(0.0),
                );
            if <R as ::lagrange::__private::Real>::WIDTH == 1
                && !<R as ::lagrange::__private::Real>::all(__lagrange_ok)
            {
                break '__lagrange_fast (
                    [<R as ::lagrange::__private::Real>::NAN; 3],
                    __lagrange_ok,
                );
            }
            let __lagrange_det_1_2: R = __lagrange_x104;
            let __lagrange_ok = __lagrange_ok
                & <R as ::lagrange::__private::Real>::greater(
                    __lagrange_det_1_2,
                    <R as ::core::convert::From<f64>>::from(0.0),
                );
            if <R as ::lagrange::__private::Real>::WIDTH == 1
                && !<R as ::lagrange::__private::Real>::all(__lagrange_ok)
            {
                break '__lagrange_fast (
                    [<R as ::lagrange::__private::Real>::NAN; 3],
                    __lagrange_ok,
                );
            }
            let __lagrange_y_1: R = (__lagrange_p_i_par * __lagrange_x96
                - __lagrange_x58 * __lagrange_x77)
                / __lagrange_det_1_2;
            let __lagrange_y_2: R = (__lagrange_x57 * __lagrange_x77
                - __lagrange_x58 * __lagrange_x96)
                / __lagrange_det_1_2;
            let __lagrange_d_0: R = __lagrange_p_i_perp;
            let __lagrange_ok = __lagrange_ok
                & <R as ::lagrange::__private::Real>::greater(
                    __lagrange_d_0,
                    __lagrange_p_i_perp * ::lagrange::__private::linalg::ACCURATE_RELATIVE_PIVOT,
                );
            if <R as ::lagrange::__private::Real>::WIDTH == 1
                && !<R as ::lagrange::__private::Real>::all(__lagrange_ok)
            {
                break '__lagrange_fast (
                    [<R as ::lagrange::__private::Real>::NAN; 3],
                    __lagrange_ok,
                );
            }
            let __lagrange_y_0: R = __lagrange_x95;
            let __lagrange_y_0: R = __lagrange_y_0 / __lagrange_d_0;
            let __lagrange_ok = __lagrange_ok
                & <R as ::lagrange::__private::Real>::finite(
                    __lagrange_y_0 + __lagrange_y_1 + __lagrange_y_2,
                );
            (
                [__lagrange_y_0, __lagrange_y_1, __lagrange_y_2],
                __lagrange_ok,
            )
        };
        match done(__lagrange_qddot, __lagrange_ok) {
            ::core::option::Option::Some(o) => o,
            ::core::option::Option::None => careful(
                &[
                    [
                        __lagrange_p_i_perp,
                        <R as ::core::convert::From<f64>>::from(0.0),
                        <R as ::core::convert::From<f64>>::from(0.0),
                    ],
                    [
                        <R as ::core::convert::From<f64>>::from(0.0),
                        __lagrange_x57,
                        __lagrange_x58,
                    ],
                    [
                        <R as ::core::convert::From<f64>>::from(0.0),
                        <R as ::core::convert::From<f64>>::from(0.0),
                        __lagrange_p_i_par,
                    ],
                ],
                &[__lagrange_x95, __lagrange_x96, __lagrange_x77],
            ),
        }
    }
    #[doc = r" The Taylor coefficients of the motion through `out[0]` at t (see"]
    #[doc = r" `Lagrangian::series_in`), in the lanes of the mask."]
    #[inline(always)]
    pub(super) fn series<R: ::lagrange::__private::eom::SeriesReal>(
        __lagrange_params: &[R; PARAMS],
        __lagrange_names: [&'static str; 3],
        __lagrange_t: R,
        __lagrange_out: &mut [[[R; 3]; 2]],
        __lagrange_buf: &mut ::lagrange::__private::taylor::SeriesBuf<R>,
    ) -> ::core::result::Result<
        <R as ::lagrange::__private::Real>::Mask,
        ::lagrange::__private::DynamicsError,
    > {
        use ::lagrange::__private::taylor as __lagrange_rt;
        if __lagrange_out.len() < 2 {
            return ::core::result::Result::Ok(<R as ::lagrange::__private::Real>::EVERY_LANE);
        }
        let __lagrange_order = (__lagrange_out.len() - 1).min(__lagrange_rt::MAX_ORDER);
        let __lagrange_c: &mut [__lagrange_rt::RowOf<R>; 56] = __lagrange_buf.slots::<56>();
        let __lagrange_y0: [[R; 3]; 2] = __lagrange_out[0];
        let (__lagrange_q, __lagrange_qdot): (&[R; 3], &[R; 3]) =
            (&__lagrange_y0[0], &__lagrange_y0[1]);
        let __lagrange_p_i_perp: R = __lagrange_params[0];
        let __lagrange_p_i_par: R = __lagrange_params[1];
        let __lagrange_p_m: R = __lagrange_params[2];
        let __lagrange_p_g: R = __lagrange_params[3];
        let __lagrange_p_l: R = __lagrange_params[4];
        let ((__lagrange_x8, __lagrange_x9), __lagrange_x31, __lagrange_x109, __lagrange_x111): (
            (R, R),
            R,
            R,
            R,
        ) = (
            __lagrange_q[0].sin_cos(),
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_p_i_perp * __lagrange_p_i_par,
            __lagrange_p_i_par * __lagrange_p_i_par,
        );
        let (
            __lagrange_x15,
            __lagrange_x22,
            __lagrange_x33,
            __lagrange_x53,
            __lagrange_x55,
            __lagrange_x58,
            __lagrange_x59,
            __lagrange_x60,
            __lagrange_x79,
            __lagrange_x114,
            __lagrange_x117,
        ): (R, R, R, R, R, R, R, R, R, R, R) = (
            __lagrange_qdot[1] * __lagrange_x8,
            __lagrange_qdot[1] * __lagrange_x9,
            __lagrange_x31 * __lagrange_p_l,
            __lagrange_x8 * __lagrange_x8,
            __lagrange_x9 * __lagrange_x9,
            __lagrange_x9 * __lagrange_p_i_par,
            __lagrange_qdot[0] * __lagrange_x9,
            __lagrange_qdot[0] * __lagrange_x8,
            -__lagrange_x8,
            __lagrange_qdot[2] * __lagrange_x111,
            __lagrange_x8 * __lagrange_x109,
        );
        let (
            __lagrange_x23,
            __lagrange_x54,
            __lagrange_x56,
            __lagrange_x63,
            __lagrange_x65,
            __lagrange_x80,
            __lagrange_x93,
            __lagrange_x112,
        ): (R, R, R, R, R, R, R, R) = (
            __lagrange_qdot[2] + __lagrange_x22,
            __lagrange_p_i_perp * __lagrange_x53,
            __lagrange_p_i_par * __lagrange_x55,
            __lagrange_qdot[1] * __lagrange_x60,
            __lagrange_x15 * __lagrange_x59,
            __lagrange_x15 * __lagrange_x22,
            __lagrange_x8 * __lagrange_x33,
            <R as ::lagrange::__private::Real>::madd(
                <R as ::core::convert::From<f64>>::from(-2.0),
                __lagrange_x109,
                __lagrange_x111,
            ),
        );
        let (
            __lagrange_x57,
            __lagrange_x67,
            __lagrange_x69,
            __lagrange_x77,
            __lagrange_x82,
            __lagrange_x85,
            __lagrange_x104,
            __lagrange_x113,
        ): (R, R, R, R, R, R, R, R) = (
            __lagrange_x54 + __lagrange_x56,
            __lagrange_p_i_perp * __lagrange_x65,
            __lagrange_x23 * __lagrange_x60,
            __lagrange_p_i_par * __lagrange_x63,
            __lagrange_p_i_perp * __lagrange_x80,
            __lagrange_x15 * __lagrange_x23,
            __lagrange_p_i_par * __lagrange_x54,
            __lagrange_x22 * __lagrange_x112,
        );
        let (__lagrange_x68, __lagrange_x72, __lagrange_x89, __lagrange_x115): (R, R, R, R) = (
            <R as ::core::convert::From<f64>>::from(2.0) * __lagrange_x67,
            __lagrange_x65 + __lagrange_x69,
            __lagrange_p_i_par * __lagrange_x85,
            __lagrange_x113 + __lagrange_x114,
        );
        let (__lagrange_x74, __lagrange_x91, __lagrange_x116): (R, R, R) = (
            __lagrange_p_i_par * __lagrange_x72,
            __lagrange_x82 - __lagrange_x89,
            __lagrange_qdot[0] * __lagrange_x115,
        );
        let (__lagrange_x95, __lagrange_x96, __lagrange_x118): (R, R, R) = (
            __lagrange_x91 + __lagrange_x93,
            __lagrange_x74 - __lagrange_x68,
            __lagrange_x116 / __lagrange_x117,
        );
        let (__lagrange_x119, __lagrange_x122): (R, R) = (
            __lagrange_x58 * __lagrange_x118,
            __lagrange_x95 / __lagrange_p_i_perp,
        );
        let __lagrange_x120: R = __lagrange_x77 - __lagrange_x119;
        let __lagrange_x121: R = __lagrange_x120 / __lagrange_p_i_par;
        let __lagrange_r118: R = <R as ::core::convert::From<f64>>::from(1.0) / __lagrange_x117;
        let __lagrange_r121: R = <R as ::core::convert::From<f64>>::from(1.0) / __lagrange_p_i_par;
        let __lagrange_r122: R = <R as ::core::convert::From<f64>>::from(1.0) / __lagrange_p_i_perp;
        __lagrange_c[1][0] = __lagrange_q[0];
        __lagrange_c[2][0] = __lagrange_qdot[0];
        __lagrange_c[3][0] = __lagrange_qdot[1];
        __lagrange_c[4][0] = __lagrange_qdot[2];
        __lagrange_c[5][0] = __lagrange_x8;
        __lagrange_c[6][0] = __lagrange_x9;
        __lagrange_c[7][0] = __lagrange_p_i_perp;
        __lagrange_c[8][0] = <R as ::core::convert::From<f64>>::from(2.0);
        __lagrange_c[9][0] = __lagrange_x15;
        __lagrange_c[10][0] = __lagrange_p_i_par;
        __lagrange_c[11][0] = __lagrange_x22;
        __lagrange_c[12][0] = __lagrange_x23;
        __lagrange_c[13][0] = __lagrange_x33;
        __lagrange_c[18][0] = __lagrange_x57;
        __lagrange_c[19][0] = __lagrange_x58;
        __lagrange_c[20][0] = __lagrange_x59;
        __lagrange_c[21][0] = __lagrange_x60;
        __lagrange_c[29][0] = __lagrange_x77;
        __lagrange_c[30][0] = __lagrange_x79;
        __lagrange_c[37][0] = __lagrange_x95;
        __lagrange_c[38][0] = __lagrange_x96;
        __lagrange_c[39][0] = __lagrange_x104;
        __lagrange_c[40][0] = __lagrange_x109;
        __lagrange_c[41][0] = __lagrange_x111;
        __lagrange_c[42][0] = __lagrange_x112;
        __lagrange_c[45][0] = __lagrange_x115;
        __lagrange_c[47][0] = __lagrange_x117;
        __lagrange_c[48][0] = __lagrange_x118;
        __lagrange_c[51][0] = __lagrange_x121;
        __lagrange_c[52][0] = __lagrange_x122;
        __lagrange_c[0][1..=__lagrange_order].fill(<R as ::lagrange::__private::Real>::ZERO);
        let __lagrange_ok = __lagrange_rt::divisors_ok(__lagrange_c, [10, 39, 7]);
        if !<R as ::lagrange::__private::Real>::all(__lagrange_ok) {
            if let ::core::option::Option::Some(__lagrange_e) =
                <R as ::lagrange::__private::eom::SeriesReal>::declined(
                    &__lagrange_rt::order0_matrix(
                        __lagrange_c,
                        [[7, 0, 0], [0, 18, 19], [0, 0, 10]],
                    ),
                    &__lagrange_rt::order0_column(__lagrange_c, [37, 38, 29]),
                    __lagrange_names,
                    __lagrange_q,
                    __lagrange_qdot,
                    __lagrange_t,
                )
            {
                return ::core::result::Result::Err(__lagrange_e);
            }
        }
        let mut __lagrange_a: [R; 3];
        for __lagrange_k in 0..__lagrange_order {
            if __lagrange_k > 0 {
                __lagrange_c[1][__lagrange_k] = __lagrange_out[__lagrange_k][0][0];
                __lagrange_c[2][__lagrange_k] = __lagrange_out[__lagrange_k][1][0];
                __lagrange_c[3][__lagrange_k] = __lagrange_out[__lagrange_k][1][1];
                __lagrange_c[4][__lagrange_k] = __lagrange_out[__lagrange_k][1][2];
                __lagrange_rt::deriv_at(__lagrange_c, 5, 1, 6, __lagrange_k);
                __lagrange_rt::deriv_at(__lagrange_c, 6, 1, 30, __lagrange_k);
                __lagrange_rt::mul_at(__lagrange_c, 9, 5, 3, __lagrange_k);
                __lagrange_rt::mul_at(__lagrange_c, 11, 6, 3, __lagrange_k);
                __lagrange_c[12][__lagrange_k] =
                    __lagrange_c[4][__lagrange_k] + __lagrange_c[11][__lagrange_k];
                __lagrange_c[19][__lagrange_k] = __lagrange_p_i_par * __lagrange_c[6][__lagrange_k];
                __lagrange_rt::mul_at(__lagrange_c, 21, 5, 2, __lagrange_k);
                __lagrange_rt::mul_at(__lagrange_c, 22, 21, 3, __lagrange_k);
                let __lagrange_t77: R = __lagrange_p_i_par * __lagrange_c[22][__lagrange_k];
                __lagrange_c[30][__lagrange_k] = -__lagrange_c[5][__lagrange_k];
                __lagrange_rt::mul_at(__lagrange_c, 31, 9, 11, __lagrange_k);
                let __lagrange_t82: R = __lagrange_p_i_perp * __lagrange_c[31][__lagrange_k];
                __lagrange_rt::mul_at(__lagrange_c, 33, 12, 9, __lagrange_k);
                let __lagrange_t89: R = __lagrange_p_i_par * __lagrange_c[33][__lagrange_k];
                let __lagrange_t91: R = __lagrange_t82 - __lagrange_t89;
                let __lagrange_t93: R = __lagrange_x33 * __lagrange_c[5][__lagrange_k];
                let __lagrange_t95: R = __lagrange_t91 + __lagrange_t93;
                let __lagrange_t113: R = __lagrange_x112 * __lagrange_c[11][__lagrange_k];
                let __lagrange_t114: R = __lagrange_x111 * __lagrange_c[4][__lagrange_k];
                __lagrange_c[45][__lagrange_k] = __lagrange_t113 + __lagrange_t114;
                __lagrange_rt::mul_at(__lagrange_c, 46, 45, 2, __lagrange_k);
                __lagrange_c[47][__lagrange_k] = __lagrange_x109 * __lagrange_c[5][__lagrange_k];
                __lagrange_rt::div_at(
                    __lagrange_c,
                    48,
                    __lagrange_c[46][__lagrange_k],
                    47,
                    __lagrange_r118,
                    __lagrange_k,
                );
                __lagrange_rt::mul_at(__lagrange_c, 49, 48, 19, __lagrange_k);
                let __lagrange_t120: R = __lagrange_t77 - __lagrange_c[49][__lagrange_k];
                __lagrange_c[51][__lagrange_k] = __lagrange_t120 * __lagrange_r121;
                __lagrange_c[52][__lagrange_k] = __lagrange_t95 * __lagrange_r122;
            }
            __lagrange_a = [
                __lagrange_c[52][__lagrange_k],
                __lagrange_c[48][__lagrange_k],
                __lagrange_c[51][__lagrange_k],
            ];
            __lagrange_rt::next_order(__lagrange_out, __lagrange_a, __lagrange_k);
            if __lagrange_k + 1 < __lagrange_order {
                __lagrange_rt::muls_mid_at(
                    __lagrange_c,
                    [9, 11, 21, 22, 31],
                    [5, 6, 5, 21, 9],
                    [3, 3, 2, 3, 11],
                    __lagrange_k + 1,
                );
                __lagrange_rt::muls_mid_at(
                    __lagrange_c,
                    [33, 46, 48, 49],
                    [12, 45, 47, 48],
                    [9, 2, 48, 19],
                    __lagrange_k + 1,
                );
                __lagrange_rt::derivs_mid_at(
                    __lagrange_c,
                    [5, 6],
                    [1, 1],
                    [6, 30],
                    __lagrange_k + 1,
                );
            }
        }
        for __lagrange_x in &mut __lagrange_out[__lagrange_order + 1..] {
            *__lagrange_x = [[<R as ::lagrange::__private::Real>::NAN; 3]; 2];
        }
        ::core::result::Result::Ok(__lagrange_ok)
    }
}
#[doc = "# Equations of motion\n\nDerived at compile time by `#[lagrangian]` (d/dt ∂L/∂q\u{307} = ∂L/∂q, one line per coordinate):\n\n```text\ntheta: i_perp θ\u{308} = −i_par φ\u{307} ψ\u{307} sin(θ) + (i_perp − i_par) φ\u{307}² sin(θ) cos(θ) + m g l sin(θ)\nphi: i_perp φ\u{308} sin²(θ) + i_par φ\u{308} cos²(θ) + i_par ψ\u{308} cos(θ) = 2 (i_par − i_perp) θ\u{307} φ\u{307} sin(θ) cos(θ) + i_par θ\u{307} ψ\u{307} sin(θ)\npsi: i_par φ\u{308} cos(θ) + i_par ψ\u{308} = i_par θ\u{307} φ\u{307} sin(θ)\n```\n"]
impl HeavyTop {
    #[doc = "The Euler–Lagrange equations, derived at compile time by `#[lagrangian]`: one line per coordinate, `Σₖ Mᵢₖ q\u{308}ₖ = fᵢ` (accelerations on the left).\n\n```text\ntheta: i_perp θ\u{308} = −i_par φ\u{307} ψ\u{307} sin(θ) + (i_perp − i_par) φ\u{307}² sin(θ) cos(θ) + m g l sin(θ)\nphi: i_perp φ\u{308} sin²(θ) + i_par φ\u{308} cos²(θ) + i_par ψ\u{308} cos(θ) = 2 (i_par − i_perp) θ\u{307} φ\u{307} sin(θ) cos(θ) + i_par θ\u{307} ψ\u{307} sin(θ)\npsi: i_par φ\u{308} cos(θ) + i_par ψ\u{308} = i_par θ\u{307} φ\u{307} sin(θ)\n```"]
    pub const EQUATIONS : & 'static str = "theta: i_perp θ\u{308} = −i_par φ\u{307} ψ\u{307} sin(θ) + (i_perp − i_par) φ\u{307}² sin(θ) cos(θ) + m g l sin(θ)\nphi: i_perp φ\u{308} sin²(θ) + i_par φ\u{308} cos²(θ) + i_par ψ\u{308} cos(θ) = 2 (i_par − i_perp) θ\u{307} φ\u{307} sin(θ) cos(θ) + i_par θ\u{307} ψ\u{307} sin(θ)\npsi: i_par φ\u{308} cos(θ) + i_par ψ\u{308} = i_par θ\u{307} φ\u{307} sin(θ)" ;
    #[doc = "The Euler–Lagrange equations in LaTeX, one line per coordinate (the same equations as `EQUATIONS`)."]
    pub const EQUATIONS_LATEX : & 'static str = "i_{\\mathrm{perp}} \\ddot{\\theta} = -i_{\\mathrm{par}} \\dot{\\phi} \\dot{\\psi} \\sin\\left(\\theta\\right) + \\left(i_{\\mathrm{perp}} - i_{\\mathrm{par}}\\right) \\dot{\\phi}^{2} \\sin\\left(\\theta\\right) \\cos\\left(\\theta\\right) + m g l \\sin\\left(\\theta\\right)\ni_{\\mathrm{perp}} \\ddot{\\phi} \\sin^{2}\\left(\\theta\\right) + i_{\\mathrm{par}} \\ddot{\\phi} \\cos^{2}\\left(\\theta\\right) + i_{\\mathrm{par}} \\ddot{\\psi} \\cos\\left(\\theta\\right) = 2 \\left(i_{\\mathrm{par}} - i_{\\mathrm{perp}}\\right) \\dot{\\theta} \\dot{\\phi} \\sin\\left(\\theta\\right) \\cos\\left(\\theta\\right) + i_{\\mathrm{par}} \\dot{\\theta} \\dot{\\psi} \\sin\\left(\\theta\\right)\ni_{\\mathrm{par}} \\ddot{\\phi} \\cos\\left(\\theta\\right) + i_{\\mathrm{par}} \\ddot{\\psi} = i_{\\mathrm{par}} \\dot{\\theta} \\dot{\\phi} \\sin\\left(\\theta\\right)" ;
    #[doc = r" The parameters of the generic kernels, loaded from `self`."]
    #[doc(hidden)]
    #[inline(always)]
    fn __lagrange_params(&self) -> [f64; 5] {
        let __lagrange_p_i_perp: f64 = self.i_perp;
        let __lagrange_p_i_par: f64 = self.i_par;
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_g: f64 = self.g;
        let __lagrange_p_l: f64 = self.l;
        [
            __lagrange_p_i_perp,
            __lagrange_p_i_par,
            __lagrange_p_m,
            __lagrange_p_g,
            __lagrange_p_l,
        ]
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
    println!("EQUATIONS:\n{}", HeavyTop::EQUATIONS);
    match top.accelerations(&q, &qdot, 0.0) {
        Ok(a) => println!("q̈ at θ = 1, φ̇ = −0.5, ψ̇ = 8: {a:?}"),
        Err(e) => println!("error: {e}"),
    }
}
