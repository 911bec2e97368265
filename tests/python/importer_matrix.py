"""One co-simulation case run through three FMI 2.0 importers with the same semantics, and the
comparison of their results (used by test_importer_matrix.py; docs/importer_matrix.md).

A case is a set of FMU instances, start values, connections output -> input and a fixed
communication grid. Every importer runs it as a Jacobi (explicit) master:

- setupExperiment(startTime) without tolerance and without stop time, as libcosim and Ecos call it;
- start values set before exitInitializationMode, connections propagated in initialization mode
  and once more after exitInitializationMode (libcosim and Ecos both do this);
- at each communication point t_k every instance steps from t_k with the inputs set at t_k; then
  all connected outputs are read and only then set on their inputs.

Outputs (every variable of causality output, Real/Integer/Boolean, of every instance) are
recorded at t_1 .. t_n, after each step and before inputs are set; none of the packaged models
has direct feedthrough (their outputs change only in doStep), so this is also what libcosim's
and Ecos's observers see.

The importers differ in the doubles they pass to fmi2DoStep for the same grid (TIME_MODES):
libcosim keeps time in integer nanoseconds and passes h_k = t_{k+1} - t_k of the rounded time
points (differs from the nominal step by up to one ulp of t); Ecos passes the nominal h and
accumulates t. fmpy's loop can reproduce either (`run_fmpy(case, time_mode)`).
"""

import atexit
import dataclasses
import math
import pathlib
import shutil
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

# Importers of the matrix: module to import -> how it gets installed (for skip messages).
IMPORTERS = {
    "fmpy": "tests/python/requirements.txt",
    "libcosimpy": "tests/python/requirements.txt",
    "ecospy": "tests/python/requirements.txt (its libecosc.so needs apt libtbb12)",
}

# fmpy time mode that reproduces an importer's doStep arguments:
#   "grid":     t_k = start + (k * h_ns) / 1e9 and the nominal h (a plain fixed-step loop)
#   "libcosim": t_k as "grid", h_k = t_{k+1} - t_k (libcosim's to_double_duration(d, t_k))
#   "ecos":     t_{k+1} = t_k + h accumulated in floating point, the nominal h
TIME_MODES = ("grid", "libcosim", "ecos")
TIME_MODE_OF = {"fmpy": "grid", "libcosimpy": "libcosim", "ecospy": "ecos"}

RTOL = 1e-9
# Floor of the relative comparison, per output, as a fraction of that output's largest magnitude
# over the run (both importers): |a - b| <= RTOL * max(|a|, |b|, FLOOR * peak). Without a floor a
# zero crossing turns round-off-sized differences into relative differences of order one.
FLOOR = 1e-6


@dataclasses.dataclass
class Case:
    """A co-simulation experiment: instances, start values, connections, communication grid."""

    name: str
    models: dict  # instance name -> path of the .fmu
    step_ns: int  # communication step [ns]
    n_steps: int
    start: float = 0.0
    values: dict = dataclasses.field(default_factory=dict)  # instance -> {variable: value}
    connections: list = dataclasses.field(default_factory=list)  # (src inst, output, dst inst, input)

    @property
    def step(self):
        return self.step_ns / 1e9

    def time(self, k):
        """Communication point k (libcosim's grid: exact nanoseconds, one rounding)."""
        return self.start + (k * self.step_ns) / 1e9

    @property
    def stop(self):
        return self.time(self.n_steps)


_MD = {}
_UNZIPPED = {}


def model_description(path):
    path = pathlib.Path(path)
    if path not in _MD:
        _MD[path] = read_model_description(str(path))
    return _MD[path]


def variables(path):
    return {v.name: v for v in model_description(path).modelVariables}


def outputs(path):
    """The output variables compared, in model-description order."""
    out = [v for v in model_description(path).modelVariables if v.causality == "output"]
    unsupported = [v.name for v in out if v.type not in ("Real", "Integer", "Boolean")]
    assert not unsupported, f"outputs of a type the matrix does not compare: {unsupported}"
    return out


def to_ns(seconds):
    ns = round(seconds * 1e9)
    assert ns > 0 and abs(ns / 1e9 - seconds) <= 1e-15 * max(1.0, abs(seconds)), \
        f"{seconds!r} s is not a whole number of nanoseconds"
    return ns


