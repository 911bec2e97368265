"""Seeded random call sequences against one unpacked FMU.

usage: fuzz_worker.py <unzip-dir> <model-identifier> <seed> <count>
Prints a JSON summary: sequences, calls, status histogram, and invariant violations. The parent
detects crashes from the exit status; the sequence in progress is in the progress file
(`<seed>.progress` in the current folder) so that it can be replayed.

Invariants checked after every call: the status is one of OK..Fatal; every Discard, Error or Fatal
comes with a logged message of that status; a refused instantiation logs its reason.
"""

import json
import math
import os
import pathlib
import random
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fmi2raw as R
from fmpy import read_model_description

CATEGORIES = ["logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal", "logEvents", "logSolver", "logBogus"]


class Fuzzer:
    def __init__(self, unzip, identifier):
        self.md = read_model_description(os.path.join(unzip, "modelDescription.xml"))
        self.lib = R.Library(unzip, identifier)
        vs = self.md.modelVariables
        self.vrs = {t: [v.valueReference for v in vs if v.type == t] for t in ("Real", "Integer", "Boolean", "String")}
        self.vrs["Integer"] += [v.valueReference for v in vs if v.type == "Enumeration"]
        self.unknown = max(v.valueReference for v in vs) + 7
        self.calls = 0
        self.hist = {}
        self.violations = []

    # random arguments
    def vr_list(self, rng, kind):
        pool = self.vrs[kind] + [self.unknown]
        return [rng.choice(pool) for _ in range(rng.choice([0, 1, 1, 2, 3]))]

    def real(self, rng):
        if rng.random() < 0.7:
            return rng.uniform(0.0, 2.0)
        return rng.choice([rng.uniform(-1e3, 1e3), -1.0, 1e300, -1e300, math.nan, math.inf, -math.inf, 5e-324])

    def step(self, rng):
        if rng.random() < 0.7:
            return rng.choice([0.01, 0.001, rng.uniform(1e-6, 0.3)])
        return rng.choice([0.0, -0.01, math.nan, math.inf, 1e9])

    def check(self, inst, before, status, what):
        self.calls += 1
        self.hist[status] = self.hist.get(status, 0) + 1
        if status not in (R.OK, R.WARNING, R.DISCARD, R.ERROR, R.FATAL):
            self.violations.append(f"{what}: invalid status {status}")
        elif status >= R.DISCARD:
            new = inst.log[before:]
            if not any(s == status for (s, _, _) in new):
                self.violations.append(f"{what}: status {R.STATUS_NAMES[status]} without a logged message")

    def sequence(self, rng):
        kind = rng.random()
        if kind < 0.05:
            bad = rng.choice([dict(guid="{nope}"), dict(fmu_type=0), dict(name=None), dict(guid=None)])
            args = {"guid": self.md.guid, **bad}
            inst = R.Instance(self.lib, args.pop("guid"), **args)
            self.calls += 1
            if inst.c:
                self.violations.append(f"instantiate {bad} succeeded")
                inst.free()
            elif not inst.messages():
                self.violations.append(f"instantiate {bad} refused without a message")
            return
        inst = R.Instance(self.lib, self.md.guid, logging_on=rng.random() < 0.3)
        if not inst.c:
            self.violations.append("valid instantiate failed")
            return
        t = start = 0.0
        state_time = {}
        states = []
        serialized = []
        if rng.random() < 0.7:  # a valid start, so that the later states get explored too
            before = len(inst.log)
            self.check(inst, before, inst.init(stop=rng.choice([None, 10.0])), "init")
        last = R.OK
        for _ in range(rng.randint(3, 60)):
            op = rng.randrange(24)
            if last >= R.ERROR and rng.random() < 0.5:
                op = rng.choice([7, 15])  # recover: reset or restore a state
            before = len(inst.log)
            what = f"op{op}"
            if op == 0:
                stop = rng.choice([None, 1.0, 10.0, -1.0, math.nan])
                t0 = rng.choice([0.0, 0.0, 1.0, math.nan])
                status = inst.setup(start=t0, stop=stop, tol=rng.choice([None, 1e-6, -1.0]))
                if status == R.OK:
                    start = t0
            elif op == 1:
                status = inst.enter()
            elif op == 2:
                status = inst.exit()
                if status == R.OK:
                    t = start
            elif op in (3, 4, 5):
                h = self.step(rng)
                t_call = t if rng.random() < 0.8 else rng.choice([t + 1e-13, t + 0.5, math.nan])
                status = inst.do_step(t_call, h)
                if status == R.OK:
                    t = t_call + h
            elif op == 6:
                status = inst.terminate()
            elif op == 7:
                status = inst.reset()
                if status == R.OK:
                    t = start = 0.0
            elif op in (8, 9):
                vrs = self.vr_list(rng, "Real")
                status = inst.set_real(vrs, [self.real(rng) for _ in vrs])
            elif op == 10:
                vrs = self.vr_list(rng, "Integer")
                status = inst.set_integer(vrs, [rng.randint(-3, 5) for _ in vrs])
            elif op == 11:
                vrs = self.vr_list(rng, "Boolean")
                status = inst.set_boolean(vrs, [rng.random() < 0.5 for _ in vrs])
            elif op == 12:
                vrs = self.vr_list(rng, "String")
                status = inst.set_string(vrs, [rng.choice(["a", "%s%n", "", None]) for _ in vrs])
            elif op == 13:
                kind = rng.choice(["Real", "Integer", "Boolean", "String"])
                getter = {"Real": inst.get_real, "Integer": inst.get_integer, "Boolean": inst.get_boolean,
                          "String": inst.get_string}[kind]
                status = getter(self.vr_list(rng, kind))[0]
            elif op == 14:
                status, h = inst.get_state(rng.choice([None] * 4 + states[-1:] + [0x10]))
                if status == R.OK:
                    state_time[h] = t
                    if h not in states:
                        states.append(h)
            elif op == 15:
                h = rng.choice(states + [None, 0x20])
                status = inst.set_state(h)
                if status == R.OK:
                    t = state_time.get(h, t)
            elif op == 16:
                h = rng.choice(states + [None, 0x30])
                status, _ = inst.free_state(h)
                if status == R.OK and h in states:
                    states.remove(h)
            elif op == 17:
                status, data = inst.serialize(rng.choice(states + [0x40]))
                if status == R.OK:
                    serialized.append(data)
            elif op == 18:
                data = rng.choice(serialized) if serialized else b"junk"
                mutation = rng.randrange(5)
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
                    states.append(h)
            elif op == 19:
                status = inst.real_status(rng.choice([0, 1, 2, 3, 99]))[0]
            elif op == 20:
                status = inst.boolean_status(rng.choice([0, 1, 2, 3, 99]))[0]
            elif op == 21:
                cats = None if rng.random() < 0.3 else rng.sample(CATEGORIES, rng.randint(1, 3))
                status = inst.set_debug_logging(rng.random() < 0.5, cats)
            elif op == 22:
                fname = rng.choice(["fmi2CancelStep", "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives"])
                args = {"fmi2CancelStep": (), "fmi2SetRealInputDerivatives": (None, 0, None, None),
                        "fmi2GetRealOutputDerivatives": (None, 0, None, None)}[fname]
                status = getattr(self.lib, fname)(inst.c, *args)
                what = fname
            else:
                # NULL arrays with a non-zero length
                status = self.lib.fmi2GetReal(inst.c, None, rng.randint(1, 3), None)
            self.check(inst, before, status, what)
            last = status
        inst.free()

    def run(self, seed, count, progress):
        for s in range(count):
            with open(progress, "w") as f:
                f.write(f"{seed}:{s}\n")
            self.sequence(random.Random(f"{seed}:{s}"))
        return {"sequences": count, "calls": self.calls, "statuses": {R.STATUS_NAMES[k]: v for k, v in sorted(self.hist.items())},
                "violations": self.violations[:20], "violation_count": len(self.violations)}


if __name__ == "__main__":
    unzip, identifier, seed, count = sys.argv[1:]
    summary = Fuzzer(unzip, identifier).run(int(seed), int(count), f"{seed}.progress")
    print(json.dumps(summary))
