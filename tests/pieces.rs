//! The one assembly point of the equations of motion, used as outside code would: a hand-written
//! system supplies its pieces (M and f_L by hand) and every derived quantity follows from them;
//! the jets derive the same pieces from L alone; `Method` is non-exhaustive.

use lagrange::eom::{solve, Pieces};
use lagrange::lagrangian::jet_pieces;
use lagrange::prelude::*;

/// A particle on a vertical circle of radius r (a pendulum), L = m r² θ̇²/2 + m g r cos θ, whose
/// pieces are written by hand: M = m r², f_L = −m g r sin θ.
struct HandPieces {
    m: f64,
    r: f64,
    g: f64,
}

impl Lagrangian<1> for HandPieces {
    const COORDINATES: [&'static str; 1] = ["theta"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * (self.m * self.r * self.r / 2.0) + q[0].cos() * (self.m * self.g * self.r)
    }
    fn pieces(&self, q: &[f64; 1], _v: &[f64; 1], _t: f64) -> Pieces<1> {
        Pieces::new(
            [[self.m * self.r * self.r]],
            [-self.m * self.g * self.r * q[0].sin()],
        )
    }
}

#[test]
fn a_hand_written_system_supplies_its_pieces_and_everything_follows() {
    let sys = HandPieces {
        m: 2.0,
        r: 0.5,
        g: 9.81,
    };
    let (q, v) = ([0.7], [1.3]);
    let hand = sys.pieces(&q, &v, 0.0);
    let jets = jet_pieces(&sys, &q, &v, 0.0);
    assert!((hand.mass[0][0] - jets.mass[0][0]).abs() <= 1e-15);
    assert!((hand.lagrangian_force[0] - jets.lagrangian_force[0]).abs() <= 1e-14);
    assert_eq!(hand.applied, [0.0]);
    // accelerations and mass_matrix read the pieces; momenta and the energy come from L.
    let a = sys.accelerations(&q, &v, 0.0).unwrap();
    assert!((a[0] + 9.81 / 0.5 * 0.7_f64.sin()).abs() <= 1e-14);
    assert_eq!(a, solve(&hand, ["theta"], &q, &v, 0.0).unwrap());
    assert_eq!(sys.mass_matrix(&q, &v, 0.0)[(0, 0)], 0.5);
    assert!((sys.momenta(&q, &v, 0.0)[0] - 0.5 * 1.3).abs() <= 1e-15);
    let (h, p) = sys.energy_and_momenta(&q, &v, 0.0);
    assert!((h - sys.energy(&q, &v, 0.0)).abs() <= 1e-15 && p == sys.momenta(&q, &v, 0.0));
}

#[test]
fn the_symbolic_mode_and_the_jets_supply_the_same_pieces() {
    use crate::support::systems::HeavyTop;
    let top = HeavyTop {
        i_perp: 1.3,
        i_par: 0.7,
        m: 0.9,
        g: 9.81,
        l: 0.4,
    };
    let (q, v) = ([0.9, 0.2, -0.4], [0.3, -0.6, 7.0]);
    let sym = top.pieces(&q, &v, 0.0);
    let jets = jet_pieces(&top, &q, &v, 0.0);
    for i in 0..3 {
        for k in i..3 {
            assert!(
                (sym.mass[i][k] - jets.mass[i][k]).abs() <= 1e-13,
                "M[{i}][{k}]"
            );
        }
        assert!(
            (sym.lagrangian_force[i] - jets.lagrangian_force[i]).abs() <= 1e-12,
            "f[{i}]"
        );
    }
}

#[test]
fn method_is_non_exhaustive() {
    let describe = |m: Method| match m {
        Method::Rk4 { .. } | Method::VariationalMidpoint { .. } => "fixed step",
        Method::DormandPrince { .. } | Method::Dop853 { .. } => "adaptive",
        // Outside the runtime a match needs this arm: new methods are coming.
        _ => "another method",
    };
    assert_eq!(
        describe(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12
        }),
        "adaptive"
    );
}
