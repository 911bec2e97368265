"""Unbounded inputs (issue #48, item 3): every file the FMU reads is checked to be a regular file,
read with a size cap, and its tables and keys counted against caps (docs/bounded_inputs.md).

Each case (bounded_inputs_worker.py) gives a RopeBlock FMU a hostile `scene.toml` or mesh file and
must be refused with fmi2Error, at instantiation (or at initialization for a `mesh_file` set by
fmi2SetString), with a message naming the file or parameter and the cap, within 1 s of CPU
time (user + system, measured by the worker with resource.getrusage around the FMI calls; wall
time is not used, the machine may be loaded). The worker runs in its own process under a
wall-clock timeout only so that a blocking read (a FIFO before this fix) fails the case instead
of hanging pytest.

Before this fix: a FIFO blocked fmi2Instantiate forever; /dev/zero and /dev/urandom were read to
2 GB and "out of memory"; 100,000 [[lug]] tables, 80,000 unknown keys and 20,000 long keys ran
past 20 s of CPU inside fmi2Instantiate (the line of every key was found by counting newlines from
the start); 2,000 [[sling]] tables instantiated and were then built at initialization (200,000
rope segments). Every case below but the controls and `scene_unreadable` fails on that code. An
unreadable scene.toml was already refused, but its only test passed without checking anything
when run as root (root reads a mode-000 file); it now runs without that privilege.
"""

import json
import os
import shutil
import subprocess
import sys

import pytest
from conftest import HERE, packed
from fmpy import extract

# must stay below, with room for a loaded machine; the refusals measured 0.00-0.2 s
CPU_LIMIT = 1.0

# case -> (where it is refused, snippets of the Error message)
EXPECT = {
    "mesh_fifo": ("instantiate", ["block.obj", "FIFO", "not a regular file"]),
    "mesh_file_fifo": ("instantiate", ["mesh_file", "block.obj", "FIFO"]),
    "mesh_file_fifo_at_init": ("initialization", ["mesh_file", "block.obj", "FIFO"]),
    "mesh_dev_zero": ("instantiate", ["/dev/zero", "character device"]),
    "mesh_dev_urandom": ("instantiate", ["/dev/urandom", "character device"]),
    "mesh_file_dev_zero_at_init": ("initialization", ["mesh_file", "/dev/zero", "character device"]),
    "mesh_directory": ("instantiate", ["block.obj", "a folder"]),
    "mesh_symlink_loop": ("instantiate", ["block.obj", "symbolic-link loop"]),
    "mesh_too_big": ("instantiate", ["block.stl", "MESH_FILE_BYTES", "256 MiB"]),
    "mesh_too_many_triangles": ("instantiate", ["block.stl", "MAX_MESH_TRIANGLES", "4000000"]),
    "scene_fifo": ("instantiate", ["scene.toml", "FIFO"]),
    "scene_dev_zero": ("instantiate", ["scene.toml", "character device"]),
    "scene_too_big": ("instantiate", ["scene.toml", "SCENE_FILE_BYTES", "4 MiB"]),
    "scene_2000_slings": ("instantiate", ["scene.toml", "MAX_SCENE_TABLES", "1000"]),
    "scene_65_slings": ("instantiate", ["scene.toml", "[[sling]] 64", "MAX_RIG_SLINGS"]),
    "scene_257_lugs": ("instantiate", ["scene.toml", "[[lug]] 256", "MAX_RIG_LUGS"]),
    "scene_100000_lugs": ("instantiate", ["scene.toml", "MAX_SCENE_TABLES"]),
    "scene_80000_unknown_keys": ("instantiate", ["scene.toml", "keys and array values", "MAX_SCENE_KEYS", "10000"]),
    "scene_20000_long_keys": ("instantiate", ["scene.toml", "SCENE_FILE_BYTES"]),
    "scene_20000_keys_under_size_cap": ("instantiate", ["scene.toml", "keys and array values", "MAX_SCENE_KEYS"]),
    "scene_unreadable": ("instantiate", ["scene.toml", "Permission denied"]),
}
CONTROLS = ["control_valid_rig", "control_largest_rig"]

_UNZIPPED = {}


def unzipped(tmp_path_factory):
    path = packed("RopeBlock")
    if path not in _UNZIPPED:
        _UNZIPPED[path] = extract(str(path), unzipdir=str(tmp_path_factory.mktemp("bounded")))
    return _UNZIPPED[path]


def without_file_permissions():
    """The command prefix that makes file permissions apply: as root (which reads a mode-000 file
    through CAP_DAC_OVERRIDE) `setpriv` drops that capability and CAP_DAC_READ_SEARCH for the
    worker; the FMU's open then really fails with EACCES."""
    if os.geteuid() != 0:
        return []
    setpriv = shutil.which("setpriv")
    if setpriv is None:
        pytest.fail("running as root, and setpriv (util-linux) is missing to drop CAP_DAC_OVERRIDE")
    drop = "-dac_override,-dac_read_search"
    return [setpriv, "--bounding-set", drop, "--inh-caps", drop]


def run(case, unzip):
    prefix = without_file_permissions() if case == "scene_unreadable" else []
    cmd = prefix + [sys.executable, str(HERE / "bounded_inputs_worker.py"), unzip, case]
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{case}: no answer within 60 s wall time (a read that blocks or never ends)")
    assert r.returncode == 0, f"{case}: exit code {r.returncode}\n{r.stderr[-4000:]}"
    return json.loads(r.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("case", sorted(EXPECT))
def test_hostile_input_is_refused_quickly_naming_the_cap(case, tmp_path_factory):
    where, snippets = EXPECT[case]
    out = run(case, unzipped(tmp_path_factory))
    assert out["refused_at"] == where, f"{case}: {out}"
    assert out["errors"], out
    message = out["errors"][-1]
    missing = [s for s in snippets if s not in message]
    assert not missing, f"{case}: {missing} not in {message!r}"
    assert out["cpu"] < CPU_LIMIT, f"{case}: refused after {out['cpu']:.3f} s CPU"


@pytest.mark.parametrize("case", CONTROLS)
def test_rigs_within_the_caps_are_accepted(case, tmp_path_factory):
    out = run(case, unzipped(tmp_path_factory))
    assert out["refused_at"] is None and not out["errors"], out
