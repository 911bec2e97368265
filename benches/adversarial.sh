#!/usr/bin/env bash
# The adversarial harness at benchmark size (issues #25, #48; docs/adversarial_harness.md):
# 100,000 seeded FMI 2.0 sequences (forged FMU states, parameter envelopes, random call
# sequences, callback re-entry, serialize/deserialize continuation, data files) and 10,000 FMI 3.0
# sequences (random call sequences, callback re-entry) against the packed FMUs, in 2 forked
# worker processes with a CPU watchdog; every hang or slow case is replayed once alone in a fresh
# process before it is counted. Prints both tallies: tried, crashes, hangs (after replay),
# NaN-with-OK, refused-with-message, completed, other violations, slow (wall only) and the
# largest CPU time of any refused or completed sequence.
#
#   bash benches/adversarial.sh [--count N] [--count3 N] [--seed S] [--workers W] [--cpu-limit SECONDS]
#
# Writes the full summaries (counts per model and kind, every finding with its seed:index for
# replay, every replay with both CPU times) to target/adversarial/summary-<seed>.json and
# summary3-<seed>.json. Installs what it needs (tests/setup_env.sh); packs the FMUs when dist/
# lacks them (MBCOSIM_REPACK=1 packs anyway).
set -euo pipefail
cd "$(dirname "$0")/.."
source tests/setup_env.sh

count=100000 count3=10000 seed=1 workers=2 cpu_limit=5
while [ $# -gt 0 ]; do
    case "$1" in
        --count) count="$2"; shift 2 ;;
        --count3) count3="$2"; shift 2 ;;
        --seed) seed="$2"; shift 2 ;;
        --workers) workers="$2"; shift 2 ;;
        --cpu-limit) cpu_limit="$2"; shift 2 ;;
        *) echo "unknown argument: $1" >&2; exit 2 ;;
    esac
done

log "build mbcosim (state-fields) and pack the FMUs"
cargo build --release --bin mbcosim
target_dir="$(cargo metadata --format-version 1 --no-deps | .venv/bin/python -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
if [ -n "${MBCOSIM_REPACK:-}" ] || ! ls dist/{,fmi3/}{PanelLock,RopeBlock,PidController}.fmu >/dev/null 2>&1; then
    cargo run --release --bin mbcosim -- pack
fi

out="$target_dir/adversarial"
mkdir -p "$out"
run() {  # fmi version, count, summary file
    log "adversarial harness, FMI $1.0: $2 sequences, seed $seed, $workers workers, $cpu_limit s CPU per sequence"
    .venv/bin/python tests/python/adversarial.py --dist dist --bin "$target_dir/release/mbcosim" --fmi "$1" \
        --seed "$seed" --count "$2" --workers "$workers" --cpu-limit "$cpu_limit" \
        --progress 5000 --json "$3" >/dev/null
}
run 2 "$count" "$out/summary-$seed.json"
run 3 "$count3" "$out/summary3-$seed.json"
.venv/bin/python tests/python/adversarial_report.py "$out/summary-$seed.json" "$out/summary3-$seed.json"
