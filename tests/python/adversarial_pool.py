"""The adversarial harness's forked workers, their CPU watchdog and the replay of every hang or
slow case (docs/adversarial_harness.md, "Forked workers, watchdog and replay").

A worker is a forked child that runs its list of sequences and writes one JSON line when a
sequence starts, what it is doing, and its result (with the CPU seconds the sequence took). The
parent reads the child's CPU time from /proc/<pid>/stat. A sequence is stopped (SIGKILL, the
worker restarted at the next sequence) and becomes a *candidate* when it

- uses more than its CPU bound ("cpu"): `cpu_limit`, or more where the sequence announced the
  work it asks for (`BUDGET`: the steps a small `h_max` forces, each at a measured cost),
- runs for more than 10x its CPU bound in wall time ("wall": a loaded machine, or a stall), or
- sleeps in the kernel (state S or D) without using CPU for `cpu_limit` wall seconds
  ("blocked": an open() of a FIFO, a read that waits).

No candidate is counted by its first run. After every worker is done, each candidate is replayed
once on its own (nothing else of the harness running): a fresh process runs that seed:index
inline under the same watch. It is a hang only if the replay also goes over the CPU bound, or is
blocked again; a replay that finishes counts with its outcome (refused, completed, violation), a
replay that only overruns the wall bound while runnable is counted as `slow_wall_only`. Both CPU
times are kept in the summary's `replays`.
"""

import json
import os
import select
import signal
import subprocess
import sys
import tempfile
import time

from adversarial_run import ANNOUNCE, BUDGET, TALLIES, count_class

WALL_FACTOR = 10  # the wall bound is this times the CPU bound


def proc_stat(pid):
    """(state letter, user + system CPU seconds) of a live process (/proc/<pid>/stat)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return fields[0], (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return "?", 0.0


def cpu_seconds(pid):
    return proc_stat(pid)[1]


def wchan(pid):
    try:
        with open(f"/proc/{pid}/wchan") as f:
            return f.read().strip() or "?"
    except OSError:
        return "?"


class Watch:
    """The watch over one running sequence of process `pid`."""

    def __init__(self, pid, cpu_limit):
        self.pid, self.cpu_limit, self.base_limit = pid, cpu_limit, cpu_limit
        self.cpu0 = cpu_seconds(pid)
        self.wall0 = time.time()
        self.cpu_seen, self.cpu_seen_at = self.cpu0, self.wall0

    def allow(self, seconds):
        """Raises this sequence's CPU bound to `seconds` (never below the harness's bound)."""
        self.cpu_limit = max(self.base_limit, float(seconds))

    def used(self):
        """(CPU seconds, wall seconds) of the sequence so far."""
        return cpu_seconds(self.pid) - self.cpu0, time.time() - self.wall0

    def verdict(self):
        """None while the sequence may go on; else "cpu", "wall" or "blocked: <wchan>"."""
        state, cpu = proc_stat(self.pid)
        now = time.time()
        if cpu != self.cpu_seen:
            self.cpu_seen, self.cpu_seen_at = cpu, now
        if cpu - self.cpu0 > self.cpu_limit:
            return "cpu"
        if state in ("S", "D") and now - self.cpu_seen_at > self.cpu_limit:
            return f"blocked: {wchan(self.pid)}"
        if now - self.wall0 > WALL_FACTOR * self.cpu_limit:
            return "wall"
        return None


class Lines:
    """JSON lines from a pipe, as they come."""

    def __init__(self, fd):
        self.fd, self.buf = fd, ""

    def read(self):
        chunk = os.read(self.fd, 1 << 16).decode()
        if not chunk:
            return None
        self.buf += chunk
        *done, self.buf = self.buf.split("\n")
        return [json.loads(x) for x in done if x]


class Worker:
    """A forked child running sequences `indices` in order; reports one JSON line each."""

    def __init__(self, job, indices, errdir):
        self.indices = list(indices)
        self.errfile = tempfile.TemporaryFile(dir=errdir)
        r, w = os.pipe()
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:  # child
            os.close(r)
            os.dup2(self.errfile.fileno(), 2)
            out = os.fdopen(w, "w", buffering=1)
            os._exit(stream(job, self.indices, out))
        os.close(w)
        self.pid = pid
        self.fd = r
        self.lines = Lines(r)
        self.current = None
        self.case = ""
        self.field = None
        self.meta = {}
        self.watch = None

    def stderr_tail(self):
        self.errfile.seek(0)
        return self.errfile.read()[-1500:].decode(errors="replace")


def stream(job, indices, out):
    """Runs `indices` of `job` writing the protocol's lines to `out`; the exit code."""
    ANNOUNCE[0] = lambda text, field=None: out.write(json.dumps({"doing": text[:600], "field": field}) + "\n")
    BUDGET[0] = lambda seconds: out.write(json.dumps({"budget": seconds}) + "\n")
    try:
        for i in indices:
            out.write(json.dumps({"start": i, **job.describe(i)}) + "\n")
            cpu0 = time.process_time()
            try:
                res = job.sequence(i)
            except Exception as e:  # noqa: BLE001 - a bug of the harness: a finding, go on
                res = {"i": i, **job.describe(i), "outcome": "violation", "violations": [("harness-error", repr(e))]}
            res["cpu"] = round(time.process_time() - cpu0, 4)
            out.write(json.dumps(res) + "\n")
    except BaseException as e:  # noqa: BLE001 - a harness error, reported as such
        out.write(json.dumps({"harness_error": repr(e)}) + "\n")
        out.flush()
        return 3
    out.flush()
    return 0


