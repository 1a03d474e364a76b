//! Jet designs for the Euler–Lagrange right-hand side, against hand-written closed forms measured
//! in the same run. `cargo bench --bench jets` (results and conclusions in BENCHMARKS.md).
//!
//! - heavy top (N = 3): (a) closed form, (b) `Lagrangian::accelerations` with `ElJet` (flags),
//!   (c1) the same packed jet without structural flags, (c2) nested first-order duals
//!   (N + 1 passes: one vector dual for ∂L/∂q, then per coordinate i a dual over a vector dual
//!   giving row i of M and the mixed term);
//! - 3×3 mass-matrix solve: `linalg::solve_symmetric` vs nalgebra's Cholesky and LU;
//! - planar pendulum chains N = 4 and 8: closed form vs `accelerations`.
//!
//! The alternative designs implement a small bench-local number trait [`Num`]; the Lagrangians are
//! written once over it (and once over `Scalar`, the same arithmetic) so every design evaluates
//! the same formula.
#![allow(missing_docs)]
// index loops mirror the jet code in runtime/src/jet/el.rs (same shapes, same formulas)
#![allow(clippy::needless_range_loop)]

use std::hint::black_box;
use std::ops::{Add, Mul, Sub};

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::linalg::solve_symmetric;
use lagrange::prelude::*;

// ---------------------------------------------------------------------------------------------
// Systems
// ---------------------------------------------------------------------------------------------

/// Heavy symmetric top, eq. 92 of the reference text (Euler angles θ, φ, ψ).
struct HeavyTop {
    i_perp: f64,
    i_par: f64,
    mgl: f64,
}

impl HeavyTop {
    fn l<S: Num>(&self, q: &[S], qd: &[S]) -> S {
        let (s, c) = q[0].sin_cos();
        let w3 = qd[2] + qd[1] * c;
        (qd[0] * qd[0] + qd[1] * qd[1] * s * s) * (self.i_perp / 2.0) + w3 * w3 * (self.i_par / 2.0)
            - c * self.mgl
    }

    /// Hand-derived: I⊥θ̈ = I⊥φ̇²sc − I∥ω₃φ̇s + mgl s; φ̈ = θ̇(I∥ω₃ − 2I⊥φ̇c)/(I⊥s); ψ̈ = φ̇θ̇s − φ̈c.
    #[inline(never)]
    fn closed_form(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 3] {
        let (s, c) = q[0].sin_cos();
        let (th_d, ph_d, ps_d) = (qd[0], qd[1], qd[2]);
        let w3 = ps_d + ph_d * c;
        let th_dd = ph_d * ph_d * s * c - self.i_par / self.i_perp * w3 * ph_d * s
            + self.mgl / self.i_perp * s;
        let ph_dd = th_d * (self.i_par * w3 - 2.0 * self.i_perp * ph_d * c) / (self.i_perp * s);
        let ps_dd = ph_d * th_d * s - ph_dd * c;
        [th_dd, ph_dd, ps_dd]
    }
}

impl Lagrangian<3> for HeavyTop {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], qd: &[S; 3], _t: S) -> S {
        let (s, c) = q[0].sin_cos();
        let w3 = qd[2] + qd[1] * c;
        (qd[0] * qd[0] + qd[1] * qd[1] * s * s) * (self.i_perp / 2.0) + w3 * w3 * (self.i_par / 2.0)
            - c * self.mgl
    }
}

/// Planar chain of N equal pendulums (mass m, length l) hanging from a fixed pivot; θ_j from the
/// downward vertical.
struct Chain<const N: usize> {
    m: f64,
    l: f64,
    g: f64,
}

impl<const N: usize> Chain<N> {
    fn l_generic<S: Scalar>(&self, q: &[S; N], qd: &[S; N]) -> S {
        let zero = S::constant(0.0);
        let (mut vx, mut vy, mut y, mut t, mut v) = (zero, zero, zero, zero, zero);
        for j in 0..N {
            let (s, c) = q[j].sin_cos();
            vx += c * qd[j] * self.l;
            vy += s * qd[j] * self.l;
            y -= c * self.l;
            t += vx * vx + vy * vy;
            v += y;
        }
        t * (self.m / 2.0) - v * (self.m * self.g)
    }

