//! Holonomic constraints end to end: systems written in Cartesian coordinates with their
//! constraints (`Holonomic`, by hand) against the same systems in independent angle coordinates,
//! the multipliers against the closed-form constraint forces, a rheonomic constraint's energy
//! balance, a four-bar linkage over 1000 crank revolutions, bad input, CSV and every method.
//!
//! Convention: M q̈ = f + Gᵀλ with G = ∂g/∂q, so Gᵀλ is the constraint force.

use std::f64::consts::{PI, TAU};

use lagrange::constraints::Constrained;
use lagrange::prelude::*;
use lagrange::ConstraintResidual;

use crate::support::four_bar::FourBar;

// ---------------------------------------------------------------------------------------------
// Systems
// ---------------------------------------------------------------------------------------------

/// A bob on a rod of length l from the origin, in x, y, z: L = m|v|²/2 − m g z, g = |r|² − l².
struct SphereBob {
    m: f64,
    g: f64,
    l: f64,
}

impl Lagrangian<3> for SphereBob {
    const COORDINATES: [&'static str; 3] = ["x", "y", "z"];
    const CYCLIC: [bool; 3] = [true, true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * (0.5 * self.m) - q[2] * (self.m * self.g)
    }
}

impl Holonomic<3, 1> for SphereBob {
    const SCLERONOMIC: bool = true;
    fn constraints<S: Scalar>(&self, q: &[S; 3], _t: S) -> [S; 1] {
        [q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - self.l * self.l]
    }
}

/// The spherical pendulum in its angles, θ from +z and φ about z, written independently:
/// L = m l²(θ̇² + sin²θ φ̇²)/2 − m g l cos θ.
struct SphericalAngles {
    m: f64,
    g: f64,
    l: f64,
}

impl Lagrangian<2> for SphericalAngles {
    const COORDINATES: [&'static str; 2] = ["theta", "phi"];
    const CYCLIC: [bool; 2] = [false, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        let s = q[0].sin();
        let ml2 = self.m * self.l * self.l;
        (v[0] * v[0] + s * s * v[1] * v[1]) * (0.5 * ml2) - q[0].cos() * (self.m * self.g * self.l)
    }
}

/// (θ, φ, θ̇, φ̇) → (r, ṙ) on the sphere of radius l.
fn sphere_point(l: f64, q: &[f64; 2], v: &[f64; 2]) -> ([f64; 3], [f64; 3]) {
    let (st, ct) = q[0].sin_cos();
    let (sp, cp) = q[1].sin_cos();
    (
        [l * st * cp, l * st * sp, l * ct],
        [
            l * (ct * cp * v[0] - st * sp * v[1]),
            l * (ct * sp * v[0] + st * cp * v[1]),
            -l * st * v[0],
        ],
    )
}

/// A plane pendulum in x, y (y up): L = m|v|²/2 − m g y, g = x² + y² − l².
struct PlanePendulum {
    m: f64,
    g: f64,
    l: f64,
}

impl Lagrangian<2> for PlanePendulum {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m) - q[1] * (self.m * self.g)
    }
}

impl Holonomic<2, 1> for PlanePendulum {
    const SCLERONOMIC: bool = true;
    fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
        [q[0] * q[0] + q[1] * q[1] - self.l * self.l]
    }
}

/// The plane pendulum in its angle from the downward vertical, declared with `#[lagrangian]`.
struct AnglePendulum {
    m: f64,
    g: f64,
    l: f64,
}

#[lagrangian]
impl AnglePendulum {
    fn lagrangian(&self, (th, th_dot): Coord) -> Scalar {
        self.m * self.l * self.l * th_dot * th_dot / 2.0 + self.m * self.g * self.l * th.cos()
    }
}

/// (θ, θ̇) → (x, y, ẋ, ẏ): x = l sin θ, y = −l cos θ.
fn plane_point(l: f64, th: f64, w: f64) -> ([f64; 2], [f64; 2]) {
    let (s, c) = th.sin_cos();
    ([l * s, -l * c], [l * c * w, l * s * w])
}

/// A bead on a hoop of radius r (centred at the origin) that turns about z at the constant rate
/// ω, in x, y, z: the plane −x sin ωt + y cos ωt = 0 and the circle |r|² = R².
struct HoopBead {
    m: f64,
    g: f64,
    r: f64,
    omega: f64,
}

