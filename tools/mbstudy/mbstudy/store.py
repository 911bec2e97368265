"""Where a study's results go: a journal of finished cases (one JSON line each, flushed as it
comes, read back to resume), then results.parquet and results.csv (one row per case: every
varied value and every figure) and, when the study keeps them, series/<case id>.parquet.

Floats go through JSON as Python's shortest round-trip repr, and into the CSV the same way, so
the Parquet, the CSV and the journal hold the same bits."""

import csv
import json
import os
import pathlib

import pyarrow as pa
import pyarrow.parquet as pq

# Columns that describe how a case ran, not what it computed (they differ between runs).
RUN_COLUMNS = ("seconds", "worker")


class Store:
    def __init__(self, out_dir):
        self.dir = pathlib.Path(out_dir)
        self.dir.mkdir(parents=True, exist_ok=True)
        self.journal = self.dir / "journal.jsonl"

    def finished(self, retry_failed=False) -> dict:
        """Rows already in the journal, by case id (a torn last line is ignored)."""
        rows = {}
        if self.journal.exists():
            text = self.journal.read_text()
            if text and not text.endswith("\n"):  # torn by a kill mid-write: cut it off
                text = text[: text.rfind("\n") + 1]
                self.journal.write_text(text)
            for line in text.splitlines():
                try:
                    row = json.loads(line)
                except json.JSONDecodeError:
                    continue
                if retry_failed and row["status"] != "done":
                    continue
                rows[row["case_id"]] = row
        return rows

    def record(self, row, series=None):
        if series is not None:
            (self.dir / "series").mkdir(exist_ok=True)
            pq.write_table(pa.table(series), self.dir / "series" / f"{row['case_id']}.parquet")
        with open(self.journal, "a") as f:
            f.write(json.dumps(row, allow_nan=True) + "\n")
            f.flush()
            os.fsync(f.fileno())

    def write_tables(self, rows):
        """results.parquet and results.csv from `rows` (ordered by case index)."""
        rows = sorted(rows, key=lambda r: r["case_index"])
        columns = []
        for r in rows:
            columns += [c for c in r if c not in columns and c not in RUN_COLUMNS]
        columns += list(RUN_COLUMNS)
        return self.write_named("results", rows, columns)

    def write_named(self, name, rows, columns=None):
        """NAME.parquet and NAME.csv from `rows` (dicts), columns in first-seen order."""
        if columns is None:
            columns = []
            for r in rows:
                columns += [c for c in r if c not in columns]
        table = pa.table({c: _column(c, [r.get(c) for r in rows]) for c in columns})
        pq.write_table(table, self.dir / f"{name}.parquet")
        with open(self.dir / f"{name}.csv", "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(columns)
            for r in rows:
                w.writerow(["" if r.get(c) is None else repr(r[c]) if isinstance(r[c], float) else r[c]
                            for c in columns])
        return table


def _column(name, values):
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return pa.array(values, pa.bool_())
    if present and all(isinstance(v, int) and not isinstance(v, bool) for v in present):
        return pa.array(values, pa.int64())
    if present and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
        return pa.array([None if v is None else float(v) for v in values], pa.float64())
    return pa.array(["" if v is None else str(v) for v in values], pa.string())
