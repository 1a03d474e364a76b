#!/usr/bin/env bash
# Beyond one machine, tested for real: runs the bifurcation sweep as a Slurm
# job array of 4 shards (`--shard K/4`) on a one-node Slurm cluster started on this machine,
# concatenates the shard CSVs in shard order and compares the result byte for byte with the same
# sweep run here without sharding. Prints PASS or FAIL; exits non-zero on a difference.
#
# Not part of CI. Needs root (it installs the Debian packages slurm-wlm and munge when slurmctld,
# slurmd or munged is missing, and runs the daemons as root). Everything else it starts lives in a
# temporary directory: its own munge key and socket, slurm.conf, state, spool and logs. The daemons
# are stopped and the directory removed on exit; the outputs stay in $OUT.
#
# Usage: bash scripts/slurm_shards.sh
# Environment (all optional):
#   MEMBERS=64 TRANSIENT=50 STROBES=20   the sweep's size (--members, --transient, --strobes)
#   SHARDS=4                             the job array's size
#   OUT=out/slurm_shards                 where the CSVs, the SVG and the jobs' logs go
#   CARGO_TARGET_DIR                     cargo's target directory (default: target/)
#   KEEP_TMP=1                           keep the temporary directory (for debugging the cluster)

set -euo pipefail

MEMBERS=${MEMBERS:-64}
TRANSIENT=${TRANSIENT:-50}
STROBES=${STROBES:-20}
SHARDS=${SHARDS:-4}

# The repository root (this script is in scripts/), so the script runs from anywhere.
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$REPO"
OUT=$(mkdir -p "${OUT:-out/slurm_shards}" && cd "${OUT:-out/slurm_shards}" && pwd)
TARGET=$(cd "$REPO" && mkdir -p "${CARGO_TARGET_DIR:-target}" && cd "${CARGO_TARGET_DIR:-target}" && pwd)
BIN=$TARGET/release/examples/bifurcation

log() { printf '[slurm_shards] %s\n' "$*"; }

# --- 1. Slurm and munge -------------------------------------------------------------------------
# The daemons live in /usr/sbin, which a non-login root shell may not have on PATH.
export PATH=$PATH:/usr/sbin:/sbin
# Debian 12 ships Slurm 22.05 as slurm-wlm (slurmctld, slurmd, slurm-client) and munge 0.5.15.
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v munged >/dev/null; then
    log "installing slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends slurm-wlm munge
fi

# --- 2. A one-node cluster in a temporary directory ---------------------------------------------
TMP=$(mktemp -d /tmp/slurm_shards.XXXXXX)
# munged wants its socket's directories searchable by all, and the key's not writable by others.
chmod 755 "$TMP"
mkdir -p "$TMP/munge" "$TMP/state" "$TMP/spool"
chmod 755 "$TMP/munge"
PIDS=()   # the daemons this script started, stopped in reverse order on exit

