"""FMI 3.0 Co-Simulation FMUs (dist/fmi3/<Model>.fmu, docs/fmi3.md): the same library, state
machine and variable table as the FMI 2.0 FMUs in dist/.

- every FMI 3.0 FMU passes fmpy's validate_fmu and runs with simulate_fmu;
- its outputs equal the FMI 2.0 FMU's (same model, parameters and output interval); families of
  outputs `<prefix><k>_<field>` are FMI 3.0 arrays `<prefix>_<field>` whose elements are the
  FMI 2.0 scalars, read with one value reference and nValues = number of elements;
- FMU state get/set round trip, and serialize -> deserialize in a second process, reproduce the
  continuation bit for bit;
- misuse (call order, unknown or mistyped value references, NaN, unsupported functions) gives
  fmi3Error with a logged message, never a crash.

Short runs keep it at a few seconds per model.
"""

import json
import math
import pathlib
import re
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave, fmi3LogMessageCallback
from fmpy.validation import validate_fmu

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from conftest import DIST, SCENARIOS, bits  # noqa: E402

DIST3 = DIST / "fmi3"
MODELS = ["PanelLock", "PidController", "RopeBlock"]
# (stop time, output interval) of the short runs
SHORT = {"PanelLock": (0.5, 0.05), "PidController": (1.0, 0.01), "RopeBlock": (0.3, 0.05)}
STATUS = ["OK", "Warning", "Discard", "Error", "Fatal"]


def size(v):
    """Number of values of an FMI 3.0 variable (1 for a scalar)."""
    return int(np.prod(v.shape)) if v.shape else 1


def elements(v, names2):
    """The FMI 2.0 names behind FMI 3.0 variable `v`: the scalar's own name, or for an array
    `<prefix>_<field>` the family `<prefix><k>_<field>` of `names2` in order of k (docs/fmi3.md)."""
    if not v.shape:
        return [v.name]
    prefix, field = v.name.split("_", 1)
    pattern = re.compile(rf"{re.escape(prefix)}(0|[1-9][0-9]*)_{re.escape(field)}")
    found = sorted((int(m.group(1)), n) for n in names2 if (m := pattern.fullmatch(n)))
    ks = [k for k, _ in found]
    assert ks == list(range(ks[0], ks[0] + len(ks))) and len(ks) == size(v), (v.name, found, v.shape)
    return [n for _, n in found]


def fmu3_path(model):
    path = DIST3 / f"{model}.fmu"
    if not path.exists():
        pytest.fail(f"{path} is missing: run `cargo run --release --bin mbcosim -- pack` first")
    return path


