//! The heavy symmetric top of the reference text (section D, eqs. 92–102), end to end: the top is
//! declared with `#[lagrangian]` as eq. 92 reads (once, in examples/support/systems.rs), integrated
//! with DOP853, and every equation is checked against the simulation and against
//! `lagrange_theory::heavy_top`.
//!
//! Where the text is wrong (eq. 102; the names of θ and φ in section D's first paragraph) the
//! tests assert the correct physics; `docs/ERRATA.md`, section D, records the difference.
//!
//! Regimes: wavy (φ̇ keeps its sign), loops, cusps, a top below the horizontal with negative spin
//! and non-unit parameters, a slow top with large nutation, a fast oblate top.

use lagrange::prelude::*;
use lagrange::Direction;
use lagrange_theory::heavy_top::{
    fast_top_cos_theta, fast_top_precession_rate, sleeping_top_lowest_cos, sleeping_top_max_angle,
    Constants, Motion, Nutation,
};

// The symmetric heavy top, eq. 92: the shared `#[lagrangian]` declaration.
use crate::support::systems::HeavyTop;
use crate::support::Rng;

/// A top and an initial state.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Regime {
    pub(crate) name: &'static str,
    pub(crate) top: HeavyTop,
    pub(crate) q0: [f64; 3],
    pub(crate) qdot0: [f64; 3],
    motion: Motion,
}

const UNIT: HeavyTop = HeavyTop {
    i_perp: 1.0,
    i_par: 0.6,
    m: 1.0,
    g: 1.0,
    l: 1.0,
};

pub(crate) fn regimes() -> [Regime; 6] {
    [
        Regime {
            name: "wavy",
            top: HeavyTop {
                i_perp: 1.0,
                i_par: 0.5,
                m: 0.5,
                g: 9.81,
                l: 1.0,
            },
            q0: [0.7, 0.0, 0.0],
            qdot0: [0.0, 0.8, 12.0],
            motion: Motion::Wavy,
        },
        Regime {
            name: "loops",
            top: UNIT,
            q0: [1.0, 0.0, 0.0],
            qdot0: [0.0, -0.5, 8.0],
            motion: Motion::Loops,
        },
        Regime {
            name: "cusps",
            top: UNIT,
            q0: [0.8, 0.3, -0.2],
            qdot0: [0.0, 0.0, 6.0],
            motion: Motion::Cusps,
        },
        Regime {
            name: "below the horizontal, negative spin",
            top: HeavyTop {
                i_perp: 2.3,
                i_par: 0.7,
                m: 1.3,
                g: 9.81,
                l: 0.35,
            },
            q0: [2.2, 0.3, 1.0],
            qdot0: [0.4, 0.3, -9.0],
            motion: Motion::Loops,
        },
        Regime {
            name: "slow, large nutation",
            top: UNIT,
            q0: [0.3, 0.0, 0.0],
            qdot0: [0.0, 0.2, 1.5],
            motion: Motion::Wavy,
        },
        Regime {
            name: "fast oblate",
            top: HeavyTop {
                i_perp: 0.5,
                i_par: 0.9,
                m: 0.2,
                g: 9.81,
                l: 0.5,
            },
            q0: [1.1, 0.0, 0.0],
            qdot0: [0.1, 0.4, 40.0],
            motion: Motion::Loops,
        },
    ]
}

/// θ̇ = 0 going from + to −: a maximum of θ (the lowest point of the axis, p = p1).
const LOW: &str = "theta max";

