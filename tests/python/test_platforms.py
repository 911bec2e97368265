"""Every FMU's binaries run where they run: x86_64 Linux natively, x86_64 Windows under wine,
aarch64 Linux under qemu-user (issue #44 items 1-3, docs/platforms.md).

One small importer (tools/platform_importer, built here for the three targets) loads the
shipped library of each unpacked FMU (FMI 2.0 and 3.0) by dynamic loading and runs the default
experiment through the exported C functions; at the middle point it saves the state, serializes
it, runs on, then deserializes and restores it and runs the second half again. Each FMU is
unpacked once into the wine prefix's C: drive under a folder whose name has a space, and its
resources/scene.toml changes one parameter: the runs get the resources folder as a
percent-encoded `file:///C:/...` URI (wine) or `file:///...` URI (Linux) in FMI 2.0 and as a
native path in FMI 3.0, and read the changed value back.

Checked: the restored second half equals the first bit for bit and so do the final serialized
states (within each platform); every output at every point equals the x86_64 Linux run to 1e-12
relative to the output's largest magnitude over the run; the changed parameter reads back.
And every artifact carries its own libm: no library of an FMU and not the native executable
takes a math function (sin, pow, ...) from the C runtime (docs/platforms.md).
"""

import concurrent.futures
import os
import pathlib
import re
import shutil
import subprocess
import struct
import time
import urllib.parse
import zipfile

import pytest
from fmpy import read_model_description

from conftest import DIST, ROOT

TOOL = ROOT / "tools" / "platform_importer"
BIN = pathlib.Path(os.environ.get("MBCOSIM_BIN", ROOT / "target" / "release" / "mbcosim"))
TARGET = BIN.resolve().parents[1]
BUILD = TARGET / "platform_importer"
PREFIX = TARGET / "wine-prefix"
# The folder on wine's C: drive the FMUs are unpacked into; its space is percent-encoded in URIs.
FOLDER = "mbcosim platforms"
SYSROOT = pathlib.Path("/usr/aarch64-linux-gnu")
REL_TOL = 1e-12
MODELS = ["PanelLock", "RopeBlock", "PidController"]
# A parameter per model and the value its unpacked scene.toml gets (the default differs), read
# back at the first point: proof that the run read the resources through the URI.
CHANGED = {"PanelLock": ("hinge_damping", 0.025), "RopeBlock": ("block_mass", 180000.0),
           "PidController": ("kp", 1.5)}
# Measured times [s] and largest relative differences, written to REPORT after the session (the
# figures of docs/platforms.md).
TIMES = {}
REPORT = TARGET / "platforms-report.txt"


def run(cmd, env=None, timeout=900):
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, stdin=subprocess.DEVNULL)
    assert r.returncode == 0, f"{cmd}\nstdout: {r.stdout[-3000:]}\nstderr: {r.stderr[-3000:]}"
    return r


def wine_env():
    return dict(os.environ, WINEPREFIX=str(PREFIX), WINEDEBUG="-all")


def wine():
    for c in ("/usr/lib/wine/wine64", "wine64", "wine"):
        if shutil.which(c):
            return shutil.which(c)
    pytest.fail("wine is not installed (tests/setup_env.sh installs Debian's wine64)")


def cargo_build(target=None, zig=False):
    """The importer for `target` (None: this machine), built with its committed Cargo.lock."""
    args = ["build", "--release", "--locked", "--quiet", "--manifest-path", str(TOOL / "Cargo.toml"),
            "--target-dir", str(BUILD)]
    env = dict(os.environ)
    if zig:
        # aarch64: linked by zig against glibc 2.17, as the FMUs' library (scripts/build_portable.sh)
        cmd = [str(ROOT / ".venv" / "bin" / "cargo-zigbuild"), "zig" + args[0], *args[1:],
               "--target", f"{target}.2.17"]
        env["CARGO_ZIGBUILD_PYTHON_PATH"] = str(ROOT / ".venv" / "bin" / "python")
    else:
        cmd = ["cargo", *args] + (["--target", target] if target else [])
        env["CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER"] = "x86_64-w64-mingw32-gcc"
    run(cmd, env=env)
    exe = "platform_importer.exe" if target and "windows" in target else "platform_importer"
    path = BUILD / (target or "") / "release" / exe
    assert path.is_file(), path
    return path


@pytest.fixture(scope="session", autouse=True)
def report():
    yield
    lines = []
    for k, v in TIMES.items():
        if isinstance(v, dict):
            lines += [f"{k} {' '.join(map(str, kk))}: {vv:.3e}" if isinstance(vv, float)
                      else f"{k} {' '.join(map(str, kk))}: {vv}" for kk, vv in sorted(v.items())]
        else:
            lines.append(f"{k}: {v:.1f}")
    if lines:
        REPORT.write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="session")
