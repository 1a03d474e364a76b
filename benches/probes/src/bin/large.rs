//! 64-coordinate probes in every Jacobian path, in the three ways to write a system, each on a
//! 2 MiB thread in a child process.
#![allow(clippy::all)]

#[path = "../common.rs"]
mod common;
use common::*;

use lagrange::prelude::*;
use lagrange::sensitivity::{Lyapunov, Shooting};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;

const N: usize = 64;

/// The chain L = Σ ½q̇ᵢ² − ½Σ (q_{i+1} − q_i)² (fixed ends q_{−1} = q_N = 0) + ½ c Σ qᵢ²:
/// K = tridiag(−1, 2 − c, −1), eigenvalues 4 sin²(jπ/(2(N+1))) − c.
#[derive(Clone, Copy)]
pub struct ChainS {
    pub c: f64,
}
#[lagrangian]
impl ChainS {
    fn lagrangian(&self, (q, q_dot): Coords<64>) -> Scalar {
        let mut lag = 0.0;
        for k in 0..q.len() {
            lag += 0.5 * q_dot[k] * q_dot[k] + 0.5 * self.c * q[k] * q[k];
        }
        lag -= 0.5 * q[0] * q[0];
        for (a, b) in q.iter().zip(q.iter().skip(1)) {
            lag -= 0.5 * (*b - *a) * (*b - *a);
        }
        lag -= 0.5 * q[63] * q[63];
        lag
    }
}
#[derive(Clone, Copy)]
pub struct ChainJ {
    pub c: f64,
}
#[lagrangian(mode = "jets")]
impl ChainJ {
    fn lagrangian(&self, (q, q_dot): Coords<64>) -> Scalar {
        let mut lag = 0.0;
        for k in 0..q.len() {
            lag += 0.5 * q_dot[k] * q_dot[k] + 0.5 * self.c * q[k] * q[k];
        }
        lag -= 0.5 * q[0] * q[0];
        for (a, b) in q.iter().zip(q.iter().skip(1)) {
            lag -= 0.5 * (*b - *a) * (*b - *a);
        }
        lag -= 0.5 * q[63] * q[63];
        lag
    }
}
#[derive(Clone, Copy)]
pub struct ChainH {
    pub c: f64,
}
impl Lagrangian<64> for ChainH {
    const COORDINATES: [&'static str; 64] = NAMES;
    const CYCLIC: [bool; 64] = [false; 64];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 64], v: &[S; 64], _t: S) -> S {
        let mut lag = S::constant(0.0);
        for k in 0..64 {
            lag += v[k] * v[k] * 0.5 + q[k] * q[k] * (0.5 * self.c);
        }
        lag -= q[0] * q[0] * 0.5;
        for k in 1..64 {
            let d = q[k] - q[k - 1];
            lag -= d * d * 0.5;
        }
        lag -= q[63] * q[63] * 0.5;
        lag
    }
}
const NAMES: [&str; 64] = [
    "q0", "q1", "q2", "q3", "q4", "q5", "q6", "q7", "q8", "q9", "q10", "q11", "q12", "q13", "q14", "q15", "q16", "q17",
    "q18", "q19", "q20", "q21", "q22", "q23", "q24", "q25", "q26", "q27", "q28", "q29", "q30", "q31", "q32", "q33",
    "q34", "q35", "q36", "q37", "q38", "q39", "q40", "q41", "q42", "q43", "q44", "q45", "q46", "q47", "q48", "q49",
    "q50", "q51", "q52", "q53", "q54", "q55", "q56", "q57", "q58", "q59", "q60", "q61", "q62", "q63",
];

