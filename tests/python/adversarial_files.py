"""Data files in the adversarial harness: kind `files` (FMI 2.0; FMI 3.0 shares the reader).

Every file the FMUs read, made hostile (VARIANTS, visited in turn by the model's sequence
number): `resources/scene.toml` as a FIFO, a link to /dev/zero or /dev/urandom, a directory, a
symbolic-link loop, an oversized (sparse) file, 80,000 unknown keys, 20,000 keys of 1,000
characters; for RopeBlock also 2,000 `[[sling]]`, 100,000 `[[lug]]`, `[block] mesh` and
`mesh_file` (in the scene, and set with fmi2SetString) as a FIFO, /dev/zero, /dev/urandom, a
directory, a link loop, an oversized file, and a 10 MB `mesh_file` string.

The instance is made with a resources folder holding the variant (fmi2Instantiate), or (for
`mesh_file` set by the importer) made normally, the string set and initialized. Expected: a
refusal (fmi2Instantiate returns NULL, or a call returns fmi2Error) with a logged message that
names the file (`scene.toml`, `mesh`), within the CPU bound. Violations: `accepted` (initialized
and stepped), `unnamed-file`, `long-message` (a logged message over 4,200 characters: messages
are cut at 4,096), `unbounded-read` (the process's peak resident memory grew by more than 64 MB
in the sequence: the file was read whole). The sequence runs under an address-space limit of
1 GiB above the process's size (RLIMIT_AS), so that /dev/zero cannot take the machine's memory:
an FMU that reads it whole aborts (a crash) instead.

The variant files are made once per run (`prepare`, before the workers fork).
"""

import os
import pathlib
import resource
import shutil

import fmi2raw as R
from adversarial_run import ANNOUNCE, Run

MB = 1 << 20
OVERSIZE = 300 * MB  # sparse: no disk space
AS_HEADROOM = 1 << 30
RSS_GROWTH = 64 * MB
MAX_MESSAGE = 4200


def replace_line(text, key, line):
    out = [line if ln.split("=")[0].strip() == key else ln for ln in text.splitlines()]
    return "\n".join(out) + "\n"


def fifo(p):
    os.mkfifo(p)


def link(target):
    return lambda p: os.symlink(target, p)


def loop(p):
    os.symlink(p.name, p)


def directory(p):
    p.mkdir()


def sparse(head, size=OVERSIZE):
    """A file of `size` bytes starting with `head`, the rest zeros that take no disk space."""
    def make(p):
        with open(p, "wb") as f:
            f.write(head)
            f.truncate(size)
    return make


def unknown_keys(n):
    """`n` keys no model knows, one per line."""
    return "".join(f"unknown_key_{k:06d} = 1\n" for k in range(n))


def long_keys(n, length):
    """`n` distinct keys of `length` characters each, one per line."""
    return "".join(f"{'k' * (length - 10)}{k:010d} = 1\n" for k in range(n))


def text(build):
    """Writes the text `build()` gives (built when the variant is made)."""
    return lambda p: p.write_text(build())


def scene_variants(default):
    """(name, how scene.toml is made) for every model."""
    def unknown():
        return default + unknown_keys(80_000)

    def long():
        return default + long_keys(20_000, 1000)

    return [
        ("scene.toml FIFO", fifo),
        ("scene.toml -> /dev/zero", link("/dev/zero")),
        ("scene.toml -> /dev/urandom", link("/dev/urandom")),
        ("scene.toml directory", directory),
        ("scene.toml symlink loop", loop),
        ("scene.toml oversized (300 MB)", sparse(default.encode() + b"\n# ")),
        ("scene.toml 80,000 unknown keys", text(unknown)),
        ("scene.toml 20,000 long keys", text(long)),
    ]


def rope_variants(default):
    """RopeBlock's rig tables and mesh files: (name, how scene.toml is made, mesh file maker or None,
    route) with route "scene" (the mesh named in scene.toml) or "param" (mesh_file set by the
    importer)."""
    def slings():
        return default + "".join("[[sling]]\nlug = 0\nhook = 0\nlength = 23.1\n" for _ in range(2_000))

    def lugs():
        return default + "".join("[[lug]]\nposition = [7.5, 7.3, 7.0]\n" for _ in range(100_000))

    meshes = [("FIFO", fifo), ("-> /dev/zero", link("/dev/zero")), ("-> /dev/urandom", link("/dev/urandom")),
              ("directory", directory), ("symlink loop", loop),
              ("oversized (300 MB)", sparse(b"# an OBJ file\nv 0 0 0\n"))]
    out = [("scene.toml 2,000 [[sling]]", text(slings), None, "scene"),
           ("scene.toml 100,000 [[lug]]", text(lugs), None, "scene")]
    for name, make in meshes:
        block = text(lambda: default + '\n[block]\nmesh = "block.obj"\nmass = 250e3\n')
        in_scene = text(lambda: replace_line(default, "mesh_file", 'mesh_file = "block.obj"'))
        out.append((f"[block] mesh {name}", block, make, "scene"))
        out.append((f"scene mesh_file {name}", in_scene, make, "scene"))
        out.append((f"fmi2SetString mesh_file {name}", None, make, "param"))
    out.append(("fmi2SetString mesh_file of 10 MB", None, None, "long"))
    return out


