"""The figures docs/parameter_studies.md and README.md quote from the shipped studies of issue
#47 item 4 are what mbstudy's analysis gives on the committed results
(docs/parameter_studies/<study>_results.csv): the sensitivity, extremes and allowance tables
are recomputed from those rows and compared with the committed tables and the quoted numbers.
(The runs themselves are minutes of FMU time; the FMU side of the same statistics is tested at
CI size by test_study_rope_sensitivity.py and test_study_scene.py.)"""

import csv
import math
import sys

import pyarrow.csv as pacsv
import pytest
from conftest import ROOT, packed

sys.path.insert(0, str(ROOT / "tools" / "mbstudy"))  # this tree's mbstudy, not an installed one
from mbstudy import analysis, spec  # noqa: E402

DOCS = ROOT / "docs" / "parameter_studies"


def recomputed(name, model):
    study = spec.load(ROOT / "studies" / f"{name}.toml", fmu=packed(model))
    return analysis.analyse(study, pacsv.read_csv(DOCS / f"{name}_results.csv"))


def committed(name, table):
    with open(DOCS / f"{name}_{table}.csv", newline="") as f:
        return list(csv.DictReader(f))


def same(ours, theirs):
    assert len(ours) == len(theirs)
    for a, b in zip(ours, theirs):
        for k, v in a.items():
            if isinstance(v, float):
                assert float(b[k]) == pytest.approx(v, rel=1e-12, nan_ok=True) or (math.isinf(v) and float(b[k]) == v), k
            else:
                assert str(v) == b[k], k


@pytest.mark.parametrize("name,model,tables", [
    ("lift_signoff", "RopeBlock", ("extremes", "allowances")),
    ("deployment_margin", "PanelLock", ("extremes", "allowances")),
    ("rope_sobol", "RopeBlock", ("sensitivity",)),
])
def test_committed_tables_are_the_analysis_of_the_committed_rows(name, model, tables):
    found = recomputed(name, model)
    for t in tables:
        same(found[t], committed(name, t))


def test_quoted_figures():
    docs = (ROOT / "docs" / "parameter_studies.md").read_text()
    readme = (ROOT / "README.md").read_text()
    sobol = {(r["variable"], r["index"]): r for r in recomputed("rope_sobol", "RopeBlock")["sensitivity"]}
    st = sobol[("hoist_speed", "ST")]
    assert f"{st['value']:.2f} +- {st['conf']:.2f}" == "1.00 +- 0.24" and "1.00 +- 0.24" in readme
    assert f"hoist speed\n{st['value']:.3f} +- {st['conf']:.3f}" in docs
    assert all(sobol[(v, "ST")]["high"] < 1e-4 for v in ("mu", "block_mass"))  # README: below 1e-4

    lift = recomputed("lift_signoff", "RopeBlock")
    al = {r["column"]: r for r in lift["allowances"]}
    assert (al["daf.peak"]["count"], al["daf.peak"]["n"]) == (36, 45) and "36 of 45 cases over DAF 1.05" in docs
    assert (al["skew"]["count"], al["utilisation"]["count"]) == (0, 0)
    ex = {(r["column"], r["statistic"]): r for r in lift["extremes"]}
    p95 = ex[("daf.peak", "P95")]
    assert f"DAF 1.2009 [{p95['low']:.4f}, {p95['high']:.4f}]" in docs.replace("\n", " ")

    dep = recomputed("deployment_margin", "PanelLock")
    al = {r["column"]: r for r in dep["allowances"]}
    assert (al["all_latched"]["count"], al["deploy_time"]["count"], al["torque_ratio"]["count"]) == (8, 14, 32)
    ex = {(r["column"], r["statistic"]): r for r in dep["extremes"]}
    assert ex[("deploy_time", "P90")]["value"] == math.inf
    for q in ("P90", "P95"):
        f = ex[("peak_lock_force", q)]
        assert f"{q} = {f['value']:.0f} N [{f['low']:.0f}, {f['high']:.0f}]" in docs.replace("\n", " "), f
