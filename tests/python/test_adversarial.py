"""The adversarial harness (adversarial.py, docs/adversarial_harness.md): a seeded slice of forged
FMU states, parameter envelopes and random call sequences in forked workers with a watchdog,
every field of the serialized state format forged, a valgrind memcheck run, and the regression
tests of what the harness found.

The benchmark (`bash benches/adversarial.sh`) runs the same harness at >= 100,000 sequences.
"""

import json
import math
import os
import pathlib
import re
import shutil
import struct
import subprocess
import sys

import pytest
from conftest import DIST, HERE, ROOT, packed

import adversarial as A
import fmi2raw as R

SEED = 25
CPU_LIMIT = 5.0


def mbcosim():
    exe = os.environ.get("MBCOSIM_BIN", str(ROOT / "target" / "release" / "mbcosim"))
    assert pathlib.Path(exe).exists(), f"{exe} is missing: build it (cargo build --release --bin mbcosim)"
    return exe


def harness(tmp_path, *args, timeout=400):
    for m in A.MODELS:
        packed(m)
    out = tmp_path / "summary.json"
    r = subprocess.run([sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
                        "--json", str(out), *map(str, args)], capture_output=True, text=True, timeout=timeout)
    assert r.returncode == 0, r.stderr[-3000:]
    return json.loads(out.read_text())


def unexpected(summary):
    """Findings that are not listed in adversarial.KNOWN_FAILURES."""
    return [f for f in summary["findings"]
            if not all(A.known_failure(f["model"], cls, text) for cls, text in f["violations"])]


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    work = tmp_path_factory.mktemp("adversarial")
    return {m: A.Model(DIST, m, work, mbcosim()) for m in A.MODELS}


def test_seeded_slice_has_no_crash_hang_or_nan_with_ok(tmp_path, capsys):
    s = harness(tmp_path, "--seed", SEED, "--count", 1500, "--workers", 2, "--cpu-limit", CPU_LIMIT)
    assert s["tried"] == 1500
    for key in ("crashes", "hangs", "nan_with_ok", "other_violations"):
        known = sum(1 for f in s["findings"] for cls, text in f["violations"]
                    if A.known_failure(f["model"], cls, text) and A.count_class(cls) == key)
        assert s[key] == known, (key, unexpected(s)[:5])
    assert not unexpected(s), unexpected(s)[:5]
    # every model and kind ran, and the refusals are a real share (the checks are exercised)
    assert {k.split("/")[0] for k in s["by_kind"]} == set(A.MODELS)
    assert {k.split("/")[1] for k in s["by_kind"]} == set(A.KINDS)
    assert s["refused_with_message"] > 100 and s["completed"] > 100, s
    with capsys.disabled():
        print(f"\n[adversarial slice] {A.counts_line(s)} in {s['seconds']} s")


@pytest.mark.parametrize("model", A.MODELS)
def test_every_field_of_the_state_format_is_forged(model, tmp_path, models):
    m = models[model]
    total = sum(len(fields) for (_, _, fields) in m.bases)
    s = harness(tmp_path, "--seed", SEED, "--models", model, "--kinds", "forge", "--count", total,
                "--workers", 2, "--cpu-limit", CPU_LIMIT)
    assert s["fields_visited"] == s["fields_total"] == total, s["fields_missed"]
    assert s["crashes"] == s["hangs"] == s["nan_with_ok"] == 0, unexpected(s)[:5]
    assert not unexpected(s), unexpected(s)[:5]
    # the model-level checks are reached: refusals name fields past the envelope's header
    assert s["refused_with_message"] > total // 2, s


@pytest.mark.parametrize("model", A.MODELS)
def test_forged_non_finite_numbers_never_pass_as_ok(model, models):
    """Regression (found by the harness): a state with NaN or inf in a model field (PanelLock
    speeds, lock times, contact forces) restored with fmi2OK and NaN outputs. Every f64 field of
    each base state, at NaN and at -inf: refused with a message, or the outputs stay finite."""
    m = models[model]
    checked = 0
    for base, data, fields in m.bases:
        for field in fields:
            if field["kind"] != "f64":
                continue
            for bad in (math.nan, -math.inf):
                span = field["spans"][0]
                body = bytearray(data[:-8])
                body[span["offset"]:span["offset"] + 8] = struct.pack("<d", bad)
                inst = m.new()
                s, handle = inst.deserialize(R.reseal(bytes(body)))
                if s == R.OK:
                    s = inst.set_state(handle)
                if s == R.OK and A.state_code(data) not in (0, None):
                    s_get, values = inst.get_real(m.outputs)
                    assert s_get == R.OK
                    assert all(math.isfinite(v) for v in values), (base, field["what"], bad, values)
                elif s != R.OK:
                    assert s == R.ERROR and inst.messages(), (base, field["what"], s)
                inst.free()
                checked += 1
    assert checked > 10


def test_valgrind_memcheck_of_a_short_sequence_set(tmp_path):
    """A short inline sequence set under valgrind memcheck: no invalid access, no use of
    uninitialised values, no definite leak in the FMU library (suppressions and their reasons:
    tests/python/valgrind.supp, docs/adversarial_harness.md)."""
    valgrind = shutil.which("valgrind")
    assert valgrind, "valgrind is missing: tests/setup_env.sh installs it"
    for m in A.MODELS:
        packed(m)
    log = tmp_path / "memcheck.log"
    env = {**os.environ, "PYTHONMALLOC": "malloc"}
    cmd = [valgrind, "--tool=memcheck", "--error-exitcode=99", "--leak-check=full",
           "--errors-for-leak-kinds=definite", "--show-leak-kinds=definite",
           f"--suppressions={HERE / 'valgrind.supp'}", f"--log-file={log}",
           sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
           "--seed", SEED, "--count", 24, "--inline", "--json", str(tmp_path / "s.json")]
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=600, env=env)
    text = log.read_text()
    assert r.returncode == 0, text[-4000:]
    assert "ERROR SUMMARY: 0 errors" in text, text[-4000:]
    s = json.loads((tmp_path / "s.json").read_text())
    assert s["tried"] == 24
