"""The adversarial harness (adversarial.py, docs/adversarial_harness.md): a seeded slice of forged
FMU states, parameter envelopes, random call sequences, callback re-entry and serialize/deserialize
continuation (FMI 2.0), a slice of FMI 3.0 call sequences and re-entry, the data-file variants
(with the file-reading defects still open on this branch), every field of the serialized state
format forged, a valgrind memcheck run, and the regression tests of what the harness found.
The watchdog's replay is tested on fake sequences in test_adversarial_pool.py.

The benchmark (`bash benches/adversarial.sh`) runs the same harness at 100,000 FMI 2.0 and
10,000 FMI 3.0 sequences.
"""

import json
import math
import os
import pathlib
import re
import shutil
import struct
import subprocess
import sys

import pytest
from conftest import DIST, HERE, ROOT, packed

import adversarial as A
import fmi2raw as R

SEED = 25
SLICE = 3000  # ~30 s on 2 shared cores under load (with the new kinds; 6,000 of the first three took ~20 s)
SLICE3 = 1000  # ~15 s
CPU_LIMIT = 5.0
# The CI slice's kinds: all but `files`, which runs every variant on its own below (a seeded
# draw would leave most variants out and move the other kinds' seeded cases)
SLICE_KINDS = [k for k in A.KINDS if k != "files"]
# valgrind's short set: no `continuation` (a RopeBlock run under memcheck doubled the test's time)
VALGRIND_KINDS = ["forge", "envelope", "calls", "reentry"]
# seed 25: PidController forge, PanelLock forge, RopeBlock reentry, PidController envelope,
# PanelLock forge, RopeBlock forge (about 37 s CPU, most of it the set-up under memcheck)
VALGRIND_COUNT = 6


def mbcosim():
    exe = os.environ.get("MBCOSIM_BIN", str(ROOT / "target" / "release" / "mbcosim"))
    assert pathlib.Path(exe).exists(), f"{exe} is missing: build it (cargo build --release --bin mbcosim)"
    return exe


def harness(tmp_path, *args, timeout=400):
    for m in A.MODELS:
        packed(m)
    out = tmp_path / "summary.json"
    r = subprocess.run([sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
                        "--json", str(out), *map(str, args)], capture_output=True, text=True, timeout=timeout)
    assert r.returncode == 0, r.stderr[-3000:]
    return json.loads(out.read_text())


def unexpected(summary):
    """Findings that are not listed in adversarial.KNOWN_FAILURES."""
    return [f for f in summary["findings"]
            if not all(A.known_failure(f["model"], cls, text) for cls, text in f["violations"])]


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    work = tmp_path_factory.mktemp("adversarial")
    return {m: A.Model(DIST, m, work, mbcosim()) for m in A.MODELS}


def only_known(s):
    for key in ("crashes", "hangs", "nan_with_ok", "other_violations"):
        # a sequence counts once per class (as the summary counts it)
        known = sum(1 for f in s["findings"]
                    if key in {A.count_class(cls) for cls, text in f["violations"]
                               if A.known_failure(f["model"], cls, text)})
        assert s[key] == known, (key, unexpected(s)[:5])
    assert not unexpected(s), unexpected(s)[:5]


def test_seeded_slice_has_no_crash_hang_or_nan_with_ok(tmp_path, capsys):
    s = harness(tmp_path, "--seed", SEED, "--count", SLICE, "--workers", 2, "--cpu-limit", CPU_LIMIT,
                "--kinds", ",".join(SLICE_KINDS))
    assert s["tried"] == SLICE
    only_known(s)
    # every model and kind ran, and the refusals are a real share (the checks are exercised)
    assert {k.split("/")[0] for k in s["by_kind"]} == set(A.MODELS)
    assert {k.split("/")[1] for k in s["by_kind"]} == set(SLICE_KINDS)
    assert s["refused_with_message"] > SLICE // 4 and s["completed"] > SLICE // 10, s
    # the new kinds at a modest count: each re-entry fired and was refused; continuations compared
    for model in A.MODELS:
        assert s["by_kind"][f"{model}/reentry"]["refused"] >= 15, s["by_kind"]
        assert s["by_kind"][f"{model}/continuation"]["tried"] >= 15, s["by_kind"]
    assert s["max_cpu"]["seconds"] < CPU_LIMIT, s["max_cpu"]
    with capsys.disabled():
        print(f"\n[adversarial slice] {A.counts_line(s)} in {s['seconds']} s")


