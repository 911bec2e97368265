"""Callback re-entry in the adversarial harness: kinds `reentry` (FMI 2.0) and `reentry3` (FMI 3.0).

A call that makes the FMU call one of the importer's callbacks (the *trigger*) runs on an
instance whose callback calls back into the same instance (the *action*: reset, free, doStep,
get/set values, get state, terminate, ...), once or for each of the first few callbacks. A twin
instance, in the same state, makes the same trigger call without re-entry. Expected
(src/fmi/handle.rs): every re-entered call returns Error (fmi2FreeInstance/fmi3FreeInstance:
nothing) with a logged refusal ("... called while ... is running on this instance"), the outer
call returns what the twin's returned, the instance is still alive, and the next step gives
outputs equal bit for bit to the twin's.

Violations: `reentry-accepted` (an inner call not refused), `reentry-unlogged` (no refusal
logged), `reentry-outer-changed` (the outer status differs from the twin's), `reentry-freed`
(the instance is gone after a re-entered free), `reentry-changed-state` (the next step differs
from the twin's).

Triggers. FMI 2.0 logger: a refused fmi2DoStep (h < 0), fmi2SetReal of NaN, fmi2GetReal of an
unknown value reference, fmi2SetDebugLogging of an unknown category. FMI 3.0: the same through
its logger, and the intermediate-update callback during a completed fmi3DoStep (called after
every accepted internal step).
"""

import math
import struct

import fmi2raw as R2
import fmi3raw as R3
from adversarial_run import ANNOUNCE, Run
from callback_hook import Hook

UNKNOWN_VR = 987654
REFUSAL = "called while"


def bits(values):
    return [struct.pack("<d", x).hex() for x in values]


# ---------------------------------------------------------------------------------------------
# FMI 2.0

TRIGGERS2 = {
    "fmi2DoStep h<0": lambda m, i, t: i.do_step(t, -1.0),
    "fmi2SetReal NaN": lambda m, i, t: i.set_real([m.inputs[0].valueReference], [math.nan]) if m.inputs
    else i.get_real([UNKNOWN_VR])[0],
    "fmi2GetReal unknown": lambda m, i, t: i.get_real([UNKNOWN_VR])[0],
    "fmi2SetDebugLogging unknown": lambda m, i, t: i.set_debug_logging(True, ["no-such-category"]),
}
ACTIONS2 = {
    "fmi2Reset": lambda m, i, t: i.lib.fmi2Reset(i.c),
    "fmi2FreeInstance": lambda m, i, t: i.lib.fmi2FreeInstance(i.c),
    "fmi2DoStep": lambda m, i, t: i.lib.fmi2DoStep(i.c, t, m.h, 1),
    "fmi2GetReal": lambda m, i, t: i.get_real(m.outputs)[0],
    "fmi2SetReal": lambda m, i, t: i.set_real([m.inputs[0].valueReference], [0.1]) if m.inputs
    else i.get_real(m.outputs)[0],
    "fmi2GetFMUstate": lambda m, i, t: i.get_state()[0],
    "fmi2Terminate": lambda m, i, t: i.terminate(),
    "fmi2SetupExperiment": lambda m, i, t: i.setup(stop=1.0),
    "fmi2SetDebugLogging": lambda m, i, t: i.set_debug_logging(False),
}


def start2(m, run, steps, inputs):
    """A logging instance of `m` initialized and stepped `steps` times with `inputs`."""
    inst = m.new(logging_on=True)
    for k, v in m.baseline.items():
        run.call(inst, f"set {k}", m.set_value, inst, k, v)
    run.call(inst, "init", inst.init, 10.0, initialized=True)
    t = 0.0
    for k in range(steps):
        if m.inputs:
            inst.set_real([m.inputs[0].valueReference], [inputs[k]])
        run.call(inst, "fmi2DoStep", inst.do_step, t, m.h, initialized=True)
        t += m.h
    return inst, t


def reentry(m, rng, index):
    """One FMI 2.0 logger re-entry (action chosen in turn, trigger at random)."""
    action = sorted(ACTIONS2)[index % len(ACTIONS2)]
    trigger = rng.choice(sorted(TRIGGERS2))
    times = rng.choice([1, 1, 3])
    steps = rng.randint(0, 2)
    inputs = [rng.uniform(-0.2, 0.2) for _ in range(steps + 1)]
    ANNOUNCE[0](f"reentry {action} from the logger of {trigger} (x{times}, after {steps} steps)")
    run = Run(m)
    inst, t = start2(m, run, steps, inputs)
    twin, _ = start2(m, Run(m), steps, inputs)
    hook = Hook(lambda: ACTIONS2[action](m, inst, t), times)
    hook.extend(inst.log)
    R2.LOGS[inst.env] = hook
    outer = run.call(inst, f"{trigger} (logger re-enters {action})", TRIGGERS2[trigger], m, inst, t)
    outer_twin = TRIGGERS2[trigger](m, twin, t)
    R2.LOGS[inst.env] = list(hook)
    judge(run, action, trigger, hook, outer, outer_twin, R2.ERROR, inst.log)
    # alive, and continues as the twin does
    s, _ = inst.get_real(m.outputs)
    if s != R2.OK:
        run.violations.append(("reentry-freed", f"{action} from the logger of {trigger}: fmi2GetReal after it "
                                                 f"returns {R2.STATUS_NAMES[s]}: {inst.messages()[-1:]}"))
    else:
        after = []
        for i in (inst, twin):
            if i.do_step(t, m.h) != R2.OK:  # the trigger left it in error: start again
                i.reset()
                for k, v in m.baseline.items():
                    m.set_value(i, k, v)
                i.init(10.0)
                i.do_step(0.0, m.h)
            after.append(i.get_real(m.outputs))
        if after[0][0] != after[1][0] or bits(after[0][1]) != bits(after[1][1]):
            run.violations.append(("reentry-changed-state", f"{action} from the logger of {trigger}: the next step "
                                                            f"differs from the twin's"))
    inst.free()
    twin.free()
    R2.LOGS.pop(inst.env, None)
    R2.LOGS.pop(twin.env, None)
    return run, {"case": f"{action} <- {trigger} x{times}", "fired": len(hook.results)}


