#!/usr/bin/env bash
# Makes sure the pinned portable toolchain (scripts/portable-requirements.txt: cargo-zigbuild and
# zig from PyPI's ziglang) is installed in the source tree's .venv, installing it on first use:
# python3-venv from apt when missing, then pip. Idempotent: the hash of the pin file is kept in
# .venv/.portable-requirements.sha, and a run with a matching hash does nothing. Exits non-zero
# when the toolchain cannot be had (no python3, no PyPI). Run by scripts/link_host.sh (the link
# of the x86_64 Linux library) and scripts/build_portable.sh (aarch64); docs/portable_binary.md.
set -uo pipefail
cd "$(dirname "$0")/.."

say() { printf 'portable_toolchain: %s\n' "$*" >&2; }

req=scripts/portable-requirements.txt
stamp=.venv/.portable-requirements.sha
hash="$(sha256sum "$req" | cut -d' ' -f1)"
if [ "$(cat "$stamp" 2>/dev/null)" = "$hash" ] && [ -x .venv/bin/cargo-zigbuild ] &&
    .venv/bin/python -m ziglang version >/dev/null 2>&1; then
    exit 0
fi
if ! .venv/bin/python -c 'import sys' >/dev/null 2>&1; then
    command -v python3 >/dev/null || { say "no python3"; exit 1; }
    if ! python3 -c 'import ensurepip, venv' >/dev/null 2>&1; then
        say "installing python3-venv"
        sudo=""
        if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
        { $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
            $sudo apt-get install -y -qq python3-venv; } >&2 || exit 1
    fi
    rm -rf .venv
    python3 -m venv .venv >&2 || exit 1
fi
say "installing the portable toolchain into .venv ($(grep -v '^#' "$req" | xargs))"
.venv/bin/python -m pip install -q --retries 2 -r "$req" >&2 || exit 1
.venv/bin/cargo-zigbuild --version >/dev/null && .venv/bin/python -m ziglang version >/dev/null ||
    exit 1
echo "$hash" >"$stamp"