def test_fmi3_slice_has_no_crash_hang_or_nan_with_ok(tmp_path, capsys):
    """FMI 3.0 call sequences (fuzz3_worker's generator and invariants) and re-entry from the
    logger and the intermediate-update callback, counted like the FMI 2.0 slice."""
    for m in A.MODELS:
        packed(m)
        assert (DIST / "fmi3" / f"{m}.fmu").exists(), "pack the FMI 3.0 FMUs too (mbcosim pack)"
    s = harness(tmp_path, "--fmi", 3, "--seed", SEED, "--count", SLICE3, "--workers", 2, "--cpu-limit", CPU_LIMIT)
    assert s["tried"] == SLICE3
    only_known(s)
    assert {k.split("/")[1] for k in s["by_kind"]} == set(A.KINDS3)
    assert all(s["by_kind"][f"{m}/reentry3"]["refused"] >= 5 for m in A.MODELS), s["by_kind"]
    with capsys.disabled():
        print(f"\n[adversarial slice, FMI 3.0] {A.counts_line(s)} in {s['seconds']} s")


# Every data-file variant of each model (adversarial_files.py: scene.toml as a FIFO, /dev/zero,
# /dev/urandom, a directory, a link loop, oversized, 80,000 unknown keys, 20,000 long keys; for
# RopeBlock also 2,000 slings, 100,000 lugs and every hostile mesh named three ways, and a 10 MB
# mesh_file string), at the bound of 1 s CPU: each must be refused with a message naming
# the file, within the bound, without an unbounded read (issue #48 item 3; the bounded reader,
# docs/bounded_inputs.md). `files` is not among SLICE_KINDS so that the slice's seeded cases keep
# their kinds; this test runs every variant instead of a random draw.
FILE_CPU_LIMIT = 1.0


@pytest.mark.parametrize("model", ["PanelLock", "RopeBlock"])
def test_every_data_file_variant_is_refused_within_the_bound(model, tmp_path, capsys):
    import adversarial_files as AF
    variants = len(AF.specs(model, ""))
    s = harness(tmp_path, "--kinds", "files", "--models", model, "--seed", SEED, "--count", variants,
                "--workers", 2, "--cpu-limit", FILE_CPU_LIMIT)
    assert s["tried"] == variants
    assert s["findings"] == [], [(f["case"], f["violations"]) for f in s["findings"]]
    assert s["refused_with_message"] == variants, s
    with capsys.disabled():
        print(f"\n[adversarial files, {model}] {A.counts_line(s)} in {s['seconds']} s, "
              f"largest CPU {s.get('max_cpu')}")


@pytest.mark.parametrize("known", A.KNOWN_FAILURES, ids=lambda k: f"{k['model']}-{k['case']}")
def test_known_failures_still_fail(known, tmp_path):
    """Each accepted finding is reproduced alone (seed SEED, its case): when it stops failing
    this test fails, and the entry must go from KNOWN_FAILURES."""
    s = harness(tmp_path, "--seed", SEED, "--first", known["case"], "--count", 1, "--workers", 1,
                "--cpu-limit", CPU_LIMIT, "--kinds", ",".join(SLICE_KINDS))
    found = [(cls, text) for f in s["findings"] for cls, text in f["violations"]]
    assert found and all(A.known_failure(known["model"], cls, text) for cls, text in found), found


