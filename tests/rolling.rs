//! Velocity (nonholonomic) constraints, `fn velocity_constraints`: a thin disc rolling without
//! slipping, written twice — from its geometry (`velocity` of the centre, the angular velocity
//! of its rotation: the contact point of the disc does not slide) in symbolic mode, and from the
//! rolling conditions ẋ = r ψ̇ cos φ, ẏ = r ψ̇ sin φ in jets mode — against each other and
//! against closed forms: steady rolling on a circle (the relation between lean, turning rate and
//! speed), the upright disc's stability threshold ψ̇² = g/(3r) and the growth and oscillation
//! rates on either side of it; energy conserved (rolling does no work) and the constraints held.

use lagrange::prelude::*;

/// A thin uniform disc of mass m and radius r on the ground z = 0: (x, y) the contact point,
/// φ the heading, θ the lean (rotation about the rolling direction), ψ the spin about the axle.
pub struct Disc {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[lagrangian]
impl Disc {
    fn lagrangian(
        &self,
        (x, _x_dot): Coord,
        (y, _y_dot): Coord,
        (phi, _phi_dot): Coord,
        (theta, _theta_dot): Coord,
        (psi, _psi_dot): Coord,
    ) -> Scalar {
        let frame = Rotation::about_z(phi) * Rotation::about_x(theta);
        let body = frame * Rotation::about_y(psi);
        let center = Vector3::new(x, y, 0.0) + frame * Vector3::new(0.0, 0.0, self.r);
        let v = velocity(center);
        let w = body_angular_velocity(&body);
        // About a diameter m r²/4, about the axle m r²/2.
        let (a, c) = (
            0.25 * self.m * self.r * self.r,
            0.5 * self.m * self.r * self.r,
        );
        0.5 * self.m * v.norm_squared() + 0.5 * (a * (w.x * w.x + w.z * w.z) + c * w.y * w.y)
            - self.m * self.g * center.z
    }
    /// The disc's material point at the contact does not slide.
    fn velocity_constraints(
        &self,
        (x, _): Coord,
        (y, _): Coord,
        (phi, _): Coord,
        (theta, _): Coord,
        (psi, _): Coord,
    ) -> [Scalar; 2] {
        let frame = Rotation::about_z(phi) * Rotation::about_x(theta);
        let body = frame * Rotation::about_y(psi);
        let arm = frame * Vector3::new(0.0, 0.0, self.r);
        let center = Vector3::new(x, y, 0.0) + arm;
        let slip = velocity(center) - angular_velocity(&body).cross(&arm);
        [slip.x, slip.y]
    }
}

/// The same disc in jets mode, its rolling conditions written out.
pub struct JetsDisc {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl JetsDisc {
    fn lagrangian(
        &self,
        (x, _x_dot): Coord,
        (y, _y_dot): Coord,
        (phi, _phi_dot): Coord,
        (theta, _theta_dot): Coord,
        (psi, _psi_dot): Coord,
    ) -> Scalar {
        let frame = Rotation::about_z(phi) * Rotation::about_x(theta);
        let body = frame * Rotation::about_y(psi);
        let center = Vector3::new(x, y, 0.0) + frame * Vector3::new(0.0, 0.0, self.r);
        let v = velocity(center);
        let w = body_angular_velocity(&body);
        let (a, c) = (
            0.25 * self.m * self.r * self.r,
            0.5 * self.m * self.r * self.r,
        );
        0.5 * self.m * v.norm_squared() + 0.5 * (a * (w.x * w.x + w.z * w.z) + c * w.y * w.y)
            - self.m * self.g * center.z
    }
    fn velocity_constraints(
        &self,
        (_, x_dot): Coord,
        (_, y_dot): Coord,
        (phi, _): Coord,
        (_, _): Coord,
        (_, psi_dot): Coord,
    ) -> [Scalar; 2] {
        [
            x_dot - self.r * psi_dot * phi.cos(),
            y_dot - self.r * psi_dot * phi.sin(),
        ]
    }
}

const M: f64 = 1.3;
const R: f64 = 0.5;
const G: f64 = 9.81;

/// A state on the rolling constraints: the contact point moves at r ψ̇ along the heading.
fn rolling(q: [f64; 5], rates: [f64; 3]) -> ([f64; 5], [f64; 5]) {
    let [phi_dot, theta_dot, psi_dot] = rates;
    let v = [
        R * psi_dot * q[2].cos(),
        R * psi_dot * q[2].sin(),
        phi_dot,
        theta_dot,
        psi_dot,
    ];
    (q, v)
}

#[test]
fn geometry_and_written_out_rolling_conditions_agree() {
    let (d, j) = (Disc { m: M, r: R, g: G }, JetsDisc { m: M, r: R, g: G });
    const { assert!(<Disc as Holonomic<5, 2>>::SCLERONOMIC) };
    const { assert!(<Disc as Holonomic<5, 2>>::VELOCITY_ROWS == 2) };
    let states = [
        ([0.3, -0.2, 0.7, 0.25, 1.1], [0.4, -0.3, 2.0]),
        ([1.0, 2.0, -1.3, -0.6, 0.2], [-1.2, 0.8, -3.5]),
        ([0.0, 0.0, 2.5, 0.9, -2.0], [0.1, 0.05, 0.7]),
    ];
    for (q, rates) in states {
        let (q, v) = rolling(q, rates);
        let rows_d = d.constraint_rows(&q, &v, 0.0);
        let rows_j = j.constraint_rows(&q, &v, 0.0);
        for k in 0..2 {
            assert!(rows_d.rate[k].abs() < 1e-14 && rows_j.rate[k].abs() < 1e-14);
        }
        let (a_d, l_d) = d.constrained_accelerations(&q, &v, 0.0).unwrap();
        let (a_j, l_j) = j.constrained_accelerations(&q, &v, 0.0).unwrap();
        for i in 0..5 {
            assert!(
                (a_d[i] - a_j[i]).abs() < 1e-12 * (1.0 + a_j[i].abs()),
                "q̈{i}: {a_d:?} vs {a_j:?}"
            );
        }
        // The rows differ by a factor (the geometric slip is the written-out one in the
        // ground frame), so the forces Aᵀλ agree, not λ.
        for i in 0..5 {
            let f_d: f64 = (0..2).map(|k| rows_d.jacobian[k][i] * l_d[k]).sum();
            let f_j: f64 = (0..2).map(|k| rows_j.jacobian[k][i] * l_j[k]).sum();
            assert!(
                (f_d - f_j).abs() < 1e-11 * (1.0 + f_j.abs()),
                "force {i}: {f_d} vs {f_j}"
            );
        }
    }
}

#[test]
fn steady_rolling_on_a_circle() {
    // Lean θ, turning rate Ω = φ̇, spin ψ̇ = s, n = Ω sin θ + s (the centre moves at r n): the
    // balance of angular momentum about the centre,
    // A Ω² sin θ cos θ − (C + m r²) n Ω cos θ = m g r sin θ (A = m r²/4, C = m r²/2),
    // derived by hand in the heading frame, gives n for θ and Ω.
    let (theta, omega) = (0.3_f64, 3.0_f64);
    let n = (0.25 * R * omega * omega * theta.sin() * theta.cos() - G * theta.sin())
        / (1.5 * R * omega * theta.cos());
    let s = n - omega * theta.sin();
    for (name, a) in [
        ("symbolic", {
            let (q, v) = rolling([0.0, 0.0, 0.0, theta, 0.0], [omega, 0.0, s]);
            Disc { m: M, r: R, g: G }
                .constrained_accelerations(&q, &v, 0.0)
                .unwrap()
                .0
        }),
        ("jets", {
            let (q, v) = rolling([0.0, 0.0, 0.0, theta, 0.0], [omega, 0.0, s]);
            JetsDisc { m: M, r: R, g: G }
                .constrained_accelerations(&q, &v, 0.0)
                .unwrap()
                .0
        }),
    ] {
        // φ̈ = θ̈ = ψ̈ = 0: a steady motion.
        for i in 2..5 {
            assert!(a[i].abs() < 1e-12, "{name}: q̈ = {a:?}");
        }
    }
    // And the run stays on it: the contact point on a circle of radius |r s/Ω|.
    let disc = Disc { m: M, r: R, g: G };
    let (q0, v0) = rolling([0.0, 0.0, 0.0, theta, 0.0], [omega, 0.0, s]);
    let tr = Simulation::constrained(&disc, q0, v0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(2.0)
        .sample_every(0.1)
        .run()
        .unwrap();
    let radius = (R * s / omega).abs();
    // The circle's centre: a quarter turn from the heading, on the side the disc leans to.
    let centre = [0.0, R * s / omega];
    for (i, q) in tr.q.iter().enumerate() {
        assert!(
            (q[3] - theta).abs() < 1e-8,
            "t = {}: lean {}",
            tr.t[i],
            q[3]
        );
        let d = ((q[0] - centre[0]).powi(2) + (q[1] - centre[1]).powi(2)).sqrt();
        assert!(
            (d - radius).abs() < 1e-8,
            "t = {}: {d} vs {radius}",
            tr.t[i]
        );
    }
    let inv = tr.invariants();
    assert!(inv.energy.unwrap().max_abs < 1e-10);
    assert!(inv.constraints.unwrap().velocity < 1e-12);
}

#[test]
fn upright_disc_is_stable_above_its_threshold_spin() {
    // Upright rolling at spin n: θ̈ = (4/5)(g/r − 3n²) θ, the lean equation with the heading
    // rate Ω = −(C/A) n θ eliminated (angular momentum about the vertical). The threshold is
    // n² = g/(3r); from θ = 0, θ̇ = ε the lean is ε sinh(σt)/σ below it, ε sin(ωt)/ω above.
    let eps = 1e-6;
    for (factor, grows) in [(0.8, true), (1.2, false)] {
        let n: f64 = (factor * G / (3.0 * R)).sqrt();
        let lambda = 0.8 * (G / R - 3.0 * n * n);
        let rate = lambda.abs().sqrt();
        for run in [0, 1] {
            let (q0, v0) = rolling([0.0; 5], [0.0, eps, n]);
            let t_end = 2.0;
            let method = Method::Dop853 {
                rtol: 1e-12,
                atol: 1e-16,
            };
            let tr = if run == 0 {
                Simulation::constrained(&Disc { m: M, r: R, g: G }, q0, v0)
                    .method(method)
                    .until(t_end)
                    .sample_every(0.5)
                    .run()
                    .unwrap()
            } else {
                Simulation::constrained(&JetsDisc { m: M, r: R, g: G }, q0, v0)
                    .method(method)
                    .until(t_end)
                    .sample_every(0.5)
                    .run()
                    .unwrap()
            };
            for (i, &t) in tr.t.iter().enumerate() {
                let want = if grows {
                    eps * (rate * t).sinh() / rate
                } else {
                    eps * (rate * t).sin() / rate
                };
                let scale = eps * (rate * t).cosh() / rate;
                assert!(
                    (tr.q[i][3] - want).abs() < 1e-5 * scale,
                    "n² = {factor} g/3r, t = {t}: θ = {} vs {want}",
                    tr.q[i][3]
                );
            }
        }
    }
}

#[test]
fn variational_method_refuses_velocity_constraints() {
    let disc = Disc { m: M, r: R, g: G };
    let (q0, v0) = rolling([0.0; 5], [0.0, 0.0, 3.0]);
    let err = Simulation::constrained(&disc, q0, v0)
        .method(Method::VariationalMidpoint { dt: 0.01 })
        .until(1.0)
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("velocity (nonholonomic)"), "{err}");
    // And linearize refuses the constrained system (the manifold linearization is separate).
    assert!(matches!(
        disc.linearize(&q0, &v0, 0.0),
        Err(DynamicsError::Constrained { .. })
    ));
}

/// A knife edge (a skate) on a plane inclined at α, in space coordinates (X downhill
/// horizontal, Y across, Z up) with the plane as a holonomic constraint Z = −X tan α and the
/// blade's no-sideslip condition as a velocity constraint: both kinds in one system.
pub struct Skate {
    pub m: f64,
    pub i: f64,
    pub g: f64,
    pub alpha: f64,
}

#[lagrangian]
impl Skate {
    fn lagrangian(
        &self,
        (_x, x_dot): Coord,
        (_y, y_dot): Coord,
        (z, z_dot): Coord,
        (_phi, phi_dot): Coord,
    ) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot + z_dot * z_dot)
            + 0.5 * self.i * phi_dot * phi_dot
            - self.m * self.g * z
    }
    fn constraints(
        &self,
        (x, _): Coord,
        (_, _): Coord,
        (z, _): Coord,
        (_, _): Coord,
    ) -> [Scalar; 1] {
        [z + x * self.alpha.tan()]
    }
    /// No sideslip: the velocity across the blade (heading φ in the plane, measured from the
    /// downhill direction) vanishes; the downhill speed in the plane is Ẋ / cos α.
    fn velocity_constraints(
        &self,
        (_, x_dot): Coord,
        (_, y_dot): Coord,
        (_, _): Coord,
        (phi, _): Coord,
    ) -> [Scalar; 1] {
        [y_dot * phi.cos() - x_dot / self.alpha.cos() * phi.sin()]
    }
}

