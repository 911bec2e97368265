//! Redraws the work-precision plots from a written report (`work_precision.csv` and
//! `report.md` in one folder) without running anything: the runs are matched to the settings of
//! [`super::problems`] by problem, series and swept value; the reference check (which sets the
//! error floor of the observed orders) is read from the report's "Reference" lines.

use super::output::{CSV_HEADER, plot};
use super::{Outcome, Sample, Study, problems};
use crate::integrator::Stats;
use std::path::Path;

/// One CSV row: the run's problem, series, swept value, quantity and what was measured.
struct Row {
    problem: String,
    series: String,
    x: f64,
    quantity: String,
    value: f64,
    reference: f64,
    error: f64,
    cpu_median: f64,
    cpu_best: f64,
    stats: Stats,
    failure: String,
}

fn rows(csv: &str) -> Result<Vec<Row>, String> {
    let mut lines = csv.lines();
    if lines.next() != Some(CSV_HEADER) {
        return Err("work_precision.csv: unexpected header".into());
    }
    let n = CSV_HEADER.split(',').count();
    lines
        .filter(|l| !l.is_empty())
        .map(|l| {
            let f: Vec<&str> = l.splitn(n, ',').collect();
            if f.len() != n {
                return Err(format!("work_precision.csv: short row {l:?}"));
            }
            let num = |i: usize| {
                f[i].parse::<f64>()
                    .map_err(|_| format!("bad number in {l:?}"))
            };
            let int = |i: usize| {
                f[i].parse::<u64>()
                    .map_err(|_| format!("bad count in {l:?}"))
            };
            Ok(Row {
                problem: f[0].into(),
                series: f[1].into(),
                x: num(3)?,
                quantity: f[5].into(),
                value: num(7)?,
                reference: num(8)?,
                error: num(9)?,
                cpu_median: num(10)?,
                cpu_best: num(11)?,
                stats: Stats {
                    steps: int(12)?,
                    rejected: int(13)?,
                    newton_iterations: int(14)?,
                    factorizations: int(15)?,
                    rhs_evaluations: int(16)?,
                    ..Stats::default()
                },
                failure: f[17].into(),
            })
        })
        .collect()
}

/// The "(check u)" values of problem `name`'s reference line in `report`, in quantity order.
fn checks(report: &str, name: &str) -> Option<Vec<f64>> {
    let section = report.split(&format!("## {name}\n")).nth(1)?;
    let line = section.lines().find(|l| l.starts_with("Reference ("))?;
    line.split("(check ")
        .skip(1)
        .map(|s| s.split(')').next()?.parse().ok())
        .collect()
}

/// Rewrites every `{problem}_{quantity}.svg` of the report in `dir`; returns the files written.
pub fn replot(dir: &Path) -> Result<Vec<String>, String> {
    let read = |f: &str| {
        std::fs::read_to_string(dir.join(f)).map_err(|e| format!("{}: {e}", dir.join(f).display()))
    };
    let (all, report) = (rows(&read("work_precision.csv")?)?, read("report.md")?);
    let mut written = Vec::new();
    for p in problems(false) {
        let mine: Vec<&Row> = all.iter().filter(|r| r.problem == p.name).collect();
        if mine.is_empty() {
            continue;
        }
        let uncertainty =
            checks(&report, p.name).ok_or(format!("report.md: no reference of {}", p.name))?;
        let mut samples = Vec::new();
        for s in &p.settings {
            let of = |q: &str| {
                mine.iter().find(|r| {
                    r.series == s.series && r.quantity == q && (r.x - s.x).abs() <= 1e-9 * s.x.abs()
                })
            };
            let found: Option<Vec<&&Row>> = p.quantities.iter().map(|q| of(q.name)).collect();
            let Some(found) = found else { continue };
            let first = found[0];
            samples.push(Sample {
                setting: s.clone(),
                outcome: if first.failure.is_empty() {
                    Ok(Outcome {
                        values: found.iter().map(|r| r.value).collect(),
                        stats: first.stats,
                    })
                } else {
                    Err(first.failure.clone())
                },
                cpu_median: first.cpu_median,
                cpu_best: first.cpu_best,
                errors: found.iter().map(|r| r.error).collect(),
            });
        }
        let reference_values = p
            .quantities
            .iter()
            .map(|q| {
                mine.iter()
                    .find(|r| r.quantity == q.name)
                    .map_or(f64::NAN, |r| r.reference)
            })
            .collect();
        let st = Study {
            name: p.name,
            title: p.title.clone(),
            simulated: p.simulated,
            quantities: p.quantities.clone(),
            reference: p.reference.clone(),
            reference_values,
            reference_uncertainty: uncertainty,
            samples,
        };
        for (q, quantity) in st.quantities.iter().enumerate() {
            let path = dir.join(format!("{}_{}.svg", st.name, quantity.name));
            std::fs::write(&path, plot(&st, q)).map_err(|e| format!("{}: {e}", path.display()))?;
            written.push(path.display().to_string());
        }
    }
    Ok(written)
}
