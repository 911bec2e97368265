//! Applied forces and torques with prescribed or input-driven magnitudes.

use super::point_force::add_point_force;
use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::math::{Matrix6, skew};
use crate::model::AppliedLoad;
use crate::model::kinematics::kin_of;

/// All applied loads of a model.
#[derive(Debug, Clone)]
pub struct AppliedLoads {
    pub elements: Vec<AppliedLoad>,
}

impl ForceEffect for AppliedLoads {
    fn name(&self) -> &str {
        "applied-load"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for e in &self.elements {
            let k = kin_of(ctx.kins, e.at.body);
            if !k.is_free() {
                continue;
            }
            let force = e.force_direction * e.force.eval(ctx.t, ctx.inputs).0;
            add_point_force(k, &e.at.origin, &force, f);
            if k.rotational {
                let tau =
                    k.rot.transpose() * (e.torque_direction * e.torque.eval(ctx.t, ctx.inputs).0);
                for i in 0..3 {
                    f[k.col + 3 + i] += tau[i];
                }
            }
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let k = kin_of(ctx.kins, e.at.body);
            let force = e.force_direction * e.force.eval(ctx.t, ctx.inputs).0;
            let torque = e.torque_direction * e.torque.eval(ctx.t, ctx.inputs).0;
            let mut k6 = Matrix6::zeros();
            if k.rotational {
                // f_rot = s x R^T F + R^T T; d(R^T w)/dtheta = (R^T w)~
                let block = skew(&e.at.origin) * skew(&(k.rot.transpose() * force))
                    + skew(&(k.rot.transpose() * torque));
                k6.fixed_view_mut::<3, 3>(3, 3).copy_from(&(-block));
            }
            sink.add(k, k, &k6, &Matrix6::zeros());
        }
    }

    fn input_power(&self, ctx: &EvalCtx) -> f64 {
        let mut p = 0.0;
        for e in &self.elements {
            let k = kin_of(ctx.kins, e.at.body);
            let force = e.force_direction * e.force.eval(ctx.t, ctx.inputs).0;
            let torque = e.torque_direction * e.torque.eval(ctx.t, ctx.inputs).0;
            p += force.dot(&k.point_velocity(&e.at.origin)) + torque.dot(&(k.rot * k.omega));
        }
        p
    }
}
