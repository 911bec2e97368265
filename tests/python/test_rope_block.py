"""RopeBlock through fmpy, against independent references: static hook load = total weight,
native runner, communication-step independence, hook travel = block travel, effect switches."""

import math

import numpy as np
import pytest
from conftest import DIST, native_table
from fmpy import simulate_fmu

ROPE = DIST / "RopeBlock.fmu"
SEG = 20  # segments per sling: fast, and enough for the statics checked here
G = 9.81


def _sim(values, stop=1.0, step=0.05, **kw):
    return simulate_fmu(str(ROPE), start_values={"segments": SEG, **values}, stop_time=stop,
                        output_interval=step, **kw)


def _native(stop, step, values):
    args = ["simulate", "RopeBlock", "--stop", repr(stop), "--step", repr(step)]
    for k, v in {"segments": SEG, **values}.items():
        args += ["--set", f"{k}={float(v)!r}"]
    return native_table(*args, timeout=600)


def _energy_balance(res):
    """Kinetic + potential + dissipated - hook work - events [J], per output row."""
    return (res["energy_kinetic"] + res["energy_potential"] + res["energy_dissipated"]
            - res["energy_input"] - res["energy_events"])


def _sling_length(hook, lug, edge_y, edge_z):
    """Shortest path hook -> point (x, edge_y, edge_z) of a deck edge -> lug [m] (the rigging's
    unstretched sling length at length factor 1), by golden-section search over x."""
    f = lambda x: math.dist(hook, (x, edge_y, edge_z)) + math.dist((x, edge_y, edge_z), lug)
    a, b = min(hook[0], lug[0]) - 1.0, max(hook[0], lug[0]) + 1.0
    r = (math.sqrt(5) - 1) / 2
    for _ in range(200):
        c, d = b - r * (b - a), a + r * (b - a)
        if f(c) < f(d):
            b = d
        else:
            a = c
    return f(0.5 * (a + b))


def _default_lift_weight(block_mass=200e3, rope_mass_per_length=15.0):
    """Block plus the four slings of the default lift (18 m x 12 m x 7 m block, hook 19 m above
    the deck on the centre line, lugs 6.5 m fore/aft, 0.3 m outside the side shell, 1 m below
    the deck edge), from the geometry alone [N]."""
    length = _sling_length((0.0, 0.0, 26.0), (6.5, 6.3, 6.0), 6.0, 7.0)
    return (block_mass + 4 * rope_mass_per_length * length) * G


def _slots(res):
    """(normal, friction, slip) arrays of every contact slot the run filled."""
    return [(res[f"contact{i}_normal"], res[f"contact{i}_friction"], res[f"contact{i}_slip"])
            for i in range(8) if (res[f"contact{i}_sling"] >= 0).all()]


def test_friction_off_reports_exactly_zero_friction_and_no_slip():
    # a block hanging at rest on frictionless slings: no friction element acts at any node (the
    # rope runs through with equal tensions), so friction and slip flag read exactly 0 on every
    # row (they read 30.76 N and +-1 when the outputs were the line joint's reaction)
    for values in ({"friction": False}, {"mu": 0.0}):
        res = _sim(values, stop=2.0, step=0.5)
        slots = _slots(res)
        assert len(slots) == 4, values
        for normal, friction, slip in slots:
            assert (normal > 0.0).all(), values
            assert (friction == 0.0).all() and (slip == 0).all(), (values, friction, slip)


def test_lift_contact_outputs_inside_the_coulomb_cone():
    # the lift hoisted at 0.2 m/s from 0.5 s (ramped in over hook_ramp): at every communication
    # point friction <= mu N (1 + 1e-9), and = mu N (1 - 1e-9) where the slip flag says the rope
    # slides (friction / (mu N) reached 1.235 when the outputs were the line joint's reaction)
    mu = 0.15
    signal = np.array([(0.0, 0.0), (0.5, 0.0), (0.5001, 0.2), (3.0, 0.2)],
                      dtype=[("time", float), ("hook0_vz", float)])
    res = _sim({"mu": mu}, stop=3.0, step=0.05, input=signal)
    worst, sliding = 0.0, 0
    for normal, friction, slip in _slots(res):
        assert (normal > 0.0).all()
        ratio = friction / (mu * normal)
        worst = max(worst, ratio.max())
        assert (ratio <= 1.0 + 1e-9).all(), ratio.max()
        on = slip != 0
        sliding += int(on.sum())
        assert (ratio[on] >= 1.0 - 1e-9).all(), ratio[on].min()
    assert sliding > 0, "the lift never slid through a node"


