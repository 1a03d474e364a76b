//! What `#[lagrangian]` writes for the smallest system: a plane pendulum, one coordinate.
//!
//! The user writes:
//!
//! ```ignore
//! #[lagrangian]
//! impl Pendulum {
//!     /// A plane pendulum: a point mass m on a massless rod of length l.
//!     fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
//!         0.5 * self.m * self.l * self.l * theta_dot * theta_dot + self.m * self.g * self.l * theta.cos()
//!     }
//! }
//! ```
//!
//! and the macro emits the code between the markers below (kept in sync by a test in
//! `lagrange-macros`; regenerate with `UPDATE_EXPANDED=1 cargo test -p lagrange-macros expanded`).
//! A one-coordinate system shows every generated method at its shortest: the body as written
//! over any `Scalar` (`lagrangian`), the accelerations from M = m l² and f = −m g l sin θ with the
//! pivot test and the fallback, the pieces, the power, the energy and momenta, the lanes code for
//! ensembles and the Taylor series (order by order, each kernel after what it reads). The heavy
//! top's expansion, with a 2×2 block solved by Cramer's rule, is `heavy_top_expanded.rs`.
//!
//! Run it: `cargo run --example pendulum_expanded`.

use lagrange::prelude::*;

/// A plane pendulum.
#[derive(Debug, Clone)]
pub struct Pendulum {
    /// Mass of the bob.
    pub m: f64,
    /// Gravitational acceleration.
    pub g: f64,
    /// Length of the rod.
    pub l: f64,
}