def default_experiment(path):
    """The case of an FMU's DefaultExperiment, read from the FMU itself (no start values)."""
    de = model_description(path).defaultExperiment
    assert de is not None and de.stopTime is not None and de.stepSize is not None, \
        f"{path} has no complete DefaultExperiment"
    start = float(de.startTime or 0.0)
    step_ns = to_ns(float(de.stepSize))
    n = round((float(de.stopTime) - start) * 1e9 / step_ns)
    assert math.isclose(start + n * step_ns / 1e9, float(de.stopTime), rel_tol=1e-12), \
        "stopTime is not a whole number of steps"
    return Case(name=pathlib.Path(path).stem, models={"model": pathlib.Path(path)},
                step_ns=step_ns, n_steps=n, start=start)


def pid_panel_lock(dist, stop=40.0):
    """The PID loop of test_panel_lock.py: one panel, springs and latches off, the PID's output
    drives the root motor torque and the root hinge angle is its measurement (set point 1 rad)."""
    step_ns = to_ns(0.02)
    return Case(
        name="PID+PanelLock",
        models={"array": pathlib.Path(dist) / "PanelLock.fmu", "pid": pathlib.Path(dist) / "PidController.fmu"},
        step_ns=step_ns,
        n_steps=round(stop * 1e9 / step_ns),
        values={
            "array": {"n_panels": 1, "latches": False, "root_spring_preload": 0.0, "root_spring_stiffness": 0.0,
                      "panel_spring_preload": 0.0, "panel_spring_stiffness": 0.0, "hinge_damping": 0.5},
            "pid": {"kp": 8.0, "ki": 1.0, "kd": 12.0, "Tf": 0.05, "setpoint": 1.0, "u_min": -5.0, "u_max": 5.0},
        },
        connections=[("array", "hinge0_angle", "pid", "measurement"), ("pid", "u", "array", "root_motor_torque")],
    )


def typed(var, value):
    """A start value as the Python type of its FMI variable type."""
    if var.type == "Real":
        return float(value)
    if var.type == "Integer":
        return int(value)
    if var.type == "Boolean":
        return bool(value)
    raise AssertionError(f"{var.name}: start values of type {var.type} are not supported by every importer "
                         "(libcosim ignores Enumeration variables)")


class Result:
    """Recorded outputs: name 'instance.variable' -> array over t_1 .. t_n; wall time [s]."""

    def __init__(self, importer, case):
        self.importer = importer
        self.case = case
        self.series = {}
        self.wall = 0.0

    def append(self, instance, vars_, values):
        for v, x in zip(vars_, values):
            self.series.setdefault(f"{instance}.{v.name}", []).append(x)

    def finish(self, wall):
        self.wall = wall
        self.series = {k: np.asarray(v, dtype=float) for k, v in self.series.items()}
        for k, v in self.series.items():
            assert len(v) == self.case.n_steps, f"{self.importer}: {k} has {len(v)} samples, expected {self.case.n_steps}"
        return self


def _split(vars_):
    by = {"Real": [], "Integer": [], "Boolean": []}
    for v in vars_:
        by[v.type].append(v)
    return by


