"""fmpy's simulate_fmu: same results as the native run, standard call order, step independence."""

import random
import re

import pytest
from conftest import bits, native_table
from fmpy import simulate_fmu


def _native_table(fmu, stop, step, values):
    args = ["simulate", fmu.id, "--stop", repr(stop), "--step", repr(step)]
    for k, v in values.items():
        args += ["--set", f"{k}={float(v)!r}"]
    return native_table(*args)


def test_simulate_fmu_matches_the_native_run_bit_for_bit(fmu):
    res = simulate_fmu(str(fmu.path), start_values=fmu.values, stop_time=fmu.stop, output_interval=fmu.step)
    ref = _native_table(fmu, fmu.stop, fmu.step, fmu.values)
    assert len(res) == len(ref) > 10
    assert [bits(t) for t in res["time"]] == [bits(t) for t in ref["time"]]
    outputs = [v.name for v in fmu.by_causality("output") if v.type != "String"]
    assert outputs
    for name in outputs:
        got = [bits(float(x)) for x in res[name]]
        want = [bits(float(x)) for x in ref[name]]
        assert got == want, f"{name}: first difference at row {next(i for i, (a, b) in enumerate(zip(got, want)) if a != b)}"


def test_call_order_is_the_standard_one(fmu):
    calls = []
    simulate_fmu(str(fmu.path), start_values=fmu.values, stop_time=10 * fmu.step, output_interval=fmu.step,
                 fmi_call_logger=calls.append)
    statuses = [c for c in calls if "-> " in c and not c.startswith("fmi2Instantiate")]
    assert statuses and all(c.endswith("-> OK") for c in statuses), [c for c in statuses if not c.endswith("-> OK")]
    names = [c.split("(")[0] for c in calls]
    # one letter per call: I(nstantiate) X(setupExperiment) S(et) E(nter) L(eave init) G(et) D(oStep) T F(ree)
    letter = {"fmi2Instantiate": "I", "fmi2SetupExperiment": "X", "fmi2EnterInitializationMode": "E",
              "fmi2ExitInitializationMode": "L", "fmi2DoStep": "D", "fmi2Terminate": "T", "fmi2FreeInstance": "F"}
    seq = "".join(letter.get(n, "S" if n.startswith("fmi2Set") else "G" if n.startswith("fmi2Get") else "?") for n in names)
    assert re.fullmatch(r"IXS*ES*LG*(S*DG*)+TF", seq), seq
    assert seq.count("D") == 10


@pytest.mark.scenario_key("step_independence")
def test_results_do_not_depend_on_the_communication_step(fmu):
    spec = fmu.step_independence
    for h in [1e-4, 1e-3, 0.01, 0.1, 0.25, 0.5]:
        res = simulate_fmu(str(fmu.path), start_values=spec["values"], stop_time=1.0, output_interval=h)
        for t, y in zip(res["time"], res[spec["output"]]):
            assert y == pytest.approx(spec["exact"](t), rel=1e-12, abs=1e-12), (h, t)
        assert res["time"][-1] == pytest.approx(1.0)


@pytest.mark.scenario_key("step_independence")
def test_random_step_sequence_gives_the_same_trajectory(fmu):
    spec = fmu.step_independence
    rng = random.Random(4)
    s = fmu.slave()
    fmu.start(s, spec["values"], stop=2.0)
    vr = fmu.vars[spec["output"]].valueReference
    t = 0.0
    while t < 2.0 - 1e-12:
        h = min(10 ** rng.uniform(-4, -0.3), 2.0 - t)
        s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        t += h
        assert s.getReal([vr])[0] == pytest.approx(spec["exact"](t), rel=1e-12)
    s.terminate()
    s.freeInstance()


def test_debug_logging_switches_model_messages(fmu):
    def run(debug):
        seen = []
        simulate_fmu(str(fmu.path), start_values=fmu.values, stop_time=fmu.stop, output_interval=fmu.step,
                     debug_logging=debug, logger=lambda c, n, status, cat, msg: seen.append((status, cat.decode())))
        return seen
    assert run(False) == [], "without debug logging an error-free run is silent"
    on = run(True)
    assert on, f"{fmu.id} emits no debug messages in its scenario"
    assert {cat for _, cat in on} <= {"logEvents", "logSolver", "logStatusWarning"}
