//! Twin systems for the tests (tests/symbolic.rs, tests/heavy_top.rs, tests/macro_contract.rs,
//! tests/gallery.rs, …) and benches/symbolic.rs: each declared ONCE as a pair (the default
//! symbolic mode and `mode = "jets"`) from one body, by [`twins!`](crate::twins); the pendulum
//! chains N = 2, 4, 8, 16 by `chain!`. The test crates reach it as `crate::support::systems` and
//! call `twins!` for twins of their own.

/// Declares `$sym` (symbolic mode) and `$jet` (`mode = "jets"`) with the same public `f64`-like
/// fields and the same `fn lagrangian`, plus `$sym::jets()` copying the fields into the twin.
/// `#[lagrangian]` sees the caller's plain tokens for the `fn` item.
#[macro_export]
macro_rules! twins {
    (
        $(#[$meta:meta])*
        $sym:ident, $jet:ident { $($field:ident : $ty:ty),* $(,)? }
        $($lagrangian:tt)*
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy)]
        pub struct $sym {
            $(pub $field: $ty,)*
        }

        #[::lagrange::lagrangian]
        impl $sym {
            $($lagrangian)*
        }

        $(#[$meta])*
        #[derive(Debug, Clone, Copy)]
        pub struct $jet {
            $(pub $field: $ty,)*
        }

        #[::lagrange::lagrangian(mode = "jets")]
        impl $jet {
            $($lagrangian)*
        }

        impl $sym {
            /// The same system with run-time jets.
            #[allow(dead_code)]
            pub fn jets(&self) -> $jet {
                $jet {
                    $($field: self.$field,)*
                }
            }
        }
    };
}

/// An N-link planar pendulum chain (equal masses m and lengths l), L written out link by link:
/// one `(θₖ, θ̇ₖ, sin θₖ, cos θₖ)` name tuple per link.
macro_rules! chain {
    (
        $n:literal, $sym:ident, $jet:ident;
        ($th1:ident, $v1:ident, $s1:ident, $c1:ident)
        $(($th:ident, $v:ident, $s:ident, $c:ident))*
    ) => {
        $crate::twins! {
            #[doc = concat!("A ", stringify!($n), "-link pendulum chain (equal masses and lengths), L written out.")]
            $sym, $jet { m: f64, l: f64, g: f64 }
            #[allow(clippy::too_many_arguments)]
            fn lagrangian(&self, ($th1, $v1): Coord $(, ($th, $v): Coord)*) -> Scalar {
                let ($s1, $c1) = $th1.sin_cos();
                let mut vx = self.l * $c1 * $v1;
                let mut vy = self.l * $s1 * $v1;
                let mut y = -self.l * $c1;
                let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
                $(
                    let ($s, $c) = $th.sin_cos();
                    vx += self.l * $c * $v;
                    vy += self.l * $s * $v;
                    y -= self.l * $c;
                    lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
                )*
                lag
            }
        }
    };
}

twins! {
    /// Symmetric heavy top, eq. (92).
    HeavyTop, HeavyTopJets { i_perp: f64, i_par: f64, m: f64, g: f64, l: f64 }
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let (s, c) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
            - self.m * self.g * self.l * c
    }
}

impl HeavyTop {
    /// m g l, the product the motion depends on.
    pub fn mgl(&self) -> f64 {
        self.m * self.g * self.l
    }

    /// The same top for the closed forms of `lagrange_theory::heavy_top`.
    pub fn theory(&self) -> lagrange_theory::heavy_top::Top {
        lagrange_theory::heavy_top::Top {
            i_perp: self.i_perp,
            i_par: self.i_par,
            mgl: self.mgl(),
        }
    }
}

twins! {
    /// A body of mass `m` in the potential −k/r, in polar coordinates (φ cyclic).
    Kepler, KeplerJets { m: f64, k: f64 }
    fn lagrangian(&self, (r, r_dot): Coord, (phi, phi_dot): Coord) -> Scalar {
        self.m / 2.0 * (r_dot * r_dot + r * r * phi_dot * phi_dot) + self.k / r
    }
}

chain!(2, Chain2, Chain2Jets; (th1, th1_dot, s1, c1) (th2, th2_dot, s2, c2));

chain!(4, Chain4, Chain4Jets;
    (th1, th1_dot, s1, c1) (th2, th2_dot, s2, c2) (th3, th3_dot, s3, c3) (th4, th4_dot, s4, c4));

chain!(8, Chain8, Chain8Jets;
    (th1, th1_dot, s1, c1) (th2, th2_dot, s2, c2) (th3, th3_dot, s3, c3) (th4, th4_dot, s4, c4)
    (th5, th5_dot, s5, c5) (th6, th6_dot, s6, c6) (th7, th7_dot, s7, c7) (th8, th8_dot, s8, c8));

chain!(16, Chain16, Chain16Jets;
    (th1, th1_dot, s1, c1) (th2, th2_dot, s2, c2) (th3, th3_dot, s3, c3) (th4, th4_dot, s4, c4)
    (th5, th5_dot, s5, c5) (th6, th6_dot, s6, c6) (th7, th7_dot, s7, c7) (th8, th8_dot, s8, c8)
    (th9, th9_dot, s9, c9) (th10, th10_dot, s10, c10) (th11, th11_dot, s11, c11)
    (th12, th12_dot, s12, c12) (th13, th13_dot, s13, c13) (th14, th14_dot, s14, c14)
    (th15, th15_dot, s15, c15) (th16, th16_dot, s16, c16));

/// The heavy top as a user who starts from geometry writes it: the body angular velocity under
/// R = R_z(φ) R_x(θ) R_z(ψ) worked out component by component, not the hand-simplified L of
/// eq. 92. ψ (and φ) enter L, but ψ leaves it through sin²ψ + cos²ψ = 1.
#[derive(Debug, Clone, Copy)]
pub struct RotationTop {
    /// Moment of inertia about a transverse axis through the fixed point.
    pub i_perp: f64,
    /// Moment of inertia about the symmetry axis.
    pub i_par: f64,
    /// Mass × gravity × distance from the fixed point to the centre of mass.
    pub mgl: f64,
}

#[::lagrange::lagrangian]
impl RotationTop {
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = psi.sin_cos();
        let wx = phi_dot * st * sp + theta_dot * cp;
        let wy = phi_dot * st * cp - theta_dot * sp;
        let wz = phi_dot * ct + psi_dot;
        0.5 * (self.i_perp * (wx * wx + wy * wy) + self.i_par * wz * wz) - self.mgl * ct
    }
}

use lagrange::geometry::{body_angular_velocity, Rotation};
use lagrange::Vector3;

twins! {
    /// The heavy top written from its rotation R = R_z(φ) R_x(θ) R_z(ψ) and
    /// `body_angular_velocity`: the macro derives ω, and the symbolic mode
    /// simplifies it to eq. 92.
    GeometryTop, GeometryTopJets { i_perp: f64, i_par: f64, mgl: f64 }
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let r = Rotation::about_z(phi) * Rotation::about_x(theta) * Rotation::about_z(psi);
        let w = body_angular_velocity(&r);
        0.5 * (self.i_perp * (w.x * w.x + w.y * w.y) + self.i_par * w.z * w.z)
            - self.mgl * (r * Vector3::z()).z
    }
}
