"""Second process of the state walk (test_state_walk.py): restore every recorded state, step once.

usage: state_walk_worker.py <walk.pickle>

The pickle holds the FMU (path, unzip folder), the communication points t_k, the step h and the
serialized state recorded at every t_k. One fresh instance (instantiated only) restores the
states in order, reads the outputs right after each restore and after one doStep from t_k, and
prints one JSON object per point: {"k", "restored", "stepped"} (output texts as `outputs` gives
them) or {"k", "error"} when a call fails (the walk then goes on with the next state).

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


def restore_and_step(slave, outputs, data, t, h):
    """Restores serialized state `data` into `slave`; outputs right after and after one step."""
    state = slave.deSerializeFMUstate(data)
    try:
        slave.setFMUstate(state)
    finally:
        slave.freeFMUstate(state)
    restored = outputs.read(slave)
    slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
    return restored, outputs.read(slave)


def main(walk_file):
    from fmpy import read_model_description

    walk = pickle.loads(pathlib.Path(walk_file).read_bytes())
    md = read_model_description(walk["fmu"])
    outputs = Outputs(md)
    slave = FMU2Slave(guid=md.guid, unzipDirectory=walk["unzip"],
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="walk-second-process")
    slave.instantiate()
    for k, (t, data) in enumerate(zip(walk["times"], walk["states"])):
        try:
            restored, stepped = restore_and_step(slave, outputs, data, t, walk["h"])
            line = {"k": k, "restored": restored, "stepped": stepped}
        except Exception as e:  # noqa: BLE001 - reported per point to the parent
            line = {"k": k, "error": f"{type(e).__name__}: {e}"}
        print(json.dumps(line))
    slave.freeInstance()


if __name__ == "__main__":
    main(sys.argv[1])
