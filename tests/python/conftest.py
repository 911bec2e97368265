"""Shared fixtures: the packaged FMUs in dist/, per-model scenarios, the native runner.

Tests that take the `fmu` fixture run once per `.fmu` in `dist/` (set MBCOSIM_DIST to use another
folder). A model gets meaningful inputs from SCENARIOS; models without an entry run with their
defaults. The native reference runs come from `mbcosim simulate` (MBCOSIM_BIN, or cargo run).
"""

import io
import math
import os
import pathlib
import re
import struct
import subprocess
import sys

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parents[2]
DIST = pathlib.Path(os.environ.get("MBCOSIM_DIST", ROOT / "dist"))
HERE = pathlib.Path(__file__).resolve().parent

# Per-model scenarios: start values, run length, and input signals u(t) for hand-driven loops.
SCENARIOS = {
    "PanelLock": dict(
        values={"rtol": 1e-6, "atol": 1e-8},
        stop=6.0,
        step=0.05,
        inputs={"root_motor_torque": lambda t: 0.02 * math.sin(2.0 * t)},
        alt_values={"contact_stiffness": 1e8, "n_panels": 2},
        fuzz_sequences=150,
    ),
    "RopeBlock": dict(
        # 20 segments per sling keep CI fast; the hook starts hoisting at 0.5 s (one command change)
        values={"segments": 20},
        stop=2.0,
        step=0.05,
        inputs={"hook0_vz": lambda t: 0.2 if t >= 0.5 - 1e-9 else 0.0},
        alt_values={"block_mass": 150e3, "mu": 0.3, "scenario": 1},
        fuzz_sequences=40,
        # contact friction (~300 N) is a difference of sling forces of ~5e5 N: libcosim's exact
        # nanosecond grid moves it by ~6e-7 N (1e-12 of the tension)
        importer_abs=1e-5,
    ),
    "PidController": dict(
        values={"setpoint": 1.0, "kp": 2.0, "ki": 1.5, "kd": 0.1, "Tf": 0.05, "u_min": -1.5, "u_max": 1.5, "Tt": 0.05},
        stop=3.0,
        step=0.01,
        inputs={"measurement": lambda t: 0.8 * math.sin(3.0 * t) + 0.3},
        alt_values={"kp": 0.5, "ki": 0.2},
        # the controller's own misuse cases (inverted output limits)
        pid_misuse=True,
        # constant error e = 0.7: u(t) = kp*e + ki*e*t exactly, whatever the step sequence
        step_independence=dict(values={"setpoint": 1.0, "measurement": 0.3, "kp": 2.0, "ki": 1.5},
                               output="u", exact=lambda t: 2.0 * 0.7 + 1.5 * 0.7 * t),
    ),
    "SpringMassDamper": dict(
        values={"c": 1.0, "k": 200.0},
        stop=3.0,
        step=0.01,
        inputs={"F": lambda t: 5.0 * math.sin(4.0 * t)},
        alt_values={"m": 2.0, "x0": -0.2},
    ),
}


def fmu_paths():
    return sorted(DIST.glob("*.fmu"))


def packed(identifier):
    """Path of dist/<identifier>.fmu; the test fails when it was not packed (the test command
    packs every model before pytest runs)."""
    path = DIST / f"{identifier}.fmu"
    if not path.exists():
        pytest.fail(f"{path} is missing: run `cargo run --release --bin mbcosim -- pack` first")
    return path


def bits(x: float) -> str:
    """Exact text of a float, for bit-identical comparisons."""
    return struct.pack("<d", x).hex()


