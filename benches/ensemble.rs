//! Ensembles: 1024 heavy tops with random parameters and initial states (I⊥ ∈ [0.8, 1.2],
//! I∥ ∈ [0.4, 0.6], m g l ∈ [4, 6], θ0 ∈ [0.5, 0.9], φ̇0 ∈ [1.5, 2.5], ψ̇0 ∈ [10, 14]; seeded),
//! each to t = 114.3, on the ensemble API: DOP853 (rtol 1e-10, 1e-11) and the Taylor method (tol
//! 1e-10, 1e-12, 1e-13) one member at a time and on every lanes path the CPU has (`Simd`: AVX2
//! lanes exact, AVX2 lanes with FMA; DOP853 4 members per pass, Taylor 8), on one thread and on
//! two, and, as the reference for two threads on this machine, the two halves of the tops as two
//! one-thread ensembles side by side (final
//! errors near 1e-10 and 1e-11, the matched accuracies); and — in the same run, when python3
//! with heyoka is installed — heyoka's batch mode at its fastest batch size on this machine
//! (`benches/peers/heyoka_batch.py` times 1, 2, 4, 8 and 16 tops per vector and reports the
//! fastest) at tol 1e-10, 1e-11, 1e-12, 1e-13 and 1e-14 (the last so that our Taylor rows at tol
//! 1e-13 have heyoka tolerances on both sides of their error), with
//! the hand-written right-hand side and with the equations heyoka derives from the Lagrangian.
//! Every final θ is compared with a reference run of the same top (our Taylor method at tol
//! 2e-17, not timed); the time per top is the best of five passes (`PASSES=n`: n), interleaved over the
//! configurations. Each member records its initial and final states only (`sample_every(T_END)`),
//! as heyoka's `propagate_until` returns the final state only. Last, floors under our DOP853 lanes
//! at the evaluations DOP853 takes at rtol 1e-11 (the generated vector right-hand side alone, one
//! vector in flight and two; whole DOP853-shaped steps without step control), against heyoka at
//! the same error.
//!
//! Run: `cargo bench --bench ensemble` (`-- --ours`: our rows only, without the floors and the
//! peer)

use lagrange::ensemble::Simd;
use lagrange::prelude::*;
use std::io::Write;
use std::process::{Command, Stdio};
use std::time::Instant;

use lagrange_examples::bench_top::MacroTop as Top;

// DOP853's tableau, for the floor measured with DOP853-shaped steps.
use lagrange::integrate::dop853_coefficients::{A, C};
use lagrange::lanes::Lanes;

const T_END: f64 = 114.3;
const TOPS: usize = 1024;
/// Rounds over the configurations (the best time of each is reported); the environment variable
/// `PASSES` sets another number (more on a machine whose load moves).
fn passes() -> usize {
    std::env::var("PASSES")
        .ok()
        .and_then(|p| p.parse().ok())
        .filter(|&p| p >= 1)
        .unwrap_or(5)
}

/// The tops: (parameters, θ0, φ̇0, ψ̇0), from a fixed xorshift sequence.
fn tops() -> Vec<(Top, f64, f64, f64)> {
    let mut s: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut u = |lo: f64, hi: f64| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
    };
    (0..TOPS)
        .map(|_| {
            let top = Top {
                i_perp: u(0.8, 1.2),
                i_par: u(0.4, 0.6),
                mgl: u(4.0, 6.0),
            };
            (top, u(0.5, 0.9), u(1.5, 2.5), u(10.0, 14.0))
        })
        .collect()
}

/// Final θ of every top with `method` on `threads` threads, and the best wall time of `passes`.
fn sweep(
    tops: &[(Top, f64, f64, f64)],
    method: Method,
    simd: Simd,
    threads: usize,
    passes: usize,
) -> (Vec<f64>, f64) {
    let mut best = f64::INFINITY;
    let mut theta = Vec::new();
    for _ in 0..passes {
        let t0 = Instant::now();
        let r = Ensemble::new(tops.len(), |i| {
            let (top, th, ph_d, ps_d) = tops[i];
            Member::new(top, [th, 0.0, 0.0], [0.0, ph_d, ps_d])
        })
        .configure(move |sim| {
            sim.method(method)
                .until(T_END)
                .sample_every(T_END)
                .keep_samples(false)
        })
        .threads(threads)
        .lanes(if simd == Simd::Off { 1 } else { 4 })
        .simd(simd)
        .reduce(&["theta"], |tr| tr.q[tr.q.len() - 1][0]);
        best = best.min(t0.elapsed().as_secs_f64());
        theta = r
            .results
            .into_iter()
            .map(|x| x.expect("every top integrates"))
            .collect();
    }
    (theta, best)
}

