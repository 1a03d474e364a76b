//! Orbits as users ask for them: periodic up to a shift of the coordinates (a pendulum whirling
//! over the top), and fixed points of a Poincaré section's return map (a limit cycle, a
//! libration), each against a closed form or against plain runs that share no code with the
//! shooting (no variational equations: event times and differences of returns).

use lagrange::prelude::*;
use lagrange::sensitivity::{OrbitStability, Shooting};
use lagrange_examples::pendulum_system::{elliptic_ke, Pendulum};
use lagrange_examples::stiff_system::RigidPendulumXy;
use std::f64::consts::PI;

/// The van der Pol oscillator ẍ − μ(1 − x²)ẋ + x = 0: L = ½ẋ² − ½x² with the force
/// Q = μ(1 − x²)ẋ. Its limit cycle attracts every motion but the equilibrium.
pub struct VanDerPol {
    /// μ.
    pub mu: f64,
}

#[lagrangian]
impl VanDerPol {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - 0.5 * x * x
    }
    /// The negative damping inside |x| < 1, positive outside.
    fn forces(&self, (x, x_dot): Coord) -> [Scalar; 1] {
        [self.mu * (1.0 - x * x) * x_dot]
    }
}

const TIGHT: Method = Method::Dop853 {
    rtol: 1e-13,
    atol: 1e-13,
};

/// θ̈ = −sin θ whirling over the top: with θ̇ = θ̇₀ at θ = 0, energy ½θ̇² − cos θ conserved, one
/// turn takes T = ∫₀^{2π} dθ/θ̇ = ∫₀^{2π} dθ / √(θ̇₀² − 4 sin²(θ/2)) = (4/θ̇₀) K(k), k = 2/θ̇₀
/// (θ = 2φ). The orbit closes up to θ ↦ θ + 2π; pinned to the energy ½·9 − 1 = 3.5 from a start
/// off it (θ̇ = 2.9, θ = 0.1) and a period guess 5 % off, the shooting finds T = 4K(2/3)/3 to
/// 1e-10 (the runs at 1e-13) with the start at that energy; its multipliers are 1, 1 (a
/// conservative family: neutral).
#[test]
fn a_whirling_pendulum_is_periodic_up_to_a_turn() {
    let p = Pendulum { g: 1.0, l: 1.0 };
    let (kk, _) = elliptic_ke(2.0 / 3.0);
    let t_closed = 4.0 * kk / 3.0;
    let orbit = Shooting::autonomous(&p, [0.1], [2.9], 2.3)
        .method(TIGHT)
        .shift([2.0 * PI])
        .pin_energy(3.5)
        .find()
        .unwrap();
    let energy = 0.5 * orbit.qdot0[0] * orbit.qdot0[0] - orbit.q0[0].cos();
    eprintln!(
        "whirl: T off by {:.1e}, energy by {:.1e}, closure {:.1e}, multipliers {:?}",
        orbit.period - t_closed,
        energy - 3.5,
        orbit.closure,
        orbit.multipliers
    );
    assert!((orbit.period - t_closed).abs() < 1e-10, "{}", orbit.period);
    assert!((energy - 3.5).abs() < 1e-10, "{energy}");
    assert!(orbit.multipliers.iter().all(|m| (m - 1.0).norm() < 1e-4));
    assert_eq!(orbit.stability, OrbitStability::Neutral);
    // Without the shift the same start is no orbit: θ never comes back.
    assert!(Shooting::autonomous(&p, [0.1], [2.9], 2.3)
        .method(TIGHT)
        .pin_energy(3.5)
        .max_iterations(8)
        .find()
        .is_err());
}

/// The return times of a plain run from `x0` through the section x = 0 going up (x < 0 → x > 0),
/// none of the shooting's code: the event's located times.
fn returns(vdp: &VanDerPol, v0: f64, until: f64) -> (Vec<f64>, Vec<f64>) {
    let run = Simulation::new(vdp, [0.0], [v0])
        .method(TIGHT)
        .until(until)
        .event(Event::zero_crossing("x = 0 up", |_t, q: &[f64; 1], _v| q[0]).rising())
        .run()
        .unwrap();
    run.events.iter().map(|h| (h.t, h.qdot[0])).unzip()
}

