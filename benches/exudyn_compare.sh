#!/usr/bin/env bash
# Accuracy suite, ours against Exudyn (issue #17 item 7): see benches/exudyn_compare.py.
#   bash benches/exudyn_compare.sh            # full run (chains 2/8/32, four-bar, impacts)
#   bash benches/exudyn_compare.sh --quick    # fewer problems and settings, one run each
#   bash benches/exudyn_compare.sh --problem chain100 --our-integrators dopri5_tree,verner65_tree,verner87_tree --exudyn-tightest 1e-8
# Further arguments go to exudyn_compare.py (--problem, --repeats, --budget, --out, --no-exudyn,
# --our-integrators, --exudyn-tightest). Ours and Exudyn run in interleaved rounds, best of N (--repeats, default 3).
# Output: out/accuracy_suite/report.md (also printed), ours.csv, ours_tables.md, exudyn.csv.
set -euo pipefail
cd "$(dirname "$0")/.."

source benches/exudyn_venv.sh

cargo build --release --example accuracy_suite
TARGET="${CARGO_TARGET_DIR:-target}"
exec "$VENV/bin/python" benches/exudyn_compare.py \
    --suite-bin "$TARGET/release/examples/accuracy_suite" "$@"
