"""mbstudy's designs and statistics (tools/mbstudy/mbstudy/cases.py, analysis.py;
docs/parameter_studies.md "Designs and what a study answers") against independent values:
- Sobol' indices of the Ishigami function (a = 7, b = 0.1) against its analytic S1 and ST;
- Morris mu* of Ishigami against values enumerated by hand on the 4-level grid, and its ranking;
- P90 / P95 of normal samples against the exact quantiles, the most probable maximum of Gumbel
  samples against the Gumbel mode, each inside its bootstrap interval;
- the fraction over an allowance against a hand count and the Wilson interval's closed form;
- the designs: a Latin hypercube has one point per stratum per variable, Sobol' / Saltelli /
  Morris designs have the documented sizes, a non-power of 2 is refused.
No FMU runs here: the rows are computed in the test from the design's own case values."""

import itertools
import math
import pathlib
import sys

import numpy as np
import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "tools" / "mbstudy"))  # this tree's mbstudy, not an installed one
from mbstudy import analysis, cases, spec  # noqa: E402

PI = math.pi
HEAD = """
[study]
name = "{name}"
fmu = "none.fmu"
stop_time = 1.0
step = 1.0
[outputs]
y = ["final"]
"""
ISHIGAMI_VARS = """
[random.vary]
x1 = {{ uniform = [{lo}, {hi}] }}
x2 = {{ uniform = [{lo}, {hi}] }}
x3 = {{ uniform = [{lo}, {hi}] }}
""".format(lo=-PI, hi=PI)


def load(tmp_path, text, name="t"):
    (tmp_path / "none.fmu").write_bytes(b"not an FMU: the case ids hash these bytes")
    path = tmp_path / f"{name}.toml"
    path.write_text(HEAD.format(name=name) + text)
    return spec.load(path)


def ishigami(x1, x2, x3, a=7.0, b=0.1):
    return np.sin(x1) + a * np.sin(x2) ** 2 + b * x3**4 * np.sin(x1)


def rows_of(study, f):
    return [{"status": "done", "case_index": c.index, **c.values, "y": float(f(**c.values))}
            for c in cases.generate(study)]


def by(found, index):
    return {r["variable"]: r for r in found if r["index"] == index}


def test_sobol_indices_of_ishigami_hold_the_analytic_values(tmp_path):
    # Analytic (a = 7, b = 0.1): V = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2,
    # V1 = (1 + b pi^4/5)^2 / 2, V2 = a^2/8, V13 = b^2 pi^8 (1/18 - 1/50), V3 = 0.
    a, b = 7.0, 0.1
    v1, v2, v13 = (1 + b * PI**4 / 5) ** 2 / 2, a**2 / 8, b**2 * PI**8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    exact_s1 = {"x1": v1 / v, "x2": v2 / v, "x3": 0.0}
    exact_st = {"x1": (v1 + v13) / v, "x2": v2 / v, "x3": v13 / v}
    assert [round(exact_s1[k], 4) for k in exact_s1] == [0.3139, 0.4424, 0.0]
    assert [round(exact_st[k], 4) for k in exact_st] == [0.5576, 0.4424, 0.2437]

    study = load(tmp_path, '[random]\ndesign = "saltelli"\nseed = 47\nsamples = 1024\n' + ISHIGAMI_VARS
                 + '[sensitivity]\ncolumns = ["y"]\n')
    rows = rows_of(study, ishigami)
    assert len(rows) == 1024 * (3 + 2)
    found = analysis.sensitivity(study, rows)
    for index, exact in (("S1", exact_s1), ("ST", exact_st)):
        got = by(found, index)
        for name, value in exact.items():
            r = got[name]
            assert r["low"] <= value <= r["high"], (index, name, r, value)
            assert r["conf"] < 0.1  # an interval that says something (N = 1024)
    # and one failed case: no indices, a message
    rows[5]["status"] = "failed"
    broken = analysis.sensitivity(study, rows)
    assert all(math.isnan(r["value"]) for r in broken) and "1 of 5120" in broken[0]["message"]


