//! Symbolic mode (issue 7) benchmarks: generated accelerations against hand-written closed forms
//! and run-time jets, in the same run.
//!
//! `cargo bench --bench symbolic`
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;

/// Symmetric heavy top, eq. (92): symbolic (the default mode).
#[derive(Debug, Clone, Copy)]
pub struct HeavyTop {
    pub i_perp: f64,
    pub i_par: f64,
    pub m: f64,
    pub g: f64,
    pub l: f64,
}

#[lagrangian]
impl HeavyTop {
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let (s, c) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
            - self.m * self.g * self.l * c
    }
}

/// The same top with run-time jets.
#[derive(Debug, Clone, Copy)]
pub struct HeavyTopJets {
    pub i_perp: f64,
    pub i_par: f64,
    pub m: f64,
    pub g: f64,
    pub l: f64,
}

#[lagrangian(mode = "jets")]
impl HeavyTopJets {
    fn lagrangian(
        &self,
        (theta, theta_dot): Coord,
        (phi, phi_dot): Coord,
        (psi, psi_dot): Coord,
    ) -> Scalar {
        let (s, c) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
            - self.m * self.g * self.l * c
    }
}

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
    let jets = HeavyTopJets {
        i_perp: 2.0,
        i_par: 0.7,
        m: 1.3,
        g: 9.81,
        l: 0.4,
    };
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
    ($c:expr, $n:literal, $sym:ident, $jet:ident) => {{
        let (m, l, g) = (0.7, 0.9, 9.81);
        let sym = $sym { m, l, g };
        let jets = $jet { m, l, g };
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
    chain_bench!(c, 2, Chain2, Chain2Jets);
    chain_bench!(c, 4, Chain4, Chain4Jets);
    chain_bench!(c, 8, Chain8, Chain8Jets);
    chain_bench!(c, 16, Chain16, Chain16Jets);
}

criterion_group! {
    name = benches;
    config = config();
    targets = heavy_top, chains
}
criterion_main!(benches);

/// A 2-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct Chain2 {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian]
impl Chain2 {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(&self, (th1, th1_dot): Coord, (th2, th2_dot): Coord) -> Scalar {
        let (s1, c1) = th1.sin_cos();
        let mut vx = self.l * c1 * th1_dot;
        let mut vy = self.l * s1 * th1_dot;
        let mut y = -self.l * c1;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s2, c2) = th2.sin_cos();
        vx += self.l * c2 * th2_dot;
        vy += self.l * s2 * th2_dot;
        y -= self.l * c2;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        lag
    }
}

/// A 2-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct Chain2Jets {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl Chain2Jets {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(&self, (th1, th1_dot): Coord, (th2, th2_dot): Coord) -> Scalar {
        let (s1, c1) = th1.sin_cos();
        let mut vx = self.l * c1 * th1_dot;
        let mut vy = self.l * s1 * th1_dot;
        let mut y = -self.l * c1;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s2, c2) = th2.sin_cos();
        vx += self.l * c2 * th2_dot;
        vy += self.l * s2 * th2_dot;
        y -= self.l * c2;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        lag
    }
}

/// A 4-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct Chain4 {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian]
impl Chain4 {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (th1, th1_dot): Coord,
        (th2, th2_dot): Coord,
        (th3, th3_dot): Coord,
        (th4, th4_dot): Coord,
    ) -> Scalar {
        let (s1, c1) = th1.sin_cos();
        let mut vx = self.l * c1 * th1_dot;
        let mut vy = self.l * s1 * th1_dot;
        let mut y = -self.l * c1;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s2, c2) = th2.sin_cos();
        vx += self.l * c2 * th2_dot;
        vy += self.l * s2 * th2_dot;
        y -= self.l * c2;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s3, c3) = th3.sin_cos();
        vx += self.l * c3 * th3_dot;
        vy += self.l * s3 * th3_dot;
        y -= self.l * c3;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s4, c4) = th4.sin_cos();
        vx += self.l * c4 * th4_dot;
        vy += self.l * s4 * th4_dot;
        y -= self.l * c4;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        lag
    }
}

