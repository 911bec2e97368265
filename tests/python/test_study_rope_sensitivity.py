"""A RopeBlock Sobol' study through the `mbstudy run` command (docs/parameter_studies.md,
"Designs and what a study answers"): hoist speed, edge friction and block mass over a Saltelli
design of 8 x (3 + 2) = 40 short lifts (2 s, 20 segments per sling, hoisting from 0.5 s).
The hoist speed must have the largest total index of the peak `daf` (the Monte Carlo study of
docs/parameter_studies.md found the DAF set by the hoist speed alone: correlation 0.99998), and
the command must write the sensitivity, extremes and allowance tables and plots."""

import os
import subprocess
import sys

import pyarrow.parquet as pq
from conftest import ROOT, packed

STUDY = """
[study]
name = "rope_sobol"
fmu = "{fmu}"
stop_time = 2.0
step = 0.05

[fixed]
segments = 20

[random]
design = "saltelli"
seed = 47
samples = 8
[random.vary]
hoist_speed = {{ uniform = [0.05, 0.5] }}
mu = {{ uniform = [0.05, 0.4] }}
block_mass = {{ uniform = [1.0e5, 3.0e5] }}

[inputs]
hook0_vz = [[0.0, 0.0], [0.5, "hoist_speed"]]

[outputs]
daf = ["initial", "peak"]

[sensitivity]
columns = ["daf.peak"]
resamples = 200

[extremes]
columns = ["daf.peak"]
resamples = 200

[allowances]
"daf.peak" = 1.05  # user-given (a test value)

[[plot]]
kind = "sensitivity"
file = "sensitivity.svg"
column = "daf.peak"

[[plot]]
kind = "histogram"
file = "daf.svg"
column = "daf.peak"
"""


def test_hoist_speed_dominates_the_daf(tmp_path):
    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(fmu=packed("RopeBlock")))
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "tools" / "mbstudy")}
    run = subprocess.run([sys.executable, "-m", "mbstudy.cli", "run", str(path), "--serial", "--no-progress",
                          "--out", str(out)], env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    rows = pq.read_table(out / "results.parquet").to_pylist()
    assert len(rows) == 40 and all(r["status"] == "done" for r in rows)
    assert all(abs(r["daf.initial"] - 1.0) < 0.01 for r in rows)  # hanging at rest at 0 s

    sa = pq.read_table(out / "sensitivity.parquet").to_pylist()
    st = {r["variable"]: r for r in sa if r["index"] == "ST"}
    assert set(st) == {"hoist_speed", "mu", "block_mass"}
    ranked = sorted(st, key=lambda k: -st[k]["value"])
    assert ranked[0] == "hoist_speed", st
    # and by a margin the interval can tell: its lower end above the others' upper ends
    assert all(st["hoist_speed"]["low"] > st[k]["high"] for k in ("mu", "block_mass")), st

    ex = {r["statistic"]: r for r in pq.read_table(out / "extremes.parquet").to_pylist()}
    daf = sorted(r["daf.peak"] for r in rows)
    assert ex["P95"]["low"] <= ex["P95"]["value"] <= ex["P95"]["high"] <= daf[-1]
    (al,) = pq.read_table(out / "allowances.parquet").to_pylist()
    assert (al["side"], al["count"], al["n"]) == ("over", sum(d > 1.05 for d in daf), 40)
    assert 0 < al["count"] < 40  # the range of hoist speeds straddles the allowance
    for name in ("sensitivity.svg", "daf.svg", "sensitivity.csv", "extremes.csv", "allowances.csv"):
        assert (out / name).stat().st_size > 0, name
    assert "ST(hoist_speed)" in run.stdout
