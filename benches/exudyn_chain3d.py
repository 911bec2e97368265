"""Cost per step of the spinning 3D chain, ours against Exudyn (issue #18).

The chain of tests/common/chain3d.rs: n rods (0.1 m, 0.1 kg, radius 1 cm) joined by spherical
joints, hanging from the ground at 0.5 rad from the vertical and spinning about the vertical
through the pivot at sqrt(g / L), gravity 9.81 m/s^2 along -y. Both codes integrate it in
redundant coordinates (rigid bodies with Euler parameters, joints by Lagrange multipliers) with
generalized-alpha at a fixed step of 1 ms:
  ours    `bench_core chain3d` (spectral radius 0.8, Newton to round-off, best of 3);
  Exudyn  GeneralizedAlpha with its default settings (spectral radius 0.9, modified Newton) and
          the EigenSparse linear solver, CPU time around SolveDynamic (Assemble excluded),
          best of 3.
Per size the two run one after the other (interleaved), so both see the same machine load.
Printed: time per step, the cost-per-step exponent from the first to the last size and by
least squares, and, as a check that both integrate the same motion, the far end of the last
rod after the run from both codes.

Run through benches/exudyn_chain3d.sh, which makes the venv and builds the example.
"""

import argparse
import math
import os
import subprocess
import time

import numpy as np

G = 9.81
M, L, R = 0.1, 0.1, 0.01
ANGLE = 0.5
H = 1e-3


def exudyn_chain(exu, n, steps, repeats):
    """Best CPU time [s] of `steps` fixed steps and the far end of the last rod [m]."""
    from exudyn.rigidBodyUtilities import RigidBodyInertia
    from exudyn.itemInterface import ObjectGround

    best, tip = math.inf, None
    for _ in range(repeats):
        sc = exu.SystemContainer()
        mbs = sc.AddSystem()
        prev = mbs.AddObject(ObjectGround())
        inertia = RigidBodyInertia(mass=M, inertiaTensor=np.diag([
            0.5 * M * R * R, M * (3 * R * R + L * L) / 12, M * (3 * R * R + L * L) / 12]))
        direction = np.array([math.sin(ANGLE), -math.cos(ANGLE), 0.0])
        a = ANGLE - math.pi / 2
        rot = np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0],
                        [0.0, 0.0, 1.0]])
        spin = np.array([0.0, math.sqrt(G / (n * L)), 0.0])
        for k in range(n):
            c = direction * (L * k + 0.5 * L)
            body = mbs.CreateRigidBody(
                referencePosition=c.tolist(), referenceRotationMatrix=rot,
                initialVelocity=np.cross(spin, c).tolist(),
                initialAngularVelocity=spin.tolist(), inertia=inertia,
                gravity=[0.0, -G, 0.0], show=False)
            mbs.CreateSphericalJoint(itemNumbers=[prev, body],
                                     position=(direction * L * k).tolist(), show=False)
            prev = body
        mbs.Assemble()
        s = exu.SimulationSettings()
        ti = s.timeIntegration
        ti.endTime = steps * H
        ti.numberOfSteps = steps
        ti.verboseMode = 0
        s.solution.file.write = False
        s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
        t0 = time.process_time()
        ok = mbs.SolveDynamic(s, solverType=exu.DynamicSolverType.GeneralizedAlpha)
        cpu = time.process_time() - t0
        if not ok:
            raise RuntimeError(f"Exudyn failed on n = {n}")
        best = min(best, cpu)
        tip = np.array(mbs.GetObjectOutputBody(prev, exu.OutputVariableType.Position,
                                               localPosition=[0.5 * L, 0.0, 0.0]))
    return best, tip


def ours(bench, n, steps):
    """Time per step [s] and the far end of the last rod [m] from `bench_core chain3d`."""
    env = dict(os.environ, CHAIN_SIZES=str(n), CHAIN_STEPS=str(steps), CHAIN_TIP="1")
    out = subprocess.run([bench, "chain3d"], env=env, check=True, capture_output=True,
                         text=True).stdout
    per, tip = None, None
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 3 and cells[0] == str(n):
            per = float(cells[2]) * 1e-6
        if line.startswith("tip "):
            tip = np.array([float(x) for x in line.split()[1:4]])
    if per is None:
        raise RuntimeError("bench_core chain3d printed no row for n = " + str(n) + ":\n" + out)
    return per, tip


def slope(xs, ys):
    lx, ly = np.log(xs), np.log(ys)
    return float(np.polyfit(lx, ly, 1)[0]), float((ly[-1] - ly[0]) / (lx[-1] - lx[0]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bench", required=True, help="the built bench_core example")
    ap.add_argument("--sizes", default="10,30,100,300,1000")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    import exudyn as exu

    sizes = [int(x) for x in args.sizes.split(",")]
    rows = []
    for n in sizes:
        mine, tip_ours = ours(args.bench, n, args.steps)
        theirs, tip_exu = exudyn_chain(exu, n, args.steps, args.repeats)
        theirs /= args.steps
        diff = float(np.linalg.norm(tip_ours - tip_exu)) if tip_ours is not None else math.nan
        rows.append((n, mine, theirs, diff))
        print(f"n = {n}: ours {mine * 1e6:.1f} us, Exudyn {theirs * 1e6:.1f} us per step, "
              f"tips differ by {diff:.1e} m", flush=True)
    print(f"\n## 3D chain, generalized-alpha, h = 1 ms, {args.steps} steps "
          f"(Exudyn {exu.__version__})\n")
    print("| n bodies | ours [us/step] | Exudyn [us/step] | ours / Exudyn | far end of the last rod, "
          "ours - Exudyn [m] |")
    print("|---|---|---|---|---|")
    for n, a, b, d in rows:
        print(f"| {n} | {a * 1e6:.1f} | {b * 1e6:.1f} | {a / b:.2f} | {d:.1e} |")
    if len(rows) > 1:
        xs = [r[0] for r in rows]
        for name, k in (("ours", 1), ("Exudyn", 2)):
            ls, ends = slope(xs, [r[k] for r in rows])
            print(f"\nCost-per-step exponent, {name} ({xs[0]} -> {xs[-1]} bodies): {ends:.2f} "
                  f"first to last, {ls:.2f} least squares")


if __name__ == "__main__":
    main()