    /// Hand-derived: Σ_j m l² c_ij [cos(θi−θj) θ̈_j + sin(θi−θj) θ̇_j²] + m g l (N−i) sin θ_i = 0,
    /// c_ij = N − max(i, j), solved with the same LDLᵀ.
    #[inline(never)]
    fn closed_form(&self, q: &[f64; N], qd: &[f64; N]) -> [f64; N] {
        let ml2 = self.m * self.l * self.l;
        let mut sc = [(0.0, 0.0); N];
        for j in 0..N {
            sc[j] = q[j].sin_cos();
        }
        let mut m = [[0.0; N]; N];
        let mut rhs = [0.0; N];
        for i in 0..N {
            let (si, ci) = sc[i];
            let mut f = -self.m * self.g * self.l * (N - i) as f64 * si;
            for j in 0..N {
                let (sj, cj) = sc[j];
                let cij = ml2 * (N - i.max(j)) as f64;
                if j >= i {
                    m[i][j] = cij * (ci * cj + si * sj);
                }
                f -= cij * (si * cj - ci * sj) * qd[j] * qd[j];
            }
            rhs[i] = f;
        }
        solve_symmetric(&m, &rhs).unwrap_or([f64::NAN; N])
    }
}

impl<const N: usize> Lagrangian<N> for Chain<N> {
    const COORDINATES: [&'static str; N] = ["theta"; N];
    const CYCLIC: [bool; N] = [false; N];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; N], qd: &[S; N], _t: S) -> S {
        self.l_generic(q, qd)
    }
}

// ---------------------------------------------------------------------------------------------
// The bench-local number trait and the alternative designs
// ---------------------------------------------------------------------------------------------

pub trait Num:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Mul<f64, Output = Self>
{
    fn sin_cos(self) -> (Self, Self);
}

/// (c1) The packed second-order jet of `ElJet`, without structural flags: every operation updates
/// every block.
#[derive(Clone, Copy)]
pub struct Packed<const N: usize> {
    v: f64,
    gq: [f64; N],
    gv: [f64; N],
    gd: f64,
    hvv: [[f64; N]; N],
    hvd: [f64; N],
}

impl<const N: usize> Packed<N> {
    const ZERO: Self = Packed {
        v: 0.0,
        gq: [0.0; N],
        gv: [0.0; N],
        gd: 0.0,
        hvv: [[0.0; N]; N],
        hvd: [0.0; N],
    };
    #[inline(always)]
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let a = &self;
        let mut r = Self::ZERO;
        r.v = f0;
        for j in 0..N {
            r.gq[j] = f1 * a.gq[j];
            r.gv[j] = f1 * a.gv[j];
            r.hvd[j] = f1 * a.hvd[j] + f2 * a.gv[j] * a.gd;
        }
        r.gd = f1 * a.gd;
        for i in 0..N {
            for k in i..N {
                r.hvv[i][k] = f1 * a.hvv[i][k] + f2 * a.gv[i] * a.gv[k];
            }
        }
        r
    }
}
impl<const N: usize> Add for Packed<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let a = &self;
        let mut r = Self::ZERO;
        r.v = a.v + b.v;
        r.gd = a.gd + b.gd;
        for i in 0..N {
            r.gq[i] = a.gq[i] + b.gq[i];
            r.gv[i] = a.gv[i] + b.gv[i];
            r.hvd[i] = a.hvd[i] + b.hvd[i];
            for k in i..N {
                r.hvv[i][k] = a.hvv[i][k] + b.hvv[i][k];
            }
        }
        r
    }
}
impl<const N: usize> Sub for Packed<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        self + b * -1.0
    }
}
impl<const N: usize> Mul<f64> for Packed<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(mut self, c: f64) -> Self {
        self.v *= c;
        self.gd *= c;
        for i in 0..N {
            self.gq[i] *= c;
            self.gv[i] *= c;
            self.hvd[i] *= c;
            for k in i..N {
                self.hvv[i][k] *= c;
            }
        }
        self
    }
}
impl<const N: usize> Mul for Packed<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = &self;
        let mut r = Self::ZERO;
        r.v = a.v * b.v;
        r.gd = a.v * b.gd + b.v * a.gd;
        for i in 0..N {
            r.gq[i] = a.v * b.gq[i] + b.v * a.gq[i];
            r.gv[i] = a.v * b.gv[i] + b.v * a.gv[i];
            r.hvd[i] = a.v * b.hvd[i] + b.v * a.hvd[i] + a.gv[i] * b.gd + b.gv[i] * a.gd;
            for k in i..N {
                r.hvv[i][k] =
                    a.v * b.hvv[i][k] + b.v * a.hvv[i][k] + a.gv[i] * b.gv[k] + a.gv[k] * b.gv[i];
            }
        }
        r
    }
}
impl<const N: usize> Num for Packed<N> {
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.v.sin_cos();
        (self.chain(s, c, -s), self.chain(c, -s, -c))
    }
}

