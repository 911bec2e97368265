"""Misuse cases: each returns the status of the offending call; the table says what is expected.

Every case runs in its own forked process (misuse_worker.py) on a fresh instance, so a crash is
reported per case and cannot take pytest down. `Ctx` finds suitable variables in any model's
description, so the same cases apply to every packaged FMU.
"""

import ctypes as C
import random
import resource
import sys

import fmi2raw as R

NULL = "NULL"  # expected "status" of a refused fmi2Instantiate
SKIP = "SKIP"  # the model has no variable of the kind a case needs


class Ctx:
    def __init__(self, lib, md):
        self.lib, self.md, self.guid = lib, md, md.guid
        vs = md.modelVariables
        reals = [v for v in vs if v.type == "Real"]
        self.param = next(v.valueReference for v in reals if v.causality == "parameter")
        self.input = next((v.valueReference for v in reals if v.causality == "input"), None)
        self.output = next(v.valueReference for v in reals if v.causality == "output")
        fixed = [v for v in vs if v.causality == "parameter" and v.variability == "fixed"]
        self.fixed = fixed[0] if fixed else None
        self.with_min = next((v for v in reals if v.causality in ("parameter", "input") and v.min is not None), None)
        self.unknown = max(v.valueReference for v in vs) + 1000
        de = md.defaultExperiment
        self.h = float(de.stepSize) if de and de.stepSize else 0.01
        self.names = {v.name: v for v in vs}

    def new(self, **kw):
        return R.Instance(self.lib, kw.pop("guid", self.guid), **kw)

    def ready(self, stop=1.0):
        i = self.new()
        assert i.init(stop=stop) == R.OK, i.messages()
        return i

    def errored(self):
        """An instance moved to the error state by a refused call."""
        i = self.ready()
        assert i.set_real([self.output], [1.0]) == R.ERROR
        return i


def _state_bytes(x):
    i = x.ready()
    i.do_step(0.0, x.h)
    s, h = i.get_state()
    s, data = i.serialize(h)
    assert s == R.OK
    return i, data


def _with_identifier(data, new_ident):
    n = int.from_bytes(data[12:20], "little")
    body = data[:12] + len(new_ident).to_bytes(8, "little") + new_ident + data[20 + n:-8]
    return R.reseal(body)


def _fixed_after_init(x):
    if x.fixed is None:
        return SKIP, None
    i = x.ready()
    vr = x.fixed.valueReference
    t = x.fixed.type
    if t == "Real":
        return i.set_real([vr], [1.0]), i
    if t == "Boolean":
        return i.set_boolean([vr], [True]), i
    return i.set_integer([vr], [1]), i


def _below_min(x):
    if x.with_min is None:
        return SKIP, None
    i = x.new()
    return i.set_real([x.with_min.valueReference], [float(x.with_min.min) - 1.0]), i


def _raw(x, fname, *args):
    i = x.ready()
    return getattr(x.lib, fname)(i.c, *args), i


def _seq(i, *calls):
    """Runs calls on `i`; returns the status of the last one."""
    s = None
    for c in calls:
        s = c(i)
    return s, i


def _null_component(x):
    return x.lib.fmi2DoStep(None, 0.0, 0.1, 1), None


def _free_null(x):
    x.lib.fmi2FreeInstance(None)
    return R.OK, None


def _instantiate(x, **kw):
    i = x.new(**kw)
    return (NULL if not i.c else R.OK), i


def _cycles(x):
    """10,000 instantiate/free and 10,000 get/free state cycles without memory growth."""
    def rss_kb():
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss

    for _ in range(200):  # warm-up: allocator pools
        x.new().free()
    before = rss_kb()
    for _ in range(10_000):
        x.new().free()
    i = x.ready()
    for _ in range(10_000):
        s, h = i.get_state()
        assert s == R.OK
        assert i.free_state(h)[0] == R.OK
    growth = rss_kb() - before
    print(f"rss growth over 10,000 + 10,000 cycles: {growth} kB", file=sys.stderr)
    return (R.OK if growth < 8 * 1024 else R.ERROR), i


