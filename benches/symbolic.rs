//! Symbolic-mode benchmarks (derivatives taken at compile time): generated accelerations against
//! hand-written closed forms and run-time jets, in the same run. The systems (each a symbolic/jets
//! twin from one body) are shared with the integration tests: examples/support/systems.rs.
//!
//! `cargo bench --bench symbolic`
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;

use lagrange_examples::systems::{
    Chain16, Chain2, Chain4, Chain8, GeometryTop, HeavyTop, RotationTop,
};

/// The heavy top's accelerations in closed form, written by hand (θ̈ directly, the φ–ψ block by
/// Cramer's rule with det = I∥ I⊥ sin²θ).
#[inline(never)]
fn top_closed_form(p: &HeavyTop, q: &[f64; 3], v: &[f64; 3]) -> [f64; 3] {
    let (s, c) = q[0].sin_cos();
    let (td, pd, sd) = (v[0], v[1], v[2]);
    let th = ((p.i_perp - p.i_par) * pd * pd * s * c - p.i_par * pd * sd * s + p.m * p.g * p.l * s)
        / p.i_perp;
    let f1 = 2.0 * (p.i_par - p.i_perp) * td * pd * s * c + p.i_par * td * sd * s;
    let f2 = p.i_par * td * pd * s;
    let ph = (f1 - c * f2) / (p.i_perp * s * s);
    let ps = f2 / p.i_par - c * ph;
    [th, ph, ps]
}

/// The chain's M and f written by hand (equal links): M_ij = m l² (N − max(i, j)) cos(θᵢ − θⱼ),
/// f_i = −m l² Σⱼ (N − max(i, j)) sin(θᵢ − θⱼ) θ̇ⱼ² − m g l (N − i) sin θᵢ, with one sin_cos per
/// link and the difference formulas; then the runtime's LDLᵀ.
#[inline(never)]
fn chain_closed_form<const N: usize>(
    m: f64,
    l: f64,
    g: f64,
    q: &[f64; N],
    v: &[f64; N],
) -> Result<[f64; N], DynamicsError> {
    let mut s = [0.0; N];
    let mut c = [0.0; N];
    for i in 0..N {
        (s[i], c[i]) = q[i].sin_cos();
    }
    let ml2 = m * l * l;
    let mut mm = [[0.0; N]; N];
    let mut f = [0.0; N];
    for i in 0..N {
        f[i] = -m * g * l * (N - i) as f64 * s[i];
    }
    for i in 0..N {
        for j in i..N {
            let w = ml2 * (N - j) as f64;
            mm[i][j] = w * (c[i] * c[j] + s[i] * s[j]);
            let sij = w * (s[i] * c[j] - c[i] * s[j]);
            f[i] -= sij * v[j] * v[j];
            if j != i {
                f[j] += sij * v[i] * v[i];
            }
        }
    }
    lagrange::__private::solve_mass_matrix(&mm, &f, ["θ"; N], q, v, 0.0)
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(30)
}

fn heavy_top(c: &mut Criterion) {
    let top = HeavyTop {
        i_perp: 2.0,
        i_par: 0.7,
        m: 1.3,
        g: 9.81,
        l: 0.4,
    };
    let jets = top.jets();
    let q = [0.7, 0.2, -0.4];
    let v = [0.3, -1.1, 2.5];
    let mut group = c.benchmark_group("heavy_top_accelerations");
    group.bench_function("hand_closed_form", |b| {
        b.iter(|| top_closed_form(black_box(&top), black_box(&q), black_box(&v)))
    });
    // The same closed form behind the trait's return type (Result with DynamicsError) and the
    // same finiteness test as the generated code: isolates what the signature costs.
    group.bench_function("hand_closed_form_as_result", |b| {
        b.iter(|| top_closed_form_result(black_box(&top), black_box(&q), black_box(&v)))
    });
    group.bench_function("symbolic", |b| {
        b.iter(|| black_box(&top).accelerations(black_box(&q), black_box(&v), 0.0))
    });
    group.bench_function("jets", |b| {
        b.iter(|| black_box(&jets).accelerations(black_box(&q), black_box(&v), 0.0))
    });
    // The same top written from its body angular velocity under R_z(φ) R_x(θ) R_z(ψ): ψ leaves L
    // through sin²ψ + cos²ψ = 1 (target: within 1.1× of `symbolic`).
    let rotation = RotationTop {
        i_perp: top.i_perp,
        i_par: top.i_par,
        mgl: top.m * top.g * top.l,
    };
    group.bench_function("symbolic_from_rotation", |b| {
        b.iter(|| black_box(&rotation).accelerations(black_box(&q), black_box(&v), 0.0))
    });
    // Written from the rotation matrix itself (`Rotation`, `body_angular_velocity`): the macro
    // derives ω (target: within 1.1× of `symbolic`).
    let geometry = GeometryTop {
        i_perp: top.i_perp,
        i_par: top.i_par,
        mgl: top.m * top.g * top.l,
    };
    let geometry_jets = geometry.jets();
    group.bench_function("symbolic_from_rotation_matrix", |b| {
        b.iter(|| black_box(&geometry).accelerations(black_box(&q), black_box(&v), 0.0))
    });
    group.bench_function("jets_from_rotation_matrix", |b| {
        b.iter(|| black_box(&geometry_jets).accelerations(black_box(&q), black_box(&v), 0.0))
    });
    group.finish();
}

/// `top_closed_form` returning `Result<[f64; 3], DynamicsError>` like `Lagrangian::accelerations`
/// (the error arm is the runtime's solve, as in the generated code).
#[inline]
fn top_closed_form_result(
    p: &HeavyTop,
    q: &[f64; 3],
    v: &[f64; 3],
) -> Result<[f64; 3], DynamicsError> {
    let x = top_closed_form(p, q, v);
    if x.iter().all(|a| a.is_finite()) {
        Ok(x)
    } else {
        lagrange::__private::solve_mass_matrix(&[[1.0; 3]; 3], &x, ["θ"; 3], q, v, 0.0)
    }
}

macro_rules! chain_bench {
    ($c:expr, $n:literal, $sym:ident) => {{
        let (m, l, g) = (0.7, 0.9, 9.81);
        let sym = $sym { m, l, g };
        let jets = sym.jets();
        let q: [f64; $n] = std::array::from_fn(|i| 0.3 * ((i as f64) * 1.7).sin());
        let v: [f64; $n] = std::array::from_fn(|i| 0.5 * ((i as f64) * 0.9).cos());
        let mut group = $c.benchmark_group(concat!("chain_", stringify!($n), "_accelerations"));
        group.bench_function("hand_closed_m_ldlt", |b| {
            b.iter(|| {
                chain_closed_form(
                    black_box(m),
                    black_box(l),
                    black_box(g),
                    black_box(&q),
                    black_box(&v),
                )
            })
        });
        group.bench_function("symbolic", |b| {
            b.iter(|| black_box(&sym).accelerations(black_box(&q), black_box(&v), 0.0))
        });
        group.bench_function("jets", |b| {
            b.iter(|| black_box(&jets).accelerations(black_box(&q), black_box(&v), 0.0))
        });
        group.finish();
    }};
}

fn chains(c: &mut Criterion) {
    chain_bench!(c, 2, Chain2);
    chain_bench!(c, 4, Chain4);
    chain_bench!(c, 8, Chain8);
    chain_bench!(c, 16, Chain16);
}

criterion_group! {
    name = benches;
    config = config();
    targets = heavy_top, chains
}
criterion_main!(benches);
