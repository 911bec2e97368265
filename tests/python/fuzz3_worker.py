"""Seeded random FMI 3.0 call sequences against one unpacked FMI 3.0 FMU, through fmpy's FMU3Slave
bindings (fmi3raw.py).

usage: fuzz3_worker.py <unzip-dir> <seed> <count>
Prints a JSON summary: sequences, calls, status histogram, invariant violations. The parent
detects crashes from the exit status; the sequence in progress is in `<seed>.progress` (current
folder), so a failure can be replayed with the same seed and count.

A shadow of the standard's state machine follows each instance (instantiated, initialization
mode, step mode, terminated, error) from the statuses it gets. Invariants after every call:
- the status is one of OK..Error: fmi3Fatal means an internal error (a panic) in this library;
- every Discard or Error comes with a message of that status logged by that call;
- a call that the state machine forbids in the shadow state returns fmi3Error;
- after OK: no NaN or infinity in any fmi3GetFloat64 value; a completed fmi3DoStep sets no flag,
  its lastSuccessfulTime is the end of the step and `time` reads it; a refused fmi3DoStep in step
  mode sets no flag and reports the start of the step;
- a mutated serialized state never deserializes.
"""

import json
import math
import pathlib
import random
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fmi3raw as R  # noqa: E402
from conftest import SCENARIOS  # noqa: E402
import ctypes as C  # noqa: E402

from fmpy.fmi3 import fmi3Boolean, fmi3Float64, fmi3ValueReference  # noqa: E402

CATEGORIES = ["logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal", "logEvents", "logSolver", "logBogus"]
TYPES = ("Float64", "Int32", "Enumeration", "Boolean", "String")
UNSUPPORTED = {
    "fmi3EnterEventMode": (),
    "fmi3EnterConfigurationMode": (),
    "fmi3EvaluateDiscreteStates": (),
    "fmi3SetTime": (1.0,),
    "fmi3GetDirectionalDerivative": (None, 0, None, 0, None, 0, None, 0),
    "fmi3GetOutputDerivatives": (None, 0, None, None, 0),
}
# shadow states
INST, INIT, STEP, TERM, ERR = "instantiated", "initializationMode", "stepMode", "terminated", "error"
# the states in which each operation is allowed (the library's masks, src/fmi/machine.rs)
ALLOWED = {
    "enter": {INST}, "exit": {INIT}, "step": {STEP}, "step_mode": {STEP}, "terminate": {STEP},
    "set": {INST, INIT, STEP}, "get": {INIT, STEP, TERM, ERR},
}


