//! The price of constraints: the heavy top in unit quaternions (four coordinates, |q|² = 1,
//! multipliers, a projection after every step) against the same top in Euler angles (three
//! coordinates, no constraint), DOP853 at rtol 1e-10 over the same motion, in one run. Also the
//! right-hand side alone: `constrained_accelerations` of the quaternion top against the Euler-angle
//! top's `accelerations` (16 states of the same motion).
//!
//! Run: `cargo bench --bench constraints`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;

use heavy_top_system::HeavyTop;
use lagrange_examples::heavy_top_system;
use lagrange_examples::quaternion_top_system;
use quaternion_top_system::{from_euler, QuaternionTop};

/// The heavy-top benchmark of the integrator benches: I⊥ = 1, I∥ = 0.5, mgl = 4.905,
/// θ0 = 0.7, φ̇0 = 2, ψ̇0 = 12, to t = 114.3 (100 nutation periods).
const ANGLES: [f64; 3] = [0.7, 0.0, 0.0];
const RATES: [f64; 3] = [0.0, 2.0, 12.0];
const UNTIL: f64 = 114.3;
const METHOD: Method = Method::Dop853 {
    rtol: 1e-10,
    atol: 1e-12,
};

fn euler(top: &HeavyTop) -> Trajectory<3> {
    Simulation::new(top, ANGLES, RATES)
        .method(METHOD)
        .until(UNTIL)
        .sample_every(UNTIL)
        .run()
        .expect("the Euler-angle top integrates")
}

fn quaternion(top: &QuaternionTop) -> Trajectory<4> {
    let (q0, v0) = from_euler(ANGLES, RATES);
    Simulation::constrained(top, q0, v0)
        .method(METHOD)
        .until(UNTIL)
        .sample_every(UNTIL)
        .run()
        .expect("the quaternion top integrates")
}