def importers():
    """The importer for each platform, and the command prefix that runs it there."""
    t0 = time.monotonic()
    native = cargo_build()
    windows = cargo_build("x86_64-pc-windows-gnu")
    arm = cargo_build("aarch64-unknown-linux-gnu", zig=True)
    TIMES["build importers [s]"] = time.monotonic() - t0
    t0 = time.monotonic()
    if not (PREFIX / "system.reg").is_file():
        run([wine(), "wineboot", "--init"], env=wine_env())
    # wine 8.0 lacks bcryptprimitives.dll (Windows 10's; Rust's std imports it): a test-only shim
    shim = PREFIX / "drive_c" / "windows" / "system32" / "bcryptprimitives.dll"
    source = TOOL / "wine" / "bcryptprimitives.c"
    if not shim.is_file() or shim.stat().st_mtime < source.stat().st_mtime:
        run(["x86_64-w64-mingw32-gcc", "-O2", "-shared", "-s", "-o", str(shim), str(source), "-ladvapi32"])
    TIMES["wine prefix [s]"] = time.monotonic() - t0
    qemu = shutil.which("qemu-aarch64")
    assert qemu, "qemu-aarch64 is not installed (tests/setup_env.sh installs Debian's qemu-user)"
    assert (SYSROOT / "lib" / "ld-linux-aarch64.so.1").exists(), f"no aarch64 sysroot in {SYSROOT}"
    return {
        "x86_64-linux": [str(native)],
        "x86_64-windows": [wine(), str(windows)],
        "aarch64-linux": [qemu, "-L", str(SYSROOT), str(arm)],
    }


@pytest.fixture(scope="session")
def drive_c(importers):
    root = PREFIX / "drive_c" / FOLDER
    shutil.rmtree(root, ignore_errors=True)
    root.mkdir(parents=True)
    return root


def windows_path(path):
    """The path of `path` (under the prefix's drive_c) on wine's C: drive."""
    rel = path.relative_to(PREFIX / "drive_c")
    return "C:\\" + "\\".join(rel.parts)


def locations(version, unzip, model, platform):
    """(library, resources) as the importer on `platform` passes them."""
    res = unzip / "resources"
    if platform == "x86_64-windows":
        folder = "win64" if version == 2 else "x86_64-windows"
        lib = windows_path(unzip / "binaries" / folder / f"{model}.dll")
        if version == 2:
            rel = res.relative_to(PREFIX / "drive_c").as_posix()
            return lib, "file:///C:/" + urllib.parse.quote(rel)
        return lib, windows_path(res) + "\\"
    folder = {("x86_64-linux", 2): "linux64"}.get((platform, version), platform)
    lib = str(unzip / "binaries" / folder / f"{model}.so")
    if version == 2:
        return lib, "file://" + urllib.parse.quote(str(res))
    return lib, str(res) + "/"


def parse(text):
    """{'run': {k: [bits]}, 'replay': {k: [bits]}, 'end run': (size, hash), ...}"""
    out = {"run": {}, "replay": {}}
    for line in text.splitlines():
        f = line.split()
        if f[0] in ("run", "replay"):
            out[f[0]][int(f[1])] = [int(x, 16) for x in f[2:]]
        elif f[0] == "end":
            out["end " + f[1]] = (int(f[2]), f[3])
        elif f[0] == "saved":
            out["saved"] = (int(f[1]), int(f[2]))
    return out


def value(b):
    return struct.unpack("<d", struct.pack("<Q", b))[0]


def unpack(path, model, version, drive_c):
    unzip = drive_c / f"fmi{version}" / model
    with zipfile.ZipFile(path) as z:
        z.extractall(unzip)
    scene = unzip / "resources" / "scene.toml"
    name, new = CHANGED[model]
    text, n = re.subn(rf"^{name} = .*$", f"{name} = {new!r}", scene.read_text(), flags=re.M)
    assert n == 1, f"{name} in {scene}"
    scene.write_text(text)
    return unzip


def prepare(version, model, drive_c):
    """The unpacked FMU and the importer's arguments after the platform's (library, resources)."""
    path = DIST / f"{model}.fmu" if version == 2 else DIST / "fmi3" / f"{model}.fmu"
    assert path.is_file(), f"{path}: run `cargo run --release --bin mbcosim -- pack` first"
    md = read_model_description(str(path))
    unzip = unpack(path, model, version, drive_c)
    param = next(v for v in md.modelVariables if v.name == CHANGED[model][0])
    outputs = [v for v in md.modelVariables
               if v.causality == "output" and v.type in ("Real", "Float64") and not getattr(v, "dimensions", None)]
    assert outputs, f"{model}: no scalar real outputs"
    vrs = [param.valueReference] + [v.valueReference for v in outputs]
    ex = md.defaultExperiment
    start, stop, step = float(ex.startTime), float(ex.stopTime), float(ex.stepSize)
    args = [md.guid, repr(start), repr(stop), repr(step), ",".join(map(str, vrs))]
    return unzip, args, round((stop - start) / step), [param.name] + [v.name for v in outputs]


