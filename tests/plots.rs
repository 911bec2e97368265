//! The plots as images, read back from their SVG: the Table 1 force plot shows the located peak
//! force although the output step (0.01 s) is far longer than the lock-up impact, and the
//! plots of the PanelLock study keep their legends outside the data and their text on the
//! canvas (issue #23). Forces in N, times in s.

use mbcosim::report::svg_check::{check, check_any, parse};
use mbcosim::scene::panel_lock::PanelLockParams;
use mbcosim::scene::panel_lock::study::{
    CaseResult, backbone_plot, force_plot, run_case, spectrum_plot, tip_velocity_plot,
};
use std::sync::OnceLock;

/// One flexible panel with 4 modes, the stiff n = 0.9 contact of Table 1's third case, to 9 s
/// (the root hinge locks near 5 s): a short run with the same brief impact, run once for both
/// tests.
fn short_case() -> CaseResult {
    static CASE: OnceLock<CaseResult> = OnceLock::new();
    CASE.get_or_init(|| {
        let p = PanelLockParams {
            n_panels: 1,
            contact_stiffness: 1e8,
            contact_exponent: 0.9,
            ..PanelLockParams::flexible(4)
        };
        run_case(p, 9.0, 0.01).unwrap()
    })
    .clone()
}

#[test]
fn force_plot_reaches_the_located_peak_that_the_samples_miss() {
    let c = short_case();
    assert!(
        c.lock_times.iter().all(|t| t.is_finite()),
        "{:?}",
        c.lock_times
    );
    // the plot is the root hinge's (the paper's Fig. 4)
    let root_peak = c.peak_forces[0];
    let sampled = c.forces[0].iter().copied().fold(0.0, f64::max);
    let svg = force_plot(std::slice::from_ref(&c), "flexible");
    let plot = parse(&svg).unwrap();
    check(&plot).unwrap();
    let plotted = plot.series[0]
        .points
        .iter()
        .map(|p| p.1)
        .fold(0.0, f64::max);
    println!(
        "root peak {root_peak:.1} N (largest {:.1} N, hinge {}), plotted {plotted:.1} N, largest 0.01 s root sample {sampled:.1} N, {} accepted steps",
        c.peak_force,
        c.peak_hinge,
        c.trace.t.len()
    );
    assert!(
        (plotted - root_peak).abs() <= 1e-3 * root_peak,
        "plotted {plotted} N against the root hinge's located peak {root_peak} N"
    );
    assert!(
        sampled < root_peak,
        "the 0.01 s samples reach the peak here"
    );
    // the located peaks and the trace agree exactly (same parabola, same samples)
    assert!((c.trace.hinge_peak(0).1 - root_peak).abs() <= 1e-9 * root_peak);
    assert!((c.trace.peak().1 - c.peak_force).abs() <= 1e-9 * c.peak_force);
}

#[test]
fn study_plots_pass_the_layout_checks_with_three_cases() {
    let c = short_case();
    let cases = [c.clone(), c.clone(), c];
    for svg in [
        force_plot(&cases, "flexible"),
        tip_velocity_plot(&cases, "flexible"),
        spectrum_plot(&cases, "flexible", 0.01),
        backbone_plot(&cases, "flexible"),
    ] {
        let plot = parse(&svg).unwrap();
        check(&plot).unwrap();
        assert_eq!(plot.series.len(), 3);
        let dashes: std::collections::BTreeSet<&str> =
            plot.series.iter().map(|s| s.dash.as_str()).collect();
        assert_eq!(dashes.len(), 3, "dash patterns repeat");
        assert!(
            plot.texts.iter().any(|t| t.text.contains('[')),
            "no unit in the labels"
        );
    }
}

/// Every plot the project has written into docs/ (any folder below it) passes the layout checks
/// of its kind: our own SVGs (demo, Table 1, work-precision) the full checks, the parameter
/// studies' matplotlib plots the layout their renderer measured ([`check_any`]); among them, no
/// legend covers a mark or a label.
#[test]
fn committed_plots_pass_the_layout_checks() {
    fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|x| x == "svg") {
                out.push(path);
            }
        }
    }
    let docs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
    let mut files = Vec::new();
    walk(&docs, &mut files);
    assert!(files.len() >= 30, "{} plots", files.len());
    let studies = files
        .iter()
        .filter(|f| f.to_string_lossy().contains("parameter_studies"))
        .count();
    assert!(studies >= 3, "{studies} parameter-study plots");
    for f in files {
        let svg = std::fs::read_to_string(&f).unwrap();
        check_any(&svg).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
    }
}
