//! `fn dissipation` and `fn forces` in `#[lagrangian]`, both modes, as outside code writes them
//! (the contract's text): accelerations against the hand-written equation at random states,
//! the two modes against each other, the conservation flags, and the energy balance.

use lagrange::prelude::*;

use crate::support::Rng;

macro_rules! driven_pendulum {
    ($name:ident, $($mode:tt)*) => {
        pub struct $name {
            pub m: f64,
            pub l: f64,
            pub g: f64,
            pub b: f64,
            pub a: f64,
            pub w: f64,
        }

        #[lagrangian $($mode)*]
        impl $name {
            fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
                0.5 * self.m * self.l * self.l * theta_dot.powi(2) + self.m * self.g * self.l * theta.cos()
            }
            /// Rayleigh dissipation function D(q, q̇, t) ≥ 0; its −∂D/∂q̇ joins the generalized forces.
            fn dissipation(&self, (theta, theta_dot): Coord) -> Scalar {
                0.5 * self.b * theta_dot.powi(2)
            }
            /// Generalized forces Q(q, q̇, t), one per coordinate in declaration order.
            fn forces(&self, (theta, theta_dot): Coord, t: Time) -> [Scalar; 1] {
                [self.a * (self.w * t).cos()]
            }
        }
    };
}

driven_pendulum!(DrivenPendulum,);
driven_pendulum!(DrivenPendulumJets, (mode = "jets"));

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1.0)
}

#[test]
fn the_driven_pendulum_matches_its_hand_written_equation_in_both_modes() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..1000 {
        let (m, l, g) = (
            rng.uniform(0.5, 2.0),
            rng.uniform(0.3, 2.0),
            rng.uniform(1.0, 10.0),
        );
        let (b, a, w) = (
            rng.uniform(0.0, 2.0),
            rng.uniform(-3.0, 3.0),
            rng.uniform(0.1, 3.0),
        );
        let (q, v, t) = (
            rng.uniform(-7.0, 7.0),
            rng.uniform(-5.0, 5.0),
            rng.uniform(-50.0, 50.0),
        );
        let want = (-m * g * l * q.sin() - b * v + a * (w * t).cos()) / (m * l * l);
        let sym = DrivenPendulum { m, l, g, b, a, w };
        let jets = DrivenPendulumJets { m, l, g, b, a, w };
        let (s, j) = (
            sym.accelerations(&[q], &[v], t).unwrap()[0],
            jets.accelerations(&[q], &[v], t).unwrap()[0],
        );
        assert!(rel(s, want) <= 1e-12, "symbolic {s} vs {want}");
        assert!(rel(j, want) <= 1e-12, "jets {j} vs {want}");
        let (ps, pj) = (sym.pieces(&[q], &[v], t), jets.pieces(&[q], &[v], t));
        assert!(rel(ps.applied[0], pj.applied[0]) <= 1e-12);
        assert!(rel(ps.applied[0], a * (w * t).cos() - b * v) <= 1e-12);
        assert!(rel(sym.power(&[q], &[v], t), jets.power(&[q], &[v], t)) <= 1e-12);
        assert!(rel(sym.dissipation(&[q], &[v], t), 0.5 * b * v * v) <= 1e-12);
        assert_eq!(
            sym.generalized_forces(&[q], &[v], t),
            jets.generalized_forces(&[q], &[v], t)
        );
    }
}

#[test]
fn the_flags_say_what_is_conserved() {
    for (cyclic, momentum, energy, autonomous) in [
        (
            <DrivenPendulum as Lagrangian<1>>::CYCLIC,
            <DrivenPendulum as Lagrangian<1>>::MOMENTUM_CONSERVED,
            <DrivenPendulum as Lagrangian<1>>::ENERGY_CONSERVED,
            <DrivenPendulum as Lagrangian<1>>::AUTONOMOUS,
        ),
        (
            <DrivenPendulumJets as Lagrangian<1>>::CYCLIC,
            <DrivenPendulumJets as Lagrangian<1>>::MOMENTUM_CONSERVED,
            <DrivenPendulumJets as Lagrangian<1>>::ENERGY_CONSERVED,
            <DrivenPendulumJets as Lagrangian<1>>::AUTONOMOUS,
        ),
    ] {
        assert_eq!(
            (cyclic, momentum, energy, autonomous),
            ([false], [false], false, true)
        );
    }
    assert!(DrivenPendulum::EQUATIONS.contains("D = 0.5 * self.b * theta_dot.powi(2)"));
    assert!(DrivenPendulum::EQUATIONS.contains("Q = [self.a * (self.w * t).cos()]"));
}

