"""FMI 3.0 early return and intermediate updates (docs/fmi3.md, src/scene/watch.rs).

Each located event is checked against an independent bracket: the same model through the FMI
2.0 FMU (no early return, no location code) with fine fixed communication steps, where the
event shows as the first output sample that has it. The intermediate-update callback is checked
against the model's own count of accepted integrator steps.
"""

import math
import sys
import pathlib

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from conftest import DIST  # noqa: E402

DIST3 = DIST / "fmi3"


class Fmu:
    """One unpacked FMU (FMI 2.0 or 3.0) with its variables by name."""

    def __init__(self, path, scene=None):
        self.path = str(path)
        self.md = read_model_description(self.path)
        self.unzip = extract(self.path)
        if scene is not None:  # the FMU reads its scene file at instantiation
            (pathlib.Path(self.unzip) / "resources" / "scene.toml").write_text(scene)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.log = []

    def fmi3(self, early=False, callback=None):
        s = FMU3Slave(guid=self.md.guid, unzipDirectory=self.unzip,
                      modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="er")

        def log(env, status, category, message):
            self.log.append(message.decode())

        s.instantiate(loggingOn=True, earlyReturnAllowed=early, logMessage=log,
                      intermediateUpdate=callback)
        return s

    def fmi2(self):
        s = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzip,
                      modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="ref")
        s.instantiate()
        return s


def panel3(**kw):
    f = Fmu(DIST3 / "PanelLock.fmu")
    s = f.fmi3(**kw)
    # generalized-alpha, as these tests were written for (`auto` would run dopri5_tree here,
    # whose outputs with the intermediate-update callback differ from a plain run in the last
    # bits: docs/auto_integrator.md)
    s.setInt64([f.vr["integrator"]], [1])
    s.setFloat64([f.vr["rtol"]], [1e-6])
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    return f, s


def panel2():
    f = Fmu(DIST / "PanelLock.fmu")
    s = f.fmi2()
    s.setInteger([f.vr["integrator"]], [1])
    s.setReal([f.vr["rtol"]], [1e-6])
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    return f, s


def first_sample_with(s, get, t, schedule):
    """Steps the FMI 2.0 instance `s` along `schedule` [(h, until)] from `t` and returns the
    bracket (t_before, t_after) of the first sample at which `get()` turns true."""
    for h, until in schedule:
        n = round((until - t) / h)
        for _ in range(n):
            before = get()
            s.doStep(t, h)
            t += h
            if get() and not before:
                return t - h, t
    pytest.fail("the event did not happen in the reference run")


def test_panel_lock_returns_early_at_each_latch_engagement():
    f, s = panel3(early=True)
    lock = f.vr["hinge_lock_time"]  # an FMI 3.0 array, one element per hinge
    t, events = 0.0, []
    while t < 8.0 - 1e-9:
        _, _, early, last = s.doStep(t, min(0.5, 8.0 - t))
        if early:
            assert t < last < t + 0.5
            events.append((last, s.getFloat64([lock], nValues=7)))
        else:
            assert last == pytest.approx(min(t + 0.5, 8.0), abs=1e-12)
        t = last
    # the root hinge locks at about 4.92 s, hinge 3 at about 7.14 s (docs/details.md)
    assert [e[0] for e in events] == pytest.approx([4.9194, 7.1431], abs=1e-3), events
    reasons = [m for m in f.log if "early return" in m]
    assert "hinge 0 locked" in reasons[0] and "hinge 3 locked" in reasons[1], reasons
    # the model stopped right after the located engagement: its lock time is there
    assert events[0][1][0] == pytest.approx(events[0][0], abs=2e-8)
    assert events[1][1][3] == pytest.approx(events[1][0], abs=2e-8)

    # independent bracket: the FMI 2.0 FMU at fixed steps of 1e-4 s around the root lock-up
    f2, s2 = panel2()
    lo, hi = first_sample_with(s2, lambda: s2.getReal([f2.vr["hinge0_lock_time"]])[0] >= 0.0, 0.0,
                               [(0.5, 4.5), (0.01, 4.9), (1e-4, 5.0)])
    # the two runs take different internal steps (rtol 1e-6): 1e-5 s is far inside the 1e-4 bracket
    assert lo - 1e-5 < events[0][0] <= hi + 1e-5, (lo, events[0][0], hi)


def test_panel_lock_without_early_return_completes_every_step():
    f, s = panel3(early=False)
    t = 0.0
    while t < 5.5 - 1e-9:
        _, _, early, last = s.doStep(t, 0.5)
        assert not early and last == pytest.approx(t + 0.5, abs=1e-12)
        t = last
    assert s.getFloat64([f.vr["hinge_lock_time"]], nValues=7)[0] == pytest.approx(4.9194, abs=1e-3)