@pytest.fixture(scope="session")
def all_runs(importers, drive_c):
    """{(version, model): {platform: parsed output, "n": steps, "names": columns}}: every FMU's
    default experiment on every platform, run once, as many at a time as there are cores (the
    qemu runs of PanelLock take longest and go first)."""
    jobs, results = [], {}
    for version in (2, 3):
        for model in MODELS:
            unzip, (token, *experiment), n, names = prepare(version, model, drive_c)
            results[version, model] = {"n": n, "names": names}
            for platform, prefix in importers.items():
                lib, resources = locations(version, unzip, model, platform)
                cmd = [*prefix, str(version), lib, token, resources, *experiment]
                jobs.append((version, model, platform, cmd))
    jobs.sort(key=lambda j: (j[2] != "aarch64-linux", j[1] != "PanelLock"))

    def one(job):
        version, model, platform, cmd = job
        t0 = time.monotonic()
        r = run(cmd, env=wine_env() if platform == "x86_64-windows" else None)
        TIMES[f"FMI {version} {model} {platform} [s]"] = time.monotonic() - t0
        return job, parse(r.stdout)

    t0 = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        for (version, model, platform, _), parsed in pool.map(one, jobs):
            results[version, model][platform] = parsed
    TIMES["every run, wall [s]"] = time.monotonic() - t0
    return results


CASES = [(v, m, p) for v in (2, 3) for m in MODELS for p in ("x86_64-linux", "x86_64-windows", "aarch64-linux")]


@pytest.mark.parametrize("version,model,platform", CASES)
def test_default_experiment_with_state_restored(version, model, platform, all_runs):
    """Runs to the end, read the resources through the URI, and the restored state reproduces the
    second half bit for bit, up to the final serialized state."""
    runs = all_runs[version, model]
    got, n = runs[platform], runs["n"]
    where = f"FMI {version} {model} on {platform}"
    assert sorted(got["run"]) == list(range(n + 1)), where
    assert value(got["run"][0][1]) == CHANGED[model][1], f"{where}: scene.toml not read"
    mid = got["saved"][0]
    assert mid == n // 2 and got["saved"][1] > 0, where
    assert sorted(got["replay"]) == list(range(mid, n + 1)), where
    for k in range(mid, n + 1):
        assert got["replay"][k] == got["run"][k], f"{where}: restored run differs at point {k}"
    assert got["end replay"] == got["end run"], where
    # the time grid is the importer's own: identical everywhere
    assert [r[0] for r in got["run"].values()] == [r[0] for r in runs["x86_64-linux"]["run"].values()]


def max_relative_difference(runs, platform):
    """(largest difference over every output and point, relative to the output's largest
    magnitude on x86_64 Linux; name of that output)."""
    reference, got = runs["x86_64-linux"]["run"], runs[platform]["run"]
    worst = (0.0, None)
    for j, name in enumerate(runs["names"]):
        ref = [value(reference[k][j + 1]) for k in sorted(reference)]
        mine = [value(got[k][j + 1]) for k in sorted(reference)]
        scale = max(abs(x) for x in ref)
        diff = max(abs(a - b) for a, b in zip(ref, mine))
        worst = max(worst, (diff / scale if scale > 0 else diff, name), key=lambda w: w[0])
    return worst


@pytest.mark.parametrize("version,model,platform", [c for c in CASES if c[2] != "x86_64-linux"])
def test_outputs_equal_x86_64_linux(version, model, platform, all_runs):
    """Every output at every point equals the x86_64 Linux run to 1e-12 relative (Windows too:
    every library computes sin, pow, ... with the same pure-Rust libm, docs/platforms.md)."""
    runs = all_runs[version, model]
    rel, name = max_relative_difference(runs, platform)
    key = (platform, version, model)
    TIMES.setdefault("max relative difference", {})[key] = rel
    TIMES.setdefault("bit-identical to x86_64 Linux", {})[key] = runs[platform]["run"] == runs["x86_64-linux"]["run"]
    assert rel <= REL_TOL, f"FMI {version} {model} on {platform}: {name} differs from x86_64 Linux by {rel:.3e}"


