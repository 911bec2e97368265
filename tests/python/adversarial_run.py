"""What every adversarial sequence shares (adversarial.py and its kinds): the per-call checks
(`Run`), the watchdog's announcement hook and the names of the tallies."""

import math

import fmi2raw as R


def count_class(cls):
    """The summary count a violation class adds to."""
    return {"nan-with-ok": "nan_with_ok", "crash": "crashes", "hang": "hangs"}.get(cls, "other_violations")


# The tallies of a run, in the order they are printed.
TALLIES = ("tried", "crashes", "hangs", "nan_with_ok", "refused_with_message", "completed", "other_violations")


def counts_line(s):
    line = ", ".join(f"{k} {s[k]}" for k in TALLIES)
    if "max_cpu" in s:
        line += f", largest CPU time {s['max_cpu']['seconds']:.2f} s"
    return line


# Tells the watchdog what the current sequence is doing (a forked worker sets it), so that a
# hang or a crash is reported with its case.
ANNOUNCE = [lambda text, field=None: None]

# Tells the watchdog the current sequence's own CPU bound [s] when the work it asks for is known
# to exceed the harness's bound (the integrator steps a user's small `h_max` forces, see
# `forced_step_cpu` in adversarial.py): the watch then allows that much, never less than its own
# bound. A forked worker sets it.
BUDGET = [lambda seconds: None]


class Run:
    """One sequence's checks: every call goes through `call`."""

    def __init__(self, model):
        self.m = model
        self.violations = []
        self.refused = False  # a clean refusal (Error/Discard with a logged message) happened
        self.calls = 0
        self.text = ""
        self.trail = None  # a list: every call is announced to the watchdog (call sequences)

    def call(self, inst, what, fn, *args, initialized=False):
        if self.trail is not None:
            self.trail.append(what)
            ANNOUNCE[0]("calls " + " | ".join(self.trail[-15:]))
        before = len(inst.log)
        out = fn(*args)
        status = out[0] if isinstance(out, tuple) else out
        self.calls += 1
        if status not in (R.OK, R.WARNING, R.DISCARD, R.ERROR, R.FATAL):
            self.violations.append(("invalid-status", f"{what}: status {status}"))
        elif status >= R.DISCARD:
            msgs = [m for (s, _, m) in inst.log[before:] if s == status]
            if not msgs:
                self.violations.append(("no-message", f"{what}: {R.STATUS_NAMES[status]} without a logged message"))
            elif status == R.FATAL:
                self.violations.append(("fatal", f"{what}: Fatal: {msgs[0][:300]}"))
            else:
                self.refused = True
        elif initialized:
            self.check_outputs(inst, what)
        return out

    def check_outputs(self, inst, what):
        before = len(inst.log)
        s, values = inst.get_real(self.m.outputs)
        self.calls += 1
        if s == R.OK:
            bad = [f"{n}={x}" for n, x in zip(self.output_names(), values) if not math.isfinite(x)]
            if bad:
                self.violations.append(("nan-with-ok", f"{what} returned OK with outputs {', '.join(bad[:4])}"))
        elif s >= R.DISCARD and not any(st == s for (st, _, _) in inst.log[before:]):
            self.violations.append(("no-message", f"fmi2GetReal after {what}: {R.STATUS_NAMES[s]} without a message"))

    def output_names(self):
        by_vr = {v.valueReference: v.name for v in self.m.md.modelVariables if v.type == "Real"}
        return [by_vr[vr] for vr in self.m.outputs]

    def messages(self, inst):
        return [m for (s, _, m) in inst.log if s >= R.DISCARD]
