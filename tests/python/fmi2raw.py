"""Thin ctypes binding of the 34 FMI 2.0 functions of an unpacked FMU, returning raw statuses.

fmpy raises on error statuses; the misuse cases and the fuzzer need the raw status codes and
every logged message, so they call the shared library directly. Messages are formatted by
fmpy's native logger proxy (the FMU's logger is printf-variadic) and collected per instance.
"""

import ctypes as C
import os
from ctypes import POINTER, byref, c_char_p, c_double, c_int, c_size_t, c_uint, c_void_p

import fmpy.logging
from fmpy.fmi2 import fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

OK, WARNING, DISCARD, ERROR, FATAL, PENDING = range(6)
STATUS_NAMES = ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"]
DO_STEP_STATUS, PENDING_STATUS, LAST_SUCCESSFUL_TIME, TERMINATED = range(4)

_vr = POINTER(c_uint)
_SIGNATURES = {
    "fmi2GetTypesPlatform": (c_char_p, []),
    "fmi2GetVersion": (c_char_p, []),
    "fmi2SetDebugLogging": (c_int, [c_void_p, c_int, c_size_t, POINTER(c_char_p)]),
    "fmi2Instantiate": (c_void_p, [c_char_p, c_int, c_char_p, c_char_p, c_void_p, c_int, c_int]),
    "fmi2FreeInstance": (None, [c_void_p]),
    "fmi2SetupExperiment": (c_int, [c_void_p, c_int, c_double, c_double, c_int, c_double]),
    "fmi2EnterInitializationMode": (c_int, [c_void_p]),
    "fmi2ExitInitializationMode": (c_int, [c_void_p]),
    "fmi2Terminate": (c_int, [c_void_p]),
    "fmi2Reset": (c_int, [c_void_p]),
    "fmi2GetReal": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_double)]),
    "fmi2GetInteger": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_int)]),
    "fmi2GetBoolean": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_int)]),
    "fmi2GetString": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_char_p)]),
    "fmi2SetReal": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_double)]),
    "fmi2SetInteger": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_int)]),
    "fmi2SetBoolean": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_int)]),
    "fmi2SetString": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_char_p)]),
    "fmi2GetFMUstate": (c_int, [c_void_p, POINTER(c_void_p)]),
    "fmi2SetFMUstate": (c_int, [c_void_p, c_void_p]),
    "fmi2FreeFMUstate": (c_int, [c_void_p, POINTER(c_void_p)]),
    "fmi2SerializedFMUstateSize": (c_int, [c_void_p, c_void_p, POINTER(c_size_t)]),
    "fmi2SerializeFMUstate": (c_int, [c_void_p, c_void_p, c_char_p, c_size_t]),
    "fmi2DeSerializeFMUstate": (c_int, [c_void_p, c_char_p, c_size_t, POINTER(c_void_p)]),
    "fmi2GetDirectionalDerivative": (c_int, [c_void_p, _vr, c_size_t, _vr, c_size_t, POINTER(c_double), POINTER(c_double)]),
    "fmi2SetRealInputDerivatives": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_int), POINTER(c_double)]),
    "fmi2GetRealOutputDerivatives": (c_int, [c_void_p, _vr, c_size_t, POINTER(c_int), POINTER(c_double)]),
    "fmi2DoStep": (c_int, [c_void_p, c_double, c_double, c_int]),
    "fmi2CancelStep": (c_int, [c_void_p]),
    "fmi2GetStatus": (c_int, [c_void_p, c_int, POINTER(c_int)]),
    "fmi2GetRealStatus": (c_int, [c_void_p, c_int, POINTER(c_double)]),
    "fmi2GetIntegerStatus": (c_int, [c_void_p, c_int, POINTER(c_int)]),
    "fmi2GetBooleanStatus": (c_int, [c_void_p, c_int, POINTER(c_int)]),
    "fmi2GetStringStatus": (c_int, [c_void_p, c_int, POINTER(c_char_p)]),
}
assert len(_SIGNATURES) == 34

# Messages per component environment id (fmpy's proxy keeps one global Python logger).
LOGS: dict[int, list[tuple[int, str, str]]] = {}
_next_env = [1]


@fmi2CallbackLoggerTYPE
def _dispatch(env, instance_name, status, category, message):
    LOGS.setdefault(env or 0, []).append(
        (status, (category or b"").decode(errors="replace"), (message or b"").decode(errors="replace"))
    )


class Library:
    """The FMU's shared library with typed functions."""

    def __init__(self, unzip_dir, identifier):
        path = os.path.join(unzip_dir, "binaries", "linux64", identifier + ".so")
        self.unzip_dir = unzip_dir
        self.dll = C.CDLL(path)
        for name, (restype, argtypes) in _SIGNATURES.items():
            f = getattr(self.dll, name)
            f.restype, f.argtypes = restype, argtypes
            setattr(self, name, f)


def arr(ctype, values):
    """A C array (or NULL for None)."""
    return None if values is None else (ctype * len(values))(*values)


