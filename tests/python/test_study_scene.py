"""mbstudy's scene templates (docs/parameter_studies.md, "Scene templates"): each case runs the
FMU with resources/scene.toml replaced by the study's template, the case's values put in. Here
the centre of gravity of studies/lift_signoff_scene.toml moves over part of its envelope
(6 short lifts: 2 s, 20 segments per sling, hoisting from 0.5 s):
- a case equals `mbcosim simulate RopeBlock --scene <the template filled in by hand>` (the native
  command, another way into the same scene) in every figure, to 1e-9;
- mirror symmetry of the rig: the centre of gravity at (x, y) and at (-x, -y) give the same sling
  loads with the slings swapped diagonally (0 <-> 2, 1 <-> 3);
- the slings on the side the centre of gravity moved to carry more;
- the shared unzipped FMU is left as it was (the per-case copy's scene is a new file, not
  written through the hard link; the binaries are links, not copies);
- a template naming a variable the study does not vary is refused when the study is read."""

import os
import subprocess
import sys

import numpy as np
import pyarrow.parquet as pq
import pytest
from conftest import ROOT, native_table, packed

sys.path.insert(0, str(ROOT / "tools" / "mbstudy"))  # this tree's mbstudy, not an installed one
from mbstudy import spec  # noqa: E402

TEMPLATE = ROOT / "studies" / "lift_signoff_scene.toml"
SLINGS = [f"sling{i}_utilisation" for i in range(4)]
STUDY = """
[study]
name = "scene_test"
fmu = "{fmu}"
scene = "{scene}"
stop_time = 2.0
step = 0.05

[fixed]
segments = 20

[grid]
cog_x = [-1.0, 0.0, 1.0]
cog_y = [-0.5, 0.5]

[inputs]
hook0_vz = [[0.0, 0.0], [0.5, 0.3]]

[outputs]
daf = ["initial", "peak", "final"]
{slings}
"""


def test_scene_template_moves_the_centre_of_gravity(tmp_path):
    path = tmp_path / "study.toml"
    slings = "\n".join(f'{s} = ["initial", "peak", "final"]' for s in SLINGS)
    path.write_text(STUDY.format(fmu=packed("RopeBlock"), scene=TEMPLATE, slings=slings))
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "tools" / "mbstudy")}
    run = subprocess.run([sys.executable, "-m", "mbstudy.cli", "run", str(path), "--serial", "--no-progress",
                          "--out", str(out)], env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    rows = {(r["cog_x"], r["cog_y"]): r for r in pq.read_table(out / "results.parquet").to_pylist()}
    assert len(rows) == 6 and all(r["status"] == "done" for r in rows.values()), rows

    # against the native command on the template filled in by hand
    scene = tmp_path / "scene.toml"
    scene.write_text(TEMPLATE.read_text().replace("$cog_x", "1.0").replace("$cog_y", "0.5"))
    inputs = tmp_path / "inputs.csv"
    inputs.write_text("time,hook0_vz\n0,0\n0.5,0.3\n")
    ref = native_table("simulate", "RopeBlock", "--scene", scene, "--set", "segments=20", "--stop", 2.0,
                       "--step", 0.05, "--inputs", inputs, "--outputs", ",".join(["daf"] + SLINGS))
    ours = rows[(1.0, 0.5)]
    for name in ["daf"] + SLINGS:
        assert ours[f"{name}.initial"] == pytest.approx(ref[name][0], rel=1e-9), name
        assert ours[f"{name}.final"] == pytest.approx(ref[name][-1], rel=1e-9), name
        assert ours[f"{name}.peak"] == pytest.approx(np.max(ref[name]), rel=1e-9), name

    # mirror symmetry: (x, y) and (-x, -y) swap slings 0 <-> 2 and 1 <-> 3
    for x, y in ((1.0, 0.5), (0.0, 0.5), (1.0, -0.5)):
        a, b = rows[(x, y)], rows[(-x, -y)]
        for i in range(4):
            for fig in ("initial", "peak"):
                assert a[f"{SLINGS[i]}.{fig}"] == pytest.approx(b[f"{SLINGS[(i + 2) % 4]}.{fig}"], rel=1e-6)
    # lugs 0 (+x, +y), 1 (-x, +y), 2 (-x, -y), 3 (+x, -y): centre of gravity at (+1, +0.5)
    u = [ours[f"{s}.initial"] for s in SLINGS]
    assert u[0] == max(u) and u[2] == min(u) and u[3] > u[1], u



def test_case_directory_leaves_the_shared_copy_alone():
    from mbstudy import fmu_run

    base, _ = fmu_run.unzipped(packed("RopeBlock").read_bytes())
    scene = os.path.join(base, "resources", "scene.toml")
    before = open(scene).read()
    case_dir = fmu_run._case_directory(base, TEMPLATE.read_text(), {"cog_x": 1.0, "cog_y": -0.5})
    try:
        assert "cog = [1.0, -0.5, 3.5]" in open(os.path.join(case_dir, "resources", "scene.toml")).read()
        assert open(scene).read() == before  # the hard-linked scene was replaced, not written through
        binaries = [os.path.join(r, f) for r, _, fs in os.walk(os.path.join(base, "binaries")) for f in fs]
        assert binaries and all(os.stat(b).st_nlink >= 2 for b in binaries)  # shared, not copied
    finally:
        import shutil

        shutil.rmtree(case_dir)
    assert open(scene).read() == before


def test_scene_template_names_only_varied_variables(tmp_path):
    path = tmp_path / "study.toml"
    slings = "\n".join(f'{s} = ["peak"]' for s in SLINGS)
    path.write_text(STUDY.format(fmu=packed("RopeBlock"), scene=TEMPLATE, slings=slings)
                    .replace("cog_y = [-0.5, 0.5]\n", ""))
    with pytest.raises(ValueError, match=r"\['cog_y'\], which are not"):
        spec.load(path)
    bad = tmp_path / "bad_scene.toml"
    bad.write_text(TEMPLATE.read_text() + "# costs $ 5\n")
    path.write_text(STUDY.format(fmu=packed("RopeBlock"), scene=bad, slings=slings))
    with pytest.raises(ValueError, match="not a placeholder"):
        spec.load(path)
