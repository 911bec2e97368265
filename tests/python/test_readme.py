"""The README's fmpy snippet runs as it stands (with dist/ pointing at the packed FMUs), and its
numbers are right: PanelLock against the native solver on the same grid (bit for bit) and the
known lock window; RopeBlock against the hoist it commands (block rise = hook rise, hook load
= the block's weight)."""

import re
import warnings

import numpy as np
from conftest import DIST, ROOT, native_table


def _snippet():
    text = (ROOT / "README.md").read_text()
    section = text.split("## Using the FMUs from fmpy", 1)[1]
    m = re.search(r"```python\n(.*?)```", section, re.S)
    assert m, "the README's fmpy section has no python block"
    return m.group(1)


def test_readme_fmpy_snippet_runs_and_its_numbers_hold(capsys):
    code = _snippet().replace('"dist/', f'"{DIST}/')
    scope = {}
    with warnings.catch_warnings(record=True) as raised:
        warnings.simplefilter("always")
        exec(compile(code, "README.md", "exec"), scope)
    captured = capsys.readouterr()
    printed = captured.out
    assert "root hinge locked at" in printed and "hook load" in printed, printed
    # the block prints its two results and nothing else: no fmpy "Warning: missing input ..."
    # lines (27 of them before the input table had every input), no Python warnings
    lines = [x for x in (captured.out + captured.err).splitlines() if x.strip()]
    assert len(lines) == 2 and lines[0].startswith("root hinge locked at") and lines[1].startswith("hook load"), \
        "\n".join(lines)
    assert not [x for x in lines if "warning" in x.lower()], lines
    assert not raised, [str(w.message) for w in raised]

    panel = scope["panel"]
    ref = native_table("simulate", "PanelLock", "--stop", "60", "--step", "0.01", timeout=600)
    for name in ["hinge0_lock_time", "hinge0_peak_force", "hinge0_angle"]:
        assert np.array_equal(panel[name], ref[name]), name
    # the root hinge locks once, inside the window every integrator finds at tight tolerances
    assert panel["hinge0_latched"][-1]
    assert 4.8 < panel["hinge0_lock_time"][-1] < 5.1

    rope = scope["rope"]
    hook_rise = rope["hook0_z"][-1] - rope["hook0_z"][0]
    block_rise = rope["block_z"][-1] - rope["block_z"][0]
    # the commanded speed is reached between 1 s and 2 s (fmpy ramps the input from 1 s to
    # 1.5 s, the model reaches each command over 0.5 s): between 0.2 (4 - 2) and 0.2 (4 - 1) m
    assert 0.4 < hook_rise < 0.6, hook_rise
    # the slings keep their length: the block follows the hook (stretch changes with the load
    # swing only, a few mm at 1.96 MN on steel slings)
    assert abs(block_rise - hook_rise) < 0.02, (block_rise, hook_rise)
    weight = 200e3 * 9.81
    assert abs(rope["hook0_load"][-1] - weight) < 0.15 * weight, rope["hook0_load"][-1]


def _table1_rows(text):
    """The README's Table 1 rows: (setup, k) -> (root peak [N], locked frequency [Hz])."""
    section = text.split("## Table 1 of the solar-array paper", 1)[1].split("\n## ", 1)[0]
    rows, setup = {}, None
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) != 6 or not re.fullmatch(r"1e\d", cells[1]):
            continue
        setup = cells[0] or setup
        peak, freq = (float(c.split()[0]) for c in (cells[2], cells[4]))
        rows[(setup.split()[0], cells[1])] = (peak, freq)
    return rows