/// Van der Pol at μ = 1 shot to the section x = 0, ẋ > 0 from ẋ = 2 (the cycle crosses at
/// ẋ ≈ 2.17) with a period guess of 6: the return map's fixed point and its multipliers. Against
/// plain runs (no variational equations): the return times of a run from the fixed point, each
/// the period to 1e-9 (measured: 6.6632868593231 ± 6e-14 over 9 turns; the shooting's
/// 6.663286859323372, Newton stopped at its closure tolerance), the return map's derivative
/// dP/dẋ by central differences of the returns of runs from ẋ* ± 1e-4 (error ≈ h² P'''/6 and
/// the returns' 1e-13 over 2h) against the section's nontrivial multiplier 8.597e-4, to 1e-6
/// relative (measured 8e-9); the flow's direction maps to 0. And the same orbit by the phase
/// condition (`Shooting::autonomous` without a section): the same period to 1e-9, its
/// nontrivial multiplier the section's to 1e-8 relative (measured 6e-11; both are
/// exp ∫ μ(1 − x²) dt over the cycle, by Liouville).
#[test]
fn a_limit_cycle_is_a_fixed_point_of_its_section() {
    let vdp = VanDerPol { mu: 1.0 };
    let orbit = Shooting::autonomous(&vdp, [0.0], [2.0], 6.0)
        .method(TIGHT)
        .section(|| Event::zero_crossing("x = 0 up", |_t, q: &[f64; 1], _v| q[0]).rising())
        .find()
        .unwrap();
    let v_star = orbit.qdot0[0];
    assert!(orbit.q0[0].abs() < 1e-12, "{:?}", orbit.q0);
    // The return times of a plain run from the fixed point.
    let (times, speeds) = returns(&vdp, v_star, 70.0);
    let gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    let t_plain = times[0];
    eprintln!(
        "section: ẋ* = {v_star}, T = {} ({} iterations); plain run's returns {:?}",
        orbit.period, orbit.iterations, gaps
    );
    assert!(
        (orbit.period - t_plain).abs() < 1e-9,
        "{} vs {t_plain}",
        orbit.period
    );
    assert!(
        (speeds[0] - v_star).abs() < 1e-9,
        "{} vs {v_star}",
        speeds[0]
    );
    assert!(
        gaps.iter().all(|g| (g - orbit.period).abs() < 1e-9),
        "{gaps:?}"
    );
    // The multipliers: one at 0 (the flow's direction), one the cycle's.
    let mut moduli: Vec<f64> = orbit.multipliers.iter().map(|m| m.norm()).collect();
    moduli.sort_by(f64::total_cmp);
    assert!(moduli[0] < 1e-8, "{moduli:?}");
    let mu = orbit
        .multipliers
        .iter()
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))
        .unwrap()
        .re;
    let h = 1e-4;
    let p = |v: f64| returns(&vdp, v, 7.0).1[0];
    let dp = (p(v_star + h) - p(v_star - h)) / (2.0 * h);
    eprintln!("multiplier {mu:e}, dP/dẋ by differences {dp:e}");
    assert!((mu - dp).abs() < 1e-6 * mu.abs(), "{mu} vs {dp}");
    assert_eq!(orbit.stability, OrbitStability::AsymptoticallyStable);
    // The phase-condition shooting: the same orbit.
    let plain = Shooting::autonomous(&vdp, [0.0], [2.0], 6.0)
        .method(TIGHT)
        .find()
        .unwrap();
    let nontrivial = plain
        .multipliers
        .iter()
        .min_by(|a, b| a.norm().total_cmp(&b.norm()))
        .unwrap()
        .re;
    eprintln!(
        "phase condition: T = {}, nontrivial multiplier {nontrivial:e}",
        plain.period
    );
    assert!((plain.period - orbit.period).abs() < 1e-9);
    assert!((nontrivial - mu).abs() < 1e-8 * mu.abs().max(1e-300) + 1e-14);
}