def test_morris_mu_star_of_ishigami_against_the_grid_by_hand(tmp_path):
    study = load(tmp_path, '[random]\ndesign = "morris"\nseed = 47\nsamples = 200\nlevels = 4\n'
                 + ISHIGAMI_VARS + '[sensitivity]\ncolumns = ["y"]\n')
    rows = rows_of(study, ishigami)
    assert len(rows) == 200 * (3 + 1)
    mu_star = by(analysis.sensitivity(study, rows), "mu_star")
    # x2's elementary effect is the same at every grid point: the step of 2/3 of the range takes
    # x2 from -pi to pi/3 or from -pi/3 to pi, 7 sin^2 from 0 to 0.75 or back: |EE| = 5.25 / (2/3)
    assert mu_star["x2"]["value"] == pytest.approx(7.875, abs=1e-9)
    # x3's mean |EE| over the 4-level grid (other variables uniform on their levels), enumerated
    levels = np.array([0.0, 1 / 3, 2 / 3, 1.0])
    phys = lambda u: -PI + 2 * PI * u  # noqa: E731
    effects = []
    for lo in (0.0, 1 / 3):
        for x1, x2 in itertools.product(levels, repeat=2):
            effects.append(abs(ishigami(phys(x1), phys(x2), phys(lo + 2 / 3))
                               - ishigami(phys(x1), phys(x2), phys(lo))) / (2 / 3))
    r3 = mu_star["x3"]
    assert r3["low"] <= np.mean(effects) <= r3["high"], (r3, np.mean(effects))
    # ranking: x3 (an interaction only) has the smallest mu*, x1 and x2 the two largest
    assert min(mu_star, key=lambda k: mu_star[k]["value"]) == "x3"


def test_quantiles_and_most_probable_maximum_inside_their_bootstrap_intervals(tmp_path):
    study = load(tmp_path, '[extremes]\ncolumns = ["normal", "gumbel"]\nquantiles = [0.9, 0.95]\n'
                 'resamples = 999\nseed = 3\n')
    rng = np.random.default_rng(11)
    normal = rng.normal(1.1, 0.02, 1000)
    gumbel = rng.gumbel(1.08, 0.015, 1000)
    rows = [{"status": "done", "normal": float(x), "gumbel": float(g)} for x, g in zip(normal, gumbel)]
    rows.append({"status": "failed", "normal": None, "gumbel": None})  # left out
    found = {(r["column"], r["statistic"]): r for r in analysis.extremes(study, rows)}
    # exact quantiles of N(1.1, 0.02): 1.1 + 0.02 z, z(0.90) = 1.2815516, z(0.95) = 1.6448536
    for label, z in (("P90", 1.2815515655446004), ("P95", 1.6448536269514722)):
        r = found[("normal", label)]
        assert r["n"] == 1000
        assert r["low"] <= 1.1 + 0.02 * z <= r["high"], r
        q = {"P90": 0.9, "P95": 0.95}[label]
        assert r["value"] == np.sort(normal)[math.ceil(q * 1000) - 1]  # the 900th / 950th of 1000
    # the mode of a Gumbel(loc, scale) is loc
    r = found[("gumbel", "MPM")]
    assert r["low"] <= 1.08 <= r["high"] and r["high"] - r["low"] < 0.01, r


def test_a_time_that_never_came_is_the_largest_value(tmp_path):
    study = load(tmp_path, '[extremes]\ncolumns = ["t"]\nquantiles = [0.5, 0.9]\nresamples = 99\n'
                 "[allowances]\nt = 45.0\n")
    # 20 cases: 17 deployed at 1..17 s, 3 never (+inf): P50 is the 10th value, P90 the 18th (inf)
    rows = [{"status": "done", "t": float(v)} for v in range(1, 18)] + [{"status": "done", "t": math.inf}] * 3
    found = {r["statistic"]: r for r in analysis.extremes(study, rows)}
    assert found["P50"]["value"] == 10.0 and found["P50"]["n"] == 20
    assert found["P90"]["value"] == math.inf and found["P90"]["high"] == math.inf
    assert math.isnan(found["MPM"]["value"])  # no Gumbel fit to infinite values
    (al,) = analysis.allowances(study, rows)
    assert (al["count"], al["n"]) == (3, 20)


def test_fraction_over_allowance_against_a_hand_count(tmp_path):
    study = load(tmp_path, "[allowances]\ny = 1.05  # user-given\nz = { below = 1.04 }\n")
    values = [1.00, 1.04, 1.05, 1.06, 1.20]  # 1.05 itself is not over: 2 of 5; below 1.04: 1
    rows = [{"status": "done", "y": v, "z": v} for v in values] + [{"status": "failed", "y": None, "z": None}]
    r, below = analysis.allowances(study, rows)
    assert (r["side"], r["count"], r["n"], r["fraction"]) == ("over", 2, 5, 0.4)
    assert (below["side"], below["count"], below["n"], below["fraction"]) == ("below", 1, 5, 0.2)
    # Wilson score interval, closed form, z of the 95 % two-sided level
    z, k, n = 1.959963984540054, 2, 5
    centre, half = (k + z * z / 2) / (n + z * z), z / (n + z * z) * math.sqrt(k * (n - k) / n + z * z / 4)
    assert (r["low"], r["high"]) == pytest.approx((centre - half, centre + half), rel=1e-12)


