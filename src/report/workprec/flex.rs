//! Flexible PanelLock work-precision problem: the paper's recommended contact set (k = 1e7,
//! n = 1.5) with three Craig-Bampton panels of 10 modes: largest lock force and post-lock
//! frequency (tip-velocity spectrum) across integrators and tolerances, and across the model
//! resolution (modes per panel, finite-element mesh).

use super::{ErrorKind, Outcome, Problem, Quantity, Setting, Sweep};
use crate::integrator::IntegratorKind::{Bdf, GenAlpha};
use crate::integrator::Settings;
use crate::scene::panel_lock::{PanelLockParams, study};

fn quantities() -> Vec<Quantity> {
    vec![
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
    ]
}

/// Runs the flexible scene `p` with solver `s` over `t_end` [s]: the largest lock force and the
/// post-lock frequency.
fn run_flexible(s: &Setting, p: PanelLockParams, t_end: f64) -> Result<Outcome, String> {
    // per step, as the PanelLock FMU runs: per unit step neither BDF nor gen-alpha starts the
    // flexible scene (docs/integrator_error_control.md, "Found 2026-11-28")
    let p = PanelLockParams {
        integrator: Some(s.integrator),
        settings: Settings {
            error_per_unit_step: false,
            ..s.settings
        },
        ..p
    };
    let r = study::run_case(p, t_end, 0.01)?;
    let f = r
        .frequency
        .ok_or("no post-lock frequency (a hinge did not lock in the window)")?;
    Ok(Outcome {
        values: vec![r.peak_force, f],
        stats: r.stats,
    })
}

/// The solver of the resolution sweeps: gen-alpha at rtol 1e-5 (its error there is well below
/// the resolution errors measured).
fn resolution_setting(knob: &'static str, x: f64) -> Setting {
    Setting {
        series: "gen-alpha rtol 1e-5".into(),
        sweep: Sweep::Resolution(knob),
        x,
        ..Setting::tolerance(GenAlpha, 1e-5, 1e-2, 0.02)
    }
}

/// Modes per panel (2 to 12) against 16, on the default 8 x 4 mesh, over `t_end` [s].
pub fn modes(t_end: f64) -> Problem {
    let at = |n: f64| resolution_setting("modes per panel", n);
    Problem {
        name: "panel_modes",
        title: format!(
            "PanelLock with flexible panels as in panel_flex, {t_end} s, with 2 to 12 Craig-Bampton modes per panel against 16 (check: 14): what each mode costs and buys."
        ),
        simulated: t_end,
        quantities: quantities(),
        reference: at(16.0),
        reference_check: at(14.0),
        settings: [2.0, 4.0, 6.0, 8.0, 10.0, 12.0]
            .iter()
            .map(|&n| at(n))
            .collect(),
        run: Box::new(move |s| run_flexible(s, PanelLockParams::flexible(s.x as usize), t_end)),
    }
}

/// Finite-element mesh of each panel (n x n/2 plate elements, n = 4 to 16; n/2 must be even)
/// against 24 x 12, with 10 modes per panel, over `t_end` [s].
pub fn mesh(t_end: f64) -> Problem {
    let at = |n: f64| resolution_setting("elements along the panel", n);
    Problem {
        name: "panel_mesh",
        title: format!(
            "PanelLock with flexible panels as in panel_flex (10 modes per panel), {t_end} s, with a plate mesh of n x n/2 elements per panel, n = 4 to 16, against 24 x 12 (check: 20 x 10): what the finite-element mesh costs and buys. The hinge and latch loads, moments included, enter each plate at single nodes; a thin plate's rotation under a concentrated moment grows without bound (logarithmically) as the mesh is refined, so the lock force, which feels that local flexibility, converges slowly with the mesh while the frequency converges fast."
        ),
        simulated: t_end,
        quantities: quantities(),
        reference: at(24.0),
        reference_check: at(20.0),
        settings: [4.0, 8.0, 12.0, 16.0].iter().map(|&n| at(n)).collect(),
        run: Box::new(move |s| {
            let n = s.x as usize;
            let p = PanelLockParams {
                panel_mesh: [n, n / 2],
                ..PanelLockParams::flexible(10)
            };
            run_flexible(s, p, t_end)
        }),
    }
}

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
        quantities: quantities(),
        reference: Setting::tolerance(Bdf, 1e-8, 1e-2, 0.02),
        reference_check: Setting::tolerance(Bdf, 1e-7, 1e-2, 0.02),
        settings,
        run: Box::new(move |s| run_flexible(s, PanelLockParams::flexible(10), t_end)),
    }
}
