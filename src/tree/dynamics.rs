//! Joint accelerations of a tree: `M(theta) theta'' = J^T (f - M_b c)`.
//!
//! All vectors are world-frame; every joint's quantities are taken about its joint point `o_m`.
//!
//! - Velocity-product accelerations `c` (the body accelerations at `theta'' = 0`) by a forward
//!   pass (recursive Newton-Euler with zero joint accelerations).
//! - Each body's residual wrench `(f_lin - m a_k, R (tau_b - J R^T alpha_k))` from the applied
//!   forces of [`System::forces`] (its generalized force per body: force at the centre of mass,
//!   world; torque, body frame, with the gyroscopic term), summed over subtrees about the joint
//!   points (backward pass): `g_m = z_m . tau_m` (revolute) or `z_m . f_m` (prismatic).
//! - Generalized mass by the composite-rigid-body algorithm: subtree inertias (mass, first moment
//!   and rotational inertia about `o_m`) by parallel-axis shifts between neighbouring joint
//!   points (no large moment arms about a distant origin), `M_mn = S_n . (I_m S_m)` along the
//!   path from `m` to the root.

use super::cholesky;
use super::kinematics::{self, Link};
use super::{JointTree, TreeJointKind};
use crate::dae::System;
use crate::math::{Mat3, Vec3};
use crate::model::kinematics::BodyKin;

/// Scratch of the joint-space evaluation (sized once; no allocation per evaluation).
#[derive(Debug, Clone, Default)]
pub struct TreeScratch {
    /// Pose and motion of every tree body (one per joint, fixed ones included).
    pub links: Vec<Link>,
    /// Maximal positions and speeds of the last evaluation.
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    /// Generalized forces of [`System::forces`] there.
    pub f: Vec<f64>,
    /// Velocity-product angular and linear (centre of mass) accelerations, world.
    alpha: Vec<Vec3>,
    acc: Vec<Vec3>,
    /// Subtree wrenches about the joint points: torque [N m], force [N].
    torque: Vec<Vec3>,
    force: Vec<Vec3>,
    /// Subtree inertias about the joint points: mass [kg], first moment [kg m], inertia [kg m^2].
    cmass: Vec<f64>,
    cmom: Vec<Vec3>,
    cinertia: Vec<Mat3>,
    /// Joint-space mass matrix (then its Cholesky factor), row-major `n x n`.
    pub mass: Vec<f64>,
}

impl TreeScratch {
    /// Sizes the buffers for `tree` in `sys`; `q` starts as a copy of `q0` (the tree writes every
    /// body's coordinates, this only fills the vector).
    pub fn size_for(&mut self, tree: &JointTree, sys: &System, q0: &[f64]) {
        let (nj, n) = (tree.joints.len(), tree.n());
        self.links.resize(nj, Link::default());
        if self.q.len() != sys.n_q() {
            self.q.clear();
            self.q.extend_from_slice(q0);
        }
        self.v.resize(sys.n_v(), 0.0);
        self.f.resize(sys.n_v(), 0.0);
        for x in [
            &mut self.alpha,
            &mut self.acc,
            &mut self.torque,
            &mut self.force,
            &mut self.cmom,
        ] {
            x.resize(nj, Vec3::zeros());
        }
        self.cmass.resize(nj, 0.0);
        self.cinertia.resize(nj, Mat3::zeros());
        self.mass.resize(n * n, 0.0);
    }

    /// Maps `(theta, dtheta)` to the maximal state in `self.q`, `self.v` (and the links).
    pub fn map(&mut self, tree: &JointTree, theta: &[f64], dtheta: &[f64]) {
        kinematics::forward(
            tree,
            theta,
            dtheta,
            &mut self.links,
            &mut self.q,
            &mut self.v,
        );
    }

    /// Joint accelerations `ddtheta` [rad/s^2, m/s^2] at time `t` [s] and joint coordinates
    /// `theta`, rates `dtheta`; leaves the mapped maximal state in `self.q`, `self.v`.
    pub fn accelerations(
        &mut self,
        tree: &JointTree,
        sys: &mut System,
        t: f64,
        theta: &[f64],
        dtheta: &[f64],
        ddtheta: &mut [f64],
    ) -> Result<(), String> {
        self.map(tree, theta, dtheta);
        let links = &self.links;
        sys.set_kinematics(&self.q, &self.v, |kins| {
            for (j, l) in tree.joints.iter().zip(links) {
                kins[j.body] = BodyKin {
                    r: l.r,
                    rot: l.rot,
                    v: l.vel,
                    omega: l.omega_body,
                    col: j.v_offset,
                    rotational: true,
                };
            }
        });
        sys.forces(t, &self.q, &self.v, &mut self.f);
        self.bias(tree, dtheta);
        self.wrenches(tree, ddtheta);
        self.composite(tree);
        self.mass_matrix(tree);
        let n = tree.n();
        cholesky::factor(&mut self.mass, n)?;
        cholesky::solve(&self.mass, n, ddtheta);
        Ok(())
    }

    /// Forward pass: body accelerations at zero joint accelerations.
    fn bias(&mut self, tree: &JointTree, dtheta: &[f64]) {
        for (m, j) in tree.joints.iter().enumerate() {
            let (a_p, acc_p, om_p) = match j.parent {
                Some(p) => (self.alpha[p], self.acc[p], self.links[p].omega),
                None => (Vec3::zeros(), Vec3::zeros(), Vec3::zeros()),
            };
            let l = &self.links[m];
            let mut acc_o = acc_p + a_p.cross(&l.rho_p) + om_p.cross(&om_p.cross(&l.rho_p));
            let alpha = match j.kind {
                TreeJointKind::Revolute(c) => a_p + om_p.cross(&(l.axis * dtheta[c])),
                TreeJointKind::Prismatic(c) => {
                    acc_o += 2.0 * om_p.cross(&(l.axis * dtheta[c]));
                    a_p
                }
                TreeJointKind::Fixed => a_p,
            };
            self.alpha[m] = alpha;
            self.acc[m] = acc_o - alpha.cross(&l.rho_c) - l.omega.cross(&l.omega.cross(&l.rho_c));
        }
    }

