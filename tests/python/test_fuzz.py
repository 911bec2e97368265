"""Seeded random call sequences (fuzz_worker.py) in parallel subprocesses: no crash, no hang,
every refused call logged. A failing sequence is named `<seed>:<index>` for replay."""

import json
import subprocess
import sys

from conftest import HERE, SCENARIOS

WORKERS = 4
SEQUENCES_PER_WORKER = 1500


def test_random_call_sequences_never_crash(fmu, tmp_path, capsys):
    # physics models integrate real dynamics in every doStep: their scenario sets a smaller count
    per_worker = SCENARIOS.get(fmu.id, {}).get("fuzz_sequences", SEQUENCES_PER_WORKER)
    procs = [
        subprocess.Popen([sys.executable, str(HERE / "fuzz_worker.py"), fmu.unzip, fmu.id, str(seed), str(per_worker)],
                         cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for seed in range(1, WORKERS + 1)
    ]
    totals = {"sequences": 0, "calls": 0, "statuses": {}}
    for seed, p in enumerate(procs, start=1):
        out, err = p.communicate(timeout=240)
        progress = (tmp_path / f"{seed}.progress").read_text().strip() if (tmp_path / f"{seed}.progress").exists() else "?"
        assert p.returncode == 0, f"worker {seed} died with {p.returncode} in sequence {progress}\n{err[-2000:]}"
        summary = json.loads(out)
        assert summary["violation_count"] == 0, summary["violations"]
        totals["sequences"] += summary["sequences"]
        totals["calls"] += summary["calls"]
        for k, v in summary["statuses"].items():
            totals["statuses"][k] = totals["statuses"].get(k, 0) + v
    assert totals["sequences"] == WORKERS * per_worker
    assert set(totals["statuses"]) <= {"OK", "Warning", "Discard", "Error", "Fatal"}
    with capsys.disabled():
        print(f"\n[fuzz {fmu.id}] {totals['sequences']} sequences, {totals['calls']} calls, statuses {totals['statuses']}, 0 crashes")