def run_fmpy(case, time_mode="grid"):
    """fmpy's FMU2Slave driven by an explicit Jacobi loop (fmpy has no master for several FMUs).
    `time_mode` picks the doubles passed to doStep (see TIME_MODES)."""
    assert time_mode in TIME_MODES
    t0 = time.perf_counter()
    slaves = {}
    for inst, path in case.models.items():
        if path not in _UNZIPPED:
            _UNZIPPED[path] = extract(str(path), unzipdir=tempfile.mkdtemp(prefix=f"matrix-{path.stem}-"))
            atexit.register(shutil.rmtree, _UNZIPPED[path], ignore_errors=True)
        md = model_description(path)
        s = FMU2Slave(guid=md.guid, unzipDirectory=_UNZIPPED[path], modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=inst)
        s.instantiate()
        slaves[inst] = s
    vars_ = {inst: variables(path) for inst, path in case.models.items()}

    def set_value(inst, name, value):
        v = vars_[inst][name]
        if v.type == "Enumeration":  # fmpy sets the named choices (fmi2SetInteger); the C++ masters cannot
            slaves[inst].setInteger([v.valueReference], [int(value)])
            return
        value = typed(v, value)
        {"Real": slaves[inst].setReal, "Integer": slaves[inst].setInteger,
         "Boolean": slaves[inst].setBoolean}[v.type]([v.valueReference], [value])

    def get_value(inst, name):
        v = vars_[inst][name]
        return {"Real": slaves[inst].getReal, "Integer": slaves[inst].getInteger,
                "Boolean": slaves[inst].getBoolean}[v.type]([v.valueReference])[0]

    def exchange():
        got = [get_value(a, x) for (a, x, _, _) in case.connections]  # every output first (Jacobi)
        for (_, _, b, y), value in zip(case.connections, got):
            set_value(b, y, value)

    for s in slaves.values():
        s.setupExperiment(startTime=case.start)
        s.enterInitializationMode()
    for inst, values in case.values.items():
        for name, value in values.items():
            set_value(inst, name, value)
    for _ in range(len(slaves)):
        exchange()
    for s in slaves.values():
        s.exitInitializationMode()
    exchange()

    res = Result(f"fmpy ({time_mode} time)", case)
    outs = {inst: _split(outputs(path)) for inst, path in case.models.items()}
    t = case.start
    for k in range(case.n_steps):
        if time_mode != "ecos":
            t = case.time(k)
        h = case.time(k + 1) - t if time_mode == "libcosim" else case.step
        for s in slaves.values():
            s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        t += h
        for inst, by in outs.items():
            s = slaves[inst]
            res.append(inst, by["Real"], s.getReal([v.valueReference for v in by["Real"]]) if by["Real"] else [])
            res.append(inst, by["Integer"], s.getInteger([v.valueReference for v in by["Integer"]]) if by["Integer"] else [])
            res.append(inst, by["Boolean"], s.getBoolean([v.valueReference for v in by["Boolean"]]) if by["Boolean"] else [])
        exchange()
    for s in slaves.values():
        s.terminate()
        s.freeInstance()
    return res.finish(time.perf_counter() - t0)


