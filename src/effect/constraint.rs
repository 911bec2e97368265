//! Holonomic joint constraints built from three primitives, each with analytic Jacobian rows and
//! acceleration right-hand sides.
//!
//! Conventions: `Phi(q, t) = 0`; velocity level `G v + Phi_t = 0`; acceleration level
//! `G v_dot = gamma` with `gamma = -(G_dot v) - Phi_tt`. The equations of motion read
//! `M v_dot + G^T lambda = f`, so `-G^T lambda` is the reaction. A row's Jacobian has one 6-block
//! per body (translation [world], rotation [body frame]); particles use the translation part only.
//!
//! Primitives (`u = R a` world-frame image of a body-frame unit vector, `p = r + R s` a point):
//! - *point*: `p_i - p_j` (3 rows);
//! - *dot1*: `u_i . u_j` (axes perpendicular);
//! - *dot2*: `u_i . (p_j - p_i)` (point j in the plane through p_i normal to u_i);
//! - *angle*: rotation of `x_j` about `z_i` (see [`super::angle`]).

use super::angle::{angle_curvature, relative_angle, wrap_angle};
use crate::math::Vec3;
use crate::model::kinematics::{BodyKin, kin_of};
use crate::model::{Frame, Joint, JointKind};

/// One evaluated constraint row.
#[derive(Debug, Clone, Copy, Default)]
pub struct RowEval {
    /// Residual `Phi`.
    pub phi: f64,
    /// Partial time derivative `Phi_t`.
    pub phi_t: f64,
    /// Acceleration right-hand side `gamma`.
    pub gamma: f64,
    /// Jacobian blocks of body i and body j (translation, rotation).
    pub g: [[f64; 6]; 2],
}

fn row(phi: f64, gamma: f64, gi_t: Vec3, gi_r: Vec3, gj_t: Vec3, gj_r: Vec3) -> RowEval {
    let mut g = [[0.0; 6]; 2];
    for k in 0..3 {
        g[0][k] = gi_t[k];
        g[0][k + 3] = gi_r[k];
        g[1][k] = gj_t[k];
        g[1][k + 3] = gj_r[k];
    }
    RowEval {
        phi,
        phi_t: 0.0,
        gamma,
        g,
    }
}

/// Point coincidence `p_i - p_j = 0`: three rows appended to `out`.
fn point_rows(ki: &BodyKin, fi: &Frame, kj: &BodyKin, fj: &Frame, out: &mut Vec<RowEval>) {
    let d = ki.point(&fi.origin) - kj.point(&fj.origin);
    let ji = ki.point_rot_jacobian(&fi.origin);
    let jj = kj.point_rot_jacobian(&fj.origin);
    let acc = ki.point_centripetal(&fi.origin) - kj.point_centripetal(&fj.origin);
    for k in 0..3 {
        let e = Vec3::ith(k, 1.0);
        let gi_r: Vec3 = ji.row(k).transpose();
        let gj_r: Vec3 = -jj.row(k).transpose();
        out.push(row(d[k], -acc[k], e, gi_r, -e, gj_r));
    }
}

/// `u_i . u_j = 0` for body-frame axes `a_i`, `a_j`.
fn dot1_row(ki: &BodyKin, a_i: Vec3, kj: &BodyKin, a_j: Vec3) -> RowEval {
    let ui = ki.rot * a_i;
    let uj = kj.rot * a_j;
    let ui_dot = ki.rot * ki.omega.cross(&a_i);
    let uj_dot = kj.rot * kj.omega.cross(&a_j);
    let gdv = ki.point_centripetal(&a_i).dot(&uj)
        + 2.0 * ui_dot.dot(&uj_dot)
        + ui.dot(&kj.point_centripetal(&a_j));
    let z = Vec3::zeros();
    row(
        ui.dot(&uj),
        -gdv,
        z,
        a_i.cross(&(ki.rot.transpose() * uj)),
        z,
        a_j.cross(&(kj.rot.transpose() * ui)),
    )
}

