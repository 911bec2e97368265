"""One case: a fresh FMU instance through fmpy, driven step by step, reduced to a result row.

A pure function of the FMU's bytes, the study's run settings and the case's values, so a task
that is run again (its worker died) gives the same row bit for bit. The FMU is unzipped once per
process (keyed by its SHA-256); every case instantiates, runs, terminates and frees its own
instance, so nothing carries over from one case to the next."""

import ctypes
import hashlib
import io
import os
import shutil
import socket
import string
import tempfile
import time
import zipfile

import numpy as np
from fmpy import read_model_description
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.logging import addLoggerProxy

from . import summary

_UNZIPPED = {}  # sha256 -> (directory, model description)
_LOGS = {}  # component environment id -> [message]
_next_env = [1]


@fmi2CallbackLoggerTYPE
def _logger(env, instance_name, status, category, message):
    _LOGS.setdefault(env or 0, []).append((message or b"").decode(errors="replace"))


_libc = ctypes.CDLL(None)
_calloc = _libc.calloc
_calloc.restype, _calloc.argtypes = ctypes.c_void_p, [ctypes.c_size_t, ctypes.c_size_t]
_free = _libc.free
_free.restype, _free.argtypes = None, [ctypes.c_void_p]
_alloc_cb = fmi2CallbackAllocateMemoryTYPE(lambda n, size: _calloc(n, size))
_free_cb = fmi2CallbackFreeMemoryTYPE(lambda p: _free(p))


def unzipped(fmu_bytes):
    sha = hashlib.sha256(fmu_bytes).hexdigest()
    if sha not in _UNZIPPED:
        d = tempfile.mkdtemp(prefix=f"mbstudy-{sha[:12]}-")
        zipfile.ZipFile(io.BytesIO(fmu_bytes)).extractall(d)
        _UNZIPPED[sha] = (d, read_model_description(d))
    return _UNZIPPED[sha]


def _schedule(points, values):
    """Breakpoints (t, value) of a piecewise-constant input; a value may name a case variable."""
    return [(float(t), float(values[v]) if isinstance(v, str) else float(v)) for t, v in points]


def _at(schedule, t):
    v = schedule[0][1] if schedule else 0.0
    for ti, vi in schedule:
        if ti <= t + 1e-12:
            v = vi
    return v


def _enum_value(var, md, value):
    if isinstance(value, str):
        for td in md.typeDefinitions:
            if td.name == var.declaredType.name:
                for item in td.items:
                    if item.name == value:
                        return int(item.value)
        raise ValueError(f"{var.name}: no enumeration item {value!r}")
    return int(value)


def _set(fmu, md, var, value):
    vr = [var.valueReference]
    if var.type == "Real":
        fmu.setReal(vr, [float(value)])
    elif var.type == "Integer":
        fmu.setInteger(vr, [int(value)])
    elif var.type == "Enumeration":
        fmu.setInteger(vr, [_enum_value(var, md, value)])
    elif var.type == "Boolean":
        fmu.setBoolean(vr, [bool(value)])
    else:
        fmu.setString(vr, [str(value)])


