//! Work-precision studies: run a problem across solver and model-resolution settings, measure the
//! error of the quantities users care about against a much tighter reference (itself checked
//! against a second tight run), and the CPU time (median of several runs).
//!
//! A [`Problem`] is data plus one closure that runs a [`Setting`] and returns the quantities; the
//! study ([`run_study`]) does the timing, the errors and the fits, and [`output`] writes the CSV,
//! the log-log plots and the markdown report.

pub mod flex;
pub mod output;
pub mod panel;
pub mod replot;
pub mod rope;

use crate::integrator::{IntegratorKind, Settings, Stats};
use std::time::Instant;

/// What a series sweeps (its `x`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sweep {
    /// Relative tolerance of an adaptive integrator.
    Tolerance,
    /// Fixed step [s] (order study).
    FixedStep,
    /// A model-resolution count (modes, mesh cells, rope nodes), named.
    Resolution(&'static str),
}

impl Sweep {
    /// Axis label.
    pub fn label(self) -> &'static str {
        match self {
            Sweep::Tolerance => "rtol",
            Sweep::FixedStep => "h [s]",
            Sweep::Resolution(n) => n,
        }
    }
}

/// One run configuration: the integrator and its settings, the swept value `x`, and the series
/// (curve) it belongs to.
#[derive(Debug, Clone)]
pub struct Setting {
    pub series: String,
    pub sweep: Sweep,
    pub x: f64,
    pub integrator: IntegratorKind,
    pub settings: Settings,
    /// Theoretical order of the series (fixed-step and resolution sweeps), for the annotation.
    pub theory: Option<f64>,
}

impl Setting {
    /// An adaptive run of `kind` at `rtol` (atol = `atol_ratio` rtol, largest step `h_max`).
    pub fn tolerance(kind: IntegratorKind, rtol: f64, atol_ratio: f64, h_max: f64) -> Self {
        Setting {
            series: kind.name().into(),
            sweep: Sweep::Tolerance,
            x: rtol,
            integrator: kind,
            settings: Settings {
                rtol,
                atol: rtol * atol_ratio,
                h_max,
                ..Settings::default()
            },
            theory: None,
        }
    }

    /// A fixed-step run of `kind` (BDF of order `order`; ignored by the others).
    pub fn fixed(kind: IntegratorKind, h: f64, order: usize) -> Self {
        let newton_rtol = match kind {
            IntegratorKind::Bdf => 10f64.powi(-(6 + order.clamp(1, 4) as i32)),
            _ => 1e-10,
        };
        let (series, theory) = match kind {
            IntegratorKind::GenAlpha => ("gen-alpha".to_string(), 2.0),
            IntegratorKind::Bdf => (format!("bdf{order}"), order as f64),
            IntegratorKind::Dopri5 => ("dopri5".to_string(), 5.0),
            IntegratorKind::Dopri5Tree => ("dopri5-tree".to_string(), 5.0),
            IntegratorKind::Verner65Tree => ("verner65-tree".to_string(), 6.0),
            IntegratorKind::Verner87Tree => ("verner87-tree".to_string(), 8.0),
        };
        Setting {
            series,
            sweep: Sweep::FixedStep,
            x: h,
            integrator: kind,
            settings: Settings {
                fixed_step: h,
                h_max: h,
                max_order: order.clamp(1, 5),
                // Newton tolerance only (no error control at fixed steps): below the method's
                // truncation error (BDF: 1e-7 for order 1 .. 1e-10 for orders 4 and 5, no
                // tighter, so that low orders converge in 10 iterations at the largest steps)
                rtol: newton_rtol,
                atol: 1e-2 * newton_rtol,
                ..Settings::default()
            },
            theory: Some(theory),
        }
    }

    /// Short text for tables.
    pub fn describe(&self) -> String {
        match self.sweep {
            Sweep::Tolerance => format!("{} rtol {:.0e}", self.series, self.x),
            Sweep::FixedStep => format!("{} h {:.1e} s", self.series, self.x),
            Sweep::Resolution(n) => format!("{} {n} {}", self.series, self.x),
        }
    }
}

/// How a quantity's error is measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ErrorKind {
    /// `|v - ref| / |ref|`.
    Relative,
    /// `|v - ref|` in the quantity's unit.
    Absolute,
    /// The value is itself an error (energy balance, constraint drift): `|v|`.
    Intrinsic,
}