def test_hook_load_at_rest_equals_the_total_weight():
    for mass in (200e3, 80e3):
        res = _sim({"block_mass": mass}, stop=1.0)
        w = _default_lift_weight(mass)
        for row in (0, -1):  # right after settling, and 1 s later
            assert res["hook0_load"][row] == pytest.approx(w, rel=1e-3)
            assert -res["hook0_fz"][row] == pytest.approx(w, rel=1e-3)
        # fore/aft symmetric pairs share the load equally (the bilge on one side moves the centre
        # of mass across, so the two sides differ); the slings sit on the deck edges
        t = [res[f"sling{r}_tension_hook"][-1] for r in range(4)]
        assert abs(t[0] - t[1]) < 1e-6 * t[0] and abs(t[2] - t[3]) < 1e-6 * t[2]
        assert sum(t) > w / 4, "legs at about 25 degrees carry more than their vertical share"
        assert res["contact_count"][-1] == 4
        assert all(abs(res[f"contact{i}_z"][-1] - 7.0) < 1e-6 for i in range(4))


def test_fmu_equals_the_native_runner_for_the_turnover_with_hook_inputs():
    values = {"scenario": 1, "segments": 12, "hook1_vz": -0.3, "hook0_payout_rate": 0.05, "mu": 0.3}
    res = simulate_fmu(str(ROPE), start_values=values, stop_time=1.5, output_interval=0.05)
    ref = _native(1.5, 0.05, values)
    names = [n for n in ref.dtype.names if n != "time"]
    assert len(names) > 90
    for n in names:
        assert np.array_equal(res[n], ref[n]), n
    assert res["hook1_z"][-1] < res["hook1_z"][0] - 0.2, "hook 1 input acts in the turn-over"


def test_results_do_not_depend_on_the_communication_step():
    # at rtol 1e-4 ... 1e-6 the difference stays near 1e-4 m (the contact manager's stick/slip
    # decisions after each accepted step do not scale with the tolerance); at 1e-8 it is 8e-7 m
    values = {"hook0_vz": 0.2, "rtol": 1e-8, "atol": 1e-10}
    fine = _sim(values, stop=2.0, step=0.01)
    coarse = _sim(values, stop=2.0, step=0.05)
    common = fine[::5]
    assert np.allclose(common["time"], coarse["time"])
    for name, tol in [("block_z", 1e-5), ("hook0_z", 1e-12), ("block_vz", 1e-4)]:
        assert np.max(np.abs(common[name] - coarse[name])) < tol, name
    load = np.max(np.abs(common["hook0_load"] - coarse["hook0_load"])) / coarse["hook0_load"][0]
    assert load < 1e-4


def test_raising_the_hook_raises_the_block_by_the_same_amount():
    # 0.2 m/s commanded at 0 s and 0 at 1 s: 0.5 s ramps, so the hook rises exactly 0.2 m
    signal = np.array([(0.0, 0.2), (0.999, 0.2), (1.0, 0.0), (9.0, 0.0)],
                      dtype=[("time", float), ("hook0_vz", float)])
    res = _sim({}, stop=8.0, step=0.05, input=signal)
    rise = res["hook0_z"][-1] - res["hook0_z"][0]
    assert rise == pytest.approx(0.2, rel=1e-9)
    # a slow stick-slip sway at the edges (period about 4 s, +-3 mm) is left after the lift:
    # compare the mean over 2 s ... 8 s
    late = res["time"] >= 2.0
    assert np.mean(res["block_z"][late]) - res["block_z"][0] == pytest.approx(rise, abs=2e-3)
    assert np.max(np.abs(res["block_vz"][late])) < 0.05


def _final(values, stop=0.5):
    res = _sim(values, stop=stop)
    return {n: res[n][-1] for n in res.dtype.names}


def test_effect_switches_change_the_outputs_as_expected():
    base = _final({})
    w = base["hook0_load"]
    # drag acts on moving rope only: at rest, on and off agree
    drag = _final({"drag": True, "fluid_density": 1025.0})
    for n in ["hook0_load", "block_z", "sling0_tension_lug", "contact0_normal"]:
        assert drag[n] == pytest.approx(base[n], rel=1e-9, abs=1e-9), n
    # bending changes the shape, never the weight the hook carries
    bend = _final({"bending": True, "bending_stiffness": 5e4})
    assert bend["hook0_load"] == pytest.approx(w, rel=1e-3)
    # friction off: the friction the nodes carry does not grow (the edge hold releases it step by
    # step), and stays below mu N with friction on
    on, off = base["contact0_friction"], _final({"friction": False})["contact0_friction"]
    assert off < on <= 0.15 * base["contact0_normal"]
    # no gravity: nothing to carry but the small pretension of slings rigged just taut
    assert abs(_final({"gravity_on": False})["hook0_load"]) < 1e-2 * w
    # heavier ropes: more load; no contact: slings straight through the block, no contact nodes
    assert _final({"rope_mass_per_length": 30.0})["hook0_load"] > w
    off = _final({"contact": False})
    assert off["contact_count"] == 0 and off["contact0_sling"] == -1
    assert off["hook0_load"] == pytest.approx(w, rel=2e-3)
    # values of switched-off effects are ignored, but never a negative one
    assert _final({"friction": False, "mu": 1.5})["hook0_load"] == _final({"friction": False})["hook0_load"]


