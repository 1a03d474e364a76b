//! Integrators: convergence orders on problems with known solutions, the heavy top's
//! invariants over 100 nutation periods, events, invalid options and error paths.
//!
//! Every system here is a hand-written `impl Lagrangian` (the heavy top of eq. 92 is the shared
//! one of tests/support/hand.rs), so these tests depend on the runtime alone, not on the macro.

use lagrange::prelude::*;
use lagrange::Direction;

use crate::support::{slope, TOP, TOP_Q0, TOP_V0};

/// x'' = −x (unit mass and frequency).
struct Oscillator;
impl Lagrangian<1> for Oscillator {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        (v[0] * v[0] - q[0] * q[0]) * 0.5
    }
}

/// Kepler problem, GM = 1, in polar coordinates (φ cyclic).
struct Kepler;
impl Lagrangian<2> for Kepler {
    const COORDINATES: [&'static str; 2] = ["r", "phi"];
    const CYCLIC: [bool; 2] = [false, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + q[0] * q[0] * v[1] * v[1]) * 0.5 + S::constant(1.0) / q[0]
    }
}

/// Kepler ellipse e = 0.5, a = 1 from perihelion; after one period (2π) the state returns.
const KEPLER_Q0: [f64; 2] = [0.5, 0.0];
const KEPLER_V0: [f64; 2] = [0.0, 2.0 * 1.732_050_807_568_877_2]; // r φ̇ = √3 at r = 0.5
const KEPLER_T: f64 = 2.0 * std::f64::consts::PI;

fn kepler_error(method: Method) -> (f64, usize) {
    kepler_error_capped(method, None)
}

fn kepler_error_capped(method: Method, max_step: Option<f64>) -> (f64, usize) {
    let mut sim = Simulation::new(&Kepler, KEPLER_Q0, KEPLER_V0)
        .method(method)
        .until(KEPLER_T);
    if let Some(h) = max_step {
        sim = sim.max_step(h);
    }
    let tr = sim.run().unwrap();
    let (q, v) = (tr.q.last().unwrap(), tr.qdot.last().unwrap());
    // Compare in Cartesian position/velocity (φ returns to 2π).
    let (x, y) = (q[0] * q[1].cos(), q[0] * q[1].sin());
    let (vx, vy) = (
        v[0] * q[1].cos() - q[0] * v[1] * q[1].sin(),
        v[0] * q[1].sin() + q[0] * v[1] * q[1].cos(),
    );
    let err = [x - 0.5, y, vx, vy - 3.0_f64.sqrt()]
        .iter()
        .fold(0.0_f64, |m, e| m.max(e.abs()));
    (err, tr.stats.steps)
}

fn oscillator_error(method: Method) -> (f64, usize) {
    oscillator_error_capped(method, None)
}

fn oscillator_error_capped(method: Method, max_step: Option<f64>) -> (f64, usize) {
    let t_end = 10.0;
    let mut sim = Simulation::new(&Oscillator, [1.0], [0.0])
        .method(method)
        .until(t_end);
    if let Some(h) = max_step {
        sim = sim.max_step(h);
    }
    let tr = sim.run().unwrap();
    let err = (tr.q.last().unwrap()[0] - t_end.cos())
        .abs()
        .max((tr.qdot.last().unwrap()[0] + t_end.sin()).abs());
    (err, tr.stats.steps)
}

#[test]
fn fixed_step_methods_show_their_order() {
    for (name, problem) in [
        ("oscillator", oscillator_error as fn(Method) -> (f64, usize)),
        ("kepler", kepler_error),
    ] {
        let base = if name == "kepler" { 400.0 } else { 100.0 };
        let span = if name == "kepler" { KEPLER_T } else { 10.0 };
        let rk4: Vec<_> = [1.0, 2.0, 4.0]
            .iter()
            .map(|m| {
                let dt = span / (base * m);
                (dt, problem(Method::Rk4 { dt }).0)
            })
            .collect();
        let p = slope(&rk4);
        assert!((p - 4.0).abs() < 0.25, "{name} RK4 order {p}: {rk4:?}");
        let vm: Vec<_> = [1.0, 2.0, 4.0]
            .iter()
            .map(|m| {
                let dt = span / (base * m);
                (dt, problem(Method::VariationalMidpoint { dt }).0)
            })
            .collect();
        let p = slope(&vm);
        assert!(
            (p - 2.0).abs() < 0.15,
            "{name} variational order {p}: {vm:?}"
        );
    }
}

