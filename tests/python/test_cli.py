"""The mbcosim command line (issue #23): --help on every command, model and variable names with
did-you-mean, typed --set, input schedules, output selection, units in the CSV header, partial CSV
on failure, paths relative to the current directory, progress only when asked for or on a
terminal. Drives the built binary (MBCOSIM_BIN, as test_adversarial.py); needs no FMU."""

import csv
import io
import os
import pathlib
import subprocess

import pytest
from conftest import ROOT

EXE = os.environ.get("MBCOSIM_BIN", str(ROOT / "target" / "release" / "mbcosim"))
COMMANDS = ["pack", "model-descriptions", "demo", "readme-figures", "simulate", "models", "variables", "report",
            "table1", "calibrate", "state-fields"]


def run(*args, cwd=None, env=None):
    assert pathlib.Path(EXE).exists(), f"{EXE} is missing: build it (cargo build --release --bin mbcosim)"
    return subprocess.run([EXE, *map(str, args)], cwd=cwd or ROOT, capture_output=True, text=True, timeout=300,
                          env=env)


def ok(*args, **kw):
    r = run(*args, **kw)
    assert r.returncode == 0, r.stderr
    return r


def refused(*args, **kw):
    r = run(*args, **kw)
    assert r.returncode != 0, r.stdout[:500]
    assert "panicked" not in r.stderr, r.stderr
    return r.stderr


