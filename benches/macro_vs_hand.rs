//! Heavy-top accelerations three ways, in one run: the hand-derived closed form (baseline), a
//! hand-written generic `impl Lagrangian<3>`, and the same L declared with `#[lagrangian]` (the
//! contract text).
//!
//! Run: `cargo bench --bench macro_vs_hand`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;

// The heavy top of the macro contract, declared with the macro (the tests' declaration).
use lagrange_examples::systems::HeavyTop as MacroTop;

/// The same L, hand-written generic code, operation for operation what the macro should emit
/// (constants on the right of Scalar ops, `powi(2)` as written).
pub struct HandTop {
    pub i_perp: f64,
    pub i_par: f64,
    pub m: f64,
    pub g: f64,
    pub l: f64,
}

impl Lagrangian<3> for HandTop {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    #[inline]
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], qd: &[S; 3], _t: S) -> S {
        let (s, c) = q[0].sin_cos();
        (qd[0].powi(2) + (qd[1] * s).powi(2)) * (self.i_perp / 2.0)
            + (qd[2] + qd[1] * c).powi(2) * (self.i_par / 2.0)
            - c * (self.m * self.g * self.l)
    }
}

/// The hand-written impl of tests/support/hand.rs (products instead of `powi`).
pub struct HandTopProducts {
    pub i_perp: f64,
    pub i_par: f64,
    pub mgl: f64,
}

impl Lagrangian<3> for HandTopProducts {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    #[inline]
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], qd: &[S; 3], _t: S) -> S {
        let (s, c) = q[0].sin_cos();
        let w3 = qd[2] + qd[1] * c;
        (qd[0] * qd[0] + qd[1] * qd[1] * s * s) * (self.i_perp / 2.0) + w3 * w3 * (self.i_par / 2.0)
            - c * self.mgl
    }
}

/// Hand-derived: I⊥θ̈ = I⊥φ̇²sc − I∥ω₃φ̇s + mgl s;  φ̈ = θ̇(I∥ω₃ − 2I⊥φ̇c)/(I⊥s);  ψ̈ = φ̇θ̇s − φ̈c.
#[inline(never)]
fn closed_form(i_perp: f64, i_par: f64, mgl: f64, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 3] {
    let (s, c) = q[0].sin_cos();
    let w3 = qd[2] + qd[1] * c;
    let th = qd[1] * qd[1] * s * c - i_par / i_perp * w3 * qd[1] * s + mgl / i_perp * s;
    let ph = qd[0] * (i_par * w3 - 2.0 * i_perp * qd[1] * c) / (i_perp * s);
    let ps = qd[1] * qd[0] * s - ph * c;
    [th, ph, ps]
}

#[inline(never)]
fn via_trait<L: Lagrangian<3>>(sys: &L, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 3] {
    sys.accelerations(q, qd, 0.0).unwrap_or([f64::NAN; 3])
}

fn bench(c: &mut Criterion) {
    let (i_perp, i_par, m, g, l) = (1.3, 0.7, 0.9, 9.81, 0.4);
    let mac = MacroTop {
        i_perp,
        i_par,
        m,
        g,
        l,
    };
    let hand = HandTop {
        i_perp,
        i_par,
        m,
        g,
        l,
    };
    let prod = HandTopProducts {
        i_perp,
        i_par,
        mgl: m * g * l,
    };
    // 16 fixed states, cycled through in every iteration (as in benches/jets.rs), so one lucky
    // state cannot decide the comparison; the reported time is per 16 calls.
    let states: Vec<([f64; 3], [f64; 3])> = (0..16)
        .map(|k| {
            let x = f64::from(k);
            (
                [0.3 + 0.15 * x, 0.3 - 0.2 * x, -1.0 + 0.1 * x],
                [0.4 - 0.05 * x, -0.6 + 0.1 * x, 9.0 - 0.5 * x],
            )
        })
        .collect();

    // All four agree before anything is timed.
    for (q, qd) in &states {
        let want = closed_form(i_perp, i_par, m * g * l, q, qd);
        for got in [
            via_trait(&mac, q, qd),
            via_trait(&hand, q, qd),
            via_trait(&prod, q, qd),
        ] {
            for i in 0..3 {
                assert!((got[i] - want[i]).abs() < 1e-12 * want[i].abs().max(1.0));
            }
        }
    }

    let mgl = m * g * l;
    let mut group = c.benchmark_group("heavy_top_accelerations_x16");
    group.bench_function("closed_form", |b| {
        b.iter(|| {
            for (q, qd) in black_box(&states) {
                black_box(closed_form(
                    black_box(i_perp),
                    black_box(i_par),
                    black_box(mgl),
                    q,
                    qd,
                ));
            }
        });
    });
    group.bench_function("hand_impl_powi", |b| {
        b.iter(|| {
            for (q, qd) in black_box(&states) {
                black_box(via_trait(black_box(&hand), q, qd));
            }
        });
    });
    group.bench_function("hand_impl_products", |b| {
        b.iter(|| {
            for (q, qd) in black_box(&states) {
                black_box(via_trait(black_box(&prod), q, qd));
            }
        });
    });
    group.bench_function("macro", |b| {
        b.iter(|| {
            for (q, qd) in black_box(&states) {
                black_box(via_trait(black_box(&mac), q, qd));
            }
        });
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(60)
        .warm_up_time(std::time::Duration::from_secs(1))
        .measurement_time(std::time::Duration::from_secs(4));
    targets = bench
}
criterion_main!(benches);
