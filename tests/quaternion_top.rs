//! The heavy symmetric top of eq. 92 in unit-quaternion coordinates (four coordinates, one
//! constraint |q|² = 1, a rank-3 mass matrix): no chart singularity, so Example 1's sleeping top
//! starts exactly upright. Checked against Euler's equations (section B) for the accelerations,
//! against the Euler-angle top and eq. 97 on the six regimes of tests/heavy_top.rs, and against
//! eq. 98 from exactly upright.

use lagrange::prelude::*;
use lagrange_theory::heavy_top::{sleeping_top_lowest_cos, Constants, Top};

use crate::support::quaternion_top::{axis, axis_z_rate, from_euler, tilt, QuaternionTop};
use crate::support::systems::HeavyTop;
use crate::support::Rng;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The body angular velocity ω = 2 E(q) q̇.
fn omega(q: &[f64; 4], v: &[f64; 4]) -> [f64; 3] {
    let [w, x, y, z] = *q;
    [
        2.0 * (-x * v[0] + w * v[1] + z * v[2] - y * v[3]),
        2.0 * (-y * v[0] - z * v[1] + w * v[2] + x * v[3]),
        2.0 * (-z * v[0] + y * v[1] - x * v[2] + w * v[3]),
    ]
}

/// The constrained accelerations give the body angular acceleration ω̇ = 2E(q)q̈ (E(q̇)q̇ = 0) of
/// Euler's equations with the gravity torque m g l (R₃₂, −R₃₁, 0), and keep |q|² = 1 to second
/// order (q·q̈ = −|q̇|²), at random states: to 1e-12 relative to the size of the terms.
#[test]
fn accelerations_are_eulers_equations_with_the_gravity_torque() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..200 {
        let top = QuaternionTop {
            i_perp: rng.uniform(0.2, 3.0),
            i_par: rng.uniform(0.1, 3.0),
            mgl: rng.uniform(0.1, 5.0),
        };
        let angles = [
            rng.uniform(0.02, 3.12),
            rng.uniform(-7.0, 7.0),
            rng.uniform(-7.0, 7.0),
        ];
        let rates = rng.arr3(-10.0, 10.0);
        let (q, v) = from_euler(angles, rates);
        let (a, _lambda) = top.constrained_accelerations(&q, &v, 0.0).unwrap();
        let wd = omega(&q, &a);
        let w = omega(&q, &v);
        let [qw, qx, qy, qz] = q;
        let (r31, r32) = (2.0 * (qx * qz - qw * qy), 2.0 * (qy * qz + qw * qx));
        let want = [
            ((top.i_perp - top.i_par) * w[1] * w[2] + top.mgl * r32) / top.i_perp,
            ((top.i_par - top.i_perp) * w[2] * w[0] - top.mgl * r31) / top.i_perp,
            0.0,
        ];
        let scale = (w[0].abs() + w[1].abs() + w[2].abs()).powi(2) + top.mgl / top.i_perp;
        for k in 0..3 {
            assert!(
                (wd[k] - want[k]).abs() <= 1e-12 * scale,
                "ω̇{k}: {} vs Euler {} (scale {scale})",
                wd[k],
                want[k]
            );
        }
        let qa: f64 = (0..4).map(|i| q[i] * a[i]).sum();
        let vv: f64 = v.iter().map(|x| x * x).sum();
        assert!(
            (qa + vv).abs() <= 1e-12 * vv.max(1.0),
            "q·q̈ = {qa}, |q̇|² = {vv}"
        );
    }
}

/// The six regimes of tests/heavy_top.rs (same tops, same initial states).
fn regimes() -> [(&'static str, HeavyTop, [f64; 3], [f64; 3]); 6] {
    let unit = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    let top = |i_perp, i_par, m, g, l| HeavyTop {
        i_perp,
        i_par,
        m,
        g,
        l,
    };
    [
        (
            "wavy",
            top(1.0, 0.5, 0.5, 9.81, 1.0),
            [0.7, 0.0, 0.0],
            [0.0, 0.8, 12.0],
        ),
        ("loops", unit, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0]),
        ("cusps", unit, [0.8, 0.3, -0.2], [0.0, 0.0, 6.0]),
        (
            "below the horizontal, negative spin",
            top(2.3, 0.7, 1.3, 9.81, 0.35),
            [2.2, 0.3, 1.0],
            [0.4, 0.3, -9.0],
        ),
        (
            "slow, large nutation",
            unit,
            [0.3, 0.0, 0.0],
            [0.0, 0.2, 1.5],
        ),
        (
            "fast oblate",
            top(0.5, 0.9, 0.2, 9.81, 0.5),
            [1.1, 0.0, 0.0],
            [0.1, 0.4, 40.0],
        ),
    ]
}