@pytest.mark.parametrize("model", A.MODELS)
def test_every_field_of_the_state_format_is_forged(model, tmp_path, models):
    m = models[model]
    total = sum(len(fields) for (_, _, fields) in m.bases)
    s = harness(tmp_path, "--seed", SEED, "--models", model, "--kinds", "forge", "--count", total,
                "--workers", 2, "--cpu-limit", CPU_LIMIT)
    assert s["fields_visited"] == s["fields_total"] == total, s["fields_missed"]
    assert s["crashes"] == s["nan_with_ok"] == 0, unexpected(s)[:5]
    assert not unexpected(s), unexpected(s)[:5]  # hangs only as listed in KNOWN_FAILURES
    # the model-level checks are reached: refusals name fields past the envelope's header
    assert s["refused_with_message"] > total // 2, s


@pytest.mark.parametrize("model", A.MODELS)
def test_forged_non_finite_numbers_never_pass_as_ok(model, models):
    """Regression (found by the harness): a state with NaN or inf in a model field (PanelLock
    speeds, lock times, contact forces) restored with fmi2OK and NaN outputs. Every f64 field of
    each base state, at NaN and at -inf: refused with a message, or the outputs stay finite."""
    m = models[model]
    checked = 0
    for base, data, fields in m.bases:
        for field in fields:
            if field["kind"] != "f64":
                continue
            for bad in (math.nan, -math.inf):
                span = field["spans"][0]
                body = bytearray(data[:-8])
                body[span["offset"]:span["offset"] + 8] = struct.pack("<d", bad)
                inst = m.new()
                s, handle = inst.deserialize(R.reseal(bytes(body)))
                if s == R.OK:
                    s = inst.set_state(handle)
                if s == R.OK and A.state_code(data) not in (0, None):
                    s_get, values = inst.get_real(m.outputs)
                    assert s_get == R.OK
                    assert all(math.isfinite(v) for v in values), (base, field["what"], bad, values)
                elif s != R.OK:
                    assert s == R.ERROR and inst.messages(), (base, field["what"], s)
                inst.free()
                checked += 1
    assert checked > 10


VALGRIND_HEADER = re.compile(r"^==\d+== (Invalid |Conditional jump|Use of uninitialised|Syscall param|Mismatched|"
                             r"Source and destination|Argument |[\d,]+ (\([\d,]+ direct, [\d,]+ indirect\) )?bytes in )")


def valgrind_records(text):
    """The error and leak records of a memcheck log, each as its lines (with origin stacks)."""
    records, cur = [], None
    for line in text.splitlines():
        if VALGRIND_HEADER.match(line):
            cur = [line]
            records.append(cur)
        elif re.match(r"^==\d+== (LEAK|HEAP|ERROR) SUMMARY", line):
            cur = None
        elif cur is not None:
            cur.append(line)
    return records


def test_valgrind_memcheck_of_a_short_sequence_set(tmp_path, capsys):
    """A short inline sequence set (every model, forged states, envelopes, a callback re-entry)
    under valgrind memcheck with origin tracking and full leak checking. It fails on any error
    or definite leak with a frame in the FMU's library (the error's stack, the origin of an
    uninitialised value or the allocation of a leaked block). Noise of the interpreter is
    tolerated and counted; suppressed: tests/python/valgrind.supp (docs/adversarial_harness.md)."""
    valgrind = shutil.which("valgrind")
    assert valgrind, "valgrind is missing: tests/setup_env.sh installs it"
    for m in A.MODELS:
        packed(m)
    log = tmp_path / "memcheck.log"
    env = {**os.environ, "PYTHONMALLOC": "malloc"}
    cmd = [valgrind, "--tool=memcheck", "--track-origins=yes", "--leak-check=full", "--show-leak-kinds=definite",
           "--num-callers=30", f"--suppressions={HERE / 'valgrind.supp'}", f"--log-file={log}",
           sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
           "--seed", SEED, "--count", VALGRIND_COUNT, "--inline", "--kinds", ",".join(VALGRIND_KINDS),
           "--json", str(tmp_path / "s.json")]
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=600, env=env)
    assert r.returncode == 0, r.stderr[-3000:]
    text = log.read_text()
    assert "ERROR SUMMARY" in text, text[-3000:]
    s = json.loads((tmp_path / "s.json").read_text())
    assert s["tried"] == VALGRIND_COUNT and {x["model"] for x in s["results"]} == set(A.MODELS)
    assert "reentry" in {x["kind"] for x in s["results"]}, [x["kind"] for x in s["results"]]
    assert s["violations"] == 0, [x for x in s["results"] if x["violations"]]
    records = valgrind_records(text)
    ours = [rec for rec in records if any("/binaries/linux64/" in line or "mbcosim" in line for line in rec)]
    assert not ours, "\n\n".join("\n".join(rec[:40]) for rec in ours[:3])
    with capsys.disabled():
        print(f"\n[memcheck] {len(records)} records outside the FMU (interpreter), 0 in the FMU")


