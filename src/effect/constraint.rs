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
//!
//! Frames on a flexible-body node (see [`crate::model::Frame::on_node`]) enter through
//! [`NodeKin`]: their body-frame origin and axes then depend on the modal coordinates, with
//! elastic rates, and each row carries per side two body-frame covectors [`RowEval::gn`] from
//! which the system forms the modal columns `Phi_k^T gn_t + Psi_k^T gn_r` (`6 + n` entries per
//! body in all). The formulas stay those of a rigid body with, for a body vector `s` (origin or
//! axis) of elastic rate `s'`: velocity `R (omega x s + s')`, acceleration bias
//! `R (omega x (omega x s) + 2 omega x s')`.

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
    /// Node covectors of sides i and j (body frame): `[gn_t (3), gn_r (3)]`; the row's modal
    /// columns of a node frame are `Phi_k^T gn_t + Psi_k^T gn_r` (zero for other frames).
    pub gn: [[f64; 6]; 2],
}

/// Motion of a flexible-body node relative to its body frame (body-frame vectors).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NodeKin {
    /// Deformed position `rho_k + Phi_k a` [m].
    pub u: Vec3,
    /// Elastic velocity `Phi_k a_dot` [m/s].
    pub u_dot: Vec3,
    /// Small rotation `Psi_k a` [rad].
    pub theta: Vec3,
    /// Its rate `Psi_k a_dot` [rad/s].
    pub theta_dot: Vec3,
}

/// A body-frame vector of a frame (origin or axis) at the current configuration.
#[derive(Debug, Clone, Copy)]
struct BVec {
    /// Current value (body frame).
    s: Vec3,
    /// Elastic rate (body frame).
    rate: Vec3,
    /// For node frames: the offset `d` (origin) or undeformed axis `e`, whose cross product with
    /// a covector gives the node-rotation covector; `None` off nodes.
    lever: Option<Vec3>,
}

/// One side of a joint: body kinematics and the frame's node motion (if any).
#[derive(Debug, Clone, Copy)]
struct Side<'a> {
    k: &'a BodyKin,
    f: &'a Frame,
    node: Option<NodeKin>,
}

impl Side<'_> {
    /// The frame origin as a body vector.
    fn origin(&self) -> BVec {
        let d = self.f.origin;
        match self.node {
            None => BVec {
                s: d,
                rate: Vec3::zeros(),
                lever: None,
            },
            Some(n) => BVec {
                s: n.u + d + n.theta.cross(&d),
                rate: n.u_dot + n.theta_dot.cross(&d),
                lever: Some(d),
            },
        }
    }

    /// Frame axis `c` (0, 1, 2) as a body vector.
    fn axis(&self, c: usize) -> BVec {
        let e: Vec3 = self.f.axes.column(c).into();
        match self.node {
            None => BVec {
                s: e,
                rate: Vec3::zeros(),
                lever: None,
            },
            Some(n) => BVec {
                s: e + n.theta.cross(&e),
                rate: n.theta_dot.cross(&e),
                lever: Some(e),
            },
        }
    }

    /// World image `R s` (without the body origin).
    fn world(&self, b: &BVec) -> Vec3 {
        self.k.rot * b.s
    }

    /// World point `r + R s`.
    fn point(&self, b: &BVec) -> Vec3 {
        self.k.r + self.k.rot * b.s
    }

    /// Rate of `R s` (without the body velocity).
    fn world_rate(&self, b: &BVec) -> Vec3 {
        self.k.rot * (self.k.omega.cross(&b.s) + b.rate)
    }

    /// Velocity of the point `r + R s`.
    fn point_velocity(&self, b: &BVec) -> Vec3 {
        self.k.v + self.world_rate(b)
    }

    /// Acceleration bias of `R s`: `R (omega x (omega x s) + 2 omega x s')`.
    fn bias(&self, b: &BVec) -> Vec3 {
        let w = self.k.omega;
        self.k.rot * (w.cross(&w.cross(&b.s)) + 2.0 * w.cross(&b.rate))
    }
}

/// Jacobian of one side of a row, accumulated from world covectors of its body vectors.
#[derive(Debug, Clone, Copy, Default)]
struct SideJac {
    t: Vec3,
    r: Vec3,
    nt: Vec3,
    nr: Vec3,
}

impl SideJac {
    /// Adds `c . (R s)` of an axis-like vector (no translation dependence).
    fn vector(&mut self, side: &Side, b: &BVec, c: &Vec3) {
        let cb = side.k.rot.transpose() * c;
        self.r += b.s.cross(&cb);
        if let Some(l) = b.lever {
            self.nr += l.cross(&cb);
        }
    }

    /// Adds `c . (r + R s)` of a point.
    fn point(&mut self, side: &Side, b: &BVec, c: &Vec3) {
        self.t += c;
        self.vector(side, b, c);
        if b.lever.is_some() {
            self.nt += side.k.rot.transpose() * c;
        }
    }

    fn pack(&self) -> ([f64; 6], [f64; 6]) {
        let (mut g, mut gn) = ([0.0; 6], [0.0; 6]);
        for k in 0..3 {
            g[k] = self.t[k];
            g[k + 3] = self.r[k];
            gn[k] = self.nt[k];
            gn[k + 3] = self.nr[k];
        }
        (g, gn)
    }
}

fn row(phi: f64, gamma: f64, ji: &SideJac, jj: &SideJac) -> RowEval {
    let (gi, gni) = ji.pack();
    let (gj, gnj) = jj.pack();
    RowEval {
        phi,
        phi_t: 0.0,
        gamma,
        g: [gi, gj],
        gn: [gni, gnj],
    }
}

