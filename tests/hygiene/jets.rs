//! Constants in the user's module named like the generated parameters and locals do not break
//! the jets mode.
#![allow(non_upper_case_globals, dead_code)]

use lagrange::prelude::*;

const q: f64 = 1.0;
const qdot: f64 = 2.0;
const t: f64 = 3.0;
const x: f64 = 4.0;
const x3: f64 = 5.0;
const scale: f64 = 1.0;
const tol: f64 = 7.0;
const fast: f64 = 8.0;
const det_0_1: f64 = 9.0;
const p_m: f64 = 10.0;
const b_0: bool = true;
const y_0: f64 = 11.0;
const s: f64 = 12.0;
const a: f64 = 13.0;

/// A plane pendulum with a time-dependent (but here constant) length factor.
pub struct Pendulum {
    pub g: f64,
    pub l: f64,
}

#[lagrangian(mode = "jets")]
impl Pendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord, time: Time) -> Scalar {
        // `scale` is the user's constant (1.0); `time` enters with weight zero.
        let len = self.l * scale + 0.0 * time;
        0.5 * len * len * theta_dot.powi(2) + self.g * len * theta.cos()
    }
}

#[test]
fn the_generated_code_ignores_the_constants() {
    let p = Pendulum { g: 9.0, l: 2.0 };
    let theta0: f64 = 0.3;
    let acc = p
        .accelerations(&[theta0], &[0.0], 0.0)
        .expect("accelerations");
    // θ̈ = −(g / l) sin θ.
    assert!((acc[0] + 4.5 * theta0.sin()).abs() < 1e-12, "{acc:?}");
}

/// A pendulum in x, y whose rod length moves with the time: `fn constraints` next to the
/// constants named like the generated parameters (`q`, `t`, `s`, `a`).
pub struct MovingRod {
    pub m: f64,
    pub g: f64,
    pub l: f64,
}

#[lagrangian(mode = "jets")]
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
