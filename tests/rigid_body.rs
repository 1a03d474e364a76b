//! Sections A–C of the reference text (rigid bodies), each test named after the equations it
//! confirms: fixed-axis rotation (eqs. 67–74), the inertia tensor and its shift to the centre of
//! mass (eqs. 75–77), Euler's equations (81–85), the free symmetric top (86–89) and the free
//! asymmetric top (90–91), all from Lagrangians declared with `#[lagrangian]`.
//!
//! Errors of the text found here are recorded in docs/ERRATA.md ("Sections A–C — Rigid body");
//! the tests check the corrected physics, derived independently, and show the printed forms fail.

use lagrange::prelude::*;
use lagrange::rigid::{
    body_angular_velocity_zxz, centre_of_mass, euler_rates_zxz, inertia_tensor, moment_about_axis,
    rotation_zxz, shift_from_centre_of_mass, EulerChartGuard,
};
use lagrange::{Direction, DynamicsError};
use nalgebra::{Matrix3, Rotation3, Unit};
use std::f64::consts::PI;

// ---------------------------------------------------------------------------------------------
// Systems
// ---------------------------------------------------------------------------------------------

/// A rigid body of point masses on a fixed horizontal axis (the body x axis through the origin),
/// gravity along −z. L is written from the positions alone, r_a(θ) = R_x(θ) b_a and
/// ṙ_a = (∂r_a/∂θ) θ̇: no moment of inertia, no ω × r is assumed. The body loops over the
/// masses, which the symbolic mode cannot unroll (their number is a run-time value), so this one
/// uses the run-time jets.
pub struct PhysicalPendulum {
    pub points: Vec<(f64, [f64; 3])>,
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl PhysicalPendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        let (s, c) = theta.sin_cos();
        let mut l = theta_dot * 0.0;
        for p in &self.points {
            let m = p.0;
            let b = p.1;
            // r = (b_x, c b_y − s b_z, s b_y + c b_z); dr/dθ = (0, −s b_y − c b_z, c b_y − s b_z).
            let z = s * b[1] + c * b[2];
            let dy = -(s * b[1]) - c * b[2];
            let dz = c * b[1] - s * b[2];
            l = l + m * 0.5 * (dy * dy + dz * dz) * theta_dot * theta_dot - m * self.g * z;
        }
        l
    }
}

/// A free rigid body with principal moments I1, I2, I3, in z-x-z Euler angles (φ, θ, ψ):
/// L = ½ Σ I_i ϖ_i², ϖ1 = φ̇ sinθ sinψ + θ̇ cosψ, ϖ2 = φ̇ sinθ cosψ − θ̇ sinψ, ϖ3 = φ̇ cosθ + ψ̇.
pub struct FreeTop {
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
}

