"""Robustness of the C boundary (issue #48), found by an independent ctypes harness.

- Calls into an instance from inside one of its own callbacks (the logger in FMI 2.0 and 3.0)
  are refused with a logged Error and change nothing; fmi2FreeInstance/fmi3FreeInstance
  re-entered does not free.
- A freed instance handle or a pointer that is not an instance gets Error (free: ignored)
  instead of a crash (docs/fmu_conformance.md says where this guard stops).
- fmuResourceLocation / resourcePath: the URI scheme is case-insensitive; another scheme, another
  host, a query or fragment, a missing folder, or a scene.toml that cannot be read refuses the
  instance with the location and the cause named; NULL or empty stays a Warning with the built-in
  defaults (docs/resource_location.md).
- Log messages are cut after 4096 bytes with "... (N more characters)" (a 10 MB string echoed
  in a message reached the logger whole).

Each case runs in its own interpreter (robust_worker.py) on PidController, so a crash fails the
case, not pytest; the unreadable scene.toml runs, as root, under `setpriv` without
CAP_DAC_OVERRIDE (root would read it otherwise). Every case but the controls (`*_control`, `*localhost*`, NULL and empty
locations, `fmi2_scene_not_utf8`) fails on the code before issue #48.
"""

import os
import subprocess
import sys

import pytest
from conftest import DIST, HERE, python_script
from fmpy import extract
from robust_worker import CASES

_UNZIPPED = {}


def unzipped(version, tmp_path_factory):
    path = DIST / "PidController.fmu" if version == "fmi2" else DIST / "fmi3" / "PidController.fmu"
    if not path.exists():
        pytest.fail(f"{path} is missing: run `cargo run --release --bin mbcosim -- pack` first")
    if path not in _UNZIPPED:
        _UNZIPPED[path] = extract(str(path), unzipdir=str(tmp_path_factory.mktemp(f"robust_{version}")))
    return _UNZIPPED[path]


# what the FMU must print on stderr (no logger can be reached for a freed or foreign handle)
STDERR = {
    "fmi2_free_twice": "already freed",
    "fmi2_call_after_free": "already freed",
    "fmi2_garbage_handle": "not an instance",
    "fmi3_free_twice": "already freed",
    "fmi3_call_after_free": "already freed",
    "fmi3_garbage_handle": "not an instance",
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_robust(case, tmp_path_factory):
    version = case[:4]
    unzip = unzipped(version, tmp_path_factory)
    if case.endswith("_unreadable") and os.geteuid() == 0:
        # root reads a mode-000 file: drop the capability for this worker (test_bounded_inputs.py)
        from test_bounded_inputs import without_file_permissions

        cmd = without_file_permissions() + [sys.executable, str(HERE / "robust_worker.py"), version, unzip, case]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    else:
        r = python_script("robust_worker.py", version, unzip, case, timeout=120)
    assert r.returncode == 0, f"{case}: exit code {r.returncode} (negative: killed by that signal)\n{r.stderr[-4000:]}"
    if case in STDERR:
        assert STDERR[case] in r.stderr, r.stderr[-4000:]
