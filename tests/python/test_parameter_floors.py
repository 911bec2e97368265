"""Solver settings below their floors are refused where they are set, with the floor named
(issue #25 item 1: PanelLock with BDF or DOPRI5 and h_max below 1e-8 used to panic at
fmi2ExitInitializationMode: "min > max", fmi2Fatal)."""

import re

import pytest
from conftest import Fmu, packed
from fmpy import extract

import fmi2raw


@pytest.fixture(scope="module")
def panel_lock(tmp_path_factory):
    path = packed("PanelLock")
    return Fmu(path, extract(str(path), unzipdir=str(tmp_path_factory.mktemp("floors"))))


@pytest.mark.parametrize("integrator", ["bdf", "dopri5", "gen_alpha"])
@pytest.mark.parametrize("name, value, floor", [("h_max", 1e-12, 1e-4), ("rtol", 1e-16, 1e3 * 2.0 ** -52), ("atol", 1e-20, 1e-15)])
def test_settings_below_their_floor_are_refused_with_the_floor_named(panel_lock, integrator, name, value, floor):
    lib = fmi2raw.Library(panel_lock.unzip, panel_lock.id)
    inst = fmi2raw.Instance(lib, panel_lock.guid, logging_on=True)
    items = {i.name: k + 1 for k, i in enumerate(panel_lock.vars["integrator"].declaredType.items)}
    assert inst.set_integer([panel_lock.vars["integrator"].valueReference], [items[integrator]]) == fmi2raw.OK
    status = inst.set_real([panel_lock.vars[name].valueReference], [value])
    assert status == fmi2raw.ERROR, f"{name} = {value} accepted"
    text = " ".join(inst.messages())
    named = re.search(rf"`{name}` = \S+ is below its minimum (\S+)", text)
    assert named and float(named.group(1)) == floor, text
    inst.free()
