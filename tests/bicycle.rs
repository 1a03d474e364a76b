//! The Whipple bicycle benchmark (Meijaard, Papadopoulos, Ruina, Schwab, Proc. R. Soc. A 463
//! (2007), Table 1 parameters; the published values quoted in
//! `lagrange_examples::bicycle_system::published`), written from its nonlinear geometry with
//! one holonomic and four velocity constraints, linearized on the constraint manifold:
//! M, C₁, K₀, K₂ to 1e-10 relative, the standstill eigenvalues, the weave and capsize speeds by
//! a root finder to 1e-9; and the nonlinear bicycle against the linear solution at 3, 5 and
//! 7 m/s.

use lagrange::prelude::*;
use lagrange_examples::bicycle_system::{published, Bicycle};

fn close(a: &SMatrix<f64, 2, 2>, b: [[f64; 2]; 2], what: &str) {
    let scale = b.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    for i in 0..2 {
        for j in 0..2 {
            assert!(
                (a[(i, j)] - b[i][j]).abs() <= 1e-10 * scale,
                "{what}[{i}][{j}] = {} against the paper's {}",
                a[(i, j)],
                b[i][j]
            );
        }
    }
}

#[test]
fn benchmark_matrices_from_the_nonlinear_bicycle() {
    let bike = Bicycle::benchmark();
    let l0 = bike.lean_and_steer(0.0).unwrap();
    close(&l0.m, published::M, "M");
    close(&(l0.k / bike.g), published::K0, "K0");
    for v in [1.0, 3.0, 7.5] {
        let l = bike.lean_and_steer(v).unwrap();
        close(&l.m, published::M, "M");
        close(&(l.c / v), published::C1, "C1");
        close(&((l.k - l0.k) / (v * v)), published::K2, "K2");
    }
    // At standstill: ±5.53094371765393 and ±3.13164324790656 (the paper's Table 2).
    let eig = l0.eigenvalues().unwrap();
    let [a, b] = published::STANDSTILL;
    let want = [a, b, -b, -a];
    for (l, w) in eig.iter().zip(want) {
        assert!((l.re - w).abs() < 1e-9 && l.im == 0.0, "{eig:?}");
    }
    // The stable band, from a root finder on the linearization.
    let (weave, capsize) = bike.stable_band();
    assert!(
        (weave - published::WEAVE).abs() < 1e-9,
        "weave speed {weave}"
    );
    assert!(
        (capsize - published::CAPSIZE).abs() < 1e-9,
        "capsize speed {capsize}"
    );
}

/// The lean of the linearized bicycle from z₀ = (φ, δ, φ̇, δ̇), by RK4 on the reduced state
/// matrix with steps of 1e-3 s, at the times `t`.
fn linear_lean(a: &nalgebra::DMatrix<f64>, z0: [f64; 4], t: &[f64]) -> Vec<f64> {
    let f = |z: &nalgebra::DVector<f64>| a * z;
    let mut z = nalgebra::DVector::from_row_slice(&z0);
    let (mut now, dt) = (0.0_f64, 1e-3_f64);
    let mut out = Vec::new();
    for &ts in t {
        while now < ts - 1e-12 {
            let h = dt.min(ts - now);
            let k1 = f(&z);
            let k2 = f(&(&z + &k1 * (h / 2.0)));
            let k3 = f(&(&z + &k2 * (h / 2.0)));
            let k4 = f(&(&z + &k3 * h));
            z += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
            now += h;
        }
        out.push(z[0]);
    }
    out
}

#[test]
fn nonlinear_bicycle_follows_its_linearization() {
    let bike = Bicycle::benchmark();
    for (v, grows) in [(3.0, true), (5.0, false), (7.0, true)] {
        let (q0, mut v0) = bike.upright(v);
        v0[3] = 1e-3;
        let until = if v < 4.0 { 3.0 } else { 8.0 };
        let tr = Simulation::constrained(&bike, q0, v0)
            .project_initial_state()
            .method(Method::Dop853 {
                rtol: 1e-11,
                atol: 1e-14,
            })
            .until(until)
            .sample_every(0.05)
            .run()
            .unwrap();
        let (q, u) = (tr.q[0], tr.qdot[0]);
        let a = bike
            .linearize_on_constraints(&bike.upright(v).0, &bike.upright(v).1, 0.0)
            .unwrap()
            .state_matrix(&["phi", "delta"], &["phi", "delta"])
            .unwrap();
        let lin = linear_lean(&a, [q[3], q[5], u[3], u[5]], &tr.t);
        let peak = lin.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for (i, &t) in tr.t.iter().enumerate() {
            // The nonlinear terms are of the amplitude's order (|φ| ≤ 0.04 here).
            assert!(
                (tr.q[i][3] - lin[i]).abs() <= 0.02 * peak,
                "v = {v}, t = {t}: φ = {} against the linear {}",
                tr.q[i][3],
                lin[i]
            );
        }
        // Growing or decaying as the linearization says; at 7 m/s, past the weave's transient,
        // at the capsize eigenvalue's rate.
        let (mid, end) = (tr.t.len() / 2, tr.t.len() - 1);
        let (a_mid, a_end) = (tr.q[mid][3].abs(), tr.q[end][3].abs());
        assert_eq!(a_end > a_mid, grows, "v = {v}: {a_mid} -> {a_end}");
        if v == 7.0 {
            let rate = (a_end / a_mid).ln() / (tr.t[end] - tr.t[mid]);
            let sigma = bike.growth(v);
            assert!(
                (rate - sigma).abs() < 0.01 * sigma,
                "capsize rate {rate} vs {sigma}"
            );
        }
        let inv = tr.invariants();
        assert!(inv.energy.unwrap().max_rel < 1e-11);
        let c = inv.constraints.unwrap();
        assert!(c.position < 1e-13 && c.velocity < 1e-12, "{c:?}");
    }
}
