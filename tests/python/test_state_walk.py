"""FMU state at every communication point of every DefaultExperiment (issue #20).

For every FMU and every item of its `integrator` enumeration (one run when it has none), the
DefaultExperiment runs with default parameters and no inputs; at every communication point t_k
the state is taken and serialized (fmi2GetFMUstate + fmi2SerializeFMUstate) before the step to
t_k + h, and every output (Real bits, Integer, Boolean) is recorded after it. Then every state is
restored

  (a) in one fresh instance of this process (instantiated only, never initialized), from the last
      point back to the first, so that every restore jumps back in time and a field that
      fmi2SetFMUstate failed to overwrite would show;
  (b) in one fresh instance of a second process (state_walk_worker.py), first to last;

and after each restore the outputs must be those at t_k and, after one doStep from t_k, bit for
bit those of the original run at t_k + h. A failure names the FMU, the integrator, k and t_k.

This is the test that catches a state refused or continued differently after some time of a run
(PanelLock with BDF refused its own state after ~7.6 s of its default run).

Cost: RopeBlock runs with 20 segments per sling (as in conftest.SCENARIOS); every other case runs
the whole DefaultExperiment (see STOP_TIMES for any shortened one and why).
"""

import json
import pathlib
import pickle
import struct
import subprocess
import sys
import time

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from conftest import HERE, fmu_paths
from state_walk_worker import Outputs, restore_and_step

# Parameters other than the integrator (default parameters otherwise).
VALUES = {"RopeBlock": {"segments": 20}}

# Shortened stop times by (model, integrator), with the measured reason. Empty: every case runs
# its whole DefaultExperiment (RopeBlock with dopri5, the costliest, takes ~36 s per pass for the
# 10 s experiment at 20 segments; three passes fit the file's budget).
STOP_TIMES = {}

# Shown per point in a failure message; the rest are counted.
MAX_REPORTED = 5


def _cases():
    cases = []
    for path in fmu_paths():
        md = read_model_description(str(path))
        integ = next((v for v in md.modelVariables if v.name == "integrator"), None)
        if integ is None:
            cases.append(pytest.param(path, None, None, id=path.stem))
            continue
        for item in integ.declaredType.items:
            cases.append(pytest.param(path, item.name, int(item.value), id=f"{path.stem}-{item.name}"))
    return cases


_UNZIPPED = {}


def _unzip(path, tmp_path_factory):
    if path not in _UNZIPPED:
        _UNZIPPED[path] = extract(str(path), unzipdir=str(tmp_path_factory.mktemp(path.stem + "-walk")))
    return _UNZIPPED[path]


def _float(text):
    return struct.unpack("<d", bytes.fromhex(text))[0]


def _differences(outputs, got, want, limit=4):
    """The outputs that differ, as `name: got != want`."""
    diffs = []
    for i, (name, g, w) in enumerate(zip(outputs.names, got, want)):
        if g != w:
            if i < len(outputs.real):
                g, w = repr(_float(g)), repr(_float(w))
            diffs.append(f"{name}: {g} != {w}")
    more = f" (+{len(diffs) - limit} more)" if len(diffs) > limit else ""
    return "; ".join(diffs[:limit]) + more