class Fmu3:
    """An unpacked FMI 3.0 FMU with helpers to drive it through fmpy."""

    def __init__(self, path, unzip):
        self.path = pathlib.Path(path)
        self.unzip = unzip
        self.md = read_model_description(str(path))
        self.id = self.md.coSimulation.modelIdentifier
        self.vars = {v.name: v for v in self.md.modelVariables}
        sc = SCENARIOS.get(self.id, {})
        self.values = sc.get("values", {})
        self.inputs = sc.get("inputs", {})
        self.log = []

    @property
    def float_outputs(self):
        return [v for v in self.md.modelVariables if v.causality == "output" and v.type == "Float64"]

    @property
    def scalar_output(self):
        """A scalar Float64 output."""
        return next(v for v in self.float_outputs if not v.shape)

    @property
    def arrays(self):
        return [v for v in self.md.modelVariables if v.shape]

    def slave(self, name="inst", logging_on=False):
        s = FMU3Slave(guid=self.md.guid, unzipDirectory=self.unzip, modelIdentifier=self.id,
                      instanceName=name)

        def log(env, status, category, message):
            self.log.append((STATUS[status], category.decode(), message.decode()))

        s.instantiate(loggingOn=logging_on, logMessage=log)
        return s

    def set_values(self, s, values):
        for name, value in values.items():
            v = self.vars[name]
            if v.type == "Float64":
                s.setFloat64([v.valueReference], [float(value)])
            elif v.type == "Int32":
                s.setInt32([v.valueReference], [int(value)])
            elif v.type == "Enumeration":
                s.setInt64([v.valueReference], [int(value)])
            elif v.type == "Boolean":
                s.setBoolean([v.valueReference], [bool(value)])
            else:
                s.setString([v.valueReference], [str(value)])

    def start(self, s):
        self.set_values(s, self.values)
        s.enterInitializationMode(startTime=0.0)
        s.exitInitializationMode()

    def run(self, s, t0, n, h):
        """n steps from t0; the bits of every Float64 output (arrays element by element) per step."""
        vrs = [v.valueReference for v in self.float_outputs]
        n_values = sum(size(v) for v in self.float_outputs)
        rows = []
        for k in range(n):
            t = t0 + k * h
            for name, f in self.inputs.items():
                s.setFloat64([self.vars[name].valueReference], [f(t)])
            event, terminate, early, last = s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            assert (event, terminate, early) == (False, False, False)
            assert last == pytest.approx(t + h, rel=1e-12)
            rows.append([bits(x) for x in s.getFloat64(vrs, nValues=n_values)])
        return rows

    def errors(self):
        return [m for st, _, m in self.log if st == "Error"]


@pytest.fixture(params=MODELS)
def fmu3(request, tmp_path_factory):
    path = fmu3_path(request.param)
    return Fmu3(path, extract(str(path), str(tmp_path_factory.mktemp(request.param))))


@pytest.mark.parametrize("model", MODELS)
def test_validate_fmu_finds_no_problems(model):
    path = fmu3_path(model)
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    md2 = read_model_description(str(DIST / f"{model}.fmu"))
    assert md.fmiVersion == "3.0"
    assert md.guid == md2.guid, "instantiationToken is the FMI 2.0 GUID"
    names = zipfile.ZipFile(path).namelist()
    assert {n for n in names if n.startswith("binaries/")} == {
        f"binaries/x86_64-linux/{model}.so", f"binaries/x86_64-windows/{model}.dll",
        f"binaries/aarch64-linux/{model}.so"}
    # the same variables, with FMI 3.0 types (plus the independent variable time), an array
    # standing for its elements; value references unique
    kinds = {"Real": "Float64", "Integer": "Int32", "Enumeration": "Enumeration",
             "Boolean": "Boolean", "String": "String"}
    names2 = [v.name for v in md2.modelVariables]
    expanded = [(n, v.type, v.causality, v.variability, (v.unit or (v.declaredType.unit if v.declaredType else None)) if v.type == "Float64" else None)
                for v in md.modelVariables if v.name != "time" for n in elements(v, names2)]
    assert sorted(expanded) == sorted((v.name, kinds[v.type], v.causality, v.variability,
                                       v.unit if v.type == "Real" else None) for v in md2.modelVariables)
    vrs = [v.valueReference for v in md.modelVariables]
    assert len(set(vrs)) == len(vrs)
    # arrays: outputs only, one dimension, in every model with indexed families
    for v in md.modelVariables:
        if v.shape:
            assert v.causality == "output" and len(v.shape) == 1 and v.shape[0] >= 2, v.name
        elif v.causality in ("input", "parameter"):
            continue
        else:
            assert not re.fullmatch(r"[A-Za-z]+(0|[1-9][0-9]*)_.+", v.name) or v.name == "time", \
                f"{v.name} should be part of an array"
    expected = {"PanelLock": {"hinge_angle": 7, "hinge_latched": 7, "panel_mode1": 6},
                "RopeBlock": {"contact_normal": 8, "contact_slip": 8, "sling_tension_hook": 4, "hook_x": 4},
                "PidController": {}}[model]
    shapes = {v.name: v.shape for v in md.modelVariables if v.shape}
    for name, n in expected.items():
        assert shapes.get(name) == (n,), (name, shapes.get(name))
    if model != "PidController":
        assert shapes
    # ModelStructure: each output once (an array by its one reference); an array's initial
    # dependencies are the union of its elements' FMI 2.0 dependencies
    assert [u.variable.name for u in md.outputs] == [v.name for v in md.modelVariables if v.causality == "output"]
    deps2 = {u.variable.name: u.dependencies for u in md2.initialUnknowns}
    unknowns3 = md.initialUnknowns
    assert sorted(n for u in unknowns3 for n in elements(u.variable, names2)) == sorted(deps2)
    for u in unknowns3:
        want = [deps2[n] for n in elements(u.variable, names2)]
        if any(d is None for d in want):
            assert u.dependencies is None, u.variable.name
        else:
            assert {d.name for d in u.dependencies} == {d.name for ds in want for d in ds}, u.variable.name


