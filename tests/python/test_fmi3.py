"""FMI 3.0 Co-Simulation FMUs (dist/fmi3/<Model>.fmu, docs/fmi3.md): the same library, state
machine and variable table as the FMI 2.0 FMUs in dist/.

- every FMI 3.0 FMU passes fmpy's validate_fmu and runs with simulate_fmu;
- its outputs equal the FMI 2.0 FMU's (same model, parameters and output interval);
- FMU state get/set round trip, and serialize -> deserialize in a second process, reproduce the
  continuation bit for bit;
- misuse (call order, unknown or mistyped value references, NaN, unsupported functions) gives
  fmi3Error with a logged message, never a crash.

Short runs keep it at a few seconds per model.
"""

import json
import math
import pathlib
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
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
        vrs = [v.valueReference for v in self.float_outputs]
        rows = []
        for k in range(n):
            t = t0 + k * h
            for name, f in self.inputs.items():
                s.setFloat64([self.vars[name].valueReference], [f(t)])
            event, terminate, early, last = s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            assert (event, terminate, early) == (False, False, False)
            assert last == pytest.approx(t + h, rel=1e-12)
            rows.append([bits(x) for x in s.getFloat64(vrs)])
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
    assert f"binaries/x86_64-linux/{model}.so" in names
    # the same variables, with FMI 3.0 types (plus the independent variable time)
    kinds = {"Real": "Float64", "Integer": "Int32", "Enumeration": "Enumeration",
             "Boolean": "Boolean", "String": "String"}
    assert [(v.name, kinds[v.type], v.causality) for v in md2.modelVariables] == \
        [(v.name, v.type, v.causality) for v in md.modelVariables if v.name != "time"]


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
    stop, h = SHORT[model]
    values = SCENARIOS[model]["values"]
    md = read_model_description(str(fmu3_path(model)))
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    kw = dict(start_values=values, stop_time=stop, output_interval=h, output=outputs)
    r3 = simulate_fmu(str(fmu3_path(model)), **kw)
    r2 = simulate_fmu(str(DIST / f"{model}.fmu"), **kw)
    assert len(r3) == len(r2) > 2
    np.testing.assert_array_equal(r3["time"], r2["time"])
    for name in outputs:
        np.testing.assert_allclose(r3[name].astype(float), r2[name].astype(float), rtol=1e-12, atol=1e-12,
                                   err_msg=name)


def test_state_round_trip_and_second_process(fmu3, tmp_path):
    stop, h = SHORT[fmu3.id]
    n = max(2, int(round(stop / h / 3)))
    s = fmu3.slave()
    fmu3.start(s)
    fmu3.run(s, 0.0, n, h)
    state = s.getFMUState()
    t0 = n * h
    first = fmu3.run(s, t0, n, h)
    s.setFMUState(state)
    assert fmu3.run(s, t0, n, h) == first, "get/set FMU state round trip"
    blob = s.serializeFMUState(state)
    restored = s.deserializeFMUState(blob)
    s.setFMUState(restored)
    assert fmu3.run(s, t0, n, h) == first, "serialize -> deserialize in the same process"
    (tmp_path / "state.bin").write_bytes(blob)
    out = subprocess.run(
        [sys.executable, str(HERE / "fmi3_worker.py"), str(fmu3.path), fmu3.unzip,
         str(tmp_path / "state.bin"), repr(t0), str(n), repr(h)],
        capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout) == first, "deserialized in a second process"
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
    out = fmu3.float_outputs[0].valueReference
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