def prepare(m, workdir, eager=True):
    """Sets m.file_variants for model `m`: (name, resources folder, route, maker) each; `eager`
    makes every folder now (before the workers fork), else each is made when first used (a
    replay needs one)."""
    src = pathlib.Path(m.unzip, "resources")
    m.file_variants = []
    for k, name, make_scene, make_mesh, route in specs(m.id, (src / "scene.toml").read_text()):
        res = pathlib.Path(workdir, f"files-{m.id}-{k}")

        def make(res=res, make_scene=make_scene, make_mesh=make_mesh):
            shutil.copytree(src, res)
            if make_scene is not None:
                (res / "scene.toml").unlink()
                make_scene(res / "scene.toml")
            if make_mesh is not None:
                make_mesh(res / "block.obj")

        m.file_variants.append((name, res, route, make))
        if eager:
            make()


def specs(model, default):
    """(k, name, scene maker, mesh maker, route) of every variant of `model` (cheap: the texts are
    built by the makers)."""
    variants = [(name, make, None, "scene") for name, make in scene_variants(default)]
    if model == "RopeBlock":
        variants += rope_variants(default)
    return [(k, *v) for k, v in enumerate(variants)]


def vm_size():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return 0


def files(m, rng, index):
    name, res, route, make = m.file_variants[index % len(m.file_variants)]
    if not res.exists():
        make()
    ANNOUNCE[0](f"files {m.id}: {name}")
    run = Run(m)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = vm_size() + AS_HEADROOM
    resource.setrlimit(resource.RLIMIT_AS, (limit if hard == resource.RLIM_INFINITY else min(limit, hard), hard))
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    try:
        inst = attempt(m, run, res, route, name)
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
    grew = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - rss0
    if grew > RSS_GROWTH and route != "long":  # (the 10 MB string is the harness's own, copied by ctypes)
        run.violations.append(("unbounded-read", f"{name}: peak resident memory grew by {grew / MB:.0f} MB"))
    long = [msg for (_, _, msg) in inst.log if len(msg) > MAX_MESSAGE]
    if long:
        run.violations.append(("long-message", f"{name}: a message of {len(long[0])} characters was logged"))
    errors = [msg for (s, _, msg) in inst.log if s >= R.ERROR]
    if not run.violations:
        if not run.refused:
            run.violations.append(("accepted", f"{name}: instantiated, initialized and stepped"))
        elif not any(("mesh" if "mesh" in name else "scene.toml") in msg for msg in errors):
            run.violations.append(("unnamed-file", f"{name}: refused without naming the file: {errors[-1:]}"))
    inst.free()
    R.LOGS.pop(inst.env, None)
    return run, {"case": name}


def attempt(m, run, res, route, name):
    """Instantiates (with the variant's resources, or normally for the importer's mesh_file),
    sets what the route sets, initializes and steps once; the instance (maybe NULL)."""
    if route in ("param", "long"):
        inst = R.Instance(m.lib, m.md.guid, logging_on=True)
        for k, v in m.baseline.items():
            run.call(inst, f"set {k}", m.set_value, inst, k, v)
        value = "a" * (10 * MB) if route == "long" else str(res / "block.obj")
        run.call(inst, "set mesh_file", m.set_value, inst, "mesh_file", value)
    else:
        inst = R.Instance(m.lib, m.md.guid, logging_on=True, resource_uri=res.as_uri())
        if not inst.c:
            if not [msg for (s, _, msg) in inst.log if s >= R.ERROR]:
                run.violations.append(("no-message", f"{name}: fmi2Instantiate returned NULL without an Error"))
            run.refused = True
            return inst
        for k, v in m.baseline.items():
            run.call(inst, f"set {k}", m.set_value, inst, k, v)
    if not run.refused:
        run.call(inst, "init", inst.init, 10.0, initialized=True)
    if not run.refused:
        run.call(inst, "fmi2DoStep", inst.do_step, 0.0, m.h, initialized=True)
    return inst