@pytest.mark.parametrize("model", MODELS)
def test_fmutool_check_passes(model):
    import shutil
    venv_tool = pathlib.Path(sys.executable).parent / "fmutool"
    fmutool = str(venv_tool) if venv_tool.exists() else shutil.which("fmutool")
    assert fmutool, "fmutool (fmu-manipulation-toolbox) is not installed"
    r = subprocess.run([fmutool, "-input", str(fmu3_path(model)), "-check"], capture_output=True, text=True,
                       timeout=120)
    out = r.stdout + r.stderr
    assert r.returncode == 0, out
    assert "No semantic error against the FMI-3 standard" in out and "compliant with FMI-3.0" in out, out
    assert "ERROR" not in out and "WARNING" not in out, out


@pytest.mark.parametrize("model", MODELS)
def test_simulate_fmu_with_defaults_runs(model):
    stop, _ = SHORT[model]
    res = simulate_fmu(str(fmu3_path(model)), stop_time=stop)
    assert res["time"][-1] == pytest.approx(stop)
    for name in res.dtype.names:
        assert np.all(np.isfinite(res[name].astype(float))), name


@pytest.mark.parametrize("model", MODELS)
def test_results_equal_the_fmi2_fmu(model):
    """simulate_fmu records an array as one column of shape (n,); its elements equal the FMI 2.0
    FMU's scalars."""
    stop, h = SHORT[model]
    values = SCENARIOS[model]["values"]
    md = read_model_description(str(fmu3_path(model)))
    md2 = read_model_description(str(DIST / f"{model}.fmu"))
    names2 = [v.name for v in md2.modelVariables]
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    kw = dict(start_values=values, stop_time=stop, output_interval=h)
    r3 = simulate_fmu(str(fmu3_path(model)), output=[v.name for v in outputs], **kw)
    r2 = simulate_fmu(str(DIST / f"{model}.fmu"), output=[n for v in outputs for n in elements(v, names2)], **kw)
    assert len(r3) == len(r2) > 2
    np.testing.assert_array_equal(r3["time"], r2["time"])
    for v in outputs:
        col = r3[v.name]
        assert col.shape == (len(r3),) + (v.shape or ()), (v.name, col.shape)
        for j, name in enumerate(elements(v, names2)):
            got = col[:, j] if v.shape else col
            np.testing.assert_allclose(got.astype(float), r2[name].astype(float), rtol=1e-12, atol=1e-12,
                                       err_msg=f"{v.name}[{j}] vs {name}")


