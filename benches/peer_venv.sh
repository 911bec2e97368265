# Sourced by the peer benchmarks: `peer_venv DIR MODULE PACKAGE VERSION NUMPY_VERSION` makes (once)
# the venv DIR with PACKAGE==VERSION and numpy, checked by MODULE.__version__, and sets VENV.
peer_venv() {
    VENV="$1"
    local module="$2" package="$3" version="$4" numpy_version="$5"
    if ! "$VENV/bin/python" -c "import $module, sys; sys.exit($module.__version__ != '$version')" 2>/dev/null; then
        echo "creating $VENV with $package==$version" >&2
        rm -rf "$VENV"
        python3 -m venv "$VENV"
        "$VENV/bin/pip" install --quiet --disable-pip-version-check \
            "$package==$version" "numpy==$numpy_version"
    fi
}
