#!/usr/bin/env bash
# A user's first crate, written from the README's "Use it in your crate": the heavy top run 20
# times through `Simulation` and a 256-member `Ensemble`, in debug (with the README's two profile
# lines, and without them) and in release; prints each build's time and each binary's timings
# (BENCHMARKS.md, "A newcomer's debug build").
#
#   bash benches/newcomer/run.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
work="${NEWCOMER_DIR:-${TMPDIR:-/tmp}/lagrange-newcomer}"
rm -rf "$work" && mkdir -p "$work/src"
cp "$here/main.rs.txt" "$work/src/main.rs"
manifest() {
    cat <<TOML
[package]
name = "newcomer"
version = "0.1.0"
edition = "2021"
[dependencies]
lagrange = { path = "$root" }
[workspace]
TOML
    if [ "$1" = with ]; then
        printf '[profile.dev]\nopt-level = 1\n[profile.dev.package."*"]\nopt-level = 3\n'
    fi
}
cd "$work"
manifest without > Cargo.toml
/usr/bin/time -f "debug build without the profile lines: %e s" cargo build -q
echo "debug, without: $(./target/debug/newcomer)"
manifest with > Cargo.toml
/usr/bin/time -f "debug build with the profile lines: %e s" cargo build -q
echo "debug, with:    $(./target/debug/newcomer)"
/usr/bin/time -f "release build: %e s" cargo build --release -q
echo "release:        $(./target/release/newcomer)"
