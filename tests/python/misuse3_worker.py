"""Runs the FMI 3.0 misuse cases against one unpacked FMU, each case in its own forked process.

usage: misuse3_worker.py <unzip-dir> [<other-unzip-dir>] [--case NAME ...]
<other-unzip-dir> is another model's unpacked FMI 3.0 FMU (for the cross-model state cases).
Prints one JSON object: case name -> {status, log: [[status, message], ...], stderr, exit}. A case
whose process dies is reported with its signal or exit code instead of a status.
"""

import json
import os
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fmi3raw as R  # noqa: E402
import misuse3_cases  # noqa: E402


def run_case(ctx, fn):
    status, inst = fn(ctx)
    log = [] if inst is None else [[s, m] for (s, _, m) in inst.log]
    if inst is not None:
        inst.free()
    return {"status": status, "log": log}


def in_child(ctx, fn, out, err):
    """Runs one case in a forked child; returns the child's result."""
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:
        code = 0
        try:
            os.dup2(err.fileno(), 2)
            result = run_case(ctx, fn)
        except BaseException as e:  # noqa: BLE001 - report, never crash the worker
            result = {"status": "exception", "log": [[R.FATAL, repr(e)]]}
            code = 3
        out.write(json.dumps(result).encode())
        out.flush()
        os._exit(code)
    _, wait_status = os.waitpid(pid, 0)
    out.seek(0)
    err.seek(0)
    raw = out.read().decode()
    result = json.loads(raw) if raw else {"status": "crashed", "log": []}
    result["exit"] = os.waitstatus_to_exitcode(wait_status)
    result["stderr"] = err.read().decode(errors="replace")
    return result


def main():
    args = sys.argv[1:]
    names = []
    if "--case" in args:
        k = args.index("--case")
        args, names = args[:k], args[k + 1:]
    unzip, *rest = args
    other = R.Library(rest[0]) if rest else None
    ctx = misuse3_cases.Ctx(R.Library(unzip), other)
    cases = {c[0]: c[3] for c in misuse3_cases.CASES}
    results = {}
    for name in names or list(cases):
        with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
            results[name] = in_child(ctx, cases[name], out, err)
    print(json.dumps(results))


if __name__ == "__main__":
    main()
