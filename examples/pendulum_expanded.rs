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
#[allow(
    unused_parens,
    unused_braces,
    non_snake_case,
    clippy::all,
    clippy::pedantic,
    clippy::nursery
)]
impl ::lagrange::__private::Lagrangian<1> for Pendulum {
    const COORDINATES: [&'static str; 1] = ["theta"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    #[doc = " A plane pendulum: a point mass m on a massless rod of length l."]
    #[inline]
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
    #[inline(always)]
    fn accelerations(
        &self,
        __lagrange_q: &[f64; 1],
        __lagrange_qdot: &[f64; 1],
        __lagrange_t: f64,
    ) -> ::core::result::Result<[f64; 1], ::lagrange::__private::DynamicsError> {
        __lagrange_Pendulum_2105f53a_kernels::accelerations::<f64, _>(
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
                    <Self as ::lagrange::__private::Lagrangian<1>>::COORDINATES,
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
    #[inline]
    fn power(&self, __lagrange_q: &[f64; 1], __lagrange_qdot: &[f64; 1], __lagrange_t: f64) -> f64 {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        0.0
    }
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
    #[inline]
    fn energy(
        &self,
        __lagrange_q: &[f64; 1],
        __lagrange_qdot: &[f64; 1],
        __lagrange_t: f64,
    ) -> f64 {
        <Self as ::lagrange::__private::Lagrangian<1>>::energy_and_momenta(
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
    #[inline(always)]
    fn accelerations_in<R: ::lagrange::__private::Real>(
        __lagrange_members: &[&Self],
        __lagrange_params: &mut ::std::vec::Vec<R>,
        __lagrange_q: &[R; 1],
        __lagrange_qdot: &[R; 1],
        __lagrange_t: R,
    ) -> ::core::option::Option<([R; 1], <R as ::lagrange::__private::Real>::Mask)> {
        ::core::option::Option::Some(__lagrange_Pendulum_2105f53a_kernels::accelerations::<R, _>(
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
                    [<R as ::lagrange::__private::Real>::NAN; 1],
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
        __lagrange_out: &mut [[[R; 1]; 2]],
        __lagrange_buf: &mut ::lagrange::__private::taylor::SeriesBuf<R>,
    ) -> ::core::option::Option<
        ::core::result::Result<
            <R as ::lagrange::__private::Real>::Mask,
            ::lagrange::__private::DynamicsError,
        >,
    > {
        ::core::option::Option::Some(__lagrange_Pendulum_2105f53a_kernels::series::<R>(
            ::lagrange::__private::kernel_params(
                __lagrange_members,
                __lagrange_params,
                Self::__lagrange_params,
            )?,
            <Self as ::lagrange::__private::Lagrangian<1>>::COORDINATES,
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
    const KERNEL_FIELDS: &'static [&'static str] = &["m", "l", "g"];
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
mod __lagrange_Pendulum_2105f53a_kernels {
    #[doc = r" How many numbers `__lagrange_params` loads (the kernels' parameters)."]
    pub(super) const PARAMS: usize = 3;
    #[doc = r" q̈ from M q̈ = f (the straight-line LDLᵀ) and the lanes where every pivot test"]
    #[doc = r" passed and every value is finite, handed to `done`; where that declines, M (upper"]
    #[doc = r" triangle) and f to `careful` (formed only on that path)."]
    #[inline(always)]
    pub(super) fn accelerations<R: ::lagrange::__private::Real, O>(
        __lagrange_params: &[R; PARAMS],
        __lagrange_q: &[R; 1],
        __lagrange_qdot: &[R; 1],
        __lagrange_t: R,
        done: impl FnOnce([R; 1], <R as ::lagrange::__private::Real>::Mask) -> ::core::option::Option<O>,
        careful: impl FnOnce(&[[R; 1]; 1], &[R; 1]) -> O,
    ) -> O {
        let _ = (__lagrange_q, __lagrange_qdot, __lagrange_t);
        let __lagrange_p_m: R = __lagrange_params[0];
        let __lagrange_p_l: R = __lagrange_params[1];
        let __lagrange_p_g: R = __lagrange_params[2];
        let (__lagrange_x8, __lagrange_x17, __lagrange_x24): (R, R, R) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].sin(),
        );
        let (__lagrange_x10, __lagrange_x18): (R, R) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
        );
        let __lagrange_x26: R = __lagrange_x18 * __lagrange_x24;
        let __lagrange_x27: R = -__lagrange_x26;
        let (__lagrange_qddot, __lagrange_ok) = '__lagrange_fast: {
            let __lagrange_ok = <R as ::lagrange::__private::Real>::EVERY_LANE;
            let __lagrange_d_0: R = __lagrange_x10;
            let __lagrange_ok = __lagrange_ok
                & <R as ::lagrange::__private::Real>::greater(
                    __lagrange_d_0,
                    __lagrange_x10 * ::lagrange::__private::linalg::ACCURATE_RELATIVE_PIVOT,
                );
            if <R as ::lagrange::__private::Real>::WIDTH == 1
                && !<R as ::lagrange::__private::Real>::all(__lagrange_ok)
            {
                break '__lagrange_fast (
                    [<R as ::lagrange::__private::Real>::NAN; 1],
                    __lagrange_ok,
                );
            }
            let __lagrange_y_0: R = __lagrange_x27;
            let __lagrange_y_0: R = __lagrange_y_0 / __lagrange_d_0;
            let __lagrange_ok =
                __lagrange_ok & <R as ::lagrange::__private::Real>::finite(__lagrange_y_0);
            ([__lagrange_y_0], __lagrange_ok)
        };
        match done(__lagrange_qddot, __lagrange_ok) {
            ::core::option::Option::Some(o) => o,
            ::core::option::Option::None => careful(&[[__lagrange_x10]], &[__lagrange_x27]),
        }
    }
    #[doc = r" The Taylor coefficients of the motion through `out[0]` at t (see"]
    #[doc = r" `Lagrangian::series_in`), in the lanes of the mask."]
    #[inline(always)]
    pub(super) fn series<R: ::lagrange::__private::eom::SeriesReal>(
        __lagrange_params: &[R; PARAMS],
        __lagrange_names: [&'static str; 1],
        __lagrange_t: R,
        __lagrange_out: &mut [[[R; 1]; 2]],
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
        let __lagrange_c: &mut [__lagrange_rt::RowOf<R>; 10] = __lagrange_buf.slots::<10>();
        let __lagrange_y0: [[R; 1]; 2] = __lagrange_out[0];
        let (__lagrange_q, __lagrange_qdot): (&[R; 1], &[R; 1]) =
            (&__lagrange_y0[0], &__lagrange_y0[1]);
        let __lagrange_p_m: R = __lagrange_params[0];
        let __lagrange_p_l: R = __lagrange_params[1];
        let __lagrange_p_g: R = __lagrange_params[2];
        let (__lagrange_x8, __lagrange_x17, (__lagrange_x24, __lagrange_x19)): (R, R, (R, R)) = (
            __lagrange_p_m * __lagrange_p_l,
            __lagrange_p_m * __lagrange_p_g,
            __lagrange_q[0].sin_cos(),
        );
        let (__lagrange_x10, __lagrange_x18, __lagrange_x25): (R, R, R) = (
            __lagrange_p_l * __lagrange_x8,
            __lagrange_p_l * __lagrange_x17,
            -__lagrange_x24,
        );
        let __lagrange_x26: R = __lagrange_x18 * __lagrange_x24;
        let __lagrange_x27: R = -__lagrange_x26;
        __lagrange_c[1][0] = __lagrange_q[0];
        __lagrange_c[2][0] = __lagrange_x10;
        __lagrange_c[3][0] = __lagrange_x18;
        __lagrange_c[4][0] = __lagrange_x19;
        __lagrange_c[6][0] = __lagrange_x25;
        __lagrange_c[8][0] = __lagrange_x27;
        __lagrange_c[0][1..=__lagrange_order].fill(<R as ::lagrange::__private::Real>::ZERO);
        let (__lagrange_factor , __lagrange_ok) = << R as :: lagrange :: __private :: eom :: SeriesReal > :: Factor < 1 > as :: lagrange :: __private :: eom :: SeriesFactor < R , 1 >> :: new (& __lagrange_rt :: order0_matrix (__lagrange_c , [[2]]) , & __lagrange_rt :: order0_column (__lagrange_c , [8]) , __lagrange_names , __lagrange_q , __lagrange_qdot , __lagrange_t) ;
        if let ::core::option::Option::Some(__lagrange_e) =
            ::lagrange::__private::eom::SeriesFactor::error(
                &__lagrange_factor,
                __lagrange_names,
                __lagrange_q,
                __lagrange_qdot,
                __lagrange_t,
            )
        {
            return ::core::result::Result::Err(__lagrange_e);
        }
        let mut __lagrange_a = [<R as ::lagrange::__private::Real>::ZERO; 1];
        for __lagrange_k in 0..__lagrange_order {
            let __lagrange_b: [R; 1] = if __lagrange_k == 0 {
                __lagrange_rt::order0_column(__lagrange_c, [8])
            } else {
                __lagrange_c[1][__lagrange_k] = __lagrange_out[__lagrange_k][0][0];
                __lagrange_rt::deriv_at(__lagrange_c, 4, 1, 6, __lagrange_k);
                __lagrange_rt::deriv_at(__lagrange_c, 5, 1, 4, __lagrange_k);
                __lagrange_c[6][__lagrange_k] = -__lagrange_c[5][__lagrange_k];
                let __lagrange_t26: R = __lagrange_x18 * __lagrange_c[5][__lagrange_k];
                let __lagrange_t27: R = -__lagrange_t26;
                [__lagrange_t27]
            };
            ::lagrange::__private::eom::SeriesFactor::solve(
                &__lagrange_factor,
                &__lagrange_b,
                &mut __lagrange_a,
                __lagrange_names,
                __lagrange_q,
                __lagrange_qdot,
                __lagrange_t,
            )?;
            __lagrange_rt::next_order(__lagrange_out, __lagrange_a, __lagrange_k);
            if __lagrange_k + 1 < __lagrange_order {
                __lagrange_rt::derivs_mid_at(
                    __lagrange_c,
                    [4, 5],
                    [1, 1],
                    [6, 4],
                    __lagrange_k + 1,
                );
            }
        }
        for __lagrange_x in &mut __lagrange_out[__lagrange_order + 1..] {
            *__lagrange_x = [[<R as ::lagrange::__private::Real>::NAN; 1]; 2];
        }
        ::core::result::Result::Ok(__lagrange_ok)
    }
}
#[doc = "# Equations of motion\n\nDerived at compile time by `#[lagrangian]` (d/dt ∂L/∂q\u{307} = ∂L/∂q, one line per coordinate):\n\n```text\ntheta: m l² θ\u{308} = −m l g sin(θ)\n```\n"]
impl Pendulum {
    #[doc = "The Euler–Lagrange equations, derived at compile time by `#[lagrangian]`: one line per coordinate, `Σₖ Mᵢₖ q\u{308}ₖ = fᵢ` (accelerations on the left).\n\n```text\ntheta: m l² θ\u{308} = −m l g sin(θ)\n```"]
    pub const EQUATIONS: &'static str = "theta: m l² θ\u{308} = −m l g sin(θ)";
    #[doc = "The Euler–Lagrange equations in LaTeX, one line per coordinate (the same equations as `EQUATIONS`)."]
    pub const EQUATIONS_LATEX: &'static str =
        "m l^{2} \\ddot{\\theta} = -m l g \\sin\\left(\\theta\\right)";
    #[doc = r" The parameters of the generic kernels, loaded from `self`."]
    #[doc(hidden)]
    #[inline(always)]
    fn __lagrange_params(&self) -> [f64; 3] {
        let __lagrange_p_m: f64 = self.m;
        let __lagrange_p_l: f64 = self.l;
        let __lagrange_p_g: f64 = self.g;
        [__lagrange_p_m, __lagrange_p_l, __lagrange_p_g]
    }
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