@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_forged_parameter_outside_its_rules_is_refused_at_restore(models, bad):
    """Regression (found by the harness, seed 2 sequence 1383): a PidController state with
    u_max = NaN restored with fmi2OK; fmi2ExitInitializationMode then panicked in the output clamp
    ("min > max, or either was NaN", fmi2Fatal). Parameters and inputs in a state now obey the
    rules of their setters: fmi2DeSerializeFMUstate refuses the state and names the parameter."""
    m = models["PidController"]
    name, data, fields = m.bases[0]  # instantiated: outputs are not checked there
    field = next(f for f in fields if f["what"] == "value of `u_max`" and f["kind"] == "f64")
    off = field["spans"][0]["offset"]
    forged = R.reseal(data[:off] + struct.pack("<d", bad) + data[off + 8:-8])
    inst = m.new()
    s, handle = inst.deserialize(forged)
    if s == R.OK:  # before the fix: restore, initialize and see the panic
        s = max(inst.set_state(handle), inst.init(stop=10.0))
    assert s == R.ERROR, (R.STATUS_NAMES[s], inst.messages())
    assert any("`u_max`" in msg for msg in inst.messages()), inst.messages()
    inst.free()


# Regressions (found by the harness's parameter envelope): each case used to fail without
# naming the parameter (the message it gave is in the comment), or to run for minutes.
ENVELOPE_CASES = [
    # "body 'yoke': inertia tensor has non-finite entries"
    ("PanelLock", ["panel_width=1e300"], "panel_width"),
    # "PanelLock solver failed: step size fell below 9.5e-15 s ... singular Newton matrix"
    ("PanelLock", ["yoke_mass=1e300"], "yoke_mass"),
    # "linear solve produced non-finite values (singular Newton matrix)"
    ("PanelLock", ["hinge_mass=6.768156305329782e+84"], "hinge_mass"),
    # fmi2ExitInitializationMode OK with potential_energy = inf, then a non-finite Newton residual
    ("PanelLock", ["root_spring_preload=1e300"], "root_spring_preload"),
    # "latch of hinge 0: invalid contact parameter groove width w_g = 0.012: expected >= 2 r_p"
    ("PanelLock", ["pin_radius=0.01"], "pin_radius"),
    # "latch of hinge 0: invalid contact parameter groove depth d_g = 0.131: expected < cam radius R_c"
    ("PanelLock", ["groove_depth=0.13099587966577175"], "groove_depth"),
    # "panel hinge travel 3.1416 rad must be below pi (stow the panels a little open)"
    ("PanelLock", ["panel_stowed_angle=0.0"], "panel_stowed_angle"),
    # "RopeBlock could not be set up: mesh '/dev/null': ... unknown format (expected .obj or .stl)"
    ("RopeBlock", ["mesh_file=/dev/null"], "mesh_file"),
    # "no static equilibrium within the slings' strength: sling 0 carries 6.9047e9 N at rest ...
    # (the block is too heavy for this sling: lower block_mass, or use stronger slings ...)"
    ("RopeBlock", ["ground_contact=1", "ground_height=1000"], "ground_height"),
    # "no static equilibrium found in 300 iterations: largest force imbalance 1.381e-2 N (... e.g.
    # block_mass against rope_ea, or too few segments, also ends here)" (benchmark seed 1, 35000)
    ("RopeBlock", ["ground_contact=1", "ground_stiffness=1e13"], "ground_stiffness"),
    # h_max at its floor: a 0.01 s step is 1e6 integrator steps; it failed after 200,000 of them
    # ("more than 200000 steps in one call"), 5-15 s CPU per doStep (benchmark seed 1, 3484)
    ("PanelLock", ["h_max=1e-8", "integrator=3"], "h_max"),
    # dopri5 at 263 segments: one 0.05 s step took 193 s CPU (a hang under any CPU bound)
    ("RopeBlock", ["integrator=3", "segments=263"], "segments"),
    # a winch pay-out rate of -375 m/s (benchmark seed 3, 63485, in a forged state: the slings
    # shortened by 19 m per step and the solver crawled); hook inputs are bounded to 10 m/s
    ("RopeBlock", ["hook0_payout_rate=-375.43499227333064"], "hook0_payout_rate"),
    # dopri5 at the stability boundary of the rope damping: 125,000 steps of 4e-7 s per 0.05 s
    # step (34 s CPU; known failure 2 of the benchmark); now refused as stiff after 1,000 steps
    ("RopeBlock", ["segments=4", "rope_damping=1e9", "integrator=3"], "integrator"),
    # a 400 kN m panel spring on a 6e-5 kg panel (seeded slice 25, 664, when the declared ranges
    # spanned six decades): 6,000 BDF steps and 4.2 s CPU for the first 0.5 ms of a step; the
    # springs would swing the panel tip to 3.5e5 m/s. Within today's three decades: 1.3e3 m/s,
    # refused above 100 m/s
    ("PanelLock", ["panel_spring_preload=400", "panel_areal_density=1.5e-3", "gravity_on=1"],
     "panel_spring_preload"),
    # the same on a narrow panel (slice 25, 2890: 1.5 um wide, 119 km yoke)
    ("PanelLock", ["yoke_length=118.867", "panel_width=1.5e-3", "panel_spring_preload=400"],
     "panel_spring_preload"),
    # atol at 5e-324 (slice 25, 4687): every integrator failed in its first step blaming
    # stiffness or singular accelerations; refused below 1e-15
    ("PanelLock", ["atol=5e-324"], "atol"),
    # a millimetre yoke under a 600 N m root spring (benchmark seed 4, 82039): a hang with BDF;
    # generalized-alpha stops in 0.3 s ("the step this tolerance needs (8.4e-9 s) ...") and the
    # message now names the springs and the yoke (it turns at about 1e4 rad/s)
    # (on generalized-alpha: `auto` runs this rigid array on dopri5_tree, which completes it)
    ("PanelLock", ["integrator=1", "yoke_length=0.001", "root_spring_preload=600.0"], "yoke_length"),
    # dopri5 on a stiff ground contact at atol 1e-12 (known failure 1): steps of 3e-7 s
    ("RopeBlock", ["segments=4", "gravity=20", "integrator=3", "atol=1e-12", "ground_contact=1",
                   "ground_slip_speed=1e-6", "contact=0"], "integrator"),
    # the cases flexible_panels = true alone (10 modes) opened to the envelope kind (2026-12-07):
    # "dopri5-tree: body `satellite` is not connected to the ground by joints" (benchmark seed 7,
    # 60055) and "body `panel1` is flexible (modal)" (62815) named no parameter
    ("PanelLock", ["integrator=4", "free_satellite=1"], "free_satellite"),
    ("PanelLock", ["integrator=4", "flexible_panels=1"], "flexible_panels"),
    # "bending rigidity D [N m] must be > 0, got 0" (slice 25, 853)
    ("PanelLock", ["flexible_panels=1", "panel_youngs_modulus=5e-324"], "panel_youngs_modulus"),
    # 1 + nu ~ 1e-16: "K_ii is singular" (seed 7, 54955) or 124 s CPU to max_steps (28537)
    ("PanelLock", ["flexible_panels=1", "panel_poisson=-0.9999999999999999"], "panel_poisson"),
]