@pytest.mark.parametrize("model", ["PanelLock", "RopeBlock"])
def test_arrays_read_with_one_reference_equal_the_fmi2_scalars(model, tmp_path):
    """Step both FMUs side by side with the scenario's inputs: every array read with
    get<Type>([vr], nValues=n) equals the n FMI 2.0 scalars (<= 1e-12), at every step."""
    stop, h = SHORT[model]
    path3, path2 = fmu3_path(model), DIST / f"{model}.fmu"
    f3 = Fmu3(path3, extract(str(path3), str(tmp_path / "3")))
    md2 = read_model_description(str(path2))
    vars2 = {v.name: v for v in md2.modelVariables}
    s2 = FMU2Slave(guid=md2.guid, unzipDirectory=extract(str(path2), str(tmp_path / "2")),
                   modelIdentifier=f3.id, instanceName="fmi2")
    s2.instantiate()
    s2.setupExperiment(startTime=0.0)
    for name, value in f3.values.items():
        v = vars2[name]
        {"Real": s2.setReal, "Integer": s2.setInteger, "Enumeration": s2.setInteger,
         "Boolean": s2.setBoolean}[v.type]([v.valueReference], [value])
    s2.enterInitializationMode()
    s2.exitInitializationMode()
    s3 = f3.slave()
    f3.start(s3)
    get3 = {"Float64": s3.getFloat64, "Int32": s3.getInt32, "Boolean": s3.getBoolean}
    get2 = {"Float64": s2.getReal, "Int32": s2.getInteger, "Boolean": s2.getBoolean}
    assert {v.type for v in f3.arrays} <= set(get3)
    checked = 0
    for k in range(int(round(stop / h))):
        t = k * h
        for name, f in f3.inputs.items():
            s3.setFloat64([f3.vars[name].valueReference], [f(t)])
            s2.setReal([vars2[name].valueReference], [f(t)])
        s3.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        s2.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        for v in f3.arrays:
            names = elements(v, vars2)
            got = get3[v.type]([v.valueReference], nValues=len(names))
            want = get2[v.type]([vars2[n].valueReference for n in names])
            np.testing.assert_allclose(np.asarray(got, float), np.asarray(want, float), rtol=1e-12, atol=1e-12,
                                       err_msg=f"{v.name} at t = {t + h}")
            checked += 1
        # several arrays and a scalar in one call: the values are concatenated in order
        mixed = [f3.scalar_output] + [v for v in f3.arrays if v.type == "Float64"][:2]
        got = s3.getFloat64([v.valueReference for v in mixed], nValues=sum(size(v) for v in mixed))
        want = s2.getReal([vars2[n].valueReference for v in mixed for n in elements(v, vars2)])
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)
    assert checked >= 2 * len(f3.arrays)
    assert f3.errors() == []
    for s in (s3, s2):
        s.terminate()
        s.freeInstance()


def test_array_misuse_gives_fmi3_error_with_a_message(tmp_path):
    """A wrong nValues, the old reference of a folded element, and setting an output array are
    refused with a logged message; the instance works again after a reset."""
    path = fmu3_path("RopeBlock")
    f3 = Fmu3(path, extract(str(path), str(tmp_path)))
    arr = f3.vars["contact_normal"]
    n = size(arr)
    assert n == 8
    # nothing is settable as an array: inputs and parameters stay scalars (docs/fmi3.md)
    assert all(v.causality == "output" for v in f3.arrays)
    s = f3.slave()
    f3.start(s)
    s.doStep(0.0, 0.05)
    for wrong in (1, n - 1, n + 1):
        expect_error(f3, lambda: s.getFloat64([arr.valueReference], nValues=wrong),
                     f"nValues = {wrong}", f"`contact_normal` ({arr.valueReference}) has {n}")
        s.reset()
        f3.start(s)
    slip = f3.vars["contact_slip"]
    expect_error(f3, lambda: s.getInt32([slip.valueReference, slip.valueReference], nValues=n),
                 f"nValues = {n}", f"does not match the {2 * n} values")
    s.reset()
    f3.start(s)
    md2 = read_model_description(str(DIST / "RopeBlock.fmu"))
    old = next(v.valueReference for v in md2.modelVariables if v.name == "contact3_normal")
    expect_error(f3, lambda: s.getFloat64([old]), f"unknown value reference {old}",
                 "`contact3_normal` is element 3 of the array `contact_normal`")
    s.reset()
    f3.start(s)
    expect_error(f3, lambda: s.setFloat64([arr.valueReference], [0.0] * n), "cannot be set", "`contact_normal`")
    s.reset()
    f3.start(s)
    s.doStep(0.0, 0.05)
    values = s.getFloat64([arr.valueReference], nValues=n)
    assert len(values) == n and all(math.isfinite(x) for x in values)
    s.terminate()
    s.freeInstance()


