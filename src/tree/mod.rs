//! Joint-coordinate (minimal-coordinate) formulation of kinematic trees (issue #18).
//!
//! When every body is rigid and hangs from the ground through exactly one revolute, prismatic or
//! fixed joint (no loops), the motion is described by one coordinate per revolute or prismatic
//! joint: an angle [rad] about the joint's z axis or a displacement [m] along it (a fixed joint
//! has none: its child moves with its parent). This module
//!
//! - finds such a tree in a [`System`] or says precisely why there is none ([`JointTree::detect`],
//!   module `detect`);
//! - maps joint coordinates and rates exactly to the maximal coordinates of [`crate::state::State`]
//!   (positions, unit quaternions, world velocities, body-frame angular velocities) and back
//!   (module `kinematics`), so every output, energy and measure is computed by the existing code
//!   on the mapped state;
//! - computes the joint accelerations (module `dynamics`): generalized mass by the
//!   composite-rigid-body algorithm, velocity-product terms by a recursive Newton-Euler pass, the
//!   applied forces of [`System::forces`] (gravity, springs, dampers, gyroscopic terms, every
//!   effect) at the mapped state projected with the joint Jacobian (`J^T f`), and a dense
//!   Cholesky solve (module `cholesky`).
//!
//! Cost per evaluation: `O(n d)` for kinematics, composite inertias and the mass matrix (`d` the
//! depth of the tree, `n` for a chain) plus `O(n^3 / 6)` for the Cholesky factor; small trees
//! (up to a few dozen joints) are dominated by the `O(n)` passes and [`System::forces`].
//!
//! The integrator that steps these coordinates is [`crate::integrator::tree_rk`].

mod cholesky;
mod detect;
mod dynamics;
mod kinematics;

pub use dynamics::TreeScratch;
pub use kinematics::{Link, extract};

use crate::dae::System;
use crate::math::{Mat3, Quat, Vec3};
use nalgebra::Quaternion;

/// Kind of a tree joint, with the index of its coordinate in the joint state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TreeJointKind {
    /// Rotation about the parent-side frame's z axis; coordinate [rad].
    Revolute(usize),
    /// Translation along the parent-side frame's z axis; coordinate [m].
    Prismatic(usize),
    /// No relative motion (the frames coincide); no coordinate.
    Fixed,
}

/// One joint of the tree with the body it carries (the child).
#[derive(Debug, Clone, PartialEq)]
pub struct TreeJoint {
    /// Index of the joint in `model.joints`.
    pub joint: usize,
    /// Index of the child body in `model.bodies`.
    pub body: usize,
    /// Tree index of the parent joint (`None`: the parent is the ground). Always smaller than
    /// this joint's own index (parents come first).
    pub parent: Option<usize>,
    pub kind: TreeJointKind,
    /// Origin [m] of the parent-side frame in the parent body frame (world frame for the ground).
    pub parent_origin: Vec3,
    /// Axes of the parent-side frame relative to the parent body frame (world for the ground).
    pub parent_axes: Quat,
    /// Origin [m] of the child-side frame in the child body frame.
    pub child_origin: Vec3,
    /// Rotation from the child-side frame to the child body frame, inverted
    /// (`R_child = R_parent_frame Rz(theta) child_axes_inv`); for a prismatic joint it includes
    /// the constant half turn about z when its x axes are opposite.
    pub child_axes_inv: Quat,
    /// The rotation child body frame -> parent body frame, `parent_axes Rz(theta)
    /// child_axes_inv`, expanded in the half angle: `rel0 cos(theta / 2) + rel1 sin(theta / 2)`
    /// (`Rz` is `cos + k sin` of the half angle). Revolute joints use both; the other kinds'
    /// constant rotation is `rel0`.
    pub rel0: Quaternion<f64>,
    pub rel1: Quaternion<f64>,
    /// The joint axis (z of the parent-side frame) in the parent body frame (world for the
    /// ground).
    pub axis_in_parent: Vec3,
    /// Mass [kg] and inertia about the centre of mass [kg m^2] (body frame) of the child.
    pub mass: f64,
    pub inertia: Mat3,
    /// Offsets of the child body in `q` and `v`.
    pub q_offset: usize,
    pub v_offset: usize,
}

/// A kinematic tree of revolute, prismatic and fixed joints found in a system.
#[derive(Debug, Clone, PartialEq)]
pub struct JointTree {
    /// Joints in topological order (parents before children).
    pub joints: Vec<TreeJoint>,
    /// Number of joint coordinates (the revolute and prismatic joints, numbered in order).
    pub n_coords: usize,
}

impl JointTree {
    /// Number of joint coordinates.
    pub fn n(&self) -> usize {
        self.n_coords
    }

    /// Finds the tree at the (consistent) maximal state `q`; `Err` names the body or joint that
    /// prevents it. See [`detect`](self) for the rules.
    pub fn detect(sys: &System, q: &[f64]) -> Result<JointTree, String> {
        detect::detect(sys, q)
    }
}