/// 64 uncoupled bodies under gravity, pushed by forces u_i (inputs), two floor contacts (bodies 0, 63).
#[derive(Clone, Copy)]
pub struct Bodies {
    pub u: [f64; 64],
}
impl Lagrangian<64> for Bodies {
    const COORDINATES: [&'static str; 64] = NAMES;
    const CYCLIC: [bool; 64] = [false; 64];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 64], v: &[S; 64], _t: S) -> S {
        let mut lag = S::constant(0.0);
        for k in 0..64 {
            lag += v[k] * v[k] * 0.5 - q[k] * 9.81;
        }
        lag
    }
    fn generalized_forces<S: Scalar>(&self, _q: &[S; 64], _v: &[S; 64], _t: S) -> [S; 64] {
        core::array::from_fn(|i| S::constant(self.u[i]))
    }
}
impl Unilateral<64, 2> for Bodies {
    const SCLERONOMIC: bool = true;
    fn contacts<S: Scalar>(&self, q: &[S; 64], _t: S) -> [Contact<S>; 2] {
        [Contact::gap(q[0]).restitution(0.5).named("floor 0"), Contact::gap(q[63]).restitution(0.5).named("floor 63")]
    }
}

fn kmat(c: f64) -> DMatrix<f64> {
    DMatrix::from_fn(N, N, |i, j| if i == j { 2.0 - c } else if i + 1 == j || j + 1 == i { -1.0 } else { 0.0 })
}
fn omegas() -> Vec<f64> {
    (1..=N).map(|j| 2.0 * (j as f64 * PI / (2.0 * (N as f64 + 1.0))).sin()).collect()
}
fn bent() -> [f64; 64] {
    core::array::from_fn(|i| 0.05 * (1.0 + (i as f64 * 0.37).sin()))
}
fn vel0() -> [f64; 64] {
    core::array::from_fn(|i| 0.02 * (i as f64 * 0.91).cos())
}
/// Exact x(t) of the c = 0 chain.
fn exact(t: f64, q0: &[f64; 64], v0: &[f64; 64]) -> (Vec<f64>, Vec<f64>) {
    let eig = nalgebra::SymmetricEigen::new(kmat(0.0));
    let v = &eig.eigenvectors;
    let a = v.transpose() * DVector::from_column_slice(q0);
    let b = v.transpose() * DVector::from_column_slice(v0);
    let mut cq = DVector::zeros(N);
    let mut cv = DVector::zeros(N);
    for j in 0..N {
        let w = eig.eigenvalues[j].sqrt();
        cq[j] = a[j] * (w * t).cos() + b[j] * (w * t).sin() / w;
        cv[j] = -a[j] * w * (w * t).sin() + b[j] * (w * t).cos();
    }
    ((v * cq).iter().copied().collect(), (v * cv).iter().copied().collect())
}
fn maxdiff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

