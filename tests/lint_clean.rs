//! Macro uses compile cleanly under `#![deny(warnings)]` (checked by `cargo test`) and
//! `#![deny(clippy::pedantic)]` (checked by `cargo clippy --workspace --all-targets -- -D warnings`):
//! cyclic coordinates, an unused `t: Time`, `Coord3`, doc comments, `pub` and private structs,
//! derives and other items in the impl block, `fn dissipation`, `fn forces` and `fn constraints`
//! with bindings their bodies do not use, and a system of more than 32 coordinates (its code in
//! modules next to the impl).
#![deny(warnings)]
#![deny(clippy::pedantic)]

use lagrange::prelude::*;

/// Symmetric heavy top, φ and ψ cyclic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeavyTop {
    /// Transverse moment of inertia.
    pub i_perp: f64,
    /// Axial moment of inertia.
    pub i_par: f64,
    /// m g l.
    pub mgl: f64,
}

#[lagrangian]
impl HeavyTop {
    /// Eq. (92) of the reference text.
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let (s, c) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
            - self.mgl * c
    }

    /// Another item in the impl block, kept as written.
    #[must_use]
    pub fn spin(&self, precession: f64, rotation: f64, theta: f64) -> f64 {
        self.i_par * (rotation + precession * theta.cos())
    }
}

/// A private struct with a vector coordinate and a time parameter it never uses.
#[derive(Default)]
struct Trapped {
    k: f64,
    gravity: Vector3<f64>,
}

#[lagrangian]
impl Trapped {
    fn lagrangian(&self, (r, r_dot): Coord3, t: Time) -> Scalar {
        0.5 * r_dot.norm_squared() - self.k / 2.0 * r.norm_squared() + self.gravity.dot(&r)
    }
}

/// Explicit time, an `if` on a field, and a private field.
pub struct Driven {
    amplitude: f64,
    /// Drive frequency.
    pub w: f64,
}

// `if` on a parameter: the symbolic default derives both branches (the condition is a constant).
#[lagrangian]
impl Driven {
    #[allow(clippy::suboptimal_flops)]
    fn lagrangian(&self, (x, x_dot): Coord, t: Time) -> Scalar {
        let force = if self.amplitude > 0.0 {
            self.amplitude * (self.w * t).cos()
        } else {
            0.0
        };
        x_dot * x_dot / 2.0 - x * x / 2.0 + force * x
    }
}

/// Everything cyclic: a free particle.
#[derive(Debug)]
pub(crate) struct Free;

#[lagrangian]
impl Free {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        (x_dot * x_dot + y_dot * y_dot) / 2.0
    }
}

/// A damped, driven oscillator in both modes: bindings and a `t: Time` the bodies of
/// `dissipation` and `forces` do not use produce no warnings.
pub struct DampedDriven {
    /// Damping coefficient.
    pub b: f64,
    /// Drive amplitude.
    pub a: f64,
}

#[lagrangian]
impl DampedDriven {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        (x_dot * x_dot + y_dot * y_dot - x * x - y * y) / 2.0
    }
    /// D = ½ b ẋ²; `x`, `y`, `y_dot` and `t` are not used.
    fn dissipation(&self, (x, x_dot): Coord, (y, y_dot): Coord, t: Time) -> Scalar {
        0.5 * self.b * x_dot * x_dot
    }
    /// A constant push on y; nothing of the state is used.
    fn forces(&self, (x, x_dot): Coord, (_, _): Coord, t: Time) -> [Scalar; 2] {
        [0.0, self.a]
    }
}

/// The same in jets mode.
pub struct DampedDrivenJets {
    /// Damping coefficient.
    pub b: f64,
    /// Drive amplitude.
    pub a: f64,
}

#[lagrangian(mode = "jets")]
impl DampedDrivenJets {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        (x_dot * x_dot + y_dot * y_dot - x * x - y * y) / 2.0
    }
    fn dissipation(&self, (x, x_dot): Coord, (y, y_dot): Coord, t: Time) -> Scalar {
        0.5 * self.b * x_dot * x_dot
    }
    fn forces(&self, (x, x_dot): Coord, (_, _): Coord, t: Time) -> [Scalar; 2] {
        [0.0, self.a * 1.0]
    }
}