/// Wrong uses of a section: with a forced system's fixed period, with `pin_amplitude` (both
/// phase conditions), a section that resets the state, and one the motion does not cross again —
/// each a typed error that says what to do.
#[test]
fn section_misuses_are_refused() {
    let p = Pendulum { g: 1.0, l: 1.0 };
    let up = || Event::zero_crossing("θ = 0 up", |_t, q: &[f64; 1], _v| q[0]).rising();
    let err = Shooting::forced(&p, [0.0], [0.5], 6.3)
        .section(up)
        .find()
        .unwrap_err()
        .to_string();
    assert!(err.contains("autonomous"), "{err}");
    let err = Shooting::autonomous(&p, [0.0], [0.5], 6.3)
        .section(up)
        .pin_amplitude(0)
        .find()
        .unwrap_err()
        .to_string();
    assert!(err.contains("pin_amplitude"), "{err}");
    let err = Shooting::autonomous(&p, [0.0], [0.5], 6.3)
        .section(|| {
            Event::zero_crossing("θ = 0", |_t, q: &[f64; 1], _v| q[0]).reset(|_t, q, v| (*q, *v))
        })
        .find()
        .unwrap_err()
        .to_string();
    assert!(err.contains("resets the state"), "{err}");
    // A section through the start's level that the motion does not cross again within twice
    // the period guess (a function of time alone).
    let err = Shooting::autonomous(&p, [0.0], [0.5], 6.3)
        .section(|| Event::zero_crossing("t = 100", |t, _q: &[f64; 1], _v| t - 100.0))
        .find()
        .unwrap_err()
        .to_string();
    assert!(err.contains("was not crossed"), "{err}");
}

/// A pendulum written in x, y with its rod a constraint (`fn constraints`): the shooting takes
/// the system as declared (each shot runs on the constrained view from the iterate's
/// projection onto the rod, Φ(t₀) that projection's derivative, the flow at the ends from the
/// run's samples). Pinned to the energy of amplitude 1 (E = −m g l cos 1) from a start at
/// amplitude 0.9 and a period guess 1 % off: T = 4 √(l/g) K(sin ½) to 1e-8 (the ends' flow by
/// differences slows Newton, never moves the orbit), the start on the rod to 1e-12; the
/// multipliers 1, 1 (a conservative family) and two 0 (the directions off the rod, which each
/// start projects away).
#[test]
fn a_constrained_pendulum_is_shot_as_declared() {
    let p = RigidPendulumXy {
        m: 0.7,
        g: 9.81,
        l: 1.3,
    };
    let (kk, _) = elliptic_ke((0.5_f64).sin());
    let t_closed = 4.0 * (p.l / p.g).sqrt() * kk;
    let (q0, v0) = p.state(0.9, 0.0);
    let energy = -p.m * p.g * p.l * (1.0_f64).cos();
    let orbit = Shooting::autonomous(&p, q0, v0, 1.01 * t_closed)
        .method(TIGHT)
        .pin_energy(energy)
        .find()
        .unwrap();
    let rod = orbit.q0[0].hypot(orbit.q0[1]) - p.l;
    let mut mods: Vec<f64> = orbit.multipliers.iter().map(|m| m.norm()).collect();
    mods.sort_by(f64::total_cmp);
    eprintln!(
        "pendulum in x, y: T off by {:.1e}, rod {rod:.1e}, {} iterations, multipliers {mods:?}",
        orbit.period - t_closed,
        orbit.iterations
    );
    assert!((orbit.period - t_closed).abs() < 1e-8, "{}", orbit.period);
    assert!(rod.abs() < 1e-12, "{rod:e}");
    assert!(mods[..2].iter().all(|m| *m < 1e-6), "{mods:?}");
    assert!(mods[2..].iter().all(|m| (m - 1.0).abs() < 1e-4), "{mods:?}");
}