#[test]
fn the_energy_balance_closes_in_a_chaotic_regime() {
    let p = DrivenPendulum {
        m: 1.0,
        l: 1.0,
        g: 1.0,
        b: 0.5,
        a: 1.5,
        w: 2.0 / 3.0,
    };
    let tr = Simulation::new(&p, [0.2], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(200.0)
        .run()
        .unwrap();
    let balance = tr
        .invariants()
        .energy_balance
        .expect("the energy is not conserved");
    let w_max = tr.work.iter().fold(0.0_f64, |m, w| m.max(w.abs()));
    assert!(
        w_max > 1.0,
        "the drive and the friction exchange O(1) energy: {w_max}"
    );
    assert!(
        balance.max_abs <= 1e-9,
        "energy balance residual {:.2e}",
        balance.max_abs
    );
}

/// The heavy top with viscous friction on the spin only: φ stays cyclic and unforced, so p_φ is
/// conserved while ψ̇ decays.
macro_rules! damped_top {
    ($name:ident, $($mode:tt)*) => {
        pub struct $name {
            pub i_perp: f64,
            pub i_par: f64,
            pub mgl: f64,
            pub c: f64,
        }

        #[lagrangian $($mode)*]
        impl $name {
            fn lagrangian(&self, (theta, theta_dot): Coord, (phi, phi_dot): Coord, (psi, psi_dot): Coord) -> Scalar {
                let (s, c) = theta.sin_cos();
                self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
                    + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
                    - self.mgl * c
            }
            fn dissipation(&self, (_, _): Coord, (_, _): Coord, (_, psi_dot): Coord) -> Scalar {
                0.5 * self.c * psi_dot.powi(2)
            }
        }
    };
}

damped_top!(DampedTop,);
damped_top!(DampedTopJets, (mode = "jets"));

#[test]
fn friction_on_the_spin_leaves_p_phi_conserved() {
    assert_eq!(<DampedTop as Lagrangian<3>>::CYCLIC, [false, true, true]);
    assert_eq!(
        <DampedTop as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false, true, false]
    );
    const { assert!(!<DampedTop as Lagrangian<3>>::ENERGY_CONSERVED) };
    assert_eq!(
        <DampedTopJets as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false, true, false]
    );
    let top = DampedTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
        c: 0.05,
    };
    let jets = DampedTopJets {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
        c: 0.05,
    };
    let mut rng = Rng(7);
    for _ in 0..200 {
        let q = [
            rng.uniform(0.3, 2.8),
            rng.uniform(-3.0, 3.0),
            rng.uniform(-3.0, 3.0),
        ];
        let v = [
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-9.0, 9.0),
        ];
        let (a, b) = (
            top.accelerations(&q, &v, 0.0).unwrap(),
            jets.accelerations(&q, &v, 0.0).unwrap(),
        );
        for i in 0..3 {
            assert!(rel(a[i], b[i]) <= 1e-12, "q̈[{i}]: {} vs {}", a[i], b[i]);
        }
    }
    let tr = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(30.0)
        .run()
        .unwrap();
    let inv = tr.invariants();
    assert!(inv.momenta[2].is_none() && inv.energy.is_none());
    let p_phi = inv.momenta[1].expect("p_φ is conserved");
    assert!(p_phi.max_rel <= 1e-12, "p_φ drift {:.2e}", p_phi.max_rel);
    assert!(inv.energy_balance.unwrap().max_abs <= 1e-9);
    assert!(tr.qdot.last().unwrap()[2].abs() < 8.0, "the spin decays");
}

/// A particle in `Coord3` with quadratic drag and a constant force: Q takes one slot per component.
macro_rules! dragged {
    ($name:ident, $($mode:tt)*) => {
        pub struct $name {
            pub m: f64,
            pub c: f64,
            pub f: f64,
        }

        #[lagrangian $($mode)*]
        impl $name {
            fn lagrangian(&self, (_r, r_dot): Coord3) -> Scalar {
                0.5 * self.m * r_dot.norm_squared()
            }
            fn dissipation(&self, (_, r_dot): Coord3) -> Scalar {
                0.5 * self.c * r_dot.norm_squared()
            }
            fn forces(&self, (_, _): Coord3) -> [Scalar; 3] {
                [0.0, 0.0, -self.f]
            }
        }
    };
}

dragged!(Dragged,);
dragged!(DraggedJets, (mode = "jets"));

#[test]
fn a_coord3_particle_with_drag_and_a_constant_force() {
    assert_eq!(<Dragged as Lagrangian<3>>::CYCLIC, [true; 3]);
    assert_eq!(<Dragged as Lagrangian<3>>::MOMENTUM_CONSERVED, [false; 3]);
    assert_eq!(
        <DraggedJets as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false; 3]
    );
    let (p, j) = (
        Dragged {
            m: 2.0,
            c: 0.4,
            f: 9.0,
        },
        DraggedJets {
            m: 2.0,
            c: 0.4,
            f: 9.0,
        },
    );
    let v = [1.0, -2.0, 3.0];
    let want = [-0.4 * 1.0 / 2.0, 0.4 * 2.0 / 2.0, (-0.4 * 3.0 - 9.0) / 2.0];
    for got in [
        p.accelerations(&[0.0; 3], &v, 0.0).unwrap(),
        j.accelerations(&[0.0; 3], &v, 0.0).unwrap(),
    ] {
        for i in 0..3 {
            assert!(rel(got[i], want[i]) <= 1e-14, "{got:?} vs {want:?}");
        }
    }
}
