//! `pack`, `model-descriptions` and `demo`: the commands that need the source tree.
//!
//! The source tree is found in the current directory or above it (a `Cargo.toml` of package
//! `mbcosim` next to `modelDescription/`), or at `MBCOSIM_REPO`; what these commands write
//! (`dist/`, `out/`) resolves against the current directory, except the checked-in files that
//! `model-descriptions` regenerates, which belong to the source tree.

use std::path::{Path, PathBuf};
use std::process::Command;

use mbcosim::fmi::package::Binary;
use mbcosim::fmi::platform::Platform;
use mbcosim::fmi::{metadata, model_description, model_description3, package};
use mbcosim::scene::{self, native, scene_file};

/// True when `dir` is the root of the mbcosim source tree.
fn is_repo(dir: &Path) -> bool {
    dir.join("modelDescription").is_dir()
        && std::fs::read_to_string(dir.join("Cargo.toml"))
            .is_ok_and(|t| t.lines().any(|l| l.trim() == "name = \"mbcosim\""))
}

/// The source tree, for `what` (the command that needs it).
pub fn repo_root(what: &str) -> Result<PathBuf, String> {
    if let Some(dir) = std::env::var_os("MBCOSIM_REPO") {
        let dir = PathBuf::from(dir);
        return if is_repo(&dir) {
            std::path::absolute(&dir).map_err(|e| format!("{}: {e}", dir.display()))
        } else {
            Err(format!(
                "MBCOSIM_REPO={} is not the mbcosim source tree (no Cargo.toml of package mbcosim next to modelDescription/)",
                dir.display()
            ))
        };
    }
    let cwd = std::env::current_dir().map_err(|e| format!("no current directory: {e}"))?;
    cwd.ancestors()
        .find(|d| is_repo(d))
        .map(Path::to_path_buf)
        .ok_or_else(|| {
            format!(
                "`{what}` needs the mbcosim source tree (the build script and modelDescription/), and {} is not inside it: run it from the repository root (`cargo run --release --bin mbcosim -- {what}`) or set MBCOSIM_REPO to the repository",
                cwd.display()
            )
        })
}

/// Where `scripts/build_portable.sh` puts the stripped library of `platform` under
/// `<target>/fmu/<profile>/`.
fn stripped_name(platform: Platform) -> PathBuf {
    match platform {
        Platform::LinuxX86_64 => PathBuf::from("libmbcosim.so"),
        Platform::LinuxAarch64 => Path::new(platform.tuple()).join("libmbcosim.so"),
        Platform::WindowsX86_64 => Path::new(platform.tuple()).join("mbcosim.dll"),
    }
}

/// The library every FMU ships on `platform`, for this executable's profile and target
/// directory: built by `scripts/build_portable.sh` (x86_64 Linux: the cdylib of this
/// executable's own build, linked by zig against glibc 2.17 through scripts/link_host.sh, with
/// a loud warning when it could not be; aarch64 Linux: cargo-zigbuild for glibc 2.17; Windows:
/// mingw-w64, self-contained; stripped, debug info split into `<dist>/debug/`), or with
/// `MBCOSIM_NO_BUILD` the stripped library of the last build as it is.
fn fresh_cdylib(repo: &Path, dist: &Path, platform: Platform) -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this executable: {e}"))?;
    let profile_dir = exe.parent().ok_or("executable has no parent folder")?;
    let profile = profile_dir
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("debug");
    let target_dir = profile_dir.parent().ok_or("no target folder")?;
    let stripped = target_dir
        .join("fmu")
        .join(profile)
        .join(stripped_name(platform));
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
    // the script works in the source tree: every path it gets must be absolute
    let debug_dir = std::path::absolute(dist.join("debug")).map_err(|e| e.to_string())?;
    let script = repo.join("scripts").join("build_portable.sh");
    let out = Command::new("bash")
        .arg(&script)
        .args(["--target", platform.rust_target()])
        .args(["--profile", profile, "--target-dir"])
        .arg(target_dir)
        .arg("--debug-dir")
        .arg(debug_dir)
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