fn simulate(r: &Regime, periods: f64) -> (Trajectory<3>, Constants) {
    let c = Constants::from_state(&r.top.theory(), &r.q0, &r.qdot0).unwrap();
    let t = c.nutation.period().unwrap();
    let traj = Simulation::new(&r.top, r.q0, r.qdot0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(periods * t)
        .event(Event::zero_crossing(LOW, |_t, _q, v: &[f64; 3]| v[0]).falling())
        .run()
        .unwrap();
    (traj, c)
}

fn lows(traj: &Trajectory<3>) -> Vec<&EventHit<3>> {
    traj.events.iter().filter(|e| e.name == LOW).collect()
}

fn random_top(rng: &mut Rng) -> (HeavyTop, [f64; 3], [f64; 3]) {
    let top = HeavyTop {
        i_perp: rng.uniform(0.2, 3.0),
        i_par: rng.uniform(0.1, 3.0),
        m: rng.uniform(0.1, 2.0),
        g: 9.81,
        l: rng.uniform(0.05, 1.0),
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
    (top, q, qd)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn regimes_are_what_their_names_say() {
    for r in regimes() {
        let c = Constants::from_state(&r.top.theory(), &r.q0, &r.qdot0).unwrap();
        let n = c.nutation;
        assert_eq!(n.motion().unwrap(), r.motion, "{}", r.name);
        let roots = n.roots().unwrap();
        let (th_min, th_max) = roots.theta_range();
        match r.name {
            "below the horizontal, negative spin" => {
                assert!(c.l_par < 0.0 && th_min > std::f64::consts::FRAC_PI_2);
            }
            "slow, large nutation" => assert!(th_max - th_min > 1.0, "{th_min} {th_max}"),
            "fast oblate" => {
                assert!(r.top.i_par > r.top.i_perp && n.omega / n.omega0 > 20.0);
            }
            _ => {}
        }
    }
}

// ---------------------------------------------------------------------------------------------
// eq. 92
// ---------------------------------------------------------------------------------------------

#[test]
fn eq92_lagrangian_and_accelerations_match_closed_form() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for _ in 0..2000 {
        let (top, q, qd) = random_top(&mut rng);
        let (s, c) = q[0].sin_cos();
        let mgl = top.mgl();
        let w3 = qd[2] + qd[1] * c;
        let l_closed = top.i_perp / 2.0 * (qd[0] * qd[0] + qd[1] * qd[1] * s * s)
            + top.i_par / 2.0 * w3 * w3
            - mgl * c;
        let l_gen = top.lagrangian(&q, &qd, 0.0_f64);
        assert!((l_gen - l_closed).abs() <= 1e-12 * l_closed.abs().max(1.0));
        // Hand-derived Euler–Lagrange equations of eq. 92.
        let th =
            qd[1] * qd[1] * s * c - top.i_par / top.i_perp * w3 * qd[1] * s + mgl / top.i_perp * s;
        let ph = qd[0] * (top.i_par * w3 - 2.0 * top.i_perp * qd[1] * c) / (top.i_perp * s);
        let ps = qd[1] * qd[0] * s - ph * c;
        let got = top.accelerations(&q, &qd, 0.0).unwrap();
        let scale = [th, ph, ps].iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for (g, w) in got.iter().zip([th, ph, ps]) {
            assert!((g - w).abs() <= 1e-12 * scale, "{got:?} vs {th} {ph} {ps}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// eqs. 93–94
// ---------------------------------------------------------------------------------------------

#[test]
fn eq93_eq94_cyclic_coordinates_and_printed_momenta() {
    assert_eq!(
        <HeavyTop as Lagrangian<3>>::COORDINATES,
        ["theta", "phi", "psi"]
    );
    assert_eq!(<HeavyTop as Lagrangian<3>>::CYCLIC, [false, true, true]);
    let mut rng = Rng(77);
    for _ in 0..1000 {
        let (top, q, qd) = random_top(&mut rng);
        let (s, c) = q[0].sin_cos();
        let l_par = top.i_par * (qd[2] + qd[1] * c); // eq. 93
        let l_phi = top.i_perp * qd[1] * s * s + l_par * c; // eq. 94
        let p = top.momenta(&q, &qd, 0.0);
        assert!((p[0] - top.i_perp * qd[0]).abs() <= 1e-12 * p[0].abs().max(1.0));
        assert!((p[1] - l_phi).abs() <= 1e-12 * l_phi.abs().max(1.0));
        assert!((p[2] - l_par).abs() <= 1e-12 * l_par.abs().max(1.0));
        let k = Constants::from_state(&top.theory(), &q, &qd).unwrap();
        assert!((k.l_par - l_par).abs() <= 1e-12 * l_par.abs().max(1.0));
        assert!((k.l_phi - l_phi).abs() <= 1e-12 * l_phi.abs().max(1.0));
    }
}

#[test]
fn eq93_eq94_momenta_hold_along_trajectories_and_phi_dot_relation() {
    for r in regimes() {
        let (traj, c) = simulate(&r, 5.0);
        let n = c.nutation;
        for (i, (q, qd)) in traj.q.iter().zip(&traj.qdot).enumerate() {
            let p = traj.momenta[i];
            assert!(
                rel(p[2], c.l_par) < 1e-10,
                "{}: L∥ {} vs {}",
                r.name,
                p[2],
                c.l_par
            );
            let l_scale = c.l_phi.abs().max(c.l_par.abs());
            assert!((p[1] - c.l_phi).abs() < 1e-10 * l_scale, "{}: L_φ", r.name);
            // eq. 94: φ̇ = Ω (p0 − cos θ)/sin²θ, relative to the size of its terms.
            let (s, co) = q[0].sin_cos();
            let want = n.omega * (n.p0 - co) / (s * s);
            let scale = n.omega.abs() * (n.p0.abs() + 1.0) / (s * s);
            assert!((qd[1] - want).abs() < 1e-10 * scale, "{}: φ̇", r.name);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// eq. 95
// ---------------------------------------------------------------------------------------------

#[test]
fn eq95_energy_is_the_printed_e_and_is_conserved() {
    let mut rng = Rng(4242);
    for _ in 0..1000 {
        let (top, q, qd) = random_top(&mut rng);
        let k = Constants::from_state(&top.theory(), &q, &qd).unwrap();
        let n = k.nutation;
        let (s, c) = q[0].sin_cos();
        let printed = top.i_perp / 2.0
            * (qd[0] * qd[0] + n.omega * n.omega * (n.p0 - c).powi(2) / (s * s))
            + k.l_par * k.l_par / (2.0 * top.i_par)
            + top.mgl() * c;
        let e = top.energy(&q, &qd, 0.0);
        assert!(
            (e - printed).abs() <= 1e-10 * printed.abs().max(1.0),
            "{e} vs {printed}"
        );
        assert!((e - k.energy).abs() <= 1e-12 * e.abs().max(1.0));
    }
    for r in regimes() {
        let (traj, c) = simulate(&r, 5.0);
        let drift = traj.invariants().energy.unwrap().max_rel;
        assert!(drift < 1e-10, "{}: energy drift {drift}", r.name);
        assert!(rel(traj.energy[0], c.energy) < 1e-13);
    }
}

// ---------------------------------------------------------------------------------------------
// eq. 96
// ---------------------------------------------------------------------------------------------

#[test]
fn eq96_p_dot_squared_is_the_cubic_along_trajectories() {
    for r in regimes() {
        let (traj, c) = simulate(&r, 5.0);
        let n = c.nutation;
        let w2 = n.omega0 * n.omega0;
        for (q, qd) in traj.q.iter().zip(&traj.qdot) {
            let (s, p) = q[0].sin_cos();
            let p_dot = -s * qd[0];
            // The size of the terms of eq. 96 before the differences p_E − p, p0 − p cancel.
            let gravity = 2.0 * w2 * (1.0 - p * p) * (n.p_e.abs() + p.abs());
            let gyro = n.omega * n.omega * (n.p0.abs() + p.abs()).powi(2);
            let size = gravity + gyro + p_dot * p_dot;
            let residual = p_dot * p_dot - n.f(p);
            assert!(
                residual.abs() <= 1e-10 * size,
                "{}: {residual} vs {size}",
                r.name
            );
        }
        // The motion stays between the roots p1 and p2.
        let roots = n.roots().unwrap();
        let width = roots.p2 - roots.p1;
        for q in &traj.q {
            let p = q[0].cos();
            assert!(p > roots.p1 - 1e-9 * width && p < roots.p2 + 1e-9 * width);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// eq. 97
// ---------------------------------------------------------------------------------------------

#[test]
fn eq97_nutation_period_from_turning_points_equals_quadrature() {
    for r in regimes() {
        let (traj, c) = simulate(&r, 6.0);
        let t = c.nutation.period().unwrap();
        let hits = lows(&traj);
        assert!(hits.len() >= 5, "{}: {} turning points", r.name, hits.len());
        let roots = c.nutation.roots().unwrap();
        for w in hits.windows(2) {
            let measured = w[1].t - w[0].t;
            assert!(
                rel(measured, t) < 1e-9,
                "{}: period {measured} vs eq. 97 {t} ({:e})",
                r.name,
                rel(measured, t)
            );
            // The located turning point is the root p1.
            assert!((w[0].q[0].cos() - roots.p1).abs() < 1e-9, "{}", r.name);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// eq. 98 (Example 1): the sleeping top. The Euler-angle chart is singular at θ = 0 (the mass
// matrix loses rank), so the top starts at θ0 = 1e-3, not exactly upright, released at rest.
// ---------------------------------------------------------------------------------------------

const THETA0: f64 = 1e-3;

/// I⊥ = I∥ = 1, mgl = 1: ω0 = 1 and Ω = ψ̇ for a top released at rest.
const SLEEPER: HeavyTop = HeavyTop {
    i_perp: 1.0,
    i_par: 1.0,
    m: 1.0,
    g: 1.0,
    l: 1.0,
};

fn sleeping_run(ratio: f64, until: f64, terminal: bool) -> Trajectory<3> {
    let mut ev = Event::zero_crossing(LOW, |_t, _q, v: &[f64; 3]| v[0]).falling();
    if terminal {
        ev = ev.terminal();
    }
    Simulation::new(&SLEEPER, [THETA0, 0.0, 0.0], [0.0, 0.0, ratio])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-15,
        })
        .until(until)
        .event(ev)
        .run()
        .unwrap()
}

#[test]
fn eq98_sleeping_top_below_threshold_falls_to_the_printed_p() {
    for ratio in [1.5, 1.8, 1.9] {
        let traj = sleeping_run(ratio, 500.0, true);
        let hit = lows(&traj)[0];
        let p = hit.q[0].cos();
        let want = sleeping_top_lowest_cos(ratio, 1.0).unwrap();
        assert!((want - (ratio * ratio / 2.0 - 1.0)).abs() < 1e-15);
        assert!(
            (p - want).abs() < 1e-5,
            "Ω/ω0 = {ratio}: fell to p = {p}, eq. 98 {want}"
        );
        // And exactly (θ0 ≠ 0) to the root p1 of eq. 96.
        let c = Constants::from_state(&SLEEPER.theory(), &[THETA0, 0.0, 0.0], &[0.0, 0.0, ratio])
            .unwrap();
        assert!((p - c.nutation.roots().unwrap().p1).abs() < 1e-9);
    }
}

#[test]
fn eq98_sleeping_top_above_threshold_stays_up() {
    for ratio in [2.1, 2.5, 3.0] {
        let c = Constants::from_state(&SLEEPER.theory(), &[THETA0, 0.0, 0.0], &[0.0, 0.0, ratio])
            .unwrap();
        let t = c.nutation.period().unwrap();
        let traj = sleeping_run(ratio, 4.0 * t, false);
        let highest = traj.q.iter().map(|q| q[0]).fold(0.0, f64::max);
        let max = lows(&traj).iter().map(|e| e.q[0]).fold(0.0, f64::max);
        assert!(lows(&traj).len() >= 3 && highest <= max * (1.0 + 1e-12));
        assert!(max < 4.0 * THETA0, "Ω/ω0 = {ratio}: θ reached {max}");
        // Exactly the root p1 of eq. 96 ...
        let p1 = c.nutation.roots().unwrap().p1;
        assert!((max.cos() - p1).abs() < 1e-12, "{} vs {p1}", max.cos());
        // ... and the small-oscillation bound θ0 Ω/√(Ω² − 4ω0²), whose relative error is
        // O(θ0²/(Ω² − 4ω0²)) (1.3e-5 at Ω/ω0 = 2.1, next to the threshold).
        let bound = sleeping_top_max_angle(THETA0, ratio, 1.0).unwrap();
        assert!(
            rel(max, bound) < 1e-4,
            "Ω/ω0 = {ratio}: θ_max {max} vs bound {bound}"
        );
        // Near the pole the quadrature of ⟨φ̇⟩ (nearly singular 1/(1 − p²)) still holds to 1e-7.
        let want = c.nutation.mean_precession_rate().unwrap();
        for m in measured_mean_rates(&traj) {
            assert!(rel(m, want) < 1e-7, "Ω/ω0 = {ratio}: ⟨φ̇⟩ {m} vs {want}");
        }
    }
}

#[test]
fn eq98_at_the_threshold_the_top_is_marginally_stable() {
    // Ω = Ω_c = 2ω0 (the text counts it as unstable, "Ω ≤ Ω_c"): released at rest from θ0 the
    // axis only reaches cos θ = 1 − 2 sin(θ0/2), i.e. θ_max ≈ √(2θ0) → 0 as θ0 → 0: stable.
    let mut maxima = Vec::new();
    for theta0 in [1e-3, 1e-4] {
        let traj = Simulation::new(&SLEEPER, [theta0, 0.0, 0.0], [0.0, 0.0, 2.0])
            .method(Method::Dop853 {
                rtol: 1e-12,
                atol: 1e-16,
            })
            .until(1e4)
            .event(
                Event::zero_crossing(LOW, |_t, _q, v: &[f64; 3]| v[0])
                    .falling()
                    .terminal(),
            )
            .run()
            .unwrap();
        let max = lows(&traj)[0].q[0];
        let exact = (1.0 - 2.0 * (theta0 / 2.0).sin()).acos();
        assert!(rel(max, exact) < 1e-8, "θ0 = {theta0}: {max} vs {exact}");
        assert!(rel(max, (2.0 * theta0).sqrt()) < theta0, "{max}");
        maxima.push(max);
    }
    assert!(rel(maxima[0] / maxima[1], 10.0_f64.sqrt()) < 1e-3);
}

// ---------------------------------------------------------------------------------------------
// eqs. 99–101 (Example 2): the fast top released at rest.
// ---------------------------------------------------------------------------------------------

/// A fast top released at rest from θ = 1 with Ω/ω0 = `ratio` (ω0 = 1.5, I∥/I⊥ = 0.8).
fn fast_top(ratio: f64) -> (HeavyTop, [f64; 3], [f64; 3], Constants) {
    let top = HeavyTop {
        i_perp: 1.2,
        i_par: 0.96,
        m: 1.0,
        g: 9.81,
        l: 1.5 * 1.5 * 1.2 / 9.81,
    };
    let omega = ratio * 1.5;
    let spin = omega * top.i_perp / top.i_par;
    let (q0, qd0) = ([1.0, 0.0, 0.0], [0.0, 0.0, spin]);
    let c = Constants::from_state(&top.theory(), &q0, &qd0).unwrap();
    assert!(rel(c.nutation.omega, omega) < 1e-14 && rel(c.nutation.omega0, 1.5) < 1e-14);
    (top, q0, qd0, c)
}

/// Largest |cos θ − eq. 101| over the first nutation period, divided by 2Δ.
fn eq101_error(ratio: f64) -> f64 {
    let (top, q0, qd0, c) = fast_top(ratio);
    let n = c.nutation;
    let period = 2.0 * std::f64::consts::PI / n.omega;
    let traj = Simulation::new(&top, q0, qd0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(period)
        .sample_every(period / 500.0)
        .run()
        .unwrap();
    let delta = (n.omega0 / n.omega).powi(2) * (1.0 - n.p0 * n.p0); // Δ of eq. 99
    let err = traj
        .t
        .iter()
        .zip(&traj.q)
        .map(|(t, q)| (q[0].cos() - fast_top_cos_theta(n.p0, n.omega0, n.omega, *t)).abs())
        .fold(0.0, f64::max);
    err / (2.0 * delta)
}

#[test]
fn eq99_to_eq101_fast_top_follows_eq101_to_order_omega0_over_omega_squared() {
    let (e10, e50) = (eq101_error(10.0), eq101_error(50.0));
    // err/2Δ = C (ω0/Ω)² with a bounded C: the ratio is (50/10)² = 25.
    assert!(e10 < 0.1 && e50 < 4e-3, "{e10} {e50}");
    let ratio = e10 / e50;
    assert!(
        (ratio / 25.0 - 1.0).abs() < 0.1,
        "error ratio {ratio}, want 25"
    );
    // And eq. 99's amplitude: the roots of the exact cubic are p0 and ≈ p0 − 2Δ.
    let (_, _, _, c) = fast_top(50.0);
    let n = c.nutation;
    let r = n.roots().unwrap();
    let delta = (n.omega0 / n.omega).powi(2) * (1.0 - n.p0 * n.p0);
    assert!(rel(r.p2, n.p0) < 1e-14);
    assert!(rel(r.p2 - r.p1, 2.0 * delta) < 10.0 * (n.omega0 / n.omega).powi(2));
}

// ---------------------------------------------------------------------------------------------
// eq. 102: the mean precession rate. The text prints φ̇ ≃ (mgl/L∥)[cos Ωt − 1] and
// ⟨φ̇⟩ = mgl/2L∥; the correct fast-top limit is φ̇ ≃ (mgl/L∥)[1 − cos Ωt], ⟨φ̇⟩ = mgl/L∥.
// ---------------------------------------------------------------------------------------------

/// ⟨φ̇⟩ measured over each nutation period between successive turning points.
fn measured_mean_rates(traj: &Trajectory<3>) -> Vec<f64> {
    lows(traj)
        .windows(2)
        .map(|w| (w[1].q[1] - w[0].q[1]) / (w[1].t - w[0].t))
        .collect()
}

#[test]
fn eq102_mean_precession_rate_measured_equals_quadrature_in_every_regime() {
    for r in regimes() {
        let (traj, c) = simulate(&r, 4.0);
        let want = c.nutation.mean_precession_rate().unwrap();
        let rates = measured_mean_rates(&traj);
        assert!(rates.len() >= 2, "{}", r.name);
        for m in rates {
            assert!(
                rel(m, want) < 1e-7,
                "{}: ⟨φ̇⟩ {m} vs quadrature {want}",
                r.name
            );
        }
    }
}

fn fast_top_mean_rate(ratio: f64, spin_sign: f64) -> (f64, f64, Nutation, f64) {
    let (top, q0, mut qd0, _) = fast_top(ratio);
    qd0[2] *= spin_sign;
    let c = Constants::from_state(&top.theory(), &q0, &qd0).unwrap();
    let period = c.nutation.period().unwrap();
    let traj = Simulation::new(&top, q0, qd0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(2.2 * period)
        .sample_every(period / 200.0)
        .event(
            Event::zero_crossing(LOW, |_t, _q, v: &[f64; 3]| v[0])
                .direction_filter(Direction::Falling),
        )
        .run()
        .unwrap();
    let measured = measured_mean_rates(&traj)[0];
    // Instantaneous eq. 102 (corrected): largest |φ̇ − (mgl/L∥)(1 − cos Ωt)| / (mgl/L∥) over
    // the first nutation period.
    let n = c.nutation;
    let scale = top.mgl() / c.l_par;
    let first_period = 2.0 * std::f64::consts::PI / n.omega.abs();
    let inst = traj
        .t
        .iter()
        .zip(&traj.qdot)
        .filter(|(t, _)| **t <= first_period)
        .map(|(t, v)| (v[1] - fast_top_precession_rate(n.omega0, n.omega, *t)).abs())
        .fold(0.0, f64::max)
        / scale.abs();
    (measured, scale, n, inst)
}

#[test]
fn eq102_fast_top_mean_precession_is_mgl_over_l_not_half_of_it() {
    let (mut errs, mut insts) = (Vec::new(), Vec::new());
    for ratio in [10.0, 50.0] {
        for sign in [1.0, -1.0] {
            let (measured, mgl_over_l, n, inst) = fast_top_mean_rate(ratio, sign);
            // The precise quadrature, to 1e-7.
            let quad = n.mean_precession_rate().unwrap();
            assert!(rel(measured, quad) < 1e-7, "{measured} vs {quad}");
            // The sign follows L∥: φ̇ ≥ 0 for L∥ > 0 (the text's [cos Ωt − 1] would make it ≤ 0).
            assert_eq!(measured.signum(), sign);
            let err = rel(measured, mgl_over_l);
            assert!(
                err < 2.0 / (ratio * ratio),
                "Ω/ω0 = {ratio}: {measured} vs {mgl_over_l}"
            );
            // Clearly not the printed mgl/(2L∥).
            assert!(rel(measured, mgl_over_l / 2.0) > 0.9);
            assert!(
                inst < 10.0 / (ratio * ratio),
                "instantaneous eq. 102 error {inst}"
            );
            if sign > 0.0 {
                errs.push(err);
                insts.push(inst);
            }
        }
    }
    // Error ∝ (ω0/Ω)²: ratio 25 between Ω/ω0 = 10 and 50.
    let ratio = errs[0] / errs[1];
    assert!((ratio / 25.0 - 1.0).abs() < 0.1, "error ratio {ratio}");
    let ratio = insts[0] / insts[1];
    assert!(
        (ratio / 25.0 - 1.0).abs() < 0.1,
        "instantaneous error ratio {ratio}"
    );
}