    /// Backward pass: residual wrenches of the subtrees about the joint points, projected on
    /// the joint axes into `g`.
    fn wrenches(&mut self, tree: &JointTree, g: &mut [f64]) {
        for (m, j) in tree.joints.iter().enumerate() {
            let l = &self.links[m];
            let vo = j.v_offset;
            let f = &self.f;
            let force = Vec3::new(f[vo], f[vo + 1], f[vo + 2]) - j.mass * self.acc[m];
            let tau_b = Vec3::new(f[vo + 3], f[vo + 4], f[vo + 5])
                - j.inertia * (l.rot.transpose() * self.alpha[m]);
            self.force[m] = force;
            self.torque[m] = l.rot * tau_b - l.rho_c.cross(&force);
        }
        for m in (0..tree.joints.len()).rev() {
            let j = &tree.joints[m];
            let l = &self.links[m];
            match j.kind {
                TreeJointKind::Revolute(c) => g[c] = l.axis.dot(&self.torque[m]),
                TreeJointKind::Prismatic(c) => g[c] = l.axis.dot(&self.force[m]),
                TreeJointKind::Fixed => {}
            }
            if let Some(p) = j.parent {
                let d = l.point - self.links[p].point;
                let (tm, fm) = (self.torque[m], self.force[m]);
                self.torque[p] += tm + d.cross(&fm);
                self.force[p] += fm;
            }
        }
    }

    /// Subtree inertias about the joint points. With `[a]x [b]x = b a^T - (a . b) I`, the body's
    /// own inertia about its joint point is `R J R^T + m (|x|^2 I - x x^T)` (`x` from the joint
    /// point to the centre of mass) and the parallel-axis shift of a subtree (mass `M`, first
    /// moment `h` about point A) to point B = A - d adds
    /// `2 (h . d) I - d h^T - h d^T + M (|d|^2 I - d d^T)`.
    fn composite(&mut self, tree: &JointTree) {
        for (m, j) in tree.joints.iter().enumerate() {
            let l = &self.links[m];
            let x = -l.rho_c;
            self.cmass[m] = j.mass;
            self.cmom[m] = j.mass * x;
            let mut inertia = l.rot * j.inertia * l.rot.transpose();
            add_point_mass(&mut inertia, j.mass, &x);
            self.cinertia[m] = inertia;
        }
        for m in (0..tree.joints.len()).rev() {
            if let Some(p) = tree.joints[m].parent {
                let d = self.links[m].point - self.links[p].point;
                let (h, mm) = (self.cmom[m], self.cmass[m]);
                let mut shifted = self.cinertia[m];
                add_point_mass(&mut shifted, mm, &d);
                let hd = h.dot(&d);
                for r in 0..3 {
                    shifted[(r, r)] += 2.0 * hd;
                    for c in 0..3 {
                        shifted[(r, c)] -= d[r] * h[c] + h[r] * d[c];
                    }
                }
                self.cinertia[p] += shifted;
                let moment = h + mm * d;
                self.cmom[p] += moment;
                self.cmass[p] += mm;
            }
        }
    }

    /// `M_mn = S_n . (I_m S_m)` for `n` on the path from `m` to the root (lower triangle and its
    /// mirror).
    fn mass_matrix(&mut self, tree: &JointTree) {
        let n = tree.n();
        self.mass.fill(0.0);
        for (m, j) in tree.joints.iter().enumerate() {
            let l = &self.links[m];
            let (cm, tau, f) = match j.kind {
                TreeJointKind::Revolute(c) => {
                    (c, self.cinertia[m] * l.axis, l.axis.cross(&self.cmom[m]))
                }
                TreeJointKind::Prismatic(c) => {
                    (c, self.cmom[m].cross(&l.axis), self.cmass[m] * l.axis)
                }
                TreeJointKind::Fixed => continue,
            };
            // the joints on the path from `m` to the root that carry a coordinate (a fixed
            // joint passes the subtree's motion on unchanged)
            let mut k = Some(m);
            while let Some(a) = k {
                let ja = &tree.joints[a];
                let la = &self.links[a];
                let entry = match ja.kind {
                    TreeJointKind::Revolute(ca) => {
                        Some((ca, la.axis.dot(&(tau + (l.point - la.point).cross(&f)))))
                    }
                    TreeJointKind::Prismatic(ca) => Some((ca, la.axis.dot(&f))),
                    TreeJointKind::Fixed => None,
                };
                if let Some((ca, value)) = entry {
                    self.mass[cm * n + ca] = value;
                    self.mass[ca * n + cm] = value;
                }
                k = ja.parent;
            }
        }
    }
}

/// Adds the inertia of a point mass `m` [kg] at `x` [m]: `m (|x|^2 I - x x^T)`.
#[inline]
fn add_point_mass(inertia: &mut Mat3, m: f64, x: &Vec3) {
    let x2 = x.norm_squared();
    for r in 0..3 {
        inertia[(r, r)] += m * x2;
        for c in 0..3 {
            inertia[(r, c)] -= m * x[r] * x[c];
        }
    }
}