cleanup() {
    local rc=$?
    set +e
    # On a failure, the daemons' last words (their output is in $TMP/*.err).
    if [ "$rc" != 0 ]; then
        for f in "$TMP"/*.err; do [ -s "$f" ] && { echo "--- $f"; tail -n 25 "$f"; }; done >&2
    fi
    # Jobs left by an interrupted run go first, while slurmctld can still cancel them.
    if [ -n "${JOB:-}" ]; then scancel "$JOB" 2>/dev/null; sleep 1; fi
    for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do
        kill "${PIDS[i]}" 2>/dev/null
        # Wait (up to 10 s) for it to exit, so the next one's peer is gone first.
        for _ in $(seq 50); do kill -0 "${PIDS[i]}" 2>/dev/null || break; sleep 0.2; done
        kill -9 "${PIDS[i]}" 2>/dev/null
        wait "${PIDS[i]}" 2>/dev/null
    done
    if [ "${KEEP_TMP:-0}" = 1 ]; then log "kept $TMP"; else rm -rf "$TMP"; fi
    exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# munge: its own key, socket, pid, seed and log files, so a system munged (if any) is untouched.
if command -v mungekey >/dev/null; then
    mungekey --create --keyfile="$TMP/munge/munge.key"
else
    dd if=/dev/urandom of="$TMP/munge/munge.key" bs=1024 count=1 status=none
fi
chmod 400 "$TMP/munge/munge.key"
SOCKET=$TMP/munge/munge.socket
# --force: munged refuses some checks (running as root, /tmp's permissions) without it.
munged --foreground --force --key-file="$TMP/munge/munge.key" --socket="$SOCKET" \
    --pid-file="$TMP/munge/munged.pid" --seed-file="$TMP/munge/munged.seed" \
    --log-file="$TMP/munge/munged.log" >"$TMP/munged.err" 2>&1 &
PIDS+=($!)
for _ in $(seq 50); do [ -S "$SOCKET" ] && break; sleep 0.1; done
munge --socket="$SOCKET" -n | unmunge --socket="$SOCKET" >/dev/null
log "munged up ($SOCKET)"

# slurm.conf: the node is this machine under its short hostname, reached on 127.0.0.1; 2 CPUs;
# RealMemory nine tenths of MemTotal (a node that reports less than its configured memory is
# drained). No accounting, no cgroups (proctrack/linuxproc, task/none), every path in $TMP.
HOST=$(hostname -s)
MEM=$(awk '/^MemTotal:/ { printf "%d", $2 / 1024 * 0.9 }' /proc/meminfo)
export SLURM_CONF=$TMP/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=slurmshards
SlurmctldHost=$HOST(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$SOCKET
MpiDefault=none
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
StateSaveLocation=$TMP/state
SlurmdSpoolDir=$TMP/spool
SlurmctldPidFile=$TMP/slurmctld.pid
SlurmdPidFile=$TMP/slurmd.pid
SlurmctldLogFile=$TMP/slurmctld.log
SlurmdLogFile=$TMP/slurmd.log
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=2 RealMemory=$MEM State=UNKNOWN
PartitionName=shards Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF

# No systemd here: the daemons run in the foreground (-D) as this script's background children,
# with a fresh state (-c: no jobs or node states from an earlier run).
slurmctld -D -c -f "$SLURM_CONF" >"$TMP/slurmctld.err" 2>&1 &
PIDS+=($!)
slurmd -D -f "$SLURM_CONF" >"$TMP/slurmd.err" 2>&1 &
PIDS+=($!)

# Wait (up to 60 s) until sinfo shows the node idle.
for _ in $(seq 120); do
    state=$(sinfo -h -n "$HOST" -o %T 2>/dev/null || true)
    [ "$state" = idle ] && break
    sleep 0.5
done
if [ "$state" != idle ]; then
    log "node not idle (state: '${state:-none}')"
    exit 1
fi
log "$(sinfo --version): node $HOST idle"
sinfo

# --- 3. Build once, then the job array -----------------------------------------------------------
log "building the example (target: $TARGET)"
CARGO_TARGET_DIR=$TARGET cargo build --release --example bifurcation
SWEEP=(--members "$MEMBERS" --transient "$TRANSIENT" --strobes "$STROBES")

rm -f "$OUT"/bifurcation.*.csv "$OUT"/bifurcation.csv "$OUT"/single.csv "$OUT"/slurm-*.out
cat >"$TMP/shard.sbatch" <<EOF
#!/bin/bash
set -euo pipefail
exec "$BIN" ${SWEEP[*]} --shard \$SLURM_ARRAY_TASK_ID/$SHARDS --csv "$OUT/bifurcation.\$SLURM_ARRAY_TASK_ID.csv"
EOF

log "sbatch --array=0-$((SHARDS - 1)) --wait (members $MEMBERS, transient $TRANSIENT, strobes $STROBES)"
start=$(date +%s.%N)
# --parsable prints the job id first; --wait returns when every task has ended, non-zero if any failed.
sbatch --parsable --wait --array=0-$((SHARDS - 1)) --job-name=bifurcation --ntasks=1 \
    --cpus-per-task=1 --chdir="$REPO" --output="$OUT/slurm-%A_%a.out" "$TMP/shard.sbatch" \
    >"$TMP/sbatch.out" &
sbatch_pid=$!
# Know the job id while it runs (for the cleanup's scancel on an interrupt).
for _ in $(seq 50); do JOB=$(head -n 1 "$TMP/sbatch.out" 2>/dev/null || true); [ -n "$JOB" ] && break; sleep 0.1; done
wait "$sbatch_pid"
end=$(date +%s.%N)
# sbatch --wait polls with growing intervals (up to 10 s), so its time overstates the job's; the
# tasks' own start and end times (to the second) are in scontrol's record of the finished job.
span=$(scontrol -o show job "$JOB" | tr ' ' '\n' |
    awk -F= '$1 == "StartTime" { s[++n] = $2 } $1 == "EndTime" { e[++m] = $2 }
        END { a = s[1]; b = e[1]; for (i in s) if (s[i] < a) a = s[i]; for (i in e) if (e[i] > b) b = e[i]; print a, b }')
log "job array $JOB: sbatch --wait returned after $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }') s; tasks ran from ${span% *} to ${span#* }"
JOB=

# --- 4. Concatenate in shard order and compare with a single unsharded run -----------------------
for ((k = 0; k < SHARDS; k++)); do cat "$OUT/bifurcation.$k.csv"; done >"$OUT/bifurcation.csv"
log "single run on this machine"
"$BIN" "${SWEEP[@]}" --csv "$OUT/single.csv" --out "$OUT/single.svg"

if cmp "$OUT/bifurcation.csv" "$OUT/single.csv"; then
    log "PASS: the $SHARDS shards' CSV equals the single run's byte for byte ($(wc -l <"$OUT/single.csv") lines, $OUT)"
else
    log "FAIL: the concatenated shards differ from the single run:"
    diff "$OUT/bifurcation.csv" "$OUT/single.csv" | head -n 40 || true
    exit 1
fi