/// A quantity reported by a problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    pub name: &'static str,
    pub unit: &'static str,
    pub error: ErrorKind,
}

/// What one run returns.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// One value per quantity, in the problem's order.
    pub values: Vec<f64>,
    pub stats: Stats,
}

/// A closure running one setting.
pub type Runner = Box<dyn Fn(&Setting) -> Result<Outcome, String>>;

/// A work-precision problem.
pub struct Problem {
    /// File-name stem, e.g. `panel_rigid`.
    pub name: &'static str,
    /// One sentence: scene, duration, what is measured.
    pub title: String,
    /// Simulated time per run [s] (for the real-time factor).
    pub simulated: f64,
    pub quantities: Vec<Quantity>,
    /// The reference and an independent tight run that checks it.
    pub reference: Setting,
    pub reference_check: Setting,
    pub settings: Vec<Setting>,
    pub run: Runner,
}

/// One measured run.
#[derive(Debug, Clone)]
pub struct Sample {
    pub setting: Setting,
    /// The outcome, or why the run failed.
    pub outcome: Result<Outcome, String>,
    /// Median and best CPU time [s].
    pub cpu_median: f64,
    pub cpu_best: f64,
    /// Error per quantity (NaN when failed).
    pub errors: Vec<f64>,
}

/// The result of a study.
pub struct Study {
    pub name: &'static str,
    pub title: String,
    pub simulated: f64,
    pub quantities: Vec<Quantity>,
    pub reference: Setting,
    pub reference_values: Vec<f64>,
    /// Difference between the reference and its check, as an error per quantity.
    pub reference_uncertainty: Vec<f64>,
    pub samples: Vec<Sample>,
}

/// Error of `v` against `reference` for `q`.
pub fn error_of(q: &Quantity, v: f64, reference: f64) -> f64 {
    match q.error {
        ErrorKind::Relative => (v - reference).abs() / reference.abs().max(f64::MIN_POSITIVE),
        ErrorKind::Absolute => (v - reference).abs(),
        ErrorKind::Intrinsic => v.abs(),
    }
}

/// Runs `f` `repeats` times (at least once); returns its last result and the median and best
/// wall-clock times [s].
pub fn timed<T>(repeats: usize, mut f: impl FnMut() -> T) -> (T, f64, f64) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let t0 = Instant::now();
        last = Some(f());
        times.push(t0.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    (last.expect("ran at least once"), median, times[0])
}

/// Runs the reference, its check and every setting of `problem` (`repeats` timings each).
pub fn run_study(problem: &Problem, repeats: usize) -> Result<Study, String> {
    let reference = (problem.run)(&problem.reference)
        .map_err(|e| format!("{}: the reference run failed: {e}", problem.name))?;
    let check = (problem.run)(&problem.reference_check)
        .map_err(|e| format!("{}: the reference check run failed: {e}", problem.name))?;
    let uncertainty = problem
        .quantities
        .iter()
        .enumerate()
        .map(|(i, q)| match q.error {
            ErrorKind::Intrinsic => check.values[i].abs().max(reference.values[i].abs()),
            _ => error_of(q, check.values[i], reference.values[i]),
        })
        .collect();
    let mut samples = Vec::new();
    for s in &problem.settings {
        let (outcome, cpu_median, cpu_best) = timed(repeats, || (problem.run)(s));
        let errors = match &outcome {
            Ok(o) => problem
                .quantities
                .iter()
                .enumerate()
                .map(|(i, q)| error_of(q, o.values[i], reference.values[i]))
                .collect(),
            Err(_) => vec![f64::NAN; problem.quantities.len()],
        };
        samples.push(Sample {
            setting: s.clone(),
            outcome,
            cpu_median,
            cpu_best,
            errors,
        });
    }
    Ok(Study {
        name: problem.name,
        title: problem.title.clone(),
        simulated: problem.simulated,
        quantities: problem.quantities.clone(),
        reference: problem.reference.clone(),
        reference_values: reference.values,
        reference_uncertainty: uncertainty,
        samples,
    })
}

