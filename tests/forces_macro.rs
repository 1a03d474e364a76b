//! `fn dissipation` and `fn forces` in `#[lagrangian]`, in both modes: the accelerations against
//! hand-written equations at random states, the symbolic mode against the jets mode (pieces,
//! power, D, Q), the conservation flags, and the printed equations.

use lagrange::prelude::*;
use lagrange_examples::twins;

use crate::support::Rng;

const STATES: usize = 1000;
const REL: f64 = 1e-12;

/// |got − want| ≤ rel · max(1, max |want|), component-wise.
fn assert_close(got: &[f64], want: &[f64], rel: f64, ctx: &str) {
    assert_eq!(got.len(), want.len(), "{ctx}");
    let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() <= rel * scale,
            "{ctx}: got {got:?}, want {want:?}"
        );
    }
}

twins! {
    DrivenPendulum, DrivenPendulumJets { m: f64, l: f64, g: f64, b: f64, a: f64, w: f64 }
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

fn pendulum(rng: &mut Rng) -> DrivenPendulum {
    DrivenPendulum {
        m: rng.uniform(0.5, 2.0),
        l: rng.uniform(0.5, 2.0),
        g: rng.uniform(1.0, 10.0),
        b: rng.uniform(0.0, 1.0),
        a: rng.uniform(-2.0, 2.0),
        w: rng.uniform(0.1, 3.0),
    }
}

#[test]
fn driven_pendulum_matches_the_hand_written_equation_in_both_modes() {
    let mut rng = Rng(0x5eed_f0ce_0000_0001);
    for k in 0..STATES {
        let p = pendulum(&mut rng);
        let j = p.jets();
        let (q, v, t) = (
            [rng.uniform(-3.0, 3.0)],
            [rng.uniform(-3.0, 3.0)],
            rng.uniform(-10.0, 10.0),
        );
        let want = (-p.m * p.g * p.l * q[0].sin() - p.b * v[0] + p.a * (p.w * t).cos())
            / (p.m * p.l * p.l);
        let ctx = format!("state {k}");
        let sym = p.accelerations(&q, &v, t).expect("symbolic accelerations");
        let jet = j.accelerations(&q, &v, t).expect("jets accelerations");
        assert_close(&sym, &[want], REL, &ctx);
        assert_close(&jet, &[want], REL, &ctx);

        let (ps, pj) = (p.pieces(&q, &v, t), j.pieces(&q, &v, t));
        assert_close(&ps.mass[0], &pj.mass[0], REL, &ctx);
        assert_close(&ps.lagrangian_force, &pj.lagrangian_force, REL, &ctx);
        assert_close(&ps.applied, &pj.applied, REL, &ctx);
        assert_close(
            &ps.applied,
            &[p.a * (p.w * t).cos() - p.b * v[0]],
            REL,
            &ctx,
        );
        assert_close(&[p.power(&q, &v, t)], &[j.power(&q, &v, t)], REL, &ctx);
        assert_close(
            &[p.power(&q, &v, t)],
            &[(p.a * (p.w * t).cos() - p.b * v[0]) * v[0]],
            REL,
            &ctx,
        );
        assert_close(
            &[p.dissipation(&q, &v, t)],
            &[j.dissipation(&q, &v, t)],
            REL,
            &ctx,
        );
        assert_close(
            &p.generalized_forces(&q, &v, t),
            &j.generalized_forces(&q, &v, t),
            REL,
            &ctx,
        );
    }
}

#[test]
fn driven_pendulum_flags() {
    const {
        assert!(!<DrivenPendulum as Lagrangian<1>>::CYCLIC[0]);
        assert!(!<DrivenPendulum as Lagrangian<1>>::MOMENTUM_CONSERVED[0]);
        assert!(<DrivenPendulum as Lagrangian<1>>::AUTONOMOUS);
        assert!(!<DrivenPendulum as Lagrangian<1>>::ENERGY_CONSERVED);
        assert!(!<DrivenPendulumJets as Lagrangian<1>>::CYCLIC[0]);
        assert!(!<DrivenPendulumJets as Lagrangian<1>>::MOMENTUM_CONSERVED[0]);
        assert!(<DrivenPendulumJets as Lagrangian<1>>::AUTONOMOUS);
        assert!(!<DrivenPendulumJets as Lagrangian<1>>::ENERGY_CONSERVED);
    }
}

#[test]
fn driven_pendulum_equations_show_the_force_and_the_dissipation() {
    let eq = DrivenPendulum::EQUATIONS;
    assert!(eq.starts_with("theta: m l² θ̈ = "), "{eq}");
    assert!(eq.contains("= −m l g sin(θ) + "), "{eq}");
    assert!(eq.contains("+ a cos(w t)"), "{eq}");
    assert!(eq.ends_with("− b θ̇"), "{eq}");
    let latex = DrivenPendulum::EQUATIONS_LATEX;
    assert!(latex.contains("a \\cos\\left(w t\\right)"), "{latex}");
    assert!(latex.contains("- b \\dot{\\theta}"), "{latex}");
}

twins! {
    DampedTop, DampedTopJets { i_perp: f64, i_par: f64, m: f64, g: f64, l: f64, c: f64 }
    /// Symmetric heavy top, eq. (92), with D = ½ c ψ̇².
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let (s, c) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
            - self.m * self.g * self.l * c
    }
    fn dissipation(&self, _: Coord, (_, _): Coord, (_, psi_dot): Coord) -> Scalar {
        0.5 * self.c * psi_dot * psi_dot
    }
}