impl Lagrangian<3> for HoopBead {
    const COORDINATES: [&'static str; 3] = ["x", "y", "z"];
    const CYCLIC: [bool; 3] = [true, true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * (0.5 * self.m) - q[2] * (self.m * self.g)
    }
}

impl Holonomic<3, 2> for HoopBead {
    fn constraints<S: Scalar>(&self, q: &[S; 3], t: S) -> [S; 2] {
        let wt = t * self.omega;
        [
            -q[0] * wt.sin() + q[1] * wt.cos(),
            q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - self.r * self.r,
        ]
    }
}

/// The bead in its angle θ from the downward vertical: L = m R²(θ̇² + ω² sin²θ)/2 + m g R cos θ.
struct HoopAngle {
    m: f64,
    g: f64,
    r: f64,
    omega: f64,
}

impl Lagrangian<1> for HoopAngle {
    const COORDINATES: [&'static str; 1] = ["theta"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        let s = q[0].sin();
        let mr2 = self.m * self.r * self.r;
        (v[0] * v[0] + s * s * (self.omega * self.omega)) * (0.5 * mr2)
            + q[0].cos() * (self.m * self.g * self.r)
    }
}

/// (θ, θ̇, t) → the bead's (r, ṙ) in space.
fn hoop_point(h: &HoopAngle, th: f64, w: f64, t: f64) -> ([f64; 3], [f64; 3]) {
    let (s, c) = th.sin_cos();
    let (sw, cw) = (h.omega * t).sin_cos();
    let r = h.r;
    (
        [r * s * cw, r * s * sw, -r * c],
        [
            r * (c * w * cw - s * h.omega * sw),
            r * (c * w * sw + s * h.omega * cw),
            r * s * w,
        ],
    )
}

/// The plane pendulum's rod twice: `[g, factor·g]` (redundant for any factor).
struct Twice {
    factor: f64,
}

impl Lagrangian<2> for Twice {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
    }
}

impl Holonomic<2, 2> for Twice {
    fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 2] {
        let g = q[0] * q[0] + q[1] * q[1] - 1.0;
        [g, g * self.factor]
    }
}

/// A plane pendulum with a third coordinate `w` that nothing fixes: no kinetic term, no constraint.
struct Loose;

