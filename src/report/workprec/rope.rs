//! RopeBlock work-precision problems: the default lift (200 t block, four slings over the deck
//! edges) hoisted at 0.3 m/s from rest, across integrators and tolerances, and across rope
//! resolution (segments per sling).

use super::{ErrorKind, Outcome, Problem, Quantity, Setting, Sweep};
use crate::integrator::IntegratorKind::{Bdf, GenAlpha};
use crate::math::Vec3;
use crate::scene::rope_block::{RopeBlockParams, RopeBlockScene};

fn quantities() -> Vec<Quantity> {
    vec![
        Quantity {
            name: "peak_hook_load",
            unit: "N",
            error: ErrorKind::Relative,
        },
        Quantity {
            name: "block_z",
            unit: "m",
            error: ErrorKind::Absolute,
        },
    ]
}

/// Hoists the default lift with `segments` per sling and solver `s` for `t_end` [s]: the largest
/// hook load over 0.05 s samples and the block's height at the end.
fn hoist(s: &Setting, segments: usize, t_end: f64) -> Result<Outcome, String> {
    let p = RopeBlockParams {
        integrator: s.integrator,
        rtol: s.settings.rtol,
        atol: s.settings.atol,
        h_max: s.settings.h_max,
        segments,
        ..RopeBlockParams::default()
    };
    let mut scene = RopeBlockScene::new(p)?;
    scene.set_hook(0, Vec3::new(0.0, 0.0, 0.3), 0.0)?;
    let mut peak: f64 = 0.0;
    let n = (t_end / 0.05).round() as usize;
    for _ in 0..n {
        scene.step(0.05)?;
        peak = peak.max(scene.output("hook0.load").ok_or("no hook0.load output")?);
    }
    let z = scene.output("block.z").ok_or("no block.z output")?;
    Ok(Outcome {
        values: vec![peak, z],
        stats: scene.sim.sim.stats(),
    })
}

/// Tolerance sweep of the default lift (100 segments per sling) over `t_end` [s].
pub fn lift(t_end: f64, quick: bool) -> Problem {
    let tolerances: &[f64] = if quick {
        &[1e-3, 1e-5]
    } else {
        &[1e-3, 1e-4, 1e-5, 1e-6]
    };
    let mut settings = Vec::new();
    // the scene's own largest step (0.0125 s): it keeps generalized-alpha's numerical damping
    // (rho_inf 0) of the block's 1.6 Hz bounce near the physical damping
    let h_max = RopeBlockParams::default().h_max;
    for kind in [GenAlpha, Bdf] {
        for &rtol in tolerances {
            settings.push(Setting::tolerance(kind, rtol, 1e-2, h_max));
        }
    }
    Problem {
        name: "rope_lift",
        title: format!(
            "RopeBlock default lift (200 t block, four 60 mm slings of 100 segments over the deck edges) hoisted at 0.3 m/s from static equilibrium, {t_end} s: largest hook load and the block's final height. DOPRI5 is left out: the axial wave of a steel rope limits explicit steps to ~1e-5 s."
        ),
        simulated: t_end,
        quantities: quantities(),
        reference: Setting::tolerance(Bdf, 1e-8, 1e-2, 0.002),
        reference_check: Setting::tolerance(GenAlpha, 1e-7, 1e-2, 0.002),
        settings,
        run: Box::new(move |s| hoist(s, 100, t_end)),
    }
}

/// Resolution sweep: segments per sling against a 400-segment reference (gen-alpha, rtol 1e-6).
pub fn nodes(t_end: f64, quick: bool) -> Problem {
    let counts: &[f64] = if quick {
        &[10.0, 40.0]
    } else {
        &[10.0, 20.0, 50.0, 100.0, 200.0]
    };
    let base = Setting::tolerance(GenAlpha, 1e-6, 1e-2, RopeBlockParams::default().h_max);
    let at = |n: f64| Setting {
        series: "gen-alpha rtol 1e-6".into(),
        sweep: Sweep::Resolution("segments"),
        x: n,
        ..base.clone()
    };
    Problem {
        name: "rope_nodes",
        title: format!(
            "RopeBlock default lift hoisted at 0.3 m/s, {t_end} s, with 10 to 200 segments per sling against 400: what rope resolution costs and buys."
        ),
        simulated: t_end,
        quantities: quantities(),
        reference: at(400.0),
        reference_check: at(300.0),
        settings: counts.iter().map(|&n| at(n)).collect(),
        run: Box::new(move |s| hoist(s, s.x as usize, t_end)),
    }
}
