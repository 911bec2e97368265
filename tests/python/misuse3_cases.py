"""FMI 3.0 misuse cases: each returns the status of the offending call; the table says what is
expected and which words the logged message must contain.

Every case runs in its own forked process (misuse3_worker.py) on a fresh instance, so a crash is
reported per case. `Ctx` finds suitable variables in any model's FMI 3.0 description, so the same
cases apply to every packaged FMU; a case named `typed_*` needs a variable type that not every
model has (it returns SKIP there). Pointers to too-short arrays (undefined behaviour by the
standard) are not cases; calls on a freed instance, freeing an instance twice and calls from
inside the instance's callbacks are in test_misuse_robust.py (one interpreter per case).
"""

import ctypes as C
import math
import random

import fmi3raw as R
from fmi3raw import NULL
from fmpy.fmi3 import (
    fmi3Boolean,
    fmi3ClockUpdateCallback,
    fmi3Float64,
    fmi3FMUState,
    fmi3LockPreemptionCallback,
    fmi3LogMessageCallback,
    fmi3UnlockPreemptionCallback,
    fmi3ValueReference,
)

SKIP = "SKIP"  # the model has no variable of the kind a case needs

BLOCK = 1_000_000  # FMI 3.0 value reference = FMI 2.0 reference + block * BLOCK (docs/fmi3.md)


class Ctx:
    def __init__(self, lib, other=None):
        self.lib, self.md, self.other = lib, lib.md, other
        vs = self.md.modelVariables
        self.names = {v.name: v for v in vs}
        self.time = self.names["time"].valueReference
        floats = [v for v in vs if v.type == "Float64" and v.name != "time"]
        self.param = next(v.valueReference for v in floats if v.causality == "parameter")
        self.tunable = next((v.valueReference for v in floats
                             if v.causality == "parameter" and v.variability == "tunable"), None)
        self.input = next((v.valueReference for v in floats if v.causality == "input"), None)
        # a scalar output (families of outputs are FMI 3.0 arrays, read with nValues = their size)
        self.output = next(v.valueReference for v in floats if v.causality == "output" and not v.dimensions)
        first = lambda t: next((v for v in vs if v.type == t), None)
        self.int32, self.enum, self.boolean, self.string = (first(t) for t in ("Int32", "Enumeration", "Boolean", "String"))
        self.with_min = next((v for v in floats if v.causality in ("parameter", "input") and v.min is not None), None)
        self.unknown = max(v.valueReference for v in vs) + 1000
        de = self.md.defaultExperiment
        self.h = float(de.stepSize) if de and de.stepSize else 0.01

    @property
    def settable(self):
        """A Float64 that may be set in step mode: an input, else a tunable parameter."""
        return self.input if self.input is not None else self.tunable

    def new(self, **kw):
        return R.Instance(self.lib, **kw)

    def ready(self, stop=1.0):
        i = self.new()
        assert i.init(stop=stop) == R.OK, i.messages()
        return i

    def errored(self):
        """An instance moved to the error state by a refused call."""
        i = self.ready()
        assert i.set_float64([self.output], [1.0]) == R.ERROR
        return i


def _seq(i, *calls):
    """Runs calls on `i`; returns the status of the last one (a tuple's first element)."""
    s = None
    for c in calls:
        s = c(i)
        if isinstance(s, tuple):
            s = s[0]
    return s, i


def _raw(x, fname, *args, inst=None):
    i = x.ready() if inst is None else inst
    return i.call(fname, *args), i


def _typed(var, fn):
    if var is None:
        return SKIP, None
    return fn(var)


def _instantiate(x, **kw):
    i = x.new(**kw)
    return (NULL if not i.c else R.OK), i


def _state_bytes(i, x):
    assert i.do_step(0.0, x.h)[0] == R.OK
    s, h = i.get_state()
    assert s == R.OK
    s, data = i.serialize(h)
    assert s == R.OK
    return data


def _deser(x, mutate):
    i = x.ready()
    data = _state_bytes(i, x)
    return i.deserialize(mutate(data))[0], i