def test_negative_values_are_refused_whatever_the_switch():
    with pytest.raises(Exception):
        _sim({"drag": False, "drag_coefficient": -1.0}, stop=0.1)
    with pytest.raises(Exception):
        _sim({"scenario": 2}, stop=0.1)


def test_ground_contact_carries_what_the_hook_does_not():
    # ground 5 cm below the block's bottom: the settled block rests on it (the slings would
    # stretch by about 8 cm under the full weight), then the hook is lowered 2 cm at 0.1 m/s
    # through its input; at rest again, ground + hook carry the total weight
    w = _default_lift_weight()
    inputs = np.array([(0.0, -0.1), (0.2, -0.1), (0.2001, 0.0), (3.0, 0.0)],
                      dtype=[("time", np.float64), ("hook0_vz", np.float64)])
    res = _sim({"ground_contact": True, "ground_height": -0.05}, stop=3.0, input=inputs)
    normal, hook = res["ground_normal"][-1], -res["hook0_fz"][-1]
    assert normal + hook == pytest.approx(w, rel=2e-3)
    assert normal > 0.3 * w and hook > 0.3 * w
    assert res["ground_friction"][-1] < 1e-3 * w
    # off (the default): no ground, whatever its values say
    off = _final({"ground_height": 3.0, "ground_mu": 1.0})
    assert off["ground_normal"] == 0.0 and off["ground_friction"] == 0.0
    with pytest.raises(Exception):
        _sim({"ground_contact": True, "ground_mu": -0.1}, stop=0.1)


def test_block_set_down_until_the_slings_hang_slack():
    # the default lift as shipped (100 segments per sling) on a ground at the block's bottom:
    # the hook is lowered 0.5 m, so the slings hang slack over their deck edges; the run must
    # complete with the ground carrying the block and the energy balance kept (the clamped rope
    # damping once stopped this run within 0.7 s)
    w = _default_lift_weight()
    inputs = np.array([(0.0, -0.1), (5.0, -0.1), (5.0001, 0.0), (7.0, 0.0)],
                      dtype=[("time", np.float64), ("hook0_vz", np.float64)])
    res = _sim({"segments": 100, "ground_contact": True}, stop=7.0, input=inputs)
    normal, hook = res["ground_normal"][-1], -res["hook0_fz"][-1]
    assert normal + hook == pytest.approx(w, rel=2e-3)
    assert hook < 0.02 * w
    assert res["contact_count"][-1] == 4
    balance = _energy_balance(res)
    assert np.max(np.abs(balance - balance[0])) < 2e-4 * w


def test_turnover_onto_the_ground_rests_on_its_edge():
    # the turn-over scene (20 segments) over a ground 2 m below the block's bottom: crane B
    # lowers at 0.4 m/s for 32 s, the block's lower edge lands on the ground (about 5.5 s) and
    # crane B's slings go slack; at rest the ground and the two hooks carry what the two hooks
    # carried at the start, and the ground's friction stays within mu times its normal force
    inputs = np.array([(0.0, -0.4), (32.0, -0.4), (32.0001, 0.0), (40.0, 0.0)],
                      dtype=[("time", np.float64), ("hook1_vz", np.float64)])
    res = _sim({"scenario": 1, "ground_contact": True, "ground_height": -2.0}, stop=40.0,
               input=inputs)
    w = -(res["hook0_fz"][0] + res["hook1_fz"][0])
    normal, a, b = res["ground_normal"][-1], -res["hook0_fz"][-1], -res["hook1_fz"][-1]
    assert normal + a + b == pytest.approx(w, rel=2e-3)
    assert normal > 0.3 * w and a > 0.3 * w and b < 0.01 * w
    assert res["ground_friction"][-1] < 0.3 * normal
    balance = _energy_balance(res)
    assert np.max(np.abs(balance - balance[0])) < 1e-2 * w
