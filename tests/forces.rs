//! Non-conservative mechanics: generalized forces and Rayleigh dissipation against closed forms
//! (damped and driven oscillators), the orders of every method with damping, the energy balance
//! h(t) − h(t0) − W(t), and momenta that stay conserved while other coordinates are damped.

use lagrange::prelude::*;

use crate::support::hand::Oscillator;

/// x(t) of the free damped oscillator (F = 0) from x0, v0: under-, critically or over-damped.
fn damped_closed_form(o: &Oscillator, x0: f64, v0: f64, t: f64) -> f64 {
    let g = o.b / (2.0 * o.m);
    let w0sq = o.k / o.m;
    let disc = g * g - w0sq;
    if disc < 0.0 {
        let wd = (-disc).sqrt();
        (-g * t).exp() * (x0 * (wd * t).cos() + (v0 + g * x0) / wd * (wd * t).sin())
    } else if disc == 0.0 {
        (-g * t).exp() * (x0 + (v0 + g * x0) * t)
    } else {
        let s = disc.sqrt();
        let (r1, r2) = (-g + s, -g - s);
        let a = (v0 - r2 * x0) / (r1 - r2);
        a * (r1 * t).exp() + (x0 - a) * (r2 * t).exp()
    }
}

const UNDER: Oscillator = Oscillator {
    m: 2.0,
    k: 8.0,
    b: 1.0,
    f: 0.0,
    w: 0.0,
};
const CRITICAL: Oscillator = Oscillator {
    m: 2.0,
    k: 8.0,
    b: 8.0,
    f: 0.0,
    w: 0.0,
};
const OVER: Oscillator = Oscillator {
    m: 2.0,
    k: 8.0,
    b: 20.0,
    f: 0.0,
    w: 0.0,
};

fn max_error(o: &Oscillator, method: Method, until: f64) -> (f64, usize) {
    let tr = Simulation::new(o, [1.0], [0.5])
        .method(method)
        .until(until)
        .run()
        .expect("the damped oscillator integrates");
    let err =
        tr.t.iter()
            .zip(&tr.q)
            .map(|(&t, q)| (q[0] - damped_closed_form(o, 1.0, 0.5, t)).abs())
            .fold(0.0, f64::max);
    (err, tr.stats.steps)
}

#[test]
fn damped_oscillator_accelerations_include_the_dissipation() {
    let a = UNDER.accelerations(&[0.3], &[-1.2], 0.0).unwrap();
    assert_eq!(a, [(-8.0 * 0.3 - 1.0 * -1.2) / 2.0]);
    let p = UNDER.pieces(&[0.3], &[-1.2], 0.0);
    assert_eq!(p.applied, [1.2]);
    assert_eq!(p.lagrangian_force, [-2.4]);
}

#[test]
fn damped_oscillator_matches_the_closed_form_with_dop853() {
    for (name, o) in [("under", UNDER), ("critical", CRITICAL), ("over", OVER)] {
        let (err, _) = max_error(
            &o,
            Method::Dop853 {
                rtol: 1e-12,
                atol: 1e-14,
            },
            10.0,
        );
        assert!(
            err <= 1e-10,
            "{name}-damped: max |x − closed form| = {err:.2e}"
        );
    }
}

#[test]
fn damped_oscillator_orders_of_the_fixed_step_methods() {
    // Error at the end, halving dt: the ratio is 2^order.
    let rk4: fn(f64) -> Method = |dt| Method::Rk4 { dt };
    let variational: fn(f64) -> Method = |dt| Method::VariationalMidpoint { dt };
    for (method, order) in [(rk4, 4.0), (variational, 2.0)] {
        let rk4 = matches!(method(0.1), Method::Rk4 { .. });
        let end_error = |dt: f64| {
            let tr = Simulation::new(&UNDER, [1.0], [0.5])
                .method(method(dt))
                .until(4.0)
                .run()
                .expect("integrates");
            let last = tr.t.len() - 1;
            (tr.q[last][0] - damped_closed_form(&UNDER, 1.0, 0.5, tr.t[last])).abs()
        };
        let (e1, e2) = (end_error(0.02), end_error(0.01));
        let measured = (e1 / e2).log2();
        assert!(
            (measured - order).abs() < 0.15,
            "{}: measured order {measured:.3} (errors {e1:.3e}, {e2:.3e}), expected {order}",
            if rk4 { "RK4" } else { "variational midpoint" }
        );
    }
}

#[test]
fn damped_oscillator_order_of_dormand_prince() {
    // Adaptive: the error against the number of steps falls like steps^(−5).
    let (e1, n1) = max_error(
        &UNDER,
        Method::DormandPrince {
            rtol: 1e-6,
            atol: 1e-9,
        },
        10.0,
    );
    let (e2, n2) = max_error(
        &UNDER,
        Method::DormandPrince {
            rtol: 1e-9,
            atol: 1e-12,
        },
        10.0,
    );
    let order = (e1 / e2).ln() / (n2 as f64 / n1 as f64).ln();
    assert!(
        (4.0..6.5).contains(&order),
        "DP5 order from steps {n1} → {n2}, errors {e1:.2e} → {e2:.2e}: {order:.2}"
    );
}

