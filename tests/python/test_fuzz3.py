"""Seeded random FMI 3.0 call sequences (fuzz3_worker.py) against each FMI 3.0 FMU in dist/fmi3,
in parallel subprocesses: no crash, no hang, no fmi3Fatal, every refusal logged, the state
machine's refusals kept, no NaN after OK. A failing sequence is named `<seed>:<index>`; replay it
with `fuzz3_worker.py <unzip-dir> <seed> <index + 1>`."""

import json
import subprocess
import sys

import pytest
from conftest import DIST, HERE
from fmpy import extract

WORKERS = 2
SEQUENCES_PER_WORKER = 300
PATHS = sorted((DIST / "fmi3").glob("*.fmu"))


@pytest.mark.parametrize("path", PATHS, ids=[p.stem for p in PATHS])
def test_random_fmi3_call_sequences(path, tmp_path, capsys):
    unzip = extract(str(path), unzipdir=str(tmp_path / "fmu"))
    procs = [
        subprocess.Popen([sys.executable, str(HERE / "fuzz3_worker.py"), unzip, str(seed), str(SEQUENCES_PER_WORKER)],
                         cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for seed in range(1, WORKERS + 1)
    ]
    totals = {"sequences": 0, "calls": 0, "statuses": {}, "events": {}}
    for seed, p in enumerate(procs, start=1):
        out, err = p.communicate(timeout=240)
        progress = tmp_path / f"{seed}.progress"
        at = progress.read_text().strip() if progress.exists() else "?"
        assert p.returncode == 0, f"worker {seed} died with {p.returncode} in sequence {at}\n{err[-2000:]}"
        summary = json.loads(out)
        assert summary["violation_count"] == 0, summary["violations"]
        totals["sequences"] += summary["sequences"]
        totals["calls"] += summary["calls"]
        for key in ("statuses", "events"):
            for k, v in summary[key].items():
                totals[key][k] = totals[key].get(k, 0) + v
    assert totals["sequences"] == WORKERS * SEQUENCES_PER_WORKER
    assert set(totals["statuses"]) <= {"OK", "Warning", "Discard", "Error"}
    # the sequences reach the interesting places
    assert all(totals["events"][k] > 0 for k in totals["events"]), totals["events"]
    with capsys.disabled():
        print(f"\n[fuzz fmi3 {path.stem}] {totals['sequences']} sequences, {totals['calls']} calls, "
              f"statuses {totals['statuses']}, {totals['events']}, 0 crashes")
