//! The two declarations of the macro contract (the heavy top with three scalar coordinates, a
//! particle with a vector coordinate and explicit time), their constants and accelerations
//! against hand-derived equations, plus declarations at the contract's edges: methods of `self`,
//! `macro_rules!`-written impls and constants from the user's scope.

use lagrange::prelude::*;

// The first declaration, the symmetric heavy top of eq. (92), is the shared one in
// examples/support/systems.rs, written exactly as the contract text writes it.
use crate::support::systems::HeavyTop;
use crate::support::Rng;

/// A vector coordinate and explicit time.
pub struct Spinning {
    pub m: f64,
    pub k: f64,
    pub w: f64,
    pub gravity: Vector3<f64>,
}

#[lagrangian]
impl Spinning {
    fn lagrangian(&self, (r, r_dot): Coord3, t: Time) -> Scalar {
        let omega = Vector3::new(0.0, 0.0, self.w * (1.0 + 0.1 * t.sin()));
        let v = r_dot + omega.cross(&r);
        self.m / 2.0 * v.norm_squared() - 0.5 * self.k * r.norm_squared()
            + self.m * self.gravity.dot(&r)
    }
}

fn assert_close(got: &[f64], want: &[f64], rel: f64, ctx: &str) {
    let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() <= rel * scale,
            "{ctx}: got {got:?}, want {want:?}"
        );
    }
}

#[test]
fn heavy_top_constants() {
    assert_eq!(
        <HeavyTop as Lagrangian<3>>::COORDINATES,
        ["theta", "phi", "psi"]
    );
    assert_eq!(<HeavyTop as Lagrangian<3>>::CYCLIC, [false, true, true]);
    const { assert!(<HeavyTop as Lagrangian<3>>::AUTONOMOUS) };
}

#[test]
fn spinning_constants() {
    assert_eq!(
        <Spinning as Lagrangian<3>>::COORDINATES,
        ["r.x", "r.y", "r.z"]
    );
    assert_eq!(<Spinning as Lagrangian<3>>::CYCLIC, [false; 3]);
    const { assert!(!<Spinning as Lagrangian<3>>::AUTONOMOUS) };
}

#[test]
fn heavy_top_matches_closed_form() {
    let mut rng = Rng(12345);
    for _ in 0..2000 {
        let top = HeavyTop {
            i_perp: rng.uniform(0.2, 3.0),
            i_par: rng.uniform(0.1, 3.0),
            m: rng.uniform(0.1, 2.0),
            g: 9.81,
            l: rng.uniform(-1.0, 1.0),
        };
        let q = [
            rng.uniform(0.05, 3.09),
            rng.uniform(-7.0, 7.0),
            rng.uniform(-7.0, 7.0),
        ];
        let qd = [
            rng.uniform(-10.0, 10.0),
            rng.uniform(-10.0, 10.0),
            rng.uniform(-30.0, 30.0),
        ];
        let (s, c) = q[0].sin_cos();
        let mgl = top.m * top.g * top.l;
        let w3 = qd[2] + qd[1] * c;
        let th =
            qd[1] * qd[1] * s * c - top.i_par / top.i_perp * w3 * qd[1] * s + mgl / top.i_perp * s;
        let ph = qd[0] * (top.i_par * w3 - 2.0 * top.i_perp * qd[1] * c) / (top.i_perp * s);
        let ps = qd[1] * qd[0] * s - ph * c;
        let got = top.accelerations(&q, &qd, 0.0).unwrap();
        assert_close(&got, &[th, ph, ps], 1e-12, "heavy top");
    }
}

