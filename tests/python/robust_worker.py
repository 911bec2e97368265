"""One robustness case of issue #48 against one unpacked FMU, in a fresh interpreter.

usage: robust_worker.py <fmi2|fmi3> <unzip-dir> <case>
Exits 0 when the case's checks hold, 1 with the reason on stderr when one fails; a crash of the
FMU (double free, segmentation fault) shows as a signal exit code. test_misuse_robust.py runs
every case in its own process so that a crash fails that case and leaves pytest alive.
"""

import ctypes as C
import os
import pathlib
import shutil
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fmi2raw as R2  # noqa: E402
import fmi3raw as R3  # noqa: E402
from callback_hook import Hook  # noqa: E402
from fmpy import read_model_description  # noqa: E402


def lib2(unzip):
    md = read_model_description(os.path.join(unzip, "modelDescription.xml"))
    return R2.Library(unzip, md.coSimulation.modelIdentifier), md


def new2(unzip, **kw):
    lib, md = lib2(unzip)
    return R2.Instance(lib, md.guid, **kw), md


class AnyLocation(R2.Instance):
    """fmi2raw.Instance with any fmuResourceLocation, NULL included (fmi2raw.Instance puts its
    own resources folder in place of None)."""

    def __init__(self, lib, guid, location):
        self.lib = lib
        self.env = R2._next_env[0]
        R2._next_env[0] += 1
        R2.LOGS[self.env] = []
        self.callbacks = R2.fmi2CallbackFunctions()
        self.callbacks.logger = R2._dispatch
        R2.fmpy.logging.addLoggerProxy(R2.byref(self.callbacks))
        self.callbacks.componentEnvironment = self.env
        encoded = None if location is None else location.encode()
        self.c = lib.fmi2Instantiate(b"inst", 1, guid.encode(), encoded, R2.byref(self.callbacks), 0, 1)


def by_name(md, name):
    return next(v for v in md.modelVariables if v.name == name)


# ---------------------------------------------------------------------------------------------
# A. calls into an instance from inside its own callbacks


def reenter2(unzip, action_name):
    """fmi2DoStep fails (negative step) and logs why; the logger calls `action_name` on the
    instance from inside that call."""
    i, _ = new2(unzip)
    assert i.init(stop=1.0) == R2.OK, i.messages()
    actions = {
        "reset": lambda: i.lib.fmi2Reset(i.c),
        "free": lambda: i.lib.fmi2FreeInstance(i.c),
        "step": lambda: i.lib.fmi2DoStep(i.c, 0.0, 0.01, 1),
    }
    hook = Hook(actions[action_name])
    R2.LOGS[i.env] = hook
    outer = i.do_step(0.0, -1.0)
    assert outer == R2.ERROR, outer
    assert len(hook.results) == 1, "the logger was not called"
    inner = hook.results[0]
    if action_name != "free":
        assert inner == R2.ERROR, f"{action_name} from inside the logger returned {inner}, not Error"
    refused = [m for (s, _, m) in hook if s == R2.ERROR and "refused" in m and "callback" in m]
    assert refused, f"no logged refusal of the re-entered call: {list(hook)}"
    # nothing changed: the instance is still the one that failed a step; reset recovers it
    assert i.reset() == R2.OK, i.messages()
    assert i.init(stop=1.0) == R2.OK, i.messages()
    assert i.do_step(0.0, 0.01) == R2.OK, i.messages()
    i.free()


def new3(unzip, **kw):
    lib = R3.Library(unzip)
    return R3.Instance(lib, **kw)


def reenter3(unzip, action_name):
    i = new3(unzip)
    assert i.init(stop=1.0) == R3.OK, i.messages()
    actions = {
        "reset": lambda: i.call("fmi3Reset"),
        "free": lambda: i.lib.fmu.fmi3FreeInstance(i.c),
    }
    hook = Hook(actions[action_name])
    i.log = hook
    outer = i.do_step(0.0, -1.0)[0]
    assert outer == R3.ERROR, outer
    assert len(hook.results) == 1, "the logger was not called"
    if action_name == "reset":
        assert hook.results[0] == R3.ERROR, f"fmi3Reset from the logger returned {hook.results[0]}"
    refused = [m for (s, _, m) in hook if s == R3.ERROR and "refused" in m and "callback" in m]
    assert refused, f"no logged refusal of the re-entered call: {list(hook)}"
    assert i.call("fmi3Reset") == R3.OK, i.messages()
    assert i.init(stop=1.0) == R3.OK, i.messages()
    assert i.do_step(0.0, 0.01)[0] == R3.OK, i.messages()
    i.free()