#[test]
fn adaptive_methods_at_a_capped_step_show_their_order() {
    // With tolerances so loose that every step is accepted, the controller saturates at
    // max_step: after the first few (smaller) steps the run is a fixed-step run of the method's
    // propagating formula: order 5 for Dormand–Prince, 8 for DOP853.
    let capped = |rtol_method: fn(f64) -> Method,
                  h: f64,
                  problem: fn(Method, Option<f64>) -> (f64, usize)| {
        problem(rtol_method(1.0), Some(h)).0
    };
    let dp = |tol: f64| Method::DormandPrince {
        rtol: tol,
        atol: tol,
    };
    let d8 = |tol: f64| Method::Dop853 {
        rtol: tol,
        atol: tol,
    };
    for (name, problem, span, dp_n, d8_n) in [
        (
            "oscillator",
            oscillator_error_capped as fn(Method, Option<f64>) -> (f64, usize),
            10.0,
            [100.0, 200.0, 400.0],
            [10.0, 14.0, 20.0],
        ),
        (
            "kepler",
            kepler_error_capped,
            KEPLER_T,
            [200.0, 400.0, 800.0],
            [60.0, 80.0, 110.0],
        ),
    ] {
        let pts: Vec<_> = dp_n
            .iter()
            .map(|n| (span / n, capped(dp, span / n, problem)))
            .collect();
        let p = slope(&pts);
        assert!(
            (p - 5.0).abs() < 0.3,
            "{name} Dormand–Prince order {p}: {pts:?}"
        );
        let pts: Vec<_> = d8_n
            .iter()
            .map(|n| (span / n, capped(d8, span / n, problem)))
            .collect();
        let p = slope(&pts);
        assert!((p - 8.0).abs() < 0.5, "{name} DOP853 order {p}: {pts:?}");
    }
}

#[test]
fn adaptive_methods_error_is_proportional_to_the_tolerance() {
    for (name, problem) in [
        ("oscillator", oscillator_error as fn(Method) -> (f64, usize)),
        ("kepler", kepler_error),
    ] {
        for method in [
            (|tol: f64| Method::DormandPrince {
                rtol: tol,
                atol: tol,
            }) as fn(f64) -> Method,
            |tol: f64| Method::Dop853 {
                rtol: tol,
                atol: tol,
            },
        ] {
            let pts: Vec<_> = [1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
                .iter()
                .map(|&tol| (tol, problem(method(tol)).0))
                .collect();
            let p = slope(&pts);
            assert!(
                (0.8..1.15).contains(&p),
                "{name} {:?}: error ∝ tol^{p}: {pts:?}",
                method(1.0)
            );
            assert!(
                pts.iter().all(|(tol, e)| *e < 100.0 * tol),
                "{name}: {pts:?}"
            );
        }
    }
}

/// The θ turning points (θ̇ = 0 while falling, i.e. maxima of θ) over the first `t_end`.
fn theta_maxima(method: Method, t_end: f64) -> Vec<f64> {
    let tr = Simulation::new(&TOP, TOP_Q0, TOP_V0)
        .method(method)
        .until(t_end)
        .event(Event::zero_crossing("theta max", |_t, _q, qd: &[f64; 3]| qd[0]).falling())
        .run()
        .unwrap();
    assert!(tr.events.iter().all(|e| e.name == "theta max"));
    tr.events.iter().map(|e| e.t).collect()
}

fn nutation_period() -> f64 {
    let t = theta_maxima(
        Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        },
        10.0,
    );
    (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64
}

#[test]
fn events_locate_theta_turning_points_and_a_stable_nutation_period() {
    let tr = Simulation::new(&TOP, TOP_Q0, TOP_V0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(20.0)
        .event(Event::zero_crossing(
            "theta turning point",
            |_t, _q, qd: &[f64; 3]| qd[0],
        ))
        .run()
        .unwrap();
    let hits = &tr.events;
    assert!(hits.len() >= 20, "{} turning points", hits.len());
    // θ̇ vanishes at each hit, and minima (rising θ̇) alternate with maxima (falling θ̇).
    for (k, h) in hits.iter().enumerate() {
        assert!(h.qdot[0].abs() < 1e-9, "θ̇ = {} at t = {}", h.qdot[0], h.t);
        if k > 0 {
            assert_ne!(h.direction, hits[k - 1].direction);
        }
    }
    // Released with θ̇ = 0 at θ0 = 1 the top first falls: θ0 is a minimum of θ, the next
    // turning point is a maximum; all minima return to θ0 (energy conservation).
    assert_eq!(hits[0].direction, Direction::Falling);
    for h in hits.iter().filter(|h| h.direction == Direction::Rising) {
        assert!((h.q[0] - 1.0).abs() < 1e-9, "θ_min = {}", h.q[0]);
    }
    // The nutation period from successive maxima is the same period after period.
    let maxima: Vec<f64> = hits
        .iter()
        .filter(|h| h.direction == Direction::Falling)
        .map(|h| h.t)
        .collect();
    let periods: Vec<f64> = maxima.windows(2).map(|w| w[1] - w[0]).collect();
    let mean = periods.iter().sum::<f64>() / periods.len() as f64;
    for p in &periods {
        assert!((p - mean).abs() < 1e-9 * mean, "periods {periods:?}");
    }
    // Events found with the variational integrator (Hermite interpolation between steps)
    // converge to the DOP853 times at the method's order 2.
    let reference: Vec<f64> = maxima.iter().copied().filter(|&t| t <= 10.0).collect();
    let event_error = |dt: f64| {
        let vm = theta_maxima(Method::VariationalMidpoint { dt }, 10.0);
        assert_eq!(vm.len(), reference.len());
        vm.iter()
            .zip(&reference)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
    };
    let (e1, e2) = (event_error(2e-3), event_error(1e-3));
    assert!(
        e2 < e1 / 3.5 && e2 < 1e-4,
        "event-time errors {e1:e} (h = 2e-3), {e2:e} (h = 1e-3)"
    );
}

#[test]
fn heavy_top_dop853_keeps_energy_and_momenta_over_100_nutation_periods() {
    let t_end = 100.0 * nutation_period();
    let tr = Simulation::new(&TOP, TOP_Q0, TOP_V0)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        })
        .until(t_end)
        .sample_every(0.05)
        .run()
        .unwrap();
    let inv = tr.invariants();
    let e = inv.energy.unwrap();
    let (p_phi, p_psi) = (inv.momenta[1].unwrap(), inv.momenta[2].unwrap());
    assert!(inv.momenta[0].is_none());
    eprintln!(
        "DOP853 1e-12, t = {t_end:.3}: steps {}, energy {:.2e}, p_phi {:.2e}, p_psi {:.2e}",
        tr.stats.steps, e.max_rel, p_phi.max_rel, p_psi.max_rel
    );
    assert!(e.max_rel <= 1e-11, "energy drift {e:?}");
    assert!(p_phi.max_rel <= 1e-11, "p_phi drift {p_phi:?}");
    assert!(p_psi.max_rel <= 1e-11, "p_psi drift {p_psi:?}");
}

