//! Unilateral angle stops: a stiff, damped, non-adhesive torque that keeps a hinge angle above a
//! minimum (the stowed stack of panels resting on its snubbers). With penetration
//! `p = theta_min - theta > 0`: `tau = max(k p - c theta_dot, 0)`; no torque otherwise.

use super::angle::relative_angle;
use super::angle_force::{add_angle_force, add_angle_jacobian};
use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::model::Frame;

/// One stop on the relative angle of two frames (`theta = angle_offset + raw`).
#[derive(Debug, Clone)]
pub struct AngleStop {
    pub name: String,
    pub frame_i: Frame,
    pub frame_j: Frame,
    pub angle_offset: f64,
    /// Smallest angle [rad] reached without torque.
    pub min_angle: f64,
    /// Stiffness [N m/rad] and damping [N m s/rad] of the stop.
    pub stiffness: f64,
    pub damping: f64,
}

impl AngleStop {
    /// Torque and its partial derivatives w.r.t. theta and theta_dot.
    fn torque(&self, theta: f64, theta_dot: f64) -> (f64, f64, f64) {
        let p = self.min_angle - theta;
        if p <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let tau = self.stiffness * p - self.damping * theta_dot;
        if tau <= 0.0 {
            (0.0, 0.0, 0.0)
        } else {
            (tau, -self.stiffness, -self.damping)
        }
    }
}

/// All angle stops of a scene.
#[derive(Debug, Clone)]
pub struct AngleStops {
    pub elements: Vec<AngleStop>,
}

impl ForceEffect for AngleStops {
    fn name(&self) -> &str {
        "angle-stop"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let (tau, _, _) = e.torque(e.angle_offset + ra.theta, ra.theta_dot);
            if tau != 0.0 {
                add_angle_force(ctx, &e.frame_i, &e.frame_j, &ra, tau, f);
            }
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let (tau, dt, dtd) = e.torque(e.angle_offset + ra.theta, ra.theta_dot);
            add_angle_jacobian(ctx, &e.frame_i, &e.frame_j, &ra, tau, dt, dtd, sink);
        }
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
                let p = (e.min_angle - e.angle_offset - ra.theta).max(0.0);
                0.5 * e.stiffness * p * p
            })
            .sum()
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
                let theta = e.angle_offset + ra.theta;
                let (tau, _, _) = e.torque(theta, ra.theta_dot);
                if tau > 0.0 {
                    // the damping part of the stop torque times the rate
                    let elastic = e.stiffness * (e.min_angle - theta);
                    (elastic - tau) * ra.theta_dot
                } else {
                    0.0
                }
            })
            .sum()
    }
}
