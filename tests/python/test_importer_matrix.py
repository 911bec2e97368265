"""Importer matrix (issue #20): every packaged FMU's DefaultExperiment and a PID coupling, run
through fmpy, libcosimpy (libcosim, C++) and ecospy (Ecos, C++), give the same outputs at every
communication point to 1e-9 relative.

fmpy is the reference column: its explicit Jacobi loop reproduces each importer's fmi2DoStep
arguments (importer_matrix.TIME_MODES), so a difference means the FMU saw the same calls and
answered differently. libcosim and Ecos round the communication step differently; the FMUs' clock
(whole nanoseconds) makes their results identical anyway, which the last test checks.

The masters and the comparison are described in docs/importer_matrix.md. An importer that cannot
be imported fails the tests (tests/setup_env.sh installs all three).
"""

import pytest
from conftest import DIST, fmu_paths, packed

import importer_matrix as im

OTHERS = ["libcosimpy", "ecospy"]
PID_CASE = "PID+PanelLock"

def _case_ids():
    return [p.stem for p in fmu_paths()] + [PID_CASE]


def _case(case_id):
    if case_id == PID_CASE:
        packed("PanelLock")
        packed("PidController")
        return im.pid_panel_lock(DIST)
    return im.default_experiment(packed(case_id))


def _require(importer):
    ok, why = im.available(importer)
    assert ok, f"the importer matrix needs every column (tests/setup_env.sh installs them): {why}"


_RUNS = {}


def _run(case, runner, time_mode=None):
    """One run of a case, shared by the tests of this module."""
    key = (case.name, runner, time_mode)
    if key not in _RUNS:
        _RUNS[key] = im.run_fmpy(case, time_mode) if runner == "fmpy" else im.RUNNERS[runner](case)
    return _RUNS[key]


def _failures(case, diffs):
    return "\n".join(
        f"  {d.name}: rel {d.rel:.3g}, abs {d.abs:.3g}, peak {d.peak:.3g}, worst at t = {case.time(d.k + 1)} s"
        for d in diffs if not d.rel <= im.RTOL)


@pytest.mark.parametrize("importer", list(im.IMPORTERS))
def test_importer_is_available(importer):
    _require(importer)


@pytest.mark.parametrize("importer", OTHERS)
@pytest.mark.parametrize("case_id", _case_ids())
def test_importer_matches_fmpy(case_id, importer):
    _require("fmpy")
    _require(importer)
    case = _case(case_id)
    ref = _run(case, "fmpy", im.TIME_MODE_OF[importer])
    got = _run(case, importer)
    diffs = im.compare(ref, got)
    print(f"\n{case.name}: {importer} vs {ref.importer}, {case.n_steps} steps to {case.stop} s: "
          f"max rel {diffs[0].rel:.3g} ({diffs[0].name}); wall {ref.wall:.2f} s and {got.wall:.2f} s")
    bad = _failures(case, diffs)
    assert not bad, f"{case.name}: {importer} differs from {ref.importer} beyond {im.RTOL} relative:\n{bad}"


@pytest.mark.parametrize("case_id", _case_ids())
def test_libcosim_and_ecos_agree(case_id):
    """The two C++ masters against each other: the same Jacobi exchange, but libcosim passes
    h_k = t_{k+1} - t_k of its nanosecond grid and Ecos the nominal h."""
    for importer in OTHERS:
        _require(importer)
    case = _case(case_id)
    a, b = _run(case, "libcosimpy"), _run(case, "ecospy")
    diffs = im.compare(a, b)
    worst = diffs[0]
    summary = (f"{case.name}: libcosimpy vs ecospy: max rel {worst.rel:.3g} ({worst.name}: abs {worst.abs:.3g}, "
               f"peak {worst.peak:.3g}); max |diff|/peak {max((d.abs / d.peak for d in diffs if d.peak), default=0.0):.3g}")
    print("\n" + summary)
    bad = _failures(case, diffs)
    assert not bad, f"{case.name}: libcosimpy and ecospy differ beyond {im.RTOL} relative:\n{bad}"
