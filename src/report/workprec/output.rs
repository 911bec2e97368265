//! Files of a work-precision report: one CSV of every run, one log-log plot per problem and
//! quantity (error over median CPU time), and a markdown report with the machine, the versions,
//! the tables, the observed orders and the recommendations.

use super::{Study, Sweep};
use crate::report::loglog::{LogSeries, loglog_plot};
use std::fmt::Write as _;
use std::path::Path;

/// CSV header of [`write_csv`].
pub const CSV_HEADER: &str = "problem,series,sweep,x,integrator,quantity,unit,value,reference,error,cpu_median_s,cpu_best_s,steps,rejected,newton_iterations,factorizations,rhs_evaluations,failure";

/// Every run of every study, one row per quantity.
pub fn csv(studies: &[Study]) -> String {
    let mut out = format!("{CSV_HEADER}\n");
    for st in studies {
        for s in &st.samples {
            for (i, q) in st.quantities.iter().enumerate() {
                let (value, stats, failure) = match &s.outcome {
                    Ok(o) => (o.values[i], Some(o.stats), String::new()),
                    Err(e) => (f64::NAN, None, e.replace([',', '\n'], ";")),
                };
                let st_ = stats.unwrap_or_default();
                let _ = writeln!(
                    out,
                    "{},{},{},{:e},{},{},{},{:e},{:e},{:e},{:e},{:e},{},{},{},{},{},{}",
                    st.name,
                    s.setting.series,
                    s.setting.sweep.label(),
                    s.setting.x,
                    s.setting.integrator.name(),
                    q.name,
                    q.unit,
                    value,
                    st.reference_values[i],
                    s.errors[i],
                    s.cpu_median,
                    s.cpu_best,
                    st_.steps,
                    st_.rejected,
                    st_.newton_iterations,
                    st_.factorizations,
                    st_.rhs_evaluations,
                    failure
                );
            }
        }
    }
    out
}

/// The log-log plot of quantity `q` of `st`: error over median CPU time, one series per curve,
/// failures as crosses, the observed order in the legend.
pub fn plot(st: &Study, q: usize) -> String {
    let quantity = &st.quantities[q];
    let series: Vec<LogSeries> = st
        .series()
        .into_iter()
        .map(|name| {
            let samples: Vec<_> = st.of_series(&name).collect();
            let points = samples
                .iter()
                .filter(|s| s.outcome.is_ok())
                .map(|s| (s.cpu_median, s.errors[q]))
                .collect();
            let failures = samples
                .iter()
                .filter(|s| s.outcome.is_err())
                .map(|s| s.cpu_median)
                .collect();
            let sweep = samples.first().map(|s| s.setting.sweep);
            let theory = samples.first().and_then(|s| s.setting.theory);
            LogSeries {
                note: order_note(st.observed_order(&name, q), sweep, theory),
                name,
                points,
                failures,
            }
        })
        .collect();
    let what = quantity_words(quantity.name);
    let title = match quantity.error {
        super::ErrorKind::Intrinsic => format!(
            "{}: {} over CPU time",
            problem_words(st.name),
            what.to_lowercase()
        ),
        _ => format!(
            "{}: error of the {what} over CPU time",
            problem_words(st.name)
        ),
    };
    loglog_plot(
        &title,
        "CPU time per run, median [s]",
        &error_label(quantity),
        &series,
    )
}

/// The y-axis label of quantity `q`'s error, in words with its unit.
fn error_label(q: &super::Quantity) -> String {
    let what = quantity_words(q.name);
    match q.error {
        super::ErrorKind::Relative => format!("Relative error of the {what} [-]"),
        super::ErrorKind::Intrinsic if q.unit.is_empty() => format!("{what} [-]"),
        super::ErrorKind::Intrinsic => format!("{what} [{}]", q.unit),
        super::ErrorKind::Absolute => format!("Error of the {what} [{}]", q.unit),
    }
}

/// A problem's name in words for plot titles (the name itself when not listed).
fn problem_words(name: &str) -> String {
    match name {
        "panel_rigid" => "PanelLock, rigid panels".into(),
        "panel_smooth" => "PanelLock, smooth deployment".into(),
        "panel_flex" => "PanelLock, flexible panels".into(),
        "panel_modes" => "PanelLock, modes per flexible panel".into(),
        "panel_mesh" => "PanelLock, plate mesh of the flexible panels".into(),
        "rope_lift" => "RopeBlock lift".into(),
        "rope_nodes" => "RopeBlock lift, segments per sling".into(),
        other => other.replace('_', " "),
    }
}

