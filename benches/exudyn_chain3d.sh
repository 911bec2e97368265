#!/usr/bin/env bash
# Cost per step of the spinning 3D chain (10 .. 1000 rods, spherical joints), ours against
# Exudyn, interleaved per size (issue #18): see benches/exudyn_chain3d.py.
#   bash benches/exudyn_chain3d.sh                       # sizes 10,30,100,300,1000, 100 steps
#   bash benches/exudyn_chain3d.sh --sizes 10,100 --steps 50
set -euo pipefail
cd "$(dirname "$0")/.."

source benches/exudyn_venv.sh

cargo build --release --example bench_core
TARGET="${CARGO_TARGET_DIR:-target}"
exec "$VENV/bin/python" benches/exudyn_chain3d.py --bench "$TARGET/release/examples/bench_core" "$@"
