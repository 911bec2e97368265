"""Power bonds through the packaged FMUs (fmpy, FMI 2.0): RopeBlock's hook force against the
commanded hook velocity, the ports' work against the model's input books; PanelLock's root
interface on a fixed satellite carries no power (docs/power_bonds.md)."""

import numpy as np
from conftest import DIST
from fmpy import simulate_fmu

SEG = 20


def test_rope_block_hook_power_and_work_through_the_fmu():
    # the lift with the hook commanded to (0.3, 0, 0.2) m/s and a pay-out of 0.1 m/s from the
    # start (reached over the 0.5 s ramp): after the ramp hook0_power = -(fx, fy, fz) . v, and
    # hook + winch work = the change of energy_input (the integrator's books), 1e-9
    res = simulate_fmu(str(DIST / "RopeBlock.fmu"),
                       start_values={"segments": SEG, "rope_damping": 2e6, "hook0_vx": 0.3,
                                     "hook0_vz": 0.2, "hook0_payout_rate": 0.1},
                       stop_time=1.5, output_interval=0.05)
    after = res["time"] > 0.55
    expected = -(res["hook0_fx"] * 0.3 + res["hook0_fz"] * 0.2)
    scale = np.abs(res["hook0_power"][after]).max()
    assert scale > 1e5
    assert np.abs(res["hook0_power"][after] - expected[after]).max() < 1e-9 * scale
    assert np.allclose(res["hook0_winch_power"][after], -0.1 * res["hook0_winch_force"][after],
                       rtol=1e-12, atol=0.0)
    work = res["hook0_work"] + res["hook0_winch_work"]
    books = res["energy_input"] - res["energy_input"][0]
    assert work[-1] > 1e4
    assert np.abs(work - books).max() < 1e-9 * np.abs(work).max()


def test_panel_lock_fixed_satellite_root_bond_carries_no_power():
    res = simulate_fmu(str(DIST / "PanelLock.fmu"), start_values={"root_motor_torque": 0.3},
                       stop_time=5.0, output_interval=0.1)
    assert (res["root_power"] == 0.0).all() and (res["root_work"] == 0.0).all()
    assert np.abs(res["root_torque_z"]).max() > 0.0