class Tally:
    """The counts, per-kind counts, findings and replays of a run."""

    def __init__(self):
        self.totals = {k: 0 for k in TALLIES}
        self.totals["slow_wall_only"] = 0
        self.by_kind = {}
        self.findings = []
        self.fields = set()
        self.replays = []
        self.max_cpu = {"seconds": 0.0}

    def kind(self, meta):
        return self.by_kind.setdefault(f"{meta.get('model')}/{meta.get('kind')}",
                                       {"tried": 0, "refused": 0, "completed": 0, "violation": 0})

    def record(self, res):
        self.totals["tried"] += 1
        k = self.kind(res)
        k["tried"] += 1
        k[res["outcome"]] = k.get(res["outcome"], 0) + 1
        if "field" in res:
            self.fields.add(f"{res['model']}/{res['field']}")
        if res["outcome"] == "refused":
            self.totals["refused_with_message"] += 1
        elif res["outcome"] == "completed":
            self.totals["completed"] += 1
        if res["outcome"] in ("refused", "completed") and res.get("cpu", 0.0) > self.max_cpu["seconds"]:
            self.max_cpu = {"seconds": res["cpu"], "i": res["i"], "model": res["model"], "kind": res.get("kind"),
                            "outcome": res["outcome"]}
        for cls in {cls for cls, _ in res["violations"]}:
            self.totals[count_class(cls)] += 1
        if res["violations"]:
            self.findings.append({k: res[k] for k in res if k not in ("outcome",)})

    def lost(self, i, meta, what, text, field=None):
        """A sequence that crashed, or hung on replay, counted as such."""
        self.totals["tried"] += 1
        self.totals["crashes" if what == "crash" else "hangs"] += 1
        k = self.kind(meta)
        k["tried"] += 1
        k[what] = k.get(what, 0) + 1
        if field:  # a forged field whose run hung or crashed was visited too
            self.fields.add(f"{meta.get('model')}/{field}")
        self.findings.append({"i": i, **meta, "violations": [[what, text]]})


def run_all(job, first, count, workers, cpu_limit, replay_cmd, progress=None):
    """Runs sequences first .. first+count-1 of `job` (an object with `describe(i)` and
    `sequence(i)`) in `workers` forked children; then replays the candidates with `replay_cmd`
    (a command line to which `--first i` is appended). The summary's counts."""
    tally = Tally()
    candidates = []
    pending = [list(range(first + w, first + count, workers)) for w in range(workers)]
    errdir = tempfile.mkdtemp(prefix="adversarial-")
    live = [Worker(job, p, errdir) for p in pending if p]
    t_start = time.time()

    def rest_of(wk):
        rest = wk.indices[wk.indices.index(wk.current) + 1:]
        return Worker(job, rest, errdir) if rest else None

    while live:
        ready, _, _ = select.select([w.fd for w in live], [], [], 0.5)
        nxt = []
        for wk in live:
            replacement = wk
            if wk.fd in ready:
                lines = wk.lines.read()
                if lines is None:  # EOF: finished or died
                    _, st = os.waitpid(wk.pid, 0)
                    code = os.waitstatus_to_exitcode(st)
                    if wk.current is not None:
                        tally.lost(wk.current, {**wk.meta, "case": wk.case}, "crash",
                                   f"{wk.case}: {wk.stderr_tail()} (exit {code})", wk.field)
                        replacement = rest_of(wk)
                    elif code != 0:
                        raise RuntimeError(f"worker failed (exit {code}): {wk.stderr_tail()}")
                    else:
                        replacement = None
                else:
                    for msg in lines:
                        if "doing" in msg:
                            wk.case, wk.field = msg["doing"], msg["field"]
                        elif "budget" in msg:
                            wk.watch.allow(msg["budget"])
                        elif "start" in msg:
                            wk.current, wk.case, wk.field = msg["start"], "", None
                            wk.meta = {"model": msg.get("model"), "kind": msg.get("kind")}
                            wk.watch = Watch(wk.pid, cpu_limit)
                        elif "harness_error" in msg:
                            raise RuntimeError(f"harness error in sequence {wk.current}: {msg['harness_error']}")
                        else:
                            tally.record(msg)
                            wk.current = None
                            if progress and tally.totals["tried"] % progress == 0:
                                print(f"[{time.time() - t_start:7.0f} s] {json.dumps(tally.totals)}",
                                      file=sys.stderr, flush=True)
            if replacement is wk and wk.current is not None:
                why = wk.watch.verdict()
                if why:
                    cpu, wall = wk.watch.used()
                    os.kill(wk.pid, signal.SIGKILL)
                    os.waitpid(wk.pid, 0)
                    candidates.append({"i": wk.current, **wk.meta, "case": wk.case, "field": wk.field,
                                       "first": {"why": why, "cpu": round(cpu, 2), "wall": round(wall, 1),
                                                 "bound": wk.watch.cpu_limit}})
                    replacement = rest_of(wk)
            if replacement is not None:
                nxt.append(replacement)
        live = nxt
    for c in candidates:
        replay_candidate(c, replay_cmd, cpu_limit, tally)
    return {"first": first, "count": count, "workers": workers, "cpu_limit": cpu_limit,
            "seconds": round(time.time() - t_start, 1), **tally.totals, "max_cpu": tally.max_cpu,
            "by_kind": tally.by_kind, "replays": tally.replays, "findings": tally.findings[:200],
            "finding_count": len(tally.findings), "_fields": tally.fields}


