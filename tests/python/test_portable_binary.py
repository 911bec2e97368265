"""The shipped binaries: portable (glibc 2.17 floor on x86_64 and aarch64 Linux; the Windows DLL
importing Windows system DLLs only), stripped, their debug info split into dist/debug/.

scripts/build_portable.sh builds it (docs/portable_binary.md). When the zig toolchain cannot be
installed it falls back to the host build with a warning, and the glibc check here then fails:
a host build never passes as portable.
"""

import io
import re
import shutil
import subprocess
import zipfile
import zlib

import pytest
from elftools.elf.elffile import ELFFile
from elftools.elf.gnuversions import GNUVerNeedSection
from elftools.elf.sections import NoteSection

from conftest import DIST, fmu_paths

GLIBC_FLOOR = (2, 17)
# Measured 1.6 MB with the x86_64 Linux library alone (docs/portable_binary.md; the unstripped
# library made 8.4 MB FMUs), 7.2 MB with the three platforms' (docs/platforms.md).
MAX_FMU_MB = 8.5
DEBUG_DIR = DIST / "debug"


# The Windows DLLs the FMUs' DLL may import: system DLLs of Windows 10 and later, nothing of
# MinGW's runtime (libgcc_s_seh-1.dll, libwinpthread-1.dll, libstdc++-6.dll).
WINDOWS_SYSTEM_DLLS = {"kernel32.dll", "ntdll.dll", "msvcrt.dll", "advapi32.dll", "userenv.dll",
                       "ws2_32.dll", "bcryptprimitives.dll"}


def shared_library(path, folder="linux64", ext=".so"):
    with zipfile.ZipFile(path) as z:
        names = [n for n in z.namelist() if n.startswith(f"binaries/{folder}/") and n.endswith(ext)]
        assert len(names) == 1, names
        return z.read(names[0])


def elf(data):
    return ELFFile(io.BytesIO(data))


def glibc_versions(e):
    """Every GLIBC_x.y version the library asks for (.gnu.version_r)."""
    found = set()
    for section in e.iter_sections():
        if isinstance(section, GNUVerNeedSection):
            for _, auxiliaries in section.iter_versions():
                found |= {aux.name for aux in auxiliaries if aux.name.startswith("GLIBC_")}
    return found


def build_id(e):
    for section in e.iter_sections():
        if isinstance(section, NoteSection):
            for note in section.iter_notes():
                if note["n_type"] == "NT_GNU_BUILD_ID":
                    return note["n_desc"]
    return None


def debuglink(e):
    """(file name, CRC-32) of the .gnu_debuglink section."""
    section = e.get_section_by_name(".gnu_debuglink")
    assert section is not None, "no .gnu_debuglink section"
    data = section.data()
    name = data[: data.index(b"\0")].decode()
    crc = int.from_bytes(data[-4:], "little")
    return name, crc


def test_glibc_floor(fmu):
    versions = glibc_versions(elf(shared_library(fmu.path)))
    assert versions, "no GLIBC symbol versions found"
    assert "GLIBC_PRIVATE" not in versions
    highest = max(versions, key=lambda v: tuple(int(x) for x in v[len("GLIBC_"):].split(".")))
    floor = "GLIBC_" + ".".join(map(str, GLIBC_FLOOR))
    assert tuple(int(x) for x in highest[len("GLIBC_"):].split(".")) <= GLIBC_FLOOR, (
        f"{fmu.path.name}: the library needs {highest} (> {floor}): a host build, not the portable "
        "one (scripts/build_portable.sh fell back; see its warning and docs/portable_binary.md)")


def test_stripped_with_split_debug_info(fmu):
    lib = elf(shared_library(fmu.path))
    sections = [s.name for s in lib.iter_sections()]
    assert not [s for s in sections if s.startswith((".debug_", ".zdebug_"))], sections
    assert ".symtab" not in sections, "symbol table not stripped"

    name, crc = debuglink(lib)
    debug_file = DEBUG_DIR / name
    assert debug_file.is_file(), f"{debug_file} missing (the split debug info)"
    debug_bytes = debug_file.read_bytes()
    assert zlib.crc32(debug_bytes) == crc, f"{debug_file} is not the debug info of {fmu.path.name}"
    debug = elf(debug_bytes)
    assert debug.get_section_by_name(".debug_info") is not None
    assert debug.get_section_by_name(".debug_line") is not None
    assert build_id(lib) is not None, "no GNU build ID"
    assert build_id(lib) == build_id(debug)