#[test]
fn damped_heavy_top_flags_and_modes_agree() {
    const {
        assert!(!<DampedTop as Lagrangian<3>>::ENERGY_CONSERVED);
        assert!(!<DampedTopJets as Lagrangian<3>>::ENERGY_CONSERVED);
        assert!(<DampedTop as Lagrangian<3>>::AUTONOMOUS);
    }
    assert_eq!(
        <DampedTop as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false, true, false]
    );
    assert_eq!(
        <DampedTopJets as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false, true, false]
    );
    assert_eq!(<DampedTop as Lagrangian<3>>::CYCLIC, [false, true, true]);
    assert_eq!(
        <DampedTopJets as Lagrangian<3>>::CYCLIC,
        [false, true, true]
    );

    let mut rng = Rng(0x70b_70b_70b);
    for k in 0..STATES {
        let top = DampedTop {
            i_perp: rng.uniform(0.5, 2.0),
            i_par: rng.uniform(0.2, 1.0),
            m: rng.uniform(0.5, 2.0),
            g: rng.uniform(1.0, 10.0),
            l: rng.uniform(0.1, 1.0),
            c: rng.uniform(0.0, 1.0),
        };
        let jets = top.jets();
        let q = [
            rng.uniform(0.3, 2.8),
            rng.uniform(-3.0, 3.0),
            rng.uniform(-3.0, 3.0),
        ];
        let v = [
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-5.0, 5.0),
        ];
        let t = rng.uniform(-5.0, 5.0);
        let ctx = format!("state {k}");
        let a = top.accelerations(&q, &v, t).expect("symbolic");
        let b = jets.accelerations(&q, &v, t).expect("jets");
        assert_close(&a, &b, REL, &ctx);
        let (ps, pj) = (top.pieces(&q, &v, t), jets.pieces(&q, &v, t));
        assert_close(&ps.applied, &pj.applied, REL, &ctx);
        assert_close(&ps.applied, &[0.0, 0.0, -top.c * v[2]], REL, &ctx);
        assert_close(&ps.lagrangian_force, &pj.lagrangian_force, REL, &ctx);
        for i in 0..3 {
            assert_close(&ps.mass[i][i..], &pj.mass[i][i..], REL, &ctx);
        }
        assert_close(&[top.power(&q, &v, t)], &[jets.power(&q, &v, t)], REL, &ctx);
        assert_close(&[top.power(&q, &v, t)], &[-top.c * v[2] * v[2]], REL, &ctx);
    }
}

twins! {
    DraggedParticle, DraggedParticleJets { m: f64, c: f64, f: f64 }
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        0.5 * self.m * r_dot.norm_squared()
    }
    fn dissipation(&self, (_, r_dot): Coord3) -> Scalar {
        0.5 * self.c * r_dot.norm_squared()
    }
    fn forces(&self, _: Coord3) -> [Scalar; 3] {
        [0.0, 0.0, -self.f]
    }
}

