"""SpringMassDamper (src/scene/spring_mass_damper/): the third model, driven through fmpy as a
user would, in FMI 2.0 (dist/) and FMI 3.0 (dist/fmi3/), against the closed-form solution of
m x'' + c x' + k x = F (independent of the solver: damped harmonic motion about F/k).

- both FMUs pass fmpy's validate_fmu;
- a free damped oscillation and a step force match the closed form to 1e-6 of the amplitude at
  the default tolerances (rtol 1e-9), and the outputs a and spring_force follow from x and v;
- a force that changes between communication points acts from that point on (zero-order hold):
  the run equals the closed form pieced together step by step.
"""

import math
import pathlib
import sys

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from conftest import DIST, packed  # noqa: E402

DEFAULTS = dict(m=1.0, k=100.0, c=0.5, x0=0.1, v0=0.0)


def exact(p, force, t):
    """(x, v) at t of the underdamped oscillator p under a constant force from x0, v0 at 0."""
    s = p["c"] / (2.0 * p["m"])
    w = math.sqrt(p["k"] / p["m"] - s * s)
    a = p["x0"] - force / p["k"]
    b = (p["v0"] + s * a) / w
    e = math.exp(-s * t)
    c, sn = math.cos(w * t), math.sin(w * t)
    return force / p["k"] + e * (a * c + b * sn), e * ((-s * a + w * b) * c + (-s * b - w * a) * sn)


def fmu(version):
    path = packed("SpringMassDamper")
    return str(path if version == 2 else DIST / "fmi3" / "SpringMassDamper.fmu")


@pytest.mark.parametrize("version", [2, 3])
def test_validates(version):
    assert validate_fmu(fmu(version)) == []


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize(
    "values,force",
    [({}, 0.0), ({"x0": 0.0, "v0": 0.0, "m": 2.0, "c": 4.0}, 20.0), ({"v0": -1.5, "k": 400.0}, -5.0)],
)
def test_matches_the_closed_form(version, values, force):
    p = dict(DEFAULTS, **values)
    res = simulate_fmu(fmu(version), stop_time=4.0, output_interval=0.01, fmi_type="CoSimulation",
                       start_values=dict(values, F=force), output=["x", "v", "a", "spring_force"])
    t = res["time"]
    assert len(t) == 401 and abs(t[-1] - 4.0) < 1e-12
    xv = np.array([exact(p, force, ti) for ti in t])
    scale = np.abs(xv).max(axis=0)
    err = np.abs(np.column_stack([res["x"], res["v"]]) - xv).max(axis=0) / scale
    print(f"FMI {version} {values} F={force}: relative error x {err[0]:.2e}, v {err[1]:.2e}")
    assert err.max() < 1e-6, err
    spring = -p["k"] * res["x"] - p["c"] * res["v"]
    np.testing.assert_allclose(res["spring_force"], spring, rtol=0, atol=1e-12 * np.abs(spring).max())
    np.testing.assert_allclose(res["a"], (spring + force) / p["m"], rtol=1e-12, atol=1e-12)


def test_an_input_acts_from_the_point_it_is_set():
    # F steps from 0 to 10 N at t = 1 s: before, the free oscillation; after, the closed form
    # started from the state at 1 s
    signal = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 10.0), (2.0, 10.0)],
                      dtype=[("time", np.float64), ("F", np.float64)])
    res = simulate_fmu(fmu(2), stop_time=2.0, output_interval=0.01, input=signal, output=["x", "v"])
    p = dict(DEFAULTS)
    i1 = int(np.argmin(np.abs(res["time"] - 1.0)))
    x1, v1 = exact(p, 0.0, 1.0)
    q = dict(p, x0=x1, v0=v1)
    worst = 0.0
    for ti, x in zip(res["time"], res["x"]):
        want = exact(p, 0.0, ti)[0] if ti <= 1.0 + 1e-9 else exact(q, 10.0, ti - 1.0)[0]
        worst = max(worst, abs(x - want))
    print(f"input step at 1 s: largest error {worst:.2e} m (index of 1 s: {i1})")
    assert worst < 1e-6 * 0.2, worst
