//! Closed cable loops (CCL) synchronizing two hinges: an elastic, damped coupling of their angles,
//! `s = c_a theta_a + c_b theta_b - s0`, `T = k s + c s_dot`, torques `tau_a = -c_a T`,
//! `tau_b = -c_b T`, potential `k s^2 / 2`.

use super::angle::relative_angle;
use super::angle_force::{add_angle_force, stacked_gradient, stacked_omega};
use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::effect::angle::angle_curvature;
use crate::math::{Matrix6, Vector6};
use crate::model::Frame;
use crate::model::kinematics::kin_of;

/// One cable loop between hinge a (frames `a_i`, `a_j`) and hinge b.
#[derive(Debug, Clone)]
pub struct CableLoop {
    pub name: String,
    pub a: [Frame; 2],
    pub b: [Frame; 2],
    /// Angle coefficients (e.g. pulley ratios) and offset [rad].
    pub c_a: f64,
    pub c_b: f64,
    pub s0: f64,
    /// Cable stiffness [N m/rad] and damping [N m s/rad] in terms of `s`.
    pub stiffness: f64,
    pub damping: f64,
}

/// All cable loops of a scene.
#[derive(Debug, Clone)]
pub struct CableLoops {
    pub elements: Vec<CableLoop>,
}

impl CableLoop {
    fn eval(
        &self,
        ctx: &EvalCtx,
    ) -> (
        super::angle::RelativeAngle,
        super::angle::RelativeAngle,
        f64,
        f64,
    ) {
        let ra = relative_angle(ctx.kins, &self.a[0], &self.a[1]);
        let rb = relative_angle(ctx.kins, &self.b[0], &self.b[1]);
        let s = self.c_a * ra.theta + self.c_b * rb.theta - self.s0;
        let s_dot = self.c_a * ra.theta_dot + self.c_b * rb.theta_dot;
        (ra, rb, s, s_dot)
    }
}

impl ForceEffect for CableLoops {
    fn name(&self) -> &str {
        "cable-loop"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for e in &self.elements {
            let (ra, rb, s, s_dot) = e.eval(ctx);
            let t = e.stiffness * s + e.damping * s_dot;
            add_angle_force(ctx, &e.a[0], &e.a[1], &ra, -e.c_a * t, f);
            add_angle_force(ctx, &e.b[0], &e.b[1], &rb, -e.c_b * t, f);
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let (ra, rb, s, s_dot) = e.eval(ctx);
            let t = e.stiffness * s + e.damping * s_dot;
            let frames = [e.a[0], e.a[1], e.b[0], e.b[1]];
            // gradients of s and s_dot over the 12 rotation increments [a_i, a_j, b_i, b_j]
            let (ga, gb) = (stacked_gradient(&ra), stacked_gradient(&rb));
            let (ha, hb) = (
                angle_curvature(ctx.kins, &e.a[0], &e.a[1]),
                angle_curvature(ctx.kins, &e.b[0], &e.b[1]),
            );
            let (wa, wb) = (
                stacked_omega(ctx, &e.a[0], &e.a[1]),
                stacked_omega(ctx, &e.b[0], &e.b[1]),
            );
            let mut g = [0.0; 12];
            let mut gsd = [0.0; 12];
            let (hwa, hwb): (Vector6<f64>, Vector6<f64>) =
                (ha.transpose() * wa, hb.transpose() * wb);
            for k in 0..6 {
                g[k] = e.c_a * ga[k];
                g[6 + k] = e.c_b * gb[k];
                gsd[k] = e.c_a * hwa[k];
                gsd[6 + k] = e.c_b * hwb[k];
            }
            // f_r = g_r * (-T) over the 12 slots; K = -df/dx, D = -df/dv
            for (a, fa) in frames.iter().enumerate() {
                for (b, fb) in frames.iter().enumerate() {
                    let mut k6 = Matrix6::zeros();
                    let mut d6 = Matrix6::zeros();
                    for r in 0..3 {
                        for c in 0..3 {
                            let (ir, ic) = (3 * a + r, 3 * b + c);
                            k6[(3 + r, 3 + c)] =
                                g[ir] * (e.stiffness * g[ic] + e.damping * gsd[ic]);
                            d6[(3 + r, 3 + c)] = e.damping * g[ir] * g[ic];
                        }
                    }
                    // curvature of each angle times its torque
                    let (same_a, same_b) = (a < 2 && b < 2, a >= 2 && b >= 2);
                    if same_a {
                        let blk = ha.fixed_view::<3, 3>(3 * a, 3 * b) * (e.c_a * t);
                        let mut v = k6.fixed_view_mut::<3, 3>(3, 3);
                        v += blk;
                    }
                    if same_b {
                        let blk = hb.fixed_view::<3, 3>(3 * (a - 2), 3 * (b - 2)) * (e.c_b * t);
                        let mut v = k6.fixed_view_mut::<3, 3>(3, 3);
                        v += blk;
                    }
                    sink.add(
                        kin_of(ctx.kins, fa.body),
                        kin_of(ctx.kins, fb.body),
                        &k6,
                        &d6,
                    );
                }
            }
        }
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| 0.5 * e.stiffness * e.eval(ctx).2.powi(2))
            .sum()
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| e.damping * e.eval(ctx).3.powi(2))
            .sum()
    }
}