// ---- linearize / eigenvalues / equilibrium / modes ----
fn lin<L: Lagrangian<64>>(sys: &L) -> R {
    let lin = match sys.linearize(&[0.0; 64], &[0.0; 64], 0.0) {
        Ok(l) => l,
        Err(e) => return r("linearization", format!("Err: {e}"), false),
    };
    match lin.eigenvalues() {
        Err(e) => r("eigenvalues", format!("Err: {e}"), false),
        Ok(l) => {
            let mut im: Vec<f64> = l.iter().filter(|z| z.im > 0.0).map(|z| z.im).collect();
            im.sort_by(f64::total_cmp);
            let re = l.iter().map(|z| z.re.abs()).fold(0.0, f64::max);
            let w = omegas();
            let err = if im.len() == 64 { maxdiff(&im, &w) } else { f64::INFINITY };
            r("128 eigenvalues ±i·2 sin(jπ/130)", format!("{} with Im>0, max |Δω| {err:.1e}, max |Re| {re:.1e}", im.len()), err < 1e-9 && re < 1e-9)
        }
    }
}
fn lin_s() -> R { lin(&ChainS { c: 0.0 }) }
fn lin_j() -> R { lin(&ChainJ { c: 0.0 }) }
fn lin_h() -> R { lin(&ChainH { c: 0.0 }) }
fn eq<L: Lagrangian<64>>(sys: &L) -> R {
    match lagrange::linearize::equilibrium(sys, &bent(), 0.0) {
        Err(e) => r("q = 0", format!("Err: {e}"), false),
        Ok(q) => {
            let m = q.iter().map(|x| x.abs()).fold(0.0, f64::max);
            r("q = 0", format!("max |q| {m:.1e}"), m < 1e-10)
        }
    }
}
fn eq_s() -> R { eq(&ChainS { c: 0.0 }) }
fn eq_j() -> R { eq(&ChainJ { c: 0.0 }) }
fn eq_h() -> R { eq(&ChainH { c: 0.0 }) }
fn modes_s() -> R {
    let lin = match (ChainS { c: 0.0 }).linearize(&[0.0; 64], &[0.0; 64], 0.0) {
        Ok(l) => l,
        Err(e) => return r("modes", format!("Err: {e}"), false),
    };
    match lin.modes() {
        Err(e) => r("ω² = 4 sin²", format!("Err: {e}"), false),
        Ok(m) => {
            let mut w2: Vec<f64> = m.iter().map(|m| m.omega_squared).collect();
            w2.sort_by(f64::total_cmp);
            let want: Vec<f64> = omegas().iter().map(|w| w * w).collect();
            let err = maxdiff(&w2, &want);
            r("ω²_j = 4 sin²(jπ/130)", format!("{} modes, max err {err:.1e}", w2.len()), err < 1e-10 && w2.len() == 64)
        }
    }
}
/// Unstable chain c = 5: stability() says unstable; eigenvalues ±√(5 − ω²).
fn unstable_s() -> R {
    let lin = match (ChainS { c: 5.0 }).linearize(&[0.0; 64], &[0.0; 64], 0.0) {
        Ok(l) => l,
        Err(e) => return r("unstable", format!("Err: {e}"), false),
    };
    match (lin.stability(), lin.eigenvalues()) {
        (Ok(s), Ok(l)) => {
            let mut re: Vec<f64> = l.iter().filter(|z| z.re > 0.0).map(|z| z.re).collect();
            re.sort_by(f64::total_cmp);
            let mut want: Vec<f64> = omegas().iter().map(|w| (5.0 - w * w).sqrt()).collect();
            want.sort_by(f64::total_cmp);
            let err = if re.len() == 64 { maxdiff(&re, &want) } else { f64::INFINITY };
            r("unstable, Re λ = √(5 − ω_j²)", format!("{s}; {} positive, err {err:.1e}", re.len()), err < 1e-9 && format!("{s}").contains("unstable"))
        }
        (a, b) => r("unstable", format!("{:?} {:?}", a.err().map(|e| e.to_string()), b.err().map(|e| e.to_string())), false),
    }
}

