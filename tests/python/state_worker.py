"""Second process of the state test: restore a serialized FMU state and continue.

usage: state_worker.py <fmu> <unzip-dir> <state-file> <t0> <n>
Prints the output bits of the n steps from t0 as JSON (same format as Fmu.run).
"""

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import json

from conftest import Fmu

path, unzip, state_file, t0, n = sys.argv[1:]
fmu = Fmu(pathlib.Path(path), unzip)
s = fmu.slave("second-process")
s.setFMUstate(s.deSerializeFMUstate(pathlib.Path(state_file).read_bytes()))
print(json.dumps(fmu.run(s, float(t0), int(n))))
s.terminate()
s.freeInstance()
