//! The latch wall forces at every accepted integrator step, for plots that must not miss the
//! lock-up impacts: a contact pulse lasts milliseconds, far less than a 0.01 s output step, so a
//! force plotted from the output samples misses its peak. The trace holds, per hinge, the wall
//! force [N] (larger of the two walls, as the latch's peak tracker takes it) at each accepted
//! step time [s], and each peak the tracker located between steps (parabola vertex, see
//! [`crate::effect::latch::parabola_vertex`]); its largest value is the reported peak force.

use super::PanelLock;
use crate::dae::System;
use crate::effect::latch::{MEMORY_PER_LATCH, parabola_vertex};
use crate::integrator::{SolverError, StepAction, StepHook};
use crate::state::State;

/// Wall forces of every hinge at every accepted step, and the located peaks.
#[derive(Debug, Clone, Default)]
pub struct ForceTrace {
    /// Accepted step times [s].
    pub t: Vec<f64>,
    /// `forces[k][j]`: wall force of hinge `k` at `t[j]` [N].
    pub forces: Vec<Vec<f64>>,
    /// `peaks[k]`: located peaks `(t [s], force [N])` of hinge `k` between steps.
    pub peaks: Vec<Vec<(f64, f64)>>,
}

impl StepHook for ForceTrace {
    fn after_step(&mut self, sys: &mut System, st: &mut State) -> Result<StepAction, SolverError> {
        self.record(sys, st);
        Ok(StepAction::Continue)
    }
}

impl ForceTrace {
    /// Appends the forces of the latch memory at `st.t` (after its update), and any peak located
    /// between the last two recorded steps and this one.
    fn record(&mut self, sys: &System, st: &State) {
        let Some(range) = sys.memory_range("latch") else {
            return;
        };
        let mem = &st.memory[range];
        let n = mem.len() / MEMORY_PER_LATCH;
        self.forces.resize(n, Vec::new());
        self.peaks.resize(n, Vec::new());
        for (k, (f, peaks)) in self.forces.iter_mut().zip(&mut self.peaks).enumerate() {
            // slots 11 and 13: the wall force at this step and its time (the memory update ran)
            let now = mem[k * MEMORY_PER_LATCH + 11];
            let j = self.t.len();
            if j >= 2
                && let Some(p) = parabola_vertex(
                    (self.t[j - 2], f[j - 2]),
                    (self.t[j - 1], f[j - 1]),
                    (st.t, now),
                )
                && p.1 > f[j - 1]
            {
                peaks.push(p);
            }
            f.push(now);
        }
        self.t.push(st.t);
    }

    /// Advances `scene` to `t` [s] recording every accepted step (and, on the first call, the
    /// start: no force yet, as the latch memory holds it).
    pub fn advance(&mut self, scene: &mut PanelLock, t: f64) -> Result<(), SolverError> {
        if self.t.is_empty() {
            self.record(&scene.sim.system, &scene.sim.state);
        }
        scene.sim.advance_with(t, self)
    }

    /// The force of hinge `k` over time with its located peaks merged in, in time order.
    pub fn hinge(&self, k: usize) -> Vec<(f64, f64)> {
        let mut p: Vec<(f64, f64)> = self
            .t
            .iter()
            .copied()
            .zip(self.forces[k].iter().copied())
            .collect();
        p.extend(&self.peaks[k]);
        p.sort_by(|a, b| a.0.total_cmp(&b.0));
        p
    }

    /// The largest force of any hinge over time with all located peaks merged in, in time
    /// order.
    pub fn largest(&self) -> Vec<(f64, f64)> {
        let mut p: Vec<(f64, f64)> = (0..self.t.len())
            .map(|j| {
                (
                    self.t[j],
                    self.forces.iter().map(|f| f[j]).fold(0.0, f64::max),
                )
            })
            .collect();
        p.extend(self.peaks.iter().flatten());
        p.sort_by(|a, b| a.0.total_cmp(&b.0));
        p
    }

    /// The largest located or sampled force of any hinge: (time [s], force [N]).
    pub fn peak(&self) -> (f64, f64) {
        highest(self.largest())
    }

    /// The largest located or sampled force of hinge `k`: (time [s], force [N]).
    pub fn hinge_peak(&self, k: usize) -> (f64, f64) {
        highest(self.hinge(k))
    }
}

/// The point of `series` with the largest force (NaN time for an all-zero series).
fn highest(series: Vec<(f64, f64)>) -> (f64, f64) {
    series
        .into_iter()
        .fold((f64::NAN, 0.0), |a, b| if b.1 > a.1 { b } else { a })
}
