//! `mbcosim`: packs the FMUs, regenerates model descriptions, runs models natively.
//!
//! ```text
//! mbcosim pack                 build dist/<Model>.fmu for every registered model
//! mbcosim model-descriptions   rewrite modelDescription/<Model>.xml from the variable tables
//!         [--check]            only report (exit 1) when a checked-in file is out of date
//! mbcosim demo                 pack, then run the demos and print their tables
//! mbcosim report [--quick] [--only NAME] [--skip NAME] [--out DIR]
//!                              work-precision report (CSV, log-log plots, report.md; docs/report)
//! mbcosim table1 [--out DIR] [--stop T] [--step H] [--modes N] [--rigid] [--set name=value]...
//!                              the paper's Table 1 / Figs. 4-5 with flexible panels (PanelLock);
//!                              CSV, SVG plots and a markdown table into DIR (default docs/)
//! mbcosim simulate <Model> [--stop T] [--step H] [--scene file.toml] [--set name=value]... [--out file.csv] [--timing]
//!                              native run of one model; CSV of its outputs (stdout by default)
//! mbcosim state-fields <state-file> [--resources DIR]
//!                              every field of a serialized FMU state, one JSON object a line
//!                              (offset, len, kind, what): the adversarial harness's field map
//! ```
//!
//! Packing needs a fresh cdylib, which `cargo run --bin mbcosim` does not build, so `pack` and
//! `demo` first run `scripts/build_portable.sh` for the same profile and target directory as this
//! executable: a glibc 2.17 build through cargo-zigbuild (installed into `.venv` on first use),
//! stripped, its debug info in `dist/debug/` (docs/portable_binary.md). Set `MBCOSIM_NO_BUILD=1`
//! to skip that and pack the last stripped library as it is.
#![forbid(unsafe_code)]

use std::path::PathBuf;
use std::process::{Command, ExitCode};

use mbcosim::fmi::{model_description, package};
use mbcosim::scene::{self, native, scene_file};

/// Repository root: the folder with `Cargo.toml` and `modelDescription/`.
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn descriptions_dir() -> PathBuf {
    root().join("modelDescription")
}

/// The default scene files, one per model (rendered from the variable tables).
fn scenes_dir() -> PathBuf {
    root().join("resources").join("scenes")
}

/// The library every FMU ships, for this executable's profile and target directory: built by
/// `scripts/build_portable.sh` (portable glibc 2.17 build through cargo-zigbuild, host build with a
/// loud warning when that toolchain cannot be had; stripped, debug info split into
/// `dist/debug/`), or with `MBCOSIM_NO_BUILD` the stripped library of the last build as it is.
fn fresh_cdylib() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this executable: {e}"))?;
    let profile_dir = exe.parent().ok_or("executable has no parent folder")?;
    let profile = profile_dir
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("debug");
    let target_dir = profile_dir.parent().ok_or("no target folder")?;
    let stripped = target_dir.join("fmu").join(profile).join("libmbcosim.so");
    if std::env::var_os("MBCOSIM_NO_BUILD").is_some() {
        return if stripped.is_file() {
            Ok(stripped)
        } else {
            Err(format!(
                "{} not found: run `mbcosim pack` once without MBCOSIM_NO_BUILD",
                stripped.display()
            ))
        };
    }
    let script = root().join("scripts").join("build_portable.sh");
    let out = Command::new("bash")
        .arg(&script)
        .args(["--profile", profile, "--target-dir"])
        .arg(target_dir)
        .arg("--debug-dir")
        .arg(root().join("dist").join("debug"))
        .stderr(std::process::Stdio::inherit())
        .output()
        .map_err(|e| format!("cannot run {}: {e}", script.display()))?;
    if !out.status.success() {
        return Err(format!("{} failed ({})", script.display(), out.status));
    }
    let lib = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    if !lib.is_file() {
        return Err(format!(
            "{} named no library ({})",
            script.display(),
            lib.display()
        ));
    }
    Ok(lib)
}

fn pack_all() -> Result<Vec<PathBuf>, String> {
    let lib = fresh_cdylib()?;
    let out = root().join("dist");
    scene::registry()
        .iter()
        .map(|e| package::pack(e, &lib, &descriptions_dir(), &out))
        .collect()
}

fn model_descriptions(check: bool) -> Result<(), String> {
    let dir = descriptions_dir();
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let mut stale = Vec::new();
    for e in scene::registry() {
        let info = (e.info)();
        let path = package::description_path(&dir, info.identifier);
        let xml = model_description::write(info)?;
        let scene_path = scenes_dir().join(format!("{}.toml", info.identifier));
        for (path, text) in [(path, xml), (scene_path, scene_file::render(info))] {
            if std::fs::read_to_string(&path).ok().as_deref() == Some(text.as_str()) {
                continue;
            }
            stale.push(path.display().to_string());
            if !check {
                if let Some(parent) = path.parent() {
                    std::fs::create_dir_all(parent).map_err(|e| e.to_string())?;
                }
                std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
                println!("wrote {}", path.display());
            }
        }
    }
    match (check, stale.is_empty()) {
        (true, false) => Err(format!(
            "out of date: {}; run `{}`",
            stale.join(", "),
            package::REGENERATE
        )),
        _ => Ok(()),
    }
}

