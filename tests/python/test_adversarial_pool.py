"""The adversarial harness's watchdog and replay (adversarial_pool.py) on a job of fake sequences:
a hang is counted only when the replay, alone in a fresh process, also goes over the CPU bound
(or is blocked again); a first-run overrun that the replay does not repeat is counted by the
replay's outcome; the summary keeps both CPU times and the largest CPU time of a finished
sequence; a sequence that announces the work it asks for (the steps a small h_max forces) is
allowed that much CPU, and no more."""

import sys
import textwrap

from conftest import HERE

import adversarial_pool as P

CPU_LIMIT = 0.5

# index: what the sequence does. A marker file tells the replay from the first run.
FAKE = textwrap.dedent('''
    import os, sys, time
    sys.path.insert(0, {here!r})
    import adversarial_pool as P
    from adversarial_run import BUDGET

    MARK = {mark!r}

    def burn(seconds):
        t0 = time.process_time()
        while time.process_time() - t0 < seconds:
            pass

    class Job:
        def describe(self, i):
            return {{"model": "Fake", "kind": "fake"}}

        def sequence(self, i):
            first_run = not os.path.exists(f"{{MARK}}.{{i}}")
            open(f"{{MARK}}.{{i}}", "w").close()
            if i == 0:
                burn(1e9)  # a hang: over the bound in both runs
            elif i == 1:
                os.read(os.open(f"{{MARK}}.fifo", os.O_RDONLY), 1)  # blocked (the FIFO has no writer)
            elif i == 2 and first_run:
                burn(1e9)  # over the bound only in the first run
            elif i == 3:
                burn(0.2)
            elif i == 4:
                BUDGET[0](3 * {limit})  # announced work: 1.5x the harness's bound is allowed
                burn(1.5 * {limit})
            elif i == 5:
                BUDGET[0](2 * {limit})  # announced, and still over it: a hang at its own bound
                burn(1e9)
            return {{"i": i, "model": "Fake", "kind": "fake", "outcome": "completed", "violations": []}}

    if __name__ == "__main__":
        args = sys.argv[1:]
        first = int(args[args.index("--first") + 1])
        count = int(args[args.index("--count") + 1])
        if "--stream" in args:
            sys.exit(P.stream(Job(), range(first, first + count), sys.stdout))
''')


def test_hangs_are_counted_only_when_the_replay_repeats_them(tmp_path):
    import os

    mark = str(tmp_path / "mark")
    os.mkfifo(f"{mark}.fifo")
    script = tmp_path / "fake_job.py"
    script.write_text(FAKE.format(here=str(HERE), mark=mark, limit=CPU_LIMIT))
    sys.path.insert(0, str(tmp_path))
    try:
        import fake_job
    finally:
        sys.path.pop(0)
    s = P.run_all(fake_job.Job(), 0, 6, 2, CPU_LIMIT, [sys.executable, str(script)])
    assert s["tried"] == 6, s
    assert s["hangs"] == 3 and s["crashes"] == 0 and s["completed"] == 3, s
    verdicts = {r["i"]: (r["first"]["why"], r["replay"]["why"], r["verdict"]) for r in s["replays"]}
    assert verdicts[0] == ("cpu", "cpu", "hang"), verdicts
    assert verdicts[1][0].startswith("blocked") and verdicts[1][1].startswith("blocked") and verdicts[1][2] == "hang"
    assert verdicts[2] == ("cpu", "finished", "completed"), verdicts  # replayed, not counted as a hang
    assert 4 not in verdicts, verdicts  # within its announced bound: never a candidate
    assert verdicts[5] == ("cpu", "cpu", "hang"), verdicts
    budgeted = next(r for r in s["replays"] if r["i"] == 5)
    assert budgeted["first"]["bound"] == budgeted["replay"]["bound"] == 2 * CPU_LIMIT, budgeted
    assert 2 * CPU_LIMIT < budgeted["first"]["cpu"] < 3 * CPU_LIMIT, budgeted
    for r in s["replays"]:
        assert "cpu" in r["first"] and "cpu" in r["replay"], r
    hang = next(r for r in s["replays"] if r["i"] == 0)
    assert hang["first"]["cpu"] > CPU_LIMIT and hang["replay"]["cpu"] > CPU_LIMIT, hang
    # the largest CPU time of a finished sequence: sequence 4's 0.75 s, within its own bound
    assert s["max_cpu"]["i"] == 4 and 1.5 * CPU_LIMIT <= s["max_cpu"]["seconds"] < 3 * CPU_LIMIT, s["max_cpu"]