/// Wall time of the tops' two halves run at once as two one-thread ensembles, each in its own
/// thread: what this machine's two cores give two independent jobs, the reference a two-thread
/// ensemble is measured against (a shared machine's cores slow down now and then under load).
fn halves(tops: &[(Top, f64, f64, f64)], method: Method, simd: Simd) -> f64 {
    let (a, b) = tops.split_at(tops.len() / 2);
    let t0 = Instant::now();
    std::thread::scope(|s| {
        let other = s.spawn(|| sweep(a, method, simd, 1, 1));
        sweep(b, method, simd, 1, 1);
        other.join().expect("the other half runs");
    });
    t0.elapsed().as_secs_f64()
}

fn errors(theta: &[f64], reference: &[f64]) -> (f64, f64) {
    let mut e: Vec<f64> = theta
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b).abs())
        .collect();
    e.sort_by(f64::total_cmp);
    (e[e.len() / 2], e[e.len() - 1])
}

/// Floors under the DOP853 lanes engine, in ns per member per evaluation of the top's generated
/// vector right-hand side on AVX2 (as the engine runs it): `[one, two, steps]` = the right-hand
/// side alone with one 4-lane vector in flight (each evaluation's input waiting for the last one's
/// output, as DOP853's stages do), with two independent 4-lane vectors interleaved, and whole
/// DOP853-shaped steps in 4 lanes (the stage sums of the tableau and y₁, no error norm, no step
/// control, no bookkeeping). `None` without AVX2.
fn floors_ns(tops: &[(Top, f64, f64, f64)]) -> Option<[f64; 3]> {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: these functions only need AVX2, which the CPU has (checked just above).
        #[allow(unsafe_code)]
        return Some(unsafe {
            [
                rhs_chains_avx2::<1>(tops),
                rhs_chains_avx2::<2>(tops),
                dop853_steps_avx2(tops),
            ]
        });
    }
    let _ = tops;
    None
}

/// The members, the lanes kernel's parameters (loaded at its first call) and initial (q, q̇)
/// of 4 tops.
type Group<'t> = ([&'t Top; 4], Vec<Lanes<4>>, [[Lanes<4>; 3]; 2]);

/// q̈ of 4 tops by the generated kernel at width 4 (NaN if the system had none).
#[inline(always)]
fn rhs(
    members: &[&Top; 4],
    params: &mut Vec<Lanes<4>>,
    q: &[Lanes<4>; 3],
    qdot: &[Lanes<4>; 3],
    t: Lanes<4>,
) -> [Lanes<4>; 3] {
    Top::accelerations_in(members, params, q, qdot, t).map_or([Lanes::NAN; 3], |(x, _)| x)
}

/// The 4-lane inputs of the tops `chunk[0..4]`.
fn group(chunk: &[(Top, f64, f64, f64)]) -> Group<'_> {
    let members: [&Top; 4] = core::array::from_fn(|l| &chunk[l].0);
    let params = Vec::new();
    let y = [
        [
            Lanes(core::array::from_fn(|l| chunk[l].1)),
            Lanes::ZERO,
            Lanes::ZERO,
        ],
        [
            Lanes::ZERO,
            Lanes(core::array::from_fn(|l| chunk[l].2)),
            Lanes(core::array::from_fn(|l| chunk[l].3)),
        ],
    ];
    (members, params, y)
}

