//! Joint coordinates to maximal coordinates and back.
//!
//! For joint `m` carrying body `k` from parent `p` (the ground: at the origin, at rest):
//! parent-side frame `F = R_p A_p` at `o = r_p + R_p s_p (+ d z)`, `z = F e_z` (world);
//! revolute: `R_k = F Rz(theta) A_c^-1`, prismatic: `R_k = F A_c^-1` (with its constant half turn);
//! `r_k = o - R_k s_c`. Rates: `omega_k = omega_p + z theta'` (revolute),
//! `v_k = v_o - omega_k x (R_k s_c)`, `v_o = v_p + omega_p x (o - r_p) (+ z d')`.
//! Quaternions are products of unit quaternions, renormalized at each body (round-off).

use super::{JointTree, TreeJointKind};
use crate::math::{Mat3, Quat, Vec3};
use crate::model::kinematics::{put_quat, quat_at};
use nalgebra::Quaternion;

/// World-frame pose and motion of one tree body (the child of a joint) and its joint.
#[derive(Debug, Clone, Copy)]
pub struct Link {
    /// Orientation body -> world, as quaternion and matrix.
    pub quat: Quat,
    pub rot: Mat3,
    /// Centre of mass [m] and its velocity [m/s], world.
    pub r: Vec3,
    pub vel: Vec3,
    /// Angular velocity [rad/s], world and body frame.
    pub omega: Vec3,
    pub omega_body: Vec3,
    /// Joint axis (z of the parent-side frame), world.
    pub axis: Vec3,
    /// Joint point (origin of the parent-side frame, moved by `d` along `axis` for a prismatic
    /// joint) [m], world.
    pub point: Vec3,
    /// From the parent's centre of mass to the joint point [m], world (from the origin for the
    /// ground).
    pub rho_p: Vec3,
    /// From the body's centre of mass to the joint point [m], world.
    pub rho_c: Vec3,
}

impl Default for Link {
    fn default() -> Self {
        Link {
            quat: Quat::identity(),
            rot: Mat3::identity(),
            r: Vec3::zeros(),
            vel: Vec3::zeros(),
            omega: Vec3::zeros(),
            omega_body: Vec3::zeros(),
            axis: Vec3::z(),
            point: Vec3::zeros(),
            rho_p: Vec3::zeros(),
            rho_c: Vec3::zeros(),
        }
    }
}

/// Renormalized product (unit to round-off at every depth of the tree).
#[inline]
fn unit(q: Quaternion<f64>) -> Quat {
    Quat::new_normalize(q)
}

/// Forward kinematics at joint coordinates `theta` and rates `dtheta` (one per coordinate):
/// fills `links` (one per tree joint, fixed ones included) and writes the maximal positions `q`
/// and speeds `v` of every tree body.
pub fn forward(
    tree: &JointTree,
    theta: &[f64],
    dtheta: &[f64],
    links: &mut [Link],
    q: &mut [f64],
    v: &mut [f64],
) {
    for (m, j) in tree.joints.iter().enumerate() {
        // the ground: at the origin, at rest, unrotated
        let (pq, prot, pr, pvel, pom) = match j.parent {
            Some(p) => {
                let l = &links[p];
                (l.quat.into_inner(), l.rot, l.r, l.vel, l.omega)
            }
            None => (
                Quaternion::identity(),
                Mat3::identity(),
                Vec3::zeros(),
                Vec3::zeros(),
                Vec3::zeros(),
            ),
        };
        let axis = prot * j.axis_in_parent;
        let mut rho_p = prot * j.parent_origin;
        let (rel, omega, mut v_o) = match j.kind {
            TreeJointKind::Revolute(c) => {
                let (s, co) = (0.5 * theta[c]).sin_cos();
                (
                    j.rel0 * co + j.rel1 * s,
                    pom + axis * dtheta[c],
                    Vec3::zeros(),
                )
            }
            TreeJointKind::Prismatic(c) => {
                rho_p += axis * theta[c];
                (j.rel0, pom, axis * dtheta[c])
            }
            TreeJointKind::Fixed => (j.rel0, pom, Vec3::zeros()),
        };
        let quat = unit(pq * rel);
        v_o += pvel + pom.cross(&rho_p);
        let rot = quat.to_rotation_matrix().into_inner();
        let rho_c = rot * j.child_origin;
        let point = pr + rho_p;
        let r = point - rho_c;
        let vel = v_o - omega.cross(&rho_c);
        let omega_body = rot.transpose() * omega;
        links[m] = Link {
            quat,
            rot,
            r,
            vel,
            omega,
            omega_body,
            axis,
            point,
            rho_p,
            rho_c,
        };
        let (qo, vo) = (j.q_offset, j.v_offset);
        q[qo..qo + 3].copy_from_slice(r.as_slice());
        put_quat(q, qo + 3, &quat);
        v[vo..vo + 3].copy_from_slice(vel.as_slice());
        v[vo + 3..vo + 6].copy_from_slice(omega_body.as_slice());
    }
}

/// Joint coordinates and rates of the maximal state `(q, v)` (which should satisfy the joints):
/// revolute angles in (-pi, pi] from the relative rotation of the joint frames, prismatic
/// displacements along the parent-side z axis; rates from the relative angular velocity and the
/// relative velocity of the joint points along the axis.
pub fn extract(tree: &JointTree, q: &[f64], v: &[f64], theta: &mut [f64], dtheta: &mut [f64]) {
    let read = |qo: usize, vo: usize| {
        let quat = quat_at(q, qo + 3);
        let r = Vec3::new(q[qo], q[qo + 1], q[qo + 2]);
        let vel = Vec3::new(v[vo], v[vo + 1], v[vo + 2]);
        let omega = quat * Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]);
        (quat, r, vel, omega)
    };
    for j in &tree.joints {
        let (pq, pr, pvel, pom) = match j.parent {
            Some(p) => {
                let pj = &tree.joints[p];
                read(pj.q_offset, pj.v_offset)
            }
            None => (
                Quat::identity(),
                Vec3::zeros(),
                Vec3::zeros(),
                Vec3::zeros(),
            ),
        };
        if j.kind == TreeJointKind::Fixed {
            continue;
        }
        let (cq, cr, cvel, com) = read(j.q_offset, j.v_offset);
        let frame = pq * j.parent_axes;
        let axis = frame * Vec3::z();
        match j.kind {
            TreeJointKind::Revolute(c) => {
                // child-side frame in the parent-side frame: Rz(theta)
                let rel = (frame.inverse() * cq * j.child_axes_inv.inverse()).into_inner();
                theta[c] = 2.0 * rel.k.atan2(rel.w);
                if theta[c] > std::f64::consts::PI {
                    theta[c] -= 2.0 * std::f64::consts::PI;
                } else if theta[c] <= -std::f64::consts::PI {
                    theta[c] += 2.0 * std::f64::consts::PI;
                }
                dtheta[c] = axis.dot(&(com - pom));
            }
            TreeJointKind::Fixed => {}
            TreeJointKind::Prismatic(c) => {
                let rho_p = pq * j.parent_origin;
                let rho_c = cq * j.child_origin;
                let gap = cr + rho_c - pr - rho_p;
                theta[c] = axis.dot(&gap);
                let rate = cvel + com.cross(&rho_c) - pvel - pom.cross(&rho_p);
                dtheta[c] = axis.dot(&rate);
            }
        }
    }
}
