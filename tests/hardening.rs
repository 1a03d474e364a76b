//! Regression tests of the run time under hostile but valid input: each case once failed with a
//! spurious error or lost accuracy silently; each now integrates, or fails up front with an
//! `InvalidOptions` that says why.

use lagrange::prelude::*;

use crate::support::hand::HeavyTop;

/// A pure relative tolerance (atol = 0) is what a user asking for it expects, also where a
/// component of the state is exactly zero (the README's own heavy-top state has φ = ψ = 0, and
/// a planar motion keeps z ≡ 0): it must integrate, not fail at t0 blamed on stiffness.
#[test]
fn a_zero_absolute_tolerance_is_pure_relative_control() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    for method in [
        Method::Dop853 {
            rtol: 1e-10,
            atol: 0.0,
        },
        Method::DormandPrince {
            rtol: 1e-8,
            atol: 0.0,
        },
    ] {
        let tr = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
            .method(method)
            .until(10.0)
            .run()
            .unwrap_or_else(|e| panic!("{method:?}: {e}"));
        let reference = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
            .method(Method::Dop853 {
                rtol: 1e-13,
                atol: 1e-13,
            })
            .until(10.0)
            .run()
            .unwrap();
        let (a, b) = (tr.q.last().unwrap(), reference.q.last().unwrap());
        let tol = if matches!(method, Method::Dop853 { .. }) {
            1e-7
        } else {
            1e-5
        };
        for i in 0..3 {
            assert!(
                (a[i] - b[i]).abs() <= tol * (1.0 + b[i].abs()),
                "{method:?}: q[{i}] {} vs {}",
                a[i],
                b[i]
            );
        }
    }
}
