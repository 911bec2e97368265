//! PanelLock work-precision problems (rigid panels): the deployment through the first locks
//! (adaptive tolerance sweeps) and the smooth spring-driven phase before any lock (fixed-step
//! order study).

use super::{ErrorKind, Outcome, Problem, Quantity, Setting};
use crate::integrator::IntegratorKind::{Bdf, Dopri5, GenAlpha};
use crate::scene::panel_lock::{PanelLock, PanelLockParams};

/// Runs the default scene with `s` to `t_end` [s].
fn simulate(s: &Setting, t_end: f64) -> Result<PanelLock, String> {
    let p = PanelLockParams {
        integrator: Some(s.integrator),
        settings: s.settings,
        ..PanelLockParams::default()
    };
    let mut scene = PanelLock::new(p)?;
    scene.advance_to(t_end).map_err(String::from)?;
    Ok(scene)
}

/// When the root lock's impact is over and no other hinge has locked yet [s] (root lock at
/// about 4.9 s, the next at about 7.1 s).
const FIRST_LOCK_SETTLED: f64 = 6.0;

/// Deployment of the default scene (three rigid panels) over `t_end` [s] with the root, third and
/// second hinges locking (at about 4.9, 7.1 and 10.9 s): largest lock force, first lock time,
/// energy balance and constraint residual. `quick`: three tolerances per integrator.
pub fn deployment(t_end: f64, quick: bool) -> Problem {
    let tolerances: &[f64] = if quick {
        &[1e-3, 1e-5, 1e-7]
    } else {
        &[1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]
    };
    let mut settings = Vec::new();
    for kind in [GenAlpha, Bdf, Dopri5] {
        for &rtol in tolerances {
            let h_max = if kind == Dopri5 { 0.2 } else { 0.02 };
            settings.push(Setting::tolerance(kind, rtol, 1e-2, h_max));
        }
    }
    Problem {
        name: "panel_rigid",
        title: format!(
            "PanelLock default scene (satellite fixed, yoke and three rigid panels, Lankarani-Nikravesh latches k = 1e7 N/m^1.5), {t_end} s of deployment and lock-up. Quantities: the largest pin/groove force over all hinges, the largest force of the root lock's own impact (up to {FIRST_LOCK_SETTLED} s, before the next lock), the first (root) lock time, the energy balance error relative to the spring energy released, the constraint residual at the end."
        ),
        simulated: t_end,
        quantities: vec![
            Quantity {
                name: "peak_force",
                unit: "N",
                error: ErrorKind::Relative,
            },
            Quantity {
                name: "first_peak_force",
                unit: "N",
                error: ErrorKind::Relative,
            },
            Quantity {
                name: "lock_time",
                unit: "s",
                error: ErrorKind::Absolute,
            },
            Quantity {
                name: "energy",
                unit: "",
                error: ErrorKind::Intrinsic,
            },
            Quantity {
                name: "drift",
                unit: "m",
                error: ErrorKind::Intrinsic,
            },
        ],
        reference: Setting::tolerance(Bdf, 1e-10, 1e-2, 0.02),
        reference_check: Setting::tolerance(Dopri5, 1e-10, 1e-2, 0.02),
        settings,
        run: Box::new(move |s| {
            let p = PanelLockParams {
                integrator: Some(s.integrator),
                settings: s.settings,
                ..PanelLockParams::default()
            };
            let mut scene = PanelLock::new(p)?;
            let e0 = scene.sim.energy();
            // the root lock's own impact, before the next hinge locks
            scene
                .advance_to(FIRST_LOCK_SETTLED.min(t_end))
                .map_err(String::from)?;
            let first_peak = scene.outputs().hinges[0].peak_force;
            scene.advance_to(t_end).map_err(String::from)?;
            let o = scene.outputs();
            let e1 = scene.sim.energy();
            let released = e0.potential - e1.potential;
            Ok(Outcome {
                values: vec![
                    o.hinges.iter().map(|h| h.peak_force).fold(0.0, f64::max),
                    first_peak,
                    o.hinges[0].lock_time,
                    (e1.balance() - e0.balance()) / released.abs().max(f64::MIN_POSITIVE),
                    scene.sim.constraint_residual(),
                ],
                stats: scene.sim.stats(),
            })
        }),
    }
}

/// The smooth phase: every hinge angle at `t_end` [s] (2 s in the report: between 2 and 3 s the
/// scene passes a point where its forces are not smooth to fifth order, after which BDF5's
/// fixed-step error no longer falls as h^5; the first lock is at 4.9 s) with
/// fixed steps, for the observed order of each method: gen-alpha (2), BDF of order 1 to 5,
/// DOPRI5 (5).
pub fn smooth_phase(t_end: f64, quick: bool) -> Problem {
    let steps: &[f64] = if quick {
        &[0.04, 0.02, 0.01]
    } else {
        &[0.04, 0.02, 0.01, 0.005, 0.0025]
    };
    let mut settings = Vec::new();
    for &h in steps {
        settings.push(Setting::fixed(GenAlpha, h, 2));
    }
    let orders: &[usize] = if quick { &[1, 2, 4] } else { &[1, 2, 3, 4, 5] };
    for &k in orders {
        for &h in steps {
            settings.push(Setting::fixed(Bdf, h, k));
        }
    }
    for &h in steps {
        settings.push(Setting::fixed(Dopri5, 5.0 * h, 5));
    }
    Problem {
        name: "panel_smooth",
        title: format!(
            "PanelLock default scene, smooth spring-driven deployment from 0 to {t_end} s (no contact yet), fixed steps: the root and the outermost hinge angles at {t_end} s."
        ),
        simulated: t_end,
        quantities: vec![
            Quantity {
                name: "root_angle",
                unit: "rad",
                error: ErrorKind::Absolute,
            },
            Quantity {
                name: "outer_angle",
                unit: "rad",
                error: ErrorKind::Absolute,
            },
        ],
        reference: Setting::tolerance(Dopri5, 1e-12, 1e-2, 0.02),
        reference_check: Setting::tolerance(Bdf, 1e-12, 1e-2, 0.02),
        settings,
        run: Box::new(move |s| {
            let mut scene = simulate(s, t_end)?;
            let n = scene.layout.hinges.len();
            Ok(Outcome {
                values: vec![scene.hinge_angle(0).0, scene.hinge_angle(n - 1).0],
                stats: scene.sim.stats(),
            })
        }),
    }
}