// ---- sensitivities: Φ x0 = x(t) (linear flow), ΦᵀJΦ = J, x(t) exact ----
fn sens<L: Lagrangian<64>>(sys: &L, method: Method) -> R {
    let (q0, v0) = (bent(), vel0());
    let t = 1.0;
    let run = match Simulation::new(sys, q0, v0).method(method).until(t).sensitivity().run() {
        Ok(r) => r,
        Err(e) => return r("Φ", format!("Err: {e}"), false),
    };
    let phi = run.final_phi();
    let x0 = DVector::from_iterator(128, q0.iter().chain(v0.iter()).copied());
    let px = phi * &x0;
    let (qe, ve) = exact(t, &q0, &v0);
    let xe: Vec<f64> = qe.iter().chain(ve.iter()).copied().collect();
    let tr = &run.trajectory;
    let xt: Vec<f64> = tr.q.last().unwrap().iter().chain(tr.qdot.last().unwrap().iter()).copied().collect();
    let e1 = maxdiff(px.as_slice(), &xe);
    let e2 = maxdiff(&xt, &xe);
    let mut j = DMatrix::zeros(128, 128);
    for i in 0..64 {
        j[(i, 64 + i)] = 1.0;
        j[(64 + i, i)] = -1.0;
    }
    let e3 = (phi.transpose() * &j * phi - &j).amax();
    let tol = if matches!(method, Method::Rk4 { .. }) { 1e-6 } else { 1e-8 };
    r(format!("Φx0 = x(t) = exact, ΦᵀJΦ = J (tol {tol:e})"), format!("|Φx0 − exact| {e1:.1e}, |x − exact| {e2:.1e}, |ΦᵀJΦ − J| {e3:.1e}"), e1 < tol && e2 < tol && e3 < tol)
}
fn sens_s() -> R { sens(&ChainS { c: 0.0 }, Method::Dop853 { rtol: 1e-11, atol: 1e-12 }) }
fn sens_j() -> R { sens(&ChainJ { c: 0.0 }, Method::Dop853 { rtol: 1e-11, atol: 1e-12 }) }
fn sens_h() -> R { sens(&ChainH { c: 0.0 }, Method::Dop853 { rtol: 1e-11, atol: 1e-12 }) }
fn sens_taylor_s() -> R { sens(&ChainS { c: 0.0 }, Method::Taylor { tol: 1e-13 }) }
fn sens_rk4_j() -> R { sens(&ChainJ { c: 0.0 }, Method::Rk4 { dt: 1e-2 }) }
fn sens_dp_h() -> R { sens(&ChainH { c: 0.0 }, Method::DormandPrince { rtol: 1e-11, atol: 1e-12 }) }
/// ∂x/∂c at c = 0 (a parameter of a 64-coordinate system): against the difference of two runs.
fn sens_param_s() -> R {
    let (q0, v0) = (bent(), vel0());
    let m = Method::Dop853 { rtol: 1e-12, atol: 1e-13 };
    let run = match Simulation::new(&ChainS { c: 0.0 }, q0, v0).method(m).until(1.0).sensitivity().parameter("c", 0.0, |c| ChainS { c }).run() {
        Ok(r) => r,
        Err(e) => return r("∂x/∂c", format!("Err: {e}"), false),
    };
    let s = run.dparams.last().unwrap();
    let end = |c: f64| {
        let tr = Simulation::new(&ChainS { c }, q0, v0).method(m).until(1.0).run().unwrap();
        tr.q.last().unwrap().to_vec()
    };
    let h = 1e-4;
    let (a, b) = (end(h), end(-h));
    let fd: Vec<f64> = a.iter().zip(&b).map(|(a, b)| (a - b) / (2.0 * h)).collect();
    let got: Vec<f64> = (0..64).map(|i| s[(i, 0)]).collect();
    let e = maxdiff(&got, &fd);
    let size = fd.iter().map(|x| x.abs()).fold(0.0, f64::max);
    r("∂q/∂c against central differences (rel 1e-6)", format!("max diff {e:.1e} of {size:.1e}"), e < 1e-6 * size)
}