/// A pendulum in x, y with the rod as a constraint, in both modes: a velocity bound and not
/// used, a `t: Time` not used, and a doc comment on `fn constraints` produce no warnings.
pub struct RodPendulum {
    /// Mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
    /// Rod length.
    pub l: f64,
}

#[lagrangian]
impl RodPendulum {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    /// The rod: x² + y² = l².
    fn constraints(&self, (x, x_dot): Coord, (y, _): Coord, t: Time) -> [Scalar; 1] {
        [x * x + y * y - self.l * self.l]
    }
}

/// The same in jets mode, with a moving constraint on a `Coord3` and a constant entry.
pub struct RodPendulumJets {
    /// Mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
    /// Rod length.
    pub l: f64,
}

#[lagrangian(mode = "jets")]
impl RodPendulumJets {
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        0.5 * self.m * r_dot.norm_squared() - self.m * self.g * r.z
    }
    fn constraints(&self, (r, r_dot): Coord3, t: Time) -> [Scalar; 2] {
        [r.norm_squared() - self.l * self.l, r.y - 0.0 * t]
    }
}

#[test]
fn lint_clean_constraints() {
    let s = RodPendulum {
        m: 2.0,
        g: 9.81,
        l: 1.5,
    };
    let (a, _) = s
        .constrained_accelerations(&[0.0, -1.5], &[3.0, 0.0], 0.0)
        .unwrap_or(([f64::NAN; 2], [f64::NAN]));
    assert!(a[0].abs() < 1e-12 && (a[1] - 6.0).abs() < 1e-12, "{a:?}");
    const { assert!(<RodPendulum as Holonomic<2, 1>>::SCLERONOMIC) };
    let j = RodPendulumJets {
        m: 2.0,
        g: 9.81,
        l: 1.5,
    };
    let (a, _) = j
        .constrained_accelerations(&[0.0, 0.0, -1.5], &[3.0, 0.0, 0.0], 0.0)
        .unwrap_or(([f64::NAN; 3], [f64::NAN; 2]));
    assert!(
        a[0].abs() < 1e-12 && a[1].abs() < 1e-12 && (a[2] - 6.0).abs() < 1e-12,
        "{a:?}"
    );
    const { assert!(!<RodPendulumJets as Holonomic<3, 2>>::SCLERONOMIC) };
}

#[test]
fn lint_clean_forces_and_dissipation() {
    let s = DampedDriven { b: 0.5, a: 2.0 };
    let j = DampedDrivenJets { b: 0.5, a: 2.0 };
    let want = [-1.0 - 0.5 * 3.0, -2.0 + 2.0];
    for a in [
        s.accelerations(&[1.0, 2.0], &[3.0, 4.0], 0.0),
        j.accelerations(&[1.0, 2.0], &[3.0, 4.0], 0.0),
    ] {
        let a = a.unwrap_or([f64::NAN; 2]);
        assert!(
            (a[0] - want[0]).abs() < 1e-15 && (a[1] - want[1]).abs() < 1e-15,
            "{a:?}"
        );
    }
}

/// Beads on a line joined by springs: 34 coordinates, so the generated code of M, the right-hand
/// side and the energy goes into modules next to this impl.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringLine {
    /// Mass of each bead.
    pub m: f64,
    /// Stiffness of each spring.
    pub k: f64,
}

#[lagrangian]
impl SpringLine {
    fn lagrangian(&self, (x, x_dot): Coords<34>) -> Scalar {
        let mut l = 0.0;
        for v in x_dot.iter() {
            l += 0.5 * self.m * v * v;
        }
        for i in 1..34 {
            let d = x[i] - x[i - 1];
            l -= 0.5 * self.k * d * d;
        }
        l
    }
}