/// `u_i . (p_j - p_i)` for body-frame axis `a_i` and the frame origins.
fn dot2_row(ki: &BodyKin, fi: &Frame, a_i: Vec3, kj: &BodyKin, fj: &Frame) -> RowEval {
    let ui = ki.rot * a_i;
    let d = kj.point(&fj.origin) - ki.point(&fi.origin);
    let d_dot = kj.point_velocity(&fj.origin) - ki.point_velocity(&fi.origin);
    let ui_dot = ki.rot * ki.omega.cross(&a_i);
    let acc = kj.point_centripetal(&fj.origin) - ki.point_centripetal(&fi.origin);
    let gdv = ki.point_centripetal(&a_i).dot(&d) + 2.0 * ui_dot.dot(&d_dot) + ui.dot(&acc);
    row(
        ui.dot(&d),
        -gdv,
        -ui,
        a_i.cross(&(ki.rot.transpose() * d + fi.origin)),
        ui,
        fj.origin.cross(&(kj.rot.transpose() * ui)),
    )
}

/// Evaluates all rows of `joint` at time `t` and appends them to `out`.
pub fn joint_rows(joint: &Joint, kins: &[BodyKin], t: f64, inputs: &[f64], out: &mut Vec<RowEval>) {
    let (fi, fj) = (&joint.frame_i, &joint.frame_j);
    let ki = kin_of(kins, fi.body);
    let kj = kin_of(kins, fj.body);
    let (xi, yi, zi) = (
        fi.axes.column(0).into(),
        fi.axes.column(1).into(),
        fi.axes.column(2).into(),
    );
    let (xj, yj) = (fj.axes.column(0).into(), fj.axes.column(1).into());
    match joint.kind {
        JointKind::Spherical => point_rows(ki, fi, kj, fj, out),
        JointKind::PointOnLine => {
            out.push(dot2_row(ki, fi, xi, kj, fj));
            out.push(dot2_row(ki, fi, yi, kj, fj));
        }
        JointKind::Revolute => {
            point_rows(ki, fi, kj, fj, out);
            out.push(dot1_row(ki, zi, kj, xj));
            out.push(dot1_row(ki, zi, kj, yj));
        }
        JointKind::Fixed => {
            point_rows(ki, fi, kj, fj, out);
            out.push(dot1_row(ki, zi, kj, xj));
            out.push(dot1_row(ki, zi, kj, yj));
            out.push(dot1_row(ki, xi, kj, yj));
        }
        JointKind::Prismatic => {
            out.push(dot1_row(ki, zi, kj, xj));
            out.push(dot1_row(ki, zi, kj, yj));
            out.push(dot1_row(ki, xi, kj, yj));
            out.push(dot2_row(ki, fi, xi, kj, fj));
            out.push(dot2_row(ki, fi, yi, kj, fj));
        }
        JointKind::AngleDrive(profile) => {
            let (target, rate, acc) = profile.eval(t, inputs);
            let ra = relative_angle(kins, fi, fj);
            let h = angle_curvature(kins, fi, fj);
            let om = nalgebra::Vector6::new(
                ki.omega.x, ki.omega.y, ki.omega.z, kj.omega.x, kj.omega.y, kj.omega.z,
            );
            let quad = om.dot(&(h * om));
            let z = Vec3::zeros();
            let mut r = row(
                wrap_angle(ra.theta - target),
                -quad + acc,
                z,
                ra.grad[0],
                z,
                ra.grad[1],
            );
            r.phi_t = -rate;
            out.push(r);
        }
        JointKind::TranslationDrive(profile) => {
            let (target, rate, acc) = profile.eval(t, inputs);
            let mut r = dot2_row(ki, fi, zi, kj, fj);
            r.phi -= target;
            r.phi_t = -rate;
            r.gamma += acc;
            out.push(r);
        }
    }
}