// ---- Radau5, variational, Taylor runs ----
fn radau<L: Lagrangian<64>>(sys: &L) -> R {
    let (q0, v0) = (bent(), vel0());
    match Simulation::new(sys, q0, v0).method(Method::Radau5 { rtol: 1e-10, atol: 1e-12 }).until(2.0).run() {
        Err(e) => r("x(2) exact to 1e-6", format!("Err: {e}"), false),
        Ok(tr) => {
            let (qe, _) = exact(2.0, &q0, &v0);
            let e = maxdiff(tr.q.last().unwrap(), &qe);
            r("x(2) exact to 1e-6", format!("max err {e:.1e}, steps {}", tr.stats), e < 1e-6)
        }
    }
}
fn radau_s() -> R { radau(&ChainS { c: 0.0 }) }
fn radau_j() -> R { radau(&ChainJ { c: 0.0 }) }
fn radau_h() -> R { radau(&ChainH { c: 0.0 }) }
fn var_j() -> R {
    match Simulation::new(&ChainJ { c: 0.0 }, bent(), vel0()).method(Method::VariationalMidpoint { dt: 1e-2 }).until(2.0).run() {
        Err(e) => r("energy drift < 1e-3", format!("Err: {e}"), false),
        Ok(tr) => {
            let d = tr.invariants().energy.map(|d| d.max_rel).unwrap_or(f64::NAN);
            let (qe, _) = exact(2.0, &bent(), &vel0());
            let e = maxdiff(tr.q.last().unwrap(), &qe);
            r("energy drift < 1e-3, x(2) to 1e-3", format!("drift {d:.1e}, err {e:.1e}"), d < 1e-3 && e < 1e-3)
        }
    }
}
fn var_h() -> R {
    match Simulation::new(&ChainH { c: 0.0 }, bent(), vel0()).method(Method::VariationalMidpoint { dt: 1e-2 }).until(2.0).run() {
        Err(e) => r("energy drift < 1e-3", format!("Err: {e}"), false),
        Ok(tr) => {
            let d = tr.invariants().energy.map(|d| d.max_rel).unwrap_or(f64::NAN);
            r("energy drift < 1e-3", format!("drift {d:.1e}"), d < 1e-3)
        }
    }
}
fn taylor_s() -> R {
    match Simulation::new(&ChainS { c: 0.0 }, bent(), vel0()).method(Method::Taylor { tol: 1e-14 }).until(2.0).run() {
        Err(e) => r("x(2) exact to 1e-10 or a typed refusal naming Taylor", format!("Err: {e}"), e.to_string().contains("Taylor")),
        Ok(tr) => {
            let (qe, _) = exact(2.0, &bent(), &vel0());
            let e = maxdiff(tr.q.last().unwrap(), &qe);
            r("x(2) exact to 1e-10", format!("max err {e:.1e}"), e < 1e-10)
        }
    }
}
fn dop_j() -> R {
    match Simulation::new(&ChainJ { c: 0.0 }, bent(), vel0()).method(Method::Dop853 { rtol: 1e-12, atol: 1e-13 }).until(2.0).run() {
        Err(e) => r("x(2) exact to 1e-10", format!("Err: {e}"), false),
        Ok(tr) => {
            let (qe, _) = exact(2.0, &bent(), &vel0());
            let e = maxdiff(tr.q.last().unwrap(), &qe);
            r("x(2) exact to 1e-10", format!("max err {e:.1e}"), e < 1e-10)
        }
    }
}

// ---- Lyapunov ----
fn lyap1<L: Lagrangian<64>>(sys: &L) -> R {
    let want = (5.0 - omegas()[0].powi(2)).sqrt();
    match Lyapunov::new(sys, [0.0; 64], [0.0; 64]).duration(100.0).directions(1).tolerances(1e-9, 1e-9).compute() {
        Err(e) => r(format!("λ1 = {want:.5}"), format!("Err: {e}"), false),
        Ok(s) => r(format!("λ1 = {want:.5} (±0.02)"), format!("{:?}", s.exponents), (s.exponents[0] - want).abs() < 0.02),
    }
}
fn lyap1_s() -> R { lyap1(&ChainS { c: 5.0 }) }
/// Shorter (the compiled Jacobian costs ~9 s per unit time here): λ1 within 0.15 over 10.
fn lyap1_s_short() -> R {
    let want = (5.0 - omegas()[0].powi(2)).sqrt();
    match Lyapunov::new(&ChainS { c: 5.0 }, [0.0; 64], [0.0; 64]).duration(10.0).directions(1).tolerances(1e-8, 1e-8).compute() {
        Err(e) => r(format!("λ1 ≈ {want:.4} (±0.15)"), format!("Err: {e}"), false),
        Ok(s) => r(format!("λ1 ≈ {want:.4} (±0.15, T = 10)"), format!("{:?}", s.exponents), (s.exponents[0] - want).abs() < 0.15),
    }
}
fn lyap1_j() -> R { lyap1(&ChainJ { c: 5.0 }) }
fn lyap1_h() -> R { lyap1(&ChainH { c: 5.0 }) }
/// The whole spectrum of the inverted chain over T = 2.
///
/// Expectation corrected (it also asked for ± pairs λ_i = −λ_{129−i} to 1e-6): the exponents
/// of the linear flow are ±μ_j, μ_j = √(5 − ω_j²), but a QR run over a finite T returns
/// finite-time exponents, which are not paired (only the singular values of the symplectic
/// Φ(T) are; see y_henon in probes.rs). What holds at any T: 128 of them, sum 0 (tr A = 0),
/// sorted, and each |λ_i| ≤ (1/T) ln ‖Φ(T)‖ ≤ μ_max + ln(μ_max + 1/μ_max)/T (the modes are
/// orthogonal; a 2×2 block's e^{AT} has norm at most e^{μT}(μ + 1/μ)).
fn lyap_full_s() -> R {
    let t = 2.0;
    let mu = (5.0 - omegas()[0].powi(2)).sqrt();
    let bound = mu + (mu + 1.0 / mu).ln() / t;
    match Lyapunov::new(&ChainS { c: 5.0 }, [0.0; 64], [0.0; 64]).duration(t).renormalize_every(0.5).tolerances(1e-9, 1e-9).compute() {
        Err(e) => r("128 exponents, sum 0, sorted", format!("Err: {e}"), false),
        Ok(s) => {
            let e = &s.exponents;
            let pairs = (0..64).map(|i| (e[i] + e[127 - i]).abs()).fold(0.0, f64::max);
            let sorted = e.windows(2).all(|w| w[0] >= w[1]);
            let within = e.iter().all(|x| x.abs() <= bound);
            r(
                format!("128 exponents, sum 0 (1e-6), sorted, all |λ| ≤ {bound:.4}"),
                format!("len {}, sum {:.1e}, sorted {sorted}, within {within}, λ1 {:.4}, λ128 {:.4} (pair err {pairs:.1e}: finite T)", e.len(), s.sum(), e[0], e[e.len() - 1]),
                e.len() == 128 && s.sum().abs() < 1e-6 && sorted && within,
            )
        }
    }
}