#[test]
fn heavy_top_variational_midpoint_conserves_momenta_and_bounds_energy() {
    let t_end = 100.0 * nutation_period();
    let tr = Simulation::new(&TOP, TOP_Q0, TOP_V0)
        .method(Method::VariationalMidpoint { dt: 1e-3 })
        .until(t_end)
        .sample_every(0.01)
        .run()
        .unwrap();
    let inv = tr.invariants();
    let (p_phi, p_psi) = (inv.momenta[1].unwrap(), inv.momenta[2].unwrap());
    let e0 = tr.energy[0];
    let n = tr.len();
    let max_err = |range: std::ops::Range<usize>| {
        range
            .map(|k| (tr.energy[k] - e0).abs())
            .fold(0.0_f64, f64::max)
    };
    let first = max_err(0..n / 10);
    let last = max_err(n - n / 10..n);
    eprintln!(
        "variational h = 1e-3, t = {t_end:.3}: steps {}, Newton its {}, p_phi {:.2e}, p_psi {:.2e}, \
         energy error first tenth {first:.3e}, last tenth {last:.3e}",
        tr.stats.steps, tr.stats.newton_iterations, p_phi.max_rel, p_psi.max_rel
    );
    assert!(p_phi.max_rel <= 1e-12, "p_phi drift {p_phi:?}");
    assert!(p_psi.max_rel <= 1e-12, "p_psi drift {p_psi:?}");
    // Bounded, oscillating energy error: a secular drift would make the last tenth ~10× the first.
    assert!(
        last <= 1.2 * first,
        "energy error grew: {first:e} → {last:e}"
    );
    assert!(first < 1e-5 * e0.abs(), "energy error {first:e} of {e0}");
}

