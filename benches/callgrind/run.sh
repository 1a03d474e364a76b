#!/usr/bin/env bash
# Instruction counts (valgrind's callgrind) of the heavy top's kernels, this tree against a base
# revision, in one run: q̈ ×10⁶, one DOP853 run, one Taylor run, 64 members on DOP853 and on the
# Taylor method in 4 SIMD lanes, exact and on the CPU's default path (BENCHMARKS.md, "One body
# for every kernel, before and after").
# Instruction counts do not move with the machine's load, where a 2 % timing would; each line also
# says whether both binaries printed the same numbers (bit for bit).
#
#   bash benches/callgrind/run.sh f096717
set -euo pipefail
base="${1:?usage: run.sh BASE_REVISION}"
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="${CALLGRIND_DIR:-${TMPDIR:-/tmp}/lagrange-callgrind}"
rm -rf "$work" && mkdir -p "$work"
git -C "$root" worktree add -f "$work/base-tree" "$base" >/dev/null 2>&1
trap 'git -C "$root" worktree remove --force "$work/base-tree" >/dev/null 2>&1 || true' EXIT
for side in base this; do
    path="$root"; [ "$side" = base ] && path="$work/base-tree"
    mkdir -p "$work/$side/src"
    cat > "$work/$side/Cargo.toml" <<TOML
[package]
name = "kernels"
version = "0.0.0"
edition = "2021"
publish = false
[dependencies]
lagrange = { path = "$path" }
[profile.release]
debug = false
[workspace]
TOML
    cat > "$work/$side/src/main.rs" <<'RS'
use lagrange::ensemble::{Ensemble, Member};
use lagrange::prelude::*;
use std::hint::black_box;

#[derive(Debug, Clone, Copy)]
pub struct HeavyTop { pub i_perp: f64, pub i_par: f64, pub m: f64, pub g: f64, pub l: f64 }

#[lagrangian]
impl HeavyTop {
    fn lagrangian(&self, (theta, theta_dot): Coord, (phi, phi_dot): Coord, (psi, psi_dot): Coord) -> Scalar {
        let (s, c) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
            - self.m * self.g * self.l * c
    }
}

fn main() {
    let top = HeavyTop { i_perp: 1.0, i_par: 0.6, m: 1.0, g: 9.81, l: 0.5 };
    let mode = std::env::args().nth(1).unwrap_or_default();
    match mode.as_str() {
        "acc" => {
            let (mut s, mut q) = (0.0, [1.0, 0.0, 0.0]);
            for i in 0..1_000_000 {
                q[0] = 0.5 + 1e-7 * i as f64;
                let a = black_box(&top).accelerations(black_box(&q), black_box(&[0.1, -0.5, 8.0]), 0.0).unwrap();
                s += a[0] + a[1] + a[2];
            }
            println!("{s:e}");
        }
        "dop" | "taylor" => {
            let m = if mode == "dop" { Method::Dop853 { rtol: 1e-12, atol: 1e-12 } } else { Method::Taylor { tol: 1e-14 } };
            let tr = Simulation::new(&top, [1.0, 0.0, 0.0], [0.1, -0.5, 8.0]).method(m).until(200.0).sample_every(1.0).run().unwrap();
            let l = tr.q.last().unwrap();
            println!("{:e} {:e} {:e} {}", l[0], l[1], l[2], tr.stats.steps);
        }
        _ => {
            let method = if mode == "ens_taylor" { Method::Taylor { tol: 1e-12 } } else { Method::Dop853 { rtol: 1e-10, atol: 1e-10 } };
            let r = Ensemble::new(64, |i| Member::new(HeavyTop { l: 0.5 + 0.001 * i as f64, ..top }, [1.0, 0.0, 0.0], [0.1, -0.5, 8.0]))
                .configure(|s| s.method(method).until(30.0).sample_at([0.0; 0]))
                .threads(1)
                .run();
            let x: f64 = r.results.iter().map(|t| t.as_ref().unwrap().q.last().unwrap()[0]).sum();
            println!("{x:e}");
        }
    }
}
RS
    (cd "$work/$side" && cargo build --release -q)
done
count() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 | sed -n 's/.*refs: *//p' | tr -d ','; }
printf '| kernel | %s | this tree | change | same numbers |\n|---|---|---|---|---|\n' "$base"
# The ensembles twice: on the exact lanes (LAGRANGE_SIMD=exact: the numbers of the single runs,
# so of a base without fused lanes) and on the default path this CPU resolves (fused multiply-adds
# where it has FMA: the same numbers to round-off only).
for run in acc dop taylor ens_dop853:exact ens_taylor:exact ens_dop853:native ens_taylor:native; do
    mode="${run%%:*}"; simd="${run#*:}"; [ "$simd" = "$run" ] && simd=native
    b=$(LAGRANGE_SIMD=$simd count "$work/base/target/release/kernels" "$mode")
    t=$(LAGRANGE_SIMD=$simd count "$work/this/target/release/kernels" "$mode")
    same=no
    [ "$(LAGRANGE_SIMD=$simd "$work/base/target/release/kernels" "$mode")" = "$(LAGRANGE_SIMD=$simd "$work/this/target/release/kernels" "$mode")" ] && same=yes
    printf '| %s | %s | %s | %+.2f %% | %s |\n' "$run" "$b" "$t" "$(echo "($t - $b) * 100 / $b" | bc -l)" "$same"
done
