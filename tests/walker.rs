//! The passive compass-gait walker (`examples/support/walker_system.rs`): its period-one gaits
//! found by shooting through the heel strike on the mid-stance section, against the published
//! gaits, and the step-to-step map's multipliers (the monodromy carried across the strike by
//! its saltation matrix) against differences of the return map and against an integration of
//! the published equations that shares nothing with the library.

use lagrange::prelude::*;
use lagrange::sensitivity::PeriodicOrbit;
use lagrange_examples::walker_system::CompassGait;

fn tight() -> Method {
    Method::Dop853 {
        rtol: 1e-13,
        atol: 1e-15,
    }
}

/// The gait of the simplest walker through Garcia et al.'s state (θ, θ̇) just after a strike
/// (φ = 2θ, φ̇ = (1 − cos 2θ) θ̇ there), and the state just after its strike, Garcia's way.
fn garcia_gait(w: &CompassGait, th: f64, thd: f64) -> (PeriodicOrbit<2>, [f64; 4]) {
    let (q, v) = w.from_garcia_state(&[th, thd, 2.0 * th, (1.0 - (2.0 * th).cos()) * thd]);
    let (qm, vm) = w.to_mid_stance(q, v, tight()).unwrap();
    let orbit = w.gait(qm, vm, 4.0, tight()).unwrap();
    let (qs, vs) = w.after_strike(orbit.q0, orbit.qdot0, tight()).unwrap();
    let x = w.garcia_state(&qs, &vs);
    (orbit, x)
}

/// The return map on mid-stance through one heel strike: the state where θ₁ comes back to
/// its start's value (rising), as the shooting measures it.
fn return_map(w: &CompassGait, x: [f64; 4]) -> [f64; 4] {
    let level = x[0];
    let run = Simulation::new(w, [x[0], x[1]], [x[2], x[3]])
        .method(tight())
        .event(w.heel_strike_event())
        .event(
            Event::zero_crossing("back", move |_t, q: &[f64; 2], _v| q[0] - level)
                .rising()
                .terminal(),
        )
        .until(10.0 * (w.leg() / w.g).sqrt())
        .keep_samples(false)
        .run()
        .unwrap();
    assert_eq!(run.jumps.len(), 1, "one strike per step");
    let hit = run.events.last().unwrap();
    [hit.q[0], hit.q[1], hit.qdot[0], hit.qdot[1]]
}

/// ∂P/∂x by fourth-order central differences (step h: truncation h⁴ P⁽⁵⁾ ≈ 1e-16 at 1e-4, the
/// runs' error 1e-13 / h ≈ 1e-9 at most, far less where the runs' errors are smooth in x).
fn return_map_jacobian(w: &CompassGait, x0: [f64; 4], h: f64) -> [[f64; 4]; 4] {
    let mut jac = [[0.0; 4]; 4];
    for j in 0..4 {
        let at = |s: f64| {
            let mut x = x0;
            x[j] += s * h;
            return_map(w, x)
        };
        let (p1, m1, p2, m2) = (at(1.0), at(-1.0), at(2.0), at(-2.0));
        for i in 0..4 {
            jac[i][j] = (8.0 * (p1[i] - m1[i]) - (p2[i] - m2[i])) / (12.0 * h);
        }
    }
    jac
}

/// The section's directions (θ₁ held at the section, the other three moved): the columns of
/// the monodromy that the differences of the return map measure as they are (the θ₁ column
/// differs by design: the shooting returns to a fixed level, the differences to the level
/// through each start).
fn assert_section_columns(orbit: &PeriodicOrbit<2>, jac: &[[f64; 4]; 4], tol: f64) {
    let mut worst = 0.0_f64;
    for (i, row) in jac.iter().enumerate() {
        for (j, d) in row.iter().enumerate().skip(1) {
            worst = worst.max((orbit.monodromy[(i, j)] - d).abs());
        }
    }
    eprintln!("monodromy against differences of the return map: {worst:.1e}");
    assert!(worst < tol, "{worst:e}\n{}\n{jac:?}", orbit.monodromy);
}

/// Garcia, Chatterjee, Ruina & Coleman, "The simplest walking model: stability, complexity,
/// and scaling", J. Biomech. Eng. 120 (1998): the long-step gait at γ = 0.009, θ* =
/// 0.20031090049483, θ̇* = −0.19983247291764 just after the heel strike, and the short-step
/// gait 0.19393736960624, −0.20386692731962 (14 digits as the authors' simulation files give
/// them, computed there "to 1e-10"; Table 1 prints 6): shot from each, the library lands on
/// each to 5e-10. The long step is stable, the short one unstable (Newton finds it all the
/// same).
#[test]
fn simplest_walker_gaits_as_published() {
    let w = CompassGait::simplest(0.009);
    for (th, thd, stable) in [
        (0.20031090049483, -0.19983247291764, true),
        (0.19393736960624, -0.20386692731962, false),
    ] {
        let (orbit, x) = garcia_gait(&w, th, thd);
        eprintln!(
            "simplest walker: θ* = {:.14} θ̇* = {:.14} (published {th} {thd}), T = {}, {}",
            x[0], x[1], orbit.period, orbit.stability
        );
        assert!((x[0] - th).abs() < 5e-10, "{} vs {th}", x[0]);
        assert!((x[1] - thd).abs() < 5e-10, "{} vs {thd}", x[1]);
        // Just after the strike the legs are symmetric: φ = 2θ.
        assert!((x[2] - 2.0 * x[0]).abs() < 1e-12);
        assert_eq!(orbit.stability.is_stable(), stable);
    }
}