# ---------------------------------------------------------------------------------------------
# B. freed and foreign handles


def garbage():
    buf = C.create_string_buffer(b"\xab" * 4096)
    return buf, C.addressof(buf)


def free_twice2(unzip):
    i, _ = new2(unzip)
    c = i.c
    i.lib.fmi2FreeInstance(c)
    i.lib.fmi2FreeInstance(c)
    print("survived", file=sys.stderr)


def call_after_free2(unzip):
    i, _ = new2(unzip)
    c = i.c
    i.lib.fmi2FreeInstance(c)
    s = i.lib.fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 1.0)
    assert s == R2.ERROR, s
    s = i.lib.fmi2DoStep(c, 0.0, 0.01, 1)
    assert s == R2.ERROR, s


def garbage_handle2(unzip):
    i, _ = new2(unzip)
    buf, addr = garbage()
    assert i.lib.fmi2DoStep(addr, 0.0, 0.01, 1) == R2.ERROR
    assert i.lib.fmi2Reset(addr) == R2.ERROR
    i.lib.fmi2FreeInstance(addr)
    assert bytes(buf.raw[:64]) == b"\xab" * 64, "the FMU wrote into memory it does not own"
    # the real instance is untouched
    assert i.init(stop=1.0) == R2.OK, i.messages()
    i.free()


def free_twice3(unzip):
    i = new3(unzip)
    c = i.c
    i.lib.fmu.fmi3FreeInstance(c)
    i.lib.fmu.fmi3FreeInstance(c)
    print("survived", file=sys.stderr)


def call_after_free3(unzip):
    i = new3(unzip)
    c = i.c
    i.lib.fmu.fmi3FreeInstance(c)
    i.c = c
    assert i.enter(stop=1.0) == R3.ERROR
    assert i.do_step(0.0, 0.01)[0] == R3.ERROR
    i.c = None


def garbage_handle3(unzip):
    i = new3(unzip)
    buf, addr = garbage()
    real, i.c = i.c, addr
    assert i.do_step(0.0, 0.01)[0] == R3.ERROR
    assert i.call("fmi3Reset") == R3.ERROR
    i.lib.fmu.fmi3FreeInstance(addr)
    assert bytes(buf.raw[:64]) == b"\xab" * 64, "the FMU wrote into memory it does not own"
    i.c = real
    assert i.init(stop=1.0) == R3.OK, i.messages()
    i.free()


# ---------------------------------------------------------------------------------------------
# C. resource locations and the scene file

KP_DEFAULT, KP_EDITED = 1.0, 3.0


def edited_resources(unzip, tmp):
    """A copy of the FMU's resources folder whose scene.toml sets kp = 3 (PidController)."""
    res = pathlib.Path(tmp, "my resources")
    shutil.copytree(os.path.join(unzip, "resources"), res)
    scene = (res / "scene.toml").read_text()
    assert scene.count("kp = 1.0") == 1, scene
    (res / "scene.toml").write_text(scene.replace("kp = 1.0", "kp = 3.0"))
    return res


def kp2(i, md):
    assert i.setup() == R2.OK and i.enter() == R2.OK, i.messages()
    s, v = i.get_real([by_name(md, "kp").valueReference])
    assert s == R2.OK
    return v[0]


def kp3(i):
    assert i.enter() == R3.OK, i.messages()
    s, v = i.get_float64([by_name(i.lib.md, "kp").valueReference])
    assert s == R3.OK
    return v[0]


def location2(unzip, make_uri, expect, snippets=()):
    """fmi2Instantiate with the URI `make_uri(resources)`: `expect` is "edited" (the scene.toml
    was read), "default" (a Warning, built-in defaults) or "null" (refused with an Error whose
    message holds every snippet)."""
    with tempfile.TemporaryDirectory() as tmp:
        res = edited_resources(unzip, tmp)
        uri = make_uri(res)
        lib, md = lib2(unzip)
        i = AnyLocation(lib, md.guid, uri)
        errors = [m for (s, _, m) in i.log if s >= R2.ERROR]
        if expect == "null":
            assert not i.c, f"{uri!r} was accepted: {i.log}"
            assert errors and all(s in errors[-1] for s in snippets), (snippets, errors)
            return
        assert i.c, f"{uri!r} was refused: {i.log}"
        assert not errors, errors
        want = KP_EDITED if expect == "edited" else KP_DEFAULT
        kp = kp2(i, md)
        assert kp == want, f"{uri!r}: kp = {kp}, expected {want} ({expect})"
        if expect == "default":
            warnings = [m for (s, _, m) in i.log if s == R2.WARNING]
            assert any("scene.toml is not read" in w for w in warnings), i.log
        i.free()