def _pid_only(x, fn):
    if "u_min" not in x.names:
        return SKIP, None
    return fn(x)


def _pid_inverted_limits_at_init(x):
    i = x.new()
    i.setup(stop=1.0)
    i.set_real([x.names["u_min"].valueReference, x.names["u_max"].valueReference], [2.0, 1.0])
    i.enter()
    return i.exit(), i


def _pid_inverted_limits_in_run(x):
    i = x.ready()
    i.set_real([x.names["u_min"].valueReference, x.names["u_max"].valueReference], [2.0, 1.0])
    return i.do_step(0.0, x.h), i


def _recover_by_state(x):
    i = x.ready()
    s, h = i.get_state()
    assert i.set_real([x.output], [1.0]) == R.ERROR
    assert i.set_state(h) == R.OK
    return i.do_step(0.0, x.h), i


def _recover_by_reset(x):
    i = x.errored()
    assert i.reset() == R.OK
    assert i.init(stop=1.0) == R.OK
    return i.do_step(0.0, x.h), i


def _state_of_another_instance(x):
    a, b = x.ready(), x.ready()
    s, h = a.get_state()
    return b.set_state(h), b


def _double_free(x):
    i = x.ready()
    s, h = i.get_state()
    i.free_state(h)
    return i.free_state(h)[0], i


def _garbage(x):
    i = x.ready()
    return i.deserialize(bytes(random.Random(1).getrandbits(8) for _ in range(100)))[0], i


def _deser(x, mutate):
    i, data = _state_bytes(x)
    return i.deserialize(mutate(data))[0], i


