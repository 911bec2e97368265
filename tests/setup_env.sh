#!/usr/bin/env bash
# Sourced by tests/run_all.sh and benches/work_precision.sh: installs what the tests and the report
# need, idempotently, on a fresh Debian machine:
#   - apt: libclang-dev (bindgen for the fmi-sys/fmi dev-dependencies), python3-venv, libtbb12
#     (ecospy's libecosc.so links libtbb.so.12), valgrind (the adversarial harness's memcheck run,
#     tests/python/test_adversarial.py); only if missing
#   - apt: chromium (the replay page test loads the page headless, tests/python/test_replay.py),
#     npm (only where no npm is installed); only if missing
#   - three.js for the replay pages: `npm ci` in tools/replay (the version pinned in its
#     package-lock.json, embedded into mbcosim at build time, docs/replay.md); only if another or
#     no version is installed
#   - a Python venv in .venv with the pinned tools of tests/python/requirements.txt
#   - the mbstudy command (tools/mbstudy, an editable install into .venv)
# Expects the repository root as the current directory.

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
dpkg -s libtbb12 >/dev/null 2>&1 || missing+=(libtbb12)
command -v valgrind >/dev/null 2>&1 || missing+=(valgrind)
command -v chromium >/dev/null 2>&1 || missing+=(chromium)
command -v npm >/dev/null 2>&1 || missing+=(npm)
if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    apt_install "${missing[@]}"
else
    echo "libclang-dev, python3-venv, libtbb12, valgrind, chromium and npm present"
fi

log "three.js for the replay pages (tools/replay)"
three_version() {
    python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); print(d["packages"]["node_modules/three"]["version"] if "packages" in d else d["version"])' "$1" 2>/dev/null
}
three_pinned="$(three_version tools/replay/package-lock.json)"
if [ "$(three_version tools/replay/node_modules/three/package.json)" != "$three_pinned" ]; then
    (cd tools/replay && npm ci --ignore-scripts --no-audit --no-fund)
else
    echo "three $three_pinned present"
fi

log "python venv (.venv)"
if ! .venv/bin/python -c 'import sys' >/dev/null 2>&1; then
    rm -rf .venv
    python3 -m venv .venv
fi
req_hash="$(cat tests/python/requirements.txt tests/python/constraints.txt | sha256sum | cut -d' ' -f1)"
if [ "$(cat .venv/.requirements.sha 2>/dev/null)" != "$req_hash" ]; then
    .venv/bin/python -m pip install -q -r tests/python/requirements.txt -c tests/python/constraints.txt
    echo "$req_hash" > .venv/.requirements.sha
else
    echo "up to date"
fi

log "mbstudy (tools/mbstudy, editable: the parameter-study command)"
if ! .venv/bin/python -c 'import mbstudy, pathlib, sys; sys.exit(pathlib.Path(mbstudy.__file__).resolve().parents[1] != pathlib.Path("tools/mbstudy").resolve())' >/dev/null 2>&1 \
    || [ ! -x .venv/bin/mbstudy ]; then
    .venv/bin/python -m pip install -q --no-build-isolation --no-deps -e tools/mbstudy
else
    echo "up to date"
fi
