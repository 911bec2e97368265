#!/usr/bin/env bash
# Runs every test: the Rust core (cargo test) and the packaged FMUs driven by fmpy (pytest).
# Installs what it needs itself (apt packages, a local Python venv).
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== cargo test"
cargo test --release --all-targets 2>&1
