#!/bin/bash
# The least thread stack (KiB) on which each path of the jets' defaults runs, per N: the
# measurement behind `jet::EL_BY_COLUMNS_ABOVE` (runtime/examples/jet_stack.rs). A stack overflow
# aborts the probe, so each trial is a process of its own.
#   bash benches/scaling/jet_stack.sh [test|dev]   (the profile: opt-level 2 or 0)
set -u
profile=${1:-test}
cargo build -q -p lagrange-runtime --example jet_stack --profile "$profile" || exit 1
dir=$(cargo metadata --format-version 1 --no-deps | sed 's/.*"target_directory":"\([^"]*\)".*/\1/')
[ "$profile" = dev ] && sub=debug || sub=$profile
[ "$profile" = test ] && sub=debug
# The test profile writes to target/debug too: take the newest binary of the example.
bin=$(ls -t "$dir/$sub/examples/"jet_stack-* | grep -v '\.d$' | head -1)
least() {
  local lo=16 hi=65536 mid
  "$bin" "$1" "$2" $hi >/dev/null 2>&1 || { echo "> $hi"; return; }
  while [ $((hi - lo)) -gt 8 ]; do
    mid=$(((lo + hi) / 2))
    if "$bin" "$1" "$2" $mid >/dev/null 2>&1; then hi=$mid; else lo=$mid; fi
  done
  echo "$hi"
}
for path in whole raw acc energy; do
  for n in 16 17 24 32 48 64; do
    echo "$path N=$n: $(least $path $n 2>/dev/null) KiB"
  done
done
for n in 16 17 32 64; do "$bin" time $n 65536; done
