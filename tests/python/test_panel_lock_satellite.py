"""PanelLock on a free-floating satellite through fmpy: three PidController FMUs, one per body
axis, hold the satellite's attitude while the array deploys (a PD law on the attitude error,
torques in the satellite body frame); bad satellite inputs and parameters get fmi2Error with a
message that names them."""

import math

import numpy as np
import pytest
from conftest import DIST, Fmu, packed
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

import fmi2raw

PANEL = DIST / "PanelLock.fmu"
PID = DIST / "PidController.fmu"
AXES = "xyz"

# PD gains for a 3 rad/s, 0.7-damped loop on the largest satellite moment (350 kg m^2):
# kp = I w^2, kd = 2 zeta I w; the derivative filtered over 50 ms, torque limited to 50 N m
KP, KD, TF, U_MAX = 3150.0, 1470.0, 0.05, 100.0
STOP, H = 30.0, 0.02
# measured (docs/panel_lock_satellite.md): free 19.5 deg, held 0.325 deg (60x less), 45 N m peak
FREE_MIN_DEG, HELD_BOUND_DEG, MIN_REDUCTION = 10.0, 0.5, 30.0


def _slave(path, name):
    md = read_model_description(str(path))
    s = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)), modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    s.instantiate()
    return s, {v.name: v.valueReference for v in md.modelVariables}


def _attitude_error(q):
    """Rotation angle [rad] of the satellite from its initial attitude, and the small-angle
    rotation vector 2 q_v sign(q_w) (body frame) the controllers measure."""
    qw, qv = q[0], np.asarray(q[1:])
    angle = 2.0 * math.atan2(float(np.linalg.norm(qv)), abs(qw))
    return angle, 2.0 * math.copysign(1.0, qw) * qv


def _deploy(controlled):
    """Peak attitude error [rad], final root-hinge lock flag and the largest |torque| [N m]."""
    plant, pv = _slave(PANEL, "array")
    plant.setupExperiment(startTime=0.0)
    plant.enterInitializationMode()
    plant.setBoolean([pv["free_satellite"]], [True])
    plant.exitInitializationMode()
    ctrls = []
    if controlled:
        for axis in AXES:
            c, cv = _slave(PID, f"pd_{axis}")
            c.setupExperiment(startTime=0.0)
            c.enterInitializationMode()
            c.setReal([cv[n] for n in ["kp", "ki", "kd", "Tf", "setpoint", "u_min", "u_max"]], [KP, 0.0, KD, TF, 0.0, -U_MAX, U_MAX])
            c.exitInitializationMode()
            ctrls.append((c, cv))
    q_vrs = [pv[f"satellite_q{c}"] for c in "wxyz"]
    torque_vrs = [pv[f"satellite_torque_{a}"] for a in AXES]
    t, peak, peak_torque = 0.0, 0.0, 0.0
    for _ in range(int(round(STOP / H))):
        angle, rotvec = _attitude_error(plant.getReal(q_vrs))
        peak = max(peak, angle)
        if ctrls:
            u = []
            for (c, cv), m in zip(ctrls, rotvec):
                c.setReal([cv["measurement"]], [float(m)])
                c.doStep(currentCommunicationPoint=t, communicationStepSize=H)
                u.append(c.getReal([cv["u"]])[0])
            peak_torque = max(peak_torque, max(abs(x) for x in u))
            plant.setReal(torque_vrs, u)
        plant.doStep(currentCommunicationPoint=t, communicationStepSize=H)
        t += H
    angle, _ = _attitude_error(plant.getReal(q_vrs))
    peak = max(peak, angle)
    latched = plant.getBoolean([pv["hinge0_latched"]])[0]
    plant.terminate()
    plant.freeInstance()
    for c, _ in ctrls:
        c.terminate()
        c.freeInstance()
    return peak, latched, peak_torque


def test_pd_attitude_control_through_pid_fmus_holds_the_satellite_during_deployment():
    free_peak, free_latched, _ = _deploy(controlled=False)
    held_peak, held_latched, torque = _deploy(controlled=True)
    print(f"peak attitude error over {STOP} s of deployment: free {math.degrees(free_peak):.4f} deg, "
          f"PD-controlled {math.degrees(held_peak):.5f} deg ({free_peak / held_peak:.0f}x less), "
          f"peak control torque {torque:.3f} N m")
    assert free_latched and held_latched, "the root hinge locks within the run"
    assert math.degrees(free_peak) > FREE_MIN_DEG
    assert math.degrees(held_peak) < HELD_BOUND_DEG
    assert free_peak / held_peak > MIN_REDUCTION
    assert torque <= U_MAX



@pytest.fixture(scope="module")
def panel_lock(tmp_path_factory):
    path = packed("PanelLock")
    return Fmu(path, extract(str(path), unzipdir=str(tmp_path_factory.mktemp("satellite"))))


def test_nan_satellite_torque_is_refused_with_its_name(panel_lock):
    lib = fmi2raw.Library(panel_lock.unzip, panel_lock.id)
    inst = fmi2raw.Instance(lib, panel_lock.guid, logging_on=True)
    vr = panel_lock.vars
    assert inst.setup() == fmi2raw.OK
    assert inst.set_boolean([vr["free_satellite"].valueReference], [True]) == fmi2raw.OK
    assert inst.enter() == fmi2raw.OK and inst.exit() == fmi2raw.OK
    status = inst.set_real([vr["satellite_torque_y"].valueReference], [float("nan")])
    assert status == fmi2raw.ERROR
    text = " ".join(inst.messages())
    assert "satellite_torque_y" in text, text
    inst.free()


def test_negative_satellite_inertia_is_refused_with_its_name(panel_lock):
    lib = fmi2raw.Library(panel_lock.unzip, panel_lock.id)
    inst = fmi2raw.Instance(lib, panel_lock.guid, logging_on=True)
    status = inst.set_real([panel_lock.vars["satellite_inertia_x"].valueReference], [-300.0])
    assert status == fmi2raw.ERROR
    text = " ".join(inst.messages())
    assert "satellite_inertia_x" in text, text
    inst.free()


def test_inertia_breaking_the_triangle_inequality_is_refused_at_initialization(panel_lock):
    lib = fmi2raw.Library(panel_lock.unzip, panel_lock.id)
    inst = fmi2raw.Instance(lib, panel_lock.guid, logging_on=True)
    vr = panel_lock.vars
    assert inst.setup() == fmi2raw.OK
    assert inst.set_real([vr["satellite_inertia_z"].valueReference], [700.0]) == fmi2raw.OK
    assert inst.enter() == fmi2raw.ERROR or inst.exit() == fmi2raw.ERROR
    text = " ".join(inst.messages())
    assert "satellite_inertia_z" in text and "triangle" in text, text
    inst.free()


def test_satellite_torque_on_a_fixed_satellite_is_refused(panel_lock):
    lib = fmi2raw.Library(panel_lock.unzip, panel_lock.id)
    inst = fmi2raw.Instance(lib, panel_lock.guid, logging_on=True)
    vr = panel_lock.vars
    assert inst.setup() == fmi2raw.OK
    assert inst.enter() == fmi2raw.OK and inst.exit() == fmi2raw.OK
    assert inst.set_real([vr["satellite_torque_z"].valueReference], [0.0]) == fmi2raw.OK
    assert inst.set_real([vr["satellite_torque_z"].valueReference], [1.0]) == fmi2raw.ERROR
    text = " ".join(inst.messages())
    assert "free_satellite" in text, text
    inst.free()
