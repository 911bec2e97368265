//! Smoke run of the work-precision report on its reduced sweep (`mbcosim report --quick`): the
//! files are written, every fixed-step series shows its method's order in the smooth phase, and
//! every adaptive series converges as the tolerance tightens. Timings are reported, never tested.

use mbcosim::report::workprec::{ErrorKind, Sweep, report};

#[test]
fn quick_report_converges_with_the_theoretical_orders() {
    let dir = std::env::temp_dir().join(format!("mbcosim-wp-{}", std::process::id()));
    let (studies, files) = report(&dir, true, "", "").unwrap();
    assert!(files.iter().any(|f| f.ends_with("report.md")));
    assert!(files.iter().any(|f| f.ends_with("work_precision.csv")));
    let csv = std::fs::read_to_string(dir.join("work_precision.csv")).unwrap();
    let rows: usize = studies
        .iter()
        .map(|s| s.samples.len() * s.quantities.len())
        .sum();
    assert_eq!(csv.lines().count(), rows + 1);
    for st in &studies {
        assert!(
            st.samples.iter().all(|s| s.outcome.is_ok()),
            "{}: a run failed",
            st.name
        );
        for series in st.series() {
            let samples: Vec<_> = st.of_series(&series).collect();
            for (q, quantity) in st.quantities.iter().enumerate() {
                if quantity.error == ErrorKind::Intrinsic {
                    continue;
                }
                match samples[0].setting.sweep {
                    Sweep::FixedStep => {
                        let theory = samples[0].setting.theory.unwrap();
                        let p = st.observed_order(&series, q).unwrap();
                        assert!(
                            p > theory - 0.35 && p < theory + 1.0,
                            "{} {series} {}: observed order {p}, theory {theory}",
                            st.name,
                            quantity.name
                        );
                    }
                    Sweep::Tolerance => {
                        let loose = samples.first().unwrap().errors[q];
                        let tight = samples.last().unwrap().errors[q];
                        let floor = 10.0 * st.reference_uncertainty[q];
                        // converged, or already accurate at the loosest tolerance: to 1e-4,
                        // or 5 times better than that tolerance asks (step-bound by h_max or
                        // by the communication grid, the error has nothing left to show)
                        let asked = (0.2 * samples[0].setting.settings.rtol).max(1e-4);
                        let accurate = match quantity.error {
                            ErrorKind::Relative => loose < asked,
                            _ => loose < asked * st.reference_values[q].abs().max(1.0),
                        };
                        assert!(
                            tight < 0.1 * loose || tight < floor || accurate,
                            "{} {series} {}: error {loose:e} at the loosest tolerance, {tight:e} at the tightest",
                            st.name,
                            quantity.name
                        );
                    }
                    Sweep::Resolution(_) => {}
                }
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
