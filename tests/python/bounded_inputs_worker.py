"""One bounded-input case of issue #48 (item 3) against one unpacked RopeBlock FMU, in a fresh
interpreter.

usage: bounded_inputs_worker.py <unzip-dir> <case>

The case writes a resources folder whose `scene.toml` (or the `mesh_file` it names) is a hostile
input: a FIFO, a device, a folder, a symbolic-link loop, a file past a size cap, a scene with
too many tables or keys. The worker then instantiates (FMI 2.0, logging on) and prints one JSON
line: where the input was refused (at instantiation, or at initialization, which builds what
instantiation let through), the Error messages, and the CPU time (user + system, from
resource.getrusage of this process) spent in those calls. The test
(test_bounded_inputs.py) runs every case in its own process with a wall-clock timeout, because
the code before issue #48 blocked on a FIFO forever.
"""

import json
import os
import pathlib
import resource
import shutil
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import adversarial_files as H  # noqa: E402 - the harness's makers of hostile files
import fmi2raw as R2  # noqa: E402
from fmpy import read_model_description  # noqa: E402

# A valid rig on a 20 x 14 x 8 m box (docs/rope_block_rig.md): four lugs, one hook.
BLOCK = '[block]\nbox = [20.0, 14.0, 8.0]\nmass = 250e3\n'
LUGS = [(7.0, 7.3, 7.0), (-7.0, 7.3, 7.0), (7.0, -7.3, 7.0), (-7.0, -7.3, 7.0)]
HOOK = '[[hook]]\nposition = [0.0, 0.0, 27.0]\n'


def lug(p):
    return f"[[lug]]\nposition = [{p[0]}, {p[1]}, {p[2]}]\n"


def sling(k):
    return f"[[sling]]\nlug = {k % 4}\nhook = 0\nlength_factor = 1.0\n"


def scene(parameters="", tables=""):
    return f'model = "RopeBlock"\n\n[parameters]\n{parameters}\n{tables}'


def rig(n_lugs=4, n_slings=4, block=BLOCK):
    lugs = "".join(lug(LUGS[k % 4]) for k in range(n_lugs))
    return block + lugs + HOOK + "".join(sling(k) for k in range(n_slings))


def binary_stl_header(triangles):
    """A binary STL maker: the header claims `triangles` triangles and the file is exactly as
    long as they need (the triangles are zeros: the file is sparse)."""
    return H.sparse(b"\0" * 80 + triangles.to_bytes(4, "little"), 84 + 50 * triangles)


# Each case: res (the resources folder) -> what to do. It writes files and returns the scene
# text (None: leave the folder's scene.toml as the case made it); `at_init` cases set mesh_file
# through fmi2SetString after instantiation and read the input at initialization.


def mesh_in_block(target):
    return scene(tables=rig(block=f'[block]\nmesh = "{target}"\nmass = 250e3\n'))


def mesh(name, make):
    """A case: the mesh file `name` made by the harness's maker `make`, named in [block]."""
    def case(res):
        make(res / name)
        return mesh_in_block(res / name)
    return case


def mesh_file_fifo(res):
    H.fifo(res / "block.obj")
    return scene(parameters=f'mesh_file = "{res / "block.obj"}"', tables=rig(block=""))


def scene_file(make):
    """A case: scene.toml itself replaced by what the harness's maker `make` makes."""
    def case(res):
        (res / "scene.toml").unlink()
        make(res / "scene.toml")
    return case


def many_slings(res):
    return scene(tables=rig(n_slings=2000))


def many_lugs(res):
    return scene(tables=rig(n_lugs=100_000))


def unknown_keys(res):
    return scene(parameters=H.unknown_keys(80_000))


def long_keys(res, length):
    return scene(parameters=H.long_keys(20_000, length))


def unreadable(res):
    os.chmod(res / "scene.toml", 0)


