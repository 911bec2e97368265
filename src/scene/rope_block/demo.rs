//! Native runs of the two demonstration scenes, written as CSV (one row per output interval, one
//! column per output of [`super::RopeBlockScene::output_names`]).
//!
//! - [`Demo::Lift`]: the default lift (200 t block, four 22 m slings over the deck edges), settled
//!   hanging at rest, then hoisted at 0.2 m/s for 8 s after a 1 s hold, then held for 3 s.
//! - [`Demo::Turnover`]: the block held by two cranes, crane B (hook 1) lowering at 0.4 m/s for
//!   [`TURNOVER_LOWERING`] seconds while crane A holds, then holding: the block rolls about its
//!   length until crane A carries nearly all of it. (Lowering further unloads crane B's slings
//!   completely; a slack, unloaded steel sling flapping between slack and taut needs very small
//!   steps, so the demo stops lowering before that.)

use super::params::RopeBlockParams;
use super::scene::RopeBlockScene;
use crate::math::Vec3;
use std::io::Write;

/// Which demonstration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Demo {
    Lift,
    Turnover,
}

/// What a demo run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct DemoSummary {
    /// Rows written.
    pub rows: usize,
    /// Largest hook load [N] and largest sling tension [N] seen at the output instants.
    pub peak_hook_load: f64,
    pub peak_sling_tension: f64,
    /// Most contact nodes at once.
    pub max_contacts: usize,
    /// Simulated time [s] and wall-clock time [s].
    pub simulated: f64,
    pub wall: f64,
}

impl DemoSummary {
    /// One line for a person: rows written to `path`, the peaks [kN], contact nodes and the
    /// real-time factor.
    pub fn describe(&self, path: &std::path::Path) -> String {
        format!(
            "{} rows to {}: peak hook load {:.1} kN, peak sling tension {:.1} kN, up to {} contact nodes; {:.1} s simulated in {:.2} s ({:.0}x real time)",
            self.rows,
            path.display(),
            self.peak_hook_load / 1e3,
            self.peak_sling_tension / 1e3,
            self.max_contacts,
            self.simulated,
            self.wall,
            self.simulated / self.wall
        )
    }
}

/// How long crane B lowers in the turnover demo [s].
pub const TURNOVER_LOWERING: f64 = 32.0;

/// Vertical hook speed of the lift demo at time `t` [s]: 0.2 m/s from 1 s to 9 s, else 0 [m/s].
pub fn lift_hook_speed(t: f64) -> f64 {
    if (1.0..9.0).contains(&t) { 0.2 } else { 0.0 }
}

/// The hook inputs of a demo at time `t` [s]: (hook, velocity [m/s]) pairs.
fn schedule(demo: Demo, t: f64) -> Vec<(usize, Vec3)> {
    match demo {
        Demo::Lift => vec![(0, Vec3::new(0.0, 0.0, lift_hook_speed(t)))],
        Demo::Turnover => {
            let v = if t < TURNOVER_LOWERING { -0.4 } else { 0.0 };
            vec![(1, Vec3::new(0.0, 0.0, v))]
        }
    }
}

/// Peaks of a lift driven by [`hoist`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftPeaks {
    /// Largest hook-0 load [N] and largest sling tension [N] at the communication points.
    pub hook_load: f64,
    pub sling_tension: f64,
    /// False when `after_step` stopped the run early.
    pub finished: bool,
}

/// Drives `scene` through the lift schedule ([`lift_hook_speed`] on hook 0) for `duration` [s]
/// in communication steps of `interval` [s], tracking the peaks at every communication point;
/// `after_step` runs after each step (traces, wall-time budgets) and returns whether to go on.
pub fn hoist(
    scene: &mut RopeBlockScene,
    duration: f64,
    interval: f64,
    mut after_step: impl FnMut(&mut RopeBlockScene) -> bool,
) -> Result<LiftPeaks, String> {
    let names = scene.output_names().to_vec();
    let load = names
        .iter()
        .position(|n| n == "hook0.load")
        .ok_or("no hook0.load output")?;
    let slings: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].starts_with("sling"))
        .collect();
    let mut peaks = LiftPeaks {
        hook_load: 0.0,
        sling_tension: 0.0,
        finished: true,
    };
    let mut v_last = f64::NAN;
    let n = (duration / interval).round() as usize;
    for k in 0..=n {
        let row = scene.outputs();
        peaks.hook_load = peaks.hook_load.max(row[load]);
        for &i in &slings {
            peaks.sling_tension = peaks.sling_tension.max(row[i]);
        }
        if k == n {
            break;
        }
        let v = lift_hook_speed(scene.sim.time());
        if v != v_last {
            scene.set_hook(0, Vec3::new(0.0, 0.0, v), 0.0)?;
            v_last = v;
        }
        scene.step(interval)?;
        if !after_step(scene) {
            peaks.finished = false;
            break;
        }
    }
    Ok(peaks)
}

/// Runs `demo` for `duration` [s] with outputs every `interval` [s], writing CSV to `out`.
pub fn run(
    demo: Demo,
    params: Option<RopeBlockParams>,
    duration: f64,
    interval: f64,
    out: &mut dyn Write,
) -> Result<DemoSummary, String> {
    if !(duration.is_finite() && duration > 0.0 && interval.is_finite() && interval > 0.0) {
        return Err(format!(
            "duration and interval must be finite and > 0 s, got {duration} and {interval}"
        ));
    }
    let params = params.unwrap_or_else(|| match demo {
        Demo::Lift => RopeBlockParams::default(),
        Demo::Turnover => RopeBlockParams::turnover(),
    });
    let start = std::time::Instant::now();
    let mut scene = RopeBlockScene::new(params)?;
    let names = scene.output_names().to_vec();
    let io = |e: std::io::Error| format!("cannot write the CSV: {e}");
    writeln!(out, "{}", names.join(",")).map_err(io)?;
    let hook_cols: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].ends_with(".load"))
        .collect();
    let sling_cols: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].starts_with("sling"))
        .collect();
    let count_col = names.iter().position(|n| n == "contact.count");
    let mut summary = DemoSummary {
        rows: 0,
        peak_hook_load: 0.0,
        peak_sling_tension: 0.0,
        max_contacts: 0,
        simulated: 0.0,
        wall: 0.0,
    };
    let mut last_inputs: Vec<(usize, Vec3)> = Vec::new();
    let n = (duration / interval).round().max(1.0) as usize;
    for k in 0..=n {
        let row = scene.outputs();
        for &i in &hook_cols {
            summary.peak_hook_load = summary.peak_hook_load.max(row[i]);
        }
        for &i in &sling_cols {
            summary.peak_sling_tension = summary.peak_sling_tension.max(row[i]);
        }
        if let Some(i) = count_col {
            summary.max_contacts = summary.max_contacts.max(row[i] as usize);
        }
        let line: Vec<String> = row.iter().map(|x| format!("{x:.9e}")).collect();
        writeln!(out, "{}", line.join(",")).map_err(io)?;
        summary.rows += 1;
        if k == n {
            break;
        }
        let inputs = schedule(demo, scene.sim.time());
        if inputs != last_inputs {
            for &(h, v) in &inputs {
                scene.set_hook(h, v, 0.0)?;
            }
            last_inputs = inputs;
        }
        scene.step(interval)?;
    }
    summary.simulated = scene.sim.time();
    summary.wall = start.elapsed().as_secs_f64();
    Ok(summary)
}
