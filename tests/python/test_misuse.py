"""Misuse through the C API: each case returns the right status, logs why, and the process lives.

The cases are listed in misuse_cases.py; misuse_worker.py runs each in its own forked process.
"""

import json

import pytest
from conftest import python_script
from misuse_cases import CASES, NULL, SKIP
from fmi2raw import STATUS_NAMES

_RESULTS = {}


def results_for(fmu):
    if fmu.path not in _RESULTS:
        r = python_script("misuse_worker.py", fmu.unzip, fmu.id, timeout=300)
        assert r.returncode == 0, r.stderr
        _RESULTS[fmu.path] = json.loads(r.stdout)
    return _RESULTS[fmu.path]


GENERIC = [c for c in CASES if not c[0].startswith("pid_")]
PID_ONLY = [c for c in CASES if c[0].startswith("pid_")]


def check_case(fmu, name, expected, snippet):
    res = results_for(fmu)[name]
    assert res["exit"] == 0, f"the process died: {res}"
    assert res["status"] != SKIP, f"{fmu.id} has no variable for case {name}"
    label = lambda s: s if isinstance(s, str) else STATUS_NAMES[s]
    assert res["status"] == expected, f"{label(res['status'])} instead of {label(expected)}: {res}"
    if snippet is None:
        assert not res["messages"], res["messages"]
    elif snippet.startswith("stderr:"):
        assert snippet[7:] in res["stderr"], res
    else:
        assert any(snippet in m for m in res["messages"]), res["messages"]


@pytest.mark.parametrize("name,expected,snippet", [(n, s, snip) for (n, s, snip, _) in GENERIC],
                         ids=[c[0] for c in GENERIC])
def test_misuse(fmu, name, expected, snippet):
    check_case(fmu, name, expected, snippet)


@pytest.mark.scenario_key("pid_misuse")
@pytest.mark.parametrize("name,expected,snippet", [(n, s, snip) for (n, s, snip, _) in PID_ONLY],
                         ids=[c[0] for c in PID_ONLY])
def test_controller_misuse(fmu, name, expected, snippet):
    check_case(fmu, name, expected, snippet)


def test_case_count():
    assert len(CASES) >= 50