#[test]
fn knife_edge_on_an_incline_against_its_closed_form() {
    // Released at rest with the blade downhill and spinning at ω: φ = ωt, and along the slope
    // s = (g sin α / 2ω²) sin² ωt, across y = (g sin α / 2ω)(t − sin 2ωt / 2ω) (Neimark–Fufaev).
    let (alpha, omega) = (0.3_f64, 1.7_f64);
    let skate = Skate {
        m: 2.0,
        i: 0.4,
        g: G,
        alpha,
    };
    const { assert!(<Skate as Holonomic<4, 2>>::VELOCITY_ROWS == 1) };
    const { assert!(<Skate as Holonomic<4, 2>>::SCLERONOMIC) };
    assert_eq!(
        <Skate as Holonomic<4, 2>>::CONSTRAINED_COORDINATES,
        [true, true, true, true]
    );
    let tr = Simulation::constrained(&skate, [0.0; 4], [0.0, 0.0, 0.0, omega])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(6.0)
        .sample_every(0.25)
        .run()
        .unwrap();
    let k = G * alpha.sin();
    for (i, &t) in tr.t.iter().enumerate() {
        let s = k / (2.0 * omega * omega) * (omega * t).sin().powi(2);
        let y = k / (2.0 * omega) * (t - (2.0 * omega * t).sin() / (2.0 * omega));
        let q = tr.q[i];
        assert!(
            (q[0] - s * alpha.cos()).abs() < 1e-9,
            "t = {t}: X = {} vs {}",
            q[0],
            s * alpha.cos()
        );
        assert!((q[2] + s * alpha.sin()).abs() < 1e-9, "t = {t}: Z");
        assert!((q[1] - y).abs() < 1e-9, "t = {t}: Y = {} vs {y}", q[1]);
        assert!((q[3] - omega * t).abs() < 1e-9);
    }
    let inv = tr.invariants();
    assert!(inv.energy.unwrap().max_abs < 1e-10);
    let c = inv.constraints.unwrap();
    assert!(c.position < 1e-13 && c.velocity < 1e-12, "{c:?}");
    // Two multipliers per sample: the plane's normal force and the blade's side force.
    assert_eq!(tr.lambda[0].len(), 2);
}

