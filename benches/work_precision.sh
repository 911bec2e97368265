#!/usr/bin/env bash
# The work-precision report in one command: every model's solver and resolution sweeps
# (`mbcosim report`), then the FMU-vs-native timing through fmpy. Writes docs/report/ (CSV,
# log-log SVG plots, report.md, fmu_overhead.md). `--quick`: the reduced sweep CI runs as a smoke
# test. Installs what it needs (same set-up as tests/run_all.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
source tests/setup_env.sh

out="docs/report"
quick=()
for a in "$@"; do
    case "$a" in
        --quick) quick=(--quick) ;;
        *) out="$a" ;;
    esac
done

log "work-precision sweeps (mbcosim report ${quick[*]:-})"
cargo run --release --bin mbcosim -- report "${quick[@]}" --out "$out"

log "pack the FMUs and time them through fmpy"
cargo run --release --bin mbcosim -- pack
target_dir="$(cargo metadata --format-version 1 --no-deps | .venv/bin/python -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
.venv/bin/python benches/fmu_overhead.py dist "$target_dir/release/mbcosim" "$out" "${quick[@]}"