#[lagrangian]
impl FreeTop {
    fn lagrangian(
        &self,
        (phi, phi_dot): Coord,
        (theta, theta_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = psi.sin_cos();
        let w1 = phi_dot * st * sp + theta_dot * cp;
        let w2 = phi_dot * st * cp - theta_dot * sp;
        let w3 = phi_dot * ct + psi_dot;
        0.5 * (self.i1 * w1 * w1 + self.i2 * w2 * w2 + self.i3 * w3 * w3)
    }
}

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

const TIGHT: Method = Method::Dop853 {
    rtol: 1e-12,
    atol: 1e-12,
};

fn v3(a: [f64; 3]) -> nalgebra::Vector3<f64> {
    nalgebra::Vector3::from(a)
}

impl FreeTop {
    fn inertia(&self) -> [f64; 3] {
        [self.i1, self.i2, self.i3]
    }
    /// Body angular momentum L_i = I_i ϖ_i.
    fn l_body(&self, w: [f64; 3]) -> [f64; 3] {
        [self.i1 * w[0], self.i2 * w[1], self.i3 * w[2]]
    }
}

/// (q0, q̇0) for the body at Euler angles `angles` with body angular velocity `w`.
fn start_at(angles: [f64; 3], w: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    (angles, euler_rates_zxz(angles, w).unwrap())
}

/// (q0, q̇0) with the lab z axis along the angular momentum (φ0 = 0): then the body components
/// L/|L| = (sinθ sinψ, sinθ cosψ, cosθ), so θ0 = acos(L3/|L|), ψ0 = atan2(L1, L2).
fn start_with_lab_z_along_l(top: &FreeTop, w: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let l = v3(top.l_body(w));
    let theta = (l[2] / l.norm()).acos();
    let psi = l[0].atan2(l[1]);
    start_at([0.0, theta, psi], w)
}

/// ϖ and dϖ/dt exactly, from (q, q̇, q̈) by the chain rule.
fn body_rates_and_derivative(q: [f64; 3], v: [f64; 3], a: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let (st, ct) = q[1].sin_cos();
    let (sp, cp) = q[2].sin_cos();
    let [pd, td, sd] = v;
    let [pdd, tdd, sdd] = a;
    let w = body_angular_velocity_zxz(q, v);
    let wd = [
        pdd * st * sp + pd * (ct * td * sp + st * cp * sd) + tdd * cp - td * sp * sd,
        pdd * st * cp + pd * (ct * td * cp - st * sp * sd) - tdd * sp - td * cp * sd,
        pdd * ct - pd * st * td + sdd,
    ];
    (w, wd)
}

// ---------------------------------------------------------------------------------------------
// A. Fixed-axis rotation, eqs. 67–74
// ---------------------------------------------------------------------------------------------

/// Points whose centre of mass lies on the −z axis in the reference position, well off the plane
/// x = 0: the CM is 0.943 along the rotation axis and 0.571 from it.
fn pendulum() -> PhysicalPendulum {
    PhysicalPendulum {
        points: vec![
            (1.0, [1.3, 0.2, -1.0]),
            (2.0, [0.5, -0.1, -0.6]),
            (0.5, [2.0, 0.0, 0.4]),
        ],
        g: 9.81,
    }
}

const X_AXIS: [f64; 3] = [1.0, 0.0, 0.0];

#[test]
fn eq69_moment_of_inertia_from_point_masses_is_the_pendulum_mass() {
    let p = pendulum();
    // eq. 69 two ways: Σ m r⊥² with r⊥ the distance from the axis, and Σ m [r² − (n̂·r)²].
    let direct: f64 = p
        .points
        .iter()
        .map(|&(m, b)| m * (b[1] * b[1] + b[2] * b[2]))
        .sum();
    let eq69 = moment_about_axis(&p.points, [0.0; 3], X_AXIS);
    assert!((eq69 - direct).abs() < 1e-14 * direct);
    // The Lagrangian written from positions only has exactly this mass, at every angle (eq. 68).
    for theta in [-2.0, -0.3, 0.0, 0.7, 3.0] {
        let m = p.mass_matrix(&[theta], &[0.4], 0.0)[(0, 0)];
        assert!(
            (m - eq69).abs() < 1e-13 * eq69,
            "θ = {theta}: {m} vs {eq69}"
        );
    }
}

#[test]
fn eq70_parallel_axis_theorem_uses_the_perpendicular_distance_of_the_cm() {
    let p = pendulum();
    let (m, r_cm) = centre_of_mass(&p.points);
    let i_n = moment_about_axis(&p.points, [0.0; 3], X_AXIS);
    let i_cm = moment_about_axis(&p.points, r_cm, X_AXIS);
    let d_perp2 = r_cm[1].powi(2) + r_cm[2].powi(2);
    let r2 = v3(r_cm).norm_squared();
    // Correct reading: R_cm is the distance of the CM from the axis.
    assert!((i_n - (m * d_perp2 + i_cm)).abs() < 1e-13 * i_n);
    // Reading R_cm as |R_cm| (the CM's distance from the origin on the axis) fails here by
    // M (n̂·R_cm)² = 3.11.
    let wrong = m * r2 + i_cm;
    assert!((wrong - i_n - m * r_cm[0].powi(2)).abs() < 1e-12);
    assert!((wrong - i_n).abs() > 3.0);
}

#[test]
fn eq71_72_momentum_conjugate_to_theta_is_the_axial_angular_momentum() {
    let p = pendulum();
    for (theta, theta_dot) in [(0.3, 1.7), (-1.2, -0.4), (2.5, 3.0)] {
        let p_theta = p.momenta(&[theta], &[theta_dot], 0.0)[0];
        // n̂·Σ m r × ṙ with r = R_x(θ) b and ṙ = ω × r, ω = θ̇ x̂ (eq. 67).
        let rot = Rotation3::from_axis_angle(&nalgebra::Vector3::x_axis(), theta);
        let omega = nalgebra::Vector3::x() * theta_dot;
        let l: nalgebra::Vector3<f64> = p
            .points
            .iter()
            .map(|&(m, b)| {
                let r = rot * v3(b);
                r.cross(&omega.cross(&r)) * m
            })
            .sum();
        let i_n = moment_about_axis(&p.points, [0.0; 3], X_AXIS);
        assert!((p_theta - l.x).abs() < 1e-12 * l.norm().max(1.0));
        assert!((p_theta - i_n * theta_dot).abs() < 1e-12 * p_theta.abs().max(1.0));
    }
}

#[test]
fn eq73_74_angular_acceleration_is_torque_over_moment() {
    let p = pendulum();
    let i_n = moment_about_axis(&p.points, [0.0; 3], X_AXIS);
    for (theta, theta_dot) in [(0.3, 1.7), (-1.2, -0.4), (2.5, 3.0)] {
        let rot = Rotation3::from_axis_angle(&nalgebra::Vector3::x_axis(), theta);
        // τ_n = n̂·Σ r_a × f_a with f_a = −m_a g ẑ (eq. 73).
        let tau: f64 = p
            .points
            .iter()
            .map(|&(m, b)| {
                (rot * v3(b))
                    .cross(&(nalgebra::Vector3::z() * (-m * p.g)))
                    .x
            })
            .sum();
        let acc = p.accelerations(&[theta], &[theta_dot], 0.0).unwrap()[0];
        assert!((i_n * acc - tau).abs() < 1e-12 * tau.abs().max(1.0));
    }
}

#[test]
fn eq67_70_small_oscillation_period_is_2pi_sqrt_i_over_mgd() {
    let p = pendulum();
    let (m, r_cm) = centre_of_mass(&p.points);
    let d = (r_cm[1].powi(2) + r_cm[2].powi(2)).sqrt();
    let i_cm = moment_about_axis(&p.points, r_cm, X_AXIS);
    let i_n = m * d * d + i_cm; // eq. 70, R_cm = perpendicular distance
    let period = 2.0 * PI * (i_n / (m * p.g * d)).sqrt();
    let theta0 = 1e-3; // finite-amplitude correction θ0²/16 = 6e-8
    let traj = Simulation::new(&p, [theta0], [0.0])
        .method(TIGHT)
        .until(10.5 * period)
        .event(Event::zero_crossing("θ = 0 downwards", |_t, q: &[f64; 1], _v| q[0]).falling())
        .run()
        .unwrap();
    let hits: Vec<f64> = traj.events.iter().map(|e| e.t).collect();
    assert_eq!(hits.len(), 11, "{hits:?}");
    let measured = (hits[10] - hits[0]) / 10.0;
    println!("physical pendulum: measured period {measured:.10}, 2π√(I/(Mgd)) = {period:.10}");
    assert!(
        (measured / period - 1.0).abs() < 1e-6,
        "measured {measured}, 2π√(I/(Mgd)) = {period}"
    );
    // The residual is the finite-amplitude correction T = T0 (1 + θ0²/16 + …).
    let corrected = period * (1.0 + theta0 * theta0 / 16.0);
    assert!(
        (measured / corrected - 1.0).abs() < 1e-9,
        "{measured} vs {corrected}"
    );
    // With |R_cm| in place of the perpendicular distance the prediction is 63 % off.
    let r = v3(r_cm).norm();
    let wrong = 2.0 * PI * ((m * r * r + i_cm) / (m * p.g * d)).sqrt();
    assert!(
        (wrong / measured - 1.0).abs() > 0.6,
        "{wrong} vs {measured}"
    );
}

// ---------------------------------------------------------------------------------------------
// B. Fixed-point rotation and the inertia tensor, eqs. 75–77
// ---------------------------------------------------------------------------------------------

fn lumpy_body() -> Vec<(f64, [f64; 3])> {
    vec![
        (1.0, [0.3, -1.2, 0.8]),
        (2.5, [1.1, 0.4, -0.2]),
        (0.7, [-0.9, 0.6, 1.5]),
        (1.8, [0.2, 1.3, 0.9]),
        (0.4, [-1.4, -0.7, -1.1]),
    ]
}

#[test]
fn eq75_76_kinetic_energy_and_angular_momentum_from_the_inertia_tensor() {
    let body = lumpy_body();
    let i = inertia_tensor(&body);
    assert!((i - i.transpose()).abs().max() < 1e-15);
    for w in [[0.3, -1.1, 2.0], [1.0, 0.0, 0.0], [-0.5, 0.8, 0.1]] {
        let w = v3(w);
        // T = Σ ½ m (ω × r)² = ½ ω·Î·ω (eq. 75); L = Σ m r × (ω × r) = Î·ω (eq. 78).
        let t: f64 = body
            .iter()
            .map(|&(m, r)| 0.5 * m * w.cross(&v3(r)).norm_squared())
            .sum();
        let l: nalgebra::Vector3<f64> = body
            .iter()
            .map(|&(m, r)| v3(r).cross(&w.cross(&v3(r))) * m)
            .sum();
        assert!((t - 0.5 * w.dot(&(i * w))).abs() < 1e-13 * t);
        assert!((l - i * w).norm() < 1e-13 * l.norm());
        // I_n = n̂·Î·n̂ (text after eq. 76) is eq. 69's moment about that axis.
        let n = w.normalize();
        let i_n = moment_about_axis(&body, [0.0; 3], w.into());
        assert!((i_n - n.dot(&(i * n))).abs() < 1e-13 * i_n);
    }
}

#[test]
fn eq77_shift_to_centre_of_mass_needs_the_kronecker_delta() {
    let body = lumpy_body();
    let (m, r) = centre_of_mass(&body);
    let about_origin = inertia_tensor(&body); // eq. 76 directly
    let relative: Vec<(f64, [f64; 3])> = body
        .iter()
        .map(|&(mi, ri)| (mi, [ri[0] - r[0], ri[1] - r[1], ri[2] - r[2]]))
        .collect();
    let about_cm = inertia_tensor(&relative);
    // Corrected eq. 77: I = M (R² δ_ij − R_i R_j) + I^(cm).
    let corrected = shift_from_centre_of_mass(m, r, &about_cm);
    assert!((corrected - about_origin).abs().max() < 1e-13 * about_origin.abs().max());
    // As printed: I = M [R² − R_i R_j] + I^(cm), R² added to every entry.
    let rv = v3(r);
    let printed = (Matrix3::repeat(rv.norm_squared()) - rv * rv.transpose()) * m + about_cm;
    let diff = printed - about_origin;
    // It is off by M R² in every off-diagonal entry, and right on the diagonal.
    for a in 0..3 {
        for b in 0..3 {
            let want = if a == b { 0.0 } else { m * rv.norm_squared() };
            assert!((diff[(a, b)] - want).abs() < 1e-12, "entry ({a},{b})");
        }
    }
    assert!(
        m * rv.norm_squared() > 0.1,
        "the test body must have its CM off the origin"
    );
    // Physically: for ω = (1, 1, 1)/√3 about the origin, the kinetic energy Σ ½ m (ω × r)² is
    // ½ ω·Î·ω with the corrected tensor and is missed by M R² with the printed one.
    let w = nalgebra::Vector3::repeat(1.0).normalize();
    let t_direct: f64 = body
        .iter()
        .map(|&(mi, ri)| 0.5 * mi * w.cross(&v3(ri)).norm_squared())
        .sum();
    assert!((0.5 * w.dot(&(corrected * w)) - t_direct).abs() < 1e-13 * t_direct);
    let t_printed = 0.5 * w.dot(&(printed * w));
    assert!((t_printed - t_direct - m * rv.norm_squared()).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------------
// C. Euler angles, Euler's equations, free tops, eqs. 81–91
// ---------------------------------------------------------------------------------------------

#[test]
fn euler_zxz_rates_are_the_body_angular_velocity() {
    // [ϖ]× = Rᵀ dR/dt, R = R_z(φ) R_x(θ) R_z(ψ), by central differences along q(t) = q0 + q̇ t.
    let q0 = [0.4, 1.1, -0.8];
    let v = [0.7, -1.3, 2.1];
    let h = 1e-5;
    let at = |t: f64| rotation_zxz(q0[0] + v[0] * t, q0[1] + v[1] * t, q0[2] + v[2] * t);
    let rdot = (at(h) - at(-h)) / (2.0 * h);
    let s = at(0.0).transpose() * rdot;
    let w_fd = [s[(2, 1)], s[(0, 2)], s[(1, 0)]];
    let w = body_angular_velocity_zxz(q0, v);
    for k in 0..3 {
        assert!(
            (w[k] - w_fd[k]).abs() < 1e-8,
            "ϖ{}: {} vs {}",
            k + 1,
            w[k],
            w_fd[k]
        );
    }
}

#[test]
fn eq81_85_body_angular_velocity_satisfies_eulers_equations_along_a_trajectory() {
    let top = FreeTop {
        i1: 3.0,
        i2: 2.0,
        i3: 1.0,
    };
    let ii = top.inertia();
    let (q0, v0) = start_at([0.2, 1.0, 0.6], [0.4, 0.9, -0.7]);
    let traj = Simulation::new(&top, q0, v0)
        .method(TIGHT)
        .until(10.0)
        .sample_every(0.05)
        .event(
            EulerChartGuard {
                theta_index: 1,
                min_sin: 1e-2,
            }
            .event(),
        )
        .run()
        .unwrap();
    assert!(traj.terminated_by.is_none());
    let mut worst: f64 = 0.0;
    for (q, v) in traj.q.iter().zip(&traj.qdot) {
        let a = top.accelerations(q, v, 0.0).unwrap();
        let (w, wd) = body_rates_and_derivative(*q, *v, a);
        // eqs. 83–85 with τ = 0.
        let res = [
            ii[0] * wd[0] - w[1] * w[2] * (ii[1] - ii[2]),
            ii[1] * wd[1] - w[2] * w[0] * (ii[2] - ii[0]),
            ii[2] * wd[2] - w[0] * w[1] * (ii[0] - ii[1]),
        ];
        let scale = ii[0] * v3(w).norm_squared();
        worst = worst.max(res.iter().map(|r| r.abs()).fold(0.0, f64::max) / scale);
    }
    println!("Euler's equations: worst relative residual {worst:.2e}");
    assert!(
        worst < 1e-12,
        "worst relative residual of Euler's equations {worst:e}"
    );

    // The same, with dϖ/dt by central differences of the sampled trajectory (h = 1e-3):
    // this checks the integrated trajectory, not only the equations of motion.
    let fine = Simulation::new(&top, q0, v0)
        .method(TIGHT)
        .until(2.0)
        .sample_every(1e-3)
        .run()
        .unwrap();
    let w: Vec<[f64; 3]> = fine
        .q
        .iter()
        .zip(&fine.qdot)
        .map(|(q, v)| body_angular_velocity_zxz(*q, *v))
        .collect();
    for k in 1..w.len() - 1 {
        let wd: [f64; 3] = std::array::from_fn(|i| (w[k + 1][i] - w[k - 1][i]) / 2e-3);
        let e = [
            ii[0] * wd[0] - w[k][1] * w[k][2] * (ii[1] - ii[2]),
            ii[1] * wd[1] - w[k][2] * w[k][0] * (ii[2] - ii[0]),
            ii[2] * wd[2] - w[k][0] * w[k][1] * (ii[0] - ii[1]),
        ];
        assert!(e.iter().all(|x| x.abs() < 1e-5), "t = {}: {e:?}", fine.t[k]);
    }
}

fn symmetric_top() -> FreeTop {
    FreeTop {
        i1: 1.0,
        i2: 1.0,
        i3: 1.5,
    }
}

#[test]
fn eq86_88_free_symmetric_top_body_rates_precess_at_omega() {
    let top = symmetric_top();
    let (w_perp, w3) = (0.3, 2.0);
    let omega = w3 * (top.i3 / top.i1 - 1.0); // = 1.0
    let (q0, v0) = start_at([0.3, 1.1, 0.7], [w_perp, 0.0, w3]);
    let traj = Simulation::new(&top, q0, v0)
        .method(TIGHT)
        .until(20.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    for ((t, q), v) in traj.t.iter().zip(&traj.q).zip(&traj.qdot) {
        let w = body_angular_velocity_zxz(*q, *v);
        assert!((w[2] - w3).abs() < 1e-10, "ϖ3 at t = {t}: {}", w[2]);
        // eq. 88 with ϖ' = 0.3 and the phase zero at t = 0.
        let (s, c) = (omega * t).sin_cos();
        assert!((w[0] - w_perp * c).abs() < 1e-9, "ϖ1 at t = {t}");
        assert!((w[1] - w_perp * s).abs() < 1e-9, "ϖ2 at t = {t}");
    }
}

#[test]
fn eq89_symmetry_axis_precesses_about_l_at_l_over_i1() {
    let top = symmetric_top();
    let (q0, v0) = start_at([0.3, 1.1, 0.7], [0.3, 0.0, 2.0]);
    let lab_l = |q: &[f64; 3], v: &[f64; 3]| {
        rotation_zxz(q[0], q[1], q[2]) * v3(top.l_body(body_angular_velocity_zxz(*q, *v)))
    };
    let l0 = lab_l(&q0, &v0);
    let rate = l0.norm() / top.i1;
    let n3_0 = rotation_zxz(q0[0], q0[1], q0[2]).column(2).into_owned();
    let traj = Simulation::new(&top, q0, v0)
        .method(TIGHT)
        .until(20.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    let axis = Unit::new_normalize(l0);
    for ((t, q), v) in traj.t.iter().zip(&traj.q).zip(&traj.qdot) {
        assert!(
            (lab_l(q, v) - l0).norm() < 1e-10 * l0.norm(),
            "L not fixed at t = {t}"
        );
        let n3 = rotation_zxz(q[0], q[1], q[2]).column(2).into_owned();
        let want = Rotation3::from_axis_angle(&axis, rate * t) * n3_0;
        assert!(
            (n3 - want).norm() < 1e-9,
            "n3 at t = {t}: {n3:?} vs {want:?}"
        );
    }
}

#[test]
fn eq90_91_asymmetric_top_conserves_l_squared_and_2e() {
    let top = FreeTop {
        i1: 3.0,
        i2: 2.0,
        i3: 1.0,
    };
    let (q0, v0) = start_at([0.2, 1.0, 0.6], [0.4, 0.9, -0.7]);
    let traj = Simulation::new(&top, q0, v0)
        .method(TIGHT)
        .until(50.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    let invariants = |q: &[f64; 3], v: &[f64; 3]| {
        let w = body_angular_velocity_zxz(*q, *v);
        let l = top.l_body(w);
        let ii = top.inertia();
        (
            l.iter().map(|x| x * x).sum::<f64>(),
            (0..3).map(|i| l[i] * l[i] / ii[i]).sum::<f64>(),
        )
    };
    let (l2_0, e2_0) = invariants(&q0, &v0);
    // 2E of eq. 91 is twice the Lagrangian's energy.
    assert!((e2_0 - 2.0 * top.energy(&q0, &v0, 0.0)).abs() < 1e-14 * e2_0);
    let mut drift: f64 = 0.0;
    for (q, v) in traj.q.iter().zip(&traj.qdot) {
        let (l2, e2) = invariants(q, v);
        drift = drift
            .max((l2 / l2_0 - 1.0).abs())
            .max((e2 / e2_0 - 1.0).abs());
    }
    println!("asymmetric top: relative drift of L² and 2E {drift:.2e}");
    assert!(drift < 1e-10, "relative drift of L² or 2E: {drift:e}");
    // The motion is not trivial: every component of ϖ changes by O(1).
    let w: Vec<[f64; 3]> = traj
        .q
        .iter()
        .zip(&traj.qdot)
        .map(|(q, v)| body_angular_velocity_zxz(*q, *v))
        .collect();
    for k in 0..3 {
        let (lo, hi) = w
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x[k]), b.max(x[k])));
        assert!(hi - lo > 0.3, "ϖ{} range {lo}..{hi}", k + 1);
    }
}

fn asymmetric() -> FreeTop {
    FreeTop {
        i1: 3.0,
        i2: 2.0,
        i3: 1.0,
    }
}

#[test]
fn eq90_91_rotation_about_the_intermediate_axis_grows_at_the_predicted_rate() {
    let top = asymmetric();
    let w2 = 1.0;
    // Linearised eqs. 83, 85 about ϖ = (0, ϖ2, 0): ϖ̇1 = a ϖ3, ϖ̇3 = b ϖ1, growth λ = √(ab)
    // = ϖ2 √((I1 − I2)(I2 − I3)/(I1 I3)); start on the growing eigenvector ϖ3 = (λ/a) ϖ1.
    let a = (top.i2 - top.i3) * w2 / top.i1;
    let b = (top.i1 - top.i2) * w2 / top.i3;
    let lambda = w2 * ((top.i1 - top.i2) * (top.i2 - top.i3) / (top.i1 * top.i3)).sqrt();
    assert!((lambda - (a * b).sqrt()).abs() < 1e-15);
    let eps = 1e-6;
    let (q0, v0) = start_with_lab_z_along_l(&top, [eps, w2, eps * lambda / a]);
    let traj = Simulation::new(&top, q0, v0)
        .method(TIGHT)
        .until(12.0)
        .sample_every(0.5)
        .run()
        .unwrap();
    let w1: Vec<f64> = traj
        .q
        .iter()
        .zip(&traj.qdot)
        .map(|(q, v)| body_angular_velocity_zxz(*q, *v)[0])
        .collect();
    let (i0, i1) = (4, traj.t.len() - 1); // t = 2 .. 12, ϖ1 from 7e-6 to 1e-3
    let measured = (w1[i1] / w1[i0]).ln() / (traj.t[i1] - traj.t[i0]);
    println!("intermediate axis: measured growth {measured:.8}, predicted {lambda:.8}");
    assert!(
        (measured / lambda - 1.0).abs() < 1e-6,
        "measured growth {measured}, predicted {lambda}"
    );
    assert!(w1[i1] > 500.0 * eps);
}

/// Largest |ϖ_j| (j ≠ axis) over a run started spinning about `axis` with a 1e-3 wobble.
fn wobble(axis: usize, t_end: f64) -> f64 {
    let top = asymmetric();
    let mut w = [1e-3; 3];
    w[axis] = 1.0;
    // Lab frame chosen so the chart stays regular: the spin axis is horizontal (θ = π/2 puts the
    // Euler body z axis, and for axis 1 and 2 the spin axis too, away from the lab z axis).
    let (q0, v0) = start_at([0.0, PI / 2.0, 0.3], w);
    let traj = Simulation::new(&top, q0, v0)
        .method(TIGHT)
        .until(t_end)
        .sample_every(0.05)
        .event(
            EulerChartGuard {
                theta_index: 1,
                min_sin: 1e-2,
            }
            .event(),
        )
        .run()
        .unwrap();
    assert!(traj.terminated_by.is_none());
    traj.q
        .iter()
        .zip(&traj.qdot)
        .map(|(q, v)| {
            let w = body_angular_velocity_zxz(*q, *v);
            (0..3)
                .filter(|&j| j != axis)
                .map(|j| w[j].abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

#[test]
fn eq90_91_rotation_about_the_largest_and_smallest_axes_is_stable() {
    // Stable: the wobble stays of the order of the initial 1e-3 (bounded by √(I_max/I_min)).
    let largest = wobble(0, 40.0);
    let smallest = wobble(2, 40.0);
    assert!(largest < 3e-3, "about I1: {largest}");
    assert!(smallest < 3e-3, "about I3: {smallest}");
    // Unstable, same run length: the wobble becomes O(1) (the body flips).
    let intermediate = wobble(1, 40.0);
    println!("wobble 1e-3 after t = 40: about I1 {largest:.2e}, I3 {smallest:.2e}, I2 {intermediate:.2e}");
    assert!(intermediate > 0.5, "about I2: {intermediate}");
}

// ---------------------------------------------------------------------------------------------
// The Euler-angle chart's singularity, sin θ = 0
// ---------------------------------------------------------------------------------------------

#[test]
fn euler_chart_singularity_is_a_typed_error_not_garbage() {
    let top = asymmetric();
    // At θ = 0, φ and ψ turn about the same axis: the mass matrix has rank 2.
    let err = top
        .accelerations(&[0.0, 0.0, 0.0], &[1.0, 0.0, 0.5], 0.0)
        .unwrap_err();
    assert!(
        matches!(err, DynamicsError::SingularMassMatrix { .. }),
        "{err}"
    );
    assert!(err.to_string().contains("sin θ = 0"), "{err}");
    // A run started there fails before its first step, with the same typed error inside.
    let run = Simulation::new(&top, [0.0, 0.0, 0.0], [1.0, 0.0, 0.5])
        .method(TIGHT)
        .until(1.0)
        .run();
    match run {
        Err(SimulationError::Dynamics { source, .. }) => {
            assert!(matches!(*source, DynamicsError::SingularMassMatrix { .. }))
        }
        other => panic!("expected a singular mass matrix, got {other:?}"),
    }
    // A steady spin about body axis 1 that carries the Euler z axis onto the lab z axis:
    // θ(t) = 0.8 − 1.0 t exactly (φ̇ = ψ̇ = 0), so sin θ = 0 at t = 0.8. The guard stops the run at
    // sin θ = 1e-3 and reports where.
    let guard = EulerChartGuard {
        theta_index: 1,
        min_sin: 1e-3,
    };
    let traj = Simulation::new(&top, [0.0, 0.8, 0.0], [0.0, -1.0, 0.0])
        .method(TIGHT)
        .until(2.0)
        .event(guard.event())
        .run()
        .unwrap();
    let err = guard.check(&traj).unwrap_err();
    let want_t = 0.8 - 1e-3_f64.asin();
    assert!(
        (err.t() - want_t).abs() < 1e-9,
        "guard at t = {}, want {want_t}",
        err.t()
    );
    match &err {
        DynamicsError::SingularMassMatrix { q, message, .. } => {
            assert!((q[1].sin() - 1e-3).abs() < 1e-9);
            assert!(message.contains("Euler-angle chart"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        traj.events.last().map(|e| e.direction),
        Some(Direction::Falling)
    );
    // The same run away from the pole passes the guard.
    let ok = Simulation::new(&top, [0.0, 1.5, 0.0], [0.0, -0.1, 0.0])
        .method(TIGHT)
        .until(2.0)
        .event(guard.event())
        .run()
        .unwrap();
    assert!(guard.check(&ok).is_ok());
    // θ outside (0, π) (the same orientation as (φ + π, −θ, ψ + π)) is refused, not silently run.
    let outside = Simulation::new(&top, [0.0, -0.5, 0.0], [0.0, 0.1, 0.0])
        .method(TIGHT)
        .until(0.1)
        .event(guard.event())
        .run()
        .unwrap();
    assert!(matches!(
        guard.check(&outside),
        Err(DynamicsError::SingularMassMatrix { .. })
    ));
}