#[test]
fn spinning_matches_closed_form() {
    // m r̈ = −m Ω̇×r − 2m Ω×ṙ − m Ω×(Ω×r) − k r + m g, with Ω = (0, 0, w(1 + 0.1 sin t)).
    let mut rng = Rng(999);
    for _ in 0..2000 {
        let sys = Spinning {
            m: rng.uniform(0.1, 3.0),
            k: rng.uniform(0.0, 5.0),
            w: rng.uniform(-3.0, 3.0),
            gravity: Vector3::new(rng.uniform(-1.0, 1.0), 0.3, -9.81),
        };
        let r = Vector3::new(
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
        );
        let v = Vector3::new(
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
        );
        let t = rng.uniform(0.0, 20.0);
        let om = Vector3::new(0.0, 0.0, sys.w * (1.0 + 0.1 * t.sin()));
        let om_dot = Vector3::new(0.0, 0.0, sys.w * 0.1 * t.cos());
        let a =
            -om_dot.cross(&r) - 2.0 * om.cross(&v) - om.cross(&om.cross(&r)) - sys.k / sys.m * r
                + sys.gravity;
        let got = sys
            .accelerations(&[r.x, r.y, r.z], &[v.x, v.y, v.z], t)
            .unwrap();
        assert_close(&got, &[a.x, a.y, a.z], 1e-12, "spinning");
    }
}

/// A rotating frame whose rate is a method of the system: `self.omega(t)` with a time-dependent
/// argument (jets mode: the symbolic lowering does not call user functions).
pub struct Carousel {
    pub w: f64,
}

impl Carousel {
    fn omega<S: Scalar>(&self, t: S) -> Vector3<S> {
        Vector3::new(S::constant(0.0), S::constant(0.0), t.sin() * self.w)
    }
}

#[lagrangian(mode = "jets")]
impl Carousel {
    fn lagrangian(&self, (r, r_dot): Coord3, t: Time) -> Scalar {
        let v = r_dot + self.omega(t).cross(&r);
        0.5 * v.norm_squared()
    }
}

#[test]
fn methods_of_self_take_coordinate_arguments() {
    let c = Carousel { w: 0.7 };
    let (r, v, t) = (
        Vector3::new(0.3, -0.2, 0.5),
        Vector3::new(0.1, 0.4, -0.3),
        1.3_f64,
    );
    let om = Vector3::new(0.0, 0.0, c.w * t.sin());
    let om_dot = Vector3::new(0.0, 0.0, c.w * t.cos());
    let a = -om_dot.cross(&r) - 2.0 * om.cross(&v) - om.cross(&om.cross(&r));
    let got = c
        .accelerations(&[r.x, r.y, r.z], &[v.x, v.y, v.z], t)
        .unwrap();
    assert_close(&got, &[a.x, a.y, a.z], 1e-12, "carousel");
}

/// `#[lagrangian]` on an impl block that a `macro_rules!` writes: `self` in the body must resolve.
macro_rules! oscillator {
    ($name:ident, $mode:literal) => {
        pub struct $name {
            pub k: f64,
        }
        #[lagrangian(mode = $mode)]
        impl $name {
            fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
                0.5 * x_dot * x_dot - 0.5 * self.k * x * x
            }
        }
    };
}
oscillator!(OscJets, "jets");
oscillator!(OscSymbolic, "symbolic");

#[test]
fn declarations_inside_macro_rules_work_in_both_modes() {
    assert_eq!(
        OscJets { k: 4.0 }
            .accelerations(&[0.5], &[0.0], 0.0)
            .unwrap(),
        [-2.0]
    );
    assert_eq!(
        OscSymbolic { k: 4.0 }
            .accelerations(&[0.5], &[0.0], 0.0)
            .unwrap(),
        [-2.0]
    );
}

/// Constants from the user's scope (`const`, imported `PI`) in the default symbolic mode.
const STIFFNESS: f64 = 3.0;
use std::f64::consts::PI;
pub struct ScopedConstants;

#[lagrangian]
impl ScopedConstants {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot.powi(2) - 0.5 * STIFFNESS * x.powi(2) + PI * x
    }
}

