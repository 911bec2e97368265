//! What the flexible panels report: the tip deflection and the first modal amplitudes.
//!
//! A flexible panel's modal coordinates `a` deform it relative to its floating frame, which is
//! clamped at the inboard hinge node (Craig-Bampton) or the mean axes (free-interface): the
//! rigid shape. With the translational shapes `Phi_k` of node `k` (plate frame: x length,
//! y width, z normal):
//! - **tip deflection** [m]: the normal displacement of the outboard edge's mid-width node,
//!   `-(Phi_tip a)_z`, signed along the rigid panel's normal (its +y axis, the plate's -z: the
//!   normal of the `tip_normal_velocity` output);
//! - **mode j amplitude** [m]: the coordinate of the j-th fixed-interface (or free-free) mode,
//!   after the interface coordinates of an inner Craig-Bampton panel, scaled by the largest
//!   normal displacement that mode gives over the panel's nodes (so 0.01 means the mode bends
//!   the panel by 1 cm at its worst node), signed as the coordinate.

use crate::flex::ModalBodyData;
use crate::model::{BodyId, Model};
use std::sync::Arc;

/// Number of modal amplitudes reported per panel.
pub const MODE_OUTPUTS: usize = 3;

/// A flexible panel's body and what its outputs need.
#[derive(Debug, Clone)]
pub struct FlexPanelRef {
    pub body: BodyId,
    pub data: Arc<ModalBodyData>,
    /// Outboard edge mid-width node.
    pub tip_node: usize,
    /// Index of the first mode among the modal coordinates (3 on an inner Craig-Bampton
    /// panel: the outboard node's interface coordinates come first).
    pub first_mode: usize,
    /// Largest normal displacement [m] of each reported mode per unit coordinate over the
    /// panel's nodes (0 for a mode the panel does not have).
    pub mode_scales: [f64; MODE_OUTPUTS],
}

/// Tip deflection [m] and modal amplitudes [m] of one panel (zeros when rigid).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PanelFlexOutput {
    pub tip_deflection: f64,
    pub modes: [f64; MODE_OUTPUTS],
}

impl FlexPanelRef {
    /// The outputs' description of panel `body`: `n_modes` fixed-interface (or free-free)
    /// modes are the last of its modal coordinates.
    pub fn new(body: BodyId, data: Arc<ModalBodyData>, tip_node: usize, n_modes: usize) -> Self {
        let n = data.n_modes();
        let first_mode = n.saturating_sub(n_modes);
        let mut mode_scales = [0.0; MODE_OUTPUTS];
        for (j, scale) in mode_scales.iter_mut().enumerate() {
            let col = first_mode + j;
            if col < n {
                *scale = data
                    .translational_shapes()
                    .iter()
                    .map(|phi| phi[(2, col)].abs())
                    .fold(0.0, f64::max);
            }
        }
        FlexPanelRef {
            body,
            data,
            tip_node,
            first_mode,
            mode_scales,
        }
    }

    /// The panel's outputs at positions `q` of `model`.
    pub fn evaluate(&self, model: &Model, q: &[f64]) -> PanelFlexOutput {
        let Some(b) = self.body.index().map(|i| &model.bodies[i]) else {
            return PanelFlexOutput::default();
        };
        let n = self.data.n_modes();
        let a = &q[b.q_offset + 7..b.q_offset + 7 + n];
        let phi = &self.data.translational_shapes()[self.tip_node];
        let w: f64 = (0..n).map(|c| phi[(2, c)] * a[c]).sum();
        let mut modes = [0.0; MODE_OUTPUTS];
        for (j, m) in modes.iter_mut().enumerate() {
            if let Some(x) = a.get(self.first_mode + j) {
                *m = x * self.mode_scales[j];
            }
        }
        PanelFlexOutput {
            // 0 - w, not -w: an undeformed panel reports +0 (no sign of zero that depends on
            // the mesh, which importers comparing bits would take for a dependency)
            tip_deflection: 0.0 - w,
            modes,
        }
    }
}