const LOW: &str = "theta max";

/// The tight tolerances of the Euler-angle regime tests.
const TIGHT: Method = Method::Dop853 {
    rtol: 1e-12,
    atol: 1e-14,
};

/// (t, ⟨φ̇⟩) per nutation period of the quaternion top: successive lowest points of the axis
/// (R₃₃ = cos θ at a minimum), φ the azimuth of the axis unwrapped along every step.
fn quaternion_periods(
    top: &QuaternionTop,
    q0: [f64; 4],
    v0: [f64; 4],
    until: f64,
) -> Vec<(f64, f64)> {
    let traj = Simulation::constrained(top, q0, v0)
        .method(TIGHT)
        .until(until)
        .event(
            Event::zero_crossing(LOW, |_t, q: &[f64; 4], v: &[f64; 4]| axis_z_rate(q, v)).rising(),
        )
        .run()
        .unwrap();
    let inv = traj.invariants();
    assert!(inv.constraints.unwrap().position < 1e-14, "{inv:?}");
    assert!(inv.energy.unwrap().max_rel < 1e-11, "{inv:?}");
    let azimuth = |q: &[f64; 4]| {
        let a = axis(q);
        a[0].atan2(-a[1])
    };
    let unwrap = |phi: f64, near: f64| {
        let two_pi = std::f64::consts::TAU;
        phi + two_pi * ((near - phi) / two_pi).round()
    };
    // φ unwrapped along the steps, then each event's φ unwrapped against the step before it.
    let mut phis = Vec::with_capacity(traj.len());
    for q in &traj.q {
        let p = azimuth(q);
        let p = phis.last().map_or(p, |&prev| unwrap(p, prev));
        phis.push(p);
    }
    let lows: Vec<(f64, f64)> = traj
        .events
        .iter()
        .map(|e| {
            let k = traj.t.partition_point(|&t| t <= e.t).saturating_sub(1);
            (e.t, unwrap(azimuth(&e.q), phis[k]))
        })
        .collect();
    lows.windows(2)
        .map(|w| (w[1].0 - w[0].0, (w[1].1 - w[0].1) / (w[1].0 - w[0].0)))
        .collect()
}

/// (t, ⟨φ̇⟩) per nutation period of the Euler-angle top (θ̇ = 0 falling: θ max).
fn euler_periods(top: &HeavyTop, q0: [f64; 3], v0: [f64; 3], until: f64) -> Vec<(f64, f64)> {
    let traj = Simulation::new(top, q0, v0)
        .method(TIGHT)
        .until(until)
        .event(Event::zero_crossing(LOW, |_t, _q, v: &[f64; 3]| v[0]).falling())
        .run()
        .unwrap();
    traj.events
        .windows(2)
        .map(|w| (w[1].t - w[0].t, (w[1].q[1] - w[0].q[1]) / (w[1].t - w[0].t)))
        .collect()
}

/// On the six regimes, the quaternion top's nutation period and mean precession rate per period
/// agree with the Euler-angle top's to 1e-9, and the period with eq. 97 to 1e-9.
#[test]
fn six_regimes_agree_with_the_euler_angle_top_and_eq97() {
    for (name, top, angles, rates) in regimes() {
        let theory = Top {
            i_perp: top.i_perp,
            i_par: top.i_par,
            mgl: top.m * top.g * top.l,
        };
        let period = Constants::from_state(&theory, &angles, &rates)
            .unwrap()
            .nutation
            .period()
            .unwrap();
        let qtop = QuaternionTop {
            i_perp: top.i_perp,
            i_par: top.i_par,
            mgl: theory.mgl,
        };
        let (q0, v0) = from_euler(angles, rates);
        let quat = quaternion_periods(&qtop, q0, v0, 5.0 * period);
        let euler = euler_periods(&top, angles, rates, 5.0 * period);
        assert!(
            quat.len() >= 3 && quat.len() == euler.len(),
            "{name}: {quat:?} {euler:?}"
        );
        for ((tq, rq), (te, re)) in quat.iter().zip(&euler) {
            assert!(
                rel(*tq, period) < 1e-9,
                "{name}: period {tq} vs eq. 97 {period}"
            );
            assert!(
                rel(*tq, *te) < 1e-9,
                "{name}: period {tq} vs Euler angles {te}"
            );
            assert!(
                (rq - re).abs() < 1e-9 * re.abs().max(1e-3),
                "{name}: ⟨φ̇⟩ {rq} vs Euler angles {re}"
            );
        }
    }
}