#[test]
fn samples_land_on_the_grid_and_the_end_time() {
    let tr = Simulation::new(&Oscillator, [1.0], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(1.05)
        .sample_every(0.1)
        .run()
        .unwrap();
    assert_eq!(tr.len(), 12);
    assert_eq!(*tr.t.last().unwrap(), 1.05);
    for (t, q) in tr.t.iter().zip(&tr.q) {
        assert!((q[0] - t.cos()).abs() < 1e-9, "x({t}) = {}", q[0]);
    }
    // Fixed step: the sample interval must be a multiple of dt.
    let tr = Simulation::new(&Oscillator, [1.0], [0.0])
        .method(Method::Rk4 { dt: 0.01 })
        .until(1.0)
        .sample_every(0.25)
        .run()
        .unwrap();
    assert_eq!(tr.t.len(), 5);
    assert!((tr.t[4] - 1.0).abs() < 1e-15);
}

/// `sample_at`: the trajectory holds t0, exactly the requested times and `until`, with the
/// dense output's accuracy at irregular times, for both adaptive methods.
#[test]
fn samples_at_chosen_times_for_the_adaptive_methods() {
    let times: Vec<f64> = (0..12).map(|k| 1e-3 * 2f64.powi(k)).collect(); // 0.001 … 2.048
    for method in [
        Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        },
        Method::DormandPrince {
            rtol: 1e-10,
            atol: 1e-12,
        },
    ] {
        let tr = Simulation::new(&Oscillator, [1.0], [0.0])
            .method(method)
            .until(3.0)
            .sample_at(times.iter().copied())
            .run()
            .unwrap();
        let mut want = vec![0.0];
        want.extend(&times);
        want.push(3.0);
        assert_eq!(tr.t, want, "{method:?}");
        for ((t, q), v) in tr.t.iter().zip(&tr.q).zip(&tr.qdot) {
            assert!(
                (q[0] - t.cos()).abs() < 1e-9,
                "{method:?}: x({t}) = {}",
                q[0]
            );
            assert!(
                (v[0] + t.sin()).abs() < 1e-9,
                "{method:?}: v({t}) = {}",
                v[0]
            );
        }
        // The ends may be requested too; they are recorded once.
        let tr = Simulation::new(&Oscillator, [1.0], [0.0])
            .method(method)
            .until(3.0)
            .sample_at([0.0, 1.5, 3.0])
            .run()
            .unwrap();
        assert_eq!(tr.t, vec![0.0, 1.5, 3.0], "{method:?}");
    }
}

/// Fixed-step methods record the nodes the sample times land on: the same states as a run that
/// records every step, at the requested times only.
/// A finished run evaluated at new times (`Trajectory::at`, with `keep_dense_output`) gives
/// what `sample_at` would have recorded there, bit for bit: the heavy top with DOP853 and
/// Dormand–Prince (the steps do not depend on the samples).
#[test]
fn at_new_times_is_what_sample_at_records() {
    let times: Vec<f64> = (1..400).map(|k| 0.025 * k as f64 + 1e-3).collect();
    for method in [
        Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        },
        Method::DormandPrince {
            rtol: 1e-8,
            atol: 1e-10,
        },
    ] {
        let sim = || {
            Simulation::new(&TOP, TOP_Q0, TOP_V0)
                .method(method)
                .until(10.0)
        };
        let kept = sim().keep_dense_output(true).run().unwrap();
        let sampled = sim().sample_at(times.iter().copied()).run().unwrap();
        assert_eq!(sampled.len(), times.len() + 2);
        for k in 0..sampled.len() {
            let (q, qdot) = kept.at(sampled.t[k]).unwrap();
            assert_eq!((q, qdot), (sampled.q[k], sampled.qdot[k]), "{method:?}");
        }
        let err = kept.at(10.5).unwrap_err();
        assert!(err.to_string().contains("[0, 10]"), "{err}");
    }
}

#[test]
fn samples_at_grid_times_for_the_fixed_step_methods() {
    for method in [
        Method::Rk4 { dt: 0.01 },
        Method::VariationalMidpoint { dt: 0.01 },
    ] {
        let every = Simulation::new(&Oscillator, [1.0], [0.0])
            .method(method)
            .until(1.0)
            .run()
            .unwrap();
        let at = Simulation::new(&Oscillator, [1.0], [0.0])
            .method(method)
            .until(1.0)
            .sample_at([0.03, 0.07, 0.5, 0.93])
            .run()
            .unwrap();
        assert_eq!(at.t, vec![0.0, 0.03, 0.07, 0.5, 0.93, 1.0], "{method:?}");
        for (k, &i) in [0usize, 3, 7, 50, 93, 100].iter().enumerate() {
            assert_eq!(at.q[k], every.q[i], "{method:?}: q at t = {}", at.t[k]);
            assert_eq!(
                at.qdot[k], every.qdot[i],
                "{method:?}: q̇ at t = {}",
                at.t[k]
            );
        }
    }
}