/// A 4-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct Chain4Jets {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl Chain4Jets {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (th1, th1_dot): Coord,
        (th2, th2_dot): Coord,
        (th3, th3_dot): Coord,
        (th4, th4_dot): Coord,
    ) -> Scalar {
        let (s1, c1) = th1.sin_cos();
        let mut vx = self.l * c1 * th1_dot;
        let mut vy = self.l * s1 * th1_dot;
        let mut y = -self.l * c1;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s2, c2) = th2.sin_cos();
        vx += self.l * c2 * th2_dot;
        vy += self.l * s2 * th2_dot;
        y -= self.l * c2;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s3, c3) = th3.sin_cos();
        vx += self.l * c3 * th3_dot;
        vy += self.l * s3 * th3_dot;
        y -= self.l * c3;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s4, c4) = th4.sin_cos();
        vx += self.l * c4 * th4_dot;
        vy += self.l * s4 * th4_dot;
        y -= self.l * c4;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        lag
    }
}

/// A 8-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct Chain8 {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian]
impl Chain8 {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (th1, th1_dot): Coord,
        (th2, th2_dot): Coord,
        (th3, th3_dot): Coord,
        (th4, th4_dot): Coord,
        (th5, th5_dot): Coord,
        (th6, th6_dot): Coord,
        (th7, th7_dot): Coord,
        (th8, th8_dot): Coord,
    ) -> Scalar {
        let (s1, c1) = th1.sin_cos();
        let mut vx = self.l * c1 * th1_dot;
        let mut vy = self.l * s1 * th1_dot;
        let mut y = -self.l * c1;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s2, c2) = th2.sin_cos();
        vx += self.l * c2 * th2_dot;
        vy += self.l * s2 * th2_dot;
        y -= self.l * c2;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s3, c3) = th3.sin_cos();
        vx += self.l * c3 * th3_dot;
        vy += self.l * s3 * th3_dot;
        y -= self.l * c3;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s4, c4) = th4.sin_cos();
        vx += self.l * c4 * th4_dot;
        vy += self.l * s4 * th4_dot;
        y -= self.l * c4;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s5, c5) = th5.sin_cos();
        vx += self.l * c5 * th5_dot;
        vy += self.l * s5 * th5_dot;
        y -= self.l * c5;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s6, c6) = th6.sin_cos();
        vx += self.l * c6 * th6_dot;
        vy += self.l * s6 * th6_dot;
        y -= self.l * c6;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s7, c7) = th7.sin_cos();
        vx += self.l * c7 * th7_dot;
        vy += self.l * s7 * th7_dot;
        y -= self.l * c7;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s8, c8) = th8.sin_cos();
        vx += self.l * c8 * th8_dot;
        vy += self.l * s8 * th8_dot;
        y -= self.l * c8;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        lag
    }
}

/// A 8-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct Chain8Jets {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl Chain8Jets {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (th1, th1_dot): Coord,
        (th2, th2_dot): Coord,
        (th3, th3_dot): Coord,
        (th4, th4_dot): Coord,
        (th5, th5_dot): Coord,
        (th6, th6_dot): Coord,
        (th7, th7_dot): Coord,
        (th8, th8_dot): Coord,
    ) -> Scalar {
        let (s1, c1) = th1.sin_cos();
        let mut vx = self.l * c1 * th1_dot;
        let mut vy = self.l * s1 * th1_dot;
        let mut y = -self.l * c1;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s2, c2) = th2.sin_cos();
        vx += self.l * c2 * th2_dot;
        vy += self.l * s2 * th2_dot;
        y -= self.l * c2;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s3, c3) = th3.sin_cos();
        vx += self.l * c3 * th3_dot;
        vy += self.l * s3 * th3_dot;
        y -= self.l * c3;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s4, c4) = th4.sin_cos();
        vx += self.l * c4 * th4_dot;
        vy += self.l * s4 * th4_dot;
        y -= self.l * c4;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s5, c5) = th5.sin_cos();
        vx += self.l * c5 * th5_dot;
        vy += self.l * s5 * th5_dot;
        y -= self.l * c5;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s6, c6) = th6.sin_cos();
        vx += self.l * c6 * th6_dot;
        vy += self.l * s6 * th6_dot;
        y -= self.l * c6;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s7, c7) = th7.sin_cos();
        vx += self.l * c7 * th7_dot;
        vy += self.l * s7 * th7_dot;
        y -= self.l * c7;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s8, c8) = th8.sin_cos();
        vx += self.l * c8 * th8_dot;
        vy += self.l * s8 * th8_dot;
        y -= self.l * c8;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        lag
    }
}

