#!/usr/bin/env bash
# Runs every test: the Rust core (cargo test) and the packaged FMUs driven by fmpy (pytest).
# Installs what it needs itself, idempotently, on a fresh Debian machine:
#   - apt: libclang-dev (bindgen for the fmi-sys/fmi dev-dependencies), python3-venv, libtbb12
#     (ecospy's native library), chromium (the replay page test); only if missing
#   - three.js in tools/replay/node_modules (`npm ci`, the pinned version; read by mbcosim at run
#     time for `simulate --replay`)
#   - a Python venv in .venv with the pinned tools of tests/python/requirements.txt
# Honours CARGO_TARGET_DIR. Exit status: 0 only if everything passed.
set -euo pipefail
cd "$(dirname "$0")/.."

source tests/setup_env.sh

log "cargo test --release --all-targets"
cargo test --release --all-targets 2>&1

log "pack the FMUs into dist/"
cargo run --release --bin mbcosim -- pack

target_dir="$(cargo metadata --format-version 1 --no-deps | .venv/bin/python -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
export MBCOSIM_BIN="$target_dir/release/mbcosim"
export MBCOSIM_DIST="$PWD/dist"

log "pytest tests/python"
set +e
.venv/bin/python -m pytest -q tests/python
status=$?
set -e
if [ "$status" -eq 5 ]; then
    echo "pytest collected no tests: treating as a failure" >&2
    exit 1
fi
exit "$status"