def run_libcosimpy(case):
    """libcosim's fixed-step algorithm (Jacobi: all slaves step, then every connection is
    transferred); one `step()` per communication point, outputs from a last-value observer."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    assert case.start == 0.0, "libcosimpy's CosimExecution.from_step_size starts at t = 0"
    log_output_level(CosimLogLevel.ERROR)
    t0 = time.perf_counter()
    ex = CosimExecution.from_step_size(step_size=case.step_ns)
    keep = []  # the local slaves must outlive the execution's use of them
    idx = {}
    for inst, path in case.models.items():
        slave = CosimLocalSlave(fmu_path=str(path), instance_name=inst)
        keep.append(slave)
        idx[inst] = ex.add_local_slave(local_slave=slave)
        assert idx[inst] >= 0, f"libcosim could not load {path}"
    for inst, values in case.values.items():
        vs = variables(case.models[inst])
        for name, value in values.items():
            v = vs[name]
            value = typed(v, value)
            ok = {"Real": ex.real_initial_value, "Integer": ex.integer_initial_value,
                  "Boolean": ex.boolean_initial_value}[v.type](idx[inst], v.valueReference, value)
            assert ok, f"libcosim refused the start value {inst}.{name} = {value!r}"
    for a, x, b, y in case.connections:
        va, vb = variables(case.models[a])[x], variables(case.models[b])[y]
        assert va.type == vb.type
        connect = {"Real": ex.connect_real_variables, "Integer": ex.connect_integer_variables,
                   "Boolean": ex.connect_boolean_variables}[va.type]
        assert connect(idx[a], va.valueReference, idx[b], vb.valueReference) == 0, \
            f"libcosim refused the connection {a}.{x} -> {b}.{y}"
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)

    res = Result("libcosimpy", case)
    outs = {inst: _split(outputs(path)) for inst, path in case.models.items()}
    for _ in range(case.n_steps):
        assert ex.step(1), "libcosim step failed"
        for inst, by in outs.items():
            i = idx[inst]
            for kind, get in (("Real", obs.last_real_values), ("Integer", obs.last_integer_values),
                              ("Boolean", obs.last_boolean_values)):
                if by[kind]:
                    res.append(inst, by[kind], get(i, [v.valueReference for v in by[kind]]))
    status = ex.status()
    assert abs(status.current_time - case.step_ns * case.n_steps) == 0, \
        f"libcosim ended at {status.current_time} ns"
    del ex, obs, keep
    return res.finish(time.perf_counter() - t0)


def run_ecospy(case):
    """Ecos's fixed-step algorithm (each instance: apply its input sets, doStep, read its
    outputs; then every connection is transferred and set). Ecos accumulates its time,
    t_{k+1} = t_k + h in floating point, rather than using `case.time(k)`."""
    from ecospy import EcosLib, EcosSimulation, EcosSimulationStructure

    EcosLib.set_log_level("warn")
    t0 = time.perf_counter()
    res = Result("ecospy", case)
    outs = {inst: outputs(path) for inst, path in case.models.items()}
    with EcosSimulationStructure() as ss:
        for inst, path in case.models.items():
            ss.add_model(inst, str(path))
        for a, x, b, y in case.connections:
            va, vb = variables(case.models[a])[x], variables(case.models[b])[y]
            assert va.type == vb.type == "Real", "only Real connections are wired for Ecos"
            ss.make_real_connection(f"{a}::{x}", f"{b}::{y}")
        params = {f"{inst}::{name}": typed(variables(case.models[inst])[name], value)
                  for inst, values in case.values.items() for name, value in values.items()}
        if params:
            assert ss.add_parameter_set("start", params), EcosLib.get_last_error()
        with EcosSimulation(structure=ss, step_size=case.step) as sim:
            assert sim.init(start_time=case.start, parameter_set="start" if params else None), \
                EcosLib.get_last_error()
            getters = {"Real": sim.get_real, "Integer": sim.get_integer, "Boolean": sim.get_bool}
            for _ in range(case.n_steps):
                sim.step(1)
                for inst, vs in outs.items():
                    res.append(inst, vs, [getters[v.type](f"{inst}::{v.name}") for v in vs])
            end = sim.get_time()
            assert math.isclose(end, case.stop, rel_tol=1e-12), f"Ecos ended at {end!r} s"
            sim.terminate()
    return res.finish(time.perf_counter() - t0)


def choice_parameters(path):
    """The choice parameters of an FMU: (Enumeration variable, its Integer twin, number of items).
    Every Enumeration parameter must have a twin `<name>_number` (docs/choice_parameters.md)."""
    md = model_description(path)
    vs = variables(path)
    items = {t.name: len(t.items) for t in md.typeDefinitions if t.type == "Enumeration"}
    out = []
    for v in md.modelVariables:
        if v.type == "Enumeration" and v.causality == "parameter":
            twin = vs.get(f"{v.name}_number")
            assert twin is not None and twin.type == "Integer" and twin.causality == "parameter", \
                f"{path.name}: the Enumeration parameter {v.name} has no Integer twin {v.name}_number"
            assert int(twin.start) == 0 and int(twin.min) == 0 and int(twin.max) == items[v.declaredType.name], \
                f"{path.name}: {twin.name} is not 0 (start) .. number of items"
            out.append((v, twin, items[v.declaredType.name]))
    return out


RUNNERS = {"fmpy": run_fmpy, "libcosimpy": run_libcosimpy, "ecospy": run_ecospy}


@dataclasses.dataclass
class Difference:
    """Largest difference of one output between two runs."""

    name: str
    rel: float  # max |a-b| / max(|a|, |b|, FLOOR * peak): the tested quantity (<= RTOL)
    abs: float  # max |a-b|
    peak: float  # max |a|, |b| over the run
    k: int  # index (0-based, t_{k+1}) where `rel` is largest


def compare(ref, got):
    """Per-output differences of `got` against `ref`, largest relative first."""
    assert ref.series.keys() == got.series.keys()
    diffs = []
    for name, a in ref.series.items():
        b = got.series[name]
        with np.errstate(invalid="ignore"):
            both_nan = np.isnan(a) & np.isnan(b)
        peak = float(np.nanmax(np.maximum(np.abs(a), np.abs(b)))) if not both_nan.all() else 0.0
        d = np.where(both_nan, 0.0, np.abs(a - b))
        denom = np.maximum(np.maximum(np.abs(a), np.abs(b)), FLOOR * peak)
        rel = np.where(d == 0.0, 0.0, d / np.where(denom > 0.0, denom, 1.0))
        rel = np.where(np.isnan(rel) | ((denom == 0.0) & (d > 0.0)), np.inf, rel)
        k = int(np.argmax(rel))
        diffs.append(Difference(name, float(rel[k]), float(np.max(d)), peak, k))
    return sorted(diffs, key=lambda x: -x.rel)


def available(importer):
    """(True, '') if the importer's module loads, else (False, reason)."""
    try:
        __import__(importer)
    except Exception as e:  # ImportError, or OSError from a native library (libecosc.so needs libtbb12)
        return False, f"{importer} cannot be imported ({type(e).__name__}: {e}); installed from {IMPORTERS[importer]}"
    return True, ""