/// Least-squares slope of `log10 y` over `log10 x` (points with finite positive x and y); `None`
/// with fewer than two usable points.
pub fn loglog_slope(points: &[(f64, f64)]) -> Option<f64> {
    let p: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.log10(), y.log10()))
        .collect();
    if p.len() < 2 {
        return None;
    }
    let n = p.len() as f64;
    let (mx, my) = (
        p.iter().map(|q| q.0).sum::<f64>() / n,
        p.iter().map(|q| q.1).sum::<f64>() / n,
    );
    let sxx: f64 = p.iter().map(|q| (q.0 - mx).powi(2)).sum();
    let sxy: f64 = p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

impl Study {
    /// Names of the series, in first-appearance order.
    pub fn series(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for s in &self.samples {
            if !out.contains(&s.setting.series) {
                out.push(s.setting.series.clone());
            }
        }
        out
    }

    /// The samples of `series`.
    pub fn of_series<'a>(&'a self, series: &'a str) -> impl Iterator<Item = &'a Sample> + 'a {
        self.samples
            .iter()
            .filter(move |s| s.setting.series == series)
    }

    /// Observed order of quantity `q` in `series`: slope of the error over the swept `x`, using
    /// only errors above 10x the reference uncertainty (and, for relative errors, below 0.5, the
    /// asymptotic range).
    pub fn observed_order(&self, series: &str, q: usize) -> Option<f64> {
        if self.quantities[q].error == ErrorKind::Intrinsic {
            return None;
        }
        let floor = 10.0 * self.reference_uncertainty[q];
        let pts: Vec<(f64, f64)> = self
            .of_series(series)
            .filter(|s| s.errors[q] > floor && s.errors[q] < 0.5)
            .map(|s| (s.setting.x, s.errors[q]))
            .collect();
        loglog_slope(&pts)
    }

    /// The cheapest successful sample (median CPU) whose error on quantity `q` is at most `tol`.
    pub fn cheapest_within(&self, q: usize, tol: f64) -> Option<&Sample> {
        self.samples
            .iter()
            .filter(|s| s.outcome.is_ok() && s.errors[q] <= tol)
            .min_by(|a, b| a.cpu_median.total_cmp(&b.cpu_median))
    }
}

/// Every problem of the report (`quick`: reduced sweeps for a CI smoke run).
pub fn problems(quick: bool) -> Vec<Problem> {
    let mut p = vec![
        panel::smooth_phase(2.0, quick),
        panel::deployment(if quick { 6.0 } else { 12.0 }, quick),
        rope::lift(if quick { 1.0 } else { 4.0 }, quick),
        rope::nodes(if quick { 1.0 } else { 4.0 }, quick),
    ];
    if !quick {
        // tens of seconds per run: the full report only
        p.push(flex::flexible_deployment(65.0));
        p.push(flex::modes(65.0));
        p.push(flex::mesh(65.0));
    }
    p
}

/// Runs every problem whose name contains `only` (all when empty) and not `skip` (none when
/// empty) and writes the report into `dir`; returns the studies and the files written.
pub fn report(
    dir: &std::path::Path,
    quick: bool,
    only: &str,
    skip: &str,
) -> Result<(Vec<Study>, Vec<String>), String> {
    let repeats = if quick { 1 } else { 3 };
    let mut studies = Vec::new();
    for p in problems(quick)
        .iter()
        .filter(|p| p.name.contains(only) && (skip.is_empty() || !p.name.contains(skip)))
    {
        eprintln!("work-precision: {} ({} runs)", p.name, p.settings.len());
        studies.push(run_study(p, repeats)?);
    }
    let files = output::write_all(dir, &studies, repeats, &[1e-2, 1e-4])?;
    Ok((studies, files))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law_and_errors() {
        let pts: Vec<(f64, f64)> = [1e-3, 1e-2, 1e-1]
            .iter()
            .map(|&h| (h, 3.0 * h * h * h))
            .collect();
        assert!((loglog_slope(&pts).unwrap() - 3.0).abs() < 1e-12);
        assert_eq!(loglog_slope(&pts[..1]), None);
        let q = Quantity {
            name: "f",
            unit: "N",
            error: ErrorKind::Relative,
        };
        assert!((error_of(&q, 101.0, 100.0) - 0.01).abs() < 1e-15);
        let (v, med, best) = timed(3, || 7);
        assert_eq!(v, 7);
        assert!(best <= med);
    }
}
