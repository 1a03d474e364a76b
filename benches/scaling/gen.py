#!/usr/bin/env python3
"""Writes an N-link pendulum chain (equal masses and lengths) as a user writes it, with
`Coords<N>` and a loop, into a small crate's src/main.rs, next to a hand-written M + LDLT of the
same chain; the binary prints ns per q-double-dot of both and their ratio (one run).

Used by benches/scaling/run.sh; see BENCHMARKS.md, "Chains of N links".
Usage: gen.py N OUT_DIR
"""
import sys
n = int(sys.argv[1])
out = sys.argv[2]
src=f"""use lagrange::prelude::*;
pub struct Chain {{ pub m: f64, pub l: f64, pub g: f64 }}
#[lagrangian]
impl Chain {{
    fn lagrangian(&self, (q, q_dot): Coords<{n}>) -> Scalar {{
        let (mut vx, mut vy, mut y, mut lag) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..{n} {{
            let (s, c) = q[k].sin_cos();
            vx += self.l * c * q_dot[k];
            vy += self.l * s * q_dot[k];
            y -= self.l * c;
            lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        }}
        lag
    }}
}}
fn hand(c: &Chain, q: &[f64; {n}], v: &[f64; {n}]) -> [f64; {n}] {{
    const N: usize = {n};
    let mut s = [0.0; N];
    let mut co = [0.0; N];
    for i in 0..N {{ let (a, b) = q[i].sin_cos(); s[i] = a; co[i] = b; }}
    let ml2 = c.m * c.l * c.l;
    let mgl = c.m * c.g * c.l;
    let mut a = [[0.0; N]; N];
    let mut f = [0.0; N];
    for i in 0..N {{
        let mut fi = -mgl * (N - i) as f64 * s[i];
        for j in 0..N {{
            let w = ml2 * (N - i.max(j)) as f64;
            a[i][j] = w * (co[i] * co[j] + s[i] * s[j]);
            fi -= w * (s[i] * co[j] - co[i] * s[j]) * v[j] * v[j];
        }}
        f[i] = fi;
    }}
    // LDLᵀ, row by row: w = (L_jk d_k) once per row, then L_ij for the rows below.
    let mut w = [0.0; N];
    for j in 0..N {{
        let (upper, lower) = a.split_at_mut(j);
        let row_j = &mut lower[0];
        let mut d = row_j[j];
        for k in 0..j {{ w[k] = row_j[k] * upper[k][k]; d -= row_j[k] * w[k]; }}
        row_j[j] = d;
        let inv = 1.0 / d;
        for row_i in lower[1..].iter_mut() {{
            let mut x = row_i[j];
            for k in 0..j {{ x -= row_i[k] * w[k]; }}
            row_i[j] = x * inv;
        }}
    }}
    let mut y = f;
    for i in 0..N {{ for k in 0..i {{ y[i] -= a[i][k] * y[k]; }} }}
    for i in 0..N {{ y[i] /= a[i][i]; }}
    for i in (0..N).rev() {{ for k in i + 1..N {{ y[i] -= a[k][i] * y[k]; }} }}
    y
}}
fn main() {{
    let c = Chain {{ m: 1.0, l: 1.0, g: 9.81 }};
    let q: [f64; {n}] = std::array::from_fn(|i| 0.1 * i as f64);
    let v: [f64; {n}] = std::array::from_fn(|i| 0.05 * i as f64);
    let reps = 2_000_000 / ({n} * {n});
    let mut acc = 0.0;
    // Alternating rounds, the fastest of each: the machine's noise is one-sided.
    let (mut macro_ns, mut hand_ns) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..9 {{
        let t = std::time::Instant::now();
        for _ in 0..reps {{ acc += c.accelerations(std::hint::black_box(&q), &v, 0.0).unwrap()[0]; }}
        macro_ns = macro_ns.min(t.elapsed().as_nanos() as f64 / reps as f64);
        let t = std::time::Instant::now();
        for _ in 0..reps {{ acc += hand(&c, std::hint::black_box(&q), &v)[0]; }}
        hand_ns = hand_ns.min(t.elapsed().as_nanos() as f64 / reps as f64);
    }}
    let a = c.accelerations(&q, &v, 0.0).unwrap();
    let b = hand(&c, &q, &v);
    let diff = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    println!("N={n}: macro {{macro_ns:.0}} ns/qdd, hand {{hand_ns:.0}} ns, ratio {{:.2}}, max diff {{diff:.1e}} ({{acc}})", macro_ns / hand_ns);
}}
"""
open(out + "/src/main.rs", "w").write(src)
