"""FMI 2.0 conformance (issue #20): any start time, the experiment's tolerance, unusable resource
locations.

- Start time: every FMU started at -1, 0 and 1000 s with the same steps and inputs given as
  functions of t - tStart gives the outputs of the run started at 0 s bit for bit; outputs that
  are times (PanelLock's lock times) are shifted by tStart.
- Tolerance of fmi2SetupExperiment: becomes the model's `rtol` (bit for bit the run with `rtol`
  set to it) unless the importer sets `rtol` itself, which wins; a tolerance outside `rtol`'s
  range is an error; every decision is logged in category logSolver.
- fmuResourceLocation (docs/resource_location.md): NULL still instantiates, with a warning that
  says the scene.toml is not read; a plain absolute path is used (warning, scene.toml applied); a
  missing folder is refused (NULL, the error names it): never silently different physics; the
  FMU's root folder is taken to mean its resources/ folder (warning, scene.toml applied).
"""

import math
import os
import pathlib
import re
import shutil
import struct

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

import fmi2raw
from conftest import SCENARIOS, packed
from state_walk_worker import Outputs

START_TIMES = (-1.0, 0.0, 1000.0)

# Outputs that are model times: start time + time since the start (start time - 1 s meaning "not
# yet", which no lock time can be).
TIME_OUTPUTS = {"PanelLock": re.compile(r"hinge\d+_lock_time$")}

# Runs of the start-time and tolerance tests: parameters, steps and inputs u(t - tStart). PanelLock
# runs 6 s so that the root hinge locks (at 4.9 s) and a lock time is compared.
RUNS = {
    "PanelLock": dict(values={}, step=0.05, steps=120,
                      inputs={"root_motor_torque": lambda s: 0.02 * math.sin(2.0 * s)}),
    "RopeBlock": dict(values={"segments": 20}, step=0.05, steps=40,
                      inputs={"hook0_vz": lambda s: 0.2 if s >= 0.5 - 1e-9 else 0.0}),
    "PidController": dict(values=SCENARIOS["PidController"]["values"], step=0.01, steps=300,
                          inputs=SCENARIOS["PidController"]["inputs"]),
}

_UNZIPPED = {}


def _model(name, tmp_path_factory):
    """(model description, unzip folder) of dist/<name>.fmu."""
    path = packed(name)
    if name not in _UNZIPPED:
        _UNZIPPED[name] = (read_model_description(str(path)),
                           extract(str(path), unzipdir=str(tmp_path_factory.mktemp(name + "-conf"))))
    return _UNZIPPED[name]


def _names():
    return sorted(RUNS)


def _by_name(md):
    return {v.name: v for v in md.modelVariables}


def _set(setter_real, setter_int, setter_bool, var, value):
    if var.type == "Real":
        return setter_real([var.valueReference], [float(value)])
    if var.type in ("Integer", "Enumeration"):
        return setter_int([var.valueReference], [int(value)])
    return setter_bool([var.valueReference], [bool(value)])


# ---------------------------------------------------------------------------------------------
# any start time


def _run_from(md, unzip, t0):
    """The RUNS entry started at t0 through fmpy: output rows after every step, last time."""
    run = RUNS[md.coSimulation.modelIdentifier]
    vars_ = _by_name(md)
    outputs = Outputs(md)
    s = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName=f"start-{t0}")
    s.instantiate()
    h = run["step"]
    s.setupExperiment(startTime=t0, stopTime=t0 + run["steps"] * h)
    for name, value in run["values"].items():
        _set(s.setReal, s.setInteger, s.setBoolean, vars_[name], value)
    s.enterInitializationMode()
    s.exitInitializationMode()
    rows = [outputs.read(s)]
    for k in range(run["steps"]):
        t = t0 + k * h
        # u(t - tStart) with t - tStart taken as k h: the inputs of every start time are the same
        # numbers (t0 + k h - t0 is not always k h in floating point)
        for name, u in run["inputs"].items():
            s.setReal([vars_[name].valueReference], [u(k * h)])
        s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        rows.append(outputs.read(s))
    last = s.getRealStatus(fmi2raw.LAST_SUCCESSFUL_TIME)
    s.terminate()
    s.freeInstance()
    return outputs, rows, last