def test_readme_table1_figures_are_what_the_study_gives(tmp_path):
    """The README's Table 1 rows against fresh `mbcosim table1` runs: ours to the printed digit;
    the paper setup's root peaks (from a BDF run, 2.3 min of CPU, docs/panel_lock_table1_comparison.md)
    within 0.5 % of the same setup under the default integrator, its frequencies to the digit (the
    linearization does not depend on the integrator)."""
    import subprocess
    from test_cli import EXE
    rows = _table1_rows((ROOT / "README.md").read_text())
    assert set(rows) == {("ours", "1e7"), ("ours", "1e8"), ("paper", "1e7"), ("paper", "1e8")}, rows

    def study(*args):
        out = tmp_path / "_".join(args or ("ours",)).replace("=", "-")
        subprocess.run([EXE, "table1", "--out", str(out), *args], check=True, capture_output=True, timeout=600)
        got = {}
        for line in (out / "panel_lock_table1.csv").read_text().splitlines()[1:]:
            c = dict(zip((out / "panel_lock_table1.csv").read_text().splitlines()[0].split(","), map(float, line.split(","))))
            if c["n"] == 1.5:
                got[f"1e{round(np.log10(c['k']))}"] = (c["peak_force0"], c["linear_frequency_hz"])
        return got

    ours, loop = study(), study("--set", "cable_loop=true")
    for k in ("1e7", "1e8"):
        assert rows[("ours", k)] == (round(ours[k][0], 1), round(ours[k][1], 3)), (k, rows[("ours", k)], ours[k])
        peak, freq = rows[("paper", k)]
        assert abs(peak / loop[k][0] - 1) < 5e-3, (k, peak, loop[k])
        assert freq == round(loop[k][1], 3), (k, freq, loop[k])


def test_readme_calibration_figure_is_what_calibrate_gives(tmp_path):
    """The README's best calibration setting (restitution 0.5, preloads x 1.25, 70 mm cam) run
    through `mbcosim calibrate` alone: its worst residual against the paper's four Table 1
    numbers is the README's +8.2 %, within 10 %."""
    import re
    import subprocess
    from test_cli import EXE
    text = (ROOT / "README.md").read_text()
    m = re.search(r"\(restitution ([\d.]+), preloads x ([\d.]+), (\d+) mm cam\) comes within 10 % of all four "
                  r"\(worst \+([\d.]+) %\)", text.replace("\n", " "))
    assert m, "the README's calibration sentence"
    e, scale, cam_mm, worst = m.groups()
    out = tmp_path / "cal"
    subprocess.run([EXE, "calibrate", "--restitution", e, "--preload-scale", scale, "--cam-radius",
                    str(int(cam_mm) / 1000), "--out", str(out)], check=True, capture_output=True, timeout=600)
    lines = (out / "panel_lock_calibration.csv").read_text().splitlines()
    row = dict(zip(lines[0].split(","), map(float, lines[1].split(","))))
    assert round(100 * row["worst"], 1) == float(worst), row
    assert row["worst"] <= 0.10, row


def test_readme_adversarial_figures_are_the_recorded_run():
    """The README's figures of the latest adversarial benchmark run are those of the summaries the
    run wrote (docs/adversarial/summary-seed<S>.json, summary3-seed<S>.json), to the digit."""
    import json

    text = " ".join((ROOT / "README.md").read_text().split())
    m = re.search(r"Its latest run \(seed (\d+), .*?\): FMI 2\.0 ([\d,]+) sequences, (\d+) crashes, (\d+) hangs, "
                  r"(\d+) NaN with status OK, ([\d,]+) refused with a message, ([\d,]+) completed, (\d+) other "
                  r"violations?\b.*?largest CPU time ([\d.]+) s .*?FMI 3\.0 ([\d,]+) sequences, nothing found "
                  r"\(largest CPU time ([\d.]+) s\)", text)
    assert m, "the README's adversarial paragraph changed shape"
    seed, *figures = m.groups()
    num = [float(x.replace(",", "")) for x in figures]
    s2 = json.loads((ROOT / f"docs/adversarial/summary-seed{seed}.json").read_text())
    s3 = json.loads((ROOT / f"docs/adversarial/summary3-seed{seed}.json").read_text())
    assert num[:7] == [s2[k] for k in ("tried", "crashes", "hangs", "nan_with_ok", "refused_with_message",
                                       "completed", "other_violations")], (num, s2)
    assert abs(num[7] - s2["max_cpu"]["seconds"]) < 0.05, (num[7], s2["max_cpu"])
    assert num[8] == s3["tried"] and s3["crashes"] == s3["hangs"] == s3["nan_with_ok"] == 0, s3
    assert s3["other_violations"] == 0 and abs(num[9] - s3["max_cpu"]["seconds"]) < 0.005, (num[9], s3["max_cpu"])