/// A terminal event ends the samples too: no requested time after the event is recorded.
#[test]
fn samples_at_stop_at_a_terminal_event() {
    let tr = Simulation::new(&Oscillator, [1.0], [0.0])
        .until(10.0)
        .sample_at([1.0, 2.0, 4.0, 6.0])
        .event(
            Event::zero_crossing("x = 0 rising", |_t, q: &[f64; 1], _v| q[0])
                .rising()
                .terminal(),
        )
        .run()
        .unwrap();
    let t_star = 1.5 * std::f64::consts::PI; // 4.712…
    assert_eq!(tr.t.len(), 5);
    assert_eq!(&tr.t[..4], &[0.0, 1.0, 2.0, 4.0]);
    assert!((tr.t[4] - t_star).abs() < 1e-9);
}

#[test]
fn terminal_event_stops_the_run_at_the_crossing() {
    let tr = Simulation::new(&Oscillator, [1.0], [0.0])
        .method(Method::DormandPrince {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(10.0)
        .sample_every(0.1)
        .event(
            Event::zero_crossing("x = 0 rising", |_t, q: &[f64; 1], _v| q[0])
                .rising()
                .terminal(),
        )
        .run()
        .unwrap();
    // x = cos t rises through 0 at 3π/2.
    let t_star = 1.5 * std::f64::consts::PI;
    assert_eq!(tr.events.len(), 1);
    assert!((tr.events[0].t - t_star).abs() < 1e-9);
    assert_eq!(*tr.t.last().unwrap(), tr.events[0].t);
    assert_eq!(tr.terminated_by.as_deref(), Some("x = 0 rising"));
    assert!(tr.t.iter().all(|&t| t <= tr.events[0].t));
}

#[test]
fn invalid_options_are_rejected_before_any_step() {
    let calls = std::cell::Cell::new(0);
    let run = |sim: Simulation<'_, Oscillator, 1>| {
        let err = sim
            .event(Event::zero_crossing("count", |_t, _q, _v| {
                calls.set(calls.get() + 1);
                1.0
            }))
            .run()
            .unwrap_err();
        match &err {
            SimulationError::InvalidOptions { message } => message.clone(),
            other => panic!("expected InvalidOptions, got {other}"),
        }
    };
    let new = || Simulation::new(&Oscillator, [1.0], [0.0]);
    assert!(run(new().method(Method::Rk4 { dt: 0.0 }).until(1.0)).contains("dt"));
    assert!(run(new()
        .method(Method::VariationalMidpoint { dt: -1e-3 })
        .until(1.0))
    .contains("dt"));
    assert!(run(new()
        .method(Method::Dop853 {
            rtol: 0.0,
            atol: 1e-12
        })
        .until(1.0))
    .contains("rtol"));
    assert!(run(new()
        .method(Method::DormandPrince {
            rtol: -1e-6,
            atol: 1e-12
        })
        .until(1.0))
    .contains("rtol"));
    assert!(run(new().start_time(2.0).until(1.0)).contains("not after the start"));
    assert!(run(new()).contains("until"));
    assert!(run(Simulation::new(&Oscillator, [f64::NAN], [0.0]).until(1.0)).contains("not finite"));
    assert!(run(new()
        .method(Method::Rk4 { dt: 0.03 })
        .until(1.0)
        .sample_every(0.1))
    .contains("multiple"));
    let until1 = || new().until(1.0);
    assert!(run(until1().sample_at([0.5, 0.2])).contains("must increase"));
    assert!(run(until1().sample_at([0.5, 0.5])).contains("must increase"));
    assert!(run(until1().sample_at([0.5, 1.5])).contains("outside the run"));
    assert!(run(until1().sample_at([-0.1])).contains("outside the run"));
    assert!(run(until1().sample_at([f64::NAN])).contains("outside the run"));
    assert!(run(until1().sample_every(0.1).sample_at([0.5])).contains("choose one"));
    // 10¹⁵ samples would exhaust memory: refused up front (default limit: a 256 MiB budget).
    assert!(run(new().until(1e3).sample_every(1e-12)).contains("a 256 MiB budget"));
    assert!(run(until1().sample_at([0.25, 0.5]).max_samples(3)).contains("max_samples = 3"));
    assert!(run(new()
        .method(Method::Rk4 { dt: 0.1 })
        .until(1.0)
        .sample_at([0.25]))
    .contains("not on the fixed step grid"));
    assert_eq!(
        calls.get(),
        0,
        "the event function was called: a step was taken"
    );
}

/// The Kepler problem declared with no cyclic coordinate: the same dynamics, nothing held.
struct KeplerUndeclared;
impl Lagrangian<2> for KeplerUndeclared {
    const COORDINATES: [&'static str; 2] = ["r", "phi"];
    const CYCLIC: [bool; 2] = [false, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], t: S) -> S {
        Kepler.lagrangian(q, v, t)
    }
}

/// The explicit methods do not form the stage positions of cyclic coordinates; since q̈ does not
/// read them, the trajectory is bit for bit the one where every position is formed.
#[test]
fn held_cyclic_stage_positions_change_nothing() {
    for method in [
        Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        },
        Method::DormandPrince {
            rtol: 1e-8,
            atol: 1e-10,
        },
    ] {
        fn run<L: Lagrangian<2>>(sys: &L, method: Method) -> Trajectory<2> {
            Simulation::new(sys, [1.0, 0.3], [0.0, 1.2])
                .method(method)
                .until(20.0)
                .sample_every(0.5)
                .run()
                .unwrap()
        }
        let held = run(&Kepler, method);
        let formed = run(&KeplerUndeclared, method);
        assert_eq!(held.t, formed.t, "{method:?}");
        assert_eq!(held.q, formed.q, "{method:?}");
        assert_eq!(held.qdot, formed.qdot, "{method:?}");
        assert_eq!(held.stats, formed.stats, "{method:?}");
    }
}

