#!/usr/bin/env bash
# The build time, peak memory and q̈ speed of an N-link chain written with `Coords<N>` and a
# loop, against a hand-written M + LDLᵀ of the same chain (BENCHMARKS.md, "Chains of N links").
# Each N: a release build of the user crate with its dependencies already built (only the user
# file touched), timed with /usr/bin/time; then the binary, twice (ratios within one run).
#
#   bash benches/scaling/run.sh            # N = 4 8 16 32 64
#   bash benches/scaling/run.sh 16 24      # chosen N
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
work="${SCALING_DIR:-${TMPDIR:-/tmp}/lagrange-scaling}"
mkdir -p "$work/src"
cat > "$work/Cargo.toml" <<TOML
[package]
name = "chain_n"
version = "0.0.0"
edition = "2021"
publish = false
[dependencies]
lagrange = { path = "$root" }
[workspace]
TOML
ns=("$@")
[ ${#ns[@]} -eq 0 ] && ns=(4 8 16 32 64)
python3 "$here/gen.py" 4 "$work"
(cd "$work" && cargo build --release -q)
for n in "${ns[@]}"; do
    python3 "$here/gen.py" "$n" "$work"
    touch "$work/src/main.rs"
    (cd "$work" && /usr/bin/time -f "N=$n: build %e s, peak %M KB" cargo build --release -q)
    "$work/target/release/chain_n"
    "$work/target/release/chain_n"
done