/// The simplest walker's step-to-step multipliers, three ways: the shooting's monodromy
/// (through the strike's saltation matrix); fourth-order differences of the library's return
/// map (to 1e-8, the bar); and Garcia et al.'s own equations of the model in the limit
/// β → 0 — θ̈ = sin(θ − γ), φ̈ = sin φ (θ̇² − cos(θ − γ)) + sin(θ − γ), the strike at φ = 2θ
/// with θ⁺ = −θ⁻, θ̇⁺ = cos 2θ⁻ θ̇⁻ (their eqs. 3–5) — integrated here by a classical
/// Runge–Kutta loop that shares nothing with the library (fixed step 1e-3, the strike found by
/// bisection on the step), whose 2 × 2 stride map (θ, θ̇) ↦ (θ, θ̇) has by central differences
/// the same nonzero eigenvalues (the 4 × 4 maps of both differ from it by the directions the
/// strike collapses, eigenvalue 0), to 1e-6 (the differences' error, h = 1e-5).
///
/// The published eigenvalues, −0.19120868949940 ± 0.55633363687106i (long step) and 4.000,
/// 0.459 (short), are not these: all three computations here agree on −0.190099841 ±
/// 0.557598777i and 4.0039, 0.4596 (docs/ERRATA.md).
#[test]
fn simplest_walker_multipliers_three_ways() {
    let w = CompassGait::simplest(0.009);
    let (orbit, _) = garcia_gait(&w, 0.20031090049483, -0.19983247291764);
    let x0 = [orbit.q0[0], orbit.q0[1], orbit.qdot0[0], orbit.qdot0[1]];
    let jac = return_map_jacobian(&w, x0, 1e-4);
    assert_section_columns(&orbit, &jac, 1e-8);

    let mu = orbit
        .multipliers
        .iter()
        .copied()
        .filter(|m| m.norm() > 1e-6)
        .collect::<Vec<_>>();
    assert_eq!(mu.len(), 2, "{:?}", orbit.multipliers);

    // Garcia's equations, integrated apart from the library.
    let gamma = 0.009;
    let f = |y: [f64; 4]| {
        let s = (y[0] - gamma).sin();
        [
            y[1],
            s,
            y[3],
            y[2].sin() * (y[1] * y[1] - (y[0] - gamma).cos()) + s,
        ]
    };
    let rk4 = |y: [f64; 4], h: f64| {
        let add = |a: [f64; 4], b: [f64; 4], s: f64| core::array::from_fn(|i| a[i] + s * b[i]);
        let k1 = f(y);
        let k2 = f(add(y, k1, h / 2.0));
        let k3 = f(add(y, k2, h / 2.0));
        let k4 = f(add(y, k3, h));
        core::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
    };
    let stride = |z: [f64; 2]| -> [f64; 2] {
        let h = 1e-3;
        let mut y = [z[0], z[1], 2.0 * z[0], (1.0 - (2.0 * z[0]).cos()) * z[1]];
        let mut t = 0.0;
        loop {
            let next = rk4(y, h);
            let (g0, g1) = (y[2] - 2.0 * y[0], next[2] - 2.0 * next[0]);
            // The strike: φ − 2θ changes sign with the stance leg well past the normal.
            if t > 0.1 && next[0] < -0.05 && g0 * g1 <= 0.0 {
                let (mut lo, mut hi) = (0.0, h);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    let ym = rk4(y, mid);
                    if (ym[2] - 2.0 * ym[0]) * g0 > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let ye = rk4(y, 0.5 * (lo + hi));
                return [-ye[0], (2.0 * ye[0]).cos() * ye[1]];
            }
            y = next;
            t += h;
            assert!(t < 10.0, "no strike");
        }
    };
    let z = [0.20031090049483, -0.19983247291764];
    let d = 1e-5;
    let mut j2 = [[0.0; 2]; 2];
    for c in 0..2 {
        let (mut zp, mut zm) = (z, z);
        zp[c] += d;
        zm[c] -= d;
        let (sp, sm) = (stride(zp), stride(zm));
        for r in 0..2 {
            j2[r][c] = (sp[r] - sm[r]) / (2.0 * d);
        }
    }
    let (tr, det) = (
        j2[0][0] + j2[1][1],
        j2[0][0] * j2[1][1] - j2[0][1] * j2[1][0],
    );
    let disc = tr * tr / 4.0 - det;
    assert!(disc < 0.0, "a complex pair: {disc}");
    let (re, im) = (tr / 2.0, (-disc).sqrt());
    eprintln!("Garcia's equations: {re} ± {im}i; the library: {mu:?}");
    for m in &mu {
        assert!((m.re - re).abs() < 1e-6, "{m} vs {re}");
        assert!((m.im.abs() - im).abs() < 1e-6, "{m} vs {im}");
    }
    // And the value itself, to the digits the three agree on.
    assert!((mu[0].re + 0.190099841).abs() < 1e-9, "{}", mu[0]);
    assert!((mu[0].im.abs() - 0.557598777).abs() < 1e-9, "{}", mu[0]);
}

