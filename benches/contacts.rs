//! The price of declaring contacts: the bouncing ball of the `impacts` example run with
//! `Simulation::contacts` (its impact law derived from M and the gap, the Zeno accumulation
//! resolved to rest) against the same ball run with a hand-written reset map
//! (`Event::reset`, Newton's law written out), DOP853 at rtol 1e-12 to the accumulation time,
//! in one run; and a stride of the rimless wheel (eight sticking contacts, one impact each).
//!
//! Run: `cargo bench --bench contacts`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;
use lagrange_examples::contact_systems::{omega_star, Ball, RimlessWheel, SPOKES};

const METHOD: Method = Method::Dop853 {
    rtol: 1e-12,
    atol: 1e-14,
};
const H: f64 = 1.0;
const E: f64 = 0.8;

fn t_inf(g: f64) -> f64 {
    (2.0 * H / g).sqrt() * (1.0 + E) / (1.0 - E)
}

fn declared(ball: &Ball) -> Trajectory<2> {
    Simulation::contacts(ball, [0.0, H], [0.3, 0.0])
        .method(METHOD)
        .until(t_inf(ball.g))
        .sample_every(0.01)
        .run()
        .expect("the ball integrates")
}

fn hand_written(ball: &Ball) -> Trajectory<2> {
    let floor = Event::zero_crossing("floor", |_t, q: &[f64; 2], _v| q[1])
        .falling()
        .reset(|_t, q, v| (*q, [v[0], -E * v[1]]));
    Simulation::new(ball, [0.0, H], [0.3, 0.0])
        .method(METHOD)
        .event(floor)
        .until(t_inf(ball.g))
        .sample_every(0.01)
        .run()
        .expect("the ball integrates")
}

fn wheel_strides(wheel: &RimlessWheel, until: f64) -> Trajectory<3> {
    let alpha = std::f64::consts::PI / SPOKES as f64;
    let (l, w0) = (wheel.l, omega_star(wheel));
    let q0 = [-l * alpha.sin(), l * alpha.cos(), alpha];
    let v0 = [l * w0 * alpha.cos(), l * w0 * alpha.sin(), -w0];
    Simulation::contacts(wheel, q0, v0)
        .method(METHOD)
        .until(until)
        .keep_samples(false)
        .run()
        .expect("the wheel integrates")
}

fn bench(c: &mut Criterion) {
    let ball = Ball {
        m: 0.7,
        g: 9.81,
        e: E,
    };
    // The same impacts either way: the declared run's first seven (the seventh made plastic
    // by the Zeno resolution) at the hand-written run's times.
    let (d, h) = (declared(&ball), hand_written(&ball));
    for (a, b) in d.jumps.iter().zip(&h.jumps) {
        assert!((a.t - b.t).abs() < 1e-12, "{} vs {}", a.t, b.t);
    }
    println!(
        "declared: {} impacts, {} steps, {} evaluations; hand-written reset map: {} impacts, {} \
         steps, {} evaluations",
        d.jumps.len(),
        d.stats.steps,
        d.stats.rhs_evals,
        h.jumps.len(),
        h.stats.steps,
        h.stats.rhs_evals
    );
    let mut g = c.benchmark_group("bouncing ball to t_inf");
    g.bench_function("Simulation::contacts", |b| {
        b.iter(|| black_box(declared(black_box(&ball))))
    });
    g.bench_function("Event::reset by hand", |b| {
        b.iter(|| black_box(hand_written(black_box(&ball))))
    });
    g.finish();

    let wheel = RimlessWheel {
        m: 2.0,
        g: 9.81,
        l: 1.0,
        slope: 0.08,
    };
    let strides = wheel_strides(&wheel, 20.0);
    println!(
        "rimless wheel: {} strides in 20 s, {} steps, {} evaluations",
        strides.jumps.len(),
        strides.stats.steps,
        strides.stats.rhs_evals
    );
    let mut g = c.benchmark_group("rimless wheel");
    g.bench_function("20 s of walking", |b| {
        b.iter(|| black_box(wheel_strides(black_box(&wheel), 20.0)))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
