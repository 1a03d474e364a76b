#!/usr/bin/env bash
# Instruction counts (valgrind's callgrind) of the heavy top's kernels, this tree against a base
# revision, in one run: q̈ ×10⁶, one run of each method (DOP853, Taylor, Dormand–Prince, RK4,
# Radau5, variational; with dense samples and an event), a constrained pendulum in x, y, z, a
# sensitivity run of each explicit method and the Taylor method, 64 members on DOP853 and on the
# Taylor method in 4 SIMD lanes, exact and on the CPU's default path (BENCHMARKS.md, "One body
# for every kernel, before and after").
# Instruction counts do not move with the machine's load, where a 2 % timing would; each line also
# says whether both binaries printed the same numbers (bit for bit: every sample's bits, the
# events' times and the step counts; for a sensitivity run also Φ's last value).
# CALLGRIND_RUNS="dop pend" limits the runs.
#
#   bash benches/callgrind/run.sh f096717
set -euo pipefail
base="${1:?usage: run.sh BASE_REVISION}"
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="${CALLGRIND_DIR:-${TMPDIR:-/tmp}/lagrange-callgrind}"
# The base's binary is kept between runs against the same revision (it does not change); the
# tree's is rebuilt.
rev="$(git -C "$root" rev-parse --short "$base")"
[ -f "$work/base/rev" ] && [ "$(cat "$work/base/rev")" = "$rev" ] || rm -rf "$work/base"
rm -rf "$work/this" "$work/base-tree" && mkdir -p "$work"
git -C "$root" worktree prune
git -C "$root" worktree add -f "$work/base-tree" "$base" >/dev/null 2>&1
trap 'git -C "$root" worktree remove --force "$work/base-tree" >/dev/null 2>&1 || true' EXIT
for side in base this; do
    [ "$side" = base ] && [ -x "$work/base/target/release/kernels" ] && continue
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

/// A spherical pendulum written in x, y, z with |r| = 1 as a holonomic constraint.
#[derive(Debug, Clone, Copy)]
pub struct Pend { pub g: f64 }

#[lagrangian]
impl Pend {
    fn lagrangian(&self, (_x, x_dot): Coord, (_y, y_dot): Coord, (z, z_dot): Coord) -> Scalar {
        0.5 * (x_dot * x_dot + y_dot * y_dot + z_dot * z_dot) - self.g * z
    }
    fn constraints(&self, (x, _): Coord, (y, _): Coord, (z, _): Coord) -> [Scalar; 1] {
        [x * x + y * y + z * z - 1.0]
    }
}

/// Every sample's bits folded (FNV-1a), the last state, the step counts.
fn digest<const N: usize>(tr: &Trajectory<N>) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for x in tr.t.iter().chain(tr.q.iter().flatten()).chain(tr.qdot.iter().flatten()) {
        h = (h ^ x.to_bits()).wrapping_mul(0x100000001b3);
    }
    for e in &tr.events {
        h = (h ^ e.t.to_bits()).wrapping_mul(0x100000001b3);
    }
    let l = tr.q.last().unwrap();
    format!("{h:016x} {:e} {:e} {} {} {}", l[0], l[N - 1], tr.stats.steps, tr.stats.rejected, tr.stats.rhs_evals)
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
        "dopri5" | "rk4" | "radau5" | "var" | "events" => {
            let m = match mode.as_str() {
                "dopri5" => Method::DormandPrince { rtol: 1e-10, atol: 1e-10 },
                "rk4" => Method::Rk4 { dt: 1e-3 },
                "radau5" => Method::Radau5 { rtol: 1e-8, atol: 1e-10 },
                "var" => Method::VariationalMidpoint { dt: 1e-3 },
                _ => Method::Dop853 { rtol: 1e-12, atol: 1e-12 },
            };
            let tr = Simulation::new(&top, [1.0, 0.0, 0.0], [0.1, -0.5, 8.0])
                .method(m)
                .until(20.0)
                .sample_every(0.01)
                .event(Event::zero_crossing("theta_dot = 0", |_t, _q, v| v[0]))
                .run()
                .unwrap();
            println!("{}", digest(&tr));
        }
        "pend" => {
            let tr = Simulation::new(&Pend { g: 9.81 }, [0.6, 0.0, -0.8], [0.0, 2.0, 0.0])
                .until(20.0)
                .sample_every(0.01)
                .run()
                .unwrap();
            println!("{}", digest(&tr));
        }
        "sens_dop853" | "sens_dopri5" | "sens_rk4" | "sens_taylor" => {
            let m = match mode.as_str() {
                "sens_dopri5" => Method::DormandPrince { rtol: 1e-10, atol: 1e-10 },
                "sens_rk4" => Method::Rk4 { dt: 1e-3 },
                "sens_taylor" => Method::Taylor { tol: 1e-14 },
                _ => Method::Dop853 { rtol: 1e-12, atol: 1e-12 },
            };
            let r = Simulation::new(&top, [1.0, 0.0, 0.0], [0.1, -0.5, 8.0])
                .method(m)
                .until(20.0)
                .sample_every(1.0)
                .sensitivity()
                .run()
                .unwrap();
            let phi = r.phi.last().unwrap();
            // The motion's digest, then Φ's last value (Φ is compared to round-off only).
            println!("{} | phi {:e} {:e}", digest(&r.trajectory), phi[(0, 0)], phi[(0, 3)]);
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
echo "$rev" > "$work/base/rev"
count() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 | sed -n 's/.*refs: *//p' | tr -d ','; }
printf '| kernel | %s | this tree | change | same numbers |\n|---|---|---|---|---|\n' "$base"
# The ensembles twice: on the exact lanes (LAGRANGE_SIMD=exact: the numbers of the single runs,
# so of a base without fused lanes) and on the default path this CPU resolves (fused multiply-adds
# where it has FMA: the same numbers to round-off only).
for run in ${CALLGRIND_RUNS:-acc dop taylor dopri5 rk4 radau5 var events pend sens_dop853 sens_dopri5 sens_rk4 sens_taylor ens_dop853:exact ens_taylor:exact ens_dop853:native ens_taylor:native}; do
    mode="${run%%:*}"; simd="${run#*:}"; [ "$simd" = "$run" ] && simd=native
    b=$(LAGRANGE_SIMD=$simd count "$work/base/target/release/kernels" "$mode")
    t=$(LAGRANGE_SIMD=$simd count "$work/this/target/release/kernels" "$mode")
    same=no
    [ "$(LAGRANGE_SIMD=$simd "$work/base/target/release/kernels" "$mode")" = "$(LAGRANGE_SIMD=$simd "$work/this/target/release/kernels" "$mode")" ] && same=yes
    printf '| %s | %s | %s | %+.2f %% | %s |\n' "$run" "$b" "$t" "$(echo "($t - $b) * 100 / $b" | bc -l)" "$same"
done
