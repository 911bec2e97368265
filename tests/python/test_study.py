"""mbstudy (tools/mbstudy, docs/parameter_studies.md): a 20-case RopeBlock study on a real
LocalCluster (2 worker processes over loopback TCP) gives the same rows, bit for bit, as the
same cases run serially in this process; a case the FMU refuses is a failed row with the FMU's
message; an interrupted study resumes without running finished cases again; a worker killed
mid-study is survived. The summary figures are checked against fmpy's own simulate_fmu and the
spectrum against a sine of known frequency."""

import csv
import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pyarrow.parquet as pq
import pytest
from conftest import ROOT, packed
from fmpy import simulate_fmu

sys.path.insert(0, str(ROOT / "tools" / "mbstudy"))  # this tree's mbstudy, not an installed one
from mbstudy import cases, driver, spec, summary  # noqa: E402
from mbstudy.store import RUN_COLUMNS  # noqa: E402

# the command of this tree's mbstudy (the installed console script may be another tree's)
MBSTUDY = [sys.executable, "-m", "mbstudy.cli"]
MBSTUDY_ENV = {**os.environ, "PYTHONPATH": str(ROOT / "tools" / "mbstudy")}

# 5 block masses (the first one refused by the FMU: below its minimum) x 4 hoist speeds
STUDY = """
[study]
name = "test_rope"
fmu = "{fmu}"
stop_time = {stop}
step = 0.05

[fixed]
segments = {segments}

[grid]
block_mass = [-1.0, 1.5e5, 2e5, 2.5e5, 3e5]
hoist_speed = [0.1, 0.2, 0.3, 0.4]

[inputs]
hook0_vz = [[0.0, 0.0], [0.5, "hoist_speed"]]

[outputs]
hook0_load = ["peak", "initial", "final", "mean", "spectrum_peak"]
block_z = ["initial", "final"]

[spectrum]
start = 0.5

[derived]
daf = {{ ratio = ["hook0_load.peak", "hook0_load.initial"] }}
"""


def write_study(tmp, stop=2.0, segments=20):
    path = tmp / "study.toml"
    path.write_text(STUDY.format(fmu=packed("RopeBlock"), stop=stop, segments=segments))
    return spec.load(path)


def csv_rows(path):
    with open(path, newline="") as f:
        return [{k: v for k, v in r.items() if k not in RUN_COLUMNS} for r in csv.DictReader(f)]


