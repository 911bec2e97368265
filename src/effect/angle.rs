//! Relative rotation angle of two frames about the z axis of the first, with its gradient and
//! curvature w.r.t. the bodies' rotation increments.
//!
//! `theta = atan2(y_i . x_j, x_i . x_j)` (world-frame axes), so `theta` is the angle of `x_j`
//! from `x_i` about `z_i` when the z axes are aligned (a revolute joint keeps them so).

use crate::math::{Mat3, Matrix6, Vec3, exp_so3};
use crate::model::Frame;
use crate::model::kinematics::{BodyKin, kin_of};

/// Angle [rad] in (-pi, pi] and its gradient w.r.t. the body-frame rotation increments of body i
/// and body j (zero for a body without rotation).
pub fn angle_gradient(rot_i: &Mat3, ax_i: &Mat3, rot_j: &Mat3, ax_j: &Mat3) -> (f64, Vec3, Vec3) {
    let xi = rot_i * ax_i.column(0);
    let yi = rot_i * ax_i.column(1);
    let xj = rot_j * ax_j.column(0);
    let c = xi.dot(&xj);
    let s = yi.dot(&xj);
    let rho2 = (c * c + s * s).max(1e-300);
    // d s = dPhi_i . (y_i x x_j) + dPhi_j . (x_j x y_i); d c likewise (world-frame dPhi).
    let gi_w = (c * yi.cross(&xj) - s * xi.cross(&xj)) / rho2;
    let gj_w = (c * xj.cross(&yi) - s * xj.cross(&xi)) / rho2;
    (
        s.atan2(c),
        rot_i.transpose() * gi_w,
        rot_j.transpose() * gj_w,
    )
}

/// Angle, rate and stacked gradient `[g_i; g_j]` (rotation increments of i then j) of two frames.
#[derive(Debug, Clone, Copy)]
pub struct RelativeAngle {
    /// Raw angle [rad] in (-pi, pi].
    pub theta: f64,
    /// Angle rate [rad/s].
    pub theta_dot: f64,
    /// Gradient w.r.t. `[dtheta_i; dtheta_j]` (body-frame rotation vectors).
    pub grad: [Vec3; 2],
}

/// Evaluates the relative angle of `fj` about `fi`'s z axis.
pub fn relative_angle(kins: &[BodyKin], fi: &Frame, fj: &Frame) -> RelativeAngle {
    let ki = kin_of(kins, fi.body);
    let kj = kin_of(kins, fj.body);
    let (theta, gi, gj) = angle_gradient(&ki.rot, &fi.axes, &kj.rot, &fj.axes);
    let theta_dot = gi.dot(&ki.omega) + gj.dot(&kj.omega);
    RelativeAngle {
        theta,
        theta_dot,
        grad: [gi, gj],
    }
}

/// Derivative of the gradient, `H[r][c] = d g_r / d x_c` over `[dtheta_i; dtheta_j]`, by central
/// differences of the analytic gradient (step 1e-6 rad: relative accuracy about 1e-10). Increments
/// on the rotation group do not commute, so `H` is not symmetric; its symmetric part is the
/// second derivative along a motion (`theta_ddot = g . omega_dot + omega^T H omega`).
pub fn angle_curvature(kins: &[BodyKin], fi: &Frame, fj: &Frame) -> Matrix6<f64> {
    let ki = kin_of(kins, fi.body);
    let kj = kin_of(kins, fj.body);
    let eps = 1e-6;
    let mut h = Matrix6::zeros();
    for col in 0..6 {
        let mut e = Vec3::zeros();
        e[col % 3] = eps;
        let bump = exp_so3(&e).to_rotation_matrix().into_inner();
        let (ri_p, ri_m, rj_p, rj_m) = if col < 3 {
            let bm = exp_so3(&(-e)).to_rotation_matrix().into_inner();
            (ki.rot * bump, ki.rot * bm, kj.rot, kj.rot)
        } else {
            let bm = exp_so3(&(-e)).to_rotation_matrix().into_inner();
            (ki.rot, ki.rot, kj.rot * bump, kj.rot * bm)
        };
        let (_, gip, gjp) = angle_gradient(&ri_p, &fi.axes, &rj_p, &fj.axes);
        let (_, gim, gjm) = angle_gradient(&ri_m, &fi.axes, &rj_m, &fj.axes);
        for r in 0..3 {
            h[(r, col)] = (gip[r] - gim[r]) / (2.0 * eps);
            h[(r + 3, col)] = (gjp[r] - gjm[r]) / (2.0 * eps);
        }
    }
    h
}

/// Wraps an angle to (-pi, pi].
pub fn wrap_angle(a: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut x = a % two_pi;
    if x > std::f64::consts::PI {
        x -= two_pi;
    } else if x <= -std::f64::consts::PI {
        x += two_pi;
    }
    x
}