def _float(text):
    """The float of an output text of Outputs.read (its bits)."""
    return struct.unpack("<d", bytes.fromhex(text))[0]


@pytest.mark.parametrize("name", _names())
def test_any_start_time_gives_the_outputs_of_a_start_at_zero(name, tmp_path_factory):
    md, unzip = _model(name, tmp_path_factory)
    run = RUNS[name]
    outputs, reference, last0 = _run_from(md, unzip, 0.0)
    assert last0 == pytest.approx(run["steps"] * run["step"], abs=1e-9)
    assert len(set(map(tuple, reference))) > run["steps"] // 2, "the outputs must change along the run"
    pattern = TIME_OUTPUTS.get(name)
    timed = [i for i, n in enumerate(outputs.names) if pattern and pattern.search(n)]
    shifted_seen = 0
    for t0 in START_TIMES:
        if t0 == 0.0:
            continue
        _, rows, last = _run_from(md, unzip, t0)
        assert last == pytest.approx(t0 + run["steps"] * run["step"], abs=1e-9), \
            f"{name} tStart={t0}: lastSuccessfulTime"
        assert len(rows) == len(reference)
        for k, (got, want) in enumerate(zip(rows, reference)):
            where = f"{name} tStart={t0}: after {k} steps (t = {t0 + k * run['step']!r} s)"
            for i in timed:
                g, w = _float(got[i]), _float(want[i])
                if w == -1.0:
                    assert g == t0 - 1.0, f"{where}: {outputs.names[i]} = {g!r}, expected tStart - 1 (not yet)"
                else:
                    shifted_seen += 1
                    assert g == pytest.approx(w + t0, rel=1e-9, abs=1e-9), \
                        f"{where}: {outputs.names[i]} = {g!r}, expected {w!r} + tStart"
            diffs = [f"{outputs.names[i]}: {g} != {w}" for i, (g, w) in enumerate(zip(got, want))
                     if i not in timed and g != w]
            assert not diffs, f"{where}: outputs differ from the run started at 0 s: {diffs[:4]}"
    if timed:
        assert shifted_seen > 0, f"{name}: no lock time was reached; the time shift was not checked"


# ---------------------------------------------------------------------------------------------
# tolerance of fmi2SetupExperiment


def _raw(name, tmp_path_factory, logging_on=True, **kwargs):
    md, unzip = _model(name, tmp_path_factory)
    lib = fmi2raw.Library(unzip, md.coSimulation.modelIdentifier)
    inst = fmi2raw.Instance(lib, md.guid, name="conformance", logging_on=logging_on, **kwargs)
    assert inst.c, f"{name}: fmi2Instantiate returned NULL: {inst.log}"
    return md, inst