@pytest.mark.parametrize("model,values,named", ENVELOPE_CASES, ids=[" ".join(c[1]) for c in ENVELOPE_CASES])
def test_envelope_refusals_name_the_parameter(model, values, named, tmp_path):
    """Each case is refused naming the parameter, within 4 s CPU for the whole process (the
    harness's own set-up takes about 0.6 s; the slowest case, DOPRI5 on a rope damped at 1e9 N s,
    about 1.5 s for the 1,000 steps that show it stiff: 2.1 s in all after the rig work, over the
    2 s this bound had, against 34 s before the stiffness refusal)."""
    import resource

    packed(model)
    out = tmp_path / "case.json"

    def cpu_bound():
        resource.setrlimit(resource.RLIMIT_CPU, (4, 5))

    try:
        r = subprocess.run([sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
                            "--models", model, "--json", str(out), "--values", *values],
                           capture_output=True, text=True, timeout=60, preexec_fn=cpu_bound)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{model} {values}: no answer within 60 s")
    assert r.returncode == 0, f"exit {r.returncode} (killed over 4 s CPU?): {r.stderr[-2000:]}"
    case = json.loads(out.read_text())
    assert case["refused"], case
    assert not case["violations"], case["violations"]
    assert re.search(rf"\b{named}\b", case["messages"]), case["messages"]