#[test]
fn names_from_the_users_scope_are_constants() {
    let a = ScopedConstants.accelerations(&[0.5], &[0.0], 0.0).unwrap();
    assert!((a[0] - (-STIFFNESS * 0.5 + std::f64::consts::PI)).abs() < 1e-15);
}

/// A plane pendulum in x, y held by its rod, for the contract of the constrained method.
pub struct RodPendulum;

#[lagrangian]
impl RodPendulum {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * (x_dot * x_dot + y_dot * y_dot) - 9.81 * y
    }
    fn constraints(&self, (x, _x_dot): Coord, (y, _y_dot): Coord) -> [Scalar; 1] {
        [x * x + y * y - 1.0]
    }
}

/// A plane pendulum in its angle (no neutral coordinate: an isolated equilibrium at θ = 0).
pub struct AnglePendulum;

#[lagrangian]
impl AnglePendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * theta_dot * theta_dot + theta.cos()
    }
}

/// The public API the "One body for every kernel" issue names as its contract, used as a user
/// does with the prelude alone: every `Lagrangian` method users call by method syntax
/// (`linearize` and `equilibrium` among them), `Simulation`, `Method`, `Ensemble`, `Member`,
/// `Trajectory` and the error types.
#[test]
fn the_contract_of_the_kernel_redesign_as_a_user_writes_it() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    let (q, qdot) = ([1.0, 0.0, 0.0], [0.0, -0.5, 8.0]);
    let a: Result<[f64; 3], DynamicsError> = top.accelerations(&q, &qdot, 0.0);
    let a = a.expect("a regular state");
    let m: SMatrix<f64, 3, 3> = top.mass_matrix(&q, &qdot, 0.0);
    let p: [f64; 3] = top.momenta(&q, &qdot, 0.0);
    let h: f64 = top.energy(&q, &qdot, 0.0);
    let (h2, p2) = top.energy_and_momenta(&q, &qdot, 0.0);
    let w: f64 = top.power(&q, &qdot, 0.0);
    let pieces = top.pieces(&q, &qdot, 0.0);
    assert_eq!((h2, p2), (h, p));
    assert_eq!(w, 0.0);
    assert!((pieces.mass_entry(0, 0) - m[(0, 0)]).abs() < 1e-15);
    // M q̈ = f: the pieces' right-hand side at the accelerations.
    let f = pieces.rhs();
    for i in 0..3 {
        let mq: f64 = (0..3).map(|k| m[(i, k)] * a[k]).sum();
        assert!((mq - f[i]).abs() < 1e-12, "row {i}");
    }
    // The top hanging straight down (θ = π) is an equilibrium, stable in θ.
    let lin: Linearization<3> = top
        .linearize(&[std::f64::consts::PI, 0.0, 0.0], &[0.0, 0.0, 0.0], 0.0)
        .expect("a regular state");
    assert!(lin.k[(0, 0)] > 0.0);
    // (The top's φ and ψ are neutral: `equilibrium` asks for an isolated one.)
    let eq: Result<[f64; 1], LinearizationError> = AnglePendulum.equilibrium(&[0.3], 0.0);
    assert!(eq.expect("an equilibrium near θ = 0.3")[0].abs() < 1e-12);
    let (qdd, lambda) = RodPendulum
        .constrained_accelerations(&[1.0, 0.0], &[0.0, 0.0], 0.0)
        .expect("a regular state");
    assert!((qdd[1] + 9.81).abs() < 1e-12 && lambda[0].abs() < 1e-12);
    let tr: Result<Trajectory<3>, SimulationError> = Simulation::new(&top, q, qdot)
        .method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-10,
        })
        .until(1.0)
        .run();
    assert!(tr.expect("a regular run").t.len() > 1);
    let r = Ensemble::new(2, |i| {
        Member::new(top, [1.0 + 0.1 * i as f64, 0.0, 0.0], qdot)
    })
    .configure(|sim| sim.until(0.5))
    .run();
    assert_eq!(r.failures(), 0);
}
