//! A scalar generalized force `tau(theta, theta_dot)` [N m] conjugate to a relative angle: the
//! common core of torsion springs, hinge motors, latches and cable loops.
//!
//! With the angle's gradient `g` and gradient derivative `H` (see [`super::angle`]):
//! `f = g tau`, `K = -g (tau_theta g^T + tau_thetadot (H^T omega)^T) - tau H`,
//! `D = -tau_thetadot g g^T`, over the rotation increments `[dtheta_i; dtheta_j]`.

use super::angle::{RelativeAngle, angle_curvature};
use super::{EvalCtx, JacobianSink};
use crate::math::{Matrix6, Vector6};
use crate::model::Frame;
use crate::model::kinematics::kin_of;

/// Stacked gradient `[g_i; g_j]`.
pub fn stacked_gradient(ra: &RelativeAngle) -> Vector6<f64> {
    let [gi, gj] = ra.grad;
    Vector6::new(gi.x, gi.y, gi.z, gj.x, gj.y, gj.z)
}

/// Stacked body angular velocities `[omega_i; omega_j]` [rad/s] of the two frames' bodies.
pub fn stacked_omega(ctx: &EvalCtx, fi: &Frame, fj: &Frame) -> Vector6<f64> {
    let (wi, wj) = (
        kin_of(ctx.kins, fi.body).omega,
        kin_of(ctx.kins, fj.body).omega,
    );
    Vector6::new(wi.x, wi.y, wi.z, wj.x, wj.y, wj.z)
}

/// Adds `g tau` to the rotational rows of both bodies.
pub fn add_angle_force(
    ctx: &EvalCtx,
    fi: &Frame,
    fj: &Frame,
    ra: &RelativeAngle,
    tau: f64,
    f: &mut [f64],
) {
    for (frame, gk) in [(fi, &ra.grad[0]), (fj, &ra.grad[1])] {
        let k = kin_of(ctx.kins, frame.body);
        if k.is_free() && k.rotational {
            for r in 0..3 {
                f[k.col + 3 + r] += gk[r] * tau;
            }
        }
    }
}

/// Scatters 6x6 matrices over `[dtheta_i; dtheta_j]` into the four body blocks (fixed sequence).
pub fn scatter_rotational(
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

/// Adds the K and D blocks of `tau` with partial derivatives `tau_theta` [N m/rad] and
/// `tau_thetadot` [N m s/rad].
#[allow(clippy::too_many_arguments)]
pub fn add_angle_jacobian(
    ctx: &EvalCtx,
    fi: &Frame,
    fj: &Frame,
    ra: &RelativeAngle,
    tau: f64,
    tau_theta: f64,
    tau_thetadot: f64,
    sink: &mut dyn JacobianSink,
) {
    let g = stacked_gradient(ra);
    let h = angle_curvature(ctx.kins, fi, fj);
    let hw = h.transpose() * stacked_omega(ctx, fi, fj);
    let k6 = -g * (tau_theta * g + tau_thetadot * hw).transpose() - tau * h;
    let d6 = -tau_thetadot * g * g.transpose();
    scatter_rotational(ctx, fi, fj, &k6, &d6, sink);
}