def test_state_round_trip_and_second_process(fmu3, tmp_path):
    """fmi3Get/SetFMUState, fmi3Serialize/DeserializeFMUState in the same and a second process,
    with the scenario's inputs changing, for every item of the model's `integrator`
    enumeration (the FMI 2.0 walk, test_state_walk.py, checks every communication point)."""
    integ = fmu3.vars.get("integrator")
    items = [None] if integ is None else [int(i.value) for i in integ.declaredType.items]
    base = dict(fmu3.values)
    for item in items:
        fmu3.values = base if item is None else {**base, "integrator": item}
        _state_round_trip(fmu3, tmp_path, f"integrator {item}")


def _state_round_trip(fmu3, tmp_path, label):
    stop, h = SHORT[fmu3.id]
    n = max(2, int(round(stop / h / 3)))
    s = fmu3.slave()
    fmu3.start(s)
    fmu3.run(s, 0.0, n, h)
    state = s.getFMUState()
    t0 = n * h
    first = fmu3.run(s, t0, n, h)
    s.setFMUState(state)
    assert fmu3.run(s, t0, n, h) == first, f"{label}: get/set FMU state round trip"
    blob = s.serializeFMUState(state)
    restored = s.deserializeFMUState(blob)
    s.setFMUState(restored)
    assert fmu3.run(s, t0, n, h) == first, f"{label}: serialize -> deserialize in the same process"
    (tmp_path / "state.bin").write_bytes(blob)
    out = subprocess.run(
        [sys.executable, str(HERE / "fmi3_worker.py"), str(fmu3.path), fmu3.unzip,
         str(tmp_path / "state.bin"), repr(t0), str(n), repr(h)],
        capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout) == first, f"{label}: deserialized in a second process"
    s.freeFMUState(state)
    s.freeFMUState(restored)
    s.terminate()
    s.freeInstance()
    assert fmu3.errors() == []


def expect_error(fmu, call, *needles):
    """`call` fails with fmi3Error and logs an error message containing every needle."""
    before = len(fmu.errors())
    with pytest.raises(FMICallException, match=r"status 3 \(error\)"):
        call()
    new = fmu.errors()[before:]
    assert new, "no message logged"
    for needle in needles:
        assert any(needle in m for m in new), (needle, new)


def test_misuse_gives_fmi3_error_with_a_message(fmu3):
    s = fmu3.slave()
    out = fmu3.scalar_output.valueReference
    # wrong call order: stepping and reading outputs before initialization
    expect_error(fmu3, lambda: s.doStep(0.0, 0.01), "fmi3DoStep", "illegal call sequence")
    s.reset()
    expect_error(fmu3, lambda: s.exitInitializationMode(), "illegal call sequence")
    s.reset()
    fmu3.start(s)
    expect_error(fmu3, lambda: s.enterInitializationMode(), "illegal call sequence")
    s.reset()
    fmu3.start(s)
    # unknown value reference, and a known one through the wrong type
    expect_error(fmu3, lambda: s.getFloat64([123456]), "unknown value reference 123456")
    s.reset()
    fmu3.start(s)
    expect_error(fmu3, lambda: s.getInt32([out]), f"value reference {out}", "Float64")
    s.reset()
    fmu3.start(s)
    expect_error(fmu3, lambda: s.getInt8([0]), "no Int8 variables")
    s.reset()
    fmu3.start(s)
    # NaN into a real parameter or input
    target = next(iter(fmu3.inputs), None) or next(
        v.name for v in fmu3.md.modelVariables if v.causality == "parameter" and v.type == "Float64"
        and v.variability == "tunable")
    expect_error(fmu3, lambda: s.setFloat64([fmu3.vars[target].valueReference], [math.nan]), target)
    s.reset()
    fmu3.start(s)
    # unsupported functions
    expect_error(fmu3, lambda: s.enterEventMode(), "not supported")
    s.reset()
    fmu3.start(s)
    # the instance still works after all that
    s.doStep(0.0, SHORT[fmu3.id][1])
    assert all(math.isfinite(x) for x in s.getFloat64([out]))
    t = s.getFloat64([fmu3.vars["time"].valueReference])[0]
    assert t == pytest.approx(SHORT[fmu3.id][1])
    s.terminate()
    s.freeInstance()


