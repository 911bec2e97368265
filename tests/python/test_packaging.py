"""The archives: every registered model is packed, validators accept them, the layout is right."""

import ctypes
import pathlib
import shutil
import subprocess
import sys
import zipfile

from conftest import DIST, ROOT, fmu_paths
from fmpy.validation import validate_fmu
from test_fmi3 import FMI3_FUNCTIONS

FMI2_FUNCTIONS = """fmi2GetTypesPlatform fmi2GetVersion fmi2SetDebugLogging fmi2Instantiate fmi2FreeInstance
fmi2SetupExperiment fmi2EnterInitializationMode fmi2ExitInitializationMode fmi2Terminate fmi2Reset
fmi2GetReal fmi2GetInteger fmi2GetBoolean fmi2GetString fmi2SetReal fmi2SetInteger fmi2SetBoolean
fmi2SetString fmi2GetFMUstate fmi2SetFMUstate fmi2FreeFMUstate fmi2SerializedFMUstateSize
fmi2SerializeFMUstate fmi2DeSerializeFMUstate fmi2GetDirectionalDerivative fmi2SetRealInputDerivatives
fmi2GetRealOutputDerivatives fmi2DoStep fmi2CancelStep fmi2GetStatus fmi2GetRealStatus
fmi2GetIntegerStatus fmi2GetBooleanStatus fmi2GetStringStatus""".split()


def test_every_registered_model_is_packed():
    registered = {p.stem for p in (ROOT / "modelDescription").glob("*.xml")}
    assert registered, "no checked-in model descriptions"
    assert registered <= {p.stem for p in fmu_paths()}, f"missing in {DIST}"


def test_validate_fmu_reports_nothing(fmu):
    assert validate_fmu(str(fmu.path)) == []


def test_fmutool_check_passes(fmu):
    venv_tool = pathlib.Path(sys.executable).parent / "fmutool"
    fmutool = str(venv_tool) if venv_tool.exists() else shutil.which("fmutool")
    assert fmutool, "fmutool (fmu-manipulation-toolbox) is not installed"
    r = subprocess.run([fmutool, "-input", str(fmu.path), "-check"], capture_output=True, text=True, timeout=120)
    out = r.stdout + r.stderr
    assert r.returncode == 0, out
    assert "No semantic error" in out and "compliant with FMI-2.0" in out, out
    assert "ERROR" not in out and "WARNING" not in out, out


def test_archive_layout_and_exports(fmu):
    with zipfile.ZipFile(fmu.path) as z:
        names = set(z.namelist())
        assert {"modelDescription.xml", "documentation/index.html"} <= names
        # x86_64 Linux, x86_64 Windows, aarch64 Linux (FMI 2.0 has no aarch64 name: docs/platforms.md)
        binaries = {n for n in names if n.startswith("binaries/")}
        assert binaries == {f"binaries/linux64/{fmu.id}.so", f"binaries/win64/{fmu.id}.dll",
                            f"binaries/aarch64-linux/{fmu.id}.so"}, binaries
        packed = z.read("modelDescription.xml").decode()
        stamp = f' generationDateAndTime="{commit_time()}"'
        assert stamp in packed, packed[:800]
        assert packed.replace(stamp, "", 1) == (ROOT / "modelDescription" / f"{fmu.id}.xml").read_text()
        html = z.read("documentation/index.html").decode()
        assert "binaries for <code>linux64</code>, <code>win64</code>, <code>aarch64-linux</code>." in html
        for v in fmu.md.modelVariables:
            assert f"<code>{v.name}</code>" in html
    lib = ctypes.CDLL(f"{fmu.unzip}/binaries/linux64/{fmu.id}.so")
    for name in FMI2_FUNCTIONS:
        assert hasattr(lib, name), name
    assert len(FMI2_FUNCTIONS) == 34
    nm = shutil.which("nm")
    if nm:
        out = subprocess.run([nm, "-D", "--defined-only", f"{fmu.unzip}/binaries/linux64/{fmu.id}.so"],
                             capture_output=True, text=True).stdout
        exported = {line.split()[-1] for line in out.splitlines() if " T " in line}
        # the same library also serves the FMI 3.0 FMUs (docs/fmi3.md): nothing else is exported
        expected = set(FMI2_FUNCTIONS) | {"fmi3" + f for f in FMI3_FUNCTIONS}
        assert exported == expected, exported ^ expected


def test_capabilities_are_declared(fmu):
    cs = fmu.md.coSimulation
    assert cs.canHandleVariableCommunicationStepSize and cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.canNotUseMemoryManagementFunctions and not cs.needsExecutionTool
    assert {c.name for c in fmu.md.logCategories} >= {"logStatusWarning", "logStatusError", "logStatusFatal",
                                                  "logEvents", "logSolver"}
    assert sys.platform.startswith("linux")


def commit_time():
    """The checkout's last commit time as the xs:dateTime the pack writes (UTC, `Z`), computed by
    git and Python's calendar, not by the Rust code that stamps it."""
    import datetime
    seconds = int(subprocess.run(["git", "-C", str(ROOT), "log", "-1", "--format=%ct"],
                                 capture_output=True, text=True, check=True).stdout)
    return datetime.datetime.fromtimestamp(seconds, datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def test_licence_and_metadata_in_every_fmu():
    """Every FMU (FMI 2.0 and 3.0) carries the repository's LICENSE under
    documentation/licenses/ and its description names author, version (the crate's), copyright,
    licence, tool and the commit time (issue #44 item 5)."""
    import re
    import xml.etree.ElementTree as ET
    licence = (ROOT / "LICENSE").read_text()
    version = re.search(r'^version = "([^"]+)"', (ROOT / "Cargo.toml").read_text(), re.M).group(1)
    paths = sorted(DIST.glob("*.fmu")) + sorted((DIST / "fmi3").glob("*.fmu"))
    assert len(paths) >= 6, paths
    for path in paths:
        with zipfile.ZipFile(path) as z:
            assert z.read("documentation/licenses/license.txt").decode() == licence, path
            root = ET.fromstring(z.read("modelDescription.xml"))
        a = root.attrib
        assert a["version"] == version and a["generationTool"] == f"mbcosim {version}", (path, a)
        assert a["author"] and "Copyright" in a["copyright"] and a["license"].startswith("MIT"), (path, a)
        assert a["generationDateAndTime"] == commit_time(), (path, a)