def run_case(fmu_bytes, settings, case_index, case_id, values):
    """Runs one case; returns {"row": {...}, "series": {name: array} or None}. A case the FMU
    refuses or that fails mid-run comes back with status "failed" and the FMU's messages."""
    t0 = time.perf_counter()
    head = {"case_index": case_index, "case_id": case_id}
    try:
        body, series = _simulate(fmu_bytes, settings, values)
        row = {**head, "status": "done", "message": "", **body}
    except Exception as e:  # recorded, the study goes on
        row, series = {**head, "status": "failed", "message": str(e)}, None
    row["seconds"] = time.perf_counter() - t0
    row["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    return {"row": row, "series": series}


def scene_variables(scene):
    """The case variables a scene template names (`$name` or `${name}`)."""
    return set(string.Template(scene).get_identifiers()) if scene else set()


def _case_directory(directory, scene, values):
    """A per-case copy of the unzipped FMU (hard links) whose resources/scene.toml is the study's
    scene template with the case's values put in (`$name` -> the value as TOML text)."""
    text = string.Template(scene).substitute({k: repr(float(v)) if isinstance(v, float) else str(v)
                                              for k, v in values.items()})
    case_dir = tempfile.mkdtemp(prefix="mbstudy-case-")
    shutil.copytree(directory, case_dir, copy_function=os.link, dirs_exist_ok=True)
    target = os.path.join(case_dir, "resources", "scene.toml")
    if os.path.exists(target):
        os.unlink(target)  # a hard link to the shared copy: never write through it
    os.makedirs(os.path.dirname(target), exist_ok=True)
    with open(target, "w") as f:
        f.write(text)
    return case_dir


def _simulate(fmu_bytes, settings, values):
    directory, md = unzipped(fmu_bytes)
    scene = settings.get("scene", "")
    if not scene:
        return _simulate_in(directory, md, settings, values)
    case_dir = _case_directory(directory, scene, values)
    try:
        return _simulate_in(case_dir, md, settings, values)
    finally:
        shutil.rmtree(case_dir, ignore_errors=True)


def _simulate_in(directory, md, settings, values):
    by_name = {v.name: v for v in md.modelVariables}
    schedules = {name: _schedule(points, values) for name, points in settings["inputs"].items()}
    start = {**settings["fixed"], **{k: v for k, v in values.items() if k in by_name}}
    for name in list(start) + list(schedules) + list(settings["outputs"]):
        if name not in by_name:
            raise ValueError(f"{md.modelName} has no variable {name!r}")
    scheduled = {v for points in settings["inputs"].values() for _, v in points if isinstance(v, str)}
    scheduled |= scene_variables(settings.get("scene", ""))
    unused = [k for k in values if k not in by_name and k not in scheduled]
    if unused:
        raise ValueError(f"{unused} are neither {md.modelName} variables nor used by an input schedule "
                         "or the scene")
    outputs = [by_name[n] for n in settings["outputs"]]

    env = _next_env[0]
    _next_env[0] += 1
    callbacks = fmi2CallbackFunctions()
    callbacks.logger, callbacks.allocateMemory, callbacks.freeMemory = _logger, _alloc_cb, _free_cb
    callbacks.componentEnvironment = ctypes.c_void_p(env)
    addLoggerProxy(ctypes.byref(callbacks))  # fmpy's C proxy formats the message's varargs
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=directory,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName=f"case{env}")
    instantiated = False
    try:
        fmu.instantiate(callbacks=callbacks, loggingOn=False)
        instantiated = True
        for name, value in start.items():
            _set(fmu, md, by_name[name], value)
        for name, sched in schedules.items():
            _set(fmu, md, by_name[name], _at(sched, 0.0))
        fmu.setupExperiment(startTime=0.0, stopTime=settings["stop_time"])
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        step = settings["step"]
        n = int(round(settings["stop_time"] / step))
        t = np.arange(n + 1) * step
        data = np.empty((n + 1, len(outputs)))
        data[0] = _read(fmu, outputs)
        for i in range(n):
            for name, sched in schedules.items():
                _set(fmu, md, by_name[name], _at(sched, t[i]))
            # communication points exactly i * step (not a sum of steps)
            fmu.doStep(currentCommunicationPoint=t[i], communicationStepSize=t[i + 1] - t[i])
            data[i + 1] = _read(fmu, outputs)
        fmu.terminate()
    except Exception as e:
        log = "; ".join(_LOGS.get(env, []))
        raise RuntimeError(f"{e} FMU log: {log}" if log else str(e)) from None
    finally:
        if instantiated:
            fmu.freeInstance()
        _LOGS.pop(env, None)
    return _reduce(settings, t, data), (
        {"time": t, **{o.name: data[:, k] for k, o in enumerate(outputs)}} if settings["keep_series"] else None)


def _read(fmu, outputs):
    out = []
    for o in outputs:
        if o.type == "Real":
            out.append(fmu.getReal([o.valueReference])[0])
        elif o.type == "Boolean":
            out.append(float(fmu.getBoolean([o.valueReference])[0]))
        else:
            out.append(float(fmu.getInteger([o.valueReference])[0]))
    return out


def _reduce(settings, t, data):
    names = list(settings["outputs"])
    finals = {name: data[-1, k] for k, name in enumerate(names)}
    start = summary.spectrum_window_start(settings["spectrum"], finals)
    row = {}
    for k, name in enumerate(names):
        row.update(summary.figures(name, settings["outputs"][name], t, data[:, k], start,
                                   settings["spectrum"]["band"]))
    return row