/// A 16-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct Chain16 {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian]
impl Chain16 {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (th1, th1_dot): Coord,
        (th2, th2_dot): Coord,
        (th3, th3_dot): Coord,
        (th4, th4_dot): Coord,
        (th5, th5_dot): Coord,
        (th6, th6_dot): Coord,
        (th7, th7_dot): Coord,
        (th8, th8_dot): Coord,
        (th9, th9_dot): Coord,
        (th10, th10_dot): Coord,
        (th11, th11_dot): Coord,
        (th12, th12_dot): Coord,
        (th13, th13_dot): Coord,
        (th14, th14_dot): Coord,
        (th15, th15_dot): Coord,
        (th16, th16_dot): Coord,
    ) -> Scalar {
        let (s1, c1) = th1.sin_cos();
        let mut vx = self.l * c1 * th1_dot;
        let mut vy = self.l * s1 * th1_dot;
        let mut y = -self.l * c1;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s2, c2) = th2.sin_cos();
        vx += self.l * c2 * th2_dot;
        vy += self.l * s2 * th2_dot;
        y -= self.l * c2;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s3, c3) = th3.sin_cos();
        vx += self.l * c3 * th3_dot;
        vy += self.l * s3 * th3_dot;
        y -= self.l * c3;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s4, c4) = th4.sin_cos();
        vx += self.l * c4 * th4_dot;
        vy += self.l * s4 * th4_dot;
        y -= self.l * c4;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s5, c5) = th5.sin_cos();
        vx += self.l * c5 * th5_dot;
        vy += self.l * s5 * th5_dot;
        y -= self.l * c5;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s6, c6) = th6.sin_cos();
        vx += self.l * c6 * th6_dot;
        vy += self.l * s6 * th6_dot;
        y -= self.l * c6;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s7, c7) = th7.sin_cos();
        vx += self.l * c7 * th7_dot;
        vy += self.l * s7 * th7_dot;
        y -= self.l * c7;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s8, c8) = th8.sin_cos();
        vx += self.l * c8 * th8_dot;
        vy += self.l * s8 * th8_dot;
        y -= self.l * c8;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s9, c9) = th9.sin_cos();
        vx += self.l * c9 * th9_dot;
        vy += self.l * s9 * th9_dot;
        y -= self.l * c9;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s10, c10) = th10.sin_cos();
        vx += self.l * c10 * th10_dot;
        vy += self.l * s10 * th10_dot;
        y -= self.l * c10;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s11, c11) = th11.sin_cos();
        vx += self.l * c11 * th11_dot;
        vy += self.l * s11 * th11_dot;
        y -= self.l * c11;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s12, c12) = th12.sin_cos();
        vx += self.l * c12 * th12_dot;
        vy += self.l * s12 * th12_dot;
        y -= self.l * c12;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s13, c13) = th13.sin_cos();
        vx += self.l * c13 * th13_dot;
        vy += self.l * s13 * th13_dot;
        y -= self.l * c13;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s14, c14) = th14.sin_cos();
        vx += self.l * c14 * th14_dot;
        vy += self.l * s14 * th14_dot;
        y -= self.l * c14;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s15, c15) = th15.sin_cos();
        vx += self.l * c15 * th15_dot;
        vy += self.l * s15 * th15_dot;
        y -= self.l * c15;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s16, c16) = th16.sin_cos();
        vx += self.l * c16 * th16_dot;
        vy += self.l * s16 * th16_dot;
        y -= self.l * c16;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        lag
    }
}

