"""Serialize/deserialize continuation in the adversarial harness: kind `continuation` (FMI 2.0).

Every integrator of every model, with and without PanelLock's flexible panels and with RopeBlock
at a few rope resolutions (CASES, visited in turn by the model's sequence number): the model is
initialized and stepped with inputs changing at every step; at a random communication point the
state is got and serialized; the run goes on for a few steps (the reference outputs, read as
exact bits after every step, and the statuses). Then the same continuation, with the same
inputs, is run from

1. the live state set back into the same instance (fmi2SetFMUstate),
2. the serialized bytes deserialized and set into the same instance,
3. the serialized bytes deserialized and set into a fresh instance (instantiated only),

and every output after every step must equal the reference bit for bit (`continuation-differs`
otherwise, naming the restore, the step and the first outputs that differ). The restored state,
got and serialized again right after the restore, must give the same bytes
(`reserialized-differs`). A refusal on the way (a step that fails with a logged message) is a
clean outcome, as long as every restore refuses it at the same step.
"""

import struct

import fmi2raw as R
from adversarial_run import ANNOUNCE, Run

# per model: (label, parameter values) visited in turn; integrators by their enumeration value
CASES = {
    "PidController": [("pid", {"kd": 0.3, "Tf": 0.02, "setpoint": 1.0})],
    # flexible panels on a free satellite (whose loads are inputs then), rigid ones on a fixed one
    "PanelLock": [(f"{name}{' flexible, free satellite' if flex else ''}",
                   {"integrator": v, "flexible_panels": flex, "n_modes": 2 if flex else 0, "free_satellite": flex})
                  for v, name in enumerate(["gen_alpha", "bdf", "dopri5", "dopri5_tree"], start=1)
                  for flex in (False, True)],
    "RopeBlock": [(f"{name} segments={n}", {"integrator": v, "segments": n})
                  for v, name in enumerate(["gen_alpha", "bdf", "dopri5"], start=1) for n in (4, 12)]
    + [("bdf segments=40", {"integrator": 2, "segments": 40})],
}


def bits(values):
    return [struct.pack("<d", x).hex() for x in values]


def driven(m, values):
    """The inputs a case drives: PanelLock's satellite loads only on a free satellite."""
    if m.id == "PanelLock" and not values.get("free_satellite"):
        return [v for v in m.inputs if v.name == "root_motor_torque"]
    return m.inputs


class Leg:
    """Steps one instance through `inputs` from time `t`, recording statuses and output bits."""

    def __init__(self, m, run, inst, what, driven):
        self.m, self.run, self.inst, self.what, self.driven = m, run, inst, what, driven

    def go(self, t, inputs):
        rows = []
        for k, u in enumerate(inputs):
            if self.driven:
                self.inst.set_real([v.valueReference for v in self.driven], u)
            s = self.run.call(self.inst, f"{self.what}: fmi2DoStep {k}", self.inst.do_step, t, self.m.h,
                              initialized=True)
            if s != R.OK:
                rows.append((s, None))
                break
            st, out = self.inst.get_real(self.m.outputs)
            rows.append((s, bits(out)))
            t += self.m.h
        return rows


def inputs_for(inputs, rng, n):
    """`n` rows of values of `inputs`, changing at every step, small."""
    return [[rng.uniform(-0.1, 0.1) for _ in inputs] for _ in range(n)]


def compare(run, m, label, what, ref, got):
    names = run.output_names()
    for k, (a, b) in enumerate(zip(ref, got)):
        if a[0] != b[0] or a[1] != b[1]:
            if a[1] is not None and b[1] is not None:
                diff = [f"{n}: {x} -> {y}" for n, x, y in zip(names, a[1], b[1]) if x != y][:3]
            else:
                diff = [f"status {R.STATUS_NAMES[a[0]]} -> {R.STATUS_NAMES[b[0]]}"]
            run.violations.append(("continuation-differs", f"{label}, {what}: step {k} after the restore: "
                                                           f"{'; '.join(diff)}"))
            return
    if len(ref) != len(got):
        run.violations.append(("continuation-differs", f"{label}, {what}: {len(got)} steps, the reference {len(ref)}"))


def continuation(m, rng, index):
    label, values = CASES[m.id][index % len(CASES[m.id])]
    before, after = rng.randint(1, 4), rng.randint(2, 4)
    ANNOUNCE[0](f"continuation {m.id} {label}: state after {before} steps, {after} steps on")
    run = Run(m)
    inst = m.new()
    run.call(inst, "fmi2SetupExperiment", inst.setup, 0.0, 10.0)
    for name, value in {**m.baseline, **values}.items():
        run.call(inst, f"set {name}", m.set_value, inst, name, value)
    run.call(inst, "fmi2EnterInitializationMode", inst.enter)
    run.call(inst, "fmi2ExitInitializationMode", inst.exit, initialized=True)
    use = driven(m, values)
    head = Leg(m, run, inst, "lead-in", use).go(0.0, inputs_for(use, rng, before)) if not run.refused else []
    info = {"case": f"{label}, state after {before} steps, {after} on", "compared": 0}
    if run.refused or any(s != R.OK for s, _ in head):
        inst.free()
        return run, info
    t = before * m.h
    s, state = run.call(inst, "fmi2GetFMUstate", inst.get_state)
    s, data = run.call(inst, "fmi2SerializeFMUstate", inst.serialize, state)
    tail = inputs_for(use, rng, after)
    ref = Leg(m, run, inst, "reference", use).go(t, tail)
    restores = [("live state, same instance", inst, lambda i: i.set_state(state))]
    fresh = m.new()

    def from_bytes(i):
        s, h = i.deserialize(data)
        if s != R.OK:
            return s
        s = i.set_state(h)
        i.free_state(h)
        return s

    restores += [("serialized, same instance", inst, from_bytes), ("serialized, fresh instance", fresh, from_bytes)]
    for what, target, restore in restores:
        if run.call(target, f"{what}: restore", restore, target) != R.OK:
            continue
        s2, h2 = target.get_state()
        if s2 == R.OK:
            s3, again = target.serialize(h2)
            target.free_state(h2)
            if s3 == R.OK and again != data:
                at = next((k for k, (a, b) in enumerate(zip(again, data)) if a != b), min(len(again), len(data)))
                run.violations.append(("reserialized-differs", f"{label}, {what}: the restored state serializes to "
                                                               f"other bytes ({len(again)} vs {len(data)}, first "
                                                               f"difference at byte {at})"))
        got = Leg(m, run, target, what, use).go(t, tail)
        compare(run, m, label, what, ref, got)
        info["compared"] += len(got)
    inst.free_state(state)
    inst.free()
    fresh.free()
    R.LOGS.pop(inst.env, None)
    R.LOGS.pop(fresh.env, None)
    return run, info
