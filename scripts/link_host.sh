#!/bin/sh
# The linker of this package's x86_64 Linux builds (.cargo/config.toml; rustc runs it as `cc`).
# It links the FMUs' library, libmbcosim.so (the cdylib), with zig against glibc 2.17 through the
# pinned cargo-zigbuild (`cargo-zigbuild zig cc`, installed into .venv on first use by
# scripts/portable_toolchain.sh), so that the one host build serves `mbcosim`, the tests and the
# FMUs (docs/portable_binary.md). Every other link (executables, tests, build scripts) goes to cc
# unchanged. Falls back to cc for the library too when MBCOSIM_PORTABLE=0, when the toolchain
# cannot be had or when zig fails; scripts/build_portable.sh then finds the library not portable
# and says so.
set -u
repo="$(cd "$(dirname "$0")/.." && pwd)"
out=""
shared=0
prev=""
for a in "$@"; do
    if [ "$prev" = "-o" ]; then out="$a"; fi
    if [ "$a" = "-shared" ]; then shared=1; fi
    prev="$a"
done
case "$out" in
    */libmbcosim.so) ;;
    *) exec cc "$@" ;;
esac
if [ "$shared" = 1 ] && [ "${MBCOSIM_PORTABLE:-1}" != 0 ] &&
    bash "$repo/scripts/portable_toolchain.sh" >&2; then
    # -g: keep the debug info (split off by build_portable.sh); zig's sanitizers are off, as in
    # cargo-zigbuild's own builds
    if CARGO_ZIGBUILD_PYTHON_PATH="$repo/.venv/bin/python" "$repo/.venv/bin/cargo-zigbuild" \
        zig cc -- -g -fno-sanitize=all -target x86_64-linux-gnu.2.17 "$@"; then
        exit 0
    fi
    echo "link_host.sh: the zig link of $out failed; linking it with cc (not portable)" >&2
fi
exec cc "$@"
