//! Geometry in a body (`velocity`, `Rotation`, angular velocities), in both modes, against the
//! systems written with their velocities worked out by hand.

use crate::support::systems::RotationTop;
use crate::support::Rng;
use lagrange::prelude::*;

/// The heavy top of eq. 92 from its rotation R = R_z(φ) R_x(θ) R_z(ψ) (symbolic mode).
pub struct GeoTop {
    pub i_perp: f64,
    pub i_par: f64,
    pub mgl: f64,
}

#[lagrangian]
impl GeoTop {
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

/// The same top in jets mode.
pub struct GeoTopJets {
    pub i_perp: f64,
    pub i_par: f64,
    pub mgl: f64,
}

#[lagrangian(mode = "jets")]
impl GeoTopJets {
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
