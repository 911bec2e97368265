"""Scene files: every FMU carries its default scene in resources/scene.toml and reads it at
instantiation; an edited copy changes the defaults without recompiling, a broken one is refused
with the file, line and cause logged."""

import math
import shutil
import zipfile

import pytest
from fmpy.fmi2 import FMU2Slave

import fmi2raw
from conftest import ROOT


def edited_copy(fmu, tmp_path, text):
    unzip = tmp_path / "unzip"
    shutil.copytree(fmu.unzip, unzip)
    (unzip / "resources" / "scene.toml").write_text(text)
    return str(unzip)


def a_real_parameter(fmu):
    """A fixed or tunable real parameter with a start value, and a different legal value."""
    for v in fmu.by_causality("parameter"):
        if v.type != "Real" or v.start is None:
            continue
        start = float(v.start)
        new = start * 1.5 if start != 0.0 else 0.5
        lo = float(v.min) if v.min is not None else -math.inf
        hi = float(v.max) if v.max is not None else math.inf
        if lo <= new <= hi and new != start:
            return v, new
    raise AssertionError(f"{fmu.id} has no real parameter with a start value to vary")


def test_packed_scene_is_the_checked_in_default(fmu):
    with zipfile.ZipFile(fmu.path) as z:
        packed = z.read("resources/scene.toml")
    assert packed == (ROOT / "resources" / "scenes" / f"{fmu.id}.toml").read_bytes()


def test_edited_scene_sets_the_defaults_and_survives_reset(fmu, tmp_path):
    var, new = a_real_parameter(fmu)
    text = (ROOT / "resources" / "scenes" / f"{fmu.id}.toml").read_text()
    key = f"{var.name} = "
    lines = [ln for ln in text.splitlines() if not ln.startswith(key) and not ln.startswith(f'"{var.name}" = ')]
    lines.append(f'"{var.name}" = {new!r}')
    unzip = edited_copy(fmu, tmp_path, "\n".join(lines) + "\n")
    s = FMU2Slave(guid=fmu.guid, unzipDirectory=unzip, modelIdentifier=fmu.id, instanceName="edited")
    s.instantiate()

    def value_in_initialization_mode(override=None):
        s.setupExperiment(startTime=0.0)
        if override is not None:
            s.setReal([var.valueReference], [override])
        s.enterInitializationMode()
        return s.getReal([var.valueReference])[0]

    try:
        assert value_in_initialization_mode() == new
        s.reset()
        assert value_in_initialization_mode() == new
        # the importer's own value still wins over the scene's
        s.reset()
        assert value_in_initialization_mode(float(var.start)) == float(var.start)
    finally:
        s.freeInstance()


@pytest.mark.parametrize(
    "text, cause",
    [
        ("[parameters]\nno_such_parameter = 1\n", "has no parameter named `no_such_parameter`"),
        ("[parameters]\nx = nan\n", "refused: values must be finite"),
        ('model = "SomethingElse"\n', "the scene is for model `SomethingElse`"),
        ("[parameters\n", "unclosed table, expected `]`"),
    ],
)
def test_broken_scene_refuses_instantiation_with_the_cause(fmu, tmp_path, text, cause):
    unzip = edited_copy(fmu, tmp_path, text)
    inst = fmi2raw.Instance(fmi2raw.Library(unzip, fmu.id), fmu.guid, name="broken")
    assert not inst.c, "instantiation must fail"
    messages = inst.messages()
    assert any("scene.toml" in m and cause in m for m in messages), messages