/// Packs every registered model for `platforms` (FMI 2.0 into `dist`, FMI 3.0 into
/// `dist/fmi3`); returns the FMUs written.
fn pack_all(what: &str, dist: &Path, platforms: &[Platform]) -> Result<Vec<PathBuf>, String> {
    let repo = repo_root(what)?;
    let mut binaries = Vec::new();
    for &platform in platforms {
        let path = fresh_cdylib(&repo, dist, platform)?;
        binaries.push(Binary { platform, path });
    }
    let descriptions = repo.join("modelDescription");
    let when = generation_time(&repo)?;
    let when = when.as_deref();
    let mut packed = Vec::new();
    for e in scene::registry() {
        packed.push(package::pack(&e, &binaries, &descriptions, dist, when)?);
    }
    // FMI 3.0 FMUs of the same models, from the same libraries (docs/fmi3.md)
    for e in scene::registry() {
        packed.push(package::pack3(
            &e,
            &binaries,
            &descriptions,
            &dist.join("fmi3"),
            when,
        )?);
    }
    Ok(packed)
}

/// The FMUs' `generationDateAndTime`: `SOURCE_DATE_EPOCH` [s] when set (the reproducible-builds
/// convention), else the time of the checkout's last commit, so two packs of one commit are
/// byte-identical. Outside a git checkout without `SOURCE_DATE_EPOCH` the attribute is left out,
/// with a note on stderr.
fn generation_time(repo: &Path) -> Result<Option<String>, String> {
    let seconds = match std::env::var("SOURCE_DATE_EPOCH") {
        Ok(v) => v.trim().parse::<i64>().map_err(|e| {
            format!("SOURCE_DATE_EPOCH={v:?} is not a whole number of seconds: {e}")
        })?,
        Err(_) => {
            let out = Command::new("git")
                .arg("-C")
                .arg(repo)
                .args(["log", "-1", "--format=%ct"])
                .output();
            match out {
                Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout)
                    .trim()
                    .parse::<i64>()
                    .map_err(|e| format!("git log gave no commit time: {e}"))?,
                _ => {
                    eprintln!(
                        "note: no commit time (not a git checkout, SOURCE_DATE_EPOCH unset): the FMUs carry no generationDateAndTime"
                    );
                    return Ok(None);
                }
            }
        }
    };
    metadata::utc_date_time(seconds).map(Some)
}

/// The platforms named in `list` (FMI 3.0 tuples, comma-separated), each once.
fn platforms(list: &str) -> Result<Vec<Platform>, String> {
    let mut out = Vec::new();
    for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        let p = Platform::parse(name)?;
        if !out.contains(&p) {
            out.push(p);
        }
    }
    if out.is_empty() {
        return Err("--platforms names no platform".into());
    }
    Ok(out)
}

#[derive(clap::Args)]
pub struct PackArgs {
    /// Folder for the FMUs and their debug info (relative to the current directory).
    #[arg(long, value_name = "DIR", default_value = "dist")]
    out: PathBuf,
    /// The platforms each FMU carries a binary for, comma-separated (docs/platforms.md).
    #[arg(
        long,
        value_name = "LIST",
        default_value = "x86_64-linux,x86_64-windows,aarch64-linux"
    )]
    platforms: String,
}

pub fn pack(a: &PackArgs) -> Result<(), String> {
    for f in pack_all("pack", &a.out, &platforms(&a.platforms)?)? {
        println!("packed {}", f.display());
    }
    Ok(())
}

#[derive(clap::Args)]
pub struct DescriptionArgs {
    /// Only report (exit 1) when a checked-in file is out of date; write nothing.
    #[arg(long)]
    check: bool,
}