def test_one_library_in_every_fmu():
    for folder, ext in (("linux64", ".so"), ("win64", ".dll"), ("aarch64-linux", ".so")):
        libs = {p.name: shared_library(p, folder, ext) for p in fmu_paths()}
        assert len(libs) >= 2, f"FMUs in {DIST}: {sorted(libs)}"
        assert len(set(libs.values())) == 1, f"the FMUs ship different {folder} libraries"
        fmi3 = {p.name: shared_library(p, folder.replace("linux64", "x86_64-linux").replace(
            "win64", "x86_64-windows"), ext) for p in sorted((DIST / "fmi3").glob("*.fmu"))}
        assert set(fmi3.values()) == set(libs.values()), f"FMI 3.0 FMUs ship another {folder} library"


def test_aarch64_library_is_portable_and_stripped(fmu):
    data = shared_library(fmu.path, "aarch64-linux")
    lib = elf(data)
    assert lib["e_machine"] == "EM_AARCH64", lib["e_machine"]
    versions = glibc_versions(lib)
    highest = max(tuple(int(x) for x in v[len("GLIBC_"):].split(".")) for v in versions)
    assert highest <= GLIBC_FLOOR, f"{fmu.path.name}: aarch64 library needs GLIBC_{highest}"
    sections = [s.name for s in lib.iter_sections()]
    assert not [s for s in sections if s.startswith(".debug_")] and ".symtab" not in sections, sections
    name, crc = debuglink(lib)
    debug_file = DEBUG_DIR / "aarch64-linux" / name
    assert zlib.crc32(debug_file.read_bytes()) == crc, debug_file
    assert build_id(lib) is not None and build_id(lib) == build_id(elf(debug_file.read_bytes()))


def test_windows_dll_needs_no_mingw_runtime(fmu, tmp_path):
    objdump = shutil.which("x86_64-w64-mingw32-objdump")
    assert objdump, "x86_64-w64-mingw32-objdump missing (tests/setup_env.sh installs binutils-mingw-w64-x86-64)"
    dll = tmp_path / "lib.dll"
    dll.write_bytes(shared_library(fmu.path, "win64", ".dll"))
    headers = subprocess.run([objdump, "-p", "-h", str(dll)], capture_output=True, text=True, check=True).stdout
    assert "file format pei-x86-64" in headers, headers[:300]
    imports = {m.lower() for m in re.findall(r"DLL Name: (\S+)", headers)}
    foreign = {m for m in imports if m not in WINDOWS_SYSTEM_DLLS and not m.startswith("api-ms-win-")}
    assert not foreign, f"{fmu.path.name}: the DLL needs {sorted(foreign)} beside it"
    assert "kernel32.dll" in imports, imports
    exports = set(re.findall(r"\]\s+(fmi[23]\w+)", headers))
    assert {"fmi2Instantiate", "fmi2DoStep", "fmi3InstantiateCoSimulation", "fmi3DoStep"} <= exports, exports
    assert ".debug_info" not in headers, "debug info not stripped"
    link = tmp_path / "debuglink"
    subprocess.run([objdump.replace("objdump", "objcopy"), f"--dump-section=.gnu_debuglink={link}", str(dll),
                    str(tmp_path / "copy.dll")], check=True)
    data = link.read_bytes()
    name = data[: data.index(b"\0")].decode()
    debug_file = DEBUG_DIR / "x86_64-windows" / name
    assert debug_file.is_file(), debug_file
    assert zlib.crc32(debug_file.read_bytes()) == int.from_bytes(data[-4:], "little"), debug_file


def test_fmu_size(fmu):
    mb = fmu.path.stat().st_size / 1e6
    assert mb < MAX_FMU_MB, f"{fmu.path.name}: {mb:.1f} MB"
