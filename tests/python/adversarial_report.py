"""Prints the tallies of adversarial.py summaries (benches/adversarial.sh).

usage: adversarial_report.py SUMMARY.json [SUMMARY.json ...]
"""

import json
import sys

ROWS = ("tried", "crashes", "hangs", "nan_with_ok", "refused_with_message", "completed", "other_violations",
        "slow_wall_only")


def report(path):
    s = json.load(open(path))
    print(f"\nadversarial, FMI {s.get('fmi', 2)}.0: {s['count']} sequences (seed {s['seed']}, kinds "
          f"{','.join(s.get('kinds', []))}, {s['workers']} workers, {s['cpu_limit']} s CPU bound) in {s['seconds']} s")
    for k in ROWS:
        label = "hangs (after replay)" if k == "hangs" else k
        print(f"  {label:26} {s[k]}")
    m = s["max_cpu"]
    if "i" in m:
        print(f"  {'largest CPU time':26} {m['seconds']:.3f} s ({m['model']} {m['kind']}, {m['outcome']}, "
              f"seed:index {s['seed']}:{m['i']})")
    print(f"  {'replayed':26} {len(s['replays'])} (each with its first and replay CPU time in {path})")
    if s.get("fields_total"):
        print(f"  {'fields forged':26} {s['fields_visited']} of {s['fields_total']}")
    print(f"  {'findings':26} {s['finding_count']} (listed in {path})")


if __name__ == "__main__":
    for p in sys.argv[1:]:
        report(p)
