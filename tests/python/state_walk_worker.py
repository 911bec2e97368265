"""Second process of the state walk (test_state_walk.py): restore every recorded state, step once.

usage: state_walk_worker.py <walk.pickle>

The pickle holds the FMU (path, unzip folder), the communication points t_k, the step h, the
serialized state recorded at every t_k and the inputs set before the step from t_k (a list of
(value reference, value) per point, Real inputs; empty lists when the run has none). One fresh
instance (instantiated only) restores the states in order, reads the outputs right after each
restore and, after setting point k's inputs, after one doStep from t_k, and prints one JSON object
per point: {"k", "restored", "stepped"} (output texts as `outputs` gives them) or {"k", "error"}
when a call fails (the walk then goes on with the next state).

With "continue_from" = k0 in the pickle, a last line {"continued": [...]} follows: a second fresh
instance restores state k0 only and runs from t_k0 to the end with the recorded inputs, the
outputs after every step (what the original run gave after steps k0, k0 + 1, ...).

`outputs` is shared with the test: every output (Real as exact bits, Integer, Boolean).
"""

import json
import pathlib
import pickle
import sys

from fmpy.fmi2 import FMU2Slave

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from conftest import bits  # noqa: E402


class Outputs:
    """Reads every output of a model description, as exact texts, in one fixed order."""

    def __init__(self, md):
        outs = [v for v in md.modelVariables if v.causality == "output"]
        self.real = [v for v in outs if v.type == "Real"]
        self.integer = [v for v in outs if v.type in ("Integer", "Enumeration")]
        self.boolean = [v for v in outs if v.type == "Boolean"]
        self.names = [v.name for v in self.real + self.integer + self.boolean]

    def read(self, slave):
        row = []
        if self.real:
            row += [bits(x) for x in slave.getReal([v.valueReference for v in self.real])]
        if self.integer:
            row += [str(int(x)) for x in slave.getInteger([v.valueReference for v in self.integer])]
        if self.boolean:
            row += ["1" if x else "0" for x in slave.getBoolean([v.valueReference for v in self.boolean])]
        return row


def set_inputs(slave, inputs):
    """Sets the Real inputs `inputs`, a list of (value reference, value)."""
    if inputs:
        slave.setReal([vr for vr, _ in inputs], [v for _, v in inputs])


def restore(slave, data):
    """Restores serialized state `data` into `slave` (deserialize, set, free)."""
    state = slave.deSerializeFMUstate(data)
    try:
        slave.setFMUstate(state)
    finally:
        slave.freeFMUstate(state)


def restore_and_step(slave, outputs, data, t, h, inputs=()):
    """Restores serialized state `data` into `slave`; outputs right after and, with `inputs` set,
    after one step."""
    restore(slave, data)
    restored = outputs.read(slave)
    set_inputs(slave, inputs)
    slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
    return restored, outputs.read(slave)


def new_slave(md, unzip, name):
    slave = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=name)
    slave.instantiate()
    return slave


def main(walk_file):
    from fmpy import read_model_description

    walk = pickle.loads(pathlib.Path(walk_file).read_bytes())
    md = read_model_description(walk["fmu"])
    outputs = Outputs(md)
    inputs = walk.get("inputs") or [[] for _ in walk["times"]]
    slave = new_slave(md, walk["unzip"], "walk-second-process")
    for k, (t, data) in enumerate(zip(walk["times"], walk["states"])):
        try:
            restored, stepped = restore_and_step(slave, outputs, data, t, walk["h"], inputs[k])
            line = {"k": k, "restored": restored, "stepped": stepped}
        except Exception as e:  # noqa: BLE001 - reported per point to the parent
            line = {"k": k, "error": f"{type(e).__name__}: {e}"}
        print(json.dumps(line))
    slave.freeInstance()
    k0 = walk.get("continue_from")
    if k0 is not None:
        slave = new_slave(md, walk["unzip"], "walk-second-process-continued")
        restore(slave, walk["states"][k0])
        continued = []
        for k in range(k0, len(walk["times"])):
            set_inputs(slave, inputs[k])
            slave.doStep(currentCommunicationPoint=walk["times"][k], communicationStepSize=walk["h"])
            continued.append(outputs.read(slave))
        print(json.dumps({"continued": continued}))
        slave.freeInstance()


if __name__ == "__main__":
    main(sys.argv[1])