impl Lagrangian<3> for Loose {
    const COORDINATES: [&'static str; 3] = ["x", "y", "w"];
    const CYCLIC: [bool; 3] = [true, false, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
    }
}

impl Holonomic<3, 1> for Loose {
    fn constraints<S: Scalar>(&self, q: &[S; 3], _t: S) -> [S; 1] {
        [q[0] * q[0] + q[1] * q[1] - 1.0]
    }
}

/// A free particle in the plane whose spring acts through a redundant coordinate w with no
/// kinetic term, tied to x by the constraint w = x: L = m(ẋ² + ẏ²)/2 − k w²/2. M is singular,
/// the constrained system is regular, and x oscillates at √(k/m).
struct Shadow {
    m: f64,
    k: f64,
}

impl Lagrangian<3> for Shadow {
    const COORDINATES: [&'static str; 3] = ["x", "y", "w"];
    const CYCLIC: [bool; 3] = [true, true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m) - q[2] * q[2] * (0.5 * self.k)
    }
}

impl Holonomic<3, 1> for Shadow {
    const SCLERONOMIC: bool = true;
    fn constraints<S: Scalar>(&self, q: &[S; 3], _t: S) -> [S; 1] {
        [q[2] - q[0]]
    }
}

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

fn dop853(tol: f64) -> Method {
    Method::Dop853 {
        rtol: tol,
        atol: tol,
    }
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}

const SPHERE: SphereBob = SphereBob {
    m: 1.3,
    g: 9.81,
    l: 1.7,
};
const SPHERE_ANGLES: SphericalAngles = SphericalAngles {
    m: 1.3,
    g: 9.81,
    l: 1.7,
};
const PLANE: PlanePendulum = PlanePendulum {
    m: 0.7,
    g: 9.81,
    l: 1.3,
};
const PLANE_ANGLE: AnglePendulum = AnglePendulum {
    m: 0.7,
    g: 9.81,
    l: 1.3,
};
/// The plane pendulum's initial angle (from the downward vertical) and rate: it swings to
/// ±1.27 rad, so the rod stays in tension.
const PLANE_START: (f64, f64) = (1.2, 1.0);

// ---------------------------------------------------------------------------------------------
// 1. Particle on a sphere against the spherical pendulum in angles
// ---------------------------------------------------------------------------------------------

#[test]
fn sphere_in_xyz_matches_the_spherical_pendulum_in_angles_and_the_rod_tension() {
    // θ0 = 2.0 from +z (below the equator), moving in both angles; the angular momentum about z
    // keeps θ away from the chart's pole θ = π (checked below).
    let (th0, ph0, thd0, phd0) = (2.0, 0.3, 0.7, 3.5);
    let (r0, v0) = sphere_point(SPHERE.l, &[th0, ph0], &[thd0, phd0]);
    let xyz = Simulation::constrained(&SPHERE, r0, v0)
        .method(dop853(1e-12))
        .until(20.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    let ang = Simulation::new(&SPHERE_ANGLES, [th0, ph0], [thd0, phd0])
        .method(dop853(1e-12))
        .until(20.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    assert_eq!(xyz.t, ang.t);
    assert_eq!(xyz.len(), 201);
    let (m, g, l) = (SPHERE.m, SPHERE.g, SPHERE.l);
    let (mut pos_err, mut tension_err, mut sin_min) = (0.0_f64, 0.0_f64, 1.0_f64);
    for k in 0..xyz.len() {
        let (r, v) = sphere_point(l, &ang.q[k], &ang.qdot[k]);
        sin_min = sin_min.min(ang.q[k][0].sin());
        pos_err = pos_err.max(max_abs_diff(&xyz.q[k], &r));
        // Radially, m(−v²/l) = −T + m g_vec·r̂ with g_vec = (0, 0, −g): T = m v²/l − m g z/l,
        // from the angle solution. The rod's force on the bob is Gᵀλ = 2λ r = −T r̂: 2λ l = −T.
        let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        let tension = m * v2 / l - m * g * r[2] / l;
        assert!(tension > 0.0);
        tension_err = tension_err.max((2.0 * xyz.lambda[k][0] * l + tension).abs() / tension);
    }
    eprintln!(
        "sphere: position {pos_err:.2e}, tension rel {tension_err:.2e}, min sin θ {sin_min:.3}"
    );
    assert!(sin_min > 0.3, "the run came near the chart's pole");
    assert!(pos_err < 1e-9, "positions differ by {pos_err:e}");
    assert!(tension_err < 1e-9, "tension differs by {tension_err:e}");
    let inv = xyz.invariants();
    assert!(inv.energy.unwrap().max_rel < 1e-10);
    // The momentum about z is conserved, but not in x or y alone: not declared conserved.
    assert!(inv.momenta.iter().all(Option::is_none));
}

// ---------------------------------------------------------------------------------------------
// 2. Plane pendulum in x, y: tension and motion
// ---------------------------------------------------------------------------------------------

#[test]
fn plane_pendulum_tension_and_motion_match_the_angle_pendulum() {
    let (th0, w0) = PLANE_START;
    let (q0, v0) = plane_point(PLANE.l, th0, w0);
    let xy = Simulation::constrained(&PLANE, q0, v0)
        .method(dop853(1e-12))
        .until(10.0)
        .sample_every(0.05)
        .run()
        .unwrap();
    let ang = Simulation::new(&PLANE_ANGLE, [th0], [w0])
        .method(dop853(1e-12))
        .until(10.0)
        .sample_every(0.05)
        .run()
        .unwrap();
    let (m, g, l) = (PLANE.m, PLANE.g, PLANE.l);
    let (mut pos_err, mut tension_err, mut tension_err_ang) = (0.0_f64, 0.0_f64, 0.0_f64);
    for k in 0..xy.len() {
        let (q, _) = plane_point(l, ang.q[k][0], ang.qdot[k][0]);
        pos_err = pos_err.max(max_abs_diff(&xy.q[k], &q));
        // The rod pulls the bob toward the pivot: Gᵀλ = 2λ r = −T r̂, so T = −2λ l, with
        // T = m(l θ̇² + g cos θ), θ and θ̇ from the run's own state...
        let [x, y] = xy.q[k];
        let [vx, vy] = xy.qdot[k];
        let thd = (x * vy - y * vx) / (l * l);
        let cos_th = -y / l;
        let tension = m * (l * thd * thd + g * cos_th);
        let measured = -2.0 * xy.lambda[k][0] * l;
        tension_err = tension_err.max((measured - tension).abs() / tension);
        // ...and from the angle pendulum's.
        let (th, thd) = (ang.q[k][0], ang.qdot[k][0]);
        let tension = m * (l * thd * thd + g * th.cos());
        tension_err_ang = tension_err_ang.max((measured - tension).abs() / tension);
    }
    eprintln!(
        "plane: position {pos_err:.2e}, tension rel {tension_err:.2e} (own state), \
         {tension_err_ang:.2e} (angle run)"
    );
    assert!(tension_err < 1e-10, "tension differs by {tension_err:e}");
    assert!(
        tension_err_ang < 1e-9,
        "tension differs by {tension_err_ang:e}"
    );
    assert!(pos_err < 1e-9, "positions differ by {pos_err:e}");
    assert!(xy.invariants().constraints.unwrap().position <= 1e-12);
}

#[test]
fn the_constrained_solve_does_not_depend_on_the_unit_of_mass() {
    // Masses 2^±140 (7e-43 and 1.4e42, atoms or planets in SI units): the accelerations are the
    // same and λ scales with m, bit for bit — every step of the solve is homogeneous in M and
    // scaling by a power of two is exact, and M̃ is brought to order one before a division-free
    // elimination whose factors would otherwise leave their range (so no unit pushes the
    // solve off its fast path).
    let (q, v) = plane_point(PLANE.l, 0.7, -1.3);
    let unit = PlanePendulum { m: 1.0, ..PLANE };
    let (a1, l1) = unit.constrained_accelerations(&q, &v, 0.0).unwrap();
    for e in [-140, 140] {
        let m = 2f64.powi(e);
        let heavy = PlanePendulum { m, ..PLANE };
        let (a, l) = heavy.constrained_accelerations(&q, &v, 0.0).unwrap();
        assert_eq!(a, a1, "m = 2^{e}");
        assert_eq!(l[0], l1[0] * m, "m = 2^{e}");
    }
    // And the tension against the closed form m (l θ̇² + g cos θ), T = −2λl.
    let tension = unit.m * (PLANE.l * 1.3 * 1.3 + PLANE.g * 0.7_f64.cos());
    assert!((-2.0 * l1[0] * PLANE.l - tension).abs() < 1e-13 * tension);
    // Two constraints (the four-bar linkage: masses and flywheel scaled together).
    let fb = FourBar::crank_rocker();
    let (q, v) = fb.closed_state(0.4, 2.0);
    let (a1, l1) = fb.constrained_accelerations(&q, &v, 0.0).unwrap();
    for e in [-140, 140] {
        let m = 2f64.powi(e);
        let heavy = FourBar {
            m1: fb.m1 * m,
            m2: fb.m2 * m,
            m3: fb.m3 * m,
            flywheel: fb.flywheel * m,
            ..FourBar::crank_rocker()
        };
        let (a, l) = heavy.constrained_accelerations(&q, &v, 0.0).unwrap();
        assert_eq!(a, a1, "four-bar, m = 2^{e}");
        assert_eq!(l, l1.map(|x| x * m), "four-bar, m = 2^{e}");
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Bead on a rotating hoop: a rheonomic constraint
// ---------------------------------------------------------------------------------------------

#[test]
fn bead_on_a_rotating_hoop_matches_the_one_angle_version_and_balances_its_energy() {
    // ω² = 25 > g/R = 12.3: the bottom is unstable, the bead swings about θ = acos(g/(Rω²)).
    let (m, g, r, omega) = (0.4, 9.81, 0.8, 5.0);
    let bead = HoopBead { m, g, r, omega };
    let hoop = HoopAngle { m, g, r, omega };
    const {
        assert!(!<Constrained<HoopBead, 3, 2> as Lagrangian<3>>::ENERGY_CONSERVED);
        assert!(<HoopBead as Lagrangian<3>>::ENERGY_CONSERVED); // L itself is autonomous
    }
    let (th0, w0) = (0.5, 0.3);
    let (q0, v0) = hoop_point(&hoop, th0, w0, 0.0);
    let xyz = Simulation::constrained(&bead, q0, v0)
        .method(dop853(1e-12))
        .until(10.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    let ang = Simulation::new(&hoop, [th0], [w0])
        .method(dop853(1e-12))
        .until(10.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    assert!(!xyz.energy_conserved);
    let mut pos_err = 0.0_f64;
    for k in 0..xyz.len() {
        let (p, _) = hoop_point(&hoop, ang.q[k][0], ang.qdot[k][0], ang.t[k]);
        pos_err = pos_err.max(max_abs_diff(&xyz.q[k], &p));
    }
    let inv = xyz.invariants();
    let balance = inv.energy_balance.unwrap();
    let work_max = xyz.work.iter().fold(0.0_f64, |a, w| a.max(w.abs()));
    let h_range = xyz
        .energy
        .iter()
        .fold(0.0_f64, |a, h| a.max((h - xyz.energy[0]).abs()));
    eprintln!(
        "hoop: position {pos_err:.2e}, energy balance rel {:.2e} (abs {:.2e}, max |W| {work_max:.3}, \
         max |h − h0| {h_range:.3}), residual {:?}",
        balance.max_rel,
        balance.max_abs,
        inv.constraints.unwrap()
    );
    assert!(pos_err < 1e-9, "positions differ by {pos_err:e}");
    // The energy really changes (the hoop does work on the bead), and the recorded work of the
    // constraint forces accounts for it.
    assert!(h_range > 0.1 * xyz.energy[0].abs().max(work_max));
    assert!(
        balance.max_rel <= 1e-9,
        "energy balance off by {:e}",
        balance.max_rel
    );
    assert!(inv.energy.is_none());
    // The Jacobi integral of the rotating frame, h_θ = m R²(θ̇² − ω² sin²θ)/2 − m g R cos θ,
    // is conserved by the angle run: a check that the angle version is the right comparison.
    assert!(ang.invariants().energy.unwrap().max_rel < 1e-10);
}

// ---------------------------------------------------------------------------------------------
// 4. Four-bar linkage over 1000 crank revolutions
// ---------------------------------------------------------------------------------------------

const REVOLUTIONS: f64 = 1000.0;

#[test]
fn four_bar_initial_state_is_closed_and_g_matches_the_written_out_jacobian() {
    let fb = FourBar::crank_rocker();
    for th1 in [0.0, 0.7, 2.0, PI, 4.5] {
        let (q, v) = fb.closed_state(th1, TAU);
        let rows = fb.constraint_rows(&q, &v, 0.0);
        assert!(
            rows.value.iter().all(|g| g.abs() < 1e-14),
            "{:?}",
            rows.value
        );
        assert!(rows.rate.iter().all(|g| g.abs() < 1e-13), "{:?}", rows.rate);
        let jac = fb.jacobian(&q);
        for (row, written) in rows.jacobian.iter().zip(&jac) {
            assert!(max_abs_diff(row, written) < 1e-15);
        }
        // Above the ground line (the assembly the crank–rocker keeps).
        let (_, cy) = fb.coupler_point(&q, 1.0, 0.0);
        assert!(cy > 0.0);
    }
}

/// The crank–rocker from θ1 = 0 until the crank completes `REVOLUTIONS` turns (a terminal
/// event on θ1), keeping only the running invariants, with the largest relative energy error
/// over the first tenth of the turns and over the turns before the last (from an observer of
/// every step: the nodes of a fixed-step method, not the final sample, which the terminal event
/// interpolates between two of them).
struct FourBarRun {
    tr: Trajectory<3>,
    early_energy: f64,
    late_energy: f64,
    took: std::time::Duration,
}

fn four_bar_run(method: Method) -> FourBarRun {
    let fb = FourBar::crank_rocker();
    let (q0, v0) = fb.closed_state(0.0, TAU);
    let h0 = fb.energy(&q0, &v0, 0.0);
    let (mut early_energy, mut late_energy) = (0.0_f64, 0.0_f64);
    let start = std::time::Instant::now();
    let tr = Simulation::constrained(&fb, q0, v0)
        .method(method)
        .until(5000.0)
        .keep_samples(false)
        .observe(|s| {
            let e = (s.energy - h0).abs() / h0.abs();
            if s.q[0] < 0.1 * REVOLUTIONS * TAU {
                early_energy = early_energy.max(e);
            } else if s.q[0] < (REVOLUTIONS - 1.0) * TAU {
                late_energy = late_energy.max(e);
            }
        })
        .event(
            Event::zero_crossing("1000 turns", |_t, q: &[f64; 3], _v| {
                q[0] - REVOLUTIONS * TAU
            })
            .terminal(),
        )
        .run()
        .unwrap();
    let took = start.elapsed();
    let last = tr.q.last().unwrap();
    let inv = tr.invariants();
    eprintln!(
        "four-bar {method:?}: t = {:.1}, {} steps in {took:?}, turns {:.6}, residual {:?}, \
         energy rel {:.2e} (turns 0–100 {early_energy:.2e}, 100–999 {late_energy:.2e})",
        tr.t.last().unwrap(),
        tr.stats.steps,
        last[0] / TAU,
        inv.constraints.unwrap(),
        inv.energy.unwrap().max_rel,
    );
    assert_eq!(tr.terminated_by.as_deref(), Some("1000 turns"));
    assert!((last[0] / TAU - REVOLUTIONS).abs() < 1e-9);
    FourBarRun {
        tr,
        early_energy,
        late_energy,
        took,
    }
}

#[test]
fn four_bar_keeps_its_loop_closed_and_its_energy_with_dop853() {
    for (rtol, energy_tol) in [(1e-10, None), (1e-12, Some(1e-9))] {
        let run = four_bar_run(dop853(rtol));
        let inv = run.tr.invariants();
        let c = inv.constraints.unwrap();
        assert!(
            c.position <= 1e-12,
            "rtol {rtol:e}: residual {:e}",
            c.position
        );
        assert!(
            c.velocity <= 1e-12,
            "rtol {rtol:e}: residual {:e}",
            c.velocity
        );
        if let Some(tol) = energy_tol {
            let e = inv.energy.unwrap().max_rel;
            assert!(e <= tol, "rtol {rtol:e}: energy drift {e:e}");
        }
    }
}

#[test]
fn four_bar_keeps_its_loop_closed_with_the_variational_method() {
    // dt = 2 ms, about 500 steps a turn (2.4 s for 1000 turns in the test profile). Measured: at
    // the nodes the energy error peaks at 1.99e-6 of h in every hundred turns alike (bounded, as
    // for a symplectic method: O(dt²), 4.98e-7 at dt = 1 ms, no drift); the final sample, at the
    // terminal event between two nodes (q̇ interpolated linearly), is off by 4.3e-6.
    let run = four_bar_run(Method::VariationalMidpoint { dt: 2e-3 });
    let inv = run.tr.invariants();
    let c = inv.constraints.unwrap();
    let e = inv.energy.unwrap().max_rel;
    assert!(c.position <= 1e-12, "constraint residual {:e}", c.position);
    assert!(c.velocity <= 1e-12, "constraint residual {:e}", c.velocity);
    assert_eq!(c.projection, 0.0);
    assert!(
        run.early_energy <= 2.5e-6,
        "energy error {:e}",
        run.early_energy
    );
    assert!(
        run.late_energy <= 1.01 * run.early_energy,
        "the energy drifts: {:e} in turns 100–999, {:e} in the first 100",
        run.late_energy,
        run.early_energy
    );
    assert!(e <= 1e-5, "energy error {e:e}");
    assert!(run.took.as_secs_f64() < 30.0);
}

// ---------------------------------------------------------------------------------------------
// 5. Bad input
// ---------------------------------------------------------------------------------------------

#[test]
fn an_initial_state_off_the_constraints_is_rejected_with_its_residual_and_can_be_projected() {
    // l = 1.3: |r|² − l² = 1.4² − 1.69 = 0.27; ġ = 2 r·v = 2·1.4·0.2 = 0.56.
    let sim = || Simulation::constrained(&PLANE, [1.4, 0.0], [0.2, 0.5]).until(1.0);
    let err = sim().run().unwrap_err();
    match &err {
        SimulationError::OffConstraints {
            position_residual,
            velocity_residual,
            worst,
            ..
        } => {
            assert!(
                (position_residual - 0.27).abs() < 1e-12,
                "{position_residual}"
            );
            assert!(
                (velocity_residual - 0.56).abs() < 1e-12,
                "{velocity_residual}"
            );
            assert_eq!(*worst, 0);
        }
        other => panic!("expected OffConstraints, got {other:?}"),
    }
    let msg = err.to_string();
    assert!(msg.contains("max |g| = 2.700e-1"), "{msg}");
    assert!(msg.contains("max |ġ| = 5.600e-1"), "{msg}");
    assert!(msg.contains("project_initial_state"), "{msg}");
    // Projected: onto the circle along the radius, the velocity onto its tangent.
    let tr = sim().project_initial_state().run().unwrap();
    assert!((tr.q[0][0] - PLANE.l).abs() < 1e-15 && tr.q[0][1] == 0.0);
    assert_eq!(tr.qdot[0], [0.0, 0.5]);
    assert!(tr.invariants().constraints.unwrap().position <= 1e-12);
    // A velocity off the tangent alone is rejected too.
    let err = Simulation::constrained(&PLANE, [PLANE.l, 0.0], [0.1, 0.0])
        .until(1.0)
        .run()
        .unwrap_err();
    assert!(
        matches!(err, SimulationError::OffConstraints { .. }),
        "{err}"
    );
}

/// Redundant constraints run: the rod twice, [g, f·g], gives the accelerations of the rod once
/// with the least-norm multipliers of the one force Λ ∇g: λ₀ + f λ₁ = Λ, λ ∥ (1, f), so
/// λ₀ = Λ/(1 + f²), λ₁ = f Λ/(1 + f²). Closed form at q = (0.6, −0.8), q̇ = (0.8, 0.6) (unit
/// mass, g = 9.81 along −y, the rod x² + y² = 1): ∇g = 2q, and ∇g·q̈ + 2|q̇|² = 0 with
/// q̈ = (0, −9.81) + 2Λq gives 2 q·(0, −9.81) + 4Λ + 2 = 0, Λ = −(15.696 + 2)/4 = −4.424,
/// q̈ = (−5.3088, −2.7316).
#[test]
fn redundant_constraints_take_the_least_norm_multipliers() {
    let (lam, a_exact) = (-4.424, [-5.3088, -2.7316]);
    for factor in [1.0, 2.0] {
        let sys = Twice { factor };
        let (a, lambda) = sys
            .constrained_accelerations(&[0.6, -0.8], &[0.8, 0.6], 0.0)
            .unwrap();
        let share = 1.0 + factor * factor;
        assert!(
            (a[0] - a_exact[0]).abs() < 1e-12 && (a[1] - a_exact[1]).abs() < 1e-12,
            "{a:?}"
        );
        assert!(
            (lambda[0] - lam / share).abs() < 1e-12
                && (lambda[1] - factor * lam / share).abs() < 1e-12,
            "{lambda:?}"
        );
        // A run: the pendulum's energy and its rod kept.
        let tr = Simulation::constrained(&sys, [0.6, -0.8], [0.8, 0.6])
            .until(2.0)
            .run()
            .unwrap();
        let inv = tr.invariants();
        assert!(inv.constraints.unwrap().position < 1e-13, "{inv:?}");
        let energy = |k: usize| {
            let (q, v) = (tr.q[k], tr.qdot[k]);
            0.5 * (v[0] * v[0] + v[1] * v[1]) + 9.81 * q[1]
        };
        let drift = (energy(tr.t.len() - 1) - energy(0)).abs();
        assert!(drift < 1e-9, "energy drift {drift:e}");
    }
}

/// x held at 0 and at t² together: dependent rows (both ∂g/∂q = (1, 0)) that agree at t = 0 but
/// ask for ẍ = 0 and ẍ = 2: no motion satisfies both.
struct Contradict;

impl Lagrangian<2> for Contradict {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [true, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
    }
}

impl Holonomic<2, 2> for Contradict {
    fn constraints<S: Scalar>(&self, q: &[S; 2], t: S) -> [S; 2] {
        [q[0], q[0] - t * t]
    }
}

/// Dependent constraints that contradict each other are refused, naming both.
#[test]
fn inconsistent_constraints_are_named_by_index() {
    let err = Contradict
        .constrained_accelerations(&[0.0, 0.0], &[0.0, 0.0], 0.0)
        .unwrap_err();
    assert!(
        matches!(err, DynamicsError::DependentConstraints { .. }),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("constraints 0, 1") && msg.contains("inconsistent"),
        "{msg}"
    );
    let err = Simulation::constrained(&Contradict, [0.0, 0.0], [0.0, 0.0])
        .until(1.0)
        .run()
        .unwrap_err();
    match &err {
        SimulationError::Dynamics { source, .. } => {
            assert!(
                matches!(**source, DynamicsError::DependentConstraints { .. }),
                "{source:?}"
            );
            assert!(err.to_string().contains("constraints 0, 1"), "{err}");
        }
        other => panic!("expected Dynamics, got {other}"),
    }
}

#[test]
fn a_coordinate_without_inertia_or_constraint_is_a_singular_system_named_by_coordinate() {
    let err = Loose
        .constrained_accelerations(&[0.6, -0.8, 0.0], &[0.8, 0.6, 0.0], 0.0)
        .unwrap_err();
    assert!(
        matches!(err, DynamicsError::SingularMassMatrix { .. }),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(msg.contains("`w`"), "{msg}");
    let err = Simulation::constrained(&Loose, [0.6, -0.8, 0.0], [0.8, 0.6, 0.0])
        .until(1.0)
        .run()
        .unwrap_err();
    match &err {
        SimulationError::Dynamics { source, .. } => assert!(
            matches!(**source, DynamicsError::SingularMassMatrix { .. }),
            "{source:?}"
        ),
        other => panic!("expected Dynamics, got {other}"),
    }
    assert!(err.to_string().contains("`w`"), "{err}");
}

#[test]
fn a_singular_mass_matrix_made_regular_by_a_constraint_runs() {
    // M = diag(m, m, 0), regular with w = x: x oscillates at √(k/m), y drifts.
    let sys = Shadow { m: 2.0, k: 8.0 };
    let omega = (sys.k / sys.m).sqrt();
    let (a, lambda) = sys
        .constrained_accelerations(&[0.5, 0.0, 0.5], &[0.0, 1.0, 0.0], 0.0)
        .unwrap();
    // ẍ = −(k/m) x; the constraint carries the spring's force to x: λ = k w on w.
    assert!((a[0] + 2.0).abs() < 1e-14 && a[1].abs() < 1e-14 && (a[2] + 2.0).abs() < 1e-14);
    assert!((lambda[0] - 4.0).abs() < 1e-14, "{lambda:?}");
    let tr = Simulation::constrained(&sys, [0.5, 0.0, 0.5], [0.0, 1.0, 0.0])
        .method(dop853(1e-12))
        .until(10.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    let mut err = 0.0_f64;
    for (t, q) in tr.t.iter().zip(&tr.q) {
        let x = 0.5 * (omega * t).cos();
        err = err.max(max_abs_diff(q, &[x, *t, x]));
    }
    eprintln!("shadow: error {err:.2e}");
    assert!(err < 1e-9, "{err:e}");
    assert!(tr.invariants().energy.unwrap().max_rel < 1e-10);
}

// ---------------------------------------------------------------------------------------------
// 6. CSV
// ---------------------------------------------------------------------------------------------

#[test]
fn a_constrained_trajectory_writes_its_multipliers_to_csv() {
    let (q0, v0) = plane_point(PLANE.l, PLANE_START.0, PLANE_START.1);
    let tr = Simulation::constrained(&PLANE, q0, v0)
        .method(dop853(1e-12))
        .until(2.0)
        .sample_every(0.25)
        .run()
        .unwrap();
    let path =
        std::env::temp_dir().join(format!("lagrange_constraints_{}.csv", std::process::id()));
    tr.write_csv(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).ok();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        header,
        ["t", "x", "y", "x_dot", "y_dot", "energy", "p_x", "p_y", "lambda_0"]
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 9);
    let (m, g, l) = (PLANE.m, PLANE.g, PLANE.l);
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row[8], tr.lambda[k][0]); // full precision
                                             // λ = −T/(2l), T = m(v²/l − g y/l).
        let (x, y, vx, vy) = (row[1], row[2], row[3], row[4]);
        assert!((x * x + y * y - l * l).abs() < 1e-12);
        let tension = m * ((vx * vx + vy * vy) / l - g * y / l);
        assert!((row[8] + tension / (2.0 * l)).abs() < 1e-10 * tension);
    }
}

// ---------------------------------------------------------------------------------------------
// 7. Every method on the plane pendulum
// ---------------------------------------------------------------------------------------------

#[test]
fn every_method_keeps_the_plane_pendulum_on_its_circle_and_follows_the_angle_pendulum() {
    let (th0, w0) = PLANE_START;
    let (q0, v0) = plane_point(PLANE.l, th0, w0);
    let reference = Simulation::new(&PLANE_ANGLE, [th0], [w0])
        .method(dop853(1e-13))
        .until(10.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    // Tolerances: the global position error each method should reach over 10 s (about 6
    // periods) at these settings (measured: RK4 4.9e-11, DOPRI5 3.2e-10, DOP853 1.9e-12, the
    // second-order variational midpoint 3.5e-5, all against the angle pendulum at rtol 1e-13).
    let cases = [
        (Method::Rk4 { dt: 1e-3 }, 5e-10),
        (
            Method::DormandPrince {
                rtol: 1e-11,
                atol: 1e-11,
            },
            5e-9,
        ),
        (dop853(1e-12), 1e-10),
        (Method::VariationalMidpoint { dt: 1e-3 }, 1e-4),
    ];
    for (method, tol) in cases {
        let tr = Simulation::constrained(&PLANE, q0, v0)
            .method(method)
            .until(10.0)
            .sample_every(0.1)
            .run()
            .unwrap();
        assert_eq!(tr.len(), reference.len());
        let mut err = 0.0_f64;
        for k in 0..tr.len() {
            assert!((tr.t[k] - reference.t[k]).abs() < 1e-12);
            let (q, _) = plane_point(PLANE.l, reference.q[k][0], reference.qdot[k][0]);
            err = err.max(max_abs_diff(&tr.q[k], &q));
        }
        let c: ConstraintResidual = tr.invariants().constraints.unwrap();
        eprintln!("{method:?}: position error {err:.2e} (tolerance {tol:.0e}), residual {c:?}");
        assert!(c.position <= 1e-12, "{method:?}: residual {:e}", c.position);
        assert!(err < tol, "{method:?}: position error {err:e}");
    }
}
