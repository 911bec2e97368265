"""OSP-IS port files used by libcosim (issue #46 item 4, docs/osp_ports.md).

`mbcosim pack` writes `<Model>_OspModelDescription.xml` beside every FMU with power ports; libcosim
reads them when an OSP system structure joins two models port to port. Checked here: libcosim
accepts the files and the `VariableGroupConnection`, wires each effort to its input and each flow
back (the inputs it sets equal the outputs they are joined to), and the coupled run equals the
same two FMUs joined scalar by scalar in fmpy's Jacobi loop to the importer matrix's 1e-9.
The files' structure against the OSP-IS schema is checked in `tests/fmi/osp_ports.rs`.
"""

import numpy as np
import pytest
from conftest import DIST, packed

import importer_matrix as im
import osp_ports


@pytest.fixture(scope="module")
def winch_runs(tmp_path_factory):
    ok, why = im.available("libcosimpy")
    assert ok, why
    packed("RopeBlock")
    packed("SpringMassDamper")
    case = osp_ports.rope_winch(DIST)
    lib = osp_ports.run_libcosim_ports(case, osp_ports.WINCH_PORTS, tmp_path_factory.mktemp("osp"))
    ref = im.run_fmpy(case, time_mode="libcosim")
    return case, lib, ref


def test_every_port_file_is_beside_its_fmu():
    for model in ("RopeBlock", "SpringMassDamper", "PanelLock"):
        fmu = packed(model)
        assert fmu.with_name(f"{model}_OspModelDescription.xml").is_file(), model
    assert not (DIST / "PidController_OspModelDescription.xml").exists(), "the PID has no power port"


def test_libcosim_wires_each_effort_and_flow_across_the_port(winch_runs):
    case, lib, _ = winch_runs
    for a, x, b, y in case.connections:
        out, inp = lib.series[f"{a}.{x}"], lib.series[f"{b}.{y}"]
        # libcosim's observer reports the input a step was taken with: the output of the
        # communication point before (the first step's input, from initialization, is not
        # among the recorded outputs)
        gap = np.max(np.abs(out[:-1] - inp[1:]))
        assert np.array_equal(out[:-1], inp[1:]), f"{a}.{x} -> {b}.{y}: largest gap {gap}"
        assert np.max(np.abs(out)) > 0.0, f"{a}.{x} never moved: the case tests nothing"


def test_port_connection_equals_the_scalar_connections(winch_runs):
    _, lib, ref = winch_runs
    lib.series = {k: v for k, v in lib.series.items() if k in ref.series}
    diffs = im.compare(ref, lib)
    worst = diffs[0]
    assert worst.rel <= im.RTOL, f"{worst.name}: {worst.rel:.3e} at sample {worst.k}"
    # the winch did pay out and the line force changed with it (a coupled motion)
    payout = ref.series["rope.hook0_winch_work"]
    assert np.max(np.abs(payout)) > 0.0
    v = ref.series["winch.v"]
    assert 1e-2 < np.max(np.abs(v)) < 5.0, f"the winch drum's largest speed {np.max(np.abs(v))} m/s"
    assert np.all(np.isfinite(v))


def test_the_joined_winch_is_passive():
    """The rope and the drum are both passive, so joined at a power port their motion must die
    out: over 4 s the drum's largest speed in the last second is below 5 % of the first
    second's. Before the winch's line force carried the slings' damping share (2026-12-08) the
    force was not the pay-out rate's power conjugate and the joined pair gained energy (drum speed
    0.45 -> 1.68 m/s from the first to the second half second, and runs past 1.4 s stopped)."""
    packed("RopeBlock")
    packed("SpringMassDamper")
    case = osp_ports.rope_winch(DIST, stop=4.0)
    ref = im.run_fmpy(case, time_mode="libcosim")
    v = ref.series["winch.v"]
    per_second = round(1.0 / case.step)
    first, last = np.max(np.abs(v[:per_second])), np.max(np.abs(v[-per_second:]))
    assert first > 0.1, f"the drum hardly moved ({first} m/s)"
    assert last < 0.05 * first, f"drum speed {first:.3g} m/s in the first second, {last:.3g} m/s in the last"