def test_latin_hypercube_has_one_point_per_stratum(tmp_path):
    n = 37
    study = load(tmp_path, f'[random]\ndesign = "lhs"\nseed = 5\nsamples = {n}\n[random.vary]\n'
                 'a = { uniform = [2.0, 4.0] }\nb = { loguniform = [1e-3, 1e3] }\nc = { uniform = [-1.0, 0.0] }\n')
    values = [c.values for c in cases.generate(study)]
    assert len(values) == n
    strata = {
        "a": [math.floor((v["a"] - 2.0) / 2.0 * n) for v in values],
        "b": [math.floor((math.log10(v["b"]) + 3) / 6 * n + 1e-9) for v in values],
        "c": [math.floor((v["c"] + 1.0) * n) for v in values],
    }
    for name, s in strata.items():
        assert sorted(s) == list(range(n)), name
    again = [c.values for c in cases.generate(study)]
    assert again == values  # seeded


@pytest.mark.parametrize("design,samples,extra,size", [
    ("sobol", 64, "", 64),
    ("saltelli", 64, "", 64 * (3 + 2)),
    ("saltelli", 64, "second_order = true\n", 64 * (2 * 3 + 2)),
    ("morris", 10, "levels = 6\n", 10 * (3 + 1)),
])
def test_design_sizes(tmp_path, design, samples, extra, size):
    study = load(tmp_path, f'[random]\ndesign = "{design}"\nseed = 1\nsamples = {samples}\n{extra}'
                 + ISHIGAMI_VARS)
    values = np.array([[c.values[k] for k in ("x1", "x2", "x3")] for c in cases.generate(study)])
    assert values.shape == (size, 3)
    assert (values >= -PI).all() and (values <= PI).all()
    if design == "morris":  # on the 6-level grid
        u = (values + PI) / (2 * PI) * 5
        assert np.allclose(u, np.round(u), atol=1e-9)


def test_refusals(tmp_path):
    with pytest.raises(ValueError, match="power of 2"):
        load(tmp_path, '[random]\ndesign = "sobol"\nseed = 1\nsamples = 50\n' + ISHIGAMI_VARS)
    with pytest.raises(ValueError, match="saltelli"):
        load(tmp_path, '[random]\ndesign = "lhs"\nseed = 1\nsamples = 50\n' + ISHIGAMI_VARS
             + '[sensitivity]\ncolumns = ["y"]\n')
    with pytest.raises(ValueError, match="uniform or loguniform"):
        load(tmp_path, '[random]\ndesign = "morris"\nseed = 1\nsamples = 4\n[random.vary]\n'
             'x = { normal = [0.0, 1.0] }\n')
    with pytest.raises(ValueError, match=r"unknown keys \['quantile'\]"):
        load(tmp_path, '[extremes]\ncolumns = ["y"]\nquantile = [0.9]\n')
    with pytest.raises(ValueError, match="design"):
        load(tmp_path, '[random]\ndesign = "halton"\nseed = 1\nsamples = 4\n' + ISHIGAMI_VARS)


def test_shipped_studies(tmp_path):
    """studies/lift_signoff.toml and studies/deployment_margin.toml read, with the designs and
    allowances docs/parameter_studies.md describes (their runs are in that file)."""
    from scipy.stats import norm

    fmu = ROOT / "dist" / "RopeBlock.fmu"
    if not fmu.exists():  # the case ids hash the FMU: any FMU file will do for reading a study
        from conftest import packed

        fmu = packed("RopeBlock")
    lift = spec.load(ROOT / "studies" / "lift_signoff.toml", fmu=fmu)
    cs = cases.generate(lift)
    assert len(cs) == 3 * 3 * 5
    assert {(c.values["cog_x"], c.values["cog_y"]) for c in cs} == set(itertools.product([-1.0, 0.0, 1.0],
                                                                                         [-0.5, 0.0, 0.5]))
    assert "cog = [$cog_x, $cog_y, 3.5]" in lift.scene
    assert lift.allowances == {"daf.peak": {"over": 1.05}, "skew": {"over": 1.25}, "utilisation": {"over": 0.5}}

    dep = spec.load(ROOT / "studies" / "deployment_margin.toml", fmu=fmu)
    values = [c.values for c in cases.generate(dep)]
    assert len(values) == 48
    n = 48  # one point per stratum: uniform friction and the two normal preloads (through their CDF)
    assert sorted(math.floor((v["hinge_friction_torque"] - 0.05) / 0.45 * n) for v in values) == list(range(n))
    assert sorted(math.floor(norm.cdf(v["root_spring_preload"], 0.6, 0.03) * n) for v in values) == list(range(n))
    assert sorted(math.floor(norm.cdf(v["panel_spring_preload"], 0.4, 0.02) * n) for v in values) == list(range(n))
    assert dep.allowances["all_latched"] == {"below": 1.0} and dep.allowances["deploy_time"] == {"over": 45.0}
