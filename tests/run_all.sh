#!/usr/bin/env bash
# Runs every test: the Rust core (cargo test) and the packaged FMUs driven by fmpy (pytest).
# Installs what it needs itself, idempotently, on a fresh Debian machine:
#   - apt: libclang-dev (bindgen for the fmi-sys/fmi dev-dependencies), python3-venv; only if missing
#   - a Python venv in .venv with the pinned tools of tests/python/requirements.txt
# Honours CARGO_TARGET_DIR. Exit status: 0 only if everything passed.
set -euo pipefail
cd "$(dirname "$0")/.."

log() { printf '\n== %s\n' "$*"; }

apt_install() {
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "$@"
}

log "system packages"
missing=()
dpkg -s libclang-dev >/dev/null 2>&1 || missing+=(libclang-dev)
python3 -c 'import ensurepip, venv' >/dev/null 2>&1 || missing+=(python3-venv)
if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    apt_install "${missing[@]}"
else
    echo "libclang-dev and python3-venv present"
fi

log "python venv (.venv)"
if ! .venv/bin/python -c 'import sys' >/dev/null 2>&1; then
    rm -rf .venv
    python3 -m venv .venv
fi
req_hash="$(cat tests/python/requirements.txt tests/python/constraints.txt tests/python/optional-requirements.txt | sha256sum | cut -d' ' -f1)"
if [ "$(cat .venv/.requirements.sha 2>/dev/null)" != "$req_hash" ]; then
    .venv/bin/python -m pip install -q -r tests/python/requirements.txt -c tests/python/constraints.txt
    .venv/bin/python -m pip install -q -r tests/python/optional-requirements.txt -c tests/python/constraints.txt \
        || echo "libcosimpy could not be installed: its test will be skipped"
    echo "$req_hash" > .venv/.requirements.sha
else
    echo "up to date"
fi

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
