"""FMI 3.0 in the adversarial harness: the models (dist/fmi3/*.fmu) and the `calls3` kind.

`calls3` is one sequence of fuzz3_worker.Fuzzer (the FMI 3.0 random call sequences with their
shadow state machine and invariants: no Fatal, every Discard/Error logged, the state machine's
refusals kept, no NaN after OK, lastSuccessfulTime, mutated states never deserialize), driven by
the harness's seed:index generator and counted in the harness's summary. The call generator and
its checks live in fuzz3_worker.py only.
"""

import os
import pathlib
import re

import fmi3raw as R3
from adversarial_run import ANNOUNCE
from fmpy import extract
from fuzz3_worker import Fuzzer


class Model3:
    """One unpacked FMI 3.0 FMU with its fuzzer (which holds the loaded library)."""

    fmi = 3

    def __init__(self, dist, identifier, workdir):
        self.id = identifier
        self.unzip = str(extract(str(pathlib.Path(dist) / "fmi3" / f"{identifier}.fmu"),
                                 unzipdir=str(pathlib.Path(workdir) / f"fmi3-{identifier}")))
        self.fuzzer = Fuzzer(self.unzip)
        self.lib = self.fuzzer.lib
        self.md = self.lib.md
        vs = self.md.modelVariables
        self.inputs = [v for v in vs if v.causality == "input" and v.type == "Float64" and not v.dimensions]
        self.outputs = self.fuzzer.outputs
        self.n_outputs = self.fuzzer.n_output_values
        de = self.md.defaultExperiment
        self.h = float(de.stepSize) if de and de.stepSize else 0.01
        self.values = self.fuzzer.values  # the scenario's cheaper settings (conftest.SCENARIOS)
        self.vars = self.fuzzer.vars
        assert os.path.isdir(self.unzip)


class Outcome:
    """What the pool needs of a finished sequence (as adversarial_run.Run has it)."""

    def __init__(self, violations, refused):
        self.violations, self.refused = violations, refused


def violation_class(text):
    if "not finite" in text:
        return "nan-with-ok"
    if "fmi3Fatal" in text:
        return "fatal"
    if "without a logged message" in text:
        return "no-message"
    return "fmi3-invariant"


def calls3(m, rng, index):
    """One FMI 3.0 random call sequence (fuzz3_worker.Fuzzer.sequence)."""
    f = m.fuzzer
    f.violations = []
    refusals0 = f.hist.get(R3.DISCARD, 0) + f.hist.get(R3.ERROR, 0)
    calls0 = f.calls
    f.seq, f.where = str(index), "instantiation"
    f.trace = lambda where: ANNOUNCE[0](f"fmi3 calls: {where}")
    f.sequence(rng)
    refused = f.hist.get(R3.DISCARD, 0) + f.hist.get(R3.ERROR, 0) > refusals0
    violations = [(violation_class(v), re.sub(r"^sequence \S+, ", "", v)) for v in f.violations]
    return Outcome(violations, refused), {"calls": f.calls - calls0}