# Caps (docs/bounded_inputs.md); the test checks that each refusal names its cap.
SCENE_FILE_BYTES = 4 * 1024 * 1024
SCENE_KEYS = 10_000
SCENE_TABLES = 1_000
MESH_FILE_BYTES = 256 * 1024 * 1024
MESH_TRIANGLES = 4_000_000
RIG_SLINGS = 64
RIG_LUGS = 256

CASES = {
    "mesh_fifo": mesh("block.obj", H.fifo),
    "mesh_file_fifo": mesh_file_fifo,
    "mesh_file_fifo_at_init": "fifo",
    "mesh_dev_zero": lambda res: mesh_in_block("/dev/zero"),
    "mesh_dev_urandom": lambda res: mesh_in_block("/dev/urandom"),
    "mesh_file_dev_zero_at_init": "/dev/zero",
    "mesh_directory": mesh("block.obj", H.directory),
    "mesh_symlink_loop": mesh("block.obj", H.loop),
    "mesh_too_big": mesh("block.stl", H.sparse(b"", MESH_FILE_BYTES + 1)),
    "mesh_too_many_triangles": mesh("block.stl", binary_stl_header(MESH_TRIANGLES + 1)),
    "scene_fifo": scene_file(H.fifo),
    "scene_dev_zero": scene_file(H.link("/dev/zero")),
    "scene_too_big": scene_file(H.sparse(b"", SCENE_FILE_BYTES + 1)),
    "scene_2000_slings": many_slings,
    "scene_65_slings": lambda res: scene(tables=rig(n_slings=RIG_SLINGS + 1)),
    "scene_257_lugs": lambda res: scene(tables=rig(n_lugs=RIG_LUGS + 1)),
    "scene_100000_lugs": many_lugs,
    "scene_80000_unknown_keys": unknown_keys,
    "scene_20000_long_keys": lambda res: long_keys(res, 1000),
    "scene_20000_keys_under_size_cap": lambda res: long_keys(res, 150),
    "scene_unreadable": unreadable,
    "control_valid_rig": lambda res: scene(tables=rig()),
    "control_largest_rig": lambda res: scene(tables=rig(n_lugs=RIG_LUGS, n_slings=RIG_SLINGS)),
}

# cases whose instance is not initialized (the largest rig builds 6,400 rope segments)
INSTANTIATE_ONLY = {"control_largest_rig"}


def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main():
    unzip, case = sys.argv[1:]
    md = read_model_description(os.path.join(unzip, "modelDescription.xml"))
    lib = R2.Library(unzip, md.coSimulation.modelIdentifier)
    what = CASES[case]
    with tempfile.TemporaryDirectory() as tmp:
        os.chmod(tmp, 0o755)
        res = pathlib.Path(tmp, "resources")
        shutil.copytree(os.path.join(unzip, "resources"), res)
        at_init = isinstance(what, str)
        if not at_init:
            text = what(res)
            if text is not None:
                (res / "scene.toml").write_text(text)
        elif what == "fifo":
            H.fifo(res / "block.obj")
        t0 = cpu()
        i = R2.Instance(lib, md.guid, resource_uri=res.as_uri(), logging_on=True)
        spent = cpu() - t0
        status, refused_at = None, None if i.c else "instantiate"
        if i.c and case not in INSTANTIATE_ONLY:
            # what instantiation let through is built at initialization: that counts too
            if at_init:
                mesh = str(res / "block.obj") if what == "fifo" else what
                vr = next(v.valueReference for v in md.modelVariables if v.name == "mesh_file")
                assert i.set_string([vr], [mesh]) == R2.OK, i.messages()
            t0 = cpu()
            status = max(i.setup(stop=1.0), i.enter(), i.exit())
            spent += cpu() - t0
            if status >= R2.ERROR:
                refused_at = "initialization"
        errors = [m for (s, _, m) in i.log if s >= R2.ERROR]
        out = dict(refused_at=refused_at, status=status, errors=errors[-3:], cpu=spent)
        i.free()
        print(json.dumps(out))


if __name__ == "__main__":
    main()
