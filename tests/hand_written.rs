//! A hand-written `impl Lagrangian<3>` of the heavy top (eq. 92 of the reference text,
//! tests/support/hand.rs) against the hand-derived equations of motion, and the
//! singular-mass-matrix error at θ = 0.

use lagrange::prelude::*;

use crate::support::hand::HeavyTop;
use crate::support::Rng;

/// Hand-derived: I⊥θ̈ = I⊥φ̇²sc − I∥ω₃φ̇s + mgl s;  φ̈ = θ̇(I∥ω₃ − 2I⊥φ̇c)/(I⊥s);  ψ̈ = φ̇θ̇s − φ̈c.
fn closed_form(top: &HeavyTop, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 3] {
    let (s, c) = q[0].sin_cos();
    let (th_d, ph_d, ps_d) = (qd[0], qd[1], qd[2]);
    let w3 = ps_d + ph_d * c;
    let th_dd =
        ph_d * ph_d * s * c - top.i_par / top.i_perp * w3 * ph_d * s + top.mgl / top.i_perp * s;
    let ph_dd = th_d * (top.i_par * w3 - 2.0 * top.i_perp * ph_d * c) / (top.i_perp * s);
    let ps_dd = ph_d * th_d * s - ph_dd * c;
    [th_dd, ph_dd, ps_dd]
}

#[test]
fn heavy_top_accelerations_match_closed_form_at_random_states() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..2000 {
        let top = HeavyTop {
            i_perp: rng.uniform(0.2, 3.0),
            i_par: rng.uniform(0.1, 3.0),
            mgl: rng.uniform(-5.0, 5.0),
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
        let got = top.accelerations(&q, &qd, 0.0).unwrap();
        let want = closed_form(&top, &q, &qd);
        let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for i in 0..3 {
            assert!(
                (got[i] - want[i]).abs() <= 1e-12 * scale,
                "coordinate {i}: got {got:?}, want {want:?} at q={q:?} qd={qd:?}"
            );
        }
    }
}

#[test]
fn heavy_top_momenta_and_energy_are_eqs_93_to_95() {
    let top = HeavyTop {
        i_perp: 1.3,
        i_par: 0.7,
        mgl: 2.1,
    };
    let (q, qd) = ([0.8, 0.3, -1.0], [0.4, -0.6, 9.0]);
    let p = top.momenta(&q, &qd, 0.0);
    let (s, c) = q[0].sin_cos();
    let l_par = top.i_par * (qd[2] + qd[1] * c);
    let l_phi = top.i_perp * qd[1] * s * s + l_par * c;
    assert!((p[2] - l_par).abs() < 1e-14 * l_par.abs());
    assert!((p[1] - l_phi).abs() < 1e-14 * l_phi.abs().max(1.0));
    let e = top.i_perp / 2.0 * (qd[0] * qd[0] + qd[1] * qd[1] * s * s)
        + l_par * l_par / (2.0 * top.i_par)
        + top.mgl * c;
    assert!((top.energy(&q, &qd, 0.0) - e).abs() < 1e-13 * e.abs());
}

#[test]
fn singular_mass_matrix_at_theta_zero_is_a_typed_error() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    let err = top
        .accelerations(&[0.0, 0.2, 0.1], &[0.0, 0.0, 8.0], 1.5)
        .unwrap_err();
    match &err {
        DynamicsError::SingularMassMatrix {
            t,
            q,
            qdot,
            message,
        } => {
            assert_eq!(*t, 1.5);
            assert_eq!(q, &vec![0.0, 0.2, 0.1]);
            assert_eq!(qdot, &vec![0.0, 0.0, 8.0]);
            assert!(message.contains("sin θ = 0"), "{message}");
            assert!(message.contains("Try"), "{message}");
        }
        other => panic!("expected SingularMassMatrix, got {other:?}"),
    }
    assert!(err.to_string().contains("t = 1.5"));
}
