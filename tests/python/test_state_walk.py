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

The second test (issue #48 item 1) walks the runs of WALKS, with inputs changing and the
configurations the default experiments miss (flexible panels with modes, both RopeBlock rigs with
contact nodes created, sliding and released, the controller), over every integrator the
configuration offers. The state at t_k is taken before point k's inputs are set; every restore
sets them again before its step. Besides (a) and (b) it checks

  (c) the original instance itself: a second run of it where every state is serialized,
      deserialized and set into the same instance before its step, the whole output sequence and
      every state's bytes equal to the uninterrupted run's;
  (d) in the second process, one fresh instance restores the state at mid-run and runs to the
      end: every output equal to the uninterrupted run's.

Cost: RopeBlock runs with 20 segments per sling (as in conftest.SCENARIOS); every other case runs
the whole DefaultExperiment (see STOP_TIMES for any shortened one and why).
"""

import json
import math
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
from state_walk_worker import Outputs, restore, restore_and_step, set_inputs

# Parameters other than the integrator (default parameters otherwise).
VALUES = {"RopeBlock": {"segments": 20}}

# Shortened stop times by (model, integrator), with the measured reason. Empty: every case runs
# its whole DefaultExperiment (RopeBlock with dopri5, the costliest, takes ~36 s per pass for the
# 10 s experiment at 20 segments; three passes fit the file's budget).
STOP_TIMES = {}

# Shown per point in a failure message; the rest are counted.
MAX_REPORTED = 5


def _hoist(t):
    return 0.3 if t >= 0.5 - 1e-9 else 0.0


# Runs with inputs changing (issue #48 item 1): model -> configurations (label, parameters,
# inputs u(t), stop time [s], integrators refused with the configuration[, communication step
# [s], else the DefaultExperiment's]). Every integrator item of the model's enumeration runs
# that is not refused.
WALKS = {
    "PanelLock": [
        # the motor torque changes at every step, with a jump at 1 s; latches engage on the way
        ("rigid", {}, {"root_motor_torque": lambda t: (0.05 if t < 1.0 else -0.02) + 0.01 * math.sin(5.0 * t)},
         2.0, {}),
        # modal panels (2 Craig-Bampton modes each); dopri5_tree takes rigid panels only
        ("flexible", {"flexible_panels": True, "n_modes": 2},
         {"root_motor_torque": lambda t: (0.05 if t < 1.0 else -0.02) + 0.01 * math.sin(5.0 * t)},
         1.0, {"dopri5_tree": "joint coordinates take rigid panels only"}),
    ],
    "RopeBlock": [
        # the lift, slings over the deck edges: hoisted from 0.5 s, hook moved sideways from 1.5 s
        # (the slings slide along the edges), 8 segments per sling (DOPRI5 takes coarse slings only)
        ("lift", {"segments": 8},
         {"hook0_vz": _hoist, "hook0_vx": lambda t: 0.4 if t >= 1.5 - 1e-9 else 0.0}, 3.0, {}),
        # the turn-over: hook 1's slings around the bottom edge, lowered while hook 0 hoists
        ("turnover", {"scenario": 1, "segments": 8, "mu": 0.3},
         {"hook0_vz": _hoist, "hook1_vz": lambda t: -0.3 if t >= 1.0 - 1e-9 else 0.0,
          "hook0_payout_rate": lambda t: 0.05 if t >= 2.0 - 1e-9 else 0.0}, 3.0, {}),
        # the turn-over rolled on by lowering hook 1 (10 segments, 0.25 s steps): contact nodes
        # are inserted and removed (3 rebuilds) at 17-18 s, the states around them restored
        ("turnover-rebuilds", {"scenario": 1, "segments": 10},
         {"hook1_vz": lambda t: -1.0, "hook0_vz": lambda t: 0.1 if 5.0 <= t < 10.0 else 0.0}, 20.0,
         {"dopri5": "explicit steps on 10-segment slings take 16 s for the 20 s run alone (DOPRI5 "
                    "runs the other two RopeBlock configurations)"}, 0.25),
    ],
    "PidController": [
        # setpoint steps, measurement oscillating: the output saturates and the anti-windup acts
        ("changing", {"kp": 2.0, "ki": 1.5, "kd": 0.1, "Tf": 0.05, "u_min": -1.5, "u_max": 1.5, "Tt": 0.05},
         {"setpoint": lambda t: 1.0 if t < 0.5 else -2.0,
          "measurement": lambda t: 0.8 * math.sin(3.0 * t) + 0.3}, 1.0, {}),
    ],
}


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

    def __init__(self, path, unzip, integrator_value, label, config=None):
        """`config`: None (the DefaultExperiment without inputs) or a WALKS entry (name,
        parameters, inputs u(t) by name, stop time, refused integrators[, communication step])."""
        self.label = label if config is None else f"{label}, {config[0]}"
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
        signals = {}
        if config is not None:
            _, self.values, signals, self.stop = config[:4]
            self.values = dict(self.values)
            self.h = config[5] if len(config) > 5 else self.h
            self.n = round((self.stop - self.start) / self.h)
            self.times = [self.start + k * self.h for k in range(self.n)]
        if integrator_value is not None:
            self.values["integrator"] = integrator_value
        self.vars = {v.name: v for v in self.md.modelVariables}
        # the inputs set before the step from t_k, as (value reference, value)
        self.inputs = [[(self.vars[name].valueReference, float(f(t))) for name, f in signals.items()]
                       for t in self.times]
        self.path, self.unzip = path, unzip

    def slave(self, name):
        s = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzip, modelIdentifier=self.id, instanceName=name)
        s.instantiate()
        return s

    def started(self, name):
        """A new instance with the run's parameters, initialized at the start time."""
        s = self.slave(name)
        s.setupExperiment(startTime=self.start, stopTime=self.stop)
        for name, value in self.values.items():
            v = self.vars[name]
            if v.type == "Real":
                s.setReal([v.valueReference], [float(value)])
            elif v.type == "Boolean":
                s.setBoolean([v.valueReference], [bool(value)])
            else:
                s.setInteger([v.valueReference], [int(value)])
        s.enterInitializationMode()
        s.exitInitializationMode()
        return s

    def record(self):
        s = self.started("walk-original")
        self.initial = self.outputs.read(s)
        self.states, self.after = [], []
        for t, inputs in zip(self.times, self.inputs):
            state = s.getFMUstate()
            self.states.append(s.serializeFMUstate(state))
            s.freeFMUstate(state)
            set_inputs(s, inputs)
            s.doStep(currentCommunicationPoint=t, communicationStepSize=self.h)
            self.after.append(self.outputs.read(s))
        s.terminate()
        s.freeInstance()

    def cycled(self):
        """(c): the run again, every state serialized, deserialized and set into the same
        instance before its step; failures (k, why) where the outputs after the step or the
        state's bytes differ from the uninterrupted run's."""
        s = self.started("walk-cycled")
        failures = []
        for k, (t, inputs) in enumerate(zip(self.times, self.inputs)):
            state = s.getFMUstate()
            data = s.serializeFMUstate(state)
            s.freeFMUstate(state)
            restore(s, data)
            set_inputs(s, inputs)
            s.doStep(currentCommunicationPoint=t, communicationStepSize=self.h)
            got = self.outputs.read(s)
            if data != self.states[k]:
                first = next(i for i, (a, b) in enumerate(zip(data, self.states[k])) if a != b) \
                    if len(data) == len(self.states[k]) else None
                failures.append((k, f"state bytes differ from the uninterrupted run's (lengths {len(data)} "
                                    f"and {len(self.states[k])}, first differing byte {first})"))
            elif got != self.after[k]:
                failures.append((k, f"outputs after doStep to t_k + h differ: "
                                    f"{_differences(self.outputs, got, self.after[k])}"))
        s.terminate()
        s.freeInstance()
        return failures

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


def _walk_cases():
    cases = []
    for path in fmu_paths():
        md = read_model_description(str(path))
        integ = next((v for v in md.modelVariables if v.name == "integrator"), None)
        items = [(None, None)] if integ is None else [(i.name, int(i.value)) for i in integ.declaredType.items]
        for config in WALKS.get(md.coSimulation.modelIdentifier, []):
            name, refused = config[0], config[4]
            for label, value in items:
                if label in refused:
                    continue
                cases.append(pytest.param(path, label, value, config,
                                          id=f"{path.stem}-{name}-{label or 'none'}"))
    return cases


def _check(walk, tmp_path, extended=False):
    """Records `walk`, restores every state in (a) and (b), with `extended` also (c) and (d);
    asserts that every continuation is bit for bit the original run's."""
    clock = time.perf_counter()
    walk.record()
    recorded = time.perf_counter() - clock
    assert walk.n > 0 and len(walk.states) == walk.n
    assert len(set(walk.states)) == walk.n, "every point's state must differ (time at least)"

    # (b) starts first and runs beside (a): a second process, every state from a file
    walk_file = tmp_path / "walk.pickle"
    k0 = walk.n // 2 if extended else None
    walk_file.write_bytes(pickle.dumps(dict(fmu=str(walk.path), unzip=walk.unzip, times=walk.times, h=walk.h,
                                            states=walk.states, inputs=walk.inputs, continue_from=k0)))
    worker = subprocess.Popen([sys.executable, str(HERE / "state_walk_worker.py"), str(walk_file)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        # (a) one fresh instance of this process, last point to first
        fresh = walk.slave("walk-fresh")
        failures, compared = [], 0
        for k in reversed(range(walk.n)):
            try:
                restored, stepped = restore_and_step(fresh, walk.outputs, walk.states[k], walk.times[k], walk.h,
                                                     walk.inputs[k])
                why = walk.check(k, restored, stepped)
            except Exception as e:  # noqa: BLE001 - collected per point
                why = f"{type(e).__name__}: {e}"
            compared += 1
            if why:
                failures.append((k, why))
        fresh.freeInstance()
        failures.sort()
        problems = [walk.verdict("fresh instance, same process (last point to first)", failures, compared)]
        assert compared == walk.n
        if extended:
            problems.append(walk.verdict("the same instance, every state serialized, deserialized and set "
                                         "before its step", walk.cycled(), walk.n))

        out, err = worker.communicate(timeout=600)
    finally:
        if worker.poll() is None:
            worker.kill()
            worker.wait()
    assert worker.returncode == 0, f"{walk.id} integrator={walk.label}: worker failed:\n{err[-3000:]}"
    lines = [json.loads(line) for line in out.splitlines()]
    if extended:
        continued = lines.pop()["continued"]
        bad = [(k0 + j, f"outputs after doStep to t_k + h differ: {_differences(walk.outputs, got, walk.after[k0 + j])}")
               for j, got in enumerate(continued) if got != walk.after[k0 + j]]
        if len(continued) != walk.n - k0:
            bad.append((k0, f"{len(continued)} steps continued, not {walk.n - k0}"))
        problems.append(walk.verdict(f"second process, state {k0} restored once and run to the end", bad,
                                     walk.n - k0))
    assert [line["k"] for line in lines] == list(range(walk.n)), "the worker answered for every point"
    failures = []
    for line in lines:
        k = line["k"]
        why = line["error"] if "error" in line else walk.check(k, line["restored"], line["stepped"])
        if why:
            failures.append((k, why))
    problems.append(walk.verdict("fresh instance, second process (first point to last)", failures, len(lines)))
    total = time.perf_counter() - clock
    print(f"{walk.id} integrator={walk.label}: {walk.n} points to {walk.stop} s, "
          f"record {recorded:.1f} s, total {total:.1f} s")
    problems = [p for p in problems if p]
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("path, integrator, value", _cases())
def test_every_state_of_the_default_experiment_restores_and_continues_bit_for_bit(
        path, integrator, value, tmp_path_factory, tmp_path):
    _check(Walk(path, _unzip(path, tmp_path_factory), value, integrator or "none"), tmp_path)


@pytest.mark.parametrize("path, integrator, value, config", _walk_cases())
def test_every_state_of_a_run_with_changing_inputs_continues_bit_for_bit_everywhere(
        path, integrator, value, config, tmp_path_factory, tmp_path):
    _check(Walk(path, _unzip(path, tmp_path_factory), value, integrator or "none", config), tmp_path,
           extended=True)