class Fmu:
    """A packaged FMU, unpacked once, with helpers to drive it through fmpy like a user."""

    def __init__(self, path: pathlib.Path, unzip: str):
        self.path = path
        self.unzip = unzip
        self.md = read_model_description(str(path))
        self.id = self.md.coSimulation.modelIdentifier
        self.guid = self.md.guid
        self.vars = {v.name: v for v in self.md.modelVariables}
        sc = SCENARIOS.get(self.id, {})
        de = self.md.defaultExperiment
        self.values = sc.get("values", {})
        self.alt_values = sc.get("alt_values", {})
        self.inputs = sc.get("inputs", {})
        self.stop = sc.get("stop", float(de.stopTime) if de and de.stopTime else 1.0)
        self.step = sc.get("step", float(de.stepSize) if de and de.stepSize else self.stop / 100)
        self.step_independence = sc.get("step_independence")

    def by_causality(self, causality):
        return [v for v in self.md.modelVariables if v.causality == causality]

    @property
    def real_outputs(self):
        return [v for v in self.by_causality("output") if v.type == "Real"]

    def slave(self, name="inst", logging_on=False):
        s = FMU2Slave(guid=self.guid, unzipDirectory=self.unzip, modelIdentifier=self.id, instanceName=name)
        s.instantiate(loggingOn=logging_on)
        return s

    def set_values(self, slave, values):
        for name, value in values.items():
            v = self.vars[name]
            if v.type == "Real":
                slave.setReal([v.valueReference], [float(value)])
            elif v.type in ("Integer", "Enumeration"):
                slave.setInteger([v.valueReference], [int(value)])
            elif v.type == "Boolean":
                slave.setBoolean([v.valueReference], [bool(value)])
            else:
                slave.setString([v.valueReference], [str(value)])

    def start(self, slave, values=None, stop=None):
        slave.setupExperiment(startTime=0.0, stopTime=stop)
        self.set_values(slave, self.values if values is None else values)
        slave.enterInitializationMode()
        slave.exitInitializationMode()

    def run(self, slave, t0, n, h=None):
        """n steps from t0 with the scenario's input signals; returns output bits per step."""
        h = h or self.step
        vrs = [v.valueReference for v in self.real_outputs]
        rows = []
        for k in range(n):
            t = t0 + k * h
            for name, f in self.inputs.items():
                slave.setReal([self.vars[name].valueReference], [f(t)])
            slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            rows.append([bits(x) for x in slave.getReal(vrs)])
        return rows


_UNZIPPED = {}


@pytest.fixture
def fmu(request, tmp_path_factory):
    path = request.param
    if path not in _UNZIPPED:
        _UNZIPPED[path] = extract(str(path), unzipdir=str(tmp_path_factory.mktemp(path.stem)))
    return Fmu(path, _UNZIPPED[path])


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "scenario_key(key): run only for the models whose SCENARIOS entry has `key`")


def pytest_generate_tests(metafunc):
    if "fmu" in metafunc.fixturenames:
        paths = fmu_paths()
        marker = metafunc.definition.get_closest_marker("scenario_key")
        if marker is not None:
            paths = [p for p in paths if SCENARIOS.get(p.stem, {}).get(marker.args[0])]
        metafunc.parametrize("fmu", paths, ids=[p.stem for p in paths], indirect=True)


def native(*args, timeout=120):
    """Runs `mbcosim <args>` and returns its stdout."""
    exe = os.environ.get("MBCOSIM_BIN")
    cmd = [exe] if exe else ["cargo", "run", "--release", "--quiet", "--bin", "mbcosim", "--"]
    r = subprocess.run(cmd + [str(a) for a in args], cwd=ROOT, capture_output=True, text=True, timeout=timeout)
    assert r.returncode == 0, r.stderr
    return r.stdout


def strip_unit(cell):
    """`hinge0_angle [rad]` -> `hinge0_angle`: mbcosim's CSV header carries units (docs/cli.md)."""
    return re.sub(r" \[[^\]]*\]$", "", cell.strip())


def native_table(*args, timeout=120):
    """`mbcosim simulate ...` as a numpy structured array with one field per variable name."""
    header, _, body = native(*args, timeout=timeout).partition("\n")
    names = [strip_unit(c) for c in header.split(",")]
    return np.genfromtxt(io.StringIO(body), delimiter=",", names=names)


def python_script(script, *args, timeout=120):
    """Runs one of the helper scripts of this folder in a fresh interpreter."""
    return subprocess.run([sys.executable, str(HERE / script)] + [str(a) for a in args],
                          capture_output=True, text=True, timeout=timeout)