/// A 16-link pendulum chain (equal masses and lengths), L written out.
#[derive(Debug, Clone, Copy)]
pub struct Chain16Jets {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl Chain16Jets {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (th1, th1_dot): Coord,
        (th2, th2_dot): Coord,
        (th3, th3_dot): Coord,
        (th4, th4_dot): Coord,
        (th5, th5_dot): Coord,
        (th6, th6_dot): Coord,
        (th7, th7_dot): Coord,
        (th8, th8_dot): Coord,
        (th9, th9_dot): Coord,
        (th10, th10_dot): Coord,
        (th11, th11_dot): Coord,
        (th12, th12_dot): Coord,
        (th13, th13_dot): Coord,
        (th14, th14_dot): Coord,
        (th15, th15_dot): Coord,
        (th16, th16_dot): Coord,
    ) -> Scalar {
        let (s1, c1) = th1.sin_cos();
        let mut vx = self.l * c1 * th1_dot;
        let mut vy = self.l * s1 * th1_dot;
        let mut y = -self.l * c1;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s2, c2) = th2.sin_cos();
        vx += self.l * c2 * th2_dot;
        vy += self.l * s2 * th2_dot;
        y -= self.l * c2;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s3, c3) = th3.sin_cos();
        vx += self.l * c3 * th3_dot;
        vy += self.l * s3 * th3_dot;
        y -= self.l * c3;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s4, c4) = th4.sin_cos();
        vx += self.l * c4 * th4_dot;
        vy += self.l * s4 * th4_dot;
        y -= self.l * c4;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s5, c5) = th5.sin_cos();
        vx += self.l * c5 * th5_dot;
        vy += self.l * s5 * th5_dot;
        y -= self.l * c5;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s6, c6) = th6.sin_cos();
        vx += self.l * c6 * th6_dot;
        vy += self.l * s6 * th6_dot;
        y -= self.l * c6;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s7, c7) = th7.sin_cos();
        vx += self.l * c7 * th7_dot;
        vy += self.l * s7 * th7_dot;
        y -= self.l * c7;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s8, c8) = th8.sin_cos();
        vx += self.l * c8 * th8_dot;
        vy += self.l * s8 * th8_dot;
        y -= self.l * c8;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s9, c9) = th9.sin_cos();
        vx += self.l * c9 * th9_dot;
        vy += self.l * s9 * th9_dot;
        y -= self.l * c9;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s10, c10) = th10.sin_cos();
        vx += self.l * c10 * th10_dot;
        vy += self.l * s10 * th10_dot;
        y -= self.l * c10;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s11, c11) = th11.sin_cos();
        vx += self.l * c11 * th11_dot;
        vy += self.l * s11 * th11_dot;
        y -= self.l * c11;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s12, c12) = th12.sin_cos();
        vx += self.l * c12 * th12_dot;
        vy += self.l * s12 * th12_dot;
        y -= self.l * c12;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s13, c13) = th13.sin_cos();
        vx += self.l * c13 * th13_dot;
        vy += self.l * s13 * th13_dot;
        y -= self.l * c13;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s14, c14) = th14.sin_cos();
        vx += self.l * c14 * th14_dot;
        vy += self.l * s14 * th14_dot;
        y -= self.l * c14;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s15, c15) = th15.sin_cos();
        vx += self.l * c15 * th15_dot;
        vy += self.l * s15 * th15_dot;
        y -= self.l * c15;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        let (s16, c16) = th16.sin_cos();
        vx += self.l * c16 * th16_dot;
        vy += self.l * s16 * th16_dot;
        y -= self.l * c16;
        lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        lag
    }
}
