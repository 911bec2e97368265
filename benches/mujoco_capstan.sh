#!/usr/bin/env bash
# Ours against MuJoCo's engine loop on the 32-edge sliding capstan (issue #19): see
# benches/mujoco_capstan.py (the MuJoCo model and its limits) and examples/capstan_bench.rs.
#   bash benches/mujoco_capstan.sh                 # best of 3
#   REPEATS=5 CASES="1e-5:200 5e-6:200" bash benches/mujoco_capstan.sh
# CASES: MuJoCo runs as timestep[s]:axial damping[N s] (ours is undamped; see the .py).
# 1. one sampled MuJoCo run per case (stability, T2/T1 across the drum vs the laws);
# 2. REPEATS rounds, interleaved: our example, then a timing-only MuJoCo run of each stable case
#    whose damping is TIMED_DAMP (cost per step does not depend on the damping);
# 3. the table (best CPU time of each) -> out/mujoco_capstan/report.md, also printed.
set -euo pipefail
cd "$(dirname "$0")/.."

MUJOCO_VERSION=4.0.0
NUMPY_VERSION=2.4.6
REPEATS="${REPEATS:-3}"
CASES="${CASES:-1e-5:0 1e-5:200 1e-5:1000 5e-6:50 5e-6:200 2.5e-6:200}"
TIMED_DAMP="${TIMED_DAMP:-200}"
OUT=out/mujoco_capstan
source benches/peer_venv.sh
peer_venv benches/.venv-mujoco mujoco mujoco "$MUJOCO_VERSION" "$NUMPY_VERSION"
PY="$VENV/bin/python"

cargo build --release --example capstan_bench
OURS="${CARGO_TARGET_DIR:-target}/release/examples/capstan_bench"

mkdir -p "$OUT"
: > "$OUT/sweep.jsonl"
: > "$OUT/ours.txt"
: > "$OUT/mujoco_timed.jsonl"
: > "$OUT/mujoco_stderr.log"  # MuJoCo warnings and errors
for c in $CASES; do
    echo "MuJoCo sampled run, dt ${c%%:*} s, damping ${c##*:} N s" >&2
    "$PY" benches/mujoco_capstan.py --json --dt "${c%%:*}" --damp "${c##*:}" 2>>"$OUT/mujoco_stderr.log" \
        | tee -a "$OUT/sweep.jsonl" >&2
done
STABLE=$("$PY" -c "
import json
rows = [r for r in map(json.loads, open('$OUT/sweep.jsonl'))]
print(' '.join(sorted({repr(r['dt']) for r in rows if r.get('stable') and r['damp'] == $TIMED_DAMP})))")
for i in $(seq 1 "$REPEATS"); do
    echo "round $i of $REPEATS" >&2
    "$OURS" 32 | tee -a "$OUT/ours.txt" >&2
    for dt in $STABLE; do
        "$PY" benches/mujoco_capstan.py --json --timed --dt "$dt" --damp "$TIMED_DAMP" 2>>"$OUT/mujoco_stderr.log" \
            | tee -a "$OUT/mujoco_timed.jsonl" >&2
    done
done
{
    echo "machine: $(nproc) cores shared with other users, load average $(cut -d' ' -f1-3 /proc/loadavg)"
    echo "commit: $(git rev-parse --short HEAD)$(git diff --quiet || echo ' (dirty)')"
} > "$OUT/machine.txt"
cat "$OUT/machine.txt"
"$PY" benches/mujoco_capstan.py --report "$OUT"