def test_intermediate_update_is_called_at_every_internal_step():
    heard = []

    def callback(env, t, set_requested, get_allowed, step_finished, can_return_early, req, at):
        heard.append((t, set_requested, get_allowed, step_finished, can_return_early))

    f, s = panel3(callback=callback)
    steps = f.vr["solver_steps"]
    t = 0.0
    for _ in range(6):
        n0, k0 = s.getInt32([steps])[0], len(heard)
        _, _, early, last = s.doStep(t, 0.5)
        assert not early
        calls = heard[k0:]
        # every accepted internal step but the one that ends the communication step
        assert len(calls) == s.getInt32([steps])[0] - n0 - 1 > 10
        times = [c[0] for c in calls]
        assert all(t < a < b < t + 0.5 for a, b in zip(times, times[1:]))
        assert all(c[1:] == (False, False, True, False) for c in calls)
        t = last
    # listening changes nothing: the same internal steps, bit for bit
    g, plain = panel3()
    for k in range(6):
        plain.doStep(0.5 * k, 0.5)
    vrs = [f.vr["hinge_angle"], f.vr["hinge_rate"]]
    assert s.getFloat64(vrs, nValues=14) == plain.getFloat64(vrs, nValues=14)


def test_intermediate_update_can_end_the_step_early():
    wanted = 0.3217

    def callback(env, t, set_requested, get_allowed, step_finished, can_return_early, req, at):
        assert can_return_early
        req[0] = True
        at[0] = wanted

    f, s = panel3(early=True, callback=callback)
    _, _, early, last = s.doStep(0.0, 0.5)
    assert early and last == wanted
    assert s.getFloat64([4_000_000])[0] == wanted
    # the next step starts where it ended; the request, now in the past, ends it after its
    # first internal step
    _, _, early, last = s.doStep(last, 0.5 - last)
    assert early and wanted < last < 0.5
    assert any("the importer asked for an early return" in m for m in f.log)


def test_early_return_requests_are_ignored_without_early_return_allowed():
    def callback(env, t, set_requested, get_allowed, step_finished, can_return_early, req, at):
        assert not can_return_early
        req[0] = True
        at[0] = 0.1

    _, s = panel3(early=False, callback=callback)
    _, _, early, last = s.doStep(0.0, 0.5)
    assert not early and last == pytest.approx(0.5)


def test_calls_into_the_instance_from_its_callback_are_refused():
    refused = []
    holder = {}

    def callback(env, t, set_requested, get_allowed, step_finished, can_return_early, req, at):
        if not refused:
            try:
                holder["s"].getFloat64([0])
                refused.append(False)
            except FMICallException:
                refused.append(True)

    f, s = panel3(callback=callback)
    holder["s"] = s
    _, _, early, last = s.doStep(0.0, 0.1)
    assert refused == [True]
    assert last == pytest.approx(0.1)
    # the instance is unharmed
    angles = s.getFloat64([f.vr["hinge_angle"]], nValues=7)
    assert angles == s.getFloat64([f.vr["hinge_angle"]], nValues=7) and all(a == a for a in angles)


def test_rope_block_returns_early_when_a_sling_goes_slack():
    """The hook starts lowering (faster than the block can fall at first): the early return names
    the sling that went slack
    first, and the FMI 2.0 FMU at 10 us steps sees that sling's tension at the lug drop to zero
    at the same time."""
    values = {"segments": 20, "ground_contact": True}
    RTOL = 1e-7
    f = Fmu(DIST3 / "RopeBlock.fmu")
    s = f.fmi3(early=True)
    s.setInt32([f.vr["segments"]], [values["segments"]])
    s.setBoolean([f.vr["ground_contact"]], [True])
    s.setFloat64([f.vr["rtol"]], [RTOL])
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    vz = f.vr["hook0_vz"]
    t, event = 0.0, None
    while t < 2.0 - 1e-9 and event is None:
        s.setFloat64([vz], [-0.5 if t >= 0.5 - 1e-9 else 0.0])
        _, _, early, last = s.doStep(t, 0.05)
        if early:
            event = last
        t = last
    assert event is not None, "no early return"
    reason = [m for m in f.log if "early return" in m][-1]
    sling = int(reason.split("sling ")[1].split(" ")[0])
    assert "went slack" in reason
    assert s.getFloat64([f.vr["sling_tension_lug"]], nValues=4)[sling] == 0.0

    f2 = Fmu(DIST / "RopeBlock.fmu")
    s2 = f2.fmi2()
    s2.setInteger([f2.vr["segments"]], [values["segments"]])
    s2.setBoolean([f2.vr["ground_contact"]], [True])
    s2.setReal([f2.vr["rtol"]], [RTOL])
    s2.setupExperiment(startTime=0.0)
    s2.enterInitializationMode()
    s2.exitInitializationMode()
    util = f2.vr[f"sling{sling}_tension_lug"]
    t2 = 0.0
    for _ in range(10):
        s2.doStep(t2, 0.05)
        t2 += 0.05
    s2.setReal([f2.vr["hook0_vz"]], [-0.5])
    # slack spells can be short: 10 us samples
    coarse = 0.05 * int((event - 0.005) / 0.05)
    lo, hi = first_sample_with(s2, lambda: s2.getReal([util])[0] == 0.0, t2,
                               [(0.05, coarse), (1e-5, event + 0.002)])
    # the contact nodes slide along their edges at accepted step ends, so the rope's transient
    # depends on the step sequence: the 10 us reference and the located event differed by
    # 1.2-1.3 ms at rtol 1e-4 and 1e-7 alike (docs/fmi3.md)
    assert lo - 3e-3 < event <= hi + 3e-3, (lo, event, hi)


