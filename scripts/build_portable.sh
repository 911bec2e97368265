#!/usr/bin/env bash
# Builds the shared library that every FMU ships for one platform (run by `mbcosim pack` and
# `mbcosim demo`, once per platform):
#   1. x86_64 Linux (the default target): the host build's own libmbcosim.so (`cargo build
#      --lib`, nothing to do after `cargo run --release --bin mbcosim`). scripts/link_host.sh,
#      the linker of .cargo/config.toml, links it with zig (PyPI's `ziglang`, through the pinned
#      cargo-zigbuild) against glibc 2.17, so the FMUs load on any x86_64 Linux with glibc >= 2.17
#      (RHEL/CentOS 7, Ubuntu 18.04 and newer), and one compile serves `mbcosim`, the tests and
#      the FMUs. The pinned toolchain (scripts/portable-requirements.txt) is installed into .venv
#      on first use by scripts/portable_toolchain.sh. When the library was linked without zig
#      (the toolchain could not be had), it is relinked once the toolchain is there, else packed
#      as it is with a loud warning: its FMUs need this machine's glibc, and
#      tests/python/test_portable_binary.py fails on them.
#   2. aarch64 Linux (--target aarch64-unknown-linux-gnu): cargo-zigbuild for glibc 2.17 on
#      aarch64; no fallback (there is no host build to fall back to).
#   3. x86_64 Windows (--target x86_64-pc-windows-gnu): cargo with Debian's mingw-w64 gcc as the
#      linker; the DLL links libgcc and winpthread statically (Rust's windows-gnu default), and
#      the build fails when it imports anything but Windows system DLLs (docs/platforms.md).
#   The Rust targets come from `rustup target add`, the binutils of each platform from apt, both
#   only when missing.
#   4. split: the debug info goes to <debug-dir>[/<platform>]/<library>.debug; the library is
#      stripped and points to that file by .gnu_debuglink (name + CRC) and, on Linux, by its GNU
#      build ID.
# Usage: scripts/build_portable.sh [--target TRIPLE] [--profile P] [--target-dir DIR]
#                                  [--debug-dir DIR]
# Prints the stripped library's path, the only line on stdout; everything else goes to stderr.
# MBCOSIM_PORTABLE=0 asks for the host linker for x86_64 Linux (no warning). See
# docs/portable_binary.md and docs/platforms.md.
set -euo pipefail
cd "$(dirname "$0")/.."

profile=release
target_dir=target
debug_dir=dist/debug
triple=x86_64-unknown-linux-gnu
while [ $# -gt 0 ]; do
    case "$1" in
        --target) triple="$2"; shift 2 ;;
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
glibc_floor=2.17
cargo="${CARGO:-cargo}"

say() { printf 'build_portable: %s\n' "$*" >&2; }

# Per platform: the library cargo writes, the binutils prefix, the apt package holding them, the
# folder (under the output and debug folders) of the stripped library and its debug file.
case "$triple" in
    x86_64-unknown-linux-gnu)
        lib_name=libmbcosim.so; tools="" tools_pkg=binutils; sub="" ;;
    aarch64-unknown-linux-gnu)
        lib_name=libmbcosim.so; tools=aarch64-linux-gnu- tools_pkg=binutils-aarch64-linux-gnu
        sub=aarch64-linux ;;
    x86_64-pc-windows-gnu)
        lib_name=mbcosim.dll; tools=x86_64-w64-mingw32- tools_pkg=binutils-mingw-w64-x86-64
        sub=x86_64-windows ;;
    *) echo "build_portable.sh: unknown target $triple" >&2; exit 2 ;;
esac

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
portable_toolchain() { bash scripts/portable_toolchain.sh; }

if ! command -v "${tools}objcopy" >/dev/null 2>&1 || ! command -v "${tools}objdump" >/dev/null 2>&1
then
    say "installing $tools_pkg (${tools}objcopy, ${tools}objdump)"
    apt_install "$tools_pkg" || { say "$tools_pkg could not be installed"; exit 1; }
fi
objcopy() { command "${tools}objcopy" "$@"; }
objdump() { command "${tools}objdump" "$@"; }

# The Rust standard library of a cross target, from rustup when missing.
rust_target() {
    if ! rustup target list --installed 2>/dev/null | grep -qx "$triple"; then
        say "rustup target add $triple"
        rustup target add "$triple" >&2 || { say "rustup target add $triple failed"; exit 1; }
    fi
}