/// PID demo: a PI(D) controller closing the loop around `tau*dy/dt = -y + K*u`.
fn demo_pid() -> Result<(), String> {
    let (tau, gain, h, stop) = (0.5_f64, 2.0, 0.01, 4.0);
    let mut pid = (scene::find_by_identifier("PidController")
        .ok_or("PidController not registered")?
        .create)();
    for (name, v) in [
        ("kp", 3.0),
        ("ki", 2.0),
        ("kd", 0.05),
        ("Tf", 0.02),
        ("Tt", 0.1),
        ("u_min", -2.0),
        ("u_max", 2.0),
        ("setpoint", 1.0),
    ] {
        native::set_by_name(pid.as_mut(), name, v).map_err(|e| e.to_string())?;
    }
    pid.initialize(0.0).map_err(|e| e.to_string())?;
    println!(
        "\nPidController on a first-order plant (tau = {tau} s, gain {gain}), setpoint 1, step {h} s:"
    );
    println!("{:>6} {:>9} {:>9} {:>9}", "t [s]", "y", "u", "saturated");
    let decay = (-h / tau).exp();
    let mut y = 0.0;
    let n = (stop / h).round() as usize;
    for k in 0..=n {
        let t = k as f64 * h;
        let out = native::outputs(pid.as_ref()).map_err(|e| e.to_string())?;
        if (k <= 100 && k % 20 == 0) || k % 100 == 0 {
            println!("{t:>6.2} {y:>9.4} {:>9.4} {:>9}", out[0], out[2] != 0.0);
        }
        if k == n {
            break;
        }
        native::set_by_name(pid.as_mut(), "measurement", y).map_err(|e| e.to_string())?;
        pid.do_step(t, h).map_err(|e| e.to_string())?;
        let u = native::outputs(pid.as_ref()).map_err(|e| e.to_string())?[0];
        y = decay * y + gain * (1.0 - decay) * u;
    }
    Ok(())
}

/// PanelLock demo: a full deployment of the default rigid array, written to `out/` as CSV and SVG
/// plots of the latch contact forces and the outer panel's tip velocity.
fn demo_panel_lock() -> Result<(), String> {
    println!("== PanelLock: deployment and lock-up of a 3-panel array (60 s)");
    let summary = mbcosim::scene::panel_lock::run_demo(std::path::Path::new("out"), 60.0, 0.01)?;
    print!("{summary}");
    Ok(())
}

/// Every demo, in order; add new ones here.
const DEMOS: &[fn() -> Result<(), String>] = &[demo_panel_lock, demo_pid];

fn demo() -> Result<(), String> {
    for fmu in pack_all()? {
        println!("packed {}", fmu.display());
    }
    DEMOS.iter().try_for_each(|d| d())
}

/// The work-precision report: `report [--quick] [--only NAME] [--skip NAME] [--out DIR]`.
fn report(args: &[String]) -> Result<(), String> {
    let (mut quick, mut only, mut skip, mut out) = (
        false,
        String::new(),
        String::new(),
        root().join("docs/report"),
    );
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--quick" => quick = true,
            "--only" => only = value()?.clone(),
            "--skip" => skip = value()?.clone(),
            "--out" => out = PathBuf::from(value()?),
            other => return Err(format!("unknown option {other}")),
        }
    }
    let (_, files) = mbcosim::report::workprec::report(&out, quick, &only, &skip)?;
    for f in files {
        println!("wrote {f}");
    }
    Ok(())
}