def table(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


def pid_csv(*args, cwd=None):
    return table(ok("simulate", "PidController", *args, cwd=cwd).stdout)


# --- help and names -------------------------------------------------------------------------

def test_top_level_help_lists_every_command():
    out = ok("--help").stdout
    for c in COMMANDS:
        assert f"\n  {c} " in out, c


def test_help_names_both_fmi_versions():
    """The FMUs are FMI 2.0 and FMI 3.0 (dist/ and dist/fmi3/); the help said FMI 2.0 only."""
    top = ok("--help").stdout
    assert "FMI 2.0 and FMI 3.0" in " ".join(top.split()), top
    pack = " ".join(ok("pack", "--help").stdout.split())
    assert "(FMI 2.0)" in pack and "fmi3/<Model>.fmu (FMI 3.0)" in pack, pack


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_has_help(command):
    out = ok(command, "--help").stdout
    first = out.splitlines()[0]
    assert first and not first.startswith("Usage"), out  # a one-line description first
    assert f"Usage: mbcosim {command}" in out
    assert "-h, --help" in out


def test_simulate_help_documents_its_options():
    out = ok("simulate", "--help").stdout
    for opt in ["--stop", "--step", "--scene", "--set", "--inputs", "--outputs", "--out", "--header", "--timing",
                "--progress"]:
        assert opt in out, opt
    assert "PanelLock, PidController, RopeBlock" in out


def test_unknown_model_lists_the_models_and_suggests_the_nearest():
    err = refused("simulate", "PidControler")
    assert "PanelLock, PidController, RopeBlock" in err
    assert "similar value exists: 'PidController'" in err
    err = refused("simulate", "Crane")
    assert "PanelLock, PidController, RopeBlock" in err and "similar" not in err


def test_model_names_ignore_case():
    header, rows = table(ok("simulate", "pidcontroller", "--stop", "0.1", "--step", "0.1").stdout)
    assert header[0] == "time [s]" and len(rows) == 2


# --- typed --set ------------------------------------------------------------------------------

def test_integer_refuses_a_fraction_and_takes_a_whole_number():
    err = refused("simulate", "PanelLock", "--stop", "0", "--set", "n_panels=2.5")
    assert "`n_panels` is an Integer: `2.5` is not a whole number" in err
    for v in ["2", "2.0"]:  # 2.0: what the FMI tests' scripts write (float(v)!r)
        ok("simulate", "PanelLock", "--stop", "0", "--set", f"n_panels={v}")
    err = refused("simulate", "PanelLock", "--stop", "0", "--set", "n_panels=9")
    assert "above its maximum 6" in err


def test_enumeration_takes_an_item_name_or_its_number():
    def peak(v):
        _, rows = table(ok("simulate", "PanelLock", "--stop", "6", "--step", "0.05", "--set", f"contact_law={v}",
                           "--outputs", "hinge0_peak_force").stdout)
        return rows[-1][1]
    assert peak("hertz") == peak("1") == peak("HERTZ")
    assert peak("hertz") != peak("lankarani_nikravesh")  # the name reached the model: another force law
    err = refused("simulate", "PanelLock", "--stop", "0", "--set", "contact_law=herz")
    assert "did you mean `hertz`?" in err and "lankarani_nikravesh (2)" in err
    assert "not an item number" in refused("simulate", "PanelLock", "--stop", "0", "--set", "contact_law=9")


def test_set_rtol_above_its_range_is_refused():
    """Issue #43 item 3: `simulate PanelLock --set rtol=50` ran; rtol has one declared range for
    every model, [1e3 eps, 0.1] (docs/parameter_spec.md)."""
    for model in ["PanelLock", "RopeBlock"]:
        err = refused("simulate", model, "--stop", "0", "--set", "rtol=50")
        assert "`rtol` = 50.0 is above its maximum 0.1" in err, (model, err)
        ok("simulate", model, "--stop", "0", "--set", "rtol=0.1")


def test_boolean_takes_true_false_1_0_only():
    for v in ["true", "false", "1", "0"]:
        ok("simulate", "PidController", "--stop", "0", "--set", f"d_on_measurement={v}")
    for v in ["yes", "2", "1.5", ""]:
        err = refused("simulate", "PidController", "--stop", "0", "--set", f"d_on_measurement={v}")
        assert "is not true, false, 1 or 0" in err, (v, err)


def test_real_refuses_values_out_of_its_declared_range_and_non_finite_values():
    err = refused("simulate", "PidController", "--set", "Tf=-1")
    assert "`Tf` = -1.0 s is below its minimum 0.0 s" in err
    assert "finite" in refused("simulate", "PidController", "--set", "kp=inf")
    assert "finite" in refused("simulate", "PidController", "--set", "kp=1e400")
    assert "is not a number" in refused("simulate", "PidController", "--set", "kp=fast")


def test_unknown_or_read_only_variable_names_the_near_ones():
    err = refused("simulate", "PidController", "--set", "setpont=1")
    assert "no variable `setpont`; did you mean `setpoint`?" in err
    err = refused("simulate", "PidController", "--set", "u=1")
    assert "`u` is an output" in err and "cannot be set" in err
    assert "expected NAME=VALUE" in refused("simulate", "PidController", "--set", "kp")


# --- input schedules --------------------------------------------------------------------------

def _pid_reference(times, setpoint, kp, ki):
    """The PI controller with held error, integrated exactly (kd = 0, no limits): the output read
    at t_k acts on the error sampled at t_(k-1); error_k = sp(t_(k-1)) (measurement 0)."""
    u, err, integral = [0.0], [0.0], 0.0
    for k in range(1, len(times)):
        e = setpoint(times[k - 1])
        integral += ki * (times[k] - times[k - 1]) * e
        u.append(kp * e + integral)
        err.append(e)
    return u, err


def test_input_schedule_steps_the_setpoint_mid_run(tmp_path):
    (tmp_path / "steps.csv").write_text("# setpoint step at 0.5 s, back down at 0.8 s\ntime,setpoint\n0,0\n0.5,1\n0.8,0.25\n")
    header, rows = pid_csv("--stop", "1", "--step", "0.1", "--set", "kp=2", "--set", "ki=0.5",
                           "--inputs", tmp_path / "steps.csv")
    assert header == ["time [s]", "u", "error", "saturated"]
    times = [float(r[0]) for r in rows]
    assert len(times) == 11 and times[-1] == 1.0

    def sp(t):
        return 0.25 if t >= 0.8 - 1e-12 else 1.0 if t >= 0.5 - 1e-12 else 0.0
    u, err = _pid_reference(times, sp, kp=2.0, ki=0.5)
    assert [float(r[1]) for r in rows] == pytest.approx(u, rel=1e-12, abs=1e-12)
    assert [float(r[2]) for r in rows] == pytest.approx(err, abs=1e-15)
    assert float(rows[5][1]) == 0.0 and float(rows[6][1]) == pytest.approx(2.0 + 0.5 * 0.1)


def test_schedule_header_may_carry_units_from_our_own_csv(tmp_path):
    (tmp_path / "s.csv").write_text("time [s],setpoint\n0,3\n")
    _, rows = pid_csv("--stop", "0.2", "--step", "0.1", "--set", "ki=0", "--inputs", tmp_path / "s.csv")
    assert float(rows[-1][1]) == 3.0


@pytest.mark.parametrize("text, message", [
    ("time,setpont\n0,1\n", "s.csv:1, column 2: `setpont` is not an input of PidController; did you mean `setpoint`?"),
    ("time,kp\n0,1\n", "s.csv:1, column 2: `kp` is a parameter of PidController, not an input"),
    ("setpoint\n1\n", "no `time` column"),
    ("time,setpoint [m]\n0,1\n", "`setpoint` has no unit (dimensionless), the header says m"),
    ("time,setpoint\n0,1\n0.5,x\n", "s.csv:3, column 2 (`setpoint`): `setpoint` = `x` is not a number"),
    ("time,setpoint\n0,1\n0.5,2\n0.5,3\n", "s.csv:4, column 1 (`time`): time 0.5 s is not after the previous row's 0.5 s"),
    ("time,setpoint\n0,1,2\n", "s.csv:2: 3 cells, the header has 2"),
    ("time,setpoint\n", "a header and no rows"),
])
def test_schedule_errors_name_file_line_and_column(tmp_path, text, message):
    (tmp_path / "s.csv").write_text(text)
    err = refused("simulate", "PidController", "--inputs", "s.csv", cwd=tmp_path)
    assert message in err, err


# --- outputs and CSV format -------------------------------------------------------------------

def test_output_selection_keeps_the_given_order():
    header, rows = pid_csv("--stop", "0.3", "--step", "0.1", "--set", "setpoint=1", "--outputs", "saturated,u")
    assert header == ["time [s]", "saturated", "u"]
    assert all(len(r) == 3 for r in rows)
    err = refused("simulate", "PidController", "--outputs", "u,eror")
    assert "`eror` is not an output of PidController; did you mean `error`? (outputs: u, error, saturated)" in err
    assert "not an output" in refused("simulate", "PidController", "--outputs", "kp")


def test_header_has_units_booleans_are_0_1_and_integers_bare():
    header, rows = table(ok("simulate", "PanelLock", "--stop", "0.2", "--step", "0.1").stdout)
    assert header[0] == "time [s]"
    assert "hinge0_angle [rad]" in header and "hinge0_rate [rad/s]" in header
    assert "hinge0_contact_force [N]" in header and "solver_steps" in header  # no unit: no brackets
    latched, steps = header.index("hinge0_latched"), header.index("solver_steps")
    assert {r[latched] for r in rows} <= {"0", "1"}
    assert all(r[steps].isdigit() for r in rows) and int(rows[-1][steps]) > 0
    plain, _ = table(ok("simulate", "PanelLock", "--stop", "0", "--header", "names").stdout)
    assert plain[0] == "time" and "hinge0_angle" in plain


# --- failures, paths, progress ----------------------------------------------------------------

def test_a_failing_run_keeps_the_rows_up_to_the_failure_and_says_what_to_change(tmp_path):
    # a proportional gain of 1e308 on a setpoint step to 10 overflows the controller output in
    # the step after 0.5 s: the model stops with its own remedy
    (tmp_path / "step.csv").write_text("time,setpoint\n0,0\n0.5,10\n")
    r = run("simulate", "PidController", "--stop", "1", "--step", "0.1", "--set", "kp=1e308", "--set", "ki=0",
            "--inputs", "step.csv", "--out", "run.csv", cwd=tmp_path)
    assert r.returncode == 1
    assert "PidController stopped at t = 0.5 s" in r.stderr
    assert "reduce the gains or scale the signals" in r.stderr  # the model's remedy
    assert "holds the 6 rows up to t = 0.5 s" in r.stderr
    header, rows = table((tmp_path / "run.csv").read_text())
    assert header[0] == "time [s]" and len(rows) == 6 and float(rows[-1][0]) == 0.5
    assert all(float(r[1]) == 0.0 for r in rows)


def test_out_is_relative_to_the_current_directory(tmp_path):
    ok("simulate", "PidController", "--stop", "0.2", "--step", "0.1", "--out", "res/run.csv", cwd=tmp_path)
    header, rows = table((tmp_path / "res" / "run.csv").read_text())
    assert header[0] == "time [s]" and len(rows) == 3
    assert not (ROOT / "res" / "run.csv").exists()


def test_set_file_parameter_is_relative_to_the_current_directory(tmp_path):
    """`--set mesh_file=box.obj` names ./box.obj, as --scene and --out name files there (it was
    refused: "mesh_file `box.obj` is relative, but no FMU resources folder is known")."""
    from test_state_resources import BOX_OBJ
    (tmp_path / "box.obj").write_text(BOX_OBJ)
    args = ["simulate", "RopeBlock", "--stop", "0.1", "--set", "segments=8", "--outputs", "contact_count,hook0_load"]
    rel = ok(*args, "--set", "mesh_file=box.obj", cwd=tmp_path).stdout
    absolute = ok(*args, "--set", f"mesh_file={tmp_path / 'box.obj'}", cwd=ROOT).stdout
    assert rel == absolute
    header, rows = table(rel)
    assert int(rows[-1][1]) > 0, "the slings must touch the user mesh"
    assert "box.obj" in refused(*args, "--set", "mesh_file=box.obj", cwd=ROOT)


def test_pack_outside_the_source_tree_explains_where_to_run_it(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "MBCOSIM_REPO"}
    err = refused("pack", cwd=tmp_path, env=env)
    assert "needs the mbcosim source tree" in err and "cargo run --release --bin mbcosim -- pack" in err
    assert not (tmp_path / "dist").exists()
    assert "needs the mbcosim source tree" in refused("model-descriptions", "--check", cwd=tmp_path, env=env)


def test_model_descriptions_check_finds_the_tree_from_a_subfolder():
    ok("model-descriptions", "--check", cwd=ROOT / "tests")


def test_progress_only_when_asked_for_off_a_terminal():
    quiet = ok("simulate", "PidController", "--stop", "1", "--step", "0.01")
    assert quiet.stderr == ""
    loud = ok("simulate", "PidController", "--stop", "1", "--step", "0.01", "--progress")
    assert "progress: 100/100 steps, t = 1.00/1 s" in loud.stderr and "x real time" in loud.stderr
    assert quiet.stdout == loud.stdout


def test_variables_lists_types_units_and_items():
    out = ok("variables", "PanelLock").stdout
    assert "contact_law  (fixed parameter) ContactLaw = lankarani_nikravesh (1=hertz, 2=lankarani_nikravesh" in out
    assert "hinge0_angle [rad]  (output) Real" in out
    assert "n_panels  (fixed parameter) Integer = 3 in [1, 6]" in out


# --- table1 ---------------------------------------------------------------------------------

def test_calibrate_gives_table1s_figures_at_table1s_setting_and_refuses_an_impossible_grid(tmp_path):
    """`calibrate` (issue #45 item 3) at the Table 1 configuration's own setting (restitution 0.8,
    preloads unscaled, 50 mm cam) reports the root peaks and locked frequencies that `table1`
    prints for k 1e7 and 1e8 (the same runs through the other command); a grid with no valid
    setting (cam radius below the groove depth) is an error naming the parameter."""
    stop = "30"  # every hinge locks by 27.5 s
    ok("calibrate", "--restitution", "0.8", "--preload-scale", "1", "--cam-radius", "0.05", "--stop", stop,
       "--out", tmp_path / "cal")
    head, rows = table((tmp_path / "cal" / "panel_lock_calibration.csv").read_text())
    assert len(rows) == 1, rows
    got = dict(zip(head, map(float, rows[0])))
    ok("table1", "--stop", stop, "--out", tmp_path / "t1")
    head, rows = table((tmp_path / "t1" / "panel_lock_table1.csv").read_text())
    t1 = {(float(r[0]), float(r[1])): dict(zip(head, map(float, r))) for r in rows}
    for k, name in ((1e7, "1e7"), (1e8, "1e8")):
        assert got[f"root_peak_{name}"] == t1[(k, 1.5)]["peak_force0"], (name, got, t1[(k, 1.5)])
        assert got[f"frequency_{name}"] == t1[(k, 1.5)]["linear_frequency_hz"], (name, got, t1[(k, 1.5)])
    err = refused("calibrate", "--cam-radius", "0.005", "--restitution", "0.8", "--preload-scale", "1",
                  "--out", tmp_path / "bad")
    assert "no setting of the grid ran" in err and "cam_radius" in err, err


def test_table1_takes_booleans_and_choices_and_the_papers_setup(tmp_path):
    """`table1 --set` takes every parameter type as `simulate --set` does (issue #45 item 1: the
    cable loop and the integrator could not be switched), `--paper-setup` is the paper's cable
    loop and BDF, and the table says which setup it ran."""
    md = ok("table1", "--rigid", "--paper-setup", "--stop", 2, "--out", tmp_path).stdout
    assert "cable loop on, bdf rtol 1e-4" in md, md
    assert "| root hinge peak [N] | paper [N] | deviation | largest hinge peak [N] (hinge) |" in md
    md = ok("table1", "--rigid", "--set", "integrator=dopri5", "--set", "rtol=1e-5", "--stop", 2,
            "--out", tmp_path).stdout
    assert "cable loop off, dopri5 rtol 1e-5" in md, md
    assert "`maybe` is not true, false" in refused("table1", "--set", "cable_loop=maybe", "--out", tmp_path)
    assert "did you mean `gen_alpha`" in refused("table1", "--set", "integrator=gen-alpha", "--out", tmp_path)
