"""RopeBlock rigs described in the FMU's scene file (issue #21): a user mesh and its rig in
resources/ run through fmpy with their contact nodes and outputs; a bad rig refuses
fmi2Instantiate with its named error logged."""

import shutil

import pytest
from fmpy import extract, simulate_fmu

import fmi2raw
from conftest import ROOT, packed

SCENES = ROOT / "examples" / "scenes"


def unzipped_with(tmp_path, text, files=()):
    fmu = packed("RopeBlock")
    unzip = extract(str(fmu), unzipdir=str(tmp_path / "unzip"))
    res = tmp_path / "unzip" / "resources"
    for f in files:
        shutil.copy(SCENES / f, res / f)
    (res / "scene.toml").write_text(text)
    return unzip


def test_user_mesh_rig_runs_with_its_contact_nodes(tmp_path):
    text = (SCENES / "four_point_mesh.toml").read_text().replace("segments = 60", "segments = 20")
    unzip = unzipped_with(tmp_path, text, ["block_20x14x8.obj"])
    res = simulate_fmu(unzip, stop_time=1.0, output_interval=0.1,
                       start_values={"hook0_vz": 0.1})
    assert res["contact_count"][0] == 4
    assert res["daf"][0] == pytest.approx(1.0, abs=1e-6)
    for r, mbl in enumerate([2.5e6] * 4):
        # utilisation = highest segment tension / breaking load; the highest is at the hook end
        assert res[f"sling{r}_utilisation"][0] == pytest.approx(
            res[f"sling{r}_tension_hook"][0] / mbl, rel=1e-3)
    # centre of gravity 1.2 m towards +x: the +x slings (0, 3) carry more
    assert res["sling0_tension_hook"][0] > 1.2 * res["sling1_tension_hook"][0]


@pytest.mark.parametrize(
    "edit, cause",
    [
        (("position = [7.5, 7.3, 7.0]", "position = [7.5, 9.3, 7.0]"), "lug_off_block: lug 0"),
        (("length = 22.205                # unstretched [m] (just taut over the deck edge)",
          "length = 15.0"), "sling_too_short: sling 0"),
        (("hook = 0\nlength = 23.001", "hook = 3\nlength = 23.001"), "sling 1: hook 3 does not exist"),
    ],
)
def test_bad_rig_refuses_instantiation_with_its_named_error(tmp_path, edit, cause):
    text = (SCENES / "four_point_mesh.toml").read_text()
    assert edit[0] in text
    unzip = unzipped_with(tmp_path, text.replace(edit[0], edit[1], 1), ["block_20x14x8.obj"])
    fmu = packed("RopeBlock")
    from fmpy import read_model_description
    md = read_model_description(str(fmu))
    inst = fmi2raw.Instance(fmi2raw.Library(unzip, "RopeBlock"), md.guid, name="bad_rig")
    assert not inst.c, "instantiation must fail"
    messages = inst.messages()
    assert any("scene.toml" in m and cause in m for m in messages), messages