# Every function of C99's <math.h> (double and float) and msvcrt's `_hypot`: no artifact may take
# one from the C runtime, whose last bits differ between glibc and msvcrt.dll; src/fmi/c_math.rs
# provides the ones the code calls (docs/platforms.md, "One libm in every artifact").
MATH_FUNCTIONS = {f + s for f in """acos acosh asin asinh atan atan2 atanh cbrt ceil copysign cos cosh erf erfc exp
    exp10 exp2 expm1 fabs fdim floor fma fmax fmin fmod frexp hypot ilogb ldexp lgamma lgamma_r llrint llround
    log log10 log1p log2 logb lrint lround modf nan nearbyint nextafter nexttoward pow remainder remquo rint round
    scalbln scalbn sin sincos sinh sqrt tan tanh tgamma trunc j0 j1 jn y0 y1 yn""".split()
                  for s in ("", "f")} | {"_hypot", "_hypotf"}
# What the Windows DLL imported from msvcrt.dll before the change (docs/platforms.md): each now
# has a trampoline `__wrap_<name>` in the DLL.
IMPORTED_BEFORE = {"sin", "cos", "tan", "exp", "log", "log10", "pow", "atan2", "acos", "asin", "tanh", "_hypot"}


def elf_undefined(path):
    """The undefined dynamic symbols of an ELF file (any architecture: readelf reads them all)."""
    out = run(["readelf", "--dyn-syms", "-W", str(path)]).stdout
    names = set()
    for line in out.splitlines():
        f = line.split()
        if len(f) >= 8 and f[6] == "UND":
            names.add(f[7].split("@")[0])
    return names


def pe_imports(path):
    """{dll: {imported names}} of a Windows DLL, from its import table."""
    objdump = shutil.which("x86_64-w64-mingw32-objdump")
    assert objdump, "x86_64-w64-mingw32-objdump missing (tests/setup_env.sh installs binutils-mingw-w64-x86-64)"
    imports, dll = {}, None
    for line in run([objdump, "-p", str(path)]).stdout.splitlines():
        m = re.match(r"\s*DLL Name: (\S+)", line)
        if m:
            dll = m.group(1).lower()
            imports[dll] = set()
        elif dll and line.strip() == "":
            dll = None
        elif dll:
            m = re.match(r"\s+[0-9a-f]+\s+\d+\s+(\S+)\s*$", line)
            if m:
                imports[dll].add(m.group(1))
    return imports


@pytest.mark.parametrize("version", [2, 3])
def test_no_library_takes_math_from_the_c_runtime(version, tmp_path):
    """Every FMU's three libraries: the Linux ones leave no math function for the dynamic
    loader (glibc's libm) to bind, the Windows DLL imports none from msvcrt.dll."""
    paths = sorted(DIST.glob("*.fmu")) if version == 2 else sorted((DIST / "fmi3").glob("*.fmu"))
    assert paths, f"no FMUs in {DIST}: run `cargo run --release --bin mbcosim -- pack` first"
    for path in paths:
        with zipfile.ZipFile(path) as z:
            for name in z.namelist():
                if not name.startswith("binaries/") or name.endswith("/"):
                    continue
                lib = tmp_path / name.replace("/", "_")
                lib.write_bytes(z.read(name))
                if name.endswith(".dll"):
                    imports = pe_imports(lib)
                    assert "kernel32.dll" in imports, (path, name, imports)
                    taken = {(dll, f) for dll, names in imports.items() for f in names & MATH_FUNCTIONS}
                else:
                    undefined = elf_undefined(lib)
                    assert "malloc" in undefined, (path, name)
                    taken = undefined & MATH_FUNCTIONS
                assert not taken, f"{path.name} {name} takes math functions from the C runtime: {taken}"


def test_windows_dll_has_no_static_copy_of_the_c_runtime_math():
    """mingw-w64 links some math functions statically (libmingwex): the DLL's symbols (its debug
    file) define none of them, and do define the trampolines of src/fmi/c_math.rs."""
    debug = DIST / "debug" / "x86_64-windows" / "mbcosim.dll.debug"
    assert debug.is_file(), debug
    nm = shutil.which("x86_64-w64-mingw32-nm")
    assert nm, "x86_64-w64-mingw32-nm missing (tests/setup_env.sh installs binutils-mingw-w64-x86-64)"
    defined = {f[2] for f in (line.split() for line in run([nm, "--defined-only", str(debug)]).stdout.splitlines())
               if len(f) == 3}
    assert not defined & MATH_FUNCTIONS, defined & MATH_FUNCTIONS
    assert {"__wrap_" + f for f in IMPORTED_BEFORE} <= defined


def test_native_executable_takes_no_math_from_the_c_runtime():
    """The native `mbcosim` (whose runs the FMU runs are compared with bit for bit) is linked
    the same way (the test binaries check it on themselves: src/fmi/c_math.rs)."""
    undefined = elf_undefined(BIN)
    assert "malloc" in undefined, BIN
    assert not undefined & MATH_FUNCTIONS, undefined & MATH_FUNCTIONS
