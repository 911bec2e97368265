"""`mbstudy run STUDY.toml [--scheduler ADDR | --workers N | --serial] [--out DIR]`;
`mbstudy plot STUDY.toml --results RESULTS.csv [--out DIR] [--prefix P]` redraws a study's plots
from its results table without running it (docs/parameter_studies/ is redrawn this way)."""

import argparse
import pathlib
import sys
import time

from . import analysis, driver, plots, spec
from .store import Store


def main(argv=None):
    ap = argparse.ArgumentParser(prog="mbstudy", description=__doc__)
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a study (resumes where an earlier run stopped)")
    r.add_argument("study", help="study description (TOML)")
    where = r.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of an existing Dask scheduler (tcp://host:8786)")
    where.add_argument("--workers", type=int, help="embedded LocalCluster size (default: one per core)")
    where.add_argument("--serial", action="store_true", help="no Dask: every case in this process")
    r.add_argument("--out", help="output folder (default: out/study/<study name>)")
    r.add_argument("--fmu", help="run this FMU file instead of the one the study names")
    r.add_argument("--retry-failed", action="store_true", help="run failed cases again on resume")
    r.add_argument("--no-progress", action="store_true")
    pl = sub.add_parser("plot", help="redraw a study's plots from its results CSV (no runs)")
    pl.add_argument("study", help="study description (TOML)")
    pl.add_argument("--results", required=True, help="the study's results.csv")
    pl.add_argument("--out", default=".", help="folder for the SVGs (default: the current one)")
    pl.add_argument("--prefix", default="", help="prefix of the file names (e.g. table1_)")
    args = ap.parse_args(argv)

    if args.command == "plot":
        import pyarrow.csv as pacsv

        study = spec.load(args.study)
        table = pacsv.read_csv(args.results)
        found = analysis.analyse(study, table)
        pathlib.Path(args.out).mkdir(parents=True, exist_ok=True)
        for path in plots.draw(study, table, pathlib.Path(args.out), prefix=args.prefix, found=found):
            print(f"wrote {path}")
        return 0

    study = spec.load(args.study, fmu=args.fmu)
    out = pathlib.Path(args.out or pathlib.Path("out") / "study" / study.name)
    t0 = time.perf_counter()
    table = driver.run(study, out, scheduler=args.scheduler, workers=args.workers,
                       serial=args.serial, retry_failed=args.retry_failed,
                       progress=not args.no_progress)
    status = table.column("status").to_pylist()
    found = analysis.analyse(study, table)
    written = []
    for name, rows in found.items():  # sensitivity, extremes, allowances (.parquet and .csv)
        if rows:
            Store(out).write_named(name, rows)
            written.append(out / f"{name}.parquet")
    written += plots.draw(study, table, out, found=found)
    print(f"{study.name}: {status.count('done')} done, {len(status) - status.count('done')} failed "
          f"of {len(status)} cases in {time.perf_counter() - t0:.1f} s -> "
          f"{out / 'results.parquet'}, {out / 'results.csv'}"
          + "".join(f", {p}" for p in written))
    for row in table.to_pylist():
        if row["status"] != "done":
            print(f"  case {row['case_index']} ({row['case_id']}) failed: {row['message']}", file=sys.stderr)
    _print_found(found)
    return 0


def _print_found(found):
    for r in found["sensitivity"]:
        if r["index"] in ("ST", "mu_star"):
            print(f"  {r['column']}: {r['index']}({r['variable']}) = {r['value']:.4g} +- {r['conf']:.2g}")
    for r in found["extremes"]:
        print(f"  {r['column']}: {r['statistic']} = {r['value']:.5g} [{r['low']:.5g}, {r['high']:.5g}] (n {r['n']})")
    for r in found["allowances"]:
        print(f"  {r['column']} {'>' if r['side'] == 'over' else '<'} {r['allowance']:g}: {r['count']} of {r['n']} = "
              f"{r['fraction']:.3f} "
              f"[{r['low']:.3f}, {r['high']:.3f}]")


if __name__ == "__main__":
    sys.exit(main())
