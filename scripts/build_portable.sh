#!/usr/bin/env bash
# Builds the one shared library that every FMU ships (run by `mbcosim pack` and `mbcosim demo`):
#   1. portable: cargo-zigbuild links it against glibc 2.17 with zig from PyPI's `ziglang`, so the
#      FMUs load on any x86_64 Linux with glibc >= 2.17 (RHEL/CentOS 7, Ubuntu 18.04 and newer).
#      The pinned toolchain (scripts/portable-requirements.txt) is installed into .venv on first
#      use, idempotently; python3-venv and binutils come from apt when missing.
#   2. fallback, only when that toolchain cannot be installed or the portable build fails: the host
#      build, with a loud warning. Its FMUs need this machine's glibc, and
#      tests/python/test_portable_binary.py fails on them.
#   3. split: the debug info goes to <debug-dir>/libmbcosim.so.debug; the library is stripped and
#      points to that file by .gnu_debuglink (name + CRC) and by its GNU build ID.
# Usage: scripts/build_portable.sh [--profile P] [--target-dir DIR] [--debug-dir DIR]
# Prints the stripped library's path, the only line on stdout; everything else goes to stderr.
# MBCOSIM_PORTABLE=0 asks for the host build (no warning). See docs/portable_binary.md.
set -euo pipefail
cd "$(dirname "$0")/.."

profile=release
target_dir=target
debug_dir=dist/debug
while [ $# -gt 0 ]; do
    case "$1" in
        --profile) profile="$2"; shift 2 ;;
        --target-dir) target_dir="$2"; shift 2 ;;
        --debug-dir) debug_dir="$2"; shift 2 ;;
        *) echo "build_portable.sh: unknown argument $1" >&2; exit 2 ;;
    esac
done
# cargo's `dev` profile builds into debug/ (and `debug` is no profile name)
case "$profile" in
    dev | debug) profile=dev; profile_dir=debug ;;
    *) profile_dir="$profile" ;;
esac
triple=x86_64-unknown-linux-gnu
glibc_floor=2.17
cargo="${CARGO:-cargo}"

say() { printf 'build_portable: %s\n' "$*" >&2; }

apt_install() {
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo apt-get update -qq >&2 &&
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "$@" >&2
}

# Highest GLIBC_x.y symbol version a library asks for.
glibc_needed() {
    objdump -T "$1" | grep -o 'GLIBC_[0-9][0-9.]*' | sort -uV | tail -n 1
}

# The pinned cargo-zigbuild and zig in .venv; returns non-zero when they cannot be had.
portable_toolchain() {
    local req=scripts/portable-requirements.txt stamp=.venv/.portable-requirements.sha hash
    hash="$(sha256sum "$req" | cut -d' ' -f1)"
    if [ "$(cat "$stamp" 2>/dev/null)" = "$hash" ] && [ -x .venv/bin/cargo-zigbuild ] &&
        .venv/bin/python -m ziglang version >/dev/null 2>&1; then
        return 0
    fi
    if ! .venv/bin/python -c 'import sys' >/dev/null 2>&1; then
        command -v python3 >/dev/null || { say "no python3"; return 1; }
        if ! python3 -c 'import ensurepip, venv' >/dev/null 2>&1; then
            say "installing python3-venv"
            apt_install python3-venv || return 1
        fi
        rm -rf .venv
        python3 -m venv .venv >&2 || return 1
    fi
    say "installing the portable toolchain into .venv ($(grep -v '^#' "$req" | xargs))"
    .venv/bin/python -m pip install -q --retries 2 -r "$req" >&2 || return 1
    .venv/bin/cargo-zigbuild --version >/dev/null && .venv/bin/python -m ziglang version >/dev/null ||
        return 1
    echo "$hash" >"$stamp"
}

if ! command -v objcopy >/dev/null 2>&1 || ! command -v objdump >/dev/null 2>&1; then
    say "installing binutils (objcopy, objdump)"
    apt_install binutils || { say "binutils could not be installed"; exit 1; }
fi

lib=""
why=""
if [ "${MBCOSIM_PORTABLE:-1}" = "0" ]; then
    why="MBCOSIM_PORTABLE=0"
elif ! portable_toolchain; then
    why="the pinned cargo-zigbuild/ziglang could not be installed into .venv"
else
    # cargo-zigbuild runs zig as `<CARGO_ZIGBUILD_PYTHON_PATH> -m ziglang`; the build ID ties the
    # stripped library to its debug file (zig's linker writes none unless asked).
    flags="${CARGO_TARGET_X86_64_UNKNOWN_LINUX_GNU_RUSTFLAGS:-} -C link-arg=-Wl,--build-id=sha1"
    if CARGO_ZIGBUILD_PYTHON_PATH="$PWD/.venv/bin/python" \
        CARGO_TARGET_X86_64_UNKNOWN_LINUX_GNU_RUSTFLAGS="$flags" \
        .venv/bin/cargo-zigbuild zigbuild --lib --quiet --profile "$profile" \
        --target "$triple.$glibc_floor" --manifest-path Cargo.toml --target-dir "$target_dir" >&2; then
        lib="$target_dir/$triple/$profile_dir/libmbcosim.so"
    else
        why="cargo zigbuild failed"
    fi
fi

if [ -z "$lib" ]; then
    "$cargo" build --lib --quiet --profile "$profile" --manifest-path Cargo.toml \
        --target-dir "$target_dir" >&2
    lib="$target_dir/$profile_dir/libmbcosim.so"
    if [ "$why" != "MBCOSIM_PORTABLE=0" ]; then
        say "################################################################################"
        say "WARNING: NOT PORTABLE: $why."
        say "The FMUs get the host build, which needs $(glibc_needed "$lib") or newer instead of"
        say "GLIBC_$glibc_floor. See docs/portable_binary.md; tests/python/test_portable_binary.py"
        say "fails on these FMUs."
        say "################################################################################"
    fi
fi

out_dir="$target_dir/fmu/$profile_dir"
mkdir -p "$out_dir" "$debug_dir"
debug_file="$debug_dir/libmbcosim.so.debug"
objcopy --only-keep-debug "$lib" "$debug_file.partial"
mv "$debug_file.partial" "$debug_file"
objcopy --strip-unneeded --add-gnu-debuglink="$debug_file" "$lib" "$out_dir/libmbcosim.so.partial"
mv "$out_dir/libmbcosim.so.partial" "$out_dir/libmbcosim.so"
say "$(basename "$lib") from $lib: $(glibc_needed "$lib"), stripped to $out_dir/libmbcosim.so" \
    "($(($(stat -c %s "$out_dir/libmbcosim.so") / 1024)) KiB), debug info in $debug_file"
echo "$out_dir/libmbcosim.so"