// ---- BEGIN GENERATED (do not edit) ----
#[automatically_derived]
impl ::lagrange::__private::Lagrangian<1> for Pendulum {
    const COORDINATES: [&'static str; 1] = ["theta"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    #[doc = " A plane pendulum: a point mass m on a massless rod of length l."]
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
        __lagrange_q: &[Scalar; 1],
        __lagrange_qdot: &[Scalar; 1],
        _: Scalar,
    ) -> Scalar {
        let theta = __lagrange_q[0];
        let theta_dot = __lagrange_qdot[0];
        ::lagrange::__private::ConstMul::const_mul(0.5 * self.m * self.l * self.l, theta_dot)
            * theta_dot
            + ::lagrange::__private::ConstMul::const_mul(self.m * self.g * self.l, theta.cos())
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
        __lagrange_q: &[f64; 1],
        __lagrange_qdot: &[f64; 1],
        __lagrange_t: f64,
    ) -> ::core::result::Result<[f64; 1], ::lagrange::__private::DynamicsError> {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_l: f64 = self.l;
        let __lagrange_p_g: f64 = self.g;
        let (__lagrange_x8, __lagrange_x17, __lagrange_x24): (f64, f64, f64) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].sin(),
        );
        let (__lagrange_x10, __lagrange_x18): (f64, f64) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
        );
        let __lagrange_x26: f64 = __lagrange_x18 * __lagrange_x24;
        let __lagrange_x27: f64 = -__lagrange_x26;
        let __lagrange_fast: ::core::option::Option<[f64; 1]> = '__lagrange_fast: {
            let __lagrange_d_0: f64 = __lagrange_x10;
            if !(__lagrange_d_0
                > ::lagrange::__private::linalg::ACCURATE_RELATIVE_PIVOT * __lagrange_x10)
            {
                break '__lagrange_fast ::core::option::Option::None;
            }
            let __lagrange_y_0: f64 = __lagrange_x27;
            let __lagrange_y_0: f64 = __lagrange_y_0 / __lagrange_d_0;
            let __lagrange_qddot = [__lagrange_y_0];
            if (__lagrange_y_0).is_finite() {
                ::core::option::Option::Some(__lagrange_qddot)
            } else {
                ::core::option::Option::None
            }
        };
        match __lagrange_fast {
            ::core::option::Option::Some(__lagrange_qddot) => {
                ::core::result::Result::Ok(__lagrange_qddot)
            }
            ::core::option::Option::None => ::lagrange::__private::solve_mass_matrix(
                &[[__lagrange_x10]],
                &[__lagrange_x27],
                <Self as ::lagrange::__private::Lagrangian<1>>::COORDINATES,
                __lagrange_q,
                __lagrange_qdot,
                __lagrange_t,
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
    #[inline(always)]
    fn pieces(
        &self,
        __lagrange_q: &[f64; 1],
        __lagrange_qdot: &[f64; 1],
        __lagrange_t: f64,
    ) -> ::lagrange::__private::eom::Pieces<1> {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_l: f64 = self.l;
        let __lagrange_p_g: f64 = self.g;
        let (__lagrange_x8, __lagrange_x17, __lagrange_x24): (f64, f64, f64) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].sin(),
        );
        let (__lagrange_x10, __lagrange_x18): (f64, f64) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
        );
        let __lagrange_x26: f64 = __lagrange_x18 * __lagrange_x24;
        let __lagrange_x27: f64 = -__lagrange_x26;
        ::lagrange::__private::eom::Pieces::new([[__lagrange_x10]], [__lagrange_x27])
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
    fn power(&self, __lagrange_q: &[f64; 1], __lagrange_qdot: &[f64; 1], __lagrange_t: f64) -> f64 {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        0.0
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
        __lagrange_q: &[f64; 1],
        __lagrange_qdot: &[f64; 1],
        __lagrange_t: f64,
    ) -> ::lagrange::__private::SMatrix<f64, 1, 1> {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_l: f64 = self.l;
        let __lagrange_x8: f64 = __lagrange_p_m * __lagrange_p_l;
        let __lagrange_x10: f64 = __lagrange_p_l * __lagrange_x8;
        ::lagrange::__private::SMatrix::<f64, 1, 1>::from_row_slice(&[__lagrange_x10])
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
    fn momenta(
        &self,
        __lagrange_q: &[f64; 1],
        __lagrange_qdot: &[f64; 1],
        __lagrange_t: f64,
    ) -> [f64; 1] {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_l: f64 = self.l;
        let __lagrange_x8: f64 = __lagrange_p_m * __lagrange_p_l;
        let __lagrange_x10: f64 = __lagrange_p_l * __lagrange_x8;
        let __lagrange_x12: f64 = __lagrange_qdot[0] * __lagrange_x10;
        [__lagrange_x12]
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
    fn energy(
        &self,
        __lagrange_q: &[f64; 1],
        __lagrange_qdot: &[f64; 1],
        __lagrange_t: f64,
    ) -> f64 {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_l: f64 = self.l;
        let __lagrange_p_g: f64 = self.g;
        let (__lagrange_x8, __lagrange_x17, __lagrange_x19): (f64, f64, f64) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].cos(),
        );
        let (__lagrange_x10, __lagrange_x18): (f64, f64) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
        );
        let (__lagrange_x12, __lagrange_x20): (f64, f64) = (
            __lagrange_qdot[0] * __lagrange_x10,
            __lagrange_x18 * __lagrange_x19,
        );
        let __lagrange_x14: f64 = __lagrange_qdot[0] * __lagrange_x12;
        let __lagrange_x15: f64 = 0.5 * __lagrange_x14;
        let __lagrange_x21: f64 = __lagrange_x15 + __lagrange_x20;
        let __lagrange_x29: f64 = __lagrange_x14 - __lagrange_x21;
        __lagrange_x29
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
    fn energy_and_momenta(
        &self,
        __lagrange_q: &[f64; 1],
        __lagrange_qdot: &[f64; 1],
        __lagrange_t: f64,
    ) -> (f64, [f64; 1]) {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_l: f64 = self.l;
        let __lagrange_p_g: f64 = self.g;
        let (__lagrange_x8, __lagrange_x17, __lagrange_x19): (f64, f64, f64) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].cos(),
        );
        let (__lagrange_x10, __lagrange_x18): (f64, f64) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
        );
        let (__lagrange_x12, __lagrange_x20): (f64, f64) = (
            __lagrange_qdot[0] * __lagrange_x10,
            __lagrange_x18 * __lagrange_x19,
        );
        let __lagrange_x14: f64 = __lagrange_qdot[0] * __lagrange_x12;
        let __lagrange_x15: f64 = 0.5 * __lagrange_x14;
        let __lagrange_x21: f64 = __lagrange_x15 + __lagrange_x20;
        let __lagrange_x29: f64 = __lagrange_x14 - __lagrange_x21;
        (__lagrange_x29, [__lagrange_x12])
    }
    const LANE_PARAMS: usize = 3;
    const VECTORIZED_LANES: bool = true;
    #[allow(
        unused_variables,
        unused_parens,
        non_snake_case,
        clippy::all,
        clippy::pedantic,
        clippy::nursery
    )]
    #[inline]
    fn lane_params(&self, __lagrange_out: &mut [f64]) {
        if let ::core::option::Option::Some(__lagrange_out) = __lagrange_out.get_mut(..3) {
            let __lagrange_p_m: f64 = self.m;
            let __lagrange_p_l: f64 = self.l;
            let __lagrange_p_g: f64 = self.g;
            __lagrange_out[0] = __lagrange_p_m;
            __lagrange_out[1] = __lagrange_p_l;
            __lagrange_out[2] = __lagrange_p_g;
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
    #[inline(always)]
    fn accelerations_lanes<const __LAGRANGE_W: usize>(
        __lagrange_members: &[&Self; __LAGRANGE_W],
        __lagrange_params: &[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>],
        __lagrange_q: &[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 1],
        __lagrange_qdot: &[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 1],
        __lagrange_t: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
    ) -> [::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 1]
    where
        Self: ::core::marker::Sized,
    {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_params: &[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 3] =
            match <&[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 3]>::try_from(
                __lagrange_params,
            ) {
                ::core::result::Result::Ok(__lagrange_params) => __lagrange_params,
                ::core::result::Result::Err(_) => {
                    return ::lagrange::__private::lagrangian_lanes_one_by_one(
                        __lagrange_members,
                        __lagrange_q,
                        __lagrange_qdot,
                        __lagrange_t,
                    )
                }
            };
        let __lagrange_p_m: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
            __lagrange_params[0];
        let __lagrange_p_l: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
            __lagrange_params[1];
        let __lagrange_p_g: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
            __lagrange_params[2];
        let (__lagrange_x8, __lagrange_x17, __lagrange_x24): (
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
        ) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].sin(),
        );
        let (__lagrange_x10, __lagrange_x18): (
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
        ) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
        );
        let __lagrange_x26: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
            __lagrange_x18 * __lagrange_x24;
        let __lagrange_x27: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> = -__lagrange_x26;
        let (__lagrange_qddot, __lagrange_ok) = {
            let __lagrange_ok = ::lagrange::__private::lanes::Mask::<__LAGRANGE_W>::splat(true);
            let __lagrange_d_0: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
                <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x10);
            let __lagrange_ok = __lagrange_ok
                & <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_d_0)
                    .gt(::lagrange::__private::linalg::ACCURATE_RELATIVE_PIVOT * __lagrange_x10);
            let __lagrange_y_0: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
                <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x27);
            let __lagrange_y_0: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
                __lagrange_y_0 / __lagrange_d_0;
            let __lagrange_ok = __lagrange_ok
                & <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_y_0)
                    .finite();
            ([__lagrange_y_0], __lagrange_ok)
        };
        if __lagrange_ok.all() {
            __lagrange_qddot
        } else {
            ::lagrange::__private::lagrangian_lanes_patch(
                __lagrange_members,
                __lagrange_q,
                __lagrange_qdot,
                __lagrange_t,
                __lagrange_qddot,
                __lagrange_ok,
            )
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
    fn taylor_series(
        &self,
        __lagrange_t: f64,
        __lagrange_out: &mut [[[f64; 1]; 2]],
        __lagrange_buf: &mut ::lagrange::__private::taylor::TaylorBuf,
    ) -> ::core::option::Option<::core::result::Result<(), ::lagrange::__private::DynamicsError>>
    {
        if __lagrange_out.len() < 2 {
            return ::core::option::Option::Some(::core::result::Result::Ok(()));
        }
        let __lagrange_order =
            (__lagrange_out.len() - 1).min(::lagrange::__private::taylor::MAX_ORDER);
        let __lagrange_c: &mut [::lagrange::__private::taylor::Row; 10] =
            __lagrange_buf.slots::<10>();
        let __lagrange_y0: [[f64; 1]; 2] = __lagrange_out[0];
        let (__lagrange_q, __lagrange_qdot): (&[f64; 1], &[f64; 1]) =
            (&__lagrange_y0[0], &__lagrange_y0[1]);
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_l: f64 = self.l;
        let __lagrange_p_g: f64 = self.g;
        let (__lagrange_x8, __lagrange_x17, (__lagrange_x24, __lagrange_x19)): (
            f64,
            f64,
            (f64, f64),
        ) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].sin_cos(),
        );
        let (__lagrange_x10, __lagrange_x18, __lagrange_x25): (f64, f64, f64) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
            -__lagrange_x24,
        );
        let __lagrange_x26: f64 = __lagrange_x18 * __lagrange_x24;
        let __lagrange_x27: f64 = -__lagrange_x26;
        __lagrange_c[1][0] = __lagrange_q[0];
        __lagrange_c[2][0] = __lagrange_x10;
        __lagrange_c[3][0] = __lagrange_x18;
        __lagrange_c[4][0] = __lagrange_x19;
        __lagrange_c[5][0] = __lagrange_x24;
        __lagrange_c[6][0] = __lagrange_x25;
        __lagrange_c[7][0] = __lagrange_x26;
        __lagrange_c[8][0] = __lagrange_x27;
        __lagrange_c[0][1..=__lagrange_order].fill(0.0);
        __lagrange_c[2][1..=__lagrange_order].fill(0.0);
        __lagrange_c[3][1..=__lagrange_order].fill(0.0);
        let __lagrange_factor = match ::lagrange::__private::eom::Factor::<1>::new(
            &[[__lagrange_c[2][0]]],
            &[__lagrange_c[8][0]],
            <Self as ::lagrange::__private::Lagrangian<1>>::COORDINATES,
            __lagrange_q,
            __lagrange_qdot,
            __lagrange_t,
        ) {
            ::core::result::Result::Ok(__lagrange_f) => __lagrange_f,
            ::core::result::Result::Err(__lagrange_e) => {
                return ::core::option::Option::Some(::core::result::Result::Err(__lagrange_e));
            }
        };
        for __lagrange_k in 0..__lagrange_order {
            let __lagrange_b: [f64; 1] = if __lagrange_k == 0 {
                [__lagrange_c[8][0]]
            } else {
                __lagrange_c[1][__lagrange_k] = __lagrange_out[__lagrange_k][0][0];
                __lagrange_c[4][__lagrange_k] = ::lagrange::__private::taylor::deriv(
                    &__lagrange_c[1],
                    &__lagrange_c[6],
                    __lagrange_k,
                );
                __lagrange_c[5][__lagrange_k] = ::lagrange::__private::taylor::deriv(
                    &__lagrange_c[1],
                    &__lagrange_c[4],
                    __lagrange_k,
                );
                __lagrange_c[6][__lagrange_k] = -__lagrange_c[5][__lagrange_k];
                __lagrange_c[7][__lagrange_k] = __lagrange_x18 * __lagrange_c[5][__lagrange_k];
                __lagrange_c[8][__lagrange_k] = -__lagrange_c[7][__lagrange_k];
                [__lagrange_c[8][__lagrange_k]]
            };
            let __lagrange_a = match __lagrange_factor.solve(
                &__lagrange_b,
                <Self as ::lagrange::__private::Lagrangian<1>>::COORDINATES,
                __lagrange_q,
                __lagrange_qdot,
                __lagrange_t,
            ) {
                ::core::result::Result::Ok(__lagrange_a) => __lagrange_a,
                ::core::result::Result::Err(__lagrange_e) => {
                    return ::core::option::Option::Some(::core::result::Result::Err(__lagrange_e));
                }
            };
            let __lagrange_r = 1.0 / (__lagrange_k + 1) as f64;
            __lagrange_c[9][__lagrange_k] = __lagrange_a[0];
            __lagrange_out[__lagrange_k + 1][0][0] =
                __lagrange_out[__lagrange_k][1][0] * __lagrange_r;
            __lagrange_out[__lagrange_k + 1][1][0] = __lagrange_a[0] * __lagrange_r;
        }
        for __lagrange_x in &mut __lagrange_out[__lagrange_order + 1..] {
            *__lagrange_x = [[f64::NAN; 1]; 2];
        }
        ::core::option::Option::Some(::core::result::Result::Ok(()))
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
    fn taylor_series_lanes<const __LAGRANGE_W: usize>(
        __lagrange_members: &[&Self; __LAGRANGE_W],
        __lagrange_params: &[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>],
        __lagrange_t: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
        __lagrange_out: &mut [[[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 1]; 2]],
        __lagrange_buf: &mut ::lagrange::__private::taylor::SeriesBuf<
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
        >,
    ) -> ::core::option::Option<::lagrange::__private::lanes::Mask<__LAGRANGE_W>>
    where
        Self: ::core::marker::Sized,
    {
        if __lagrange_out.len() < 2 {
            return ::core::option::Option::Some(
                ::lagrange::__private::lanes::Mask::<__LAGRANGE_W>::splat(true),
            );
        }
        let __lagrange_params: &[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 3] =
            match <&[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 3]>::try_from(
                __lagrange_params,
            ) {
                ::core::result::Result::Ok(__lagrange_params) => __lagrange_params,
                ::core::result::Result::Err(_) => return ::core::option::Option::None,
            };
        let __lagrange_order =
            (__lagrange_out.len() - 1).min(::lagrange::__private::taylor::MAX_ORDER);
        let __lagrange_c: &mut [::lagrange::__private::taylor::RowOf<
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
        >; 10] = __lagrange_buf.slots::<10>();
        let __lagrange_y0: [[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 1]; 2] =
            __lagrange_out[0];
        let (__lagrange_q, __lagrange_qdot): (
            &[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 1],
            &[::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 1],
        ) = (&__lagrange_y0[0], &__lagrange_y0[1]);
        let __lagrange_p_m: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
            __lagrange_params[0];
        let __lagrange_p_l: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
            __lagrange_params[1];
        let __lagrange_p_g: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
            __lagrange_params[2];
        let (__lagrange_x8, __lagrange_x17, (__lagrange_x24, __lagrange_x19)): (
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
            (
                ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
                ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
            ),
        ) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].sin_cos(),
        );
        let (__lagrange_x10, __lagrange_x18, __lagrange_x25): (
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
            ::lagrange::__private::lanes::Lanes<__LAGRANGE_W>,
        ) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
            -__lagrange_x24,
        );
        let __lagrange_x26: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> =
            __lagrange_x18 * __lagrange_x24;
        let __lagrange_x27: ::lagrange::__private::lanes::Lanes<__LAGRANGE_W> = -__lagrange_x26;
        __lagrange_c[1][0] =
            <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_q[0]);
        __lagrange_c[2][0] =
            <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x10);
        __lagrange_c[3][0] =
            <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x18);
        __lagrange_c[4][0] =
            <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x19);
        __lagrange_c[5][0] =
            <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x24);
        __lagrange_c[6][0] =
            <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x25);
        __lagrange_c[7][0] =
            <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x26);
        __lagrange_c[8][0] =
            <::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::from(__lagrange_x27);
        __lagrange_c[0][1..=__lagrange_order]
            .fill(<::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::ZERO);
        __lagrange_c[2][1..=__lagrange_order]
            .fill(<::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::ZERO);
        __lagrange_c[3][1..=__lagrange_order]
            .fill(<::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::ZERO);
        let (__lagrange_factor, __lagrange_ok) = ::lagrange::__private::eom::FactorLanes::<
            1,
            __LAGRANGE_W,
        >::new(&[[__lagrange_c[2][0]]]);
        for __lagrange_k in 0..__lagrange_order {
            let __lagrange_b: [::lagrange::__private::lanes::Lanes<__LAGRANGE_W>; 1] =
                if __lagrange_k == 0 {
                    [__lagrange_c[8][0]]
                } else {
                    __lagrange_c[1][__lagrange_k] = __lagrange_out[__lagrange_k][0][0];
                    __lagrange_c[4][__lagrange_k] = ::lagrange::__private::taylor::deriv(
                        &__lagrange_c[1],
                        &__lagrange_c[6],
                        __lagrange_k,
                    );
                    __lagrange_c[5][__lagrange_k] = ::lagrange::__private::taylor::deriv(
                        &__lagrange_c[1],
                        &__lagrange_c[4],
                        __lagrange_k,
                    );
                    __lagrange_c[6][__lagrange_k] = -__lagrange_c[5][__lagrange_k];
                    __lagrange_c[7][__lagrange_k] = __lagrange_x18 * __lagrange_c[5][__lagrange_k];
                    __lagrange_c[8][__lagrange_k] = -__lagrange_c[7][__lagrange_k];
                    [__lagrange_c[8][__lagrange_k]]
                };
            let __lagrange_a = __lagrange_factor.solve(&__lagrange_b);
            let __lagrange_r = 1.0 / (__lagrange_k + 1) as f64;
            __lagrange_c[9][__lagrange_k] = __lagrange_a[0];
            __lagrange_out[__lagrange_k + 1][0][0] =
                __lagrange_out[__lagrange_k][1][0] * __lagrange_r;
            __lagrange_out[__lagrange_k + 1][1][0] = __lagrange_a[0] * __lagrange_r;
        }
        for __lagrange_x in &mut __lagrange_out[__lagrange_order + 1..] {
            *__lagrange_x = [[<::lagrange::__private::lanes::Lanes<__LAGRANGE_W>>::NAN; 1]; 2];
        }
        ::core::option::Option::Some(__lagrange_ok)
    }
}
#[doc = "# Equations of motion\n\nDerived at compile time by `#[lagrangian]` (d/dt ∂L/∂q\u{307} = ∂L/∂q, one line per coordinate):\n\n```text\ntheta: m l² θ\u{308} = −m l g sin(θ)\n```\n"]
impl Pendulum {
    #[doc = "The Euler–Lagrange equations, derived at compile time by `#[lagrangian]`: one line per coordinate, `Σₖ Mᵢₖ q\u{308}ₖ = fᵢ` (accelerations on the left).\n\n```text\ntheta: m l² θ\u{308} = −m l g sin(θ)\n```"]
    pub const EQUATIONS: &'static str = "theta: m l² θ\u{308} = −m l g sin(θ)";
    #[doc = "The Euler–Lagrange equations in LaTeX, one line per coordinate (the same equations as `EQUATIONS`)."]
    pub const EQUATIONS_LATEX: &'static str =
        "m l^{2} \\ddot{\\theta} = -m l g \\sin\\left(\\theta\\right)";
}
// ---- END GENERATED ----

fn main() {
    let p = Pendulum {
        m: 2.0,
        g: 9.81,
        l: 0.5,
    };
    println!("EQUATIONS:\n{}", Pendulum::EQUATIONS);
    let theta: f64 = 0.3;
    match p.accelerations(&[theta], &[0.0], 0.0) {
        Ok(a) => {
            // θ̈ = −(g/l) sin θ.
            let exact = -p.g / p.l * theta.sin();
            assert!((a[0] - exact).abs() < 1e-14, "{} against {exact}", a[0]);
            println!("θ̈ at θ = 0.3: {} (−(g/l) sin θ = {exact})", a[0]);
        }
        Err(e) => println!("error: {e}"),
    }
}