def _flip(data):
    b = bytearray(data)
    b[len(b) // 2] ^= 0x20
    return bytes(b)


def _newer(data):
    return R.reseal(data[:8] + (2).to_bytes(4, "little") + data[12:-8])


# (name, expected status, snippet that a logged message must contain (None: no message at all;
# "stderr:..." for messages that go to stderr without a logger; the recovery cases log the error
# they recover from), case)
CASES = [
    # wrong state: every one is an illegal call sequence
    ("state_doStep_before_init", R.ERROR, "illegal call sequence", lambda x: _seq(x.new(), lambda i: i.do_step(0, x.h))),
    ("state_doStep_in_init_mode", R.ERROR, "illegal call sequence",
     lambda x: _seq(x.new(), lambda i: i.setup(), lambda i: i.enter(), lambda i: i.do_step(0, x.h))),
    ("state_exit_without_enter", R.ERROR, "illegal call sequence", lambda x: _seq(x.new(), lambda i: i.exit())),
    ("state_enter_twice", R.ERROR, "illegal call sequence", lambda x: _seq(x.new(), lambda i: i.enter(), lambda i: i.enter())),
    ("state_exit_twice", R.ERROR, "illegal call sequence", lambda x: _seq(x.ready(), lambda i: i.exit())),
    ("state_setup_after_init", R.ERROR, "illegal call sequence", lambda x: _seq(x.ready(), lambda i: i.setup())),
    ("state_terminate_before_init", R.ERROR, "illegal call sequence", lambda x: _seq(x.new(), lambda i: i.terminate())),
    ("state_terminate_twice", R.ERROR, "illegal call sequence", lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.terminate())),
    ("state_getReal_when_instantiated", R.ERROR, "illegal call sequence", lambda x: _seq(x.new(), lambda i: i.get_real([x.output])[0])),
    ("state_setReal_after_terminate", R.ERROR, "illegal call sequence",
     lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.set_real([x.param], [1.0]))),
    ("state_doStep_after_terminate", R.ERROR, "illegal call sequence", lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.do_step(0, x.h))),
    ("state_enter_after_terminate", R.ERROR, "illegal call sequence", lambda x: _seq(x.ready(), lambda i: i.terminate(), lambda i: i.enter())),
    ("state_status_when_instantiated", R.ERROR, "illegal call sequence", lambda x: _seq(x.new(), lambda i: i.real_status()[0])),
    ("state_doStep_in_error_state", R.ERROR, "illegal call sequence", lambda x: _seq(x.errored(), lambda i: i.do_step(0, x.h))),
    ("state_setReal_in_error_state", R.ERROR, "illegal call sequence", lambda x: _seq(x.errored(), lambda i: i.set_real([x.param], [1.0]))),
    # unsupported optional functions
    ("unsupported_cancelStep", R.ERROR, "no step is in progress", lambda x: _raw(x, "fmi2CancelStep")),
    ("unsupported_setRealInputDerivatives", R.ERROR, "not supported", lambda x: _raw(x, "fmi2SetRealInputDerivatives", None, 0, None, None)),
    ("unsupported_getRealOutputDerivatives", R.ERROR, "not supported", lambda x: _raw(x, "fmi2GetRealOutputDerivatives", None, 0, None, None)),
    ("unsupported_getDirectionalDerivative", R.ERROR, "not supported",
     lambda x: _raw(x, "fmi2GetDirectionalDerivative", None, 0, None, 0, None, None)),
    # status queries without an answer
    ("status_doStepStatus", R.DISCARD, "fmi2DoStepStatus", lambda x: _raw(x, "fmi2GetStatus", R.DO_STEP_STATUS, C.byref(C.c_int()))),
    ("status_integer", R.DISCARD, "not available", lambda x: _raw(x, "fmi2GetIntegerStatus", R.DO_STEP_STATUS, C.byref(C.c_int()))),
    ("status_string_pending", R.DISCARD, "fmi2PendingStatus", lambda x: _raw(x, "fmi2GetStringStatus", R.PENDING_STATUS, C.byref(C.c_char_p()))),
    ("status_real_wrong_kind", R.DISCARD, "fmi2DoStepStatus", lambda x: _seq(x.ready(), lambda i: i.real_status(R.DO_STEP_STATUS)[0])),
    ("status_boolean_unknown_kind", R.DISCARD, "unknown status kind 99", lambda x: _seq(x.ready(), lambda i: i.boolean_status(99)[0])),
    ("status_null_value_pointer", R.ERROR, "value is NULL", lambda x: _raw(x, "fmi2GetRealStatus", R.LAST_SUCCESSFUL_TIME, None)),
    # unknown value references
    ("unknown_vr_getReal", R.ERROR, "unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_real([x.unknown])[0])),
    ("unknown_vr_setReal", R.ERROR, "unknown value reference", lambda x: _seq(x.new(), lambda i: i.set_real([x.unknown], [1.0]))),
    ("unknown_vr_getInteger", R.ERROR, "unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_integer([x.unknown])[0])),
    ("unknown_vr_setInteger", R.ERROR, "unknown value reference", lambda x: _seq(x.new(), lambda i: i.set_integer([x.unknown], [1]))),
    ("unknown_vr_getBoolean", R.ERROR, "unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_boolean([x.unknown])[0])),
    ("unknown_vr_setBoolean", R.ERROR, "unknown value reference", lambda x: _seq(x.new(), lambda i: i.set_boolean([x.unknown], [True]))),
    ("unknown_vr_getString", R.ERROR, "unknown value reference", lambda x: _seq(x.ready(), lambda i: i.get_string([x.unknown])[0])),
    ("unknown_vr_setString", R.ERROR, "unknown value reference", lambda x: _seq(x.new(), lambda i: i.set_string([x.unknown], ["%s%n%s"]))),
    ("unknown_vr_among_valid_ones", R.ERROR, "unknown value reference",
     lambda x: _seq(x.ready(), lambda i: i.get_real([x.output, x.unknown, x.output])[0])),
    # refused values
    ("set_output", R.ERROR, "is an output", lambda x: _seq(x.ready(), lambda i: i.set_real([x.output], [1.0]))),
    ("set_fixed_parameter_after_init", R.ERROR, "fixed parameter", _fixed_after_init),
    ("setReal_nan_parameter", R.ERROR, "must be finite", lambda x: _seq(x.new(), lambda i: i.set_real([x.param], [float("nan")]))),
    ("setReal_inf_input", R.ERROR, "must be finite", lambda x: _seq(x.ready(), lambda i: i.set_real([x.param if x.input is None else x.input], [float("inf")]))),
    ("setReal_minus_inf_input", R.ERROR, "must be finite", lambda x: _seq(x.ready(), lambda i: i.set_real([x.param if x.input is None else x.input], [float("-inf")]))),
    ("setReal_below_min", R.ERROR, "below its minimum", _below_min),
    ("setString_null_value", R.ERROR, "value[0] is NULL", lambda x: _seq(x.new(), lambda i: i.set_string([x.unknown], [None]))),
    ("setReal_null_vr_array", R.ERROR, "vr[] is NULL", lambda x: _raw(x, "fmi2SetReal", None, 2, None)),
    ("getReal_null_value_array", R.ERROR, "value[] is NULL", lambda x: _raw(x, "fmi2GetReal", R.arr(C.c_uint, [x.output]), 1, None)),
    ("zero_length_null_arrays_are_fine", R.OK, None, lambda x: _raw(x, "fmi2SetReal", None, 0, None)),
    # steps
    ("doStep_zero_step", R.ERROR, "must be positive", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, 0.0))),
    ("doStep_negative_step", R.ERROR, "must be positive", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, -x.h))),
    ("doStep_nan_step", R.ERROR, "must be positive", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, float("nan")))),
    ("doStep_infinite_step", R.ERROR, "must be positive", lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, float("inf")))),
    ("doStep_wrong_time", R.ERROR, "does not match the model time", lambda x: _seq(x.ready(), lambda i: i.do_step(0.5, x.h))),
    ("doStep_nan_time", R.ERROR, "must be finite", lambda x: _seq(x.ready(), lambda i: i.do_step(float("nan"), x.h))),
    ("doStep_past_stop_time", R.ERROR, "past the stop time", lambda x: _seq(x.ready(stop=1.0), lambda i: i.do_step(0.0, 1.5))),
    ("doStep_jittered_time_is_fine", R.OK, None,
     lambda x: _seq(x.ready(), lambda i: i.do_step(0.0, 0.01), lambda i: i.do_step(0.009999999999999998, 0.01))),
    # setup experiment
    ("setup_stop_before_start", R.ERROR, "stopTime", lambda x: _seq(x.new(), lambda i: i.setup(start=1.0, stop=0.5))),
    ("setup_negative_tolerance", R.ERROR, "tolerance", lambda x: _seq(x.new(), lambda i: i.setup(tol=-1e-6))),
    ("setup_nan_start", R.ERROR, "startTime", lambda x: _seq(x.new(), lambda i: i.setup(start=float("nan")))),
    # instantiation
    ("instantiate_wrong_guid", NULL, "unknown GUID", lambda x: _instantiate(x, guid="{00000000-dead-beef}")),
    ("instantiate_model_exchange", NULL, "Model Exchange", lambda x: _instantiate(x, fmu_type=0)),
    ("instantiate_unknown_type", NULL, "unknown interface type", lambda x: _instantiate(x, fmu_type=7)),
    ("instantiate_null_guid", NULL, "fmuGUID is NULL", lambda x: _instantiate(x, guid=None)),
    ("instantiate_null_name", NULL, "instanceName is NULL", lambda x: _instantiate(x, name=None)),
    ("instantiate_null_callbacks", NULL, "stderr:functions (the callback struct) is NULL", lambda x: _instantiate(x, callbacks=False)),
    ("instantiate_guid_with_format_directives", NULL, "%s%n%p%n", lambda x: _instantiate(x, guid="%s%n%p%n")),
    # an unusable resource location is refused, never run with other parameters (issue #48,
    # docs/resource_location.md)
    ("instantiate_relative_resource_location", NULL, "neither a file: URI nor an absolute path",
     lambda x: _instantiate(x, resource_uri="not a uri")),
    ("instantiate_http_resource_location", NULL, "URI scheme `http:`",
     lambda x: _instantiate(x, resource_uri="http://example.com/resources")),
    ("null_logger_still_reports", R.ERROR, "stderr:illegal call sequence", lambda x: _seq(x.new(logger=False), lambda i: i.do_step(0, x.h))),
    ("null_instance", R.ERROR, "stderr:NULL instance", _null_component),
    ("free_null_instance", R.OK, None, _free_null),
    # logging control
    ("debug_logging_unknown_category", R.ERROR, "unknown log category", lambda x: _seq(x.new(), lambda i: i.set_debug_logging(True, ["logEverything"]))),
    ("debug_logging_null_category", R.ERROR, "categories[0] is NULL", lambda x: _seq(x.new(), lambda i: i.set_debug_logging(True, [None]))),
    ("errors_are_logged_with_logging_off", R.ERROR, "must be finite",
     lambda x: _seq(x.new(logging_on=False), lambda i: i.set_real([x.param], [float("nan")]))),
    # FMU states
    ("state_truncated", R.ERROR, "truncated", lambda x: _deser(x, lambda d: d[: len(d) // 2])),
    ("state_one_byte_short", R.ERROR, "truncated", lambda x: _deser(x, lambda d: d[:-1])),
    ("state_bit_flip", R.ERROR, "checksum", lambda x: _deser(x, _flip)),
    ("state_trailing_byte", R.ERROR, "checksum", lambda x: _deser(x, lambda d: d + b"\0")),
    ("state_garbage", R.ERROR, "magic", _garbage),
    ("state_empty", R.ERROR, "truncated", lambda x: _deser(x, lambda d: b"")),
    ("state_of_another_model", R.ERROR, "belongs to model `OtherModel`", lambda x: _deser(x, lambda d: _with_identifier(d, b"OtherModel"))),
    ("state_newer_format", R.ERROR, "format version 2", lambda x: _deser(x, _newer)),
    ("state_bogus_handle", R.ERROR, "not created by this instance", lambda x: _seq(x.ready(), lambda i: i.set_state(0x1234))),
    ("state_null_handle", R.ERROR, "FMUstate is NULL", lambda x: _seq(x.ready(), lambda i: i.set_state(None))),
    ("state_freed_twice", R.ERROR, "already freed", _double_free),
    ("state_buffer_too_small", R.ERROR, "too small",
     lambda x: _seq(x.ready(), lambda i: x.lib.fmi2SerializeFMUstate(i.c, i.get_state()[1], C.create_string_buffer(10), 10))),
    ("state_get_into_null_pointer", R.ERROR, "FMUstate is NULL", lambda x: _raw(x, "fmi2GetFMUstate", None)),
    ("state_of_another_instance", R.ERROR, "not created by this instance", _state_of_another_instance),
    ("state_restore_recovers_from_error", R.OK, "is an output", _recover_by_state),
    ("reset_recovers_from_error", R.OK, "is an output", _recover_by_reset),
    # model-specific
    ("pid_inverted_limits_at_initialization", R.ERROR, "u_min", lambda x: _pid_only(x, _pid_inverted_limits_at_init)),
    ("pid_inverted_limits_during_the_run", R.ERROR, "u_min", lambda x: _pid_only(x, _pid_inverted_limits_in_run)),
    # resources
    ("cycles_10000_instances_and_states_without_growth", R.OK, None, _cycles),
]

NAMES = [c[0] for c in CASES]
assert len(set(NAMES)) == len(NAMES)
