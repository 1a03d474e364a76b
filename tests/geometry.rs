//! Geometry in a body (`velocity`, `Rotation`, angular velocities), in both modes, against the
//! systems written with their velocities worked out by hand.

use crate::support::systems::{GeometryTop as GeoTop, GeometryTopJets as GeoTopJets, RotationTop};
use crate::support::Rng;
use lagrange::prelude::*;
use lagrange_examples::twins;

fn check_against_rotation_top<L: Lagrangian<3>>(sys: &L, tol: f64) {
    let (i_perp, i_par, mgl) = (1.3, 0.7, 0.9 * 9.81 * 0.4);
    let hand = RotationTop { i_perp, i_par, mgl };
    let mut rng = Rng(5);
    for _ in 0..1000 {
        let mut q = rng.arr3(-3.0, 3.0);
        q[0] = rng.uniform(0.2, 2.9);
        let v = rng.arr3(-3.0, 3.0);
        let t = rng.uniform(-1.0, 1.0);
        let l = sys.lagrangian(&q, &v, t);
        let want = hand.lagrangian(&q, &v, t);
        assert!(
            (l - want).abs() <= tol * (1.0 + want.abs()),
            "L at {q:?}, {v:?}: {l} vs {want}"
        );
        let a = sys.accelerations(&q, &v, t).unwrap();
        let want = hand.accelerations(&q, &v, t).unwrap();
        for i in 0..3 {
            assert!(
                (a[i] - want[i]).abs() <= tol * (1.0 + want[i].abs()),
                "q = {q:?}, q̇ = {v:?}: {a:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn heavy_top_from_its_rotation_jets() {
    let top = GeoTopJets {
        i_perp: 1.3,
        i_par: 0.7,
        mgl: 0.9 * 9.81 * 0.4,
    };
    check_against_rotation_top(&top, 1e-12);
}

#[test]
fn heavy_top_from_its_rotation_symbolic() {
    let top = GeoTop {
        i_perp: 1.3,
        i_par: 0.7,
        mgl: 0.9 * 9.81 * 0.4,
    };
    check_against_rotation_top(&top, 1e-12);
}

#[test]
fn heavy_top_from_its_rotation_prints_eq_92() {
    assert_eq!(<GeoTop as Lagrangian<3>>::CYCLIC, [false, true, true]);
    let eq = GeoTop::EQUATIONS;
    assert_eq!(eq, lagrange_examples::bench_top::MacroTop::EQUATIONS);
    assert_eq!(
        GeoTop::EQUATIONS_LATEX,
        lagrange_examples::bench_top::MacroTop::EQUATIONS_LATEX
    );
    assert!(!eq.contains("(ψ)"), "{eq}");
}

twins! {
    /// The double pendulum from the positions of its bobs and their velocities.
    GeoDouble, GeoDoubleJets { m1: f64, m2: f64, l1: f64, l2: f64, g: f64 }
    fn lagrangian(&self, (th1, th1_dot): Coord, (th2, th2_dot): Coord) -> Scalar {
        let (m1, m2, l1, l2, g) = (self.m1, self.m2, self.l1, self.l2, self.g);
        let p1 = Vector3::new(l1 * th1.sin(), -l1 * th1.cos(), 0.0 * th1);
        let p2 = p1 + Vector3::new(l2 * th2.sin(), -l2 * th2.cos(), 0.0 * th2);
        let (v1, v2) = (velocity(p1), velocity(p2));
        0.5 * m1 * v1.norm_squared() + 0.5 * m2 * v2.norm_squared() - g * (m1 * p1.y + m2 * p2.y)
    }
}

#[test]
fn double_pendulum_from_positions() {
    use lagrange_examples::double_pendulum_system::DoublePendulum;
    let (m1, m2, l1, l2, g) = (1.1, 0.7, 0.9, 1.3, 9.81);
    let hand = DoublePendulum { m1, m2, l1, l2, g };
    let sym = GeoDouble { m1, m2, l1, l2, g };
    assert_eq!(GeoDouble::EQUATIONS, DoublePendulum::EQUATIONS);
    let jets = sym.jets();
    let mut rng = Rng(17);
    for _ in 0..1000 {
        let q = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let v = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let want = hand.accelerations(&q, &v, 0.0).unwrap();
        for a in [
            sym.accelerations(&q, &v, 0.0).unwrap(),
            jets.accelerations(&q, &v, 0.0).unwrap(),
        ] {
            for i in 0..2 {
                assert!(
                    (a[i] - want[i]).abs() <= 1e-12 * (1.0 + want[i].abs()),
                    "{a:?} vs {want:?}"
                );
            }
        }
        let (lh, ls, lj) = (
            hand.lagrangian(&q, &v, 0.0),
            sym.lagrangian(&q, &v, 0.0),
            jets.lagrangian(&q, &v, 0.0),
        );
        assert!(
            (ls - lh).abs() <= 1e-12 * (1.0 + lh.abs())
                && (lj - lh).abs() <= 1e-12 * (1.0 + lh.abs())
        );
    }
}

twins! {
    /// The quaternion top from the rotation of its unit quaternion.
    GeoQuatTop, GeoQuatTopJets { i_perp: f64, i_par: f64, mgl: f64 }
    fn lagrangian(&self, (w, w_dot): Coord, (x, x_dot): Coord, (y, y_dot): Coord, (z, z_dot): Coord) -> Scalar {
        let r = Rotation::from_quaternion(w, x, y, z);
        let o = body_angular_velocity(&r);
        0.5 * (self.i_perp * (o.x * o.x + o.y * o.y) + self.i_par * o.z * o.z)
            - self.mgl * (r * Vector3::z()).z
    }
    fn constraints(&self, (w, _): Coord, (x, _): Coord, (y, _): Coord, (z, _): Coord) -> [Scalar; 1] {
        [w * w + x * x + y * y + z * z - 1.0]
    }
}

#[test]
fn quaternion_top_from_its_rotation() {
    use crate::support::quaternion_top::{from_euler, QuaternionTop};
    let (i_perp, i_par, mgl) = (1.3, 0.7, 3.1);
    let hand = QuaternionTop { i_perp, i_par, mgl };
    let sym = GeoQuatTop { i_perp, i_par, mgl };
    let jets = sym.jets();
    let mut rng = Rng(23);
    for _ in 0..1000 {
        let (q, v) = from_euler(rng.arr3(-3.0, 3.0), rng.arr3(-3.0, 3.0));
        let want = hand.lagrangian(&q, &v, 0.0);
        for l in [sym.lagrangian(&q, &v, 0.0), jets.lagrangian(&q, &v, 0.0)] {
            assert!(
                (l - want).abs() <= 1e-12 * (1.0 + want.abs()),
                "{l} vs {want}"
            );
        }
        let want = hand.constrained_accelerations(&q, &v, 0.0).unwrap().0;
        for a in [
            sym.constrained_accelerations(&q, &v, 0.0).unwrap().0,
            jets.constrained_accelerations(&q, &v, 0.0).unwrap().0,
        ] {
            for i in 0..4 {
                assert!(
                    (a[i] - want[i]).abs() <= 1e-10 * (1.0 + want[i].abs()),
                    "{a:?} vs {want:?}"
                );
            }
        }
    }
}

twins! {
    /// A five-link chain from the positions of its bobs, in a loop.
    GeoChain, GeoChainJets { m: f64, l: f64, g: f64 }
    fn lagrangian(&self, (q, q_dot): Coords<5>) -> Scalar {
        let mut p = Vector3::new(0.0 * q[0], 0.0 * q[0], 0.0 * q[0]);
        let mut l = 0.0 * q[0];
        for k in 0..5 {
            p += Vector3::new(self.l * q[k].sin(), -self.l * q[k].cos(), 0.0 * q[k]);
            let v = velocity(p);
            l += 0.5 * self.m * v.norm_squared() - self.m * self.g * p.y;
        }
        l
    }
}

twins! {
    /// The same chain with its velocities written by hand.
    HandChain, HandChainJets { m: f64, l: f64, g: f64 }
    fn lagrangian(&self, (q, q_dot): Coords<5>) -> Scalar {
        let (mut vx, mut vy, mut y, mut l) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..5 {
            let (s, c) = q[k].sin_cos();
            vx += self.l * c * q_dot[k];
            vy += self.l * s * q_dot[k];
            y -= self.l * c;
            l += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        }
        l
    }
}

#[test]
fn chain_from_positions_in_a_loop() {
    let (m, l, g) = (0.8, 1.1, 9.81);
    let hand = HandChain { m, l, g };
    let sym = GeoChain { m, l, g };
    let jets = sym.jets();
    let mut rng = Rng(29);
    for _ in 0..300 {
        let q: [f64; 5] = std::array::from_fn(|_| rng.uniform(-3.0, 3.0));
        let v: [f64; 5] = std::array::from_fn(|_| rng.uniform(-3.0, 3.0));
        let want = hand.accelerations(&q, &v, 0.0).unwrap();
        for a in [
            sym.accelerations(&q, &v, 0.0).unwrap(),
            jets.accelerations(&q, &v, 0.0).unwrap(),
        ] {
            for i in 0..5 {
                assert!(
                    (a[i] - want[i]).abs() <= 1e-10 * (1.0 + want[i].abs()),
                    "{a:?} vs {want:?}"
                );
            }
        }
    }
}

twins! {
    /// Every geometry construct in one body, with explicit time, a constant rotation composed
    /// with moving ones, a transpose, both angular velocities, and velocities of a Scalar and a
    /// Vector3; with a dissipation function and a force written from velocities too.
    Everything, EverythingJets { a: f64, k: f64, c: f64, tilt: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord, (z, z_dot): Coord, t: Time) -> Scalar {
        let r = Rotation::about_x(self.tilt) * Rotation::about_y(x + 0.3 * t) * Rotation::about_z(y * z);
        let s = Rotation::from_quaternion(x.cos(), 0.2 * y, z.sin(), 0.5 + 0.0 * x);
        let w_space = angular_velocity(&(r * s.transpose()));
        let w_body = body_angular_velocity(&r);
        let p = r * Vector3::new(self.a, 0.5 * x, z * z);
        let v = velocity(p);
        let h = velocity(x * y + (0.7 * t).sin() * z);
        0.5 * v.norm_squared() + 0.25 * w_space.norm_squared() + 0.3 * w_body.dot(&w_space)
            + 0.5 * h * h + 0.5 * (x_dot * x_dot + y_dot * y_dot + z_dot * z_dot)
            - self.k * (x * x + y * y + z * z)
    }
    fn dissipation(&self, (x, x_dot): Coord, (y, y_dot): Coord, (z, z_dot): Coord) -> Scalar {
        let p = Vector3::new(x.sin(), x * y, z);
        let v = velocity(p);
        0.5 * self.c * v.norm_squared()
    }
    fn forces(&self, (x, _x_dot): Coord, (y, _y_dot): Coord, (z, _z_dot): Coord, t: Time) -> [Scalar; 3] {
        let r = Rotation::about_z(x + t);
        let w = angular_velocity(&r);
        [-self.c * w.z, 0.1 * velocity(y * z), 0.0 * z]
    }
}

#[test]
fn every_construct_jets_equal_symbolic() {
    let sym = Everything {
        a: 0.8,
        k: 1.3,
        c: 0.4,
        tilt: 0.35,
    };
    let jets = sym.jets();
    let mut rng = Rng(31);
    for _ in 0..500 {
        let q = rng.arr3(-2.0, 2.0);
        let v = rng.arr3(-2.0, 2.0);
        let t = rng.uniform(-2.0, 2.0);
        let close = |a: f64, b: f64, what: &str| {
            assert!(
                (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                "{what}: {a} vs {b} at {q:?} {v:?} {t}"
            );
        };
        close(sym.lagrangian(&q, &v, t), jets.lagrangian(&q, &v, t), "L");
        close(sym.energy(&q, &v, t), jets.energy(&q, &v, t), "energy");
        let (ms, mj) = (sym.mass_matrix(&q, &v, t), jets.mass_matrix(&q, &v, t));
        for i in 0..3 {
            for j in 0..3 {
                close(ms[(i, j)], mj[(i, j)], "M");
            }
            close(sym.momenta(&q, &v, t)[i], jets.momenta(&q, &v, t)[i], "p");
        }
        // q̈ through the residual: M may be ill-conditioned at some states.
        let (a_s, a_j) = (
            sym.accelerations(&q, &v, t).unwrap(),
            jets.accelerations(&q, &v, t).unwrap(),
        );
        let scale = ms.norm() * a_s.iter().map(|x| x.abs()).fold(1.0, f64::max);
        let d = nalgebra::Vector3::from(a_s) - nalgebra::Vector3::from(a_j);
        assert!((ms * d).norm() <= 1e-11 * scale, "q̈ {a_s:?} vs {a_j:?}");
    }
}

/// A rigid body with a full inertia tensor (a `Matrix3<f64>` field) in jets mode: ½ ωᵀ I ω with
/// ω from the rotation, against the same body with I's principal moments along the axes.
pub struct TensorBody {
    pub inertia: nalgebra::Matrix3<f64>,
}

#[lagrangian(mode = "jets")]
impl TensorBody {
    fn lagrangian(&self, (a, a_dot): Coord, (b, b_dot): Coord) -> Scalar {
        let r = Rotation::about_z(a) * Rotation::about_x(b);
        let w = body_angular_velocity(&r);
        0.5 * w.dot(&(self.inertia * w))
    }
}

#[test]
fn inertia_tensor_field_in_jets_mode() {
    let (i1, i2, i3) = (1.0, 2.0, 3.5);
    let body = TensorBody {
        inertia: nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(i1, i2, i3)),
    };
    let (q, v): ([f64; 2], [f64; 2]) = ([0.3, 0.8], [1.2, -0.7]);
    // ω_body of R_z(a) R_x(b) = (ḃ, ȧ sin b, ȧ cos b)
    let w = [v[1], v[0] * q[1].sin(), v[0] * q[1].cos()];
    let want = 0.5 * (i1 * w[0] * w[0] + i2 * w[1] * w[1] + i3 * w[2] * w[2]);
    let l = body.lagrangian(&q, &v, 0.0);
    assert!((l - want).abs() <= 1e-14 * want, "{l} vs {want}");
}