#[test]
fn driven_damped_oscillator_reaches_the_steady_state_amplitude_and_phase() {
    let o = Oscillator {
        m: 1.5,
        k: 6.0,
        b: 0.9,
        f: 2.0,
        w: 1.3,
    };
    let amplitude = o.f / ((o.k - o.m * o.w * o.w).powi(2) + (o.b * o.w).powi(2)).sqrt();
    let phase = (o.b * o.w).atan2(o.k - o.m * o.w * o.w);
    // The transient decays like e^{−b t / 2m} = e^{−0.3 t}: e^{−60} after t = 200.
    let period = 2.0 * std::f64::consts::PI / o.w;
    let tr = Simulation::new(&o, [0.4], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .start_time(0.0)
        .until(200.0 + period)
        .sample_at((0..40).map(|k| 200.0 + k as f64 * period / 40.0))
        .run()
        .expect("integrates");
    let mut worst = 0.0_f64;
    for (&t, q) in tr.t.iter().zip(&tr.q).filter(|(&t, _)| t >= 200.0) {
        worst = worst.max((q[0] - amplitude * (o.w * t - phase).cos()).abs());
    }
    assert!(
        worst <= 1e-9,
        "steady state off by {worst:.2e} (amplitude {amplitude})"
    );
}

#[test]
fn energy_balance_closes_for_every_method() {
    let o = Oscillator {
        m: 1.0,
        k: 4.0,
        b: 0.3,
        f: 0.7,
        w: 1.7,
    };
    for (method, tol) in [
        (
            Method::Dop853 {
                rtol: 1e-11,
                atol: 1e-13,
            },
            1e-9,
        ),
        (
            Method::DormandPrince {
                rtol: 1e-10,
                atol: 1e-12,
            },
            1e-8,
        ),
        (Method::Rk4 { dt: 1e-3 }, 1e-9),
        (Method::VariationalMidpoint { dt: 1e-3 }, 1e-5),
    ] {
        let tr = Simulation::new(&o, [1.0], [0.0])
            .method(method)
            .until(30.0)
            .sample_every(0.5)
            .run()
            .expect("integrates");
        assert_eq!(tr.work.len(), tr.t.len());
        assert_eq!(tr.work[0], 0.0);
        let inv = tr.invariants();
        assert!(
            inv.energy.is_none(),
            "{method:?}: the energy is not conserved"
        );
        let balance = inv
            .energy_balance
            .expect("an energy balance when h is not conserved");
        // The work is not small: friction and drive exchange O(1) energy over the run.
        let w_max = tr.work.iter().fold(0.0_f64, |m, w| m.max(w.abs()));
        assert!(w_max > 0.1, "{method:?}: |W| only reached {w_max}");
        assert!(
            balance.max_abs <= tol,
            "{method:?}: max |h − h0 − W| = {:.2e} (> {tol:.0e})",
            balance.max_abs
        );
    }
}

/// A particle in the plane in polar coordinates with drag on the radial motion only and a
/// central spring: p_φ stays conserved while r is damped.
struct RadialDrag;
impl Lagrangian<2> for RadialDrag {
    const COORDINATES: [&'static str; 2] = ["r", "phi"];
    const CYCLIC: [bool; 2] = [false, true];
    const AUTONOMOUS: bool = true;
    const MOMENTUM_CONSERVED: [bool; 2] = [false, true];
    const ENERGY_CONSERVED: bool = false;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0] + q[0] * q[0] * v[1] * v[1]) * 0.5 - (q[0] - 1.0) * (q[0] - 1.0) * 2.0
    }
    fn dissipation<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S {
        v[0] * v[0] * 0.2
    }
}

#[test]
fn a_momentum_no_force_acts_on_stays_conserved_while_another_coordinate_is_damped() {
    for (method, tol) in [
        (
            Method::Dop853 {
                rtol: 1e-12,
                atol: 1e-14,
            },
            1e-12,
        ),
        (Method::VariationalMidpoint { dt: 1e-2 }, 1e-14),
    ] {
        let tr = Simulation::new(&RadialDrag, [1.5, 0.0], [0.0, 0.8])
            .method(method)
            .until(40.0)
            .run()
            .expect("integrates");
        let inv = tr.invariants();
        assert!(inv.momenta[0].is_none());
        let p_phi = inv.momenta[1].expect("p_φ is reported: it is conserved");
        assert!(
            p_phi.max_rel <= tol,
            "{method:?}: p_φ drift {:.2e}",
            p_phi.max_rel
        );
        // r is damped: the radial oscillation decays.
        let last = tr.qdot.last().unwrap()[0].abs();
        assert!(last < 0.05, "{method:?}: ṙ at the end {last}");
        let balance = inv.energy_balance.expect("reported").max_abs;
        assert!(balance < 1e-4, "{method:?}: energy balance {balance:.2e}");
    }
}

#[test]
fn the_work_is_written_to_csv() {
    let o = Oscillator {
        m: 1.0,
        k: 1.0,
        b: 0.5,
        f: 0.0,
        w: 0.0,
    };
    let tr = Simulation::new(&o, [1.0], [0.0])
        .method(Method::Rk4 { dt: 0.5 })
        .until(1.0)
        .run()
        .unwrap();
    let path = std::env::temp_dir().join("lagrange_forces_work.csv");
    tr.write_csv(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().next(), Some("t,x,x_dot,energy,p_x,work"));
    let last: Vec<f64> = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(last[5], *tr.work.last().unwrap());
    assert!(last[5] < 0.0, "friction takes energy out: W = {}", last[5]);
}