#[test]
fn upright_disc_linearized_on_its_constraints() {
    // The same threshold from the linearization on the constraint manifold: in the lean θ
    // with the speeds θ̇ and φ̇ (the heading's angle is ignorable, its rate is not), the
    // eigenvalues are 0 and ±√((4/5)(g/r − 3n²)), in both modes.
    for factor in [0.8, 1.2, 2.0] {
        let n: f64 = (factor * G / (3.0 * R)).sqrt();
        let (q0, v0) = rolling([0.0; 5], [0.0, 0.0, n]);
        let want = 0.8 * (G / R - 3.0 * n * n);
        let eig_d = Disc { m: M, r: R, g: G }
            .linearize_on_constraints(&q0, &v0, 0.0)
            .unwrap()
            .eigenvalues(&["theta"], &["theta", "phi"])
            .unwrap();
        let eig_j = JetsDisc { m: M, r: R, g: G }
            .linearize_on_constraints(&q0, &v0, 0.0)
            .unwrap()
            .eigenvalues(&["theta"], &["theta", "phi"])
            .unwrap();
        for eig in [eig_d, eig_j] {
            assert_eq!(eig.len(), 3);
            let s = want.abs().sqrt();
            let (hi, mid, lo) = (eig[0], eig[1], eig[2]);
            if want > 0.0 {
                assert!(
                    (hi.re - s).abs() < 1e-10 && (lo.re + s).abs() < 1e-10,
                    "{eig:?}"
                );
                assert!(mid.norm() < 1e-10);
            } else {
                // ±iω and 0, all on the imaginary axis.
                assert!(eig.iter().all(|l| l.re.abs() < 1e-10), "{eig:?}");
                assert!(eig.iter().any(|l| (l.im - s).abs() < 1e-10), "{eig:?}");
            }
        }
    }
    // The spin's angle is not a coordinate that closes the lean's equations on its own:
    // without φ̇ the heading rate drives θ̈, and the reduction says so.
    let (q0, v0) = rolling([0.0; 5], [0.0, 0.0, 3.0]);
    let lin = Disc { m: M, r: R, g: G }
        .linearize_on_constraints(&q0, &v0, 0.0)
        .unwrap();
    let err = lin.state_matrix(&["theta"], &["theta"]).unwrap_err();
    assert!(err.to_string().contains("phi"), "{err}");
}