# One sling from a lug on the side shell straight up to its hook, the block on the ground, the
# sling in water; the hook moves by position commands (the scene's comments).
SIDE_SLING = (pathlib.Path(__file__).resolve().parents[2] / "examples" / "scenes"
              / "sling_over_deck_edge.toml").read_text()


def swing(t):
    """The hook's target (dy, dz) [m] at time t: 10 m inboard over the deck at the sling's
    length from the lug from 0.5 s, back above the lug from 12 s."""
    return (-10.0, math.sqrt(20.0**2 - 10.0**2) - 20.0) if 0.5 - 1e-9 <= t < 12.0 - 1e-9 else (0.0, 0.0)


def test_rope_block_returns_early_when_a_contact_node_is_created_and_released():
    """The hook swings inboard, so the sling's straight path cuts the deck edge (a contact node
    is created), and back over the lug, so the rope bends away from the edge (the node is
    released). Each early return is compared with the first samples of the FMI 2.0 FMU at 0.5,
    1 and 2 ms steps whose contact count has the change."""
    f = Fmu(DIST3 / "RopeBlock.fmu", scene=SIDE_SLING)
    s = f.fmi3(early=True)
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    count = f.vr["contact_count"]
    t, nodes = 0.0, []
    while t < 25.0 - 1e-9:
        s.setFloat64([f.vr["hook0_dy"], f.vr["hook0_dz"]], list(swing(t)))
        h = 0.5 * math.floor(t / 0.5 + 1e-9) + 0.5 - t  # back on the 0.5 s grid after a return
        _, _, early, last = s.doStep(t, h)
        reason = [m for m in f.log if "early return" in m]
        if early and "contact node" in reason[-1]:
            nodes.append((last, s.getInt32([count])[0], reason[-1]))
        t = last
    assert [(c, "created" in r) for _, c, r in nodes] == [(1, True), (0, False)], nodes
    assert "released" in nodes[1][2]

    # the FMI 2.0 FMU at communication steps of 0.5, 1 and 2 ms, each bracketing both changes
    runs = [fmi2_contact_changes(h) for h in (5e-4, 1e-3, 2e-3)]
    for seen in runs:
        assert len(seen) == 2, runs
    # the creation agrees within 3 ms with every run (measured: 3.596881 s against (3.596,
    # 3.597], (3.5965, 3.597] and (3.596, 3.598]). The release comes 15 s later, after the
    # slack sling has folded back at the edge, and its time depends on the step sequence: the
    # three runs release anywhere in 18.280-18.318 s (on e19f983 in 18.312-18.326 s, with
    # 4 ms steps too), so the early return must fall inside their spread, widened by 3 ms.
    created, released = nodes[0][0], nodes[1][0]
    for seen in runs:
        lo, hi = seen[0]
        assert lo - 3e-3 < created <= hi + 3e-3, (lo, created, hi)
    lo = min(seen[1][0] for seen in runs)
    hi = max(seen[1][1] for seen in runs)
    assert lo - 3e-3 < released <= hi + 3e-3, (lo, released, hi, runs)


def fmi2_contact_changes(h):
    """Brackets `(t - h, t]` of the FMI 2.0 FMU's first two changes of the contact count in
    the side-sling swing, at communication steps of `h` [s]."""
    f2 = Fmu(DIST / "RopeBlock.fmu", scene=SIDE_SLING)
    s2 = f2.fmi2()
    s2.setupExperiment(startTime=0.0)
    s2.enterInitializationMode()
    s2.exitInitializationMode()
    count2 = f2.vr["contact_count"]
    t2, n, seen = 0.0, 0, []
    while t2 < 25.0 - 1e-9 and len(seen) < 2:
        before = s2.getInteger([count2])[0]
        s2.setReal([f2.vr["hook0_dy"], f2.vr["hook0_dz"]], list(swing(t2)))
        s2.doStep(t2, h)
        n += 1
        t2 = n * h
        if s2.getInteger([count2])[0] != before:
            seen.append((t2 - h, t2))
    return seen
