"""Runs misuse cases against one unpacked FMU, each case in its own forked process.

usage: misuse_worker.py <unzip-dir> <model-identifier> [case ...]   (all cases by default)
Prints one JSON object: case name -> {status, messages, stderr, exit}. A case whose process dies
is reported with its signal or exit code instead of a status.
"""

import json
import os
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fmi2raw as R
import misuse_cases
from fmpy import read_model_description


def run_case(ctx, fn):
    status, inst = fn(ctx)
    messages = [] if inst is None else inst.messages()
    if inst is not None:
        inst.free()
    return {"status": status, "messages": messages}


def main():
    unzip, identifier, *names = sys.argv[1:]
    md = read_model_description(os.path.join(unzip, "modelDescription.xml"))
    ctx = misuse_cases.Ctx(R.Library(unzip, identifier), md)
    cases = {n: (n, s, snip, fn) for (n, s, snip, fn) in misuse_cases.CASES}
    results = {}
    for name in names or list(cases):
        fn = cases[name][3]
        with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
            sys.stdout.flush()
            sys.stderr.flush()
            pid = os.fork()
            if pid == 0:
                code = 0
                try:
                    os.dup2(err.fileno(), 2)
                    result = run_case(ctx, fn)
                except BaseException as e:  # noqa: BLE001 - report, never crash the worker
                    result = {"status": "exception", "messages": [repr(e)]}
                    code = 3
                out.write(json.dumps(result).encode())
                out.flush()
                os._exit(code)
            _, wait_status = os.waitpid(pid, 0)
            out.seek(0)
            err.seek(0)
            raw = out.read().decode()
            result = json.loads(raw) if raw else {"status": "crashed", "messages": []}
            result["exit"] = os.waitstatus_to_exitcode(wait_status)
            result["stderr"] = err.read().decode(errors="replace")
            results[name] = result
    print(json.dumps(results))


if __name__ == "__main__":
    main()