# Cases that once ran past the CPU bound and now complete: each must initialize and take its
# steps with finite outputs within 2 s CPU for the whole process.
COMPLETING_CASES = [
    # gravity off with 200 segments per sling (known failure 0 of the benchmark): gen-alpha's
    # energy check rejected every step of the scene at rest (1e-20 J in play, gains of 1e-20 J
    # from the dissipation's quadrature): 9,000 rejections and 10 s CPU per 0.05 s step
    ("RopeBlock", ["segments=200", "gravity_on=0"]),
    ("RopeBlock", ["segments=200", "gravity=0"]),
    # BDF at rtol 1e-10 in the two-hook scene (known failure 3): 85,000 steps, half of them
    # rejected, 18 s CPU in the first 0.05 s; BDF now holds the positions' error only in
    # RopeBlock (Settings::error_includes_speeds), 1,742 steps for three 0.05 s steps
    ("RopeBlock", ["segments=4", "integrator=2", "rtol=1e-10", "scenario=1", "atol=4e-10"]),
    # panels of 7.5e5 m (in the six-decade envelope of then; benchmark seed 3, 90970): the
    # initial projection asked for 1e-13 m, below the round-off of such coordinates, and the
    # refusal named no parameter; today's envelope ends at 2000 m, where coordinates of 6e3 m
    # carry 1e-12 m of round-off, still above what was asked
    ("PanelLock", ["panel_length=2000"]),
]


def test_bdf_with_many_segments_stops_naming_the_integrator_within_the_bound(tmp_path):
    """BDF with 240 segments per sling in the two-hook scene (known failure 5 of the benchmark:
    263 s CPU for three 0.05 s steps) stops within the harness's 5 s CPU bound, naming the
    integrator (a contact node's stick/slip decision that BDF does not settle)."""
    import resource

    packed("RopeBlock")
    out = tmp_path / "case.json"

    def cpu_bound():
        resource.setrlimit(resource.RLIMIT_CPU, (5, 6))

    r = subprocess.run([sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
                        "--models", "RopeBlock", "--json", str(out), "--values", "segments=240", "scenario=1",
                        "integrator=2"],
                       capture_output=True, text=True, timeout=120, preexec_fn=cpu_bound)
    assert r.returncode == 0, f"exit {r.returncode} (killed over 5 s CPU?): {r.stderr[-2000:]}"
    case = json.loads(out.read_text())
    assert not case["violations"], case["violations"]
    if case["refused"]:
        assert re.search(r"\bintegrator\b", case["messages"]), case["messages"]