def test_wrong_token_and_model_exchange_are_refused(fmu3):
    s = FMU3Slave(guid="{not-a-token}", unzipDirectory=fmu3.unzip, modelIdentifier=fmu3.id, instanceName="x")
    log = []
    with pytest.raises(Exception, match="Failed to instantiate"):
        s.instantiate(logMessage=lambda env, st, cat, msg: log.append(msg.decode()))
    assert any("unknown instantiationToken" in m for m in log), log
    from fmpy.fmi3 import FMU3Model
    m = FMU3Model(guid=fmu3.md.guid, unzipDirectory=fmu3.unzip, modelIdentifier=fmu3.id, instanceName="me")
    log.clear()
    with pytest.raises(Exception, match="Failed to instantiate"):
        m.instantiate(logMessage=lambda env, st, cat, msg: log.append(msg.decode()))
    assert any("Model Exchange is not provided" in m for m in log), log


# Every function of the FMI 3.0 headers (fmi3FunctionTypes.h): common, Model Exchange,
# Co-Simulation, Scheduled Execution.
FMI3_FUNCTIONS = """
GetVersion SetDebugLogging InstantiateModelExchange InstantiateCoSimulation
InstantiateScheduledExecution FreeInstance EnterInitializationMode ExitInitializationMode
EnterEventMode Terminate Reset
GetFloat32 GetFloat64 GetInt8 GetUInt8 GetInt16 GetUInt16 GetInt32 GetUInt32 GetInt64 GetUInt64
GetBoolean GetString GetBinary GetClock
SetFloat32 SetFloat64 SetInt8 SetUInt8 SetInt16 SetUInt16 SetInt32 SetUInt32 SetInt64 SetUInt64
SetBoolean SetString SetBinary SetClock
GetNumberOfVariableDependencies GetVariableDependencies
GetFMUState SetFMUState FreeFMUState SerializedFMUStateSize SerializeFMUState DeserializeFMUState
GetDirectionalDerivative GetAdjointDerivative EnterConfigurationMode ExitConfigurationMode
GetIntervalDecimal GetIntervalFraction GetShiftDecimal GetShiftFraction
SetIntervalDecimal SetIntervalFraction SetShiftDecimal SetShiftFraction
EvaluateDiscreteStates UpdateDiscreteStates
EnterContinuousTimeMode CompletedIntegratorStep SetTime SetContinuousStates
GetContinuousStateDerivatives GetEventIndicators GetContinuousStates GetNominalsOfContinuousStates
GetNumberOfEventIndicators GetNumberOfContinuousStates
EnterStepMode GetOutputDerivatives DoStep
ActivateModelPartition
""".split()


def test_every_fmi3_function_is_exported(fmu3):
    import ctypes
    lib = ctypes.CDLL(str(pathlib.Path(fmu3.unzip) / "binaries" / "x86_64-linux" / f"{fmu3.id}.so"))
    assert len(FMI3_FUNCTIONS) == 75
    missing = [f for f in FMI3_FUNCTIONS if not hasattr(lib, "fmi3" + f)]
    assert missing == []
    lib.fmi3GetVersion.restype = ctypes.c_char_p
    assert lib.fmi3GetVersion() == b"3.0"