fn bench(c: &mut Criterion) {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.5,
        mgl: 4.905,
    };
    let qtop = QuaternionTop {
        i_perp: 1.0,
        i_par: 0.5,
        mgl: 4.905,
    };
    // Same motion: the final cos θ of both runs agree (to the tolerance), and the counts.
    let (e, q) = (euler(&top), quaternion(&qtop));
    let cos_e = e.q.last().map(|q| q[0].cos()).unwrap_or(f64::NAN);
    let cos_q =
        q.q.last()
            .map(|q| q[0] * q[0] - q[1] * q[1] - q[2] * q[2] + q[3] * q[3])
            .unwrap_or(f64::NAN);
    assert!((cos_e - cos_q).abs() < 1e-6, "{cos_e} vs {cos_q}");
    println!(
        "euler angles: {} steps, {} evaluations; quaternions: {} steps, {} evaluations; final cos θ \
         differ by {:.1e}; quaternion residual {:?}",
        e.stats.steps,
        e.stats.rhs_evals,
        q.stats.steps,
        q.stats.rhs_evals,
        (cos_e - cos_q).abs(),
        q.invariants().constraints
    );

    // Same rtol is not the same accuracy: the largest error in cos θ over the run (sampled
    // every 1) against the Euler-angle top at rtol 1e-14, for both charts. The quaternions'
    // components turn with the spin (ψ̇/2 = 6 rad/s) where the Euler angles carry it in ψ alone.
    let sampled = |m: Method| {
        let e = Simulation::new(&top, ANGLES, RATES)
            .method(m)
            .until(UNTIL)
            .sample_every(1.0)
            .run()
            .expect("the Euler-angle top integrates");
        let (q0, v0) = from_euler(ANGLES, RATES);
        let q = Simulation::constrained(&qtop, q0, v0)
            .method(m)
            .until(UNTIL)
            .sample_every(1.0)
            .run()
            .expect("the quaternion top integrates");
        (e, q)
    };
    let (reference, _) = sampled(Method::Dop853 {
        rtol: 1e-14,
        atol: 1e-16,
    });
    let (e, q) = sampled(METHOD);
    let (mut err_e, mut err_q) = (0.0_f64, 0.0_f64);
    for k in 0..reference.len() {
        let want = reference.q[k][0].cos();
        let [w, x, y, z] = q.q[k];
        err_e = err_e.max((e.q[k][0].cos() - want).abs());
        err_q = err_q.max((w * w - x * x - y * y + z * z - want).abs());
    }
    println!(
        "largest cos θ error at rtol 1e-10: euler angles {err_e:.1e}, quaternions {err_q:.1e}"
    );

    // The ratio from alternating runs (fastest of 40 each): this machine's load moves either
    // side's criterion time by ±20 % between groups, alternation keeps both under the same load.
    let (mut best_e, mut best_q) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..40 {
        let start = std::time::Instant::now();
        black_box(euler(black_box(&top)));
        best_e = best_e.min(start.elapsed().as_secs_f64());
        let start = std::time::Instant::now();
        black_box(quaternion(black_box(&qtop)));
        best_q = best_q.min(start.elapsed().as_secs_f64());
    }
    println!(
        "alternating, fastest of 40: euler angles {:.3} ms, quaternions {:.3} ms, ratio {:.2}",
        best_e * 1e3,
        best_q * 1e3,
        best_q / best_e
    );

    let mut g = c.benchmark_group("heavy_top_dop853_rtol1e-10");
    g.bench_function("euler_angles", |b| b.iter(|| euler(black_box(&top))));
    g.bench_function("quaternions_constrained", |b| {
        b.iter(|| quaternion(black_box(&qtop)))
    });
    g.finish();

    // The right-hand side alone, at 16 states of the same motion.
    let states: Vec<([f64; 3], [f64; 3])> =
        e.q.iter().zip(&e.qdot).map(|(q, v)| (*q, *v)).collect();
    let picks: Vec<([f64; 3], [f64; 3])> = (0..16)
        .map(|k| states[k * (states.len() - 1) / 15])
        .collect();
    let quats: Vec<([f64; 4], [f64; 4])> = picks.iter().map(|(q, v)| from_euler(*q, *v)).collect();
    let mut g = c.benchmark_group("heavy_top_rhs_x16");
    g.bench_function("euler_angles_accelerations", |b| {
        b.iter(|| {
            for (q, v) in &picks {
                black_box(top.accelerations(black_box(q), black_box(v), 0.0).ok());
            }
        })
    });
    g.bench_function("quaternions_constrained_accelerations", |b| {
        b.iter(|| {
            for (q, v) in &quats {
                black_box(
                    qtop.constrained_accelerations(black_box(q), black_box(v), 0.0)
                        .ok(),
                );
            }
        })
    });
    // Where the constrained right-hand side's time goes: the pieces (M, f; symbolic code), the
    // constraint rows (jets), and the solve.
    g.bench_function("quaternions_pieces_only", |b| {
        b.iter(|| {
            for (q, v) in &quats {
                black_box(qtop.pieces(black_box(q), black_box(v), 0.0));
            }
        })
    });
    g.bench_function("quaternions_constraint_rows_only", |b| {
        b.iter(|| {
            for (q, v) in &quats {
                black_box(qtop.constraint_rows(black_box(q), black_box(v), 0.0));
            }
        })
    });
    let split: Vec<_> = quats
        .iter()
        .map(|(q, v)| {
            (
                qtop.pieces(q, v, 0.0),
                qtop.constraint_rows(q, v, 0.0),
                *q,
                *v,
            )
        })
        .collect();
    g.bench_function("quaternions_solve_only", |b| {
        b.iter(|| {
            for (p, r, q, v) in &split {
                black_box(
                    lagrange::eom::solve_constrained(
                        black_box(p),
                        black_box(r),
                        <QuaternionTop as Lagrangian<4>>::COORDINATES,
                        q,
                        v,
                        0.0,
                    )
                    .ok(),
                );
            }
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