class Walk:
    """The original run: the serialized state at every t_k, outputs after every step."""

    def __init__(self, path, unzip, integrator_value, label):
        self.label = label
        self.md = read_model_description(str(path))
        self.id = self.md.coSimulation.modelIdentifier
        self.outputs = Outputs(self.md)
        de = self.md.defaultExperiment
        self.start, self.h = float(de.startTime or 0.0), float(de.stepSize)
        self.stop = float(STOP_TIMES.get((self.id, label), de.stopTime))
        self.n = round((self.stop - self.start) / self.h)
        # the points as fmpy's simulate_fmu computes them
        self.times = [self.start + k * self.h for k in range(self.n)]
        self.values = dict(VALUES.get(self.id, {}))
        if integrator_value is not None:
            self.values["integrator"] = integrator_value
        self.path, self.unzip = path, unzip

    def slave(self, name):
        s = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzip, modelIdentifier=self.id, instanceName=name)
        s.instantiate()
        return s

    def record(self):
        s = self.slave("walk-original")
        s.setupExperiment(startTime=self.start, stopTime=float(self.md.defaultExperiment.stopTime))
        vars_ = {v.name: v for v in self.md.modelVariables}
        for name, value in self.values.items():
            s.setInteger([vars_[name].valueReference], [int(value)])
        s.enterInitializationMode()
        s.exitInitializationMode()
        self.initial = self.outputs.read(s)
        self.states, self.after = [], []
        for t in self.times:
            state = s.getFMUstate()
            self.states.append(s.serializeFMUstate(state))
            s.freeFMUstate(state)
            s.doStep(currentCommunicationPoint=t, communicationStepSize=self.h)
            self.after.append(self.outputs.read(s))
        s.terminate()
        s.freeInstance()

    def at(self, k):
        """Outputs at t_k (what a restore of state k must show before stepping)."""
        return self.initial if k == 0 else self.after[k - 1]

    def check(self, k, restored, stepped):
        """Why point k's continuation differs from the original run, or None."""
        if restored != self.at(k):
            return f"outputs right after the restore differ: {_differences(self.outputs, restored, self.at(k))}"
        if stepped != self.after[k]:
            return f"outputs after doStep to t_k + h differ: {_differences(self.outputs, stepped, self.after[k])}"
        return None

    def verdict(self, where, failures, compared):
        """Failure text (or None) naming the FMU, integrator, points and times."""
        if not failures:
            return None
        lines = [f"{self.id} integrator={self.label}, {where}: {len(failures)} of {compared} "
                 f"communication points do not continue bit for bit"]
        for k, why in failures[:MAX_REPORTED]:
            lines.append(f"  k={k} t_k={self.times[k]!r} s: {why}")
        if len(failures) > MAX_REPORTED:
            lines.append(f"  ... and {len(failures) - MAX_REPORTED} more (last k={failures[-1][0]} "
                         f"t_k={self.times[failures[-1][0]]!r} s)")
        return "\n".join(lines)


@pytest.mark.parametrize("path, integrator, value", _cases())
def test_every_state_of_the_default_experiment_restores_and_continues_bit_for_bit(
        path, integrator, value, tmp_path_factory, tmp_path):
    unzip = _unzip(path, tmp_path_factory)
    walk = Walk(path, unzip, value, integrator or "none")
    clock = time.perf_counter()
    walk.record()
    recorded = time.perf_counter() - clock
    assert walk.n > 0 and len(walk.states) == walk.n
    assert len(set(walk.states)) == walk.n, "every point's state must differ (time at least)"

    # (b) starts first and runs beside (a): a second process, every state from a file
    walk_file = tmp_path / "walk.pickle"
    walk_file.write_bytes(pickle.dumps(dict(fmu=str(path), unzip=unzip, times=walk.times, h=walk.h,
                                            states=walk.states)))
    worker = subprocess.Popen([sys.executable, str(HERE / "state_walk_worker.py"), str(walk_file)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        # (a) one fresh instance of this process, last point to first
        fresh = walk.slave("walk-fresh")
        failures, compared = [], 0
        for k in reversed(range(walk.n)):
            try:
                restored, stepped = restore_and_step(fresh, walk.outputs, walk.states[k], walk.times[k], walk.h)
                why = walk.check(k, restored, stepped)
            except Exception as e:  # noqa: BLE001 - collected per point
                why = f"{type(e).__name__}: {e}"
            compared += 1
            if why:
                failures.append((k, why))
        fresh.freeInstance()
        failures.sort()
        in_process = walk.verdict("fresh instance, same process (last point to first)", failures, compared)
        assert compared == walk.n

        out, err = worker.communicate(timeout=600)
    finally:
        if worker.poll() is None:
            worker.kill()
            worker.wait()
    assert worker.returncode == 0, f"{walk.id} integrator={walk.label}: worker failed:\n{err[-3000:]}"
    lines = [json.loads(line) for line in out.splitlines()]
    assert [line["k"] for line in lines] == list(range(walk.n)), "the worker answered for every point"
    failures = []
    for line in lines:
        k = line["k"]
        why = line["error"] if "error" in line else walk.check(k, line["restored"], line["stepped"])
        if why:
            failures.append((k, why))
    second = walk.verdict("fresh instance, second process (first point to last)", failures, len(lines))
    total = time.perf_counter() - clock
    print(f"{walk.id} integrator={walk.label}: {walk.n} points to {walk.stop} s, "
          f"record {recorded:.1f} s, total {total:.1f} s")
    problems = [p for p in (in_process, second) if p]
    assert not problems, "\n".join(problems)