def _raw_run(name, tmp_path_factory, tol=None, rtol=None, rtol_when="before setup"):
    """RUNS entry from 0 s through the raw binding; returns (output rows, log). `rtol` is set with
    fmi2SetReal `rtol_when`: "before setup", "after setup" or "in initialization mode"."""
    md, inst = _raw(name, tmp_path_factory)
    run = RUNS[name]
    vars_ = _by_name(md)
    outputs = Outputs(md)
    set_rtol = lambda: inst.set_real([vars_["rtol"].valueReference], [rtol])  # noqa: E731

    if rtol is not None and rtol_when == "before setup":
        assert set_rtol() == fmi2raw.OK
    assert inst.setup(0.0, None, tol) == fmi2raw.OK, inst.log
    if rtol is not None and rtol_when == "after setup":
        assert set_rtol() == fmi2raw.OK
    for n, value in run["values"].items():
        v = vars_[n]
        assert _set(inst.set_real, inst.set_integer, inst.set_boolean, v, value) == fmi2raw.OK
    assert inst.enter() == fmi2raw.OK, inst.log
    if rtol is not None and rtol_when == "in initialization mode":
        assert set_rtol() == fmi2raw.OK
    assert inst.exit() == fmi2raw.OK, inst.log

    groups = [(outputs.real, inst.get_real, lambda x: x.hex()),
              (outputs.integer, inst.get_integer, str),
              (outputs.boolean, inst.get_boolean, str)]

    def read():
        row = []
        for vs, get, fmt in groups:
            if vs:
                status, values = get([v.valueReference for v in vs])
                assert status == fmi2raw.OK
                row += [fmt(x) for x in values]
        return row

    rows = []
    h = run["step"]
    for k in range(run["steps"]):
        for n, u in run["inputs"].items():
            assert inst.set_real([vars_[n].valueReference], [u(k * h)]) == fmi2raw.OK
        assert inst.do_step(k * h, h) == fmi2raw.OK, f"{name}: step {k}: {inst.messages()}"
        rows.append(read())
    log = list(inst.log)
    inst.terminate()
    inst.free()
    return rows, log


def _solver_messages(log):
    return [m for (_, category, m) in log if category == "logSolver" and "fmi2SetupExperiment" in m]


def _rtol_models():
    return [n for n in _names() if any(v.name == "rtol" for v in read_model_description(str(packed(n))).modelVariables)]


@pytest.mark.parametrize("name", _rtol_models())
def test_experiment_tolerance_sets_rtol_unless_the_importer_sets_it(name, tmp_path_factory):
    md, _ = _model(name, tmp_path_factory)
    rtol = _by_name(md)["rtol"]
    default = float(rtol.start)
    tol = 1e-3
    assert tol != default

    plain, _ = _raw_run(name, tmp_path_factory)
    by_tolerance, log = _raw_run(name, tmp_path_factory, tol=tol)
    by_rtol, _ = _raw_run(name, tmp_path_factory, rtol=tol)
    assert by_tolerance != plain, f"{name}: rtol {tol} must change the run (default {default})"
    assert by_tolerance == by_rtol, f"{name}: tolerance {tol} must give the run with rtol = {tol}"
    used = _solver_messages(log)
    assert len(used) == 1 and "tolerance" in used[0] and "used as `rtol`" in used[0], (name, used)

    # the importer's own rtol wins, whenever it is set before the end of initialization
    for when in ("before setup", "after setup", "in initialization mode"):
        rows, log = _raw_run(name, tmp_path_factory, tol=1e-4, rtol=tol, rtol_when=when)
        assert rows == by_rtol, f"{name}: rtol set {when} must win over the tolerance"
        said = _solver_messages(log)
        if when != "in initialization mode":
            assert len(said) == 1 and "rtol" in said[0] and "takes precedence" in said[0], (name, when, said)


@pytest.mark.parametrize("name", _rtol_models())
def test_experiment_tolerance_outside_the_range_of_rtol_is_an_error(name, tmp_path_factory):
    md, unzip = _model(name, tmp_path_factory)
    rtol = _by_name(md)["rtol"]
    lo = float(rtol.min) if rtol.min is not None else None
    hi = float(rtol.max) if rtol.max is not None else None
    outside = []
    if lo is not None:
        outside.append(lo / 10 if lo > 0 else -1e-3)
    if hi is not None:
        outside.append(hi * 10)
    assert outside, f"{name}: rtol declares no range"
    for tol in outside:
        _, inst = _raw(name, tmp_path_factory)
        assert inst.setup(0.0, None, tol) == fmi2raw.ERROR, f"{name}: tolerance {tol} outside [{lo}, {hi}]"
        errors = inst.messages(fmi2raw.ERROR)
        # a positive tolerance is refused by rtol's range, a negative one as no tolerance at all
        said = [m for m in errors if "tolerance" in m and (tol <= 0 or "`rtol`" in m)]
        assert said, f"{name}: tolerance {tol}: {errors}"
        inst.free()
        s = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier)
        s.instantiate()
        with pytest.raises(Exception):
            s.setupExperiment(tolerance=tol)
        s.freeInstance()
    # the edges of the range are accepted (a positive minimum; PanelLock's 0 is not a tolerance)
    for tol in [x for x in (lo, hi) if x is not None and x > 0]:
        _, inst = _raw(name, tmp_path_factory)
        assert inst.setup(0.0, None, tol) == fmi2raw.OK, (name, tol, inst.messages())
        inst.free()