/// Kepler with a "perturbation" that depends on φ, wrongly declared cyclic.
struct WronglyCyclic;
impl Lagrangian<2> for WronglyCyclic {
    const COORDINATES: [&'static str; 2] = ["r", "phi"];
    const CYCLIC: [bool; 2] = [false, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], t: S) -> S {
        Kepler.lagrangian(q, v, t) + q[1].cos() * 0.01
    }
}

/// A `CYCLIC` declaration the dynamics contradict is rejected before any step, naming the
/// coordinate and the fix; every method checks it.
#[test]
fn a_wrong_cyclic_declaration_is_rejected_before_any_step() {
    for method in [
        Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        },
        Method::Rk4 { dt: 0.01 },
        Method::VariationalMidpoint { dt: 0.01 },
    ] {
        let err = Simulation::new(&WronglyCyclic, [1.0, 0.3], [0.0, 1.2])
            .method(method)
            .until(1.0)
            .run()
            .unwrap_err();
        let SimulationError::InvalidOptions { message } = &err else {
            panic!("expected InvalidOptions, got {err}");
        };
        assert!(
            message.contains("`phi`") && message.contains("CYCLIC[1] = false"),
            "{message}"
        );
    }
}

#[test]
fn singular_mass_matrix_is_a_typed_error_with_the_state() {
    // θ = 0 exactly: the Euler-angle chart is singular.
    for method in [
        Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        },
        Method::VariationalMidpoint { dt: 1e-3 },
    ] {
        let err = Simulation::new(&TOP, [0.0, 0.0, 0.0], [0.0, 0.0, 8.0])
            .method(method)
            .until(1.0)
            .run()
            .unwrap_err();
        match &err {
            SimulationError::Dynamics { source, t, .. } => {
                assert_eq!(*t, 0.0);
                assert!(matches!(**source, DynamicsError::SingularMassMatrix { .. }));
            }
            other => panic!("expected Dynamics, got {other}"),
        }
        let msg = err.to_string();
        assert!(msg.contains("t = 0") && msg.contains("Try"), "{msg}");
    }
}

/// L = q̇²/2 + q⁴/4: q̈ = q³ blows up at t = √2 for q(0) = 1, q̇(0) = 1/√2.
struct BlowUp;
impl Lagrangian<1> for BlowUp {
    const COORDINATES: [&'static str; 1] = ["q"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5 + q[0].powi(4) * 0.25
    }
}

