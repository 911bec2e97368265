//! Finding a kinematic tree of revolute, prismatic and fixed joints in a system.
//!
//! Rules (each refusal names the body or joint): every body is rigid (not flexible, not a
//! particle); every joint is revolute, prismatic or fixed; breadth-first from the ground, every
//! joint reaches a body not reached before (otherwise it closes a loop) and every body is reached
//! (otherwise it floats free); no force effect has contact events (the tree integrator does not
//! locate them); a revolute joint's z axes point the same way at the given state, a fixed joint's
//! frames coincide there (to 1e-6 rad).

use super::{JointTree, TreeJoint, TreeJointKind};
use crate::dae::System;
use crate::math::{Mat3, Quat, Vec3};
use crate::model::kinematics::quat_at;
use crate::model::{BodyId, BodyKind, Frame, JointKind};
use nalgebra::{Quaternion, Rotation3};
use std::collections::VecDeque;

/// Rotation of a frame's axes (columns) as a unit quaternion.
fn axes_quat(axes: &Mat3) -> Quat {
    Quat::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*axes))
}

/// World rotation of body `id` at `q` (identity for the ground).
fn body_rotation(sys: &System, id: BodyId, q: &[f64]) -> Quat {
    match sys.model.body(id) {
        Some(b) => quat_at(q, b.q_offset + 3),
        None => Quat::identity(),
    }
}

/// See the module doc.
pub fn detect(sys: &System, q: &[f64]) -> Result<JointTree, String> {
    let model = &sys.model;
    for b in &model.bodies {
        match b.kind {
            BodyKind::Rigid { .. } => {}
            BodyKind::Modal { .. } => {
                return Err(format!(
                    "body `{}` is flexible (modal): the joint-coordinate path takes rigid bodies only",
                    b.name
                ));
            }
            BodyKind::Particle { .. } => {
                return Err(format!(
                    "body `{}` is a particle (no rotation): the joint-coordinate path takes rigid bodies only",
                    b.name
                ));
            }
        }
    }
    for j in &model.joints {
        let what = match j.kind {
            JointKind::Revolute | JointKind::Prismatic | JointKind::Fixed => continue,
            JointKind::Spherical => "spherical",
            JointKind::PointOnLine => "point-on-line",
            JointKind::AngleDrive(_) => "an angle drive",
            JointKind::TranslationDrive(_) => "a translation drive",
        };
        return Err(format!(
            "joint `{}` is {what}: the joint-coordinate path takes revolute, prismatic and fixed joints only",
            j.name
        ));
    }
    if sys.n_contact_events() > 0 {
        return Err(format!(
            "the model has {} contact events: the joint-coordinate path does not locate contact events; use integrator = dopri5, bdf or gen_alpha",
            sys.n_contact_events()
        ));
    }
    let nb = model.bodies.len();
    let mut reached = vec![false; nb];
    let mut used = vec![false; model.joints.len()];
    // tree index of the joint carrying each reached body
    let mut carrier: Vec<Option<usize>> = vec![None; nb];
    let mut joints: Vec<TreeJoint> = Vec::with_capacity(nb);
    let mut n_coords = 0;
    let mut queue: VecDeque<BodyId> = VecDeque::from([BodyId::GROUND]);
    while let Some(p) = queue.pop_front() {
        for (ji, j) in model.joints.iter().enumerate() {
            if used[ji] || (j.frame_i.body != p && j.frame_j.body != p) {
                continue;
            }
            used[ji] = true;
            let (pf, cf): (&Frame, &Frame) = if j.frame_i.body == p {
                (&j.frame_i, &j.frame_j)
            } else {
                (&j.frame_j, &j.frame_i)
            };
            let k = cf
                .body
                .index()
                .ok_or_else(|| format!("joint `{}` connects the ground to the ground", j.name))?;
            if reached[k] {
                return Err(format!(
                    "joint `{}` closes a loop (body `{}` already hangs from another joint): the joint-coordinate path takes trees only",
                    j.name, model.bodies[k].name
                ));
            }
            reached[k] = true;
            let b = &model.bodies[k];
            let BodyKind::Rigid { mass, inertia } = b.kind else {
                return Err(format!("body `{}` is not rigid", b.name));
            };
            let parent_axes = axes_quat(&pf.axes);
            let child_axes = axes_quat(&cf.axes);
            // relative rotation of the child-side frame in the parent-side frame at `q`
            let rel = (body_rotation(sys, p, q) * parent_axes).inverse()
                * (body_rotation(sys, cf.body, q) * child_axes);
            let m = rel.to_rotation_matrix().into_inner();
            if m[(2, 2)] <= 0.0 {
                return Err(format!(
                    "joint `{}`: its frames' z axes point opposite ways at the start; the joint-coordinate path needs them aligned",
                    j.name
                ));
            }
            if j.kind == JointKind::Fixed && rel.angle() > 1e-6 {
                return Err(format!(
                    "joint `{}` is fixed but its frames' axes differ by {:.3e} rad at the start; the joint-coordinate path needs them to coincide",
                    j.name,
                    rel.angle()
                ));
            }
            let (kind, child_axes_inv) = match j.kind {
                JointKind::Prismatic => {
                    // x axes aligned or opposite (the joint's rows allow both): keep which
                    let flip = if m[(0, 0)] < 0.0 {
                        Quat::from_axis_angle(&Vec3::z_axis(), std::f64::consts::PI)
                    } else {
                        Quat::identity()
                    };
                    n_coords += 1;
                    (
                        TreeJointKind::Prismatic(n_coords - 1),
                        flip * child_axes.inverse(),
                    )
                }
                JointKind::Fixed => (TreeJointKind::Fixed, child_axes.inverse()),
                _ => {
                    n_coords += 1;
                    (TreeJointKind::Revolute(n_coords - 1), child_axes.inverse())
                }
            };
            carrier[k] = Some(joints.len());
            joints.push(TreeJoint {
                joint: ji,
                body: k,
                parent: p.index().and_then(|pi| carrier[pi]),
                kind,
                parent_origin: pf.origin,
                parent_axes,
                child_origin: cf.origin,
                child_axes_inv,
                rel0: (parent_axes * child_axes_inv).into_inner(),
                rel1: parent_axes.into_inner()
                    * Quaternion::new(0.0, 0.0, 0.0, 1.0)
                    * child_axes_inv.into_inner(),
                axis_in_parent: parent_axes * Vec3::z(),
                mass,
                inertia,
                q_offset: b.q_offset,
                v_offset: b.v_offset,
            });
            queue.push_back(cf.body);
        }
    }
    if let Some(k) = reached.iter().position(|r| !r) {
        return Err(format!(
            "body `{}` is not connected to the ground by joints: the joint-coordinate path takes trees hanging from the ground only",
            model.bodies[k].name
        ));
    }
    Ok(JointTree { joints, n_coords })
}