/// Point coincidence `p_i - p_j = 0`: three rows appended to `out`.
fn point_rows(si: &Side, sj: &Side, out: &mut Vec<RowEval>) {
    let (oi, oj) = (si.origin(), sj.origin());
    let d = si.point(&oi) - sj.point(&oj);
    let acc = si.bias(&oi) - sj.bias(&oj);
    for k in 0..3 {
        let e = Vec3::ith(k, 1.0);
        let (mut ji, mut jj) = (SideJac::default(), SideJac::default());
        ji.point(si, &oi, &e);
        jj.point(sj, &oj, &-e);
        out.push(row(d[k], -acc[k], &ji, &jj));
    }
}

/// `u_i . u_j = 0` for frame axes `ci` of i and `cj` of j.
fn dot1_row(si: &Side, ci: usize, sj: &Side, cj: usize) -> RowEval {
    let (ai, aj) = (si.axis(ci), sj.axis(cj));
    let ui = si.world(&ai);
    let uj = sj.world(&aj);
    let gdv = si.bias(&ai).dot(&uj)
        + 2.0 * si.world_rate(&ai).dot(&sj.world_rate(&aj))
        + ui.dot(&sj.bias(&aj));
    let (mut ji, mut jj) = (SideJac::default(), SideJac::default());
    ji.vector(si, &ai, &uj);
    jj.vector(sj, &aj, &ui);
    row(ui.dot(&uj), -gdv, &ji, &jj)
}

/// `u_i . (p_j - p_i)` for frame axis `ci` of i and the frame origins.
fn dot2_row(si: &Side, ci: usize, sj: &Side) -> RowEval {
    let (ai, oi, oj) = (si.axis(ci), si.origin(), sj.origin());
    let ui = si.world(&ai);
    let d = sj.point(&oj) - si.point(&oi);
    let d_dot = sj.point_velocity(&oj) - si.point_velocity(&oi);
    let acc = sj.bias(&oj) - si.bias(&oi);
    let gdv = si.bias(&ai).dot(&d) + 2.0 * si.world_rate(&ai).dot(&d_dot) + ui.dot(&acc);
    let (mut ji, mut jj) = (SideJac::default(), SideJac::default());
    ji.vector(si, &ai, &d);
    ji.point(si, &oi, &-ui);
    jj.point(sj, &oj, &ui);
    row(ui.dot(&d), -gdv, &ji, &jj)
}

/// Evaluates all rows of `joint` at time `t` and appends them to `out`; `nodes` holds the node
/// motion of frames i and j when they ride on a flexible-body node.
pub fn joint_rows(
    joint: &Joint,
    kins: &[BodyKin],
    nodes: [Option<NodeKin>; 2],
    t: f64,
    inputs: &[f64],
    out: &mut Vec<RowEval>,
) {
    let (fi, fj) = (&joint.frame_i, &joint.frame_j);
    let ki = kin_of(kins, fi.body);
    let kj = kin_of(kins, fj.body);
    let si = Side {
        k: ki,
        f: fi,
        node: nodes[0],
    };
    let sj = Side {
        k: kj,
        f: fj,
        node: nodes[1],
    };
    let (x, y, z) = (0, 1, 2);
    match joint.kind {
        JointKind::Spherical => point_rows(&si, &sj, out),
        JointKind::PointOnLine => {
            out.push(dot2_row(&si, x, &sj));
            out.push(dot2_row(&si, y, &sj));
        }
        JointKind::Revolute => {
            point_rows(&si, &sj, out);
            out.push(dot1_row(&si, z, &sj, x));
            out.push(dot1_row(&si, z, &sj, y));
        }
        JointKind::Fixed => {
            point_rows(&si, &sj, out);
            out.push(dot1_row(&si, z, &sj, x));
            out.push(dot1_row(&si, z, &sj, y));
            out.push(dot1_row(&si, x, &sj, y));
        }
        JointKind::Prismatic => {
            out.push(dot1_row(&si, z, &sj, x));
            out.push(dot1_row(&si, z, &sj, y));
            out.push(dot1_row(&si, x, &sj, y));
            out.push(dot2_row(&si, x, &sj));
            out.push(dot2_row(&si, y, &sj));
        }
        JointKind::AngleDrive(profile) => {
            // not allowed on node frames (checked by the model builder)
            let (target, rate, acc) = profile.eval(t, inputs);
            let ra = relative_angle(kins, fi, fj);
            let h = angle_curvature(kins, fi, fj);
            let om = nalgebra::Vector6::new(
                ki.omega.x, ki.omega.y, ki.omega.z, kj.omega.x, kj.omega.y, kj.omega.z,
            );
            let quad = om.dot(&(h * om));
            let ji = SideJac {
                r: ra.grad[0],
                ..SideJac::default()
            };
            let jj = SideJac {
                r: ra.grad[1],
                ..SideJac::default()
            };
            let mut r = row(wrap_angle(ra.theta - target), -quad + acc, &ji, &jj);
            r.phi_t = -rate;
            out.push(r);
        }
        JointKind::TranslationDrive(profile) => {
            let (target, rate, acc) = profile.eval(t, inputs);
            let mut r = dot2_row(&si, z, &sj);
            r.phi -= target;
            r.phi_t = -rate;
            r.gamma += acc;
            out.push(r);
        }
    }
}
