"""Cases per minute of a RopeBlock study (20 segments per sling, 3 s or --stop, hoist from 1 s) run
serially in one process and on a LocalCluster of 1 and of 2 single-threaded worker processes
(cluster start not counted), and the scheduler's overhead per task: the wall time per empty task
on a 1-worker cluster. Usage: study_scaling.py FMU [--cases N] [--stop S]."""

import argparse
import os
import pathlib
import tempfile
import time

from distributed import Client, LocalCluster

from mbstudy import driver, spec

STUDY = """
[study]
name = "bench"
fmu = "{fmu}"
stop_time = {stop}
step = 0.05
[fixed]
segments = 20
[random]
seed = 7
samples = {cases}
[random.vary]
mu = {{ uniform = [0.05, 0.4] }}
hoist_speed = {{ uniform = [0.05, 0.5] }}
[inputs]
hook0_vz = [[0.0, 0.0], [1.0, "hoist_speed"]]
[outputs]
hook0_load = ["peak", "initial", "mean"]
"""


def noop(i):
    return i


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("fmu")
    ap.add_argument("--cases", type=int, default=60)
    ap.add_argument("--stop", type=float, default=3.0, help="simulated time per case [s]")
    ap.add_argument("--empty-tasks", type=int, default=2000)
    a = ap.parse_args()
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="mbstudy-bench-"))
    (tmp / "bench.toml").write_text(STUDY.format(fmu=pathlib.Path(a.fmu).resolve(), cases=a.cases, stop=a.stop))
    study = spec.load(tmp / "bench.toml")
    print(f"load average before: {os.getloadavg()[0]:.2f} (cores: {os.cpu_count()})")

    t = time.perf_counter()
    table = driver.run(study, tmp / "serial", serial=True, progress=False)
    serial = time.perf_counter() - t
    per_case = sum(table.column("seconds").to_pylist()) / a.cases
    print(f"serial: {a.cases} cases in {serial:.2f} s = {60 * a.cases / serial:.0f} cases/min "
          f"({per_case * 1e3:.0f} ms per case inside the task)")

    for n in (1, 2):
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=None) as cluster, Client(cluster) as client:
            t = time.perf_counter()
            driver.run(study, tmp / f"workers{n}", client=client, progress=False)
            wall = time.perf_counter() - t
            print(f"{n} worker{'s' if n > 1 else ''}: {a.cases} cases in {wall:.2f} s = "
                  f"{60 * a.cases / wall:.0f} cases/min")
            if n == 1:
                client.submit(noop, -1).result()  # warm
                t = time.perf_counter()
                client.gather(client.map(noop, range(a.empty_tasks), pure=False))
                empty = (time.perf_counter() - t) / a.empty_tasks
                t = time.perf_counter()
                for i in range(200):
                    client.submit(noop, i, pure=False).result()
                one_by_one = (time.perf_counter() - t) / 200
                print(f"scheduler overhead per task: {empty * 1e3:.2f} ms ({a.empty_tasks} empty tasks "
                      f"in flight), {one_by_one * 1e3:.2f} ms round trip one at a time; per study "
                      f"case (1 worker - serial): {(wall - serial) / a.cases * 1e3:.1f} ms")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