# x86_64 Windows: the DLL through mingw-w64's gcc; it must import Windows system DLLs only.
windows_dll() {
    rust_target
    if ! command -v x86_64-w64-mingw32-gcc >/dev/null 2>&1; then
        say "installing gcc-mingw-w64-x86-64-posix (the linker of the Windows DLL)"
        apt_install gcc-mingw-w64-x86-64-posix || { say "mingw-w64 could not be installed"; exit 1; }
    fi
    CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER=x86_64-w64-mingw32-gcc \
        "$cargo" build --lib --quiet --profile "$profile" --target "$triple" \
        --manifest-path Cargo.toml --target-dir "$target_dir" >&2
    lib="$target_dir/$triple/$profile_dir/$lib_name"
    local foreign
    foreign="$(objdump -p "$lib" | sed -n 's/^[[:space:]]*DLL Name: //p' |
        grep -viE '^(kernel32|ntdll|msvcrt|advapi32|userenv|ws2_32|bcrypt|bcryptprimitives|api-ms-win-[a-z0-9-]+)\.dll$' || true)"
    if [ -n "$foreign" ]; then
        say "$lib imports DLLs that are not Windows system DLLs: $(echo "$foreign" | xargs)"
        exit 1
    fi
}

# aarch64 Linux: zig's glibc 2.17 build, as for x86_64 but without a host fallback.
aarch64_so() {
    rust_target
    portable_toolchain || { say "the pinned cargo-zigbuild/ziglang could not be installed"; exit 1; }
    CARGO_ZIGBUILD_PYTHON_PATH="$PWD/.venv/bin/python" \
        CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUSTFLAGS="${CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUSTFLAGS:-} -C link-arg=-Wl,--build-id=sha1" \
        .venv/bin/cargo-zigbuild zigbuild --lib --quiet --profile "$profile" \
        --target "$triple.$glibc_floor" --manifest-path Cargo.toml --target-dir "$target_dir" >&2
    lib="$target_dir/$triple/$profile_dir/$lib_name"
}

lib=""
if [ "$triple" = x86_64-pc-windows-gnu ]; then
    windows_dll
elif [ "$triple" = aarch64-unknown-linux-gnu ]; then
    aarch64_so
else
    # x86_64 Linux: the host build's own cdylib, which scripts/link_host.sh (the linker of
    # .cargo/config.toml) links with zig against glibc 2.17. After `cargo run --release --bin
    # mbcosim` this cargo has nothing to do.
    host_build() {
        "$cargo" build --lib --quiet --profile "$profile" --manifest-path Cargo.toml \
            --target-dir "$target_dir" >&2
    }
    host_build
    lib="$target_dir/$profile_dir/libmbcosim.so"
    # portable: it asks for no glibc symbol version above the floor
    portable() {
        local need
        need="$(glibc_needed "$lib")"
        [ "$(printf '%s\n' "${need#GLIBC_}" "$glibc_floor" | sort -V | tail -n 1)" = "$glibc_floor" ]
    }
    if [ "${MBCOSIM_PORTABLE:-1}" != "0" ] && ! portable && portable_toolchain; then
        # linked by cc before the toolchain could be had (or by a cargo that did not read
        # .cargo/config.toml): remove the library so that cargo builds and links it again
        say "$lib is not portable; linking it again with zig"
        rm -f "$target_dir/$profile_dir/deps/libmbcosim.so"
        host_build
    fi
    if [ "${MBCOSIM_PORTABLE:-1}" = "0" ]; then
        :
    elif ! portable; then
        say "################################################################################"
        say "WARNING: NOT PORTABLE: the library was not linked with zig (scripts/link_host.sh:"
        say "the pinned cargo-zigbuild/ziglang could not be installed into .venv, or zig failed)."
        say "The FMUs get the host build, which needs $(glibc_needed "$lib") or newer instead of"
        say "GLIBC_$glibc_floor. See docs/portable_binary.md; tests/python/test_portable_binary.py"
        say "fails on these FMUs."
        say "################################################################################"
    fi
fi

out_dir="$target_dir/fmu/$profile_dir${sub:+/$sub}"
debug_dir="$debug_dir${sub:+/$sub}"
mkdir -p "$out_dir" "$debug_dir"
debug_file="$debug_dir/$lib_name.debug"
out="$out_dir/$lib_name"
objcopy --only-keep-debug "$lib" "$debug_file.partial"
mv "$debug_file.partial" "$debug_file"
objcopy --strip-unneeded --add-gnu-debuglink="$debug_file" "$lib" "$out.partial"
mv "$out.partial" "$out"
if [ "$triple" = x86_64-pc-windows-gnu ]; then
    needs="imports $(objdump -p "$out" | sed -n 's/^[[:space:]]*DLL Name: //p' | xargs)"
else
    needs="$(glibc_needed "$lib")"
fi
say "$triple $(basename "$lib") from $lib: $needs, stripped to $out" \
    "($(($(stat -c %s "$out") / 1024)) KiB), debug info in $debug_file"
echo "$out"