def _flip(data):
    b = bytearray(data)
    b[len(b) // 2] ^= 0x20
    return bytes(b)


def _garbage(x):
    i = x.ready()
    return i.deserialize(bytes(random.Random(3).getrandbits(8) for _ in range(256)))[0], i


def _other_instance(x):
    """A ready instance of another model (its own library)."""
    j = R.Instance(x.other)
    assert j.init(stop=1.0) == R.OK, j.messages()
    return j


def _state_of_another_model(x):
    """Bytes serialized by another model's FMU, deserialized here."""
    if x.other is None:
        return SKIP, None
    j = _other_instance(x)
    data = _state_bytes(j, x)
    j.free()
    i = x.ready()
    return i.deserialize(data)[0], i


def _handle_of_another_instance(x):
    """An FMU state handle of another model's instance given to fmi3SetFMUState."""
    if x.other is None:
        return SKIP, None
    j = _other_instance(x)
    s, h = j.get_state()
    assert s == R.OK
    i = x.ready()
    return i.set_state(h), i


def _double_free_state(x):
    i = x.ready()
    s, h = i.get_state()
    i.free_state(h)
    return i.free_state(h)[0], i


def _state_from_step_mode_into_terminated(x):
    """A state saved in step mode restores a terminated instance (it is the state machine too)."""
    i = x.ready()
    s, h = i.get_state()
    assert i.terminate() == R.OK
    assert i.set_state(h) == R.OK
    return i.do_step(0.0, x.h)[0], i


def _recover_by_state(x):
    i = x.ready()
    s, h = i.get_state()
    assert i.set_float64([x.output], [1.0]) == R.ERROR
    assert i.set_state(h) == R.OK
    return i.do_step(0.0, x.h)[0], i


def _recover_by_reset(x):
    i = x.errored()
    assert i.reset() == R.OK
    assert i.init(stop=1.0) == R.OK
    return i.do_step(0.0, x.h)[0], i


def _step_then(x, *calls):
    i = x.ready()
    assert i.do_step(0.0, x.h)[0] == R.OK
    return _seq(i, *calls)


def _failed_step_reports_start(x):
    """A refused step: fmi3Error, no flag set, lastSuccessfulTime the start of the step."""
    i = x.ready(stop=1.0)
    assert i.do_step(0.0, x.h)[0] == R.OK
    s, (ev, term, early, last) = i.do_step(x.h, 5.0)
    assert (ev, term, early) == (False, False, False), (ev, term, early)
    assert last == x.h, last
    return s, i


def _ok_step_flags(x):
    """A completed step: no flag set, lastSuccessfulTime the end of the step, `time` agrees."""
    i = x.ready()
    s, (ev, term, early, last) = i.do_step(0.0, x.h)
    assert (ev, term, early) == (False, False, False)
    assert last == x.h, last
    st, t = i.get_float64([x.time])
    assert st == R.OK and abs(t[0] - x.h) <= 1e-12, t
    return s, i


def _enum_beyond_int32(var):
    def run(x):
        i = x.new()
        return i.set_int64([var.valueReference], [2**40]), i
    return run


def _below_min(x):
    if x.with_min is None:
        return SKIP, None
    i = x.new()
    return i.set_float64([x.with_min.valueReference], [float(x.with_min.min) - 1.0]), i


def _fixed_after_init(x):
    fixed = next((v for v in x.md.modelVariables if v.causality == "parameter" and v.variability == "fixed"), None)
    if fixed is None:
        return SKIP, None
    i = x.ready()
    vr = [fixed.valueReference]
    setter = {"Float64": lambda: i.set_float64(vr, [1.0]), "Int32": lambda: i.set_int32(vr, [1]),
              "Enumeration": lambda: i.set_int64(vr, [1]), "Boolean": lambda: i.set_boolean(vr, [True]),
              "String": lambda: i.set_string(vr, ["x"])}[fixed.type]
    return setter(), i


def _null_logger(x):
    i = x.new(logger=False)
    return i.do_step(0.0, x.h)[0], i


def _null_instance(x):
    return x.lib.call("fmi3DoStep", None, 0.0, 0.1, fmi3Boolean(False), None, None, None, None), None


def _free_null(x):
    x.lib.fmu.fmi3FreeInstance(None)
    return R.OK, None


def _absurd_step_with_stop(x):
    return _seq(x.ready(stop=10.0), lambda i: i.do_step(0.0, 1e300))


def _vr(*vrs):
    return (fmi3ValueReference * len(vrs))(*vrs)


def _nan_in_second_value(x):
    """NaN after a valid value: nothing is set (the whole call is refused)."""
    if x.settable is None:
        return SKIP, None
    i = x.ready()
    s0, before = i.get_float64([x.settable])
    s = i.set_float64([x.settable, x.settable], [before[0] + 0.25, math.nan])
    return s, i



class _Refused:
    """Stands in for an instance that was not created: only the messages of the refusal."""

    def __init__(self):
        self.log, self.c = [], None

    def messages(self, min_status=R.DISCARD):
        return [m for (s, _, m) in self.log if s >= min_status]

    def free(self):
        pass


def _other_interface(x, fname, *callbacks):
    """fmi3InstantiateModelExchange or fmi3InstantiateScheduledExecution: NULL with a message."""
    refused = _Refused()
    logger = fmi3LogMessageCallback(lambda env, s, cat, msg: refused.log.append((s, "", msg.decode())))
    c = getattr(x.lib.fmu, fname)(b"other", x.lib.token.encode(), x.lib.resources.encode(),
                                          fmi3Boolean(False), fmi3Boolean(False), None, logger, *callbacks)
    if c:
        x.lib.fmu.fmi3FreeInstance(c)
    return (NULL if not c else R.OK), refused



def _boolean_byte_two(x):
    """A Boolean set from the byte 2 (C `bool` must be 0 or 1) reads back as true."""
    bools = [v for v in x.md.modelVariables if v.type == "Boolean" and v.causality == "parameter"]
    if not bools:
        return SKIP, None
    var = next((v for v in bools if str(v.start).lower() == "true"), bools[0])
    vr = (fmi3ValueReference * 1)(var.valueReference)
    i = x.new()
    two = (C.c_uint8 * 1)(2)
    assert i.call("fmi3SetBoolean", vr, 1, C.cast(two, C.POINTER(fmi3Boolean)), 1) == R.OK, i.log
    assert i.enter() == R.OK, i.log
    back = (C.c_uint8 * 1)(77)
    s = i.call("fmi3GetBoolean", vr, 1, C.cast(back, C.POINTER(fmi3Boolean)), 1)
    assert back[0] == 1, back[0]
    return s, i


def _time_follows_the_experiment(x):
    """`time` reads the start time in initialization mode and the model time after a step."""
    i = x.new()
    assert i.enter(start=2.5) == R.OK
    s, t = i.get_float64([x.time])
    assert (s, t) == (R.OK, [2.5]), (s, t)
    assert i.exit() == R.OK
    s, (ev, term, early, last) = i.do_step(2.5, x.h)
    assert s == R.OK and last == 2.5 + x.h, (s, last)
    return i.get_float64([x.time])[0], i


def _undefined_values_are_not_read(x):
    """NaN tolerance and stop time with toleranceDefined = stopTimeDefined = false are ignored."""
    i = x.new()
    s = i.call("fmi3EnterInitializationMode", fmi3Boolean(False), math.nan, 0.0, fmi3Boolean(False), math.nan)
    return s, i


def _above_max_int32(var):
    def run(x):
        if var.max is None:
            return SKIP, None
        return _seq(x.new(), lambda i: i.set_int32([var.valueReference], [int(var.max) + 1]))
    return run


def _invalid_utf8(var):
    def run(x):
        i = x.new()
        return i.call("fmi3SetString", _vr(var.valueReference), 1, (C.c_char_p * 1)(b"\xff\xfe"), 1), i
    return run


def _serialize_into_null(x):
    i = x.ready()
    s, h = i.get_state()
    return i.call("fmi3SerializeFMUState", fmi3FMUState(h), None, 10), i


def _deserialize_freed_target(x):
    """Deserializing into a handle that was freed: refused, nothing is written through it."""
    i = x.ready()
    data = _state_bytes(i, x)
    s, h = i.get_state()
    assert i.free_state(h)[0] == R.OK
    return i.deserialize(data, existing=h)[0], i


# (name, expected status, snippet that a logged Discard/Error/Fatal message must contain (None: no
# such message at all; "stderr:..." for messages that go to stderr without a logger; "warning:..."
# for a message logged with status Warning; the recovery cases log the error they recover from),
# case)
# The FMI 3.0 type a `typed_*` case needs a variable of; such a case runs on the models that
# have one (test_misuse3.py collects it only there).
TYPED_NEEDS = {
    "typed_wrong_type_getFloat64_of_a_boolean": "Boolean",
    "typed_wrong_type_setInt32_of_an_enumeration": "Enumeration",
    "typed_wrong_type_getInt64_of_an_int32": "Int32",
    "typed_wrong_type_getBoolean_of_a_string": "String",
    "typed_enumeration_beyond_int32": "Enumeration",
    "typed_setInt32_above_max": "Int32",
    "typed_setInt64_negative_enumeration_item": "Enumeration",
    "typed_setString_invalid_utf8": "String",
}

CASES = [
    # wrong call order: every one an illegal call sequence named by its FMI 3.0 function
    ("order_doStep_before_init", R.ERROR, "fmi3DoStep: illegal call sequence", lambda x: _seq(x.new(), lambda i: i.do_step(0.0, x.h))),
    ("order_doStep_in_init_mode", R.ERROR, "fmi3DoStep: illegal call sequence",
     lambda x: _seq(x.new(), lambda i: i.enter(), lambda i: i.do_step(0.0, x.h))),
    ("order_exit_without_enter", R.ERROR, "fmi3ExitInitializationMode: illegal call sequence", lambda x: _seq(x.new(), lambda i: i.exit())),
    ("order_enter_twice", R.ERROR, "fmi3EnterInitializationMode: illegal call sequence",
     lambda x: _seq(x.new(), lambda i: i.enter(), lambda i: i.enter())),
    ("order_enter_in_step_mode", R.ERROR, "fmi3EnterInitializationMode: illegal call sequence", lambda x: _seq(x.ready(), lambda i: i.enter())),
    ("order_exit_twice", R.ERROR, "fmi3ExitInitializationMode: illegal call sequence", lambda x: _seq(x.ready(), lambda i: i.exit())),
    ("order_enterStepMode_when_instantiated", R.ERROR, "fmi3EnterStepMode: illegal call sequence", lambda x: _seq(x.new(), lambda i: i.enter_step_mode())),
    ("order_enterStepMode_in_init_mode", R.ERROR, "fmi3EnterStepMode: illegal call sequence",
     lambda x: _seq(x.new(), lambda i: i.enter(), lambda i: i.enter_step_mode())),
    ("order_enterStepMode_in_step_mode_is_fine", R.OK, None, lambda x: _seq(x.ready(), lambda i: i.enter_step_mode())),
    ("order_terminate_before_init", R.ERROR, "fmi3Terminate: illegal call sequence", lambda x: _seq(x.new(), lambda i: i.terminate())),
    ("order_terminate_in_init_mode", R.ERROR, "fmi3Terminate: illegal call sequence",
     lambda x: _seq(x.new(), lambda i: i.enter(), lambda i: i.terminate())),
    ("order_getFloat64_when_instantiated", R.ERROR, "fmi3GetFloat64: illegal call sequence",
     lambda x: _seq(x.new(), lambda i: i.get_float64([x.output]))),
    ("order_getState_when_instantiated_is_fine", R.OK, None, lambda x: _seq(x.new(), lambda i: i.get_state())),
    ("order_doStep_in_error_state", R.ERROR, "fmi3DoStep: illegal call sequence", lambda x: _seq(x.errored(), lambda i: i.do_step(0.0, x.h))),
    ("order_setFloat64_in_error_state", R.ERROR, "fmi3SetFloat64: illegal call sequence",
     lambda x: _seq(x.errored(), lambda i: i.set_float64([x.param], [1.0]))),
    ("order_getFloat64_in_error_state_is_fine", R.OK, "is an output", lambda x: _seq(x.errored(), lambda i: i.get_float64([x.output]))),
    # after fmi3Terminate: values stay readable, nothing else goes
    ("terminated_doStep", R.ERROR, "fmi3DoStep: illegal call sequence", lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.do_step(0.0, x.h))),
    ("terminated_terminate_again", R.ERROR, "fmi3Terminate: illegal call sequence",
     lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.terminate())),
    ("terminated_setFloat64", R.ERROR, "fmi3SetFloat64: illegal call sequence",
     lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.set_float64([x.param], [1.0]))),
    ("terminated_enter", R.ERROR, "fmi3EnterInitializationMode: illegal call sequence",
     lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.enter())),
    ("terminated_exit", R.ERROR, "fmi3ExitInitializationMode: illegal call sequence",
     lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.exit())),
    ("terminated_enterStepMode", R.ERROR, "fmi3EnterStepMode: illegal call sequence",
     lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.enter_step_mode())),
    ("terminated_getFloat64_is_fine", R.OK, None, lambda x: _step_then(x, lambda i: i.terminate(), lambda i: i.get_float64([x.output, x.time]))),
    ("terminated_reset_is_fine", R.OK, None, lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.reset(), lambda i: i.init())),
    ("terminated_restored_by_a_state", R.OK, None, _state_from_step_mode_into_terminated),
    # unknown value references, per getter and setter
    ("unknown_vr_getFloat64", R.ERROR, "fmi3GetFloat64: unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_float64([x.unknown]))),
    ("unknown_vr_setFloat64", R.ERROR, "fmi3SetFloat64: unknown value reference", lambda x: _seq(x.new(), lambda i: i.set_float64([x.unknown], [1.0]))),
    ("unknown_vr_getInt32", R.ERROR, "fmi3GetInt32: unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_int32([x.unknown]))),
    ("unknown_vr_setInt32", R.ERROR, "fmi3SetInt32: unknown value reference", lambda x: _seq(x.new(), lambda i: i.set_int32([x.unknown], [1]))),
    ("unknown_vr_getInt64", R.ERROR, "fmi3GetInt64: unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_int64([x.unknown]))),
    ("unknown_vr_setInt64", R.ERROR, "fmi3SetInt64: unknown value reference", lambda x: _seq(x.new(), lambda i: i.set_int64([x.unknown], [1]))),
    ("unknown_vr_getBoolean", R.ERROR, "fmi3GetBoolean: unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_boolean([x.unknown]))),
    ("unknown_vr_setBoolean", R.ERROR, "fmi3SetBoolean: unknown value reference", lambda x: _seq(x.new(), lambda i: i.set_boolean([x.unknown], [True]))),
    ("unknown_vr_getString", R.ERROR, "fmi3GetString: unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_string([x.unknown]))),
    ("unknown_vr_setString", R.ERROR, "fmi3SetString: unknown value reference",
     lambda x: _seq(x.new(), lambda i: i.set_string([x.unknown], ["%s%n%s"]))),
    ("unknown_vr_among_valid_ones", R.ERROR, "unknown value reference",
     lambda x: _seq(x.ready(), lambda i: i.get_float64([x.output, x.unknown, x.output]))),
    ("unknown_vr_fmi2_number_of_an_integer", R.ERROR, "unknown value reference",
     lambda x: _seq(x.ready(), lambda i: i.get_float64([BLOCK - 1]))),
    ("unknown_vr_top_of_the_range", R.ERROR, "unknown value reference 4294967295",
     lambda x: _seq(x.ready(), lambda i: i.get_int32([2**32 - 1]))),
    ("unknown_vr_getFloat32", R.ERROR, "no Float32 variables", lambda x: _raw(x, "fmi3GetFloat32", _vr(x.output), 1, (C.c_float * 1)(), 1)),
    ("unknown_vr_setUInt64", R.ERROR, "no UInt64 variables", lambda x: _raw(x, "fmi3SetUInt64", _vr(x.param), 1, (C.c_uint64 * 1)(7), 1)),
    ("unknown_vr_getBinary", R.ERROR, "no Binary variables",
     lambda x: _raw(x, "fmi3GetBinary", _vr(x.output), 1, (C.c_size_t * 1)(), (C.POINTER(C.c_uint8) * 1)(), 1)),
    ("unknown_vr_getClock", R.ERROR, "no Clock variables", lambda x: _raw(x, "fmi3GetClock", _vr(x.output), 1, (fmi3Boolean * 1)())),
    ("empty_getInt8_is_fine", R.OK, None, lambda x: _raw(x, "fmi3GetInt8", None, 0, None, 0)),
    # a known value reference through the wrong type
    ("wrong_type_getInt32_of_a_float64", R.ERROR, "a Float64 (fmi3Get/SetFloat64) variable, not Int32", lambda x: _seq(x.ready(), lambda i: i.get_int32([x.output]))),
    ("wrong_type_getBoolean_of_a_float64", R.ERROR, "a Float64 (fmi3Get/SetFloat64) variable, not Boolean",
     lambda x: _seq(x.ready(), lambda i: i.get_boolean([x.output]))),
    ("wrong_type_setString_of_a_float64", R.ERROR, "a Float64 (fmi3Get/SetFloat64) variable, not String",
     lambda x: _seq(x.new(), lambda i: i.set_string([x.param], ["1.0"]))),
    ("wrong_type_setInt64_of_a_float64", R.ERROR, "a Float64 (fmi3Get/SetFloat64) variable, not Enumeration", lambda x: _seq(x.new(), lambda i: i.set_int64([x.param], [1]))),
    ("typed_wrong_type_getFloat64_of_a_boolean", R.ERROR, "Boolean (fmi3Get/SetBoolean) variable, not Float64",
     lambda x: _typed(x.boolean, lambda v: _seq(x.ready(), lambda i: i.get_float64([v.valueReference])))),
    ("typed_wrong_type_setInt32_of_an_enumeration", R.ERROR, "not Int32",
     lambda x: _typed(x.enum, lambda v: _seq(x.new(), lambda i: i.set_int32([v.valueReference], [1])))),
    ("typed_wrong_type_getInt64_of_an_int32", R.ERROR, "an Int32 (fmi3Get/SetInt32) variable, not Enumeration",
     lambda x: _typed(x.int32, lambda v: _seq(x.ready(), lambda i: i.get_int64([v.valueReference])))),
    ("typed_wrong_type_getBoolean_of_a_string", R.ERROR, "String (fmi3Get/SetString) variable, not Boolean",
     lambda x: _typed(x.string, lambda v: _seq(x.ready(), lambda i: i.get_boolean([v.valueReference])))),
    ("typed_enumeration_beyond_int32", R.ERROR, "is not one of its enumeration items",
     lambda x: _typed(x.enum, lambda v: _enum_beyond_int32(v)(x))),
    ("time_set", R.ERROR, "independent variable `time`, which cannot be set", lambda x: _seq(x.ready(), lambda i: i.set_float64([x.time], [1.0]))),
    ("time_getInt32", R.ERROR, "unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_int32([x.time]))),
    # refused values
    ("set_output", R.ERROR, "is an output", lambda x: _seq(x.ready(), lambda i: i.set_float64([x.output], [1.0]))),
    ("set_fixed_parameter_after_init", R.ERROR, "fixed parameter", _fixed_after_init),
    ("setFloat64_nan_parameter", R.ERROR, "must be finite", lambda x: _seq(x.new(), lambda i: i.set_float64([x.param], [math.nan]))),
    ("setFloat64_inf_in_step_mode", R.ERROR, "must be finite",
     lambda x: _seq(x.ready(), lambda i: i.set_float64([x.settable], [math.inf])) if x.settable is not None else (SKIP, None)),
    ("setFloat64_minus_inf_in_step_mode", R.ERROR, "must be finite",
     lambda x: _seq(x.ready(), lambda i: i.set_float64([x.settable], [-math.inf])) if x.settable is not None else (SKIP, None)),
    ("setFloat64_nan_after_a_valid_value", R.ERROR, "must be finite", _nan_in_second_value),
    ("setFloat64_below_min", R.ERROR, "below its minimum", _below_min),
    ("setBoolean_byte_two_is_true", R.OK, None, _boolean_byte_two),
    ("typed_setInt32_above_max", R.ERROR, "is above its maximum", lambda x: _typed(x.int32, lambda v: _above_max_int32(v)(x))),
    ("typed_setInt64_negative_enumeration_item", R.ERROR, "= -1 is not an item of enumeration",
     lambda x: _typed(x.enum, lambda v: _seq(x.new(), lambda i: i.set_int64([v.valueReference], [-1])))),
    ("typed_setString_invalid_utf8", R.ERROR, "values[0] is not valid UTF-8", lambda x: _typed(x.string, lambda v: _invalid_utf8(v)(x))),
    ("setString_null_value", R.ERROR, "values[0] is NULL", lambda x: _seq(x.new(), lambda i: i.set_string([x.unknown], [None]))),
    # array lengths: nValues must equal the number of values (scalars here)
    ("nValues_larger_getFloat64", R.ERROR, "nValues = 2 does not match the 1 values of the 1 value references",
     lambda x: _seq(x.ready(), lambda i: i.get_float64([x.output], n=2))),
    ("nValues_smaller_getFloat64", R.ERROR, "nValues = 1 does not match the 2 values of the 2 value references",
     lambda x: _seq(x.ready(), lambda i: i.get_float64([x.output, x.time], n=1))),
    ("nValues_zero_setFloat64", R.ERROR, "nValues = 0 does not match the 1 values of the 1 value references",
     lambda x: _seq(x.new(), lambda i: i.set_float64([x.param], [], n=0))),
    # an unknown reference is named before the count is checked
    ("nValues_larger_setBoolean", R.ERROR, "unknown value reference",
     lambda x: _seq(x.new(), lambda i: i.set_boolean([x.unknown], [True, False]))),
    ("nValues_larger_setString", R.ERROR, "unknown value reference",
     lambda x: _seq(x.new(), lambda i: i.set_string([x.unknown], ["a", "b"]))),
    ("null_value_references", R.ERROR, "valueReferences[] is NULL", lambda x: _raw(x, "fmi3GetFloat64", None, 2, (fmi3Float64 * 2)(), 2)),
    ("null_values", R.ERROR, "values[] is NULL", lambda x: _raw(x, "fmi3SetFloat64", _vr(x.param), 1, None, 1)),
    ("zero_length_null_arrays_are_fine", R.OK, None, lambda x: _raw(x, "fmi3SetFloat64", None, 0, None, 0)),
    # steps
    ("doStep_zero_step", R.ERROR, "must be positive", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, 0.0))),
    ("doStep_negative_step", R.ERROR, "must be positive", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, -x.h))),
    ("doStep_nan_step", R.ERROR, "must be positive", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, math.nan))),
    ("doStep_infinite_step", R.ERROR, "must be positive", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, math.inf))),
    ("doStep_below_time_resolution", R.ERROR, "below the model's time resolution", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, 1e-12))),
    ("doStep_denormal_step", R.ERROR, "below the model's time resolution", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, 5e-324))),
    ("doStep_absurd_step_past_stop_time", R.ERROR, "past the stop time", _absurd_step_with_stop),
    ("doStep_past_stop_time", R.ERROR, "past the stop time", lambda x: _seq(x.ready(stop=1.0), lambda i: i.do_step(0.0, 1.5))),
    ("doStep_time_ahead_of_the_model", R.ERROR, "does not match the model time", lambda x: _seq(x.ready(), lambda i: i.do_step(0.5, x.h))),
    ("doStep_time_behind_the_model", R.ERROR, "does not match the model time", lambda x: _step_then(x, lambda i: i.do_step(0.0, x.h))),
    ("doStep_nan_time", R.ERROR, "must be finite", lambda x: _seq(x.ready(), lambda i: i.do_step(math.nan, x.h))),
    ("doStep_null_flag_pointers", R.ERROR, "eventHandlingNeeded is NULL", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, x.h, flags=False))),
    ("doStep_jittered_time_is_fine", R.OK, None,
     lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, 0.01), lambda i: i.do_step(0.009999999999999998, 0.01))),
    ("doStep_flags_of_a_completed_step", R.OK, None, _ok_step_flags),
    ("doStep_flags_of_a_refused_step", R.ERROR, "past the stop time", _failed_step_reports_start),
    # fmi3EnterInitializationMode's experiment
    ("time_follows_the_experiment", R.OK, None, _time_follows_the_experiment),
    ("enter_zero_tolerance", R.ERROR, "tolerance 0 must be positive", lambda x: _seq(x.new(), lambda i: i.enter(tol=0.0))),
    ("enter_nan_tolerance", R.ERROR, "tolerance NaN must be positive", lambda x: _seq(x.new(), lambda i: i.enter(tol=math.nan))),
    ("enter_undefined_nan_values_are_not_read", R.OK, None, _undefined_values_are_not_read),
    ("enter_stop_before_start", R.ERROR, "stopTime", lambda x: _seq(x.new(), lambda i: i.enter(start=1.0, stop=0.5))),
    ("enter_negative_tolerance", R.ERROR, "tolerance", lambda x: _seq(x.new(), lambda i: i.enter(tol=-1e-6))),
    ("enter_nan_start", R.ERROR, "startTime", lambda x: _seq(x.new(), lambda i: i.enter(start=math.nan))),
    ("enter_infinite_stop", R.ERROR, "stopTime", lambda x: _seq(x.new(), lambda i: i.enter(stop=math.inf))),
    # instantiation
    ("instantiate_wrong_token", NULL, "unknown instantiationToken", lambda x: _instantiate(x, token="{00000000-dead-beef}")),
    ("instantiate_null_token", NULL, "instantiationToken is NULL", lambda x: _instantiate(x, token=None)),
    ("instantiate_null_name", NULL, "instanceName is NULL", lambda x: _instantiate(x, name=None)),
    ("instantiate_token_with_format_directives", NULL, "%s%n%p%n", lambda x: _instantiate(x, token="%s%n%p%n")),
    # an unusable resource path is refused, never run with other parameters (issue #48,
    # docs/resource_location.md)
    ("instantiate_relative_resource_path", NULL, "is not an absolute path", lambda x: _instantiate(x, resource_path="resources/")),
    ("instantiate_early_return_allowed_is_accepted", R.OK, None, lambda x: _instantiate(x, early_return_allowed=True, logging_on=True)),
    ("instantiate_null_resource_path_is_a_warning", R.OK, "warning:resourcePath is NULL",
     lambda x: _instantiate(x, resource_path=None, logging_on=True)),
    ("instantiate_missing_resource_folder", NULL, "not an existing folder",
     lambda x: _instantiate(x, resource_path="/nonexistent/mbcosim/", logging_on=True)),
    ("instantiate_model_exchange", NULL, "Model Exchange is not provided",
     lambda x: _other_interface(x, "fmi3InstantiateModelExchange")),
    ("instantiate_scheduled_execution", NULL, "Scheduled Execution is not provided",
     lambda x: _other_interface(x, "fmi3InstantiateScheduledExecution", fmi3ClockUpdateCallback(),
                                fmi3LockPreemptionCallback(), fmi3UnlockPreemptionCallback())),
    ("null_logger_still_reports", R.ERROR, "stderr:illegal call sequence", _null_logger),
    ("null_instance", R.ERROR, "stderr:NULL instance", _null_instance),
    ("free_null_instance", R.OK, None, _free_null),
    # logging control
    ("debug_logging_unknown_category", R.ERROR, "unknown log category", lambda x: _seq(x.new(), lambda i: i.set_debug_logging(True, ["logEverything"]))),
    ("debug_logging_null_category", R.ERROR, "categories[0] is NULL", lambda x: _seq(x.new(), lambda i: i.set_debug_logging(True, [None]))),
    ("errors_are_logged_with_logging_off", R.ERROR, "must be finite",
     lambda x: _seq(x.new(logging_on=False), lambda i: i.set_float64([x.param], [math.nan]))),
    # unsupported functions
    ("debug_logging_null_categories_with_a_length", R.ERROR, "categories[] is NULL but its length is 3",
     lambda x: _seq(x.new(), lambda i: i.call("fmi3SetDebugLogging", fmi3Boolean(True), 3, None))),
    ("unsupported_enterEventMode", R.ERROR, "fmi3EnterEventMode: not supported", lambda x: _raw(x, "fmi3EnterEventMode")),
    ("unsupported_updateDiscreteStates", R.ERROR, "not supported",
     lambda x: _raw(x, "fmi3UpdateDiscreteStates", *[C.byref(fmi3Boolean()) for _ in range(5)], C.byref(fmi3Float64()))),
    ("unsupported_getDirectionalDerivative", R.ERROR, "not supported",
     lambda x: _raw(x, "fmi3GetDirectionalDerivative", None, 0, None, 0, None, 0, None, 0)),
    ("unsupported_getOutputDerivatives", R.ERROR, "maxOutputDerivativeOrder",
     lambda x: _raw(x, "fmi3GetOutputDerivatives", _vr(x.output), 1, (C.c_int32 * 1)(1), (fmi3Float64 * 1)(), 1)),
    ("unsupported_enterConfigurationMode", R.ERROR, "not supported", lambda x: _raw(x, "fmi3EnterConfigurationMode")),
    ("unsupported_setTime", R.ERROR, "Model Exchange is not provided", lambda x: _raw(x, "fmi3SetTime", 1.0)),
    # FMU states
    ("state_truncated", R.ERROR, "truncated", lambda x: _deser(x, lambda d: d[: len(d) // 2])),
    ("state_one_byte_short", R.ERROR, "truncated", lambda x: _deser(x, lambda d: d[:-1])),
    ("state_bit_flip", R.ERROR, "checksum", lambda x: _deser(x, _flip)),
    ("state_trailing_byte", R.ERROR, "checksum", lambda x: _deser(x, lambda d: d + b"\0")),
    ("state_empty", R.ERROR, "truncated", lambda x: _deser(x, lambda d: b"")),
    ("state_garbage", R.ERROR, "magic", _garbage),
    ("state_newer_format", R.ERROR, "format version 2", lambda x: _deser(x, lambda d: R.reseal(d[:8] + (2).to_bytes(4, "little") + d[12:-8]))),
    ("state_of_another_model", R.ERROR, "FMU state belongs to model", _state_of_another_model),
    ("state_handle_of_another_instance", R.ERROR, "not created by this instance", _handle_of_another_instance),
    ("state_bogus_handle", R.ERROR, "not created by this instance", lambda x: _seq(x.ready(), lambda i: i.set_state(0x1234))),
    ("state_null_handle", R.ERROR, "FMUState is NULL", lambda x: _seq(x.ready(), lambda i: i.set_state(None))),
    ("state_freed_twice", R.ERROR, "already freed", _double_free_state),
    ("state_buffer_too_small", R.ERROR, "too small",
     lambda x: _seq(x.ready(), lambda i: i.serialize(i.get_state()[1], size=10))),
    ("state_size_into_null", R.ERROR, "size is NULL",
     lambda x: _seq(x.ready(), lambda i: i.call("fmi3SerializedFMUStateSize", i.get_state()[1], None))),
    ("state_get_into_null_pointer", R.ERROR, "FMUState is NULL", lambda x: _raw(x, "fmi3GetFMUState", None)),
    ("state_serialize_into_null", R.ERROR, "serializedState[] is NULL but its length is 10", _serialize_into_null),
    ("state_deserialize_from_null", R.ERROR, "serializedState[] is NULL but its length is 10",
     lambda x: _seq(x.ready(), lambda i: i.call("fmi3DeserializeFMUState", None, 10, C.byref(fmi3FMUState())))),
    ("state_deserialize_into_a_freed_handle", R.ERROR, "was not created by this instance or was already freed", _deserialize_freed_target),
    ("state_get_over_a_bogus_handle", R.ERROR, "FMU state 0x999 was not created by this instance", lambda x: _seq(x.ready(), lambda i: i.get_state(existing=0x999))),
    ("state_free_null_pointer", R.ERROR, "FMUState is NULL", lambda x: _seq(x.ready(), lambda i: i.call("fmi3FreeFMUState", None))),
    ("state_free_null_handle_is_fine", R.OK, None, lambda x: _seq(x.ready(), lambda i: i.free_state(None))),
    ("state_restore_recovers_from_error", R.OK, "is an output", _recover_by_state),
    ("reset_recovers_from_error", R.OK, "is an output", _recover_by_reset),
]


NAMES = [c[0] for c in CASES]
assert len(set(NAMES)) == len(NAMES)