/// See [`floors_ns`]: C chains of dependent evaluations interleaved, 4 lanes each; the best of
/// five passes over the tops.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn rhs_chains_avx2<const C: usize>(tops: &[(Top, f64, f64, f64)]) -> f64 {
    const EVALS: usize = 20_000;
    let mut best = f64::INFINITY;
    let mut sum = 0.0;
    let chunks: Vec<&[(Top, f64, f64, f64)]> = tops.chunks_exact(4 * C).collect();
    for _ in 0..passes() {
        let t0 = Instant::now();
        for chunk in &chunks {
            let mut groups: [Group<'_>; C] = core::array::from_fn(|c| group(&chunk[4 * c..]));
            let mut y: [[[Lanes<4>; 3]; 2]; C] = core::array::from_fn(|c| groups[c].2);
            for _ in 0..EVALS {
                for c in 0..C {
                    let (members, params, _) = &mut groups[c];
                    let a = rhs(members, params, &y[c][0], &y[c][1], Lanes::ZERO);
                    for i in 0..3 {
                        y[c][1][i] += a[i] * 1e-9;
                    }
                    y[c][0][0] += y[c][1][0] * 1e-9;
                }
            }
            sum += std::hint::black_box(y[0][0][0].0[0]);
        }
        best = best.min(t0.elapsed().as_secs_f64());
    }
    std::hint::black_box(sum);
    best * 1e9 / ((chunks.len() * 4 * C) as f64 * EVALS as f64)
}

/// ys = y + h Σ_j a_j k_j over the stages `k[..S]` (the tableau's zeros skipped at compile time).
#[inline(always)]
fn stage_sum<const S: usize>(
    y: &[[Lanes<4>; 3]; 2],
    h: Lanes<4>,
    a: &[f64; 16],
    k: &[[[Lanes<4>; 3]; 2]; 13],
) -> [[Lanes<4>; 3]; 2] {
    let mut acc = [[Lanes::<4>::ZERO; 3]; 2];
    for j in 0..S {
        if a[j] != 0.0 {
            for r in 0..2 {
                for i in 0..3 {
                    acc[r][i] += k[j][r][i] * a[j];
                }
            }
        }
    }
    let mut out = *y;
    for r in 0..2 {
        for i in 0..3 {
            out[r][i] += h * acc[r][i];
        }
    }
    out
}

/// See [`floors_ns`]: DOP853 steps of a fixed h (12 evaluations each, FSAL apart) in 4 lanes, the
/// cyclic coordinates' stage positions held as the engine holds them; the best of five passes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn dop853_steps_avx2(tops: &[(Top, f64, f64, f64)]) -> f64 {
    const STEPS: usize = 2_000;
    let mut best = f64::INFINITY;
    let mut sum = 0.0;
    let h = Lanes::<4>::splat(0.02);
    for _ in 0..passes() {
        let t0 = Instant::now();
        for chunk in tops.chunks_exact(4) {
            let (members, mut params, mut y) = group(chunk);
            let mut k = [[[Lanes::<4>::ZERO; 3]; 2]; 13];
            for _ in 0..STEPS {
                let a0 = rhs(&members, &mut params, &y[0], &y[1], Lanes::ZERO);
                k[0] = [y[1], a0];
                macro_rules! stages {
                    ($($s:literal)*) => {$(
                        let mut ys = stage_sum::<$s>(&y, h, &A[$s], &k);
                        ys[0][1] = y[0][1];
                        ys[0][2] = y[0][2];
                        let a = rhs(&members, &mut params, &ys[0], &ys[1], h * C[$s]);
                        k[$s] = [ys[1], a];
                    )*};
                }
                stages!(1 2 3 4 5 6 7 8 9 10 11);
                y = stage_sum::<12>(&y, h, &A[12], &k);
            }
            sum += std::hint::black_box(y[0][0].0[0]);
        }
        best = best.min(t0.elapsed().as_secs_f64());
    }
    std::hint::black_box(sum);
    best * 1e9 / ((tops.len() / 4 * 4) as f64 * (STEPS * 12) as f64)
}

