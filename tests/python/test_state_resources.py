"""FMU states and the files in the resources folder (issue #25 items 3-5): a RopeBlock state naming
a relative user mesh restores in a fresh instance (it was refused: "mesh_file `box.obj` is
relative, but no FMU resources folder is known"); a state refuses to restore with a changed mesh;
fmi2Reset returns to the scene.toml read at instantiation."""

import pathlib
import shutil

import pytest
from conftest import Fmu, bits, packed
from fmpy import extract

# A plain 18 m x 12 m x 7 m box in the block's design frame (x along the length, centred; z up
# from the bottom): the default lift's lugs and slings fit it.
BOX_OBJ = """\
v -9 -6 0
v 9 -6 0
v 9 6 0
v -9 6 0
v -9 -6 7
v 9 -6 7
v 9 6 7
v -9 6 7
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
"""


@pytest.fixture
def rope_block_with_mesh(tmp_path):
    path = packed("RopeBlock")
    unzip = extract(str(path), unzipdir=str(tmp_path / "fmu"))
    (tmp_path / "fmu" / "resources" / "box.obj").write_text(BOX_OBJ)
    yield Fmu(path, unzip)
    shutil.rmtree(tmp_path / "fmu", ignore_errors=True)


def _outputs(fmu, s):
    vrs = [v.valueReference for v in fmu.real_outputs]
    return [bits(x) for x in s.getReal(vrs)]


def test_a_state_naming_a_relative_mesh_restores_in_a_fresh_instance(rope_block_with_mesh):
    fmu = rope_block_with_mesh
    values = {"mesh_file": "box.obj", "segments": 8}
    a = fmu.slave("a")
    fmu.start(a, values)
    contacts = a.getInteger([fmu.vars["contact_count"].valueReference])[0]
    assert contacts > 0, "the slings must touch the user mesh"
    h = 0.05
    for k in range(4):
        a.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
    data = a.serializeFMUstate(a.getFMUstate())
    a.doStep(currentCommunicationPoint=4 * h, communicationStepSize=h)
    expected = _outputs(fmu, a)
    b = fmu.slave("b")
    b.setFMUstate(b.deSerializeFMUstate(data))
    b.doStep(currentCommunicationPoint=4 * h, communicationStepSize=h)
    assert _outputs(fmu, b) == expected
    for s in (a, b):
        s.terminate()
        s.freeInstance()


def test_reset_returns_to_the_scene_file_read_at_instantiation(tmp_path):
    """Issue #25 item 4, decided: fmi2Reset returns to the state after instantiation, so it
    applies the scene.toml values read then, not a file changed on disk since."""
    path = packed("PanelLock")
    unzip = extract(str(path), unzipdir=str(tmp_path / "fmu"))
    scene = tmp_path / "fmu" / "resources" / "scene.toml"
    text = scene.read_text()
    assert "n_panels = 3" in text
    fmu = Fmu(path, unzip)
    vr = fmu.vars["n_panels"].valueReference

    def n_panels_at_initialization(slave):
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        n = slave.getInteger([vr])[0]
        slave.exitInitializationMode()
        return n

    scene.write_text(text.replace("n_panels = 3", "n_panels = 4"))
    s = fmu.slave("s")
    scene.write_text(text.replace("n_panels = 3", "n_panels = 2"))
    assert n_panels_at_initialization(s) == 4, "read at instantiation"
    s.reset()
    assert n_panels_at_initialization(s) == 4, "reset applies the file as read at instantiation"
    s.reset()
    s.setInteger([vr], [5])
    assert n_panels_at_initialization(s) == 5, "fmi2SetInteger still wins over the file"
    s.terminate()
    s.freeInstance()
    t = fmu.slave("t")
    assert n_panels_at_initialization(t) == 2, "a new instance reads the changed file"
    t.terminate()
    t.freeInstance()


def test_a_state_refuses_to_restore_with_a_changed_mesh(rope_block_with_mesh, tmp_path):
    """Issue #25 item 5: a mesh changed on disk under a serialized state made the restored run
    fail in its next step (energy growth); the state now carries the mesh file's digest and is
    refused with the file named."""
    import fmi2raw

    fmu = rope_block_with_mesh
    a = fmu.slave("a")
    fmu.start(a, {"mesh_file": "box.obj", "segments": 8})
    a.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.05)
    data = bytes(a.serializeFMUstate(a.getFMUstate()))
    mesh = pathlib.Path(fmu.unzip) / "resources" / "box.obj"
    mesh.write_text(BOX_OBJ.replace("-9 ", "-8 ").replace("9 ", "8 "))
    raw = fmi2raw.Instance(fmi2raw.Library(fmu.unzip, fmu.id), fmu.guid, logging_on=True)
    status, _ = raw.deserialize(data)
    assert status == fmi2raw.ERROR
    text = " ".join(raw.messages())
    assert "mesh_file" in text and "changed since this state was taken" in text, text
    raw.free()
    mesh.write_text(BOX_OBJ)
    again = fmi2raw.Instance(fmi2raw.Library(fmu.unzip, fmu.id), fmu.guid)
    status, _ = again.deserialize(data)
    assert status == fmi2raw.OK, "the same mesh restores"
    again.free()
    a.terminate()
    a.freeInstance()