#[inline(always)]
fn packed_accelerations(top: &HeavyTop, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 3] {
    let mut qj = [Packed::<3>::ZERO; 3];
    let mut vj = [Packed::<3>::ZERO; 3];
    for i in 0..3 {
        qj[i].v = q[i];
        qj[i].gq[i] = 1.0;
        qj[i].gd = qd[i];
        vj[i].v = qd[i];
        vj[i].gv[i] = 1.0;
    }
    let l = top.l(&qj, &vj);
    let mut rhs = [0.0; 3];
    for i in 0..3 {
        rhs[i] = l.gq[i] - l.hvd[i];
    }
    solve_symmetric(&l.hvv, &rhs).unwrap_or([f64::NAN; 3])
}

/// A first-order dual with K directions.
#[derive(Clone, Copy)]
pub struct DVec<const K: usize> {
    v: f64,
    d: [f64; K],
}
impl<const K: usize> Add for DVec<K> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, b: Self) -> Self {
        self.v += b.v;
        for k in 0..K {
            self.d[k] += b.d[k];
        }
        self
    }
}
impl<const K: usize> Sub for DVec<K> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, b: Self) -> Self {
        self.v -= b.v;
        for k in 0..K {
            self.d[k] -= b.d[k];
        }
        self
    }
}
impl<const K: usize> Mul for DVec<K> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let mut d = [0.0; K];
        for k in 0..K {
            d[k] = self.v * b.d[k] + b.v * self.d[k];
        }
        DVec { v: self.v * b.v, d }
    }
}
impl<const K: usize> Mul<f64> for DVec<K> {
    type Output = Self;
    #[inline(always)]
    fn mul(mut self, c: f64) -> Self {
        self.v *= c;
        for k in 0..K {
            self.d[k] *= c;
        }
        self
    }
}
impl<const K: usize> Num for DVec<K> {
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.v.sin_cos();
        let (mut ds, mut dc) = ([0.0; K], [0.0; K]);
        for k in 0..K {
            ds[k] = c * self.d[k];
            dc[k] = -s * self.d[k];
        }
        (DVec { v: s, d: ds }, DVec { v: c, d: dc })
    }
}

/// A first-order dual a + bε over another number type (for nesting).
#[derive(Clone, Copy)]
pub struct Dual<T> {
    a: T,
    b: T,
}
impl<T: Num> Add for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Dual {
            a: self.a + o.a,
            b: self.b + o.b,
        }
    }
}
impl<T: Num> Sub for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Dual {
            a: self.a - o.a,
            b: self.b - o.b,
        }
    }
}
impl<T: Num> Mul for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Dual {
            a: self.a * o.a,
            b: self.a * o.b + self.b * o.a,
        }
    }
}
impl<T: Num> Mul<f64> for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        Dual {
            a: self.a * c,
            b: self.b * c,
        }
    }
}
impl<T: Num> Num for Dual<T> {
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.a.sin_cos();
        (
            Dual {
                a: s,
                b: self.b * c,
            },
            Dual {
                a: c,
                b: self.b * s * -1.0,
            },
        )
    }
}