def broken_scene2(unzip, breaker, snippets):
    """scene.toml made unreadable by `breaker(path)`: fmi2Instantiate returns NULL and says why."""
    with tempfile.TemporaryDirectory() as tmp:
        res = edited_resources(unzip, tmp)
        breaker(res / "scene.toml")
        i, _ = new2(unzip, resource_uri=res.as_uri(), logging_on=True)
        errors = [m for (s, _, m) in i.log if s >= R2.ERROR]
        assert not i.c, f"instantiated despite a broken scene.toml: {i.log}"
        assert errors and all(s in errors[-1] for s in snippets), (snippets, errors)


def broken_scene3(unzip, breaker, snippets):
    with tempfile.TemporaryDirectory() as tmp:
        res = edited_resources(unzip, tmp)
        breaker(res / "scene.toml")
        i = new3(unzip, resource_path=str(res) + os.sep, logging_on=True)
        errors = [m for (s, _, m) in i.log if s >= R3.ERROR]
        assert not i.c, f"instantiated despite a broken scene.toml: {i.log}"
        assert errors and all(s in errors[-1] for s in snippets), (snippets, errors)


def location3(unzip, make_path, expect, snippets=()):
    with tempfile.TemporaryDirectory() as tmp:
        res = edited_resources(unzip, tmp)
        path = make_path(res)
        i = new3(unzip, resource_path=path, logging_on=True)
        errors = [m for (s, _, m) in i.log if s >= R3.ERROR]
        if expect == "null":
            assert not i.c, f"{path!r} was accepted: {i.log}"
            assert errors and all(s in errors[-1] for s in snippets), (snippets, errors)
            return
        assert i.c, f"{path!r} was refused: {i.log}"
        assert not errors, errors
        want = KP_EDITED if expect == "edited" else KP_DEFAULT
        assert kp3(i) == want, f"{path!r}: kp is not {want}"
        i.free()


def loop(p):
    p.unlink()
    os.symlink(p.name, p)


def directory(p):
    p.unlink()
    p.mkdir()


def not_utf8(p):
    p.write_bytes(p.read_bytes() + b"\n# \xff\xfe\n")


def dangling(p):
    p.unlink()
    os.symlink("nowhere.toml", p)


def unreadable(p):
    """Mode 000. As root, test_misuse_robust.py runs this case under `setpriv` without
    CAP_DAC_OVERRIDE, so the permissions apply to the FMU's open as to anyone's."""
    os.chmod(p, 0)
    try:
        open(p).close()
    except PermissionError:
        return
    raise AssertionError("the mode-000 scene.toml can be read: run this case without CAP_DAC_OVERRIDE")


# ---------------------------------------------------------------------------------------------
# D. long messages are cut (src/fmi/logger.rs: MAX_MESSAGE)

LONG = 10_000_000
MAX_MESSAGE = 4096


def cut_properly(msg, long_text_len):
    assert len(msg) <= MAX_MESSAGE + 40, f"a message of {len(msg)} characters reached the logger"
    assert msg.endswith(" more characters)"), msg[-80:]
    more = int(msg.rsplit("(", 1)[1].split()[0])
    assert MAX_MESSAGE + more >= long_text_len, (more, long_text_len)


def long_message2(unzip):
    """An unknown log category of 10 MB, echoed in the error: fmpy's proxy would cut it at 2 kB,
    so the message is taken from the raw (non-formatting) logger argument."""
    lib, md = lib2(unzip)
    got = []
    raw_type = C.CFUNCTYPE(None, C.c_void_p, C.c_char_p, C.c_int, C.c_char_p, C.c_char_p, C.c_char_p)
    raw = raw_type(lambda env, name, status, category, fmt, msg: got.append((status, fmt, msg)))
    callbacks = R2.fmi2CallbackFunctions()
    callbacks.logger = C.cast(raw, R2.fmi2CallbackLoggerTYPE)
    c = lib.fmi2Instantiate(b"inst", 1, md.guid.encode(), None, C.byref(callbacks), 0, 0)
    assert c
    cats = (C.c_char_p * 1)(b"x" * LONG)
    status = lib.fmi2SetDebugLogging(c, 1, 1, cats)
    lib.fmi2FreeInstance(c)
    assert status == R2.ERROR, status
    s, fmt, msg = got[-1]
    assert s == R2.ERROR and fmt == b"%s", (s, fmt)
    cut_properly(msg.decode(), LONG)


