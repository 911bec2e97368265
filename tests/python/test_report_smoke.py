"""Smoke run of the FMU timing part of the work-precision report (benches/fmu_overhead.py
--quick): it runs every packed FMU through fmpy and natively and writes its table. Timings are
reported, never asserted."""

import csv
import os
import subprocess
import sys

from conftest import DIST, ROOT, fmu_paths


def test_fmu_overhead_script_quick(tmp_path):
    binary = os.environ.get("MBCOSIM_BIN", str(ROOT / "target" / "release" / "mbcosim"))
    subprocess.run([sys.executable, str(ROOT / "benches" / "fmu_overhead.py"), str(DIST), binary,
                    str(tmp_path), "--quick"], check=True, timeout=600)
    rows = list(csv.DictReader(open(tmp_path / "fmu_overhead.csv")))
    assert {r["model"] for r in rows} == {p.stem for p in fmu_paths()}
    for r in rows:
        assert float(r["fmpy_wall_s"]) > 0.0 and float(r["native_wall_s"]) > 0.0
        assert int(r["steps"]) == round(float(r["stop_s"]) / float(r["step_s"]))
    assert "| model |" in (tmp_path / "fmu_overhead.md").read_text()