#[test]
fn blow_up_fails_with_the_partial_trajectory() {
    // Exact solution q = 1/(1 − t/√2)·… : q = √2/(√2 − t) with q̇ = q²/√2.
    let err = Simulation::new(&BlowUp, [1.0], [std::f64::consts::FRAC_1_SQRT_2])
        .method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-10,
        })
        .until(3.0)
        .sample_every(0.1)
        .run()
        .unwrap_err();
    assert!(
        matches!(
            err,
            SimulationError::StepSizeUnderflow { .. }
                | SimulationError::NonFinite { .. }
                | SimulationError::MaxSteps { .. }
        ),
        "{err}"
    );
    let t_fail = err.t().unwrap();
    // The blow-up is at √2; the numerical solution may pass it by about the tolerance.
    assert!(
        t_fail > 1.41 && t_fail < std::f64::consts::SQRT_2 + 1e-9,
        "failed at {t_fail}"
    );
    let partial = err.partial_trajectory::<1>().unwrap();
    assert_eq!(partial.t.len(), 16, "{:?}", partial.t); // 0.0 … 1.4 and the last state
    assert_eq!(*partial.t.last().unwrap(), t_fail);
    for (t, q) in partial.t.iter().zip(&partial.q).take(15) {
        let exact = std::f64::consts::SQRT_2 / (std::f64::consts::SQRT_2 - t);
        assert!(
            (q[0] - exact).abs() < 1e-7 * exact,
            "q({t}) = {} vs {exact}",
            q[0]
        );
    }
    assert!(err.to_string().contains("Try"));
}

#[test]
fn max_steps_keeps_what_was_computed() {
    let err = Simulation::new(&Kepler, KEPLER_Q0, KEPLER_V0)
        .method(Method::VariationalMidpoint { dt: 0.01 })
        .until(100.0)
        .max_steps(250)
        .run()
        .unwrap_err();
    let SimulationError::MaxSteps { t, max_steps, .. } = &err else {
        panic!("expected MaxSteps, got {err}");
    };
    assert_eq!(*max_steps, 250);
    assert!((t - 2.5).abs() < 1e-12);
    let tr = err.into_partial_trajectory::<2>().unwrap();
    assert_eq!(tr.len(), 251);
    assert_eq!(tr.stats.steps, 250);
    // Angular momentum is conserved by the variational integrator to round-off.
    assert!(tr.invariants().momenta[1].unwrap().max_rel < 1e-14);
}

#[test]
fn csv_has_names_velocities_energy_and_momenta() {
    let tr = Simulation::new(&TOP, TOP_Q0, TOP_V0)
        .method(Method::Rk4 { dt: 0.01 })
        .until(0.1)
        .run()
        .unwrap();
    let path = std::env::temp_dir().join(format!("lagrange_top_{}.csv", std::process::id()));
    tr.write_csv(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).ok();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("t,theta,phi,psi,theta_dot,phi_dot,psi_dot,energy,p_theta,p_phi,p_psi")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 11);
    assert_eq!(rows[0][1], 1.0);
    assert_eq!(rows[0][6], 8.0);
    assert_eq!(rows[10][7], tr.energy[10]);
    assert_eq!(rows[10][10], tr.momenta[10][2]);
}

/// The heavy top with a hand-written singular chart (θ = 0, π) and cyclic φ, ψ: the hostile
/// options below meet singular mass matrices, blow-ups and Newton failures.
mod hostile {
    use super::*;
    use proptest::prelude::*;

    /// Mostly a value from `sane` (flagged `true`); one time in twenty any f64, or one that
    /// breaks naive code (flagged `false`).
    fn value(sane: std::ops::Range<f64>) -> impl Strategy<Value = (f64, bool)> {
        prop_oneof![
            38 => sane.prop_map(|x| (x, true)),
            1 => any::<f64>().prop_map(|x| (x, false)),
            1 => prop::sample::select(vec![
                0.0,
                -0.0,
                -1.0,
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::MIN_POSITIVE,
                1e-300,
                1e300,
                f64::MAX,
            ])
            .prop_map(|x| (x, false)),
        ]
    }

    /// A method and whether all its options were drawn from the sane ranges (a zero atol, pure
    /// relative control, is sane).
    fn method() -> impl Strategy<Value = (Method, bool)> {
        let dt = || value(1e-3..0.5);
        let atol = prop_oneof![4 => value(0.0..1e-6), 1 => Just((0.0, true))];
        // rtol log-uniform over 1e-12 … 1e-3.
        let rtol =
            || value(-12.0..-3.0).prop_map(|(x, ok)| (if ok { 10f64.powf(x) } else { x }, ok));
        let tols = move || (rtol(), atol.clone());
        prop_oneof![
            dt().prop_map(|(dt, ok)| (Method::Rk4 { dt }, ok)),
            dt().prop_map(|(dt, ok)| (Method::VariationalMidpoint { dt }, ok)),
            tols()
                .prop_map(|((rtol, a), (atol, b))| (Method::DormandPrince { rtol, atol }, a && b)),
            tols().prop_map(|((rtol, a), (atol, b))| (Method::Dop853 { rtol, atol }, a && b)),
        ]
    }

