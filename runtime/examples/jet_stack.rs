//! How much thread stack the jets' defaults take, for `jet::EL_BY_COLUMNS_ABOVE`: runs one path
//! of a hand-written N-coordinate chain on a thread of the given stack (a stack overflow aborts
//! the process; `benches/scaling/jet_stack.sh` bisects the least stack on which each runs).
//!
//! `cargo run -p lagrange-runtime --example jet_stack --profile test -- PATH N STACK_KIB`, PATH
//! one of `acc` (`accelerations`), `energy`, `whole` (`jet_pieces_whole`, one `ElJet`), `cols`
//! (`jet_pieces_by_columns`, in `with_jet_stack`), `raw` (the same column evaluations without
//! `with_jet_stack`), `time` (µs per call of `cols` and of `whole`).

use lagrange_runtime::jet::ColumnJet;
use lagrange_runtime::lagrangian::{jet_pieces_by_columns, jet_pieces_whole};
use lagrange_runtime::{Lagrangian, Scalar};
use std::hint::black_box;

/// Springs between neighbours and a mass that depends on the position.
#[derive(Clone, Copy)]
struct Chain<const N: usize>;

impl<const N: usize> Lagrangian<N> for Chain<N> {
    const COORDINATES: [&'static str; N] = ["q"; N];
    const CYCLIC: [bool; N] = [false; N];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; N], v: &[S; N], _t: S) -> S {
        let mut l = S::constant(0.0);
        for k in 0..N {
            let d = if k == 0 { q[0] } else { q[k] - q[k - 1] };
            l += v[k] * v[k] * 0.5 - d * d * 0.5 + (q[k] * 0.1).cos() * v[k] * v[k] * 0.01;
        }
        l
    }
}

// Each path in a frame of its own: inlined into one `match`, the frames of all of them add up.
#[inline(never)]
fn acc<const N: usize>(q: &[f64; N], v: &[f64; N]) {
    black_box(Chain::<N>.accelerations(q, v, 0.0).ok());
}
#[inline(never)]
fn energy<const N: usize>(q: &[f64; N], v: &[f64; N]) {
    black_box(Chain::<N>.energy(q, v, 0.0));
}
#[inline(never)]
fn whole<const N: usize>(q: &[f64; N], v: &[f64; N]) {
    black_box(jet_pieces_whole(&Chain::<N>, q, v, 0.0));
}
#[inline(never)]
fn cols<const N: usize>(q: &[f64; N], v: &[f64; N]) {
    black_box(jet_pieces_by_columns(&Chain::<N>, q, v, 0.0));
}
#[inline(never)]
fn raw<const N: usize>(q: &[f64; N], v: &[f64; N]) {
    let mut mass = [[0.0; N]; N];
    let tj = ColumnJet::from(0.0);
    for k in 0..N {
        let (qj, vj) = ColumnJet::seed(q, v, Some(N + k));
        let cv = Chain::<N>.lagrangian(&qj, &vj, tj).column_qdot();
        for (row, c) in mass.iter_mut().zip(cv).take(k + 1) {
            row[k] = c;
        }
    }
    let (qj, vj, tj) = ColumnJet::seed_along(q, v, 0.0, v, 1.0);
    let l = Chain::<N>.lagrangian(&qj, &vj, tj);
    black_box((mass, l.grad_q(), l.column_qdot()));
}
#[inline(never)]
fn time<const N: usize>(q: &[f64; N], v: &[f64; N]) {
    let reps = 20;
    let t0 = std::time::Instant::now();
    for _ in 0..reps {
        black_box(jet_pieces_by_columns(&Chain::<N>, q, v, 0.0));
    }
    let c = t0.elapsed().as_secs_f64() / reps as f64;
    let t0 = std::time::Instant::now();
    for _ in 0..reps {
        black_box(jet_pieces_whole(&Chain::<N>, q, v, 0.0));
    }
    let w = t0.elapsed().as_secs_f64() / reps as f64;
    println!(
        "N = {N}: by columns {:.1} µs, whole {:.1} µs",
        c * 1e6,
        w * 1e6
    );
}

#[inline(never)]
fn run<const N: usize>(path: &str) {
    let q: [f64; N] = core::array::from_fn(|i| 0.01 * i as f64);
    let v: [f64; N] = core::array::from_fn(|i| 0.02 * i as f64);
    match path {
        "acc" => acc(&q, &v),
        "energy" => energy(&q, &v),
        "whole" => whole(&q, &v),
        "cols" => cols(&q, &v),
        "raw" => raw(&q, &v),
        "time" => time(&q, &v),
        _ => eprintln!("PATH: acc, energy, whole, cols, raw or time"),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(path), Some(Ok(n)), Some(Ok(kib))) = (
        args.get(1).cloned(),
        args.get(2).map(|a| a.parse::<usize>()),
        args.get(3).map(|a| a.parse::<usize>()),
    ) else {
        eprintln!("usage: jet_stack PATH N STACK_KIB");
        std::process::exit(2);
    };
    let spawned = std::thread::Builder::new()
        .stack_size(kib << 10)
        .spawn(move || match n {
            8 => run::<8>(&path),
            16 => run::<16>(&path),
            17 => run::<17>(&path),
            20 => run::<20>(&path),
            24 => run::<24>(&path),
            32 => run::<32>(&path),
            48 => run::<48>(&path),
            64 => run::<64>(&path),
            _ => eprintln!("N: 8, 16, 17, 20, 24, 32, 48 or 64"),
        });
    if !matches!(spawned.map(|h| h.join()), Ok(Ok(()))) {
        std::process::exit(1);
    }
}
