//! Uniform gravity acting at every body's centre of mass.

use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::math::Vec3;

/// Gravity `m g` on every body (present only when the scene enables it).
#[derive(Debug, Clone)]
pub struct Gravity {
    /// Gravity acceleration [m/s^2], world frame.
    pub g: Vec3,
    /// Mass of each body [kg] (index = body index).
    pub masses: Vec<f64>,
}

impl ForceEffect for Gravity {
    fn name(&self) -> &str {
        "gravity"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for (k, m) in ctx.kins.iter().zip(&self.masses) {
            for i in 0..3 {
                f[k.col + i] += m * self.g[i];
            }
        }
    }

    fn add_jacobian(&self, _ctx: &EvalCtx, _sink: &mut dyn JacobianSink) {}

    /// Gravity is conservative: it neither dissipates nor feeds power.
    fn has_power(&self) -> bool {
        false
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        ctx.kins
            .iter()
            .zip(&self.masses)
            .map(|(k, m)| -m * self.g.dot(&k.r))
            .sum()
    }
}