/// A cart-pole: the cart (mass `cart`) pushed along x by its field `push`, a bob (mass `bob`)
/// on a massless rod of length l, θ from the upward vertical.
pub struct CartPole {
    pub cart: f64,
    pub bob: f64,
    pub l: f64,
    pub g: f64,
    pub push: f64,
}

#[lagrangian]
impl CartPole {
    fn lagrangian(&self, (_x, x_dot): Coord, (theta, theta_dot): Coord) -> Scalar {
        0.5 * (self.cart + self.bob) * x_dot * x_dot
            + self.bob * self.l * x_dot * theta_dot * theta.cos()
            + 0.5 * self.bob * self.l * self.l * theta_dot * theta_dot
            - self.bob * self.g * self.l * theta.cos()
    }
    fn forces(&self, (_, _): Coord, (_, _): Coord) -> [Scalar; 2] {
        [self.push, 0.0]
    }
}

#[test]
fn cart_pole_gets_its_state_and_input_matrices() {
    // Upright: (M + m) ẍ + m l θ̈ = u, m l ẍ + m l² θ̈ − m g l θ = 0.
    let (mc, mb, l, g) = (2.0, 0.5, 0.8, 9.81);
    let make = |u: &[f64; 1]| CartPole {
        cart: mc,
        bob: mb,
        l,
        g,
        push: u[0],
    };
    let lin = make(&[0.0]).linearize(&[0.0; 2], &[0.0; 2], 0.0).unwrap();
    let b = lagrange::linearize::input_matrix(make, &[0.0], &[0.0; 2], &[0.0; 2], 0.0).unwrap();
    let want_m = [[mc + mb, mb * l], [mb * l, mb * l * l]];
    for (i, row) in want_m.iter().enumerate() {
        for (j, want) in row.iter().enumerate() {
            assert!((lin.m[(i, j)] - want).abs() < 1e-14);
        }
    }
    assert!((lin.k[(1, 1)] + mb * g * l).abs() < 1e-13 && lin.k[(0, 0)] == 0.0);
    assert_eq!((b[(0, 0)], b[(1, 0)]), (1.0, 0.0));
    // The first-order (A, B): B_state = (0, M⁻¹ B); the pole falls at √((M + m) g/(M l)).
    let minv = lin.m.try_inverse().unwrap();
    let bs = minv * b;
    assert!((bs[(0, 0)] - 1.0 / mc).abs() < 1e-14 && (bs[(1, 0)] + 1.0 / (mc * l)).abs() < 1e-14);
    let eig = lin.eigenvalues().unwrap();
    let rate = ((mc + mb) * g / (mc * l)).sqrt();
    assert!((eig[0].re - rate).abs() < 1e-12, "{eig:?}");
}