/// (c2) Nested duals, N + 1 passes: pass 0 a `DVec<N>` for ∂L/∂q; pass i a `Dual<DVec<N+1>>`
/// whose ε seeds q̇_i and whose inner directions are q̇_0..q̇_{N-1} and (q̇, 0, 1), giving row i of
/// M and the mixed term.
#[inline(always)]
fn nested_accelerations<const N: usize, const K: usize>(
    l: impl Fn(&[Dual<DVec<K>>; N], &[Dual<DVec<K>>; N]) -> Dual<DVec<K>>,
    l1: impl Fn(&[DVec<N>; N], &[DVec<N>; N]) -> DVec<N>,
    q: &[f64; N],
    qd: &[f64; N],
) -> [f64; N] {
    debug_assert_eq!(K, N + 1);
    let zero_n = DVec {
        v: 0.0,
        d: [0.0; N],
    };
    let mut q1 = [zero_n; N];
    let mut v1 = [zero_n; N];
    for j in 0..N {
        q1[j].v = q[j];
        q1[j].d[j] = 1.0;
        v1[j].v = qd[j];
    }
    let gq = l1(&q1, &v1).d;
    let zero = DVec {
        v: 0.0,
        d: [0.0; K],
    };
    let mut m = [[0.0; N]; N];
    let mut rhs = [0.0; N];
    for i in 0..N {
        let mut qj = [Dual { a: zero, b: zero }; N];
        let mut vj = [Dual { a: zero, b: zero }; N];
        for j in 0..N {
            qj[j].a.v = q[j];
            qj[j].a.d[N] = qd[j];
            vj[j].a.v = qd[j];
            vj[j].a.d[j] = 1.0;
        }
        vj[i].b.v = 1.0;
        let r = l(&qj, &vj);
        for k in i..N {
            m[i][k] = r.b.d[k];
        }
        rhs[i] = gq[i] - r.b.d[N];
    }
    solve_symmetric(&m, &rhs).unwrap_or([f64::NAN; N])
}

impl Num for f64 {
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        f64::sin_cos(self)
    }
}

// ---------------------------------------------------------------------------------------------
// Benchmarks
// ---------------------------------------------------------------------------------------------

/// A fixed set of generic states (θ away from 0 and π), cycled through so nothing constant-folds.
fn top_states() -> Vec<([f64; 3], [f64; 3])> {
    (0..16)
        .map(|k| {
            let x = k as f64;
            (
                [0.3 + 0.15 * x, 0.2 * x - 1.0, 0.7 - 0.1 * x],
                [0.5 - 0.07 * x, 1.1 + 0.05 * x, 12.0 - 0.4 * x],
            )
        })
        .collect()
}

fn chain_states<const N: usize>() -> Vec<([f64; N], [f64; N])> {
    (0..16)
        .map(|k| {
            let x = k as f64;
            let mut q = [0.0; N];
            let mut v = [0.0; N];
            for j in 0..N {
                let y = j as f64;
                q[j] = (0.4 * x + 0.9 * y).sin() * 1.2;
                v[j] = (0.3 * x - 0.5 * y).cos() * 0.8;
            }
            (q, v)
        })
        .collect()
}

fn check_close<const N: usize>(what: &str, a: &[f64; N], b: &[f64; N]) {
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for i in 0..N {
        assert!(
            (a[i] - b[i]).abs() <= 1e-11 * scale,
            "{what}: {a:?} vs {b:?}"
        );
    }
}