@pytest.mark.parametrize("model,values", COMPLETING_CASES, ids=[" ".join(c[1]) for c in COMPLETING_CASES])
def test_envelope_cases_complete_within_the_cpu_bound(model, values, tmp_path):
    """Each case initializes and takes its steps, outputs finite, within 2 s CPU."""
    import resource

    packed(model)
    out = tmp_path / "case.json"

    def cpu_bound():
        resource.setrlimit(resource.RLIMIT_CPU, (4, 5))

    r = subprocess.run([sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
                        "--models", model, "--json", str(out), "--values", *values],
                       capture_output=True, text=True, timeout=60, preexec_fn=cpu_bound)
    assert r.returncode == 0, f"exit {r.returncode} (killed over 4 s CPU?): {r.stderr[-2000:]}"
    case = json.loads(out.read_text())
    assert not case["refused"], case
    assert not case["violations"], case["violations"]
    assert case["steps"] == 3, case


def test_forged_pay_out_rate_beyond_its_bound_is_refused(tmp_path):
    """Benchmark seed 3, sequence 63485: a RopeBlock state whose `hook0_payout_rate` was forged to
    -375 m/s is refused at restore (it crawled over the CPU bound before). Forged by the field's
    name (the replay of that sequence picks its field by position in the field map, which moves
    when the model gains variables)."""
    packed("RopeBlock")
    out = tmp_path / "forge.json"
    r = subprocess.run([sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
                        "--models", "RopeBlock", "--forge", "1", "value of `hook0_payout_rate`",
                        "-375.43499227333064", "--json", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    s = json.loads(out.read_text())
    assert s["refused"] and s["steps"] == 0 and not s["violations"], s
    assert "hook0_payout_rate" in s["messages"] and "below its minimum" in s["messages"], s


@pytest.mark.parametrize("model,base,what,value", [
    ("PanelLock", 2, "elapsed time", 20000.0),
    ("PanelLock", 1, "state time", 20000.0),
    ("RopeBlock", 1, "elapsed time", 20000.0),
    ("RopeBlock", 1, "state time", 20000.0),
    ("PidController", 1, "elapsed time", 20000.0),
])
def test_forged_times_that_disagree_are_refused(models, model, base, what, value):
    """Regression (benchmark seed 1, sequences 8743 and 77005): a PanelLock state whose clock's
    elapsed time was forged to 20000 s (the importer's time still 0.02 s) restored with fmi2OK, and
    the next 0.01 s step integrated for 16 s CPU until max_steps. The clock's start + elapsed
    must match its time, and the scene's time its clock, or the state is refused."""
    m = models[model]
    name, data, fields = m.bases[base]
    field = next(f for f in fields if f["what"] == what and f["kind"] == "f64")
    off = field["spans"][0]["offset"]
    forged = R.reseal(data[:off] + struct.pack("<d", value) + data[off + 8:-8])
    inst = m.new()
    s, handle = inst.deserialize(forged)
    assert s == R.ERROR, (name, what, R.STATUS_NAMES[s])
    assert any("time" in msg and "match" in msg for msg in inst.messages()), inst.messages()
    inst.free()


@pytest.mark.parametrize("model", ["PanelLock", "RopeBlock"])
def test_forged_integrator_step_size_is_chosen_afresh_or_refused(models, model):
    """Regression (benchmark seed 2, listed as a known failure until fixed): a PanelLock state
    whose DOPRI5 step size in the integrator memory was forged to 0 restored with fmi2OK, and
    the next step crawled to max_steps (over 5 s CPU). A step size that cannot advance (0, -0, a
    subnormal) is now chosen afresh as at the start (or refused, as BDF does with 0); a negative
    one is refused with a message. The restored run then steps with fmi2OK."""
    m = models[model]
    tried = 0
    for base, data, fields in m.bases:
        if A.state_code(data) in (0, None):
            continue  # instantiated: no integrator yet
        memory = [f for f in fields if f["what"] == "integrator memory" and f["kind"] == "f64"]
        if not memory:
            continue
        off = memory[0]["spans"][0]["offset"]  # the first value: the step size [s]
        for value in (0.0, -0.0, 5e-324, -1.0):
            inst = m.new()
            s, handle = inst.deserialize(R.reseal(data[:off] + struct.pack("<d", value) + data[off + 8:-8]))
            if value < 0.0 or s != R.OK:
                # refused (BDF takes no step size of 0 either): with a message naming the memory
                assert s == R.ERROR and any("memory" in msg for msg in inst.messages()), \
                    (base, value, R.STATUS_NAMES[s], inst.messages())
            else:
                assert inst.set_state(handle) == R.OK
                s_t, t = inst.real_status()
                assert s_t == R.OK
                s = inst.do_step(t, 0.01)
                assert s == R.OK, (base, value, R.STATUS_NAMES[s], inst.messages())
                s_get, values = inst.get_real(m.outputs)
                assert s_get == R.OK and all(math.isfinite(v) for v in values), (base, value)
            inst.free()
            tried += 1
    assert tried >= 4


def test_forged_lug_point_off_the_block_is_refused(models):
    """Regression (benchmark seed 2, sequences 53561, 60230, 89168; listed as a known failure
    until fixed): a RopeBlock state whose lug point (where a sling is fixed to the block) was
    forged to about 2.4e6 m restored with fmi2OK, and the slings' dynamics crawled for over 5 s
    CPU per step. A lug point off the block's bounding box (widened by a tenth of its diagonal)
    is refused with a message naming it; one moved by a millimetre still restores."""
    m = models["RopeBlock"]
    tried = 0
    for base, data, fields in m.bases:
        for field in fields:
            if field["what"] != "lug point" or field["kind"] != "f64":
                continue
            off = field["spans"][0]["offset"]
            (original,) = struct.unpack("<d", data[off:off + 8])
            for value, refused in ((2.4e6, True), (original + 1e-3, False)):
                inst = m.new()
                s, _ = inst.deserialize(R.reseal(data[:off] + struct.pack("<d", value) + data[off + 8:-8]))
                if refused:
                    assert s == R.ERROR and any("lug point" in msg for msg in inst.messages()), \
                        (base, value, R.STATUS_NAMES[s], inst.messages())
                else:
                    assert s == R.OK, (base, value, inst.messages())
                inst.free()
                tried += 1
    assert tried >= 4


# Envelope cases whose h_max forces many integrator steps (benchmark seed 8: 8:44621, RopeBlock at
# 382 segments with gravity off at h_max 1e-4 s), at a
# size CI can afford: the watchdog's bound for such a run (adversarial.forced_step_cpu) must
# cover what it really costs, or the harness counts slow runs as hangs.
# (PanelLock's h_max floor is 1e-4 s since the one parameter specification: 300 forced steps at
# most in an envelope run, far inside the plain bound.)
FORCED_STEP_CASES = [
    ("RopeBlock", ["segments=40", "gravity_on=0", "h_max=0.0001"]),
    ("RopeBlock", ["segments=24", "integrator=2", "h_max=0.0001"]),
]


@pytest.mark.parametrize("model,values", FORCED_STEP_CASES, ids=[" ".join(c[1]) for c in FORCED_STEP_CASES])
def test_forced_step_bound_covers_the_cost_of_a_small_h_max(model, values, tmp_path):
    """The run completes; its CPU time stays below the bound the harness gives it, and that bound
    is above the harness's plain 5 s only through the forced steps (a bound that grew without
    them would hide hangs)."""
    packed(model)
    out = tmp_path / "case.json"
    r = subprocess.run([sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
                        "--models", model, "--json", str(out), "--values", *values],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    case = json.loads(out.read_text())
    assert not case["refused"] and not case["violations"], case
    assert case["steps"] == 3, case
    assert 0 < case["cpu"] < case["budget"], case
    default = subprocess.run([sys.executable, str(HERE / "adversarial.py"), "--dist", str(DIST), "--bin", mbcosim(),
                              "--models", model, "--json", str(out), "--values", *values[:-1]],
                             capture_output=True, text=True, timeout=120)
    assert default.returncode == 0, default.stderr[-2000:]
    assert json.loads(out.read_text())["budget"] < 1.0, "the default h_max forces no bound above the harness's"
