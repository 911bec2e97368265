"""Second process of the FMI 3.0 state test: restore a serialized FMU state and continue.

usage: fmi3_worker.py <fmu> <unzip-dir> <state-file> <t0> <n> <h>
Prints the output bits of the n steps from t0 as JSON (same format as Fmu3.run).
"""

import json
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))

from test_fmi3 import Fmu3  # noqa: E402

path, unzip, state_file, t0, n, h = sys.argv[1:]
fmu = Fmu3(pathlib.Path(path), unzip)
s = fmu.slave("second-process")
s.setFMUState(s.deserializeFMUState(pathlib.Path(state_file).read_bytes()))
print(json.dumps(fmu.run(s, float(t0), int(n), float(h))))
s.terminate()
s.freeInstance()