def test_experiment_tolerance_without_an_error_controlled_solver_is_logged_and_ignored(tmp_path_factory):
    name = "PidController"
    md, _ = _model(name, tmp_path_factory)
    assert "rtol" not in _by_name(md)
    plain, _ = _raw_run(name, tmp_path_factory)
    with_tol, log = _raw_run(name, tmp_path_factory, tol=1e-3)
    assert with_tol == plain
    said = _solver_messages(log)
    assert len(said) == 1 and "tolerance" in said[0] and "no error-controlled solver" in said[0], said


def test_experiment_tolerance_applies_again_after_reset(tmp_path_factory):
    """fmi2Reset forgets that the importer set rtol: the next experiment's tolerance is used."""
    name = "PanelLock"
    md, inst = _raw(name, tmp_path_factory)
    vr = _by_name(md)["rtol"].valueReference
    assert inst.set_real([vr], [1e-4]) == fmi2raw.OK
    assert inst.setup(0.0, None, 1e-3) == fmi2raw.OK
    assert inst.enter() == fmi2raw.OK and inst.exit() == fmi2raw.OK
    assert inst.get_real([vr]) == (fmi2raw.OK, [1e-4])
    assert inst.reset() == fmi2raw.OK
    before = len(inst.log)
    assert inst.setup(0.0, None, 1e-3) == fmi2raw.OK
    assert inst.enter() == fmi2raw.OK and inst.exit() == fmi2raw.OK
    assert inst.get_real([vr]) == (fmi2raw.OK, [1e-3])
    said = _solver_messages(inst.log[before:])
    assert len(said) == 1 and "used as `rtol`" in said[0], said
    inst.free()


# ---------------------------------------------------------------------------------------------
# fmuResourceLocation


class _Instance(fmi2raw.Instance):
    """fmi2raw.Instance with any fmuResourceLocation, NULL included (bytes or None, as given)."""

    def __init__(self, lib, guid, location):
        self.lib = lib
        self.env = fmi2raw._next_env[0]
        fmi2raw._next_env[0] += 1
        fmi2raw.LOGS[self.env] = []
        self.callbacks = fmi2raw.fmi2CallbackFunctions()
        self.callbacks.logger = fmi2raw._dispatch
        fmi2raw.fmpy.logging.addLoggerProxy(fmi2raw.byref(self.callbacks))
        self.callbacks.componentEnvironment = self.env
        self.c = lib.fmi2Instantiate(b"resources", 1, guid.encode(), location,
                                     fmi2raw.byref(self.callbacks), 0, 1)


# A parameter per model changed in a copy of its scene.toml, to see whether the file was read.
SCENE_EDITS = {
    "PanelLock": ("panel_length", "panel_length = 2.0", "panel_length = 2.5", 2.0, 2.5),
    "PidController": ("kp", "kp = 1.0", "kp = 3.0", 1.0, 3.0),
    "RopeBlock": ("segments", "segments = 100", "segments = 30", 100, 30),
}


@pytest.fixture
def edited_root(request, tmp_path, tmp_path_factory):
    """A root folder like the unpacked FMU's (modelDescription.xml, resources/) whose scene.toml
    sets SCENE_EDITS' value, and the model."""
    name = request.param
    md, unzip = _model(name, tmp_path_factory)
    root = tmp_path / "fmu root"  # a space: the URI must be percent-encoded
    (root / "resources").mkdir(parents=True)
    shutil.copy(os.path.join(unzip, "modelDescription.xml"), root / "modelDescription.xml")
    scene = pathlib.Path(unzip, "resources", "scene.toml").read_text()
    _, old, new, _, _ = SCENE_EDITS[name]
    assert scene.count(old) == 1, f"{name}: scene.toml has no line `{old}`"
    (root / "resources" / "scene.toml").write_text(scene.replace(old, new))
    return name, md, unzip, root


