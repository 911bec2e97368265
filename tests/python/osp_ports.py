"""Two FMUs joined port to port by libcosim from an OSP system structure (issue #46 item 4,
docs/osp_ports.md): the `VariableGroupConnection` of two power ports, resolved by libcosim from
the `<Model>_OspModelDescription.xml` files that `mbcosim pack` writes beside the FMUs.

The case is a compliant winch: RopeBlock's hook-0 winch port (line force out, pay-out rate in)
joined to SpringMassDamper's port (force in, velocity out), the drum brake as a mass on a spring
and damper. Its scalar twin (the same two connections written out, `WINCH_CONNECTIONS`) runs
through fmpy's Jacobi loop (`importer_matrix.run_fmpy`) as the reference.
"""

import pathlib
import shutil
import time
from xml.sax.saxutils import quoteattr

import importer_matrix as im

# start values: a light block, soft slings and a low gravity (a line force near 1 kN), so that the winch's mass, spring and damper (in
# their declared ranges) carry the line force with a slow, resolved motion
WINCH_VALUES = {
    "rope": {"block_mass": 1000.0, "rope_ea": 1.0e6, "gravity": 1.0},
    # the drum starts near its static deflection under the line (2.43 kN / 1e4 N/m), paying out
    "winch": {"m": 100.0, "k": 1.0e4, "c": 50.0, "x0": 0.243, "v0": 0.2},
}
# what the port connection must amount to, scalar by scalar (output -> input)
WINCH_CONNECTIONS = [("rope", "hook0_winch_force", "winch", "F"), ("winch", "v", "rope", "hook0_payout_rate")]
# the port connection: (instance, port) pairs
WINCH_PORTS = [("rope", "hook0_winch", "winch", "mass")]


def rope_winch(dist, step=0.005, stop=1.0):
    """The winch case on the FMI 2.0 FMUs of `dist`, as an importer-matrix case."""
    step_ns = im.to_ns(step)
    return im.Case(
        name="RopeBlock winch + SpringMassDamper",
        models={"rope": pathlib.Path(dist) / "RopeBlock.fmu", "winch": pathlib.Path(dist) / "SpringMassDamper.fmu"},
        step_ns=step_ns,
        n_steps=round(stop * 1e9 / step_ns),
        values=WINCH_VALUES,
        connections=WINCH_CONNECTIONS,
    )


def system_structure(case, ports):
    """OspSystemStructure.xml text: the case's instances with their start values and the port
    connections (no scalar connection)."""
    lines = ['<?xml version="1.0" encoding="utf-8"?>',
             '<OspSystemStructure xmlns="http://opensimulationplatform.com/MSMI/OSPSystemStructure" version="0.1">',
             "  <StartTime>0.0</StartTime>",
             f"  <BaseStepSize>{case.step!r}</BaseStepSize>",
             "  <Algorithm>fixedStep</Algorithm>",
             "  <Simulators>"]
    for inst, path in case.models.items():
        lines.append(f"    <Simulator name={quoteattr(inst)} source={quoteattr(path.name)}>")
        lines.append("      <InitialValues>")
        for name, value in case.values.get(inst, {}).items():
            lines.append(f"        <InitialValue variable={quoteattr(name)}><Real value=\"{float(value)!r}\"/></InitialValue>")
        lines.append("      </InitialValues>")
        lines.append("    </Simulator>")
    lines.append("  </Simulators>")
    lines.append("  <Connections>")
    for a, pa, b, pb in ports:
        lines.append("    <VariableGroupConnection>")
        lines.append(f"      <VariableGroup simulator={quoteattr(a)} name={quoteattr(pa)}/>")
        lines.append(f"      <VariableGroup simulator={quoteattr(b)} name={quoteattr(pb)}/>")
        lines.append("    </VariableGroupConnection>")
    lines.append("  </Connections>")
    lines.append("</OspSystemStructure>")
    return "\n".join(lines) + "\n"


def run_libcosim_ports(case, ports, workdir):
    """The case through libcosim, connected only by `ports` from an OSP system structure in
    `workdir` (the FMUs and their OSP-IS files copied beside it). Returns the importer matrix's
    Result of every output, plus the inputs named in the case's scalar connections
    (`instance.input`) as libcosim set them."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    workdir = pathlib.Path(workdir)
    for path in case.models.values():
        shutil.copy(path, workdir / path.name)
        osp = path.with_name(f"{path.stem}_OspModelDescription.xml")
        assert osp.is_file(), f"{osp} is missing: `mbcosim pack` writes it beside the FMU"
        shutil.copy(osp, workdir / osp.name)
    config = workdir / "OspSystemStructure.xml"
    config.write_text(system_structure(case, ports))

    log_output_level(CosimLogLevel.ERROR)
    t0 = time.perf_counter()
    ex = CosimExecution.from_osp_config_file(osp_path=str(config))
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    idx = {inst: ex.slave_index_from_instance_name(inst) for inst in case.models}
    res = im.Result("libcosim (OSP ports)", case)
    outs = {inst: im._split(im.outputs(path)) for inst, path in case.models.items()}
    inputs = {}
    for _, _, b, y in case.connections:
        inputs.setdefault(b, []).append(im.variables(case.models[b])[y])
    for _ in range(case.n_steps):
        assert ex.step(1), "libcosim step failed"
        for inst, by in outs.items():
            for kind, get in (("Real", obs.last_real_values), ("Integer", obs.last_integer_values),
                              ("Boolean", obs.last_boolean_values)):
                if by[kind]:
                    res.append(inst, by[kind], get(idx[inst], [v.valueReference for v in by[kind]]))
        for inst, vs in inputs.items():
            res.append(inst, vs, obs.last_real_values(idx[inst], [v.valueReference for v in vs]))
    del ex, obs
    return res.finish(time.perf_counter() - t0)
