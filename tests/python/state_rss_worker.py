"""RSS growth of FMU-state cycling in a fresh interpreter (issue #48 item 5).

usage: state_rss_worker.py <unzip-dir> <model-identifier> <guid> <cycles per window>

One instance (RopeBlock with 20 segments per sling and the default lift hoisted) runs 1 s, then
cycles its state: (get, set, free) and (get, serialize, free, deserialize, set, free), one of
each per cycle, through the raw C API (fmi2raw). After a warm-up of WARM_UP cycles (the allocator
settles its pools and mmap threshold), VmRSS (/proc/self/status) is read before and after two
windows of <cycles per window> cycles each. Prints one JSON object: the growth of each window
[kB per 1,000 cycles], the live heap (mallinfo2: bytes in use) at the same points [kB] and the
serialized state's size [bytes].
"""

import ctypes
import json
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fmi2raw as R  # noqa: E402

WARM_UP = 2000


class _MallInfo2(ctypes.Structure):
    _fields_ = [(n, ctypes.c_size_t) for n in
                "arena ordblks smblks hblks hblkhd usmblks fsmblks uordblks fordblks keepcost".split()]


def rss_kb():
    for line in pathlib.Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise RuntimeError("no VmRSS in /proc/self/status")


def heap_kb():
    """Bytes the allocator has handed out and not taken back [kB] (glibc mallinfo2)."""
    libc = ctypes.CDLL("libc.so.6")
    libc.mallinfo2.restype = _MallInfo2
    m = libc.mallinfo2()
    return (m.uordblks + m.hblkhd) // 1024


def main(unzip, identifier, guid, per_window):
    from fmpy import read_model_description

    md = read_model_description(str(pathlib.Path(unzip) / "modelDescription.xml"))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    lib = R.Library(unzip, identifier)
    i = R.Instance(lib, guid)
    assert i.c, "instantiate"
    assert i.setup(stop=10.0) == R.OK
    if identifier == "RopeBlock":
        assert i.set_integer([vr["segments"]], [20]) == R.OK
    assert i.enter() == R.OK and i.exit() == R.OK
    t, h = 0.0, 0.05
    for k in range(20):
        if identifier == "RopeBlock" and k == 10:
            assert i.set_real([vr["hook0_vz"]], [0.2]) == R.OK
        assert i.do_step(t, h) == R.OK
        t += h
    size = [0]

    def cycle():
        s, st = i.get_state()
        assert s == R.OK
        assert i.set_state(st) == R.OK
        assert i.free_state(st)[0] == R.OK
        s, st = i.get_state()
        s, data = i.serialize(st)
        assert s == R.OK
        assert i.free_state(st)[0] == R.OK
        s, st = i.deserialize(data)
        assert s == R.OK
        assert i.set_state(st) == R.OK
        assert i.free_state(st)[0] == R.OK
        size[0] = len(data)

    for _ in range(WARM_UP):
        cycle()
    rss, heap = [rss_kb()], [heap_kb()]
    for _ in range(2):
        for _ in range(per_window):
            cycle()
        rss.append(rss_kb())
        heap.append(heap_kb())
    assert i.do_step(t, h) == R.OK, "the instance still steps"
    i.free()
    per_1000 = [(b - a) * 1000.0 / per_window for a, b in zip(rss, rss[1:])]
    print(json.dumps({"rss_kb": rss, "heap_kb": heap, "kb_per_1000": per_1000, "state_bytes": size[0]}))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]))
