#!/usr/bin/env bash
# Sourced by tests/run_all.sh and benches/work_precision.sh: installs what the tests and the report
# need, idempotently, on a fresh Debian machine:
#   - apt: libclang-dev (bindgen for the fmi-sys/fmi dev-dependencies), python3-venv, libtbb12
#     (ecospy's libecosc.so links libtbb.so.12), valgrind (the adversarial harness's memcheck run,
#     tests/python/test_adversarial.py); only if missing
#   - apt: chromium (the replay page test loads the page headless, tests/python/test_replay.py),
#     npm (only where no npm is installed); only if missing
#   - the other platforms of the FMUs (`mbcosim pack`, tests/python/test_platforms.py,
#     docs/platforms.md): rustup targets x86_64-pc-windows-gnu and aarch64-unknown-linux-gnu; apt:
#     gcc-mingw-w64-x86-64-posix and binutils-mingw-w64-x86-64 (the Windows DLL's linker),
#     binutils-aarch64-linux-gnu, wine and wine64 (runs the Windows DLL), qemu-user and
#     libc6-arm64-cross (runs the aarch64 library); only if missing
#   - three.js for the replay pages: `npm ci` in tools/replay (the version pinned in its
#     package-lock.json, read by mbcosim at run time, docs/replay.md); only if another or
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

log "system packages of the FMUs' other platforms (Windows, aarch64 Linux)"
missing=()
command -v x86_64-w64-mingw32-gcc >/dev/null 2>&1 || missing+=(gcc-mingw-w64-x86-64-posix)
command -v x86_64-w64-mingw32-objdump >/dev/null 2>&1 || missing+=(binutils-mingw-w64-x86-64)
command -v aarch64-linux-gnu-objcopy >/dev/null 2>&1 || missing+=(binutils-aarch64-linux-gnu)
[ -x /usr/lib/wine/wine64 ] || missing+=(wine wine64)
command -v qemu-aarch64 >/dev/null 2>&1 || missing+=(qemu-user)
[ -e /usr/aarch64-linux-gnu/lib/ld-linux-aarch64.so.1 ] || missing+=(libc6-arm64-cross)
if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    # without recommends: wine's are 32-bit wine, fonts and desktop parts no test needs
    apt_install --no-install-recommends "${missing[@]}"
else
    echo "mingw-w64, aarch64 binutils, wine64, qemu-user and the aarch64 sysroot present"
fi

log "Rust targets of the FMUs' other platforms"
for t in x86_64-pc-windows-gnu aarch64-unknown-linux-gnu; do
    rustup target list --installed | grep -qx "$t" || rustup target add "$t"
done
echo "x86_64-pc-windows-gnu and aarch64-unknown-linux-gnu installed"

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
