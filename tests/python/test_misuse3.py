"""FMI 3.0 misuse through the C API (dist/fmi3/*.fmu): each case returns the expected status,
logs a message naming the cause, and the process lives.

The cases are listed in misuse3_cases.py; misuse3_worker.py runs each in its own forked process,
one worker per model (the next model in name order supplies the cross-model FMU states).
"""

import json

import pytest
from conftest import DIST, python_script
from fmi3raw import STATUS_NAMES, WARNING
from fmpy import extract, read_model_description
from misuse3_cases import CASES, SKIP, TYPED_NEEDS

DIST3 = DIST / "fmi3"
MODELS = ["PanelLock", "PidController", "RopeBlock"]
PATHS = [DIST3 / f"{m}.fmu" for m in MODELS]


def variable_types(path):
    """The FMI 3.0 types of the model's variables (empty when the FMU is missing: the
    presence test below fails then)."""
    if not path.exists():
        return set()
    return {v.type for v in read_model_description(str(path)).modelVariables}


TYPES = {p: variable_types(p) for p in PATHS}
# every case on every model, except a typed case on a model without a variable of its type
PAIRS = [(p, c) for p in PATHS for c in CASES if c[0] not in TYPED_NEEDS or TYPED_NEEDS[c[0]] in TYPES[p]]
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


@pytest.mark.parametrize("fmu3_path,name,expected,snippet", [(p, *c[:3]) for p, c in PAIRS],
                         ids=[f"{p.stem}-{c[0]}" for p, c in PAIRS])
def test_misuse3(fmu3_path, tmp_path_factory, name, expected, snippet):
    res = results_for(fmu3_path, tmp_path_factory)[name]
    assert res["exit"] == 0, f"the process died: {res}"
    assert res["status"] != SKIP, f"{fmu3_path.stem} has no variable for case {name}"
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


def test_the_three_fmi3_fmus_are_packed():
    missing = [str(p) for p in PATHS if not p.exists()]
    assert not missing, f"run `cargo run --release --bin mbcosim -- pack` first: {missing}"


def test_every_typed_case_runs_on_some_model():
    typed = {c[0] for c in CASES if c[0].startswith("typed_")}
    assert typed == set(TYPED_NEEDS)
    ran = {c[0] for _, c in PAIRS}
    assert typed <= ran, typed - ran


def test_case_count():
    assert len(CASES) >= 100
