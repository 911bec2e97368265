"""PanelLock's array described as data (issue #21) through fmpy: the example scene with its own
per-hinge lock angles runs in the FMU and each hinge latches at the angle its [[hinge]] table
gives; a bad table refuses fmi2Instantiate with the file and line logged; a state taken with one
array's tables does not restore into an FMU made with other tables."""

import tomllib

import pytest
from fmpy import extract, read_model_description, simulate_fmu

import fmi2raw
from conftest import ROOT, Fmu, packed

EXAMPLE = ROOT / "examples" / "scenes" / "panel_lock_array.toml"


def unzipped_with(tmp_path, text, name="unzip"):
    fmu = packed("PanelLock")
    unzip = extract(str(fmu), unzipdir=str(tmp_path / name))
    (tmp_path / name / "resources" / "scene.toml").write_text(text)
    return unzip


def test_the_example_array_latches_each_hinge_at_its_own_angle(tmp_path):
    text = EXAMPLE.read_text()
    locks = [h["lock_angle"] for h in tomllib.loads(text)["hinge"]]
    res = simulate_fmu(unzipped_with(tmp_path, text), stop_time=60.0, output_interval=0.1)
    last = res["time"] >= 40.0
    for k, lock in enumerate(locks):
        assert res[f"hinge{k}_lock_time"][-1] > 0.0, f"hinge {k} did not lock"
        # the locked pins rattle in the grooves' play (+-0.05 rad); over the last 20 s the mean
        # angle is within 0.04 rad of the hinge's own lock angle
        mean = res[f"hinge{k}_angle"][last].mean()
        assert mean == pytest.approx(lock, abs=0.04), k


@pytest.mark.parametrize(
    "edit, cause",
    [
        (("lock_angle = 3.05 ", "lock_angle = 3.5 "),
         "[[hinge]] 1 (line 17): `lock_angle` = 3.5 [rad] is outside the range of panel_lock_angle"),
        (("mass = 5.0 ", "mass = -5.0 "), "`mass` must be finite and > 0 [kg], got -5"),
        (("damping = 0.03 ", "dampening = 0.03 "), "scene.toml:19: [[hinge]] 1 has no key `dampening`"),
        (("n_panels = 3", "n_panels = 2"), "too many [[hinge]] tables (4): the array has 3 hinges"),
    ],
)
def test_a_bad_table_refuses_instantiation_with_its_line(tmp_path, edit, cause):
    text = EXAMPLE.read_text()
    assert edit[0] in text
    unzip = unzipped_with(tmp_path, text.replace(edit[0], edit[1], 1))
    md = read_model_description(str(packed("PanelLock")))
    inst = fmi2raw.Instance(fmi2raw.Library(unzip, "PanelLock"), md.guid, name="bad_array")
    assert not inst.c, "instantiation must fail"
    messages = inst.messages()
    assert any("scene.toml" in m and cause in m for m in messages), messages


def test_a_state_does_not_restore_into_an_fmu_with_other_tables(tmp_path):
    text = EXAMPLE.read_text()
    path = packed("PanelLock")
    a_fmu = Fmu(path, unzipped_with(tmp_path, text, "a"))
    a = a_fmu.slave("a")
    a_fmu.start(a, {})
    a.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.1)
    data = bytes(a.serializeFMUstate(a.getFMUstate()))
    other = unzipped_with(tmp_path, text.replace("mass = 5.0 ", "mass = 6.0 ", 1), "b")
    raw = fmi2raw.Instance(fmi2raw.Library(other, "PanelLock"), a_fmu.guid, logging_on=True)
    status, _ = raw.deserialize(data)
    assert status == fmi2raw.ERROR
    text_out = " ".join(raw.messages())
    assert "other per-hinge or per-panel values" in text_out, text_out
    raw.free()
    same = fmi2raw.Instance(fmi2raw.Library(a_fmu.unzip, "PanelLock"), a_fmu.guid, logging_on=True)
    status, _ = same.deserialize(data)
    assert status == fmi2raw.OK, same.messages()
    same.free()
    a.terminate()
    a.freeInstance()