def long_message3(unzip):
    i = new3(unzip)
    assert i.set_debug_logging(True, ["x" * LONG]) == R3.ERROR
    cut_properly(i.messages()[-1], LONG)
    i.free()


def up(s):
    return s.replace("file://", "FILE://", 1)


CASES = {
    # A
    "fmi2_logger_reenters_reset": lambda u: reenter2(u, "reset"),
    "fmi2_logger_reenters_free": lambda u: reenter2(u, "free"),
    "fmi2_logger_reenters_do_step": lambda u: reenter2(u, "step"),
    "fmi3_logger_reenters_reset": lambda u: reenter3(u, "reset"),
    "fmi3_logger_reenters_free": lambda u: reenter3(u, "free"),
    # B
    "fmi2_free_twice": free_twice2,
    "fmi2_call_after_free": call_after_free2,
    "fmi2_garbage_handle": garbage_handle2,
    "fmi3_free_twice": free_twice3,
    "fmi3_call_after_free": call_after_free3,
    "fmi3_garbage_handle": garbage_handle3,
    # C, FMI 2.0
    "fmi2_uri_control": lambda u: location2(u, lambda r: r.as_uri(), "edited"),
    "fmi2_uri_upper_case_scheme": lambda u: location2(u, lambda r: up(r.as_uri()), "edited"),
    "fmi2_uri_localhost_trailing_slash": lambda u: location2(
        u, lambda r: r.as_uri().replace("file://", "file://localhost", 1) + "/", "edited"),
    "fmi2_uri_http": lambda u: location2(
        u, lambda r: "http://example.com" + r.as_uri()[7:], "null", ["http://example.com", "scheme"]),
    "fmi2_uri_other_host": lambda u: location2(
        u, lambda r: "file://server" + r.as_uri()[7:], "null", ["file://server", "host `server`"]),
    "fmi2_uri_query": lambda u: location2(u, lambda r: r.as_uri() + "?x=1", "null", ["?x=1", "query"]),
    "fmi2_uri_fragment": lambda u: location2(u, lambda r: r.as_uri() + "#top", "null", ["#top", "fragment"]),
    "fmi2_uri_missing_folder": lambda u: location2(
        u, lambda r: (r / "missing").as_uri(), "null", ["missing", "not an existing folder"]),
    "fmi2_bare_absolute_path": lambda u: location2(u, lambda r: str(r), "edited"),
    "fmi2_bare_relative_path": lambda u: location2(u, lambda r: "not a uri", "null", ["not a uri"]),
    "fmi2_null_location": lambda u: location2(u, lambda r: None, "default"),
    "fmi2_empty_location": lambda u: location2(u, lambda r: "", "default"),
    "fmi2_scene_symlink_loop": lambda u: broken_scene2(u, loop, ["scene.toml", "cannot read", "symbolic links"]),
    "fmi2_scene_directory": lambda u: broken_scene2(u, directory, ["scene.toml", "not a regular file"]),
    "fmi2_scene_not_utf8": lambda u: broken_scene2(u, not_utf8, ["scene.toml", "UTF-8"]),
    "fmi2_scene_dangling_symlink": lambda u: broken_scene2(u, dangling, ["scene.toml", "nowhere.toml"]),
    "fmi2_scene_unreadable": lambda u: broken_scene2(u, unreadable, ["scene.toml", "ermission"]),
    # C, FMI 3.0
    "fmi3_path_control": lambda u: location3(u, lambda r: str(r) + os.sep, "edited"),
    "fmi3_uri_upper_case_scheme": lambda u: location3(u, lambda r: up(r.as_uri()), "edited"),
    "fmi3_relative_path": lambda u: location3(u, lambda r: "resources/", "null", ["resources/", "absolute"]),
    "fmi3_missing_folder": lambda u: location3(
        u, lambda r: str(r / "missing") + os.sep, "null", ["missing", "not an existing folder"]),
    "fmi3_null_path": lambda u: location3(u, lambda r: None, "default"),
    # D
    "fmi2_long_message_is_cut": long_message2,
    "fmi3_long_message_is_cut": long_message3,
    "fmi3_scene_symlink_loop": lambda u: broken_scene3(u, loop, ["scene.toml", "cannot read", "symbolic links"]),
}


def main():
    version, unzip, case = sys.argv[1:]
    assert case.startswith(version), (version, case)
    try:
        CASES[case](unzip)
    except AssertionError as e:
        print(f"{case}: check failed: {e!r}", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
