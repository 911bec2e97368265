"""FMU-state cycling does not grow the process (issue #48 item 5: RopeBlock grew 68.5 kB per
1,000 get/set/free cycles, the other models 0-1.8 kB).

Each model runs in a fresh interpreter (state_rss_worker.py): after a warm-up, two windows of
WINDOW cycles, each cycle a get/set/free and a get/serialize/free/deserialize/set/free. The bound
is BOUND_KB per 1,000 cycles on the smaller of the two windows' slopes: a leak grows both
windows alike, while a one-off step of the allocator (a new arena page, a trimmed top) shows in
one window only. Cost: a few seconds per model.
"""

import json


from conftest import python_script

WINDOW = 5000
BOUND_KB = 2.0


def test_state_cycling_does_not_grow_rss(fmu):
    r = python_script("state_rss_worker.py", fmu.unzip, fmu.id, fmu.guid, WINDOW, timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    res = json.loads(r.stdout.strip().splitlines()[-1])
    print(fmu.id, res)
    assert min(res["kb_per_1000"]) < BOUND_KB, (
        f"{fmu.id}: RSS grows {res['kb_per_1000']} kB per 1,000 state cycles in the two windows "
        f"(bound {BOUND_KB}); heap in use {res['heap_kb']} kB, state {res['state_bytes']} bytes")
