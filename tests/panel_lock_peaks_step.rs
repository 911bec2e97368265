//! Per-hinge peak latch forces (`hingeN_peak_force`) against the communication step (issue #42
//! item 4, docs/panel_lock_interface.md): the default 60 s scene advanced as an importer does,
//! one `advance_to` per communication point, at H = 0.1, 0.05, 0.01 and 0.001 s.
//!
//! - Hinges 0, 2 and 3 peak in the first 13 s (their lock-ups and the root's second impact).
//!   References: BDF at rtol 1e-10 and DOPRI5 at rtol 1e-11 over 14 s, which must agree to
//!   1e-4 first; the default solver (`integrator = auto`: dopri5_tree at rtol 1e-9 on this rigid
//!   array) must stay within 0.1 % of their mean at every H, generalized-alpha at its default
//!   rtol 1e-4 within 1 %.
//! - Hinge 1's largest force comes from a chaotic rattle after its lock-up at 27.8 s (runs that
//!   differ by round-off part there). Its reference is the median of an ensemble of tight runs
//!   (joint-coordinate DOPRI5, rtol 1e-10, at three communication steps); the ensemble's own
//!   spread is bounded, the default must hold 1 % at every H, and generalized-alpha at rtol 1e-4
//!   the band the README states for it (within 10 %).

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::{PanelLock, PanelLockParams};

/// Communication steps [s] an importer might use.
const STEPS: [f64; 4] = [0.1, 0.05, 0.01, 0.001];

/// Final peak wall force of each hinge [N] after `t_end` [s], advanced in steps of `h` [s].
fn peaks(p: PanelLockParams, t_end: f64, h: f64) -> Vec<f64> {
    let mut s = PanelLock::new(p).unwrap();
    let n = (t_end / h).round() as usize;
    for k in 1..=n {
        s.advance_to((k as f64 * h).min(t_end)).unwrap();
    }
    s.outputs().hinges.iter().map(|x| x.peak_force).collect()
}

/// The default scene on `kind` at `rtol` (atol rtol / 100).
fn with(kind: IntegratorKind, rtol: f64) -> PanelLockParams {
    let p = PanelLockParams::default();
    PanelLockParams {
        integrator: Some(kind),
        settings: Settings {
            rtol,
            atol: rtol * 1e-2,
            ..p.settings
        },
        ..p
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b
}

#[test]
fn lock_up_peaks_of_hinges_0_2_3_hold_at_every_communication_step() {
    let bdf = peaks(with(IntegratorKind::Bdf, 1e-10), 14.0, 14.0);
    let dopri = peaks(with(IntegratorKind::Dopri5, 1e-11), 14.0, 14.0);
    for k in [0, 2, 3] {
        let e = rel(bdf[k], dopri[k]);
        println!(
            "hinge {k}: BDF {} N, DOPRI5 {} N ({e:.1e})",
            bdf[k], dopri[k]
        );
        assert!(e < 1e-4, "the references disagree on hinge {k}: {e:.2e}");
    }
    let gen_alpha = PanelLockParams {
        integrator: Some(IntegratorKind::GenAlpha),
        ..PanelLockParams::default()
    };
    for h in STEPS {
        let got = peaks(PanelLockParams::default(), 14.0, h);
        let ga = peaks(gen_alpha.clone(), 14.0, h);
        for k in [0, 2, 3] {
            let reference = 0.5 * (bdf[k] + dopri[k]);
            let (e, e_ga) = (rel(got[k], reference), rel(ga[k], reference));
            println!(
                "H {h} s, hinge {k}: {} N, gen_alpha {} N vs {reference} N ({e:.1e}, {e_ga:.1e})",
                got[k], ga[k]
            );
            assert!(e < 1e-3, "hinge {k} at H = {h} s off by {e:.2e}");
            assert!(
                e_ga < 0.01,
                "gen_alpha: hinge {k} at H = {h} s off by {e_ga:.2e}"
            );
        }
    }
}

#[test]
fn rattle_peak_of_hinge_1_holds_one_percent_by_default_and_its_band_on_gen_alpha() {
    let mut ensemble: Vec<f64> = [0.1, 0.05, 0.02]
        .iter()
        .map(|&h| peaks(with(IntegratorKind::Dopri5Tree, 1e-10), 60.0, h)[1])
        .collect();
    ensemble.sort_by(f64::total_cmp);
    let median = ensemble[1];
    let spread = (ensemble[2] - ensemble[0]) / median;
    println!("tight ensemble {ensemble:?} N, spread {spread:.1e}");
    // a chaotic motion: the tight runs do not agree to 1e-5, but their peaks cluster
    assert!(spread < 0.015, "tight ensemble spread {spread:.2e}");
    assert!(
        (200.0..300.0).contains(&median),
        "hinge 1's rattle peak {median} N"
    );
    for h in STEPS {
        let default = peaks(PanelLockParams::default(), 60.0, h)[1];
        let ga = PanelLockParams {
            integrator: Some(IntegratorKind::GenAlpha),
            ..PanelLockParams::default()
        };
        let ga = peaks(ga, 60.0, h)[1];
        let (e_default, e_ga) = (rel(default, median), rel(ga, median));
        println!(
            "H {h} s: default (auto) {default} N ({e_default:.1e}), gen_alpha 1e-4 {ga} N ({e_ga:.1e})"
        );
        assert!(
            e_default < 0.01,
            "default at H = {h} s off by {e_default:.2e}"
        );
        assert!(e_ga < 0.10, "gen_alpha at H = {h} s off by {e_ga:.2e}");
    }
}