#[test]
fn lint_clean_large_system_works() {
    let line = SpringLine { m: 2.0, k: 3.0 };
    // The second bead pulled by 1: it feels −2k/m, its neighbours +k/m.
    let mut x = [0.0; 34];
    x[1] = 1.0;
    let a = line
        .accelerations(&x, &[0.0; 34], 0.0)
        .unwrap_or([f64::NAN; 34]);
    for (i, ai) in a.iter().enumerate() {
        let want = match i {
            0 | 2 => 1.5,
            1 => -3.0,
            _ => 0.0,
        };
        assert!((ai - want).abs() < 1e-14, "{i}: {ai}");
    }
    let (h, p) = line.energy_and_momenta(&x, &[1.0; 34], 0.0);
    assert!((h - (34.0 + 3.0)).abs() < 1e-12, "{h}");
    assert!(
        p.iter().all(|pi| pi.to_bits() == 2.0_f64.to_bits()),
        "{p:?}"
    );
}

#[test]
fn lint_clean_systems_work() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.5,
        mgl: 1.0,
    };
    assert_eq!(<HeavyTop as Lagrangian<3>>::CYCLIC, [false, true, true]);
    assert!(top.spin(1.0, 2.0, 0.0).to_bits() == 1.5_f64.to_bits());

    let trap = Trapped {
        k: 2.0,
        gravity: Vector3::new(0.0, 0.0, -1.0),
    };
    const { assert!(<Trapped as Lagrangian<3>>::AUTONOMOUS) };
    let a = trap
        .accelerations(&[1.0, 0.0, 0.0], &[0.0; 3], 0.0)
        .unwrap_or([f64::NAN; 3]);
    assert_eq!(a.map(f64::to_bits), [-2.0_f64, 0.0, -1.0].map(f64::to_bits));
    // The derived Default builds a system the generated impl works with: no spring, no gravity.
    let a = Trapped::default().accelerations(&[1.0, 2.0, 3.0], &[0.5; 3], 0.0);
    assert!(
        matches!(a, Ok(a) if a.iter().all(|x| x.to_bits() == 0)),
        "{a:?}"
    );

    let driven = Driven {
        amplitude: 1.0,
        w: 0.0,
    };
    const { assert!(!<Driven as Lagrangian<1>>::AUTONOMOUS) };
    let a = driven
        .accelerations(&[0.5], &[0.0], 3.0)
        .unwrap_or([f64::NAN]);
    assert!((a[0] - 0.5).abs() < 1e-15);

    assert_eq!(<Free as Lagrangian<2>>::CYCLIC, [true, true]);
    let a = Free.accelerations(&[1.0, 2.0], &[3.0, 4.0], 0.0);
    assert!(matches!(a, Ok([x, y]) if x == 0.0 && y == 0.0), "{a:?}");
}

/// A bead on a rotating hoop written from geometry: its position from a rotation about the
/// vertical at the hoop's rate, `velocity` through a helper, a drag in D from the bead's
/// velocity and a force from the hoop's angular velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeometryBead {
    /// Hoop radius.
    pub r: f64,
    /// Hoop rate.
    pub w: f64,
    /// Drag coefficient.
    pub c: f64,
}

#[lagrangian]
impl GeometryBead {
    /// The bead's position at angle `a` from the bottom of the hoop at time `t`.
    fn position(&self, a: Scalar, t: Scalar) -> Vector3<Scalar> {
        Rotation::about_z(t * self.w) * Vector3::new(self.r * a.sin(), 0.0 * a, -self.r * a.cos())
    }

    fn lagrangian(&self, (a, a_dot): Coord, t: Time) -> Scalar {
        0.5 * velocity(self.position(a, t)).norm_squared()
    }

    fn dissipation(&self, (a, a_dot): Coord, t: Time) -> Scalar {
        0.5 * self.c * velocity(self.position(a, t)).norm_squared()
    }

    fn forces(&self, (a, _a_dot): Coord, t: Time) -> [Scalar; 1] {
        [angular_velocity(&Rotation::about_z(t * self.w)).z * 0.0 * a]
    }
}

/// The same bead in jets mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeometryBeadJets {
    /// Hoop radius.
    pub r: f64,
    /// Hoop rate.
    pub w: f64,
    /// Drag coefficient.
    pub c: f64,
}

