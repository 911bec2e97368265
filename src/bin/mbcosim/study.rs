//! `report` (work-precision) and `table1` (the paper's PanelLock study).

use std::path::PathBuf;

use crate::values;
use mbcosim::scene::panel_lock::calibration::Grid;

#[derive(clap::Args)]
pub struct ReportArgs {
    /// Fewer tolerances and shorter runs (a smoke test of the report).
    #[arg(long)]
    quick: bool,
    /// Only the cases whose name contains this text.
    #[arg(long, value_name = "NAME", default_value = "")]
    only: String,
    /// Skip the cases whose name contains this text.
    #[arg(long, value_name = "NAME", default_value = "")]
    skip: String,
    /// Folder for the CSV files, plots and report.md (relative to the current directory).
    #[arg(long, value_name = "DIR", default_value = "docs/report")]
    out: PathBuf,
}

pub fn report(a: &ReportArgs) -> Result<(), String> {
    let (_, files) = mbcosim::report::workprec::report(&a.out, a.quick, &a.only, &a.skip)?;
    for f in files {
        println!("wrote {f}");
    }
    Ok(())
}

/// The span of every deployment run of `table1` and `calibrate`.
#[derive(clap::Args)]
pub struct DeploymentRun {
    /// Stop time [s] of every run.
    #[arg(long, value_name = "T", default_value_t = 80.0)]
    stop: f64,
    /// Communication step [s].
    #[arg(long, value_name = "H", default_value_t = 0.01)]
    step: f64,
}

#[derive(clap::Args)]
pub struct Table1Args {
    /// Folder for the CSV, SVG plots and markdown table (relative to the current directory).
    #[arg(long, value_name = "DIR", default_value = "docs")]
    out: PathBuf,
    #[command(flatten)]
    run: DeploymentRun,
    /// Craig-Bampton modes per flexible panel.
    #[arg(long, value_name = "N", default_value_t = 10)]
    modes: usize,
    /// Rigid panels instead of flexible ones.
    #[arg(long)]
    rigid: bool,
    /// The paper's own array and solver: the closed cable loop on and Gear's BDF
    /// (`cable_loop = true`, `integrator = bdf`), before the --set values.
    #[arg(long)]
    paper_setup: bool,
    /// Set any PanelLock parameter (number, boolean or enumeration name, checked against its
    /// type and range as `simulate --set` does): NAME=VALUE; repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
}

/// The study's parameters: the paper configuration ([`PanelLockParams::flexible`] with `modes`
/// modes per panel) or the rigid default, then the paper's cable loop and BDF with
/// `paper_setup`, then `sets` (NAME=VALUE, checked as `simulate --set` checks them).
fn base_params(
    rigid: bool,
    modes: usize,
    paper_setup: bool,
    sets: &[String],
) -> Result<mbcosim::scene::panel_lock::PanelLockParams, String> {
    use mbcosim::scene::panel_lock::{PanelLockModel, PanelLockParams};
    let mut v = Vec::new();
    if !rigid {
        let p = PanelLockParams::flexible(modes);
        v.extend([
            "flexible_panels=true".to_string(),
            format!("n_modes={}", p.n_modes),
            format!("cam_radius={}", p.cam_radius),
            format!("groove_width={}", p.groove_width),
        ]);
    }
    if paper_setup {
        v.extend(["cable_loop=true".into(), "integrator=bdf".into()]);
    }
    let info = mbcosim::scene::panel_lock::info();
    let mut model = PanelLockModel::new();
    for kv in v.iter().chain(sets) {
        let (port, value) = values::parse_set(info, kv)?;
        values::apply(&mut model, port, &value).map_err(|e| format!("--set {kv}: {e}"))?;
    }
    model.params().map_err(|e| e.to_string())
}

pub fn table1(a: &Table1Args) -> Result<(), String> {
    use mbcosim::scene::panel_lock::study;
    let p = base_params(a.rigid, a.modes, a.paper_setup, &a.sets)?;
    let md = study::table1(&a.out, &p, a.run.stop, a.run.step)?;
    println!("{md}");
    println!(
        "wrote {}/panel_lock_table1.* and SVG plots",
        a.out.display()
    );
    Ok(())
}

#[derive(clap::Args)]
pub struct CalibrateArgs {
    /// Folder for panel_lock_calibration.md and .csv (relative to the current directory).
    #[arg(long, value_name = "DIR", default_value = "docs")]
    out: PathBuf,
    #[command(flatten)]
    run: DeploymentRun,
    /// Runs at a time (threads).
    #[arg(long, value_name = "N", default_value_t = 2)]
    threads: usize,
    /// Restitution values to try, comma-separated.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_values_t = Grid::default().restitution)]
    restitution: Vec<f64>,
    /// Factors on both deployment springs' preloads, comma-separated.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_values_t = Grid::default().preload_scale)]
    preload_scale: Vec<f64>,
    /// Cam radii [m] to try, comma-separated.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_values_t = Grid::default().cam_radius)]
    cam_radius: Vec<f64>,
    /// Set any other PanelLock parameter of the paper configuration: NAME=VALUE; repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
}

pub fn calibrate(a: &CalibrateArgs) -> Result<(), String> {
    use mbcosim::scene::panel_lock::calibration;
    let p = base_params(false, 10, false, &a.sets)?;
    let grid = Grid {
        restitution: a.restitution.clone(),
        preload_scale: a.preload_scale.clone(),
        cam_radius: a.cam_radius.clone(),
    };
    let md = calibration::write(&a.out, &p, &grid, a.run.stop, a.run.step, a.threads)?;
    println!("{md}");
    println!(
        "wrote {}/panel_lock_calibration.md and .csv",
        a.out.display()
    );
    Ok(())
}