def _parameter(inst, md, name):
    """A parameter's value, read in initialization mode (fmi2Get* is not allowed before)."""
    assert inst.setup() == fmi2raw.OK and inst.enter() == fmi2raw.OK, inst.messages()
    v = _by_name(md)[name]
    if v.type == "Real":
        status, values = inst.get_real([v.valueReference])
    else:
        status, values = inst.get_integer([v.valueReference])
    assert status == fmi2raw.OK
    return values[0]


def _warnings(inst):
    return [(c, m) for (s, c, m) in inst.log if s == fmi2raw.WARNING]


@pytest.mark.parametrize("edited_root", [n for n in _names() if n in SCENE_EDITS], indirect=True)
def test_resource_locations_are_used_or_refused(edited_root):
    name, md, unzip, root = edited_root
    param, _, _, default, edited = SCENE_EDITS[name]
    lib = fmi2raw.Library(unzip, md.coSimulation.modelIdentifier)
    resources = root / "resources"

    # control: the file:// URI of the edited resources folder reads its scene.toml, no warning
    inst = _Instance(lib, md.guid, resources.as_uri().encode())
    assert inst.c and not _warnings(inst), inst.log
    assert _parameter(inst, md, param) == edited
    inst.free()

    # a plain absolute path: used, with a warning that says it is not a URI
    inst = _Instance(lib, md.guid, str(resources).encode())
    assert inst.c, f"{name} plain path: fmi2Instantiate returned NULL: {inst.log}"
    warnings = _warnings(inst)
    assert len(warnings) == 1 and str(resources) in warnings[0][1] and "plain path" in warnings[0][1], inst.log
    assert _parameter(inst, md, param) == edited, f"{name} plain path: its scene.toml must be applied"
    inst.free()

    # NULL: no resources given; a warning, the built-in defaults, and a working instance
    inst = _Instance(lib, md.guid, None)
    assert inst.c, f"{name} NULL: fmi2Instantiate returned NULL: {inst.log}"
    warnings = _warnings(inst)
    assert len(warnings) == 1, f"{name} NULL: {inst.log}"
    category, text = warnings[0]
    assert category == "logStatusWarning", (name, category)
    assert "NULL" in text and "scene.toml is not read" in text, f"{name} NULL: {text}"
    assert _parameter(inst, md, param) == default, f"{name} NULL: built-in default expected"
    for n, value in RUNS[name]["values"].items():
        assert _set(inst.set_real, inst.set_integer, inst.set_boolean, _by_name(md)[n], value) == fmi2raw.OK
    assert inst.exit() == fmi2raw.OK and inst.do_step(0.0, 0.01) == fmi2raw.OK, inst.messages()
    inst.free()

    # a folder that does not exist: refused, the error names it (never other physics silently)
    missing = (root / "missing").as_uri()
    inst = _Instance(lib, md.guid, missing.encode())
    assert not inst.c, f"{name} missing folder: instantiated: {inst.log}"
    errors = inst.messages(fmi2raw.ERROR)
    assert errors and missing in errors[-1] and "not an existing folder" in errors[-1], inst.log

    # the FMU's root folder: its resources/ is used
    inst = _Instance(lib, md.guid, root.as_uri().encode())
    assert inst.c, inst.log
    warnings = _warnings(inst)
    assert len(warnings) == 1, inst.log
    category, text = warnings[0]
    assert category == "logStatusWarning"
    assert root.as_uri() in text and "root folder" in text and str(resources) in text, text
    assert _parameter(inst, md, param) == edited, f"{name}: the root's resources/scene.toml must be applied"
    inst.free()