#[test]
fn dragged_particle_flags_and_accelerations() {
    assert_eq!(<DraggedParticle as Lagrangian<3>>::CYCLIC, [true; 3]);
    assert_eq!(<DraggedParticleJets as Lagrangian<3>>::CYCLIC, [true; 3]);
    // The drag acts on every component: no momentum is conserved.
    assert_eq!(
        <DraggedParticle as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false; 3]
    );
    assert_eq!(
        <DraggedParticleJets as Lagrangian<3>>::MOMENTUM_CONSERVED,
        [false; 3]
    );
    const {
        assert!(!<DraggedParticle as Lagrangian<3>>::ENERGY_CONSERVED);
        assert!(!<DraggedParticleJets as Lagrangian<3>>::ENERGY_CONSERVED);
    }
    let mut rng = Rng(99);
    for k in 0..STATES {
        let p = DraggedParticle {
            m: rng.uniform(0.5, 2.0),
            c: rng.uniform(0.0, 1.0),
            f: rng.uniform(0.0, 10.0),
        };
        let q = [0.0; 3].map(|_: f64| rng.uniform(-5.0, 5.0));
        let v = [0.0; 3].map(|_: f64| rng.uniform(-5.0, 5.0));
        let t = rng.uniform(0.0, 1.0);
        let want = [
            -p.c * v[0] / p.m,
            -p.c * v[1] / p.m,
            (-p.c * v[2] - p.f) / p.m,
        ];
        let ctx = format!("state {k}");
        assert_close(
            &p.accelerations(&q, &v, t).expect("symbolic"),
            &want,
            REL,
            &ctx,
        );
        assert_close(
            &p.jets().accelerations(&q, &v, t).expect("jets"),
            &want,
            REL,
            &ctx,
        );
        assert_close(
            &[p.power(&q, &v, t)],
            &[p.jets().power(&q, &v, t)],
            REL,
            &ctx,
        );
    }
}

twins! {
    PushedAlongX, PushedAlongXJets { m: f64, f: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot)
    }
    fn forces(&self, (_, _): Coord, (_, _): Coord) -> [Scalar; 2] {
        [self.f, 0.0]
    }
}

#[test]
fn a_literal_zero_force_keeps_its_momentum() {
    assert_eq!(
        <PushedAlongX as Lagrangian<2>>::MOMENTUM_CONSERVED,
        [false, true]
    );
    assert_eq!(
        <PushedAlongXJets as Lagrangian<2>>::MOMENTUM_CONSERVED,
        [false, true]
    );
    const {
        assert!(!<PushedAlongX as Lagrangian<2>>::ENERGY_CONSERVED);
    }
    let p = PushedAlongX { m: 2.0, f: 3.0 };
    assert_eq!(
        p.accelerations(&[0.0; 2], &[1.0; 2], 0.0).ok(),
        Some([1.5, 0.0])
    );
    assert_eq!(
        p.jets().accelerations(&[0.0; 2], &[1.0; 2], 0.0).ok(),
        Some([1.5, 0.0])
    );
    assert_eq!(p.power(&[0.0; 2], &[2.0; 2], 0.0), 6.0);
}

/// Constants in the user's module named like the generated parameters and locals do not break
/// `dissipation` and `forces` in either mode.
mod hygiene {
    #![allow(non_upper_case_globals, dead_code)]
    use lagrange::prelude::*;

    const q: f64 = 1.0;
    const qdot: f64 = 2.0;
    const t: f64 = 3.0;
    const x3: f64 = 5.0;
    const p_b: f64 = 10.0;
    const a: f64 = 13.0;

    macro_rules! oscillator {
        ($name:ident, $($mode:tt)*) => {
            pub struct $name {
                pub b: f64,
                pub f: f64,
            }
            #[lagrangian($($mode)*)]
            impl $name {
                fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
                    0.5 * x_dot * x_dot - 0.5 * x * x
                }
                fn dissipation(&self, (_, v): Coord) -> Scalar {
                    0.5 * self.b * v * v
                }
                fn forces(&self, (_, _): Coord, time: Time) -> [Scalar; 1] {
                    // `a` is the user's constant (13.0), weight zero.
                    [self.f + 0.0 * a * time]
                }
            }
        };
    }
    oscillator!(Symbolic,);
    oscillator!(Jets, mode = "jets");

    #[test]
    fn user_constants_do_not_collide_with_generated_names() {
        let want = -1.0 - 0.5 * 2.0 + 3.0;
        let s = Symbolic { b: 0.5, f: 3.0 };
        let j = Jets { b: 0.5, f: 3.0 };
        assert_eq!(s.accelerations(&[1.0], &[2.0], 4.0).ok(), Some([want]));
        assert_eq!(j.accelerations(&[1.0], &[2.0], 4.0).ok(), Some([want]));
    }
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

#[test]
fn friction_on_the_spin_leaves_p_phi_conserved_along_a_run() {
    let top = DampedTop {
        i_perp: 1.0,
        i_par: 0.6,
        m: 1.0,
        g: 1.0,
        l: 1.0,
        c: 0.05,
    };
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