def results(table):
    """The computed part of a results table (without run time and worker)."""
    return table.drop_columns(list(RUN_COLUMNS))


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The reference: every case in this process, one after the other."""
    tmp = tmp_path_factory.mktemp("serial")
    study = write_study(tmp)
    return study, driver.run(study, tmp / "out", serial=True, progress=False)


def test_cluster_run_equals_serial_bit_for_bit_and_records_the_failing_cases(serial, tmp_path):
    study, ref = serial
    out = tmp_path / "out"
    # the one command, as a user runs it: an embedded LocalCluster of 2 workers
    done = subprocess.run([*MBSTUDY, "run", str(study.path), "--workers", "2", "--out", str(out)],
                          capture_output=True, text=True, timeout=300, env=MBSTUDY_ENV)
    assert done.returncode == 0, done.stderr
    assert "16 done, 4 failed of 20 cases" in done.stdout, done.stdout
    table = pq.read_table(out / "results.parquet")
    assert table.num_rows == 20
    assert results(table).equals(results(ref))
    # the CSV holds the same bits (floats as shortest round-trip text)
    assert csv_rows(out / "results.csv") == csv_rows(study.path.parent / "out" / "results.csv")
    # both worker processes took cases
    assert len({w for w in table.column("worker").to_pylist()}) == 2
    rows = table.to_pylist()
    failed = [r for r in rows if r["status"] == "failed"]
    assert [r["block_mass"] for r in failed] == [-1.0] * 4
    for r in failed:
        assert "block_mass" in r["message"] and "below its minimum" in r["message"], r["message"]
        assert r["hook0_load.peak"] is None
    assert all(r["status"] == "done" for r in rows if r["block_mass"] > 0)


def test_an_existing_cluster_given_by_its_scheduler_address(serial, tmp_path):
    """`--scheduler ADDRESS`: the command connects to a running cluster (here one started in
    this process, 1 worker) instead of starting its own."""
    from distributed import LocalCluster

    study, ref = serial
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster:
        done = subprocess.run([*MBSTUDY, "run", str(study.path), "--scheduler", cluster.scheduler_address,
                               "--out", str(tmp_path / "out"), "--no-progress"],
                              capture_output=True, text=True, timeout=300, env=MBSTUDY_ENV)
        assert done.returncode == 0, done.stderr
    table = pq.read_table(tmp_path / "out" / "results.parquet")
    assert results(table).equals(results(ref))
    assert len(set(table.column("worker").to_pylist())) == 1  # the cluster's one worker


def test_summary_figures_match_fmpy_simulate_fmu(serial):
    """One case again through fmpy's own simulate_fmu (its input table, its output sampling),
    reduced with plain numpy."""
    study, ref = serial
    row = next(r for r in ref.to_pylist() if r["block_mass"] == 2e5 and r["hoist_speed"] == 0.3)
    # fmpy interpolates its input table linearly between rows and applies it at communication
    # points: one row per point (exact values, no interpolation), 0.3 m/s from 0.5 s on
    t = np.arange(41) * 0.05
    hoist = np.array([(ti, 0.3 if i >= 10 else 0.0) for i, ti in enumerate(t)],
                     dtype=[("time", np.float64), ("hook0_vz", np.float64)])
    res = simulate_fmu(str(study.fmu), stop_time=2.0, output_interval=0.05, input=hoist,
                       start_values={"segments": 20, "block_mass": 2e5},
                       output=["hook0_load", "block_z"])
    load = res["hook0_load"]
    assert len(load) == 41
    assert row["hook0_load.peak"] == load.max()
    assert row["hook0_load.initial"] == load[0]
    assert row["hook0_load.final"] == load[-1]
    assert row["hook0_load.mean"] == load.mean()
    assert row["block_z.final"] == res["block_z"][-1]
    assert row["daf"] == load.max() / load[0]
    # hoisting 0.3 m/s for 1.5 s raises the block by about 0.45 m (the model ramps each command
    # over 0.5 s: between 0.3 * 1.0 and 0.3 * 1.5)
    rise = row["block_z.final"] - row["block_z.initial"]
    assert 0.3 < rise < 0.46, rise


def test_spectrum_peak_finds_a_known_frequency():
    t = np.arange(0, 30.0, 0.01)
    x = 3.0 + 0.5 * np.sin(2 * np.pi * 0.73 * t) + 0.1 * np.sin(2 * np.pi * 2.9 * t)
    f = summary.spectrum_peak(t, x, (0.03, 5.0))
    assert abs(f - 0.73) < 1.0 / (summary.PAD * 30.0)
    assert summary.spectrum_peak(t, x, (1.0, 5.0)) == pytest.approx(2.9, abs=1.0 / (summary.PAD * 30.0))


def test_interrupted_study_resumes_without_running_finished_cases(serial, tmp_path):
    _, ref = serial
    study = write_study(tmp_path)
    out = tmp_path / "out"
    first = []

    def stop_after_7(row):
        first.append(row["case_id"])
        if len(first) == 7:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        driver.run(study, out, serial=True, progress=False, on_row=stop_after_7)
    # a torn last line, as a kill in the middle of a write leaves it
    with open(out / "journal.jsonl", "a") as f:
        f.write('{"case_index": 7, "case_id": "')
    second = []
    table = driver.run(study, out, workers=2, progress=False, on_row=lambda r: second.append(r["case_id"]))
    assert len(first) == 7 and len(second) == 13
    assert not set(first) & set(second)
    assert results(table).equals(results(ref))
    # a third run has nothing left to do
    third = []
    driver.run(study, out, serial=True, progress=False, on_row=lambda r: third.append(r))
    assert third == []


def test_a_killed_worker_is_survived(tmp_path):
    from distributed import Client, LocalCluster

    # longer cases (about 0.3 s each) so that the worker dies with a case in hand
    study = write_study(tmp_path, stop=3.0, segments=40)
    ref = driver.run(study, tmp_path / "serial", serial=True, progress=False)
    killed = []
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        assert all(a.startswith("tcp://127.0.0.1:") for a in client.scheduler_info()["workers"])
        pids = client.run(os.getpid)

        def kill_one(row):
            if killed or row["status"] != "done":
                return
            busy = {a: keys for a, keys in client.processing().items() if keys}
            victim = max(busy, key=lambda a: len(busy[a]))
            killed.append((pids[victim], busy[victim]))
            os.kill(pids[victim], signal.SIGKILL)

        table = driver.run(study, tmp_path / "cluster", client=client, progress=False, on_row=kill_one)
        assert killed and killed[0][1], "no worker was killed with a case in hand"
        deadline = time.time() + 30
        while time.time() < deadline and len(client.scheduler_info()["workers"]) < 2:
            time.sleep(0.2)
        new_pids = set(client.run(os.getpid).values())
    pid, cases_in_hand = killed[0]
    assert pid not in new_pids  # the nanny started a new worker process
    rows = table.to_pylist()
    assert len(rows) == 20
    assert results(table).equals(results(ref))
    # every case the dead worker held has its row (run again by the survivor or the new worker,
    # unless it had reported just before the kill)
    by_key = {f"mbstudy-case-{r['case_id']}": r for r in rows}
    assert set(cases_in_hand) <= set(by_key)
    assert any(not by_key[k]["worker"].endswith(f":{pid}") for k in cases_in_hand)


def test_shipped_studies_describe_the_issue_cases():
    table1 = spec.load(ROOT / "studies" / "table1.toml", fmu=packed("PanelLock"))
    c = cases.generate(table1)
    ks = sorted({x.values["contact_stiffness"] for x in c})
    ns = sorted({x.values["contact_exponent"] for x in c})
    assert ks[0] == 1e6 and ks[-1] == 1e9 and ns[0] == 0.9 and ns[-1] == 1.5
    assert len(c) == len(ks) * len(ns)
    marked = {(x.values["contact_stiffness"], x.values["contact_exponent"]) for x in c if x.mark}
    assert marked == {(1e7, 1.5), (1e8, 1.5)}  # the paper's two rows
    assert table1.derived["root_peak_lock_force"] == {"max": ["hinge0_peak_force.final"]}
    # the paper's own setup: the same study with the cable loop on and BDF, on Table 1's cases
    paper = spec.load(ROOT / "studies" / "table1_paper.toml", fmu=packed("PanelLock"))
    assert paper.fixed["cable_loop"] is True and paper.fixed["integrator"] == "bdf"
    assert {k: v for k, v in paper.fixed.items() if k not in ("cable_loop", "integrator")} == table1.fixed
    pc = cases.generate(paper)
    assert {(x.values["contact_stiffness"], x.values["contact_exponent"]) for x in pc} >= {(1e7, 1.5), (1e8, 1.5), (1e8, 0.9)}
    assert {(x.values["contact_stiffness"], x.values["contact_exponent"]) for x in pc if x.mark} == marked
    assert (paper.outputs, paper.derived, paper.spectrum) == (table1.outputs, table1.derived, table1.spectrum)
    mc = spec.load(ROOT / "studies" / "rope_monte_carlo.toml", fmu=packed("RopeBlock"))
    a, b = cases.generate(mc), cases.generate(mc)
    assert [x.values for x in a] == [x.values for x in b]  # seeded
    assert set(a[0].values) == {"mu", "block_mass", "hoist_speed"}
    assert len({x.id for x in a}) == len(a)


def test_the_readme_install_line_installs_mbstudy_into_a_fresh_environment(tmp_path):
    """The README's `pip install ... ./tools/mbstudy` line, run as written from the repository
    root into a new venv, gives a working `mbstudy` command (issue #44 item 7)."""
    readme = (ROOT / "README.md").read_text()
    lines = [l for l in readme.splitlines() if l.startswith("pip install") and "tools/mbstudy" in l]
    assert len(lines) == 1, lines
    # run in a copy of the files the line names: a non-editable pip install writes build/ into
    # the source folder, which must not land in the checkout
    import shutil
    root = tmp_path / "repo"
    shutil.copytree(ROOT / "tools" / "mbstudy", root / "tools" / "mbstudy",
                    ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    (root / "tests" / "python").mkdir(parents=True)
    shutil.copy(ROOT / "tests" / "python" / "constraints.txt", root / "tests" / "python")
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    args = lines[0].split()
    r = subprocess.run([str(venv / "bin" / "pip"), *args[1:], "-q"], cwd=root, capture_output=True,
                       text=True, timeout=900)
    assert r.returncode == 0, r.stdout + r.stderr
    r = subprocess.run([str(venv / "bin" / "mbstudy"), "--help"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and "mbstudy run STUDY.toml" in r.stdout, r.stdout + r.stderr
