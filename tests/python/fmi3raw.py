"""FMI 3.0 calls through fmpy's FMU3Slave bindings that return the raw status instead of raising.

fmpy's FMU3Slave loads the library and declares every `fmi3*` function with ctypes (argument and
result types from its annotations); its high-level methods raise on Error and drop the status of
the others. The misuse cases (misuse3_cases.py) and the fuzzer (fuzz3_worker.py) need the status
of every call and every logged message, so they call FMU3Slave's low-level `fmi3*` methods with
an explicit instance pointer and turn fmpy's FMICallException back into the status it carries.

One `Library` (one FMU3Slave: one loaded shared library) serves any number of `Instance`s; each
instance has its own logMessage callback and message list (FMI 3.0's callback is not variadic).
"""

import ctypes as C
import os
from ctypes import byref, c_size_t

from fmpy import read_model_description
from fmi2raw import reseal  # noqa: F401 - the FMU state format is the FMI 2.0 one
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import (
    FMU3Slave,
    fmi3Boolean,
    fmi3Byte,
    fmi3Float64,
    fmi3FMUState,
    fmi3Int32,
    fmi3Int64,
    fmi3InstanceEnvironment,
    fmi3IntermediateUpdateCallback,
    fmi3LogMessageCallback,
    fmi3String,
    fmi3ValueReference,
)

OK, WARNING, DISCARD, ERROR, FATAL = range(5)
STATUS_NAMES = ["OK", "Warning", "Discard", "Error", "Fatal"]
NULL = "NULL"  # the "status" of a refused instantiation
DEFAULT = object()  # an argument left to the model: its own token, its resources folder


class Library:
    """An unpacked FMI 3.0 FMU: its model description and its library bound by FMU3Slave."""

    def __init__(self, unzip_dir, identifier=None):
        self.unzip_dir = unzip_dir
        self.md = read_model_description(os.path.join(unzip_dir, "modelDescription.xml"))
        self.id = identifier or self.md.coSimulation.modelIdentifier
        self.token = self.md.guid
        self.fmu = FMU3Slave(guid=self.token, unzipDirectory=unzip_dir, modelIdentifier=self.id)
        self.resources = os.path.join(unzip_dir, "resources") + os.path.sep

    def call(self, fname, *args):
        """`fname(*args)` through fmpy; the status, whatever it is."""
        try:
            return getattr(self.fmu, fname)(*args)
        except FMICallException as e:
            return e.status


def arr(ctype, values):
    """A C array (or NULL for None)."""
    return None if values is None else (ctype * len(values))(*values)


def _text(b):
    return (b or b"").decode(errors="replace")