def judge(run, action, trigger, hook, outer, outer_twin, error, log):
    """The checks shared by FMI 2.0 and 3.0: inner calls refused and logged, outer unchanged."""
    where = f"{action} from the callback of {trigger}"
    frees = action.endswith("FreeInstance")
    for r in hook.results:
        if not frees and r != error:
            run.violations.append(("reentry-accepted", f"{where}: returned {r}, not Error"))
    if hook.results:
        refusals = [msg for (s, _, msg) in log if s == error and REFUSAL in msg and action in msg]
        if not refusals:
            run.violations.append(("reentry-unlogged", f"{where}: no logged refusal naming {action}"))
        else:
            run.refused = True
    if outer != outer_twin:
        run.violations.append(("reentry-outer-changed", f"{where}: the outer call returned {outer}, "
                                                        f"the twin's {outer_twin}"))


# ---------------------------------------------------------------------------------------------
# FMI 3.0

TRIGGERS3 = {
    "fmi3DoStep h<0 (logger)": lambda m, i, t: i.do_step(t, -1.0)[0],
    "fmi3GetFloat64 unknown (logger)": lambda m, i, t: i.get_float64([UNKNOWN_VR])[0],
    "fmi3SetDebugLogging unknown (logger)": lambda m, i, t: i.set_debug_logging(True, ["no-such-category"]),
    "fmi3DoStep (intermediate update)": lambda m, i, t: i.do_step(t, m.h)[0],
}
ACTIONS3 = {
    "fmi3Reset": lambda m, i, t: i.call("fmi3Reset"),
    "fmi3FreeInstance": lambda m, i, t: i.lib.fmu.fmi3FreeInstance(i.c),
    "fmi3DoStep": lambda m, i, t: i.do_step(t, m.h)[0],
    "fmi3GetFloat64": lambda m, i, t: i.get_float64(m.outputs, n=m.n_outputs)[0],
    "fmi3SetFloat64": lambda m, i, t: i.set_float64([m.inputs[0].valueReference], [0.1]) if m.inputs
    else i.get_float64(m.outputs, n=m.n_outputs)[0],
    "fmi3GetFMUState": lambda m, i, t: i.get_state()[0],
    "fmi3Terminate": lambda m, i, t: i.terminate(),
    "fmi3EnterStepMode": lambda m, i, t: i.enter_step_mode(),
}


def start3(m, steps, inputs, intermediate):
    inst = R3.Instance(m.lib, logging_on=True, intermediate=intermediate)
    assert inst.c, inst.messages()
    inst.enter(stop=10.0)
    for name, value in m.values.items():
        v = m.vars[name]
        (inst.set_float64 if v.type == "Float64" else inst.set_int32)([v.valueReference], [value])
    inst.exit()
    t = 0.0
    for k in range(steps):
        if m.inputs:
            inst.set_float64([m.inputs[0].valueReference], [inputs[k]])
        inst.do_step(t, m.h)
        t += m.h
    return inst, t


def reentry3(m, rng, index):
    """One FMI 3.0 re-entry from the logger or the intermediate-update callback."""
    action = sorted(ACTIONS3)[index % len(ACTIONS3)]
    trigger = rng.choice(sorted(TRIGGERS3))
    times = rng.choice([1, 1, 3])
    steps = rng.randint(0, 2)
    inputs = [rng.uniform(-0.2, 0.2) for _ in range(steps + 1)]
    ANNOUNCE[0](f"reentry3 {action} from {trigger} (x{times}, after {steps} steps)")
    run = Run(m)
    box = {}
    via_intermediate = "intermediate" in trigger
    hook = Hook(lambda: ACTIONS3[action](m, box["inst"], box["t"]), times)

    def intermediate(*args):
        if via_intermediate and box.get("armed"):
            hook.append((R3.OK, "intermediate", "update"))

    def nothing(*args):
        pass

    inst, t = start3(m, steps, inputs, intermediate)
    twin, _ = start3(m, steps, inputs, nothing)
    box.update(inst=inst, t=t, armed=True)
    if not via_intermediate:
        hook.extend(inst.log)
        inst.log = hook
    outer = run.call(inst, f"{trigger} (re-enters {action})", TRIGGERS3[trigger], m, inst, t)
    box["armed"] = False
    outer_twin = TRIGGERS3[trigger](m, twin, t)
    log = list(inst.log)
    inst.log = log
    judge(run, action, trigger, hook, outer, outer_twin, R3.ERROR, log)
    if via_intermediate and hook.results and outer == R3.OK:
        a = inst.get_float64(m.outputs, n=m.n_outputs)
        b = twin.get_float64(m.outputs, n=m.n_outputs)
        if a[0] != b[0] or bits(a[1]) != bits(b[1]):
            run.violations.append(("reentry-changed-state", f"{action} from {trigger}: the outputs after the "
                                                            f"step differ from the twin's"))
    s, _ = inst.get_float64([m.fuzzer.time])
    if s != R3.OK:
        run.violations.append(("reentry-freed", f"{action} from {trigger}: fmi3GetFloat64 after it returns "
                                                 f"{R3.STATUS_NAMES[s]}: {inst.messages()[-1:]}"))
    inst.free()
    twin.free()
    return run, {"case": f"{action} <- {trigger} x{times}", "fired": len(hook.results)}