// ---- shooting: the highest mode ----
fn shoot_s() -> R {
    let w = omegas()[63];
    let want = 2.0 * PI / w;
    let shape: Vec<f64> = (0..64).map(|i| (64.0 * (i as f64 + 1.0) * PI / 65.0).sin()).collect();
    let imax = (0..64).max_by(|&a, &b| shape[a].abs().total_cmp(&shape[b].abs())).unwrap();
    let q0: [f64; 64] = core::array::from_fn(|i| 0.1 * shape[i] / shape[imax]);
    match Shooting::autonomous(&ChainS { c: 0.0 }, q0, [0.0; 64], 1.01 * want).method(Method::Dop853 { rtol: 1e-11, atol: 1e-12 }).tolerance(1e-8).pin_amplitude(imax).find() {
        Err(e) => r(format!("T = {want:.10}"), format!("Err: {}", e.to_string().chars().take(300).collect::<String>()), false),
        Ok(o) => r(format!("T = {want:.10}"), format!("T = {:.10}, its {}, {}", o.period, o.iterations, o.stability), (o.period - want).abs() < 1e-7),
    }
}
fn shoot_j() -> R {
    let w = omegas()[63];
    let want = 2.0 * PI / w;
    let shape: Vec<f64> = (0..64).map(|i| (64.0 * (i as f64 + 1.0) * PI / 65.0).sin()).collect();
    let imax = (0..64).max_by(|&a, &b| shape[a].abs().total_cmp(&shape[b].abs())).unwrap();
    let q0: [f64; 64] = core::array::from_fn(|i| 0.1 * shape[i] / shape[imax]);
    match Shooting::autonomous(&ChainJ { c: 0.0 }, q0, [0.0; 64], 1.01 * want).method(Method::Dop853 { rtol: 1e-11, atol: 1e-12 }).tolerance(1e-8).pin_energy(ChainJ { c: 0.0 }.energy(&q0, &[0.0; 64], 0.0)).max_iterations(10).find() {
        Err(e) => r(format!("T = {want:.10}"), format!("Err: {}", e.to_string().chars().take(300).collect::<String>()), false),
        Ok(o) => r(format!("T = {want:.10} (pin_energy: the family of this energy has many orbits; T of any must be a period)"), format!("T = {:.10}, its {}", o.period, o.iterations), true),
    }
}

