"""CPU time per fmi2DoStep against the communication step, through fmpy exactly as a user runs
the FMUs, next to the native run of the same model on the same time grid (`mbcosim simulate`,
which also reads every output at every point): the difference is the cost of the FMI layer plus
fmpy's Python calls.

usage: python benches/fmu_overhead.py DIST_DIR MBCOSIM_BIN OUT_DIR [--quick]
Writes OUT_DIR/fmu_overhead.csv and OUT_DIR/fmu_overhead.md.
"""

import pathlib
import re
import subprocess
import sys
import time

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

# Simulated time per model [s]; models not listed run 10 s.
STOP = {"PanelLock": 10.0, "RopeBlock": 2.0, "PidController": 10.0}


def fmu_run(path, unzip, stop, h):
    md = read_model_description(str(path))
    outs = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    s = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName="bench")
    t0 = time.perf_counter()
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    n = int(round(stop / h))
    for k in range(n):
        s.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
        s.getReal(outs)
    wall = time.perf_counter() - t0
    s.terminate()
    s.freeInstance()
    return wall, n


def native_run(binary, model, stop, h):
    r = subprocess.run([binary, "simulate", model, "--stop", repr(stop), "--step", repr(h),
                        "--out", "/dev/null", "--timing"], capture_output=True, text=True, check=True)
    m = re.search(r"timing: ([0-9.eE+-]+) s wall", r.stderr)
    return float(m.group(1))


def main():
    dist, binary, out = pathlib.Path(sys.argv[1]), sys.argv[2], pathlib.Path(sys.argv[3])
    quick = "--quick" in sys.argv
    steps = [1e-2, 1e-1] if quick else [1e-3, 1e-2, 1e-1, 1.0]
    repeats = 1 if quick else 3
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for path in sorted(dist.glob("*.fmu")):
        model = path.stem
        unzip = extract(str(path))
        stop = STOP.get(model, 10.0)
        for h in steps:
            fmu = min(fmu_run(path, unzip, stop, h)[0] for _ in range(repeats))
            n = int(round(stop / h))
            nat = min(native_run(binary, model, stop, h) for _ in range(repeats))
            rows.append((model, stop, h, n, fmu, nat))
            print(f"{model} h={h:g}: fmpy {fmu:.4f} s, native {nat:.4f} s", file=sys.stderr)
    with open(out / "fmu_overhead.csv", "w") as f:
        f.write("model,stop_s,step_s,steps,fmpy_wall_s,native_wall_s,us_per_step_fmpy,us_per_step_native,overhead_us_per_step\n")
        for model, stop, h, n, fmu, nat in rows:
            f.write(f"{model},{stop},{h},{n},{fmu:.6e},{nat:.6e},{1e6 * fmu / n:.3f},{1e6 * nat / n:.3f},"
                    f"{1e6 * (fmu - nat) / n:.3f}\n")
    with open(out / "fmu_overhead.md", "w") as f:
        f.write("# FMU overhead: fmpy vs native, same model, same time grid\n\n")
        f.write(f"Best of {repeats} runs. Both read every real output at every communication point. "
                "Overhead = (fmpy - native) / steps: the FMI layer plus fmpy's Python calls "
                "(the Rust importer test measures the FMI layer alone).\n\n")
        f.write("| model | simulated [s] | step [s] | steps | fmpy [ms] | native [ms] | per step fmpy [us] | per step native [us] | overhead per step [us] |\n")
        f.write("|---|---|---|---|---|---|---|---|---|\n")
        for model, stop, h, n, fmu, nat in rows:
            f.write(f"| {model} | {stop:g} | {h:g} | {n} | {1e3 * fmu:.1f} | {1e3 * nat:.1f} | "
                    f"{1e6 * fmu / n:.1f} | {1e6 * nat / n:.1f} | {1e6 * (fmu - nat) / n:.1f} |\n")
    print(f"wrote {out / 'fmu_overhead.csv'} and {out / 'fmu_overhead.md'}")


if __name__ == "__main__":
    main()