pub fn model_descriptions(a: &DescriptionArgs) -> Result<(), String> {
    let repo = repo_root("model-descriptions")?;
    let dir = repo.join("modelDescription");
    let scenes = repo.join("resources").join("scenes");
    let mut stale = Vec::new();
    for e in scene::registry() {
        let info = (e.info)();
        let path = package::description_path(&dir, info.identifier);
        let xml = model_description::write(info)?;
        let scene_path = scenes.join(format!("{}.toml", info.identifier));
        let path3 = package::description_path3(&dir, info.identifier);
        let xml3 = model_description3::write(info)?;
        for (path, text) in [
            (path, xml),
            (path3, xml3),
            (scene_path, scene_file::render(info)),
        ] {
            if std::fs::read_to_string(&path).ok().as_deref() == Some(text.as_str()) {
                continue;
            }
            stale.push(path.display().to_string());
            if !a.check {
                if let Some(parent) = path.parent() {
                    std::fs::create_dir_all(parent).map_err(|e| e.to_string())?;
                }
                std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
                println!("wrote {}", path.display());
            }
        }
    }
    if a.check && !stale.is_empty() {
        return Err(format!(
            "out of date: {}; run `{}`",
            stale.join(", "),
            package::REGENERATE
        ));
    }
    Ok(())
}

#[derive(clap::Args)]
pub struct DemoArgs {
    /// Folder for the packed FMUs (relative to the current directory).
    #[arg(long, value_name = "DIR", default_value = "dist")]
    dist: PathBuf,
    /// Folder for the demos' CSV files and SVG plots (relative to the current directory).
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
    /// The platforms the FMUs carry a binary for (x86_64 Linux only by default, so the quick
    /// start compiles no cross target; `mbcosim pack` builds all three).
    #[arg(long, value_name = "LIST", default_value = "x86_64-linux")]
    platforms: String,
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

/// PanelLock demo: a full deployment of the default rigid array, written to `out` as CSV and SVG
/// plots of the latch contact forces and the outer panel's tip velocity.
fn demo_panel_lock(out: &Path) -> Result<(), String> {
    println!("== PanelLock: deployment and lock-up of a 3-panel array (60 s)");
    let summary = mbcosim::scene::panel_lock::run_demo(out, 60.0, 0.01)?;
    print!("{summary}");
    Ok(())
}

/// RopeBlock demo: the default lift (200 t block on four slings over the deck edges), hoisted
/// at 0.2 m/s from 1 s to 9 s, written to `out/rope_lift.csv` with two SVG plots
/// (`rope_lift_tensions.svg`, `rope_lift_contacts.svg`).
fn demo_rope_block(out: &Path) -> Result<(), String> {
    use mbcosim::scene::rope_block::demo::{Demo, run};
    println!("\n== RopeBlock: a 200 t block lifted on four slings (12 s, hoist 0.2 m/s)");
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let path = out.join("rope_lift.csv");
    let file = std::fs::File::create(&path)
        .map_err(|e| format!("cannot create {}: {e}", path.display()))?;
    let s = run(
        Demo::Lift,
        None,
        12.0,
        0.05,
        &mut std::io::BufWriter::new(file),
    )?;
    println!("{}", s.describe(&path));
    let plots = mbcosim::scene::rope_block::demo_plots::write_plots(
        &path,
        out,
        "rope_lift",
        "RopeBlock lift",
    )?;
    for p in plots {
        println!("plot: {}", p.display());
    }
    Ok(())
}

pub fn demo(a: &DemoArgs) -> Result<(), String> {
    for fmu in pack_all("demo", &a.dist, &platforms(&a.platforms)?)? {
        println!("packed {}", fmu.display());
    }
    // three.js for `simulate --replay`, read at run time: after the quick start's first command
    // `--replay` works without a rebuild; without npm only `--replay` lacks it, not the demo
    match crate::replay::fetch_three(&repo_root("demo")?) {
        Ok(done) => println!("replay: {done}"),
        Err(e) => eprintln!("note: {e}"),
    }
    demo_panel_lock(&a.out)?;
    demo_rope_block(&a.out)?;
    demo_pid()
}