    #[derive(Debug, Clone)]
    enum Samples {
        Steps,
        Every(f64),
        At(Vec<f64>),
    }

    fn samples() -> impl Strategy<Value = Samples> {
        prop_oneof![
            Just(Samples::Steps),
            value(0.01..2.0).prop_map(|(ds, _)| Samples::Every(ds)),
            prop::collection::vec(value(-1.0..12.0).prop_map(|(x, _)| x), 0..6).prop_map(
                |mut times| {
                    // Mostly increasing lists; the hostile values can still break the order.
                    times.sort_by(f64::total_cmp);
                    Samples::At(times)
                }
            ),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 1024, ..ProptestConfig::default() })]

        /// Whatever the options and the initial state, `run()` returns: a trajectory of finite
        /// states that starts at t0 and never goes back, or a typed error whose message says what
        /// happened and, past the options, when, with the trajectory so far. Valid options (every
        /// value from its sane range, steps recorded) are never `InvalidOptions`, and a failure
        /// at the very start has a physical reason: the Euler-angle chart is singular near there.
        #[test]
        fn run_never_panics_on_hostile_options(
            (method, method_sane) in method(),
            q0 in prop::array::uniform3(prop_oneof![9 => value(-4.0..4.0), 1 => Just((0.0, true))]),
            v0 in prop::array::uniform3(prop_oneof![9 => value(-10.0..10.0), 1 => Just((0.0, true))]),
            (t0, t0_sane) in value(-1.0..1.0),
            (span, span_sane) in value(0.01..10.0),
            samples in samples(),
            max_step in prop::option::of(value(1e-3..1.0)),
            event in any::<bool>(),
            max_steps in 1usize..300,
        ) {
            let sane = method_sane
                && t0_sane
                && span_sane
                && q0.iter().chain(&v0).all(|x| x.1)
                && max_step.is_none_or(|h| h.1)
                && matches!(samples, Samples::Steps);
            let (q0, v0) = (q0.map(|x| x.0), v0.map(|x| x.0));
            let max_step = max_step.map(|h| h.0);
            let until = t0 + span;
            let mut sim = Simulation::new(&TOP, q0, v0)
                .method(method)
                .start_time(t0)
                .until(until)
                .max_steps(max_steps)
                .max_samples(10_000);
            sim = match samples.clone() {
                Samples::Steps => sim,
                Samples::Every(ds) => sim.sample_every(ds),
                Samples::At(times) => sim.sample_at(times),
            };
            if let Some(h) = max_step {
                sim = sim.max_step(h);
            }
            if event {
                sim = sim.event(Event::zero_crossing("turning point", |_t, _q, v: &[f64; 3]| v[0]));
            }
            match sim.run() {
                Ok(tr) => {
                    prop_assert!(!tr.t.is_empty());
                    prop_assert_eq!(tr.t[0], t0);
                    prop_assert!(tr.t.windows(2).all(|w| w[0] <= w[1]), "{:?}", tr.t);
                    prop_assert!(*tr.t.last().unwrap() <= until);
                    prop_assert!(tr.q.iter().chain(&tr.qdot).flatten().all(|x| x.is_finite()));
                }
                Err(e) => {
                    let message = e.to_string();
                    prop_assert!(message.len() > 40, "{}", message);
                    if sane {
                        prop_assert!(
                            !matches!(e, SimulationError::InvalidOptions { .. }),
                            "valid options rejected: {}", message
                        );
                        let at_start = e.t() == Some(t0);
                        let stalled = matches!(
                            e,
                            SimulationError::StepSizeUnderflow { .. } | SimulationError::Dynamics { .. }
                        );
                        prop_assert!(
                            !(at_start && stalled) || q0[0].sin().abs() < 0.05,
                            "failed at the start, far from the chart singularity (θ0 = {}): {}",
                            q0[0], message
                        );
                    }
                    if !matches!(e, SimulationError::InvalidOptions { .. }) {
                        prop_assert!(e.t().is_some_and(f64::is_finite), "{}", message);
                        prop_assert!(message.contains("t = "), "{}", message);
                        let partial = e.partial_trajectory::<3>();
                        prop_assert!(partial.is_some_and(|p| p.t.first() == Some(&t0)), "{}", message);
                    }
                }
            }
        }
    }
}
