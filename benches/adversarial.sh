#!/usr/bin/env bash
# The adversarial harness at benchmark size (issue #25, docs/adversarial_harness.md):
# >= 100,000 seeded sequences (forged FMU states, parameter envelopes, random call sequences)
# against the packed FMUs, in 2 forked worker processes with a CPU watchdog. Prints the counts:
# tried, crashes, hangs, NaN-with-OK, refused-with-message (and completed, other violations).
#
#   bash benches/adversarial.sh [--count N] [--seed S] [--workers W] [--cpu-limit SECONDS]
#
# Writes the full summary (counts per model and kind, every finding with its seed:index for
# replay) to target/adversarial/summary-<seed>.json. Installs what it needs (tests/setup_env.sh);
# packs the FMUs when dist/ lacks them (MBCOSIM_REPACK=1 packs anyway).
set -euo pipefail
cd "$(dirname "$0")/.."
source tests/setup_env.sh

count=100000 seed=1 workers=2 cpu_limit=5
while [ $# -gt 0 ]; do
    case "$1" in
        --count) count="$2"; shift 2 ;;
        --seed) seed="$2"; shift 2 ;;
        --workers) workers="$2"; shift 2 ;;
        --cpu-limit) cpu_limit="$2"; shift 2 ;;
        *) echo "unknown argument: $1" >&2; exit 2 ;;
    esac
done

log "build mbcosim (state-fields) and pack the FMUs"
cargo build --release --bin mbcosim
target_dir="$(cargo metadata --format-version 1 --no-deps | .venv/bin/python -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
if [ -n "${MBCOSIM_REPACK:-}" ] || ! ls dist/PanelLock.fmu dist/RopeBlock.fmu dist/PidController.fmu >/dev/null 2>&1; then
    cargo run --release --bin mbcosim -- pack
fi

out="$target_dir/adversarial"
mkdir -p "$out"
log "adversarial harness: $count sequences, seed $seed, $workers workers, $cpu_limit s CPU per sequence"
.venv/bin/python tests/python/adversarial.py --dist dist --bin "$target_dir/release/mbcosim" \
    --seed "$seed" --count "$count" --workers "$workers" --cpu-limit "$cpu_limit" \
    --progress 5000 --json "$out/summary-$seed.json" >/dev/null
.venv/bin/python - "$out/summary-$seed.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"\nadversarial: {s['count']} sequences (seed {s['seed']}, {s['workers']} workers, "
      f"{s['cpu_limit']} s CPU bound) in {s['seconds']} s")
for k in ("tried", "crashes", "hangs", "nan_with_ok", "refused_with_message", "completed", "other_violations"):
    print(f"  {k:22} {s[k]}")
print(f"  fields forged          {s['fields_visited']} of {s['fields_total']}")
print(f"  findings               {s['finding_count']} (listed in {sys.argv[1]})")
PY