fn main() {
    let tops = tops();
    if !std::env::args().any(|a| a == "--bench") {
        // `cargo test --benches`: a smoke run of a few members.
        let (theta, _) = sweep(
            &tops[..4],
            Method::Dop853 {
                rtol: 1e-8,
                atol: 1e-10,
            },
            Simd::Native,
            2,
            1,
        );
        assert_eq!(theta.len(), 4);
        return;
    }
    // The most accurate run the time resolution at t = 114.3 allows (the run refuses tol < 1.3e-17).
    let (reference, _) = sweep(&tops, Method::Taylor { tol: 2e-17 }, Simd::Off, 2, 1);
    println!("{TOPS} heavy tops to t = {T_END}; final θ error against Taylor at tol 2e-17 (median, max); best of {} interleaved passes", passes());
    let mut one_thread = Vec::new();
    let dop853 = Method::Dop853 {
        rtol: 1e-10,
        atol: 1e-12,
    };
    let dop853_11 = Method::Dop853 {
        rtol: 1e-11,
        atol: 1e-13,
    };
    // Every lanes path this CPU has (the exact AVX2 lanes, AVX2 with FMA), each method
    // at each accuracy, in one run.
    let paths: Vec<(Simd, &str)> = [
        (Simd::Exact, "lanes AVX2 exact"),
        (Simd::Avx2Fma, "lanes AVX2+FMA"),
    ]
    .into_iter()
    .filter(|(p, _)| p.resolved() == *p)
    .collect();
    let mut configs: Vec<(String, Method, Simd)> = Vec::new();
    for (name, method) in [
        ("our DOP853 rtol 1e-10", dop853),
        ("our DOP853 rtol 1e-11", dop853_11),
        ("our Taylor tol 1e-10", Method::Taylor { tol: 1e-10 }),
        ("our Taylor tol 1e-12", Method::Taylor { tol: 1e-12 }),
        ("our Taylor tol 1e-13", Method::Taylor { tol: 1e-13 }),
    ] {
        if name.contains("1e-10") || name.contains("Taylor tol 1e-13") {
            configs.push((format!("{name}, one member at a time"), method, Simd::Off));
        }
        for (simd, what) in &paths {
            configs.push((format!("{name}, {what}"), method, *simd));
        }
    }
    // Rounds over every configuration, the best of each kept: on a shared machine the load
    // moves over seconds, and interleaving gives every configuration the same chances.
    let mut best = vec![[f64::INFINITY; 3]; configs.len()];
    let mut theta = vec![Vec::new(); configs.len()];
    for _ in 0..passes() {
        for (c, &(_, method, simd)) in configs.iter().enumerate() {
            for (k, threads) in [1, 2].into_iter().enumerate() {
                let (th, t) = sweep(&tops, method, simd, threads, 1);
                best[c][k] = best[c][k].min(t);
                theta[c] = th;
            }
            best[c][2] = best[c][2].min(halves(&tops, method, simd));
        }
    }
    for (c, (name, _, _)) in configs.iter().enumerate() {
        let [t1, t2, pair] = best[c];
        let (med, max) = errors(&theta[c], &reference);
        println!(
            "{name}: one thread {:.4} ms per top, two threads {:.4} ms per top ({:.2}x; two one-thread halves side by side {:.2}x); θ error median {med:.1e}, max {max:.1e}",
            t1 / TOPS as f64 * 1e3,
            t2 / TOPS as f64 * 1e3,
            t1 / t2,
            t1 / pair
        );
        one_thread.push((name.clone(), t1 / TOPS as f64 * 1e3, med));
    }
    if std::env::args().any(|a| a == "--ours") {
        // `cargo bench --bench ensemble -- --ours`: our rows only (no floors, no peer).
        return;
    }
    // What the vector arithmetic alone costs at the evaluations DOP853 takes at rtol 1e-11:
    // floors under our DOP853 lanes at that accuracy, however cheap the step control.
    let evals = Ensemble::new(tops.len(), |i| {
        let (top, th, ph_d, ps_d) = tops[i];
        Member::new(top, [th, 0.0, 0.0], [0.0, ph_d, ps_d])
    })
    .configure(move |sim| sim.method(dop853_11).until(T_END).sample_every(T_END))
    .reduce(&["evals"], |tr| tr.stats.rhs_evals as f64);
    let evals = evals.results.iter().flatten().sum::<f64>() / TOPS as f64;
    if let Some([one, two, steps]) = floors_ns(&tops) {
        let ms = |ns: f64| ns * evals * 1e-6;
        println!(
            "floors at the {evals:.0} evaluations per top DOP853 takes at rtol 1e-11, per member per evaluation of the vector right-hand side (4 AVX2 lanes): alone, one vector in flight {one:.2} ns ({:.4} ms per top); alone, two vectors interleaved {two:.2} ns ({:.4} ms); DOP853-shaped steps (stage sums, no step control) {steps:.2} ns ({:.4} ms)",
            ms(one),
            ms(two),
            ms(steps)
        );
        let err = one_thread
            .iter()
            .find(|r| r.0 == "our DOP853 rtol 1e-11, lanes AVX2 exact")
            .map_or(f64::NAN, |r| r.2);
        for (name, ns) in [
            (
                "floor: the right-hand sides alone, one vector in flight",
                one,
            ),
            (
                "floor: the right-hand sides alone, two vectors interleaved",
                two,
            ),
            ("floor: DOP853-shaped steps without step control", steps),
        ] {
            one_thread.push((name.to_string(), ms(ns), err));
        }
    }
    let input: String = tops
        .iter()
        .map(|(t, th, ph_d, ps_d)| {
            format!(
                "{:?} {:?} {:?} {th:?} {ph_d:?} {ps_d:?}\n",
                t.i_perp, t.i_par, t.mgl
            )
        })
        .collect();
    // heyoka with the hand-written right-hand side (the target's peer), then with the equations
    // it derives itself from the same Lagrangian (heyoka.lagrangian: what we do).
    let runs = ["hand", "lagrangian"]
        .into_iter()
        .flat_map(|path| ["1e-10", "1e-11", "1e-12", "1e-13", "1e-14"].map(|tol| (path, tol)));
    let mut peer: Vec<(&str, f64, f64)> = Vec::new();
    for (path, tol) in runs {
        let child = Command::new("python3")
            .arg(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/peers/heyoka_batch.py"
            ))
            .arg(tol)
            .arg(passes().to_string())
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn();
        let Ok(mut child) = child else {
            println!("heyoka batch peer not run: no python3");
            return;
        };
        if let Some(mut stdin) = child.stdin.take() {
            let _ = stdin.write_all(input.as_bytes());
        }
        let Ok(out) = child.wait_with_output() else {
            return;
        };
        if !out.status.success() {
            println!(
                "heyoka batch peer not run ({}): python3 -m pip install heyoka",
                String::from_utf8_lossy(&out.stderr)
                    .lines()
                    .last()
                    .unwrap_or("?")
            );
            return;
        }
        let text = String::from_utf8_lossy(&out.stdout);
        let mut lines = text.lines();
        let summary = lines.next().unwrap_or("").to_string();
        let theta: Vec<f64> = lines.filter_map(|l| l.trim().parse().ok()).collect();
        let per_top: Option<f64> = summary
            .split(" ms per top")
            .next()
            .and_then(|s| s.rsplit(' ').next())
            .and_then(|s| s.parse().ok());
        if theta.len() == TOPS {
            let (med, max) = errors(&theta, &reference);
            println!("{summary}; θ error median {med:.1e}, max {max:.1e}");
            if let Some(h) = per_top {
                peer.push((path, h, med));
            }
        } else {
            println!("{summary}");
        }
        if let Some(h) = per_top {
            for (name, ours, _) in &one_thread {
                println!(
                    "  {name}, one thread / heyoka fastest batch {path} tol {tol}: {:.2}",
                    ours / h
                );
            }
        }
    }
    // The target's measure: our time against heyoka's at our final error, heyoka's time
    // interpolated log-log between the two tolerances whose median errors bracket ours.
    println!("at matched final θ error (median), heyoka's time interpolated log-log between its tolerances:");
    for path in ["hand", "lagrangian"] {
        let mut pts: Vec<(f64, f64)> = peer
            .iter()
            .filter(|p| p.0 == path)
            .map(|p| (p.2, p.1))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (name, ours, err) in &one_thread {
            let Some(w) = pts.windows(2).find(|w| w[0].0 <= *err && *err <= w[1].0) else {
                continue;
            };
            let ((e0, t0), (e1, t1)) = (w[0], w[1]);
            let x = (err / e0).ln() / (e1 / e0).ln();
            let h = t0 * (t1 / t0).powf(x);
            println!(
                "  {name} (error {err:.1e}): {ours:.4} ms vs heyoka fastest batch {path} {h:.4} ms: {:.2}",
                ours / h
            );
        }
    }
}
