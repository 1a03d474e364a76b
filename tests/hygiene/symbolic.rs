//! Constants in the user's module named like the locals the symbolic mode generates do not
//! break it (a generated `let` of such a name would otherwise be a constant pattern).
#![allow(non_upper_case_globals, dead_code)]

use lagrange::prelude::*;

const q: f64 = 1.0;
const qdot: f64 = 2.0;
const t: f64 = 3.0;
const x: f64 = 4.0;
const x3: f64 = 5.0;
const x8: f64 = 6.0;
const x9: f64 = 7.0;
const scale: f64 = 1.0;
const tol: f64 = 9.0;
const fast: f64 = 10.0;
const det_0_1: f64 = 11.0;
const det_1_2: f64 = 12.0;
const p_m: f64 = 13.0;
const p_k: f64 = 14.0;
const c_scale: f64 = 15.0;
const b_0: bool = true;
const y_0: f64 = 16.0;
const y_1: f64 = 17.0;
const y_2: f64 = 18.0;
const d_0: f64 = 19.0;
const d_1: f64 = 20.0;
const l_0_1: f64 = 21.0;
const u_0_1: f64 = 22.0;
const r_0: f64 = 23.0;
const m: f64 = 24.0;
const a: f64 = 25.0;
const s: f64 = 26.0;
const qddot: f64 = 27.0;

/// Three masses on springs, their kinetic energies coupled (an LDLᵀ solve with every entry).
pub struct Coupled {
    pub m: f64,
    pub k: f64,
    pub e: f64,
}

#[lagrangian]
impl Coupled {
    fn lagrangian(&self, (u, u_dot): Coord, (v, v_dot): Coord, (w, w_dot): Coord) -> Scalar {
        // `scale` is the user's constant (1.0); `fast` only feeds a constant condition.
        let stiff = if fast > 5.0 { self.k * scale } else { 0.0 };
        0.5 * self.m * (u_dot.powi(2) + v_dot.powi(2) + w_dot.powi(2))
            + self.e * (u_dot * v_dot + v_dot * w_dot + u_dot * w_dot)
            - 0.5 * stiff * (u.powi(2) + v.powi(2) + w.powi(2))
    }
}

/// The symmetric heavy top (a decoupled 2×2 block solved by Cramer's rule).
pub struct HeavyTop {
    pub i_perp: f64,
    pub i_par: f64,
    pub mgl: f64,
}

#[lagrangian]
impl HeavyTop {
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (_phi, phi_dot): Coord,
        (_psi, psi_dot): Coord,
    ) -> Scalar {
        let (sn, cs) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * sn).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * cs).powi(2)
            - self.mgl * cs
    }
}

#[test]
fn the_generated_code_ignores_the_constants() {
    // M = m I + e (J − I) with m = 2, e = 0.5; f = −k q. For q = (1, 1, 1): M q̈ = −k (1, 1, 1)
    // and M (1, 1, 1) = (m + 2e) (1, 1, 1), so q̈ = −k / (m + 2e) = −3 / 3 = −1 each.
    let sys = Coupled {
        m: 2.0,
        k: 3.0,
        e: 0.5,
    };
    let acc = sys
        .accelerations(&[1.0, 1.0, 1.0], &[0.0, 0.0, 0.0], 0.0)
        .expect("accelerations");
    for v in acc {
        assert!((v + 1.0).abs() < 1e-14, "{acc:?}");
    }
    // At rest the top's nutation is driven by gravity alone: θ̈ = mgl sin θ / I⊥.
    let top = HeavyTop {
        i_perp: 2.0,
        i_par: 1.0,
        mgl: 4.0,
    };
    let theta0: f64 = 0.5;
    let acc = top
        .accelerations(&[theta0, 0.0, 0.0], &[0.0, 0.0, 0.0], 0.0)
        .expect("accelerations");
    assert!((acc[0] - 2.0 * theta0.sin()).abs() < 1e-14, "{acc:?}");
}

/// A pendulum in x, y whose rod length moves with the time: `fn constraints` next to the
/// constants named like the generated parameters (`q`, `t`, `s`, `a`).
pub struct MovingRod {
    pub m: f64,
    pub g: f64,
    pub l: f64,
}

#[lagrangian]
impl MovingRod {
    fn lagrangian(&self, (px, px_dot): Coord, (py, py_dot): Coord) -> Scalar {
        0.5 * self.m * (px_dot * px_dot + py_dot * py_dot) - self.m * self.g * py
    }
    fn constraints(&self, (px, _): Coord, (py, _): Coord, time: Time) -> [Scalar; 1] {
        // `scale` is the user's constant (1.0); the length grows as l (1 + time).
        let len = self.l * scale * (1.0 + time);
        [px * px + py * py - len * len]
    }
}

#[test]
fn constraints_ignore_the_constants() {
    let p = MovingRod {
        m: 2.0,
        g: 9.0,
        l: 1.5,
    };
    // At t = 0, hanging at rest: g = 0, ∂g/∂q = (0, −3).
    let rows = p.constraint_rows(&[0.0, -1.5], &[0.0, 0.0], 0.0);
    assert!(rows.value[0].abs() < 1e-12, "{rows:?}");
    assert!(
        rows.jacobian[0][0].abs() < 1e-12 && (rows.jacobian[0][1] + 3.0).abs() < 1e-12,
        "{rows:?}"
    );
    const { assert!(!<MovingRod as Holonomic<2, 1>>::SCLERONOMIC) };
}
