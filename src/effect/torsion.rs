//! Rotational spring-dampers and input-driven torques about a joint axis.
//!
//! With the relative angle `theta` and its stacked gradient `g` (see [`super::angle`]), a torque
//! `tau` conjugate to `theta` gives `f = g tau`, so `K = -g dtau/dx - tau H` and `D = -g dtau/dv`
//! with `H` the angle's curvature.

use super::angle::{angle_curvature, relative_angle};
use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::math::{Matrix6, Vec3};
use crate::model::kinematics::kin_of;
use crate::model::{Frame, JointTorque, TorsionSpring};

/// Adds `g tau` to the rotational rows of both bodies.
fn add_torque(ctx: &EvalCtx, fi: &Frame, fj: &Frame, g: &[Vec3; 2], tau: f64, f: &mut [f64]) {
    for (frame, gk) in [(fi, &g[0]), (fj, &g[1])] {
        let k = kin_of(ctx.kins, frame.body);
        if k.is_free() && k.rotational {
            for r in 0..3 {
                f[k.col + 3 + r] += gk[r] * tau;
            }
        }
    }
}

/// Scatters a 6x6 matrix over `[dtheta_i; dtheta_j]` into the four body blocks.
fn scatter(
    ctx: &EvalCtx,
    fi: &Frame,
    fj: &Frame,
    k6: &Matrix6<f64>,
    d6: &Matrix6<f64>,
    sink: &mut dyn JacobianSink,
) {
    let kins = [kin_of(ctx.kins, fi.body), kin_of(ctx.kins, fj.body)];
    for (a, ka) in kins.iter().enumerate() {
        for (b, kb) in kins.iter().enumerate() {
            let mut kb6 = Matrix6::zeros();
            let mut db6 = Matrix6::zeros();
            kb6.fixed_view_mut::<3, 3>(3, 3)
                .copy_from(&k6.fixed_view::<3, 3>(3 * a, 3 * b));
            db6.fixed_view_mut::<3, 3>(3, 3)
                .copy_from(&d6.fixed_view::<3, 3>(3 * a, 3 * b));
            sink.add(ka, kb, &kb6, &db6);
        }
    }
}

fn stack(g: &[Vec3; 2]) -> nalgebra::Vector6<f64> {
    nalgebra::Vector6::new(g[0].x, g[0].y, g[0].z, g[1].x, g[1].y, g[1].z)
}

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
            add_torque(ctx, &e.frame_i, &e.frame_j, &ra.grad, tau, f);
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let tau = -e.stiffness * Self::deflection(e, ra.theta) - e.damping * ra.theta_dot;
            let g = stack(&ra.grad);
            let h = angle_curvature(ctx.kins, &e.frame_i, &e.frame_j);
            let ki = kin_of(ctx.kins, e.frame_i.body);
            let kj = kin_of(ctx.kins, e.frame_j.body);
            let omega = nalgebra::Vector6::new(
                ki.omega.x, ki.omega.y, ki.omega.z, kj.omega.x, kj.omega.y, kj.omega.z,
            );
            let k6 = e.stiffness * g * g.transpose()
                + e.damping * g * (h.transpose() * omega).transpose()
                - tau * h;
            let d6 = e.damping * g * g.transpose();
            scatter(ctx, &e.frame_i, &e.frame_j, &k6, &d6, sink);
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
            add_torque(ctx, &e.frame_i, &e.frame_j, &ra.grad, tau, f);
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let tau = e.torque.eval(ctx.t, ctx.inputs).0;
            let h = angle_curvature(ctx.kins, &e.frame_i, &e.frame_j);
            scatter(
                ctx,
                &e.frame_i,
                &e.frame_j,
                &(-tau * h),
                &Matrix6::zeros(),
                sink,
            );
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