// ---- state space with 64 inputs ----
fn ss_h() -> R {
    let r0 = lagrange::linearize::state_space(|u: &[f64; 64]| Bodies { u: *u }, &[0.5; 64], &[1.0; 64], &[0.0; 64], 0.0);
    match r0 {
        Err(e) => r("A = [0 I; 0 0], B = [0; I]", format!("Err: {e}"), false),
        Ok((a, b)) => {
            let mut wa = DMatrix::zeros(128, 128);
            for i in 0..64 {
                wa[(i, 64 + i)] = 1.0;
            }
            let mut wb = DMatrix::zeros(128, 64);
            for i in 0..64 {
                wb[(64 + i, i)] = 1.0;
            }
            let ea = (&a - &wa).amax();
            let eb = (&b - &wb).amax();
            r("A = [0 I; 0 0], B = [0; I]", format!("|ΔA| {ea:.1e} |ΔB| {eb:.1e}"), ea < 1e-12 && eb < 1e-9)
        }
    }
}
// ---- ensemble of Radau5 in jets mode ----
fn ens_j() -> R {
    use lagrange::ensemble::{Ensemble, Member};
    let res = Ensemble::new(2, |i| {
        let mut q0 = bent();
        q0[0] += 0.01 * i as f64;
        Member::new(ChainJ { c: 0.0 }, q0, vel0())
    })
    .configure(|s| s.method(Method::Radau5 { rtol: 1e-10, atol: 1e-12 }).until(1.0))
    .threads(2)
    .run();
    let mut got = vec![];
    let mut ok = true;
    for (i, tr) in res.results.iter().enumerate() {
        match tr {
            Err(e) => {
                ok = false;
                got.push(format!("member {i}: Err {e}"))
            }
            Ok(tr) => {
                let mut q0 = bent();
                q0[0] += 0.01 * i as f64;
                let (qe, _) = exact(1.0, &q0, &vel0());
                let e = maxdiff(tr.q.last().unwrap(), &qe);
                ok &= e < 1e-6;
                got.push(format!("member {i}: err {e:.1e}"))
            }
        }
    }
    r("each member exact to 1e-6", got.join("; "), ok)
}
// ---- contacts with 64 coordinates ----
fn contact64() -> R {
    let mut q0 = [3.0; 64];
    q0[0] = 1.0;
    q0[63] = 0.5;
    let sys = Bodies { u: [0.0; 64] };
    let t0 = (2.0f64 / 9.81).sqrt();
    let t63 = (1.0f64 / 9.81).sqrt();
    // Body 63: next impact 2·(e·g t63)/g = t63 later.
    let want = vec![t63, t0, 2.0 * t63];
    match Simulation::contacts(&sys, q0, [0.0; 64]).method(Method::Dop853 { rtol: 1e-12, atol: 1e-13 }).until(0.7).run() {
        Err(e) => r(format!("jumps {}", fmt(&want)), format!("Err: {e}"), false),
        Ok(tr) => {
            let j: Vec<f64> = tr.jumps.iter().map(|j| j.t).collect();
            let ok = j.len() == 3 && maxdiff(&j, &want) < 1e-9;
            r(format!("jumps {}", fmt(&want)), format!("jumps {}", fmt(&j)), ok)
        }
    }
}
fn fmt(v: &[f64]) -> String {
    format!("{:?}", v.iter().map(|x| format!("{x:.9}")).collect::<Vec<_>>())
}
// ---- a resetting event on 64 coordinates with Radau5 and with sensitivities refused ----
fn reset64_radau() -> R {
    let sys = Bodies { u: [0.0; 64] };
    let mut q0 = [3.0; 64];
    q0[5] = 1.0;
    let t1 = (2.0f64 / 9.81).sqrt();
    let ev = Event::zero_crossing("floor", |_t, q: &[f64; 64], _v| q[5]).falling().reset(|_t, q, v| {
        let mut v = *v;
        v[5] = -0.5 * v[5];
        (*q, v)
    });
    // Lagrangian-only run (no contacts) with the reset event.
    struct Plain(Bodies);
    impl Lagrangian<64> for Plain {
        const COORDINATES: [&'static str; 64] = NAMES;
        const CYCLIC: [bool; 64] = [false; 64];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 64], v: &[S; 64], t: S) -> S {
            self.0.lagrangian(q, v, t)
        }
    }
    let p = Plain(sys);
    match Simulation::new(&p, q0, [0.0; 64]).method(Method::Radau5 { rtol: 1e-11, atol: 1e-12 }).event(ev).until(1.0).run() {
        Err(e) => r("jumps at t1, 2 t1", format!("Err: {e}"), false),
        Ok(tr) => {
            let j: Vec<f64> = tr.jumps.iter().map(|j| j.t).collect();
            let want = vec![t1, 2.0 * t1];
            r(format!("jumps {}", fmt(&want)), format!("jumps {}", fmt(&j)), j.len() == 2 && maxdiff(&j, &want) < 1e-8)
        }
    }
}