def replay(cmd, i, cpu_limit):
    """Runs sequence `i` alone in a fresh process (`cmd --first i --count 1`, inline, streaming
    the protocol's lines) under the same watch. (verdict, result, CPU s, wall s, CPU bound s):
    verdict None with the sequence's result, or "cpu" / "wall" / "blocked: ..." / "crash"."""
    err = tempfile.TemporaryFile()  # a file, not a pipe: a chatty FMU must not block on it
    p = subprocess.Popen([*cmd, "--first", str(i), "--count", "1", "--inline", "--stream"],
                         stdout=subprocess.PIPE, stderr=err)
    lines = Lines(p.stdout.fileno())
    watch, result = None, None
    while True:
        ready, _, _ = select.select([p.stdout], [], [], 0.2)
        if ready:
            got = lines.read()
            if got is None:
                break
            for msg in got:
                if "start" in msg:
                    watch = Watch(p.pid, cpu_limit)
                elif "budget" in msg:
                    watch.allow(msg["budget"])
                elif "harness_error" in msg:
                    raise RuntimeError(f"harness error in replay {i}: {msg['harness_error']}")
                elif "outcome" in msg:
                    result = msg
        if watch is not None and result is None:
            why = watch.verdict()
            if why:
                cpu, wall = watch.used()
                p.kill()
                p.communicate()
                return why, None, cpu, wall, watch.cpu_limit
    p.communicate()
    err.seek(0)
    err = err.read().decode(errors="replace")
    cpu, wall = watch.used() if watch else (0.0, 0.0)
    bound = watch.cpu_limit if watch else cpu_limit
    if result is None:
        return "crash", {"stderr": err[-1500:], "exit": p.returncode}, cpu, wall, bound
    return None, result, result["cpu"], wall, bound


def replay_candidate(c, cmd, cpu_limit, tally):
    """Replays candidate `c` and counts it by the replay's verdict."""
    why, res, cpu, wall, bound = replay(cmd, c["i"], cpu_limit)
    first = c["first"]
    entry = {"i": c["i"], "model": c.get("model"), "kind": c.get("kind"), "case": c["case"][:300], "first": first,
             "replay": {"why": why or "finished", "cpu": round(cpu, 2), "wall": round(wall, 1), "bound": bound}}
    meta = {"model": c.get("model"), "kind": c.get("kind"), "case": c["case"]}
    told = (f"{c['case']}: first run stopped ({first['why']}) at {first['cpu']} s CPU / {first['wall']} s wall; "
            f"replay alone: ")
    if why == "cpu" or (why or "").startswith("blocked"):
        entry["verdict"] = "hang"
        tally.lost(c["i"], meta, "hang", told + f"{why} at {cpu:.2f} s CPU / {wall:.1f} s wall "
                                         f"(bound {bound:.3g} s CPU)", c.get("field"))
    elif why == "crash":
        entry["verdict"] = "crash"
        tally.lost(c["i"], meta, "crash", told + f"crashed (exit {res['exit']}): {res['stderr']}", c.get("field"))
    elif why == "wall":
        entry["verdict"] = "slow (wall only)"
        tally.totals["tried"] += 1
        tally.totals["slow_wall_only"] += 1
    else:
        entry["verdict"] = res["outcome"]
        tally.record(res)
    tally.replays.append(entry)