/// Goswami's walker at 3°: the passive gait's state just after the heel strike as the
/// literature gives it to 4 digits — (0.2187, −0.3234, −1.0918, −0.3772): the angles from the
/// vertical of the leg that just landed and of the other, then their rates (Goswami et al.'s
/// parameters; the state Spong, Holm & Lee, IEEE Robot. Autom. Mag. 14(2), 2007, take as the
/// passive limit cycle). Found from a rough start walked for 20 s and shot; its
/// monodromy against differences of the return map to 1e-8; stable, with a complex pair and a
/// real multiplier.
#[test]
fn goswami_walker_gait_as_published() {
    let w = CompassGait::goswami(3.0);
    let (q0, v0) = w.to_mid_stance([-0.27, 0.27], [1.1, 0.4], tight()).unwrap();
    let settled = Simulation::new(&w, q0, v0)
        .method(tight())
        .event(w.heel_strike_event())
        .until(20.0)
        .keep_samples(false)
        .run()
        .unwrap();
    let (q1, v1) = settled.jumps.last().unwrap().after;
    let (qm, vm) = w.to_mid_stance(q1, v1, tight()).unwrap();
    let orbit = w.gait(qm, vm, 1.0, tight()).unwrap();
    let (qs, vs) = w.after_strike(orbit.q0, orbit.qdot0, tight()).unwrap();
    let got = [-qs[0] - w.slope, -qs[1] - w.slope, -vs[0], -vs[1]];
    let published = [0.2187, -0.3234, -1.0918, -0.3772];
    eprintln!(
        "Goswami's walker at 3°: {got:?} (published {published:?}), {}",
        orbit.stability
    );
    for (g, p) in got.iter().zip(published) {
        assert!((g - p).abs() <= 5e-5, "{got:?} vs {published:?}");
    }
    let x0 = [orbit.q0[0], orbit.q0[1], orbit.qdot0[0], orbit.qdot0[1]];
    let jac = return_map_jacobian(&w, x0, 1e-4);
    assert_section_columns(&orbit, &jac, 1e-8);
    assert!(orbit.stability.is_stable());
    assert_eq!(
        orbit
            .multipliers
            .iter()
            .filter(|m| m.im.abs() > 1e-3)
            .count(),
        2,
        "{:?}",
        orbit.multipliers
    );
}

/// Following the gait up the slope, each shot started from the last gait walked one step on
/// the new slope (a guess 1e-2 off: Newton's section rows have to be consistent off the
/// section for this), until the real multiplier passes −1 (between 4.2° and 4.6°); past it the
/// settled walk alternates a long and a short step (period two), where below it takes one.
#[test]
fn goswami_walker_period_doubling() {
    let start = CompassGait::goswami(3.0);
    let (q0, v0) = start
        .to_mid_stance([-0.27, 0.27], [1.1, 0.4], tight())
        .unwrap();
    let mut orbit = start.gait(q0, v0, 0.75, tight()).unwrap();
    let most_negative = |o: &PeriodicOrbit<2>| {
        o.multipliers
            .iter()
            .map(|m| m.re)
            .fold(f64::INFINITY, f64::min)
    };
    let mut at = Vec::new();
    let mut below = orbit.clone();
    for deg in [3.4, 3.8, 4.2, 4.6] {
        let w = CompassGait::goswami(deg);
        let (q, v) = w.to_mid_stance(orbit.q0, orbit.qdot0, tight()).unwrap();
        let next = w.gait(q, v, orbit.period, tight()).unwrap();
        below = std::mem::replace(&mut orbit, next);
        at.push((deg, most_negative(&orbit)));
    }
    eprintln!("most negative multiplier along the slope: {at:?}");
    assert!(at[2].1 > -1.0 && at[3].1 < -1.0, "{at:?}");
    // The settled walk from the other slope's gait: the distinct inter-leg angles of its last
    // 8 steps after 300.
    let distinct_steps = |deg: f64, from: &PeriodicOrbit<2>| {
        let w = CompassGait::goswami(deg);
        let run = Simulation::new(&w, from.q0, from.qdot0)
            .method(tight())
            .event(w.heel_strike_event())
            .until(300.0 * 0.75)
            .keep_samples(false)
            .run()
            .unwrap();
        let mut a: Vec<f64> = run
            .jumps
            .iter()
            .rev()
            .take(8)
            .map(|j| j.after.0[1])
            .collect();
        a.sort_by(f64::total_cmp);
        eprintln!("{deg}°: {a:?}");
        a.dedup_by(|x, y| (*x - *y).abs() < 1e-6);
        a.len()
    };
    assert_eq!(distinct_steps(4.2, &orbit), 1);
    assert_eq!(distinct_steps(4.6, &below), 2);
}