fn simulate(args: &[String]) -> Result<(), String> {
    let model = args.first().ok_or("simulate needs a model identifier")?;
    let entry =
        scene::find_by_identifier(model).ok_or_else(|| format!("unknown model `{model}`"))?;
    let info = (entry.info)();
    let (mut stop, mut step, mut values, mut out, mut scene) = (
        info.default_stop_time,
        info.default_step,
        Vec::new(),
        None,
        None,
    );
    let mut timing = false;
    let mut it = args[1..].iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        let number = |s: &String| s.parse::<f64>().map_err(|e| format!("{s}: {e}"));
        match flag.as_str() {
            "--stop" => stop = number(value()?)?,
            "--step" => step = number(value()?)?,
            "--out" => out = Some(PathBuf::from(value()?)),
            "--scene" => scene = Some(PathBuf::from(value()?)),
            "--timing" => timing = true,
            "--set" => {
                let kv = value()?;
                let (k, v) = kv
                    .split_once('=')
                    .ok_or_else(|| format!("--set {kv}: expected name=value"))?;
                values.push((k.to_string(), number(&v.to_string())?));
            }
            other => return Err(format!("unknown option {other}")),
        }
    }
    let mut m = (entry.create)();
    if let Some(path) = scene {
        scene_file::apply_file(m.as_mut(), &path)?;
    }
    let t0 = std::time::Instant::now();
    let table = native::simulate(m.as_mut(), &values, stop, step).map_err(|e| e.to_string())?;
    if timing {
        eprintln!(
            "timing: {} s wall for {} communication steps (initialization included)",
            t0.elapsed().as_secs_f64(),
            table.rows.len().saturating_sub(1)
        );
    }
    match out {
        Some(p) => std::fs::write(&p, table.to_csv()).map_err(|e| format!("{}: {e}", p.display())),
        None => {
            print!("{}", table.to_csv());
            Ok(())
        }
    }
}

/// PanelLock Table 1 study (flexible panels by default).
fn table1(args: &[String]) -> Result<(), String> {
    use mbcosim::scene::panel_lock::{PanelLockParams, ports::REAL_PARAMS, study};
    let (mut out, mut stop, mut step, mut modes, mut rigid) =
        (root().join("docs"), 80.0, 0.01, 10usize, false);
    let mut sets = Vec::new();
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        let number = |s: &String| s.parse::<f64>().map_err(|e| format!("{s}: {e}"));
        match flag.as_str() {
            "--out" => out = PathBuf::from(value()?),
            "--stop" => stop = number(value()?)?,
            "--step" => step = number(value()?)?,
            "--modes" => modes = value()?.parse().map_err(|e| format!("--modes: {e}"))?,
            "--rigid" => rigid = true,
            "--set" => {
                let kv = value()?;
                let (k, v) = kv
                    .split_once('=')
                    .ok_or_else(|| format!("--set {kv}: expected name=value"))?;
                sets.push((k.to_string(), number(&v.to_string())?));
            }
            other => return Err(format!("unknown option {other}")),
        }
    }
    let mut p = if rigid {
        PanelLockParams::default()
    } else {
        PanelLockParams::flexible(modes)
    };
    for (name, v) in sets {
        let rp = REAL_PARAMS
            .iter()
            .find(|r| r.name == name)
            .ok_or_else(|| format!("unknown real parameter `{name}`"))?;
        (rp.set)(&mut p, v);
    }
    p.validate()?;
    let md = study::table1(&out, &p, stop, step)?;
    println!("{md}");
    println!("wrote {}/panel_lock_table1.* and SVG plots", out.display());
    Ok(())
}

const USAGE: &str = "usage: mbcosim <pack | model-descriptions [--check] | demo | report [--quick] [--only NAME] [--skip NAME] [--out DIR] | table1 [--out DIR] [--stop T] [--step H] [--modes N] [--rigid] [--set name=value]... | simulate <Model> [--stop T] [--step H] [--scene file.toml] [--set name=value]... [--out file.csv] [--timing] | state-fields <state-file> [--resources DIR]>";

/// `state-fields <state-file> [--resources DIR]`: the field map of a serialized FMU state.
fn state_fields(args: &[String]) -> Result<(), String> {
    let (file, resources) = match args {
        [file] => (file, None),
        [file, flag, dir] if flag == "--resources" => (file, Some(PathBuf::from(dir))),
        _ => return Err(USAGE.to_string()),
    };
    let bytes = std::fs::read(file).map_err(|e| format!("cannot read {file}: {e}"))?;
    let spans = mbcosim::fmi::snapshot::field_map(&bytes, resources.as_deref())
        .map_err(|e| format!("{file}: {e}"))?;
    for s in spans {
        println!(
            "{{\"offset\": {}, \"len\": {}, \"kind\": \"{}\", \"what\": {:?}}}",
            s.offset, s.len, s.kind, s.what
        );
    }
    Ok(())
}

fn run(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("pack") => {
            pack_all().map(|fmus| fmus.iter().for_each(|f| println!("packed {}", f.display())))
        }
        Some("model-descriptions") => {
            model_descriptions(args.get(1).is_some_and(|a| a == "--check"))
        }
        Some("demo") => demo(),
        Some("simulate") => simulate(&args[1..]),
        Some("report") => report(&args[1..]),
        Some("table1") => table1(&args[1..]),
        Some("state-fields") => state_fields(&args[1..]),
        Some("help" | "--help" | "-h") => {
            println!("{USAGE}");
            Ok(())
        }
        _ => Err(USAGE.to_string()),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("mbcosim: {e}");
            ExitCode::FAILURE
        }
    }
}
