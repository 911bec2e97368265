//! Flexible PanelLock work-precision problem: the paper's recommended contact set (k = 1e7,
//! n = 1.5) with three Craig-Bampton panels of 10 modes: largest lock force and post-lock
//! frequency (tip-velocity spectrum) across integrators and tolerances.

use super::{ErrorKind, Outcome, Problem, Quantity, Setting};
use crate::integrator::IntegratorKind::{Bdf, GenAlpha};
use crate::scene::panel_lock::{PanelLockParams, study};

/// Deployment, lock-up and post-lock vibration over `t_end` [s] sampled every 0.01 s.
pub fn flexible_deployment(t_end: f64) -> Problem {
    let mut settings = Vec::new();
    for rtol in [1e-2, 1e-3, 1e-4, 1e-5] {
        settings.push(Setting::tolerance(GenAlpha, rtol, 1e-2, 0.02));
    }
    for rtol in [1e-3, 1e-4, 1e-5, 1e-6] {
        let mut s = Setting::tolerance(Bdf, rtol, 1e-2, 0.02);
        s.settings.max_order = 2;
        s.series = "bdf (order <= 2)".into();
        settings.push(s);
    }
    Problem {
        name: "panel_flex",
        title: format!(
            "PanelLock with flexible panels (three Craig-Bampton panels, 10 modes each, 0.5 % modal damping, latches without play, k = 1e7 N/m^1.5, n = 1.5), {t_end} s: largest lock force and post-lock frequency from the spectrum of the outer tip's normal velocity. DOPRI5 is left out: explicit steps on the panel modes make it orders of magnitude slower."
        ),
        simulated: t_end,
        quantities: vec![
            Quantity {
                name: "peak_force",
                unit: "N",
                error: ErrorKind::Relative,
            },
            Quantity {
                name: "frequency",
                unit: "Hz",
                error: ErrorKind::Relative,
            },
        ],
        reference: Setting::tolerance(Bdf, 1e-8, 1e-2, 0.02),
        reference_check: Setting::tolerance(Bdf, 1e-7, 1e-2, 0.02),
        settings,
        run: Box::new(move |s| {
            let p = PanelLockParams {
                integrator: s.integrator,
                settings: s.settings,
                ..PanelLockParams::flexible(10)
            };
            let r = study::run_case(p.clone(), t_end, 0.01)?;
            let f = r
                .frequency
                .ok_or("no post-lock frequency (a hinge did not lock in the window)")?;
            // statistics: the study runs its own scene; count steps from it
            let stats = crate::integrator::Stats {
                steps: r.steps,
                ..Default::default()
            };
            Ok(Outcome {
                values: vec![r.peak_force, f],
                stats,
            })
        }),
    }
}