fn heavy_top(c: &mut Criterion) {
    let top = HeavyTop {
        i_perp: 1.3,
        i_par: 0.7,
        mgl: 2.1,
    };
    let states = top_states();
    let nested = |q: &[f64; 3], qd: &[f64; 3]| {
        nested_accelerations::<3, 4>(|q, v| top.l(q, v), |q, v| top.l(q, v), q, qd)
    };
    // all designs agree before anything is timed
    for (q, qd) in &states {
        let want = top.closed_form(q, qd);
        check_close("ElJet", &top.accelerations(q, qd, 0.0).unwrap(), &want);
        check_close("packed", &packed_accelerations(&top, q, qd), &want);
        check_close("nested", &nested(q, qd), &want);
    }
    let mut g = c.benchmark_group("heavy_top");
    g.bench_function("a_closed_form", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (q, qd) in &states {
                acc += top.closed_form(black_box(q), black_box(qd))[1];
            }
            acc
        })
    });
    g.bench_function("b_eljet_flags", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (q, qd) in &states {
                acc += top
                    .accelerations(black_box(q), black_box(qd), 0.0)
                    .map_or(0.0, |a| a[1]);
            }
            acc
        })
    });
    g.bench_function("c1_packed_no_flags", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (q, qd) in &states {
                acc += packed_accelerations(&top, black_box(q), black_box(qd))[1];
            }
            acc
        })
    });
    g.bench_function("c2_nested_duals", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (q, qd) in &states {
                acc += nested(black_box(q), black_box(qd))[1];
            }
            acc
        })
    });
    g.finish();
}

fn solve_3x3(c: &mut Criterion) {
    let top = HeavyTop {
        i_perp: 1.3,
        i_par: 0.7,
        mgl: 2.1,
    };
    let systems: Vec<([[f64; 3]; 3], [f64; 3])> = top_states()
        .iter()
        .map(|(q, qd)| {
            let m = top.mass_matrix(q, qd, 0.0);
            let mut up = [[0.0; 3]; 3];
            for i in 0..3 {
                for k in i..3 {
                    up[i][k] = m[(i, k)];
                }
            }
            (up, [1.0, -0.5, 0.25])
        })
        .collect();
    let full = |m: &[[f64; 3]; 3]| nalgebra::Matrix3::from_fn(|i, k| m[i.min(k)][i.max(k)]);
    let mut g = c.benchmark_group("solve_3x3");
    g.bench_function("solve_symmetric", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (m, r) in &systems {
                acc += solve_symmetric(black_box(m), black_box(r)).map_or(0.0, |x| x[0]);
            }
            acc
        })
    });
    g.bench_function("nalgebra_cholesky", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (m, r) in &systems {
                let rhs = nalgebra::Vector3::from(*black_box(r));
                acc += full(black_box(m))
                    .cholesky()
                    .map_or(0.0, |ch| ch.solve(&rhs)[0]);
            }
            acc
        })
    });
    g.bench_function("nalgebra_lu", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (m, r) in &systems {
                let rhs = nalgebra::Vector3::from(*black_box(r));
                acc += full(black_box(m)).lu().solve(&rhs).map_or(0.0, |x| x[0]);
            }
            acc
        })
    });
    g.finish();
}

fn chain_group<const N: usize>(c: &mut Criterion) {
    let chain = Chain::<N> {
        m: 0.7,
        l: 1.1,
        g: 9.81,
    };
    let states = chain_states::<N>();
    for (q, qd) in &states {
        check_close(
            "chain",
            &chain.accelerations(q, qd, 0.0).unwrap(),
            &chain.closed_form(q, qd),
        );
    }
    let mut g = c.benchmark_group(format!("chain{N}"));
    g.bench_function("a_closed_form", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (q, qd) in &states {
                acc += chain.closed_form(black_box(q), black_box(qd))[0];
            }
            acc
        })
    });
    g.bench_function("b_eljet_flags", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (q, qd) in &states {
                acc += chain
                    .accelerations(black_box(q), black_box(qd), 0.0)
                    .map_or(0.0, |a| a[0]);
            }
            acc
        })
    });
    g.finish();
}

fn chains(c: &mut Criterion) {
    chain_group::<4>(c);
    chain_group::<8>(c);
}

criterion_group!(benches, heavy_top, solve_3x3, chains);
criterion_main!(benches);