/// A quantity's name in words for plot labels (the name with spaces when not listed).
fn quantity_words(name: &str) -> String {
    match name {
        "peak_force" => "largest latch contact force".into(),
        "first_peak_force" => "root latch impact force".into(),
        "lock_time" => "root lock time".into(),
        "energy" => "Energy balance error / spring energy released".into(),
        "drift" => "Constraint residual at the end".into(),
        "root_angle" => "root hinge angle".into(),
        "outer_angle" => "outer hinge angle".into(),
        "frequency" => "post-lock frequency".into(),
        "peak_hook_load" => "largest hook load".into(),
        "block_z" => "final block height".into(),
        other => other.replace('_', " "),
    }
}

/// "order 2.0 in h (theory 2)" and the like.
fn order_note(order: Option<f64>, sweep: Option<Sweep>, theory: Option<f64>) -> String {
    let Some(p) = order else {
        return "no order (intrinsic error or too few resolved points)".into();
    };
    let t = theory.map(|t| format!(" (theory {t})")).unwrap_or_default();
    match sweep {
        Some(Sweep::FixedStep) => format!("order {p:.2} in h{t}"),
        Some(Sweep::Resolution(n)) => format!("slope {p:.2} in {n}{t}"),
        _ => format!("error ~ rtol^{p:.2}"),
    }
}

/// Versions of the main dependencies, read from `Cargo.lock` at build time.
fn versions() -> String {
    let lock = include_str!("../../../Cargo.lock");
    let mut out = Vec::new();
    for name in ["nalgebra", "faer", "parry3d-f64", "quick-xml", "zip"] {
        let needle = format!("name = \"{name}\"\nversion = \"");
        if let Some(i) = lock.find(&needle) {
            let rest = &lock[i + needle.len()..];
            if let Some(j) = rest.find('"') {
                out.push(format!("{name} {}", &rest[..j]));
            }
        }
    }
    format!("mbcosim {}, {}", env!("CARGO_PKG_VERSION"), out.join(", "))
}

/// CPU model, logical CPUs and kernel of this machine.
fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let n = std::thread::available_parallelism().map_or(1, |n| n.get());
    let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease")
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|_| "unknown".into());
    let rustc = std::process::Command::new("rustc")
        .arg("--version")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "rustc unknown".into());
    format!("{cpu}, {n} logical CPUs, Linux {kernel}, {rustc} (runs single-threaded)")
}

fn sci(x: f64) -> String {
    if x.is_nan() {
        "failed".into()
    } else {
        format!("{x:.1e}")
    }
}