fn main() {
    macro_rules! p {
        ($c:expr, $f:ident, $w:expr) => {
            Probe { class: $c, name: stringify!($f), what: $w, f: $f }
        };
    }
    main_with(vec![
        p!("1-large", lin_s, "linearize+eigenvalues, symbolic 64"),
        p!("1-large", lin_j, "linearize+eigenvalues, jets 64"),
        p!("1-large", lin_h, "linearize+eigenvalues, hand-written 64"),
        p!("1-large", eq_s, "equilibrium, symbolic 64"),
        p!("1-large", eq_j, "equilibrium, jets 64"),
        p!("1-large", eq_h, "equilibrium, hand-written 64"),
        p!("1-large", modes_s, "modes(), symbolic 64"),
        p!("1-large", unstable_s, "stability of the inverted chain, symbolic 64"),
        p!("1-large", sens_s, "sensitivity Φ Dop853, symbolic 64"),
        p!("1-large", sens_j, "sensitivity Φ Dop853, jets 64"),
        p!("1-large", sens_h, "sensitivity Φ Dop853, hand-written 64"),
        p!("1-large", sens_taylor_s, "sensitivity Φ Taylor, symbolic 64"),
        p!("1-large", sens_rk4_j, "sensitivity Φ Rk4, jets 64"),
        p!("1-large", sens_dp_h, "sensitivity Φ DormandPrince, hand-written 64"),
        p!("1-large", sens_param_s, "parameter sensitivity, symbolic 64"),
        p!("1-large", radau_s, "Radau5, symbolic 64"),
        p!("1-large", radau_j, "Radau5, jets 64"),
        p!("1-large", radau_h, "Radau5, hand-written 64"),
        p!("1-large", var_j, "VariationalMidpoint, jets 64"),
        p!("1-large", var_h, "VariationalMidpoint, hand-written 64"),
        p!("1-large", taylor_s, "Taylor run, symbolic 64"),
        p!("1-large", dop_j, "Dop853 run, jets 64"),
        p!("1-large", lyap1_s, "Lyapunov λ1, symbolic 64"),
        p!("1-large", lyap1_s_short, "Lyapunov λ1 over 10, symbolic 64"),
        p!("1-large", lyap1_j, "Lyapunov λ1, jets 64"),
        p!("1-large", lyap1_h, "Lyapunov λ1, hand-written 64"),
        p!("1-large", lyap_full_s, "Lyapunov full 128 spectrum, symbolic 64"),
        p!("1-large", shoot_s, "shooting highest mode pin_amplitude, symbolic 64"),
        p!("1-large", shoot_j, "shooting highest mode pin_energy, jets 64"),
        p!("1-large", ss_h, "state_space with 64 inputs"),
        p!("1-large", ens_j, "Ensemble Radau5 jets 64, 2 threads"),
        p!("1-large", contact64, "contacts on 64 coordinates"),
        p!("1-large", reset64_radau, "resetting event on 64 coordinates, Radau5"),
    ]);
}
