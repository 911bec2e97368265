"""FMI 3.0 misuse through the C API (dist/fmi3/*.fmu): each case returns the expected status,
logs a message naming the cause, and the process lives.

The cases are listed in misuse3_cases.py; misuse3_worker.py runs each in its own forked process,
one worker per model (the next model in name order supplies the cross-model FMU states).
"""

import json

import pytest
from conftest import DIST, python_script
from fmi3raw import STATUS_NAMES, WARNING
from fmpy import extract
from misuse3_cases import CASES, SKIP

DIST3 = DIST / "fmi3"
PATHS = sorted(DIST3.glob("*.fmu"))
_UNZIPPED = {}
_RESULTS = {}


def unzipped(path, tmp_path_factory):
    if path not in _UNZIPPED:
        _UNZIPPED[path] = extract(str(path), unzipdir=str(tmp_path_factory.mktemp(path.stem + "_fmi3")))
    return _UNZIPPED[path]


def results_for(path, tmp_path_factory):
    if path not in _RESULTS:
        others = [p for p in PATHS if p != path]
        args = [unzipped(path, tmp_path_factory)]
        if others:
            args.append(unzipped(others[(PATHS.index(path)) % len(others)], tmp_path_factory))
        r = python_script("misuse3_worker.py", *args, timeout=300)
        assert r.returncode == 0, r.stderr
        _RESULTS[path] = json.loads(r.stdout)
    return _RESULTS[path]


def label(s):
    return s if isinstance(s, str) else STATUS_NAMES[s]


@pytest.fixture(params=PATHS, ids=[p.stem for p in PATHS])
def fmu3_path(request):
    return request.param


@pytest.mark.parametrize("name,expected,snippet", [c[:3] for c in CASES], ids=[c[0] for c in CASES])
def test_misuse3(fmu3_path, tmp_path_factory, name, expected, snippet):
    res = results_for(fmu3_path, tmp_path_factory)[name]
    assert res["exit"] == 0, f"the process died: {res}"
    if res["status"] == SKIP:
        if name.startswith("typed_") or len(PATHS) < 2:
            pytest.skip(f"{fmu3_path.stem} has no variable (or no other model) for {name}")
        pytest.fail(f"{fmu3_path.stem} has no variable for case {name}")
    assert res["status"] == expected, f"{label(res['status'])} instead of {label(expected)}: {res}"
    refusals = [m for (s, m) in res["log"] if s > WARNING]
    if snippet is None:
        assert not refusals, refusals
    elif snippet.startswith("stderr:"):
        assert snippet[7:] in res["stderr"], res
    elif snippet.startswith("warning:"):
        assert any(s == WARNING and snippet[8:] in m for (s, m) in res["log"]), res["log"]
    else:
        assert any(snippet in m for m in refusals), refusals


def test_every_typed_case_runs_on_some_model(tmp_path_factory):
    if len(PATHS) < 3:
        pytest.skip("needs the three packed models")
    typed = [c[0] for c in CASES if c[0].startswith("typed_")]
    ran = {n for p in PATHS for n, r in results_for(p, tmp_path_factory).items() if r["status"] != SKIP}
    assert set(typed) <= ran, set(typed) - ran


def test_case_count():
    assert len(CASES) >= 100
