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


# Choice parameters (issue #44 item 6; docs/choice_parameters.md). libcosim and Ecos cannot set
# Enumeration variables, so every choice has an Integer twin `<name>_number`. For every choice of
# every model and every item: libcosimpy and ecospy set the twin, fmpy sets the Enumeration, and
# the three runs agree bit for bit (so the twin reaches the same setting); runs of different items
# differ in at least one output (so the setting has an effect the test sees). Each entry gives a
# run long enough, and start values, for the choice to act on the outputs.
CHOICE_SETUPS = {
    # solver counters and the motion differ from the first step on
    ("PanelLock", "integrator"): (1.0, {}),
    # the latch contacts: the first lock-up is within the first 10 s of the default deployment
    ("PanelLock", "contact_law"): (10.0, {}),
    # a free satellite turned by the deployment, pushed along x: world x and body x part as it turns
    ("PanelLock", "load_frame"): (2.0, {"free_satellite": True, "satellite_force_x": 50.0}),
    # dopri5 takes coarse slings only (segments <= 32)
    ("RopeBlock", "integrator"): (1.0, {"segments": 16}),
    # hook 0 commanded 0.2 m/s up: velocity mode lifts it, position mode (dz = 0) holds it
    ("RopeBlock", "hook_command"): (1.0, {"hook0_vz": 0.2}),
    # the hoisted lift slides through nodes with load along their edges, where the laws differ
    ("RopeBlock", "friction_law"): (1.0, {"hook0_vz": 0.2}),
}


def _choices():
    return [(p.stem, v.name, twin.name, n) for p in fmu_paths() for v, twin, n in im.choice_parameters(p)]


def _choice_case(model, values, stop):
    case = im.default_experiment(packed(model))
    case.n_steps = round(stop * 1e9 / case.step_ns)
    case.values = {"model": dict(values)}
    case.name = f"{model} {values}"
    return case


def test_every_choice_parameter_is_covered():
    found = {(m, name) for m, name, _, _ in _choices()}
    assert found == set(CHOICE_SETUPS), f"choice parameters {sorted(found)} vs the setups {sorted(CHOICE_SETUPS)}"


# Items that must give the same run on their setup: PanelLock's `auto` (5) resolves to
# `dopri5_tree` (4) on rigid panels with a fixed satellite, tolerances included
# (docs/auto_integrator.md).
SAME_ITEMS = {("PanelLock", "integrator"): {(4, 5)}}


@pytest.mark.parametrize("importer", OTHERS)
@pytest.mark.parametrize("model,choice", sorted(CHOICE_SETUPS))
def test_importer_sets_every_choice_through_its_integer_twin(model, choice, importer):
    _require("fmpy")
    _require(importer)
    (_, _, twin, n), = [c for c in _choices() if c[:2] == (model, choice)]
    stop, base = CHOICE_SETUPS[(model, choice)]
    runs = {}
    for item in range(1, n + 1):
        ref = im.run_fmpy(_choice_case(model, {**base, choice: item}, stop), im.TIME_MODE_OF[importer])
        got = im.RUNNERS[importer](_choice_case(model, {**base, twin: item}, stop))
        bad = _failures(ref.case, im.compare(ref, got))
        assert not bad, f"{model}: {importer} with {twin} = {item} differs from fmpy with {choice} = {item}:\n{bad}"
        runs[item] = got
    for a in runs:
        for b in runs:
            if a < b:
                moved = [d for d in im.compare(runs[a], runs[b]) if d.rel > im.RTOL]
                if (a, b) in SAME_ITEMS.get((model, choice), ()):
                    assert not moved, f"{model}: {choice} = {a} and {b} should give the same run:\n{moved}"
                else:
                    assert moved, f"{model}: {choice} = {a} and {b} set from {importer} give the same outputs"


@pytest.mark.parametrize("model,choice", sorted(CHOICE_SETUPS))
def test_the_integer_twin_overrides_the_enumeration(model, choice):
    """Both set: a non-zero twin decides, whatever the Enumeration says; 0 leaves it to the
    Enumeration."""
    (_, _, twin, n), = [c for c in _choices() if c[:2] == (model, choice)]
    stop, base = CHOICE_SETUPS[(model, choice)]
    run = lambda values: im.run_fmpy(_choice_case(model, {**base, **values}, stop))
    same = lambda a, b: not _failures(a.case, im.compare(a, b))
    only_enum = {item: run({choice: item}) for item in (1, n)}
    assert same(run({choice: 1, twin: n}), only_enum[n])
    assert same(run({choice: n, twin: 0}), only_enum[n])
    assert not same(only_enum[1], only_enum[n])
