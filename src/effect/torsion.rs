//! Rotational spring-dampers and input-driven torques about a joint axis.
//!
//! Both are scalar torques conjugate to a relative angle (see [`super::angle_force`]).

use super::angle::relative_angle;
use super::angle_force::{add_angle_force, add_angle_jacobian};
use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::model::{JointTorque, TorsionSpring};

/// All torsion springs of a model.
#[derive(Debug, Clone)]
pub struct TorsionSprings {
    pub elements: Vec<TorsionSpring>,
}

impl TorsionSprings {
    /// Measured angle [rad] of element `e` (raw angle plus offset).
    fn angle(e: &TorsionSpring, raw: f64) -> f64 {
        e.angle_offset + raw
    }

    fn deflection(e: &TorsionSpring, raw: f64) -> f64 {
        Self::angle(e, raw) - e.free_angle
    }
}

impl ForceEffect for TorsionSprings {
    fn name(&self) -> &str {
        "torsion-spring"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let tau = -e.stiffness * Self::deflection(e, ra.theta) - e.damping * ra.theta_dot;
            add_angle_force(ctx, &e.frame_i, &e.frame_j, &ra, tau, f);
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let tau = -e.stiffness * Self::deflection(e, ra.theta) - e.damping * ra.theta_dot;
            add_angle_jacobian(
                ctx,
                &e.frame_i,
                &e.frame_j,
                &ra,
                tau,
                -e.stiffness,
                -e.damping,
                sink,
            );
        }
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
                0.5 * e.stiffness * Self::deflection(e, ra.theta).powi(2)
            })
            .sum()
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
                e.damping * ra.theta_dot * ra.theta_dot
            })
            .sum()
    }
}

/// All joint torques (motors) of a model.
#[derive(Debug, Clone)]
pub struct JointTorques {
    pub elements: Vec<JointTorque>,
}

impl ForceEffect for JointTorques {
    fn name(&self) -> &str {
        "joint-torque"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let tau = e.torque.eval(ctx.t, ctx.inputs).0;
            add_angle_force(ctx, &e.frame_i, &e.frame_j, &ra, tau, f);
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let tau = e.torque.eval(ctx.t, ctx.inputs).0;
            add_angle_jacobian(ctx, &e.frame_i, &e.frame_j, &ra, tau, 0.0, 0.0, sink);
        }
    }

    fn input_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
                e.torque.eval(ctx.t, ctx.inputs).0 * ra.theta_dot
            })
            .sum()
    }
}
