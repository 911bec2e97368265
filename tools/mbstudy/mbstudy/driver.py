"""Runs a study's unfinished cases, serially in this process or on a Dask cluster: an embedded
LocalCluster (one single-threaded worker process per core by default) or an existing one given
by its scheduler address. Finished cases go to the store as they come; a case that fails is a
row with its message; a task whose worker died is run again by Dask (tasks are pure)."""

import os

from tqdm import tqdm

from . import cases as cases_mod
from . import fmu_run, summary
from .store import Store


def default_workers():
    return len(os.sched_getaffinity(0))


def _settings(study):
    return {
        "stop_time": study.stop_time,
        "step": study.step,
        "fixed": study.fixed,
        "inputs": study.inputs,
        "outputs": study.outputs,
        "spectrum": study.spectrum,
        "keep_series": study.keep_series,
        "scene": study.scene,
    }


def _row(study, case, result):
    r = result["row"]
    row = {"case_index": case.index, "case_id": case.id, "mark": case.mark, **case.values,
           "status": r["status"], "message": r["message"]}
    figures = {k: v for k, v in r.items() if "." in k}
    row.update(figures)
    if r["status"] == "done":
        try:
            row.update(summary.derived(study.derived, {**case.values, **figures}))  # varied values too
        except Exception as e:
            row.update(status="failed", message=f"derived columns: {e}")
    row.update(seconds=r["seconds"], worker=r["worker"])
    return row


class Progress:
    def __init__(self, total, done_before, show):
        self.bar = tqdm(total=total, initial=done_before, unit="case", disable=not show,
                        dynamic_ncols=True, desc="cases")
        self.done = self.failed = 0

    def update(self, row):
        if row["status"] == "done":
            self.done += 1
        else:
            self.failed += 1
        self.bar.set_postfix(done=self.done, failed=self.failed, refresh=False)
        self.bar.update(1)

    def close(self):
        self.bar.close()


def run(study, out_dir, scheduler=None, workers=None, client=None, serial=False,
        retry_failed=False, progress=True, on_row=None):
    """Runs what is not finished yet and writes the tables; returns the pyarrow table of every
    case of the study. `client`: an existing distributed.Client (tests); `on_row(row)` is called
    after each recorded case."""
    store = Store(out_dir)
    all_cases = cases_mod.generate(study)
    finished = store.finished(retry_failed)
    todo = [c for c in all_cases if c.id not in finished]
    fmu_bytes = study.fmu.read_bytes()
    settings = _settings(study)
    bar = Progress(len(all_cases), len(all_cases) - len(todo), progress)
    rows = {c.id: finished[c.id] for c in all_cases if c.id in finished}

    def record(case, result):
        row = _row(study, case, result)
        store.record(row, result.get("series"))
        rows[case.id] = row
        bar.update(row)
        if on_row:
            on_row(row)

    try:
        if serial:
            for c in todo:
                record(c, fmu_run.run_case(fmu_bytes, settings, c.index, c.id, c.values))
        elif todo:
            _run_dask(todo, fmu_bytes, settings, record, scheduler, workers, client)
    finally:
        bar.close()
    return store.write_tables([rows[c.id] for c in all_cases if c.id in rows])


def _run_dask(todo, fmu_bytes, settings, record, scheduler, workers, client):
    from distributed import Client, LocalCluster, as_completed

    cluster = own_client = None
    if client is None:
        if scheduler:
            client = own_client = Client(scheduler)
        else:
            cluster = LocalCluster(n_workers=workers or default_workers(), threads_per_worker=1,
                                   processes=True, host="127.0.0.1", dashboard_address=None)
            client = own_client = Client(cluster)
    try:
        fmu = client.scatter(fmu_bytes, broadcast=True)
        by_key = {}
        for c in todo:
            f = client.submit(fmu_run.run_case, fmu, settings, c.index, c.id, c.values,
                              key=f"mbstudy-case-{c.id}", pure=False)
            by_key[f.key] = (c, f)
        for f in as_completed([f for _, f in by_key.values()]):
            c, _ = by_key[f.key]
            try:
                result = f.result()
            except Exception as e:  # the task itself failed in Dask (e.g. its worker kept dying)
                result = {"row": {"status": "failed", "message": f"{type(e).__name__}: {e}",
                                  "seconds": float("nan"), "worker": ""}}
            record(c, result)
            f.release()
    finally:
        if own_client is not None:
            own_client.close()
        if cluster is not None:
            cluster.close()