class Instance:
    """One instance with its own log; every method returns the raw status first."""

    def __init__(self, lib, guid, name="inst", fmu_type=1, logging_on=False, logger=True,
                 callbacks=True, resource_uri=None):
        self.lib = lib
        self.env = _next_env[0]
        _next_env[0] += 1
        LOGS[self.env] = []
        self.callbacks = fmi2CallbackFunctions()
        if logger:
            self.callbacks.logger = _dispatch
            fmpy.logging.addLoggerProxy(byref(self.callbacks))
        self.callbacks.componentEnvironment = self.env
        uri = resource_uri if resource_uri is not None else "file://" + os.path.join(lib.unzip_dir, "resources")
        encode = lambda s: None if s is None else s.encode()
        self.c = lib.fmi2Instantiate(
            encode(name), fmu_type, encode(guid), encode(uri),
            byref(self.callbacks) if callbacks else None, 0, int(logging_on))

    @property
    def log(self):
        return LOGS[self.env]

    def messages(self, min_status=DISCARD):
        return [m for (s, _, m) in self.log if s >= min_status]

    def free(self):
        if self.c:
            self.lib.fmi2FreeInstance(self.c)
            self.c = None

    # life cycle
    def setup(self, start=0.0, stop=None, tol=None):
        return self.lib.fmi2SetupExperiment(self.c, tol is not None, tol or 0.0, start, stop is not None, stop or 0.0)

    def enter(self):
        return self.lib.fmi2EnterInitializationMode(self.c)

    def exit(self):
        return self.lib.fmi2ExitInitializationMode(self.c)

    def init(self, stop=None, values=None):
        statuses = [self.setup(stop=stop)]
        for vr, v in (values or {}).items():
            statuses.append(self.set_real([vr], [v]))
        statuses += [self.enter(), self.exit()]
        return max(statuses)

    def terminate(self):
        return self.lib.fmi2Terminate(self.c)

    def reset(self):
        return self.lib.fmi2Reset(self.c)

    def do_step(self, t, h):
        return self.lib.fmi2DoStep(self.c, t, h, 1)

    # values
    def set_real(self, vrs, values):
        return self.lib.fmi2SetReal(self.c, arr(c_uint, vrs), len(vrs), arr(c_double, values))

    def get_real(self, vrs):
        out = (c_double * max(len(vrs), 1))()
        s = self.lib.fmi2GetReal(self.c, arr(c_uint, vrs), len(vrs), out)
        return s, list(out[: len(vrs)])

    def set_integer(self, vrs, values):
        return self.lib.fmi2SetInteger(self.c, arr(c_uint, vrs), len(vrs), arr(c_int, values))

    def get_integer(self, vrs):
        out = (c_int * max(len(vrs), 1))()
        s = self.lib.fmi2GetInteger(self.c, arr(c_uint, vrs), len(vrs), out)
        return s, list(out[: len(vrs)])

    def set_boolean(self, vrs, values):
        return self.lib.fmi2SetBoolean(self.c, arr(c_uint, vrs), len(vrs), arr(c_int, [int(v) for v in values]))

    def get_boolean(self, vrs):
        out = (c_int * max(len(vrs), 1))()
        s = self.lib.fmi2GetBoolean(self.c, arr(c_uint, vrs), len(vrs), out)
        return s, list(out[: len(vrs)])

    def set_string(self, vrs, values):
        return self.lib.fmi2SetString(self.c, arr(c_uint, vrs), len(vrs),
                                      arr(c_char_p, [None if v is None else v.encode() for v in values]))

    def get_string(self, vrs):
        out = (c_char_p * max(len(vrs), 1))()
        s = self.lib.fmi2GetString(self.c, arr(c_uint, vrs), len(vrs), out)
        return s, [None if v is None else v.decode() for v in out[: len(vrs)]]

    # FMU state
    def get_state(self, existing=None):
        h = c_void_p(existing)
        s = self.lib.fmi2GetFMUstate(self.c, byref(h))
        return s, h.value

    def set_state(self, handle):
        return self.lib.fmi2SetFMUstate(self.c, handle)

    def free_state(self, handle):
        h = c_void_p(handle)
        s = self.lib.fmi2FreeFMUstate(self.c, byref(h))
        return s, h.value

    def serialize(self, handle):
        size = c_size_t(0)
        s = self.lib.fmi2SerializedFMUstateSize(self.c, handle, byref(size))
        if s != OK:
            return s, b""
        buf = C.create_string_buffer(size.value)
        s = self.lib.fmi2SerializeFMUstate(self.c, handle, buf, size.value)
        return s, buf.raw

    def deserialize(self, data, existing=None):
        h = c_void_p(existing)
        s = self.lib.fmi2DeSerializeFMUstate(self.c, data, len(data), byref(h))
        return s, h.value

    # status queries
    def real_status(self, kind=LAST_SUCCESSFUL_TIME):
        v = c_double(0.0)
        return self.lib.fmi2GetRealStatus(self.c, kind, byref(v)), v.value

    def boolean_status(self, kind=TERMINATED):
        v = c_int(0)
        return self.lib.fmi2GetBooleanStatus(self.c, kind, byref(v)), v.value

    def set_debug_logging(self, on, categories=None):
        cats = arr(c_char_p, None if categories is None else [None if c is None else c.encode() for c in categories])
        return self.lib.fmi2SetDebugLogging(self.c, int(on), 0 if categories is None else len(categories), cats)


def fnv1a64(data: bytes) -> int:
    """The checksum at the end of a serialized FMU state (64-bit FNV-1a)."""
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def reseal(body: bytes) -> bytes:
    """`body` (a serialized state without its checksum) with a valid checksum appended."""
    return body + fnv1a64(body).to_bytes(8, "little")