class Fuzzer:
    def __init__(self, unzip):
        self.lib = R.Library(unzip)
        vs = self.lib.md.modelVariables
        self.vars = {v.name: v for v in vs}
        self.vrs = {t: [v.valueReference for v in vs if v.type == t and v.name != "time"] for t in TYPES}
        outs = [v for v in vs if v.type == "Float64" and v.causality == "output"]
        self.outputs = [v.valueReference for v in outs]
        # values behind them: an FMI 3.0 array counts its elements
        self.n_output_values = sum(int(v.dimensions[0].start) if v.dimensions else 1 for v in outs)
        self.time = self.vars["time"].valueReference
        self.unknown = max(v.valueReference for v in vs) + 7
        self.values = SCENARIOS.get(self.lib.id, {}).get("values", {})
        self.calls = 0
        self.hist = {}
        self.events = {"completed steps": 0, "refused steps": 0, "states restored": 0, "states deserialized": 0}
        self.violations = []
        self.trace = None  # called with `where` before every operation (the harness's watchdog)

    def violation(self, what):
        self.violations.append(f"sequence {self.seq}, {self.where}: {what}")

    # random arguments
    def vr_list(self, rng, kind):
        pool = self.vrs[kind] + [self.unknown, self.time, rng.choice(sum(self.vrs.values(), []))]
        return [rng.choice(pool) for _ in range(rng.choice([0, 1, 1, 2, 3]))]

    def real(self, rng):
        if rng.random() < 0.7:
            return rng.uniform(0.0, 2.0)
        return rng.choice([rng.uniform(-1e3, 1e3), -1.0, 1e300, -1e300, math.nan, math.inf, -math.inf, 5e-324])

    def step_size(self, rng, stop_defined):
        if rng.random() < 0.75:
            return rng.choice([0.01, 0.001, rng.uniform(1e-6, 0.3)])
        bad = [0.0, -0.01, math.nan, math.inf, 1e-12, 5e-324, 1.0]
        # an absurd step is refused at once: against a stop time, or (without one) because h_max
        # cannot cover it within max_steps (PanelLock, RopeBlock); PidController takes it
        return rng.choice(bad + [1e9, 1e300])

    def check(self, inst, before, status, what, op=None, prior=None):
        """Status conventions of one call made in shadow state `prior` (`op`: its ALLOWED rule)."""
        self.calls += 1
        self.hist[status] = self.hist.get(status, 0) + 1
        if status not in (R.OK, R.WARNING, R.DISCARD, R.ERROR, R.FATAL):
            self.violation(f"{what}: invalid status {status}")
        elif status == R.FATAL:
            self.violation(f"{what}: fmi3Fatal (internal error): {inst.messages()[-1:]}")
        elif status >= R.DISCARD and not any(s == status for (s, _, _) in inst.log[before:]):
            self.violation(f"{what}: status {R.STATUS_NAMES[status]} without a logged message")
        if op is not None and prior not in ALLOWED[op] and status < R.ERROR:
            self.violation(f"{what}: {R.STATUS_NAMES[status]} in shadow state {prior}")

    def sequence(self, rng):
        if rng.random() < 0.04:
            bad = rng.choice([dict(token="{nope}"), dict(name=None), dict(token=None)])
            inst = R.Instance(self.lib, **bad)
            self.calls += 1
            if inst.c:
                self.violation(f"instantiate {bad} succeeded")
                inst.free()
            elif not inst.messages():
                self.violation(f"instantiate {bad} refused without a message")
            return
        inst = R.Instance(self.lib, logging_on=rng.random() < 0.3, early_return_allowed=rng.random() < 0.1)
        if not inst.c:
            self.violation(f"valid instantiate failed: {inst.messages()}")
            return
        shadow = INST
        t = start = 0.0
        stop_defined = False
        meta = {}  # state handle -> (shadow, t, start, stop_defined) when it was saved
        serialized = []  # (bytes, meta)
        if rng.random() < 0.8:  # the scenario's cheaper settings (RopeBlock: 20 segments per sling)
            for name, value in self.values.items():
                v = self.vars[name]
                before = len(inst.log)
                if v.type == "Float64":
                    status = inst.set_float64([v.valueReference], [float(value)])
                else:
                    status = inst.set_int32([v.valueReference], [int(value)])
                self.check(inst, before, status, f"set {name}", "set", shadow)
                shadow = ERR if status >= R.ERROR else shadow
        if rng.random() < 0.7:  # a valid start, so that the later states get explored too
            stop = rng.choice([None, 10.0])
            before = len(inst.log)
            status = inst.init(stop=stop)
            self.check(inst, before, status, "init")
            shadow = ERR if status >= R.ERROR else shadow
            if status == R.OK:
                shadow, stop_defined = STEP, stop is not None
        for _ in range(rng.randint(3, 60)):
            op = rng.randrange(26)
            # lean towards progress, so that long runs in step mode get explored too
            if shadow == ERR and rng.random() < 0.5:
                op = rng.choice([7, 15])  # recover: reset or restore a state
            elif shadow == INST and rng.random() < 0.4:
                op = 0
            elif shadow == INIT and rng.random() < 0.6:
                op = 1
            elif shadow == STEP and rng.random() < 0.4:
                op = 2
            before, prior = len(inst.log), shadow
            self.where = f"op{op} in {shadow}"
            if self.trace:
                self.trace(self.where)
            what, rule = f"op{op}", None
            if op == 0:
                t0 = rng.choice([0.0, 0.0, 1.0, -2.0, math.nan])
                stop = rng.choice([None, None, 10.0, t0 + 0.5, -1.0, math.nan])
                tol = rng.choice([None, None, 1e-6, 1e-3, 0.0, -1.0, math.nan])
                status, rule = inst.enter(start=t0, stop=stop, tol=tol), "enter"
                if status == R.OK:
                    shadow, start, stop_defined = INIT, t0, stop is not None
            elif op == 1:
                status, rule = inst.exit(), "exit"
                if status == R.OK:
                    shadow, t = STEP, start
            elif op in (2, 3, 4, 5):
                h = self.step_size(rng, stop_defined)
                t_call = t if rng.random() < 0.85 else rng.choice([t + 1e-13, t + 0.5, t - 0.01, math.nan])
                status, (ev, term, early, last) = inst.do_step(t_call, h)
                what, rule = f"doStep(t={t_call!r}, h={h!r})", "step"
                if status == R.OK:
                    if (ev, term) != (False, False) or (early and not inst.early_return_allowed):
                        self.violation(f"{what}: flags {(ev, term, early)} after OK")
                    if early:
                        # ended at a located event, inside the step
                        if not t_call < last < t_call + h:
                            self.violation(f"{what}: early return at {last!r}, outside the step")
                    elif not abs(last - (t_call + h)) <= 1e-9 * max(1.0, abs(t_call + h)):
                        self.violation(f"{what}: lastSuccessfulTime {last!r} after OK")
                    t = last
                    self.events["completed steps"] += 1
                    s, now = inst.get_float64([self.time])
                    if s != R.OK or now[0] != last:
                        self.violation(f"{what}: time reads {now} ({s}) instead of {last!r}")
                    s, values = inst.get_float64(self.outputs, n=self.n_output_values)
                    bad = [k for k, x in enumerate(values) if not math.isfinite(x)]
                    if s != R.OK or bad:
                        self.violation(f"{what}: outputs {bad} not finite ({s}) after OK: {inst.messages()[-1:]}")
                elif prior == STEP and status == R.ERROR:
                    self.events["refused steps"] += 1
                    if (ev, term, early) != (False, False, False) or last != t:
                        self.violation(f"{what}: refused step reports {(ev, term, early, last)}, not the start {t!r}")
            elif op == 6:
                status, rule = inst.terminate(), "terminate"
                if status == R.OK:
                    shadow = TERM
            elif op == 7:
                status = inst.reset()
                if status == R.OK:
                    shadow, t, start, stop_defined = INST, 0.0, 0.0, False
            elif op == 8:
                status, rule = inst.enter_step_mode(), "step_mode"
            elif op in (9, 10):
                vrs = self.vr_list(rng, "Float64")
                status, rule = inst.set_float64(vrs, [self.real(rng) for _ in vrs]), "set"
            elif op == 11:
                kind = rng.choice(["Int32", "Enumeration"])
                vrs = self.vr_list(rng, kind)
                values = [rng.choice([rng.randint(-3, 5), 2**31 - 1, -2**31]) for _ in vrs]
                if kind == "Int32":
                    status = inst.set_int32(vrs, values)
                else:
                    status = inst.set_int64(vrs, [v * rng.choice([1, 1, 2**33]) for v in values])
                rule = "set"
            elif op == 12:
                vrs = self.vr_list(rng, "Boolean")
                status, rule = inst.set_boolean(vrs, [rng.random() < 0.5 for _ in vrs]), "set"
            elif op == 13:
                vrs = self.vr_list(rng, "String")
                status, rule = inst.set_string(vrs, [rng.choice(["a", "%s%n", "", None]) for _ in vrs]), "set"
            elif op == 14:
                kind = rng.choice(TYPES)
                vrs = self.vr_list(rng, kind) + ([self.time] if kind == "Float64" and rng.random() < 0.3 else [])
                getter = {"Float64": inst.get_float64, "Int32": inst.get_int32, "Enumeration": inst.get_int64,
                          "Boolean": inst.get_boolean, "String": inst.get_string}[kind]
                status, values = getter(vrs)
                rule = "get"
                if status == R.OK and kind == "Float64":
                    bad = [vr for vr, x in zip(vrs, values) if not math.isfinite(x)]
                    if bad:
                        self.violation(f"fmi3GetFloat64 {vrs}: {bad} not finite after OK")
            elif op == 15:
                handles = list(meta) + [None, 0x20]
                h = rng.choice(handles)
                status = inst.set_state(h)
                if status == R.OK:
                    shadow, t, start, stop_defined = meta[h]
                    self.events["states restored"] += 1
            elif op == 16:
                existing = rng.choice([None] * 4 + list(meta)[-1:] + [0x10])
                status, h = inst.get_state(existing)
                if status == R.OK:
                    meta[h] = (shadow, t, start, stop_defined)
            elif op == 17:
                h = rng.choice(list(meta) + [None, 0x30])
                status, _ = inst.free_state(h)
                if status == R.OK:
                    meta.pop(h, None)
            elif op == 18:
                h = rng.choice(list(meta) + [0x40])
                status, data = inst.serialize(h)
                if status == R.OK:
                    serialized.append((data, meta[h]))
            elif op == 19:
                data, saved = rng.choice(serialized) if serialized else (b"junk", None)
                original, mutation = data, rng.randrange(5)
                if mutation == 1:
                    data = data[: rng.randrange(len(data) + 1)]
                elif mutation == 2 and data:
                    b = bytearray(data)
                    b[rng.randrange(len(b))] ^= 1 << rng.randrange(8)
                    data = bytes(b)
                elif mutation == 3:
                    data = data + bytes([rng.randrange(256)])
                status, h = inst.deserialize(data)
                if status == R.OK:
                    if data != original or saved is None:
                        self.violation(f"a mutated state ({len(original)} -> {len(data)} bytes) deserialized")
                    meta[h] = saved
                    self.events["states deserialized"] += 1
            elif op == 20:
                cats = None if rng.random() < 0.3 else rng.sample(CATEGORIES, rng.randint(1, 3))
                status = inst.set_debug_logging(rng.random() < 0.5, cats)
            elif op == 21:
                fname = rng.choice(sorted(UNSUPPORTED))
                status, what = inst.call(fname, *UNSUPPORTED[fname]), fname
                if status != R.ERROR:
                    self.violation(f"{fname}: {status} instead of fmi3Error")
            elif op == 22:
                # nValues that differs from nValueReferences
                vrs = self.vr_list(rng, "Float64") or [self.unknown]
                status, rule = inst.get_float64(vrs, n=len(vrs) + rng.choice([-1, 1]))[0], "get"
                if status != R.ERROR:
                    self.violation(f"nValues mismatch: {status} instead of fmi3Error")
            elif op == 23:
                # NULL arrays with a non-zero length
                status = inst.call("fmi3GetFloat64", None, rng.randint(1, 3), None, rng.randint(1, 3))
                if status != R.ERROR:
                    self.violation(f"NULL arrays: {status} instead of fmi3Error")
            elif op == 24:
                # a getter of a type the models do not have
                status = inst.call("fmi3GetFloat32", None, 0, None, 0) if rng.random() < 0.3 else \
                    inst.call("fmi3GetUInt16", (fmi3ValueReference * 1)(rng.choice(self.outputs)), 1,
                              (C.c_uint16 * 1)(), 1)
            else:
                # doStep with NULL output pointers: refused whatever the state
                status = inst.call("fmi3DoStep", t, 0.01, fmi3Boolean(False), None, None, None,
                                   C.byref(fmi3Float64()))
                what = "doStep with NULL flags"
                if status != R.ERROR:
                    self.violation(f"{what}: {status} instead of fmi3Error")
            self.check(inst, before, status, what, rule, prior)
            if status >= R.ERROR:
                shadow = ERR
        inst.free()

    def run(self, seed, count, progress):
        for s in range(count):
            with open(progress, "w") as f:
                f.write(f"{seed}:{s}\n")
            self.seq, self.where = f"{seed}:{s}", "instantiation"
            self.sequence(random.Random(f"fmi3:{seed}:{s}"))
        return {"sequences": count, "calls": self.calls,
                "statuses": {R.STATUS_NAMES[k]: v for k, v in sorted(self.hist.items())}, "events": self.events,
                "violations": self.violations[:20], "violation_count": len(self.violations)}


if __name__ == "__main__":
    unzip, seed, count = sys.argv[1:]
    print(json.dumps(Fuzzer(unzip).run(int(seed), int(count), f"{seed}.progress")))
