"""The shipped binary: portable (glibc 2.17 floor), stripped, its debug info split into dist/debug/.

scripts/build_portable.sh builds it (docs/portable_binary.md). When the zig toolchain cannot be
installed it falls back to the host build with a warning, and the glibc check here then fails:
a host build never passes as portable.
"""

import io
import zipfile
import zlib

import pytest
from elftools.elf.elffile import ELFFile
from elftools.elf.gnuversions import GNUVerNeedSection
from elftools.elf.sections import NoteSection

from conftest import DIST, fmu_paths

GLIBC_FLOOR = (2, 17)
# Measured 1.6 MB (docs/portable_binary.md); the unstripped library made 8.4 MB FMUs.
MAX_FMU_MB = 3.0
DEBUG_DIR = DIST / "debug"


def shared_library(path):
    with zipfile.ZipFile(path) as z:
        names = [n for n in z.namelist() if n.startswith("binaries/linux64/") and n.endswith(".so")]
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
    libs = {p.name: shared_library(p) for p in fmu_paths()}
    assert len(libs) >= 2, f"FMUs in {DIST}: {sorted(libs)}"
    assert len(set(libs.values())) == 1, "the FMUs ship different libraries"


def test_fmu_size(fmu):
    mb = fmu.path.stat().st_size / 1e6
    assert mb < MAX_FMU_MB, f"{fmu.path.name}: {mb:.1f} MB"
