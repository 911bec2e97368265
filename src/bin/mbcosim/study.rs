//! `report` (work-precision) and `table1` (the paper's PanelLock study).

use std::path::PathBuf;

use crate::values;

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

#[derive(clap::Args)]
pub struct Table1Args {
    /// Folder for the CSV, SVG plots and markdown table (relative to the current directory).
    #[arg(long, value_name = "DIR", default_value = "docs")]
    out: PathBuf,
    /// Stop time [s].
    #[arg(long, value_name = "T", default_value_t = 80.0)]
    stop: f64,
    /// Communication step [s].
    #[arg(long, value_name = "H", default_value_t = 0.01)]
    step: f64,
    /// Craig-Bampton modes per flexible panel.
    #[arg(long, value_name = "N", default_value_t = 10)]
    modes: usize,
    /// Rigid panels instead of flexible ones.
    #[arg(long)]
    rigid: bool,
    /// Set a real PanelLock parameter: NAME=VALUE (finite number); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
}

pub fn table1(a: &Table1Args) -> Result<(), String> {
    use mbcosim::scene::panel_lock::{PanelLockParams, ports::REAL_PARAMS, study};
    let mut p = if a.rigid {
        PanelLockParams::default()
    } else {
        PanelLockParams::flexible(a.modes)
    };
    let names: Vec<&str> = REAL_PARAMS.iter().map(|r| r.name).collect();
    for kv in &a.sets {
        let (name, v) = kv
            .split_once('=')
            .ok_or_else(|| format!("--set {kv}: expected NAME=VALUE"))?;
        let rp = REAL_PARAMS
            .iter()
            .find(|r| r.name == name.trim())
            .ok_or_else(|| {
                format!(
                    "--set {kv}: `{name}` is not a real PanelLock parameter{}",
                    values::near_names(name.trim(), &names, "PanelLock")
                )
            })?;
        let v: f64 = v
            .trim()
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| format!("--set {kv}: `{v}` is not a finite number"))?;
        (rp.set)(&mut p, v);
    }
    p.validate()?;
    let md = study::table1(&a.out, &p, a.stop, a.step)?;
    println!("{md}");
    println!(
        "wrote {}/panel_lock_table1.* and SVG plots",
        a.out.display()
    );
    Ok(())
}