class Instance:
    """One Co-Simulation instance with its own log; every method returns the raw status first."""

    def __init__(self, lib, token=DEFAULT, name="inst", logging_on=False, logger=True,
                 resource_path=DEFAULT, event_mode_used=False, early_return_allowed=False,
                 required_intermediate=(), intermediate=None):
        self.lib = lib
        self.log = []
        self.early_return_allowed = early_return_allowed

        def log_message(env, status, category, message):
            self.log.append((status, _text(category), _text(message)))

        # kept referenced for as long as the instance lives (the FMU calls it)
        self._logger = fmi3LogMessageCallback(log_message) if logger else fmi3LogMessageCallback()
        # `intermediate`: a Python function of the callback's 8 arguments, or None (NULL)
        self._intermediate = fmi3IntermediateUpdateCallback(intermediate) if intermediate else \
            fmi3IntermediateUpdateCallback()
        required = arr(fmi3ValueReference, list(required_intermediate))
        encode = lambda s: None if s is None else s.encode()
        token = lib.token if token is DEFAULT else token
        self.c = lib.fmu.fmi3InstantiateCoSimulation(
            encode(name), encode(token), encode(lib.resources if resource_path is DEFAULT else resource_path),
            fmi3Boolean(False), fmi3Boolean(logging_on), fmi3Boolean(event_mode_used),
            fmi3Boolean(early_return_allowed), required, len(required_intermediate),
            fmi3InstanceEnvironment(), self._logger, self._intermediate)

    def call(self, fname, *args):
        return self.lib.call(fname, self.c, *args)

    def messages(self, min_status=DISCARD):
        return [m for (s, _, m) in self.log if s >= min_status]

    def free(self):
        if self.c:
            self.lib.fmu.fmi3FreeInstance(self.c)
            self.c = None

    # life cycle
    def enter(self, start=0.0, stop=None, tol=None):
        return self.call("fmi3EnterInitializationMode", fmi3Boolean(tol is not None), tol or 0.0, start,
                         fmi3Boolean(stop is not None), 0.0 if stop is None else stop)

    def exit(self):
        return self.call("fmi3ExitInitializationMode")

    def init(self, start=0.0, stop=None, values=None):
        statuses = [self.enter(start=start, stop=stop)]
        for vr, v in (values or {}).items():
            statuses.append(self.set_float64([vr], [v]))
        statuses.append(self.exit())
        return max(statuses)

    def terminate(self):
        return self.call("fmi3Terminate")

    def reset(self):
        return self.call("fmi3Reset")

    def enter_step_mode(self):
        return self.call("fmi3EnterStepMode")

    def do_step(self, t, h, flags=True):
        """Status, (eventHandlingNeeded, terminateSimulation, earlyReturn, lastSuccessfulTime)."""
        ev, term, early = fmi3Boolean(True), fmi3Boolean(True), fmi3Boolean(True)
        last = fmi3Float64(float("nan"))
        outs = (byref(ev), byref(term), byref(early), byref(last)) if flags else (None, None, None, None)
        s = self.call("fmi3DoStep", t, h, fmi3Boolean(False), *outs)
        return s, (ev.value, term.value, early.value, last.value)

    # values: (setter, getter, C type) per FMI 3.0 type used by the models
    def _get(self, fname, ctype, vrs, n=None):
        n = len(vrs) if n is None else n
        out = (ctype * max(n, 1))()
        s = self.call(fname, arr(fmi3ValueReference, vrs), len(vrs), out, n)
        return s, list(out[:n])

    def _set(self, fname, ctype, vrs, values, n=None):
        n = len(values) if n is None else n
        return self.call(fname, arr(fmi3ValueReference, vrs), len(vrs), arr(ctype, values), n)

    def get_float64(self, vrs, n=None):
        return self._get("fmi3GetFloat64", fmi3Float64, vrs, n)

    def set_float64(self, vrs, values, n=None):
        return self._set("fmi3SetFloat64", fmi3Float64, vrs, values, n)

    def get_int32(self, vrs, n=None):
        return self._get("fmi3GetInt32", fmi3Int32, vrs, n)

    def set_int32(self, vrs, values, n=None):
        return self._set("fmi3SetInt32", fmi3Int32, vrs, values, n)

    def get_int64(self, vrs, n=None):
        return self._get("fmi3GetInt64", fmi3Int64, vrs, n)

    def set_int64(self, vrs, values, n=None):
        return self._set("fmi3SetInt64", fmi3Int64, vrs, values, n)

    def get_boolean(self, vrs, n=None):
        return self._get("fmi3GetBoolean", fmi3Boolean, vrs, n)

    def set_boolean(self, vrs, values, n=None):
        return self._set("fmi3SetBoolean", fmi3Boolean, vrs, [bool(v) for v in values], n)

    def get_string(self, vrs, n=None):
        s, out = self._get("fmi3GetString", fmi3String, vrs, n)
        return s, [None if v is None else v.decode(errors="replace") for v in out]

    def set_string(self, vrs, values, n=None):
        return self._set("fmi3SetString", fmi3String, vrs,
                         [None if v is None else v.encode() for v in values], n)

    # FMU states
    def get_state(self, existing=None):
        h = fmi3FMUState(existing)
        s = self.call("fmi3GetFMUState", byref(h))
        return s, h.value

    def set_state(self, handle):
        return self.call("fmi3SetFMUState", fmi3FMUState(handle))

    def free_state(self, handle):
        h = fmi3FMUState(handle)
        s = self.call("fmi3FreeFMUState", byref(h))
        return s, h.value

    def serialized_size(self, handle):
        size = c_size_t(0)
        s = self.call("fmi3SerializedFMUStateSize", fmi3FMUState(handle), byref(size))
        return s, size.value

    def serialize(self, handle, size=None):
        s, n = self.serialized_size(handle)
        if s != OK:
            return s, b""
        n = n if size is None else size
        buf = C.create_string_buffer(max(n, 1))
        s = self.call("fmi3SerializeFMUState", fmi3FMUState(handle), C.cast(buf, C.POINTER(fmi3Byte)), n)
        return s, buf.raw[:n]

    def deserialize(self, data, existing=None):
        h = fmi3FMUState(existing)
        buf = C.create_string_buffer(data, max(len(data), 1))
        s = self.call("fmi3DeserializeFMUState", C.cast(buf, C.POINTER(fmi3Byte)), len(data), byref(h))
        return s, h.value

    def set_debug_logging(self, on, categories=None):
        cats = arr(fmi3String, None if categories is None else
                   [None if c is None else c.encode() for c in categories])
        return self.call("fmi3SetDebugLogging", fmi3Boolean(on), 0 if categories is None else len(categories), cats)