/// Example 1 (eq. 98) with I⊥ = I∥ = mgl = 1 (ω0 = 1): released exactly upright, spinning at Ω
/// about the axis, after a tilt of 1e-8.
fn upright(ratio: f64, until: f64, method: Method) -> Trajectory<4> {
    let top = QuaternionTop {
        i_perp: 1.0,
        i_par: 1.0,
        mgl: 1.0,
    };
    // The axis tilted by ε about the x axis, spinning at Ω (ω = (0, 0, Ω) in the body).
    let eps: f64 = 1e-8;
    let q = [(eps / 2.0).cos(), (eps / 2.0).sin(), 0.0, 0.0];
    let v = crate::support::quaternion_top::qmul(q, [0.0, 0.0, 0.0, ratio]);
    let v = [v[0] / 2.0, v[1] / 2.0, v[2] / 2.0, v[3] / 2.0];
    Simulation::constrained(&top, q, v)
        .method(method)
        .until(until)
        .event(
            Event::zero_crossing(LOW, |_t, q: &[f64; 4], v: &[f64; 4]| axis_z_rate(q, v)).rising(),
        )
        .run()
        .unwrap()
}

/// Above the threshold Ω_c = 2ω0 (Ω = 1.05 Ω_c) the axis stays within 1e-6 of upright over 100
/// periods of ω0; exactly upright (no nudge) it stays there to round-off.
#[test]
fn eq98_exactly_upright_above_threshold_stays_up() {
    let until = 100.0 * std::f64::consts::TAU;
    let traj = upright(2.0 * 1.05, until, TIGHT);
    let worst = traj.q.iter().map(tilt).fold(0.0, f64::max);
    assert!(worst < 1e-6, "tilt reached {worst}");
    // The small-oscillation bound θ0 Ω/√(Ω² − 4ω0²) = 3.3e-8 (the nudge is 1e-8).
    assert!(worst < 4e-8, "tilt reached {worst}");
    assert!(traj.invariants().constraints.unwrap().position < 1e-15);
}

/// Below the threshold (Ω = 0.95 Ω_c) it falls from upright to p = Ω²/2ω0² − 1 (eq. 98), to 1e-6.
#[test]
fn eq98_exactly_upright_below_threshold_falls_to_the_printed_p() {
    let ratio = 2.0 * 0.95;
    let traj = upright(ratio, 100.0 * std::f64::consts::TAU, TIGHT);
    let want = sleeping_top_lowest_cos(ratio, 1.0).unwrap();
    assert!((want - (ratio * ratio / 2.0 - 1.0)).abs() < 1e-15);
    // Lowest points of the axis: the falls (before the first fall, the wobble of the nudge has
    // minima of cos θ too, within 1e-15 of 1).
    let falls: Vec<f64> = traj
        .events
        .iter()
        .map(|e| axis(&e.q)[2])
        .filter(|p| *p < 1.0 - 1e-6)
        .collect();
    assert!(falls.len() >= 2, "the top fell {} times", falls.len());
    for p in falls {
        assert!((p - want).abs() < 1e-6, "fell to p = {p}, eq. 98 {want}");
    }
}

/// The variational method (RATTLE) keeps |q| = 1 at every node and the energy and the two
/// conserved angular momenta bounded, on the loops regime.
#[test]
fn rattle_keeps_the_unit_norm_and_the_energy() {
    let (_, top, angles, rates) = regimes()[1];
    let qtop = QuaternionTop {
        i_perp: top.i_perp,
        i_par: top.i_par,
        mgl: top.m * top.g * top.l,
    };
    let (q0, v0) = from_euler(angles, rates);
    let traj = Simulation::constrained(&qtop, q0, v0)
        .method(Method::VariationalMidpoint { dt: 1e-3 })
        .until(20.0)
        .run()
        .unwrap();
    let inv = traj.invariants();
    let c = inv.constraints.unwrap();
    assert!(c.position < 1e-14 && c.velocity < 1e-12, "{c:?}");
    assert_eq!(c.projection, 0.0);
    // Energy error of a second-order symplectic method at h = 1e-3: O(h²) bounded.
    assert!(inv.energy.unwrap().max_rel < 1e-5, "{inv:?}");
    // The body spin ω₃ (L∥ = I∥ ω₃, eq. 93) is conserved.
    let w30 = omega(&traj.q[0], &traj.qdot[0])[2];
    for (q, v) in traj.q.iter().zip(&traj.qdot) {
        assert!(
            (omega(q, v)[2] - w30).abs() < 1e-6 * w30.abs(),
            "ω₃ drifted"
        );
    }
}