/// The markdown report; `targets` are the accuracy levels of the recommendation table.
pub fn markdown(studies: &[Study], repeats: usize, targets: &[f64]) -> String {
    let mut md = String::from("# Work-precision report\n\n");
    let _ = writeln!(
        md,
        "Machine: {}.  \nVersions: {}.  \nTimes are the median of {repeats} runs (CPU = wall clock of a single-threaded run, set-up included). Errors are against a reference at a much tighter tolerance; the reference check row gives the difference between the reference and an independent tight run (errors below it are not resolved). In tolerance sweeps each error is followed by error / rtol in parentheses.\n",
        machine(),
        versions()
    );
    md.push_str("## Recommendations: the cheapest measured setting per accuracy target\n\n");
    md.push_str("| problem | quantity | target | setting | CPU [ms] | real-time factor |\n|---|---|---|---|---|---|\n");
    for st in studies {
        for (q, quantity) in st.quantities.iter().enumerate() {
            for &tol in targets {
                let row = match st.cheapest_within(q, tol) {
                    Some(s) => format!(
                        "{} | {:.2} | {:.0}",
                        s.setting.describe(),
                        1e3 * s.cpu_median,
                        st.simulated / s.cpu_median
                    ),
                    None => "none measured | - | -".into(),
                };
                let target = match quantity.error {
                    super::ErrorKind::Relative => format!("{}%", 100.0 * tol),
                    _ => format!("{tol:.0e} {}", quantity.unit),
                };
                let _ = writeln!(md, "| {} | {} | {target} | {row} |", st.name, quantity.name);
            }
        }
    }
    md.push('\n');
    for st in studies {
        let _ = writeln!(md, "## {}\n\n{}\n", st.name, st.title);
        let refs: Vec<String> = st
            .quantities
            .iter()
            .zip(&st.reference_values)
            .zip(&st.reference_uncertainty)
            .map(|((q, v), u)| format!("{} = {v:.9e} {} (check {u:.1e})", q.name, q.unit))
            .collect();
        let _ = writeln!(
            md,
            "Reference ({}): {}.\n",
            st.reference.describe(),
            refs.join("; ")
        );
        let names: Vec<&str> = st.quantities.iter().map(|q| q.name).collect();
        let _ = writeln!(
            md,
            "| setting | {} error | CPU [ms] | real-time factor | steps | rejected | Newton | LU | cost/step [us] |",
            names.join(" error | ")
        );
        let _ = writeln!(
            md,
            "|---|{}---|---|---|---|---|---|---|",
            "---|".repeat(names.len())
        );
        for s in &st.samples {
            // a tolerance sweep also gives error / rtol: what the tolerance bought
            let errs: Vec<String> = s
                .errors
                .iter()
                .map(|e| match s.setting.sweep {
                    Sweep::Tolerance if e.is_finite() => {
                        format!("{} ({:.2})", sci(*e), e / s.setting.x)
                    }
                    _ => sci(*e),
                })
                .collect();
            let (steps, rej, newton, lu) = match &s.outcome {
                Ok(o) => (
                    o.stats.steps,
                    o.stats.rejected,
                    o.stats.newton_iterations,
                    o.stats.factorizations,
                ),
                Err(_) => (0, 0, 0, 0),
            };
            let per_step = if steps > 0 {
                format!("{:.1}", 1e6 * s.cpu_median / steps as f64)
            } else {
                "-".into()
            };
            let _ = writeln!(
                md,
                "| {} | {} | {:.2} | {:.0} | {steps} | {rej} | {newton} | {lu} | {per_step} |",
                s.setting.describe(),
                errs.join(" | "),
                1e3 * s.cpu_median,
                st.simulated / s.cpu_median
            );
        }
        let failures: Vec<String> = st
            .samples
            .iter()
            .filter_map(|s| {
                s.outcome
                    .as_ref()
                    .err()
                    .map(|e| format!("- {}: {e}", s.setting.describe()))
            })
            .collect();
        if !failures.is_empty() {
            let _ = writeln!(
                md,
                "\nFailed runs (stopped with a message):\n{}",
                failures.join("\n")
            );
        }
        md.push_str("\nObserved orders:\n\n");
        for series in st.series() {
            let first = st
                .of_series(&series)
                .next()
                .map(|s| (s.setting.sweep, s.setting.theory));
            let notes: Vec<String> = (0..st.quantities.len())
                .map(|q| {
                    format!(
                        "{}: {}",
                        st.quantities[q].name,
                        order_note(
                            st.observed_order(&series, q),
                            first.map(|f| f.0),
                            first.and_then(|f| f.1)
                        )
                    )
                })
                .collect();
            let _ = writeln!(md, "- {series}: {}", notes.join("; "));
        }
        md.push('\n');
        for q in &st.quantities {
            let _ = writeln!(md, "![{} {}]({}_{}.svg)", st.name, q.name, st.name, q.name);
        }
        md.push('\n');
    }
    md
}

/// Writes `work_precision.csv`, the plots and `report.md` into `dir`; returns the files written.
pub fn write_all(
    dir: &Path,
    studies: &[Study],
    repeats: usize,
    targets: &[f64],
) -> Result<Vec<String>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut written = Vec::new();
    let mut put = |name: String, text: String| -> Result<(), String> {
        let path = dir.join(&name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path.display().to_string());
        Ok(())
    };
    put("work_precision.csv".into(), csv(studies))?;
    for st in studies {
        for (q, quantity) in st.quantities.iter().enumerate() {
            put(format!("{}_{}.svg", st.name, quantity.name), plot(st, q))?;
        }
    }
    put("report.md".into(), markdown(studies, repeats, targets))?;
    Ok(written)
}
