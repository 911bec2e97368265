# Sourced by the Exudyn benchmarks: makes (once) the venv benches/.venv-exudyn with the pinned
# Exudyn and numpy, and sets VENV to it.
EXUDYN_VERSION=1.13.6
NUMPY_VERSION=2.4.6
VENV=benches/.venv-exudyn
if ! "$VENV/bin/python" -c "import exudyn, sys; sys.exit(exudyn.__version__ != '$EXUDYN_VERSION')" 2>/dev/null; then
    echo "creating $VENV with exudyn==$EXUDYN_VERSION" >&2
    rm -rf "$VENV"
    python3 -m venv "$VENV"
    "$VENV/bin/pip" install --quiet --disable-pip-version-check \
        "exudyn==$EXUDYN_VERSION" "numpy==$NUMPY_VERSION"
fi