#[lagrangian(mode = "jets")]
impl GeometryBeadJets {
    /// The bead's position at angle `a` from the bottom of the hoop at time `t`.
    fn position(&self, a: Scalar, t: Scalar) -> Vector3<Scalar> {
        Rotation::about_z(t * self.w) * Vector3::new(self.r * a.sin(), 0.0 * a, -self.r * a.cos())
    }

    fn lagrangian(&self, (a, a_dot): Coord, t: Time) -> Scalar {
        0.5 * velocity(self.position(a, t)).norm_squared()
    }

    fn dissipation(&self, (a, a_dot): Coord, t: Time) -> Scalar {
        0.5 * self.c * velocity(self.position(a, t)).norm_squared()
    }

    fn forces(&self, (a, _a_dot): Coord, t: Time) -> [Scalar; 1] {
        [angular_velocity(&Rotation::about_z(t * self.w)).z * 0.0 * a]
    }
}

#[test]
fn lint_clean_geometry() {
    // L = ½ r² (ȧ² + w² sin² a), D = c L: r² ä = r² w² sin a cos a − c r² ȧ.
    let (radius, rate, drag) = (1.5, 2.0, 0.3);
    let (angle, angle_dot) = (0.7_f64, 1.1);
    let want = rate * rate * angle.sin() * angle.cos() - drag * angle_dot;
    let bead = GeometryBead {
        r: radius,
        w: rate,
        c: drag,
    };
    let jets = GeometryBeadJets {
        r: radius,
        w: rate,
        c: drag,
    };
    let symbolic = bead.accelerations(&[angle], &[angle_dot], 0.4);
    let jets = jets.accelerations(&[angle], &[angle_dot], 0.4);
    for got in [symbolic, jets] {
        let got = got.unwrap_or([f64::NAN]);
        assert!((got[0] - want).abs() < 1e-13, "{got:?} vs {want}");
    }
}

/// A ball over a moving floor with a sticking contact, in both modes: a velocity bound and not
/// used, a doc comment on `fn contacts`, a name and a restitution from a field.
pub struct FloorBall {
    /// Mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
    /// Restitution.
    pub e: f64,
}

#[lagrangian]
impl FloorBall {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    /// The floor y = 0.1 t, where the ball sticks.
    fn contacts(&self, (x, x_dot): Coord, (y, _): Coord, t: Time) -> [Contact; 1] {
        [Contact::gap(y - 0.1 * t)
            .restitution(self.e)
            .sticking(x)
            .named("floor")]
    }
}

/// The same in jets mode, on a `Coord3`, two contacts.
pub struct FloorBallJets {
    /// Mass.
    pub m: f64,
    /// Gravity.
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl FloorBallJets {
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        0.5 * self.m * r_dot.norm_squared() - self.m * self.g * r.z
    }
    fn contacts(&self, (r, r_dot): Coord3) -> [Contact; 2] {
        [Contact::gap(r.z), Contact::gap(1.0 - r.x).restitution(0.5)]
    }
}

#[test]
fn lint_clean_contacts() {
    let s = FloorBall {
        m: 2.0,
        g: 9.81,
        e: 0.5,
    };
    let rows = s.contact_rows(&[1.0, 0.5], &[0.0, -1.0], 2.0);
    assert!((rows.gap[0] - 0.3).abs() < 1e-15 && (rows.normal_rate[0] + 1.1).abs() < 1e-15);
    assert_eq!(
        (rows.sticking[0], rows.names[0], rows.restitution[0]),
        (true, "floor", 0.5)
    );
    const { assert!(!<FloorBall as Unilateral<2, 1>>::SCLERONOMIC) };
    let j = FloorBallJets { m: 1.0, g: 9.81 };
    let rows = j.contact_rows(&[0.25, 0.0, 2.0], &[0.0; 3], 0.0);
    assert_eq!((rows.gap, rows.restitution), ([2.0, 0.75], [0.0, 0.5]));
    const { assert!(<FloorBallJets as Unilateral<3, 2>>::SCLERONOMIC) };
}
