//! Body kinds and their coordinate layout.
//!
//! Every body owns a contiguous range of position coordinates `q` and of generalized speeds `v`:
//!
//! | kind      | q (per body)                                   | v (per body)                               |
//! |-----------|------------------------------------------------|--------------------------------------------|
//! | rigid     | `r` [m] world, unit quaternion (w, x, y, z)    | `v` [m/s] world, `omega` [rad/s] body frame |
//! | particle  | `r` [m] world                                  | `v` [m/s] world                             |
//! | modal     | `r` [m] world, unit quaternion, `a` (n)        | `v` world, `omega` body, `a_dot` (n)        |
//!
//! Position increments live in the tangent space, of the same length as `v`: a translation
//! increment in the world frame and a rotation vector in the body frame (`R_new = R exp(dtheta~)`).
//! Modal coordinates are additive (their increment is `da`, their chart rate is `a_dot`).
//! Integrators only ever see flat vectors and the retraction of [`crate::model::Model`].
//!
//! # Modal (floating-frame) body
//! A modally reduced flexible body ([`BodyKind::Modal`], data [`ModalBodyData`]):
//!
//! - `r` [m] is the world position of the **body reference frame's origin** (for a panel from
//!   [`crate::flex`] the panel corner, or the Craig-Bampton frame node), *not* the centre of mass;
//!   the quaternion is the orientation of that reference frame (body to world).
//! - A material point with undeformed body-frame position `rho` [m] is at `r + A (rho + Phi a)`;
//!   the modal coordinates `a` (length n) are the reduced coordinates of the body data: amplitudes
//!   of free-interface modes (mass-normalized: `a` in kg^1/2 m, `Phi` in kg^-1/2), or for
//!   a Craig-Bampton body the w [m], theta_x, theta_y [rad] of the other attachment nodes followed by
//!   the fixed-interface mode amplitudes. `a = 0` is the undeformed body.
//! - Speeds `[v (world, of the frame origin), omega (body frame), a_dot]`, mass matrix `M(a)`,
//!   quadratic-velocity vector and gravity exactly as in [`crate::flex::invariants`].
//! - **Linear-modes limit**: deformations are a linear superposition of small-deflection modes of
//!   the unloaded body: no geometric (stress) stiffening, no foreshortening, small node rotations
//!   (see the module doc of [`crate::flex`]). Keep spin rates well below the first frequency.
//!
//! Frames on a modal body either ride on the reference frame (a [`crate::model::Frame`] without a
//! node) or on an attachment **node** ([`crate::model::Frame::at_node`]): origin
//! `rho_k + Phi_k a + d + theta_k x d`, axes `e + theta_k x e` with the node's small rotation
//! `theta_k = Psi_k a` (linear in `a`, consistent with the linear-modes limit). Joints use such
//! frames directly (their Jacobian rows get `6 + n` entries for the body); force elements given a
//! node frame act on a *node body* ([`crate::model::ModelBuilder::node_body`]), a rigid frame
//! riding on the node whose forces are carried over to the modal body (see `dae::node_body`).

use crate::flex::ModalBodyData;
use crate::math::{Mat3, Quat, Vec3};
use std::sync::Arc;

/// Identifies a body of a model; [`BodyId::GROUND`] is the fixed world frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BodyId(pub(crate) usize);

impl BodyId {
    /// The inertial frame, which has no coordinates.
    pub const GROUND: BodyId = BodyId(usize::MAX);

    /// Whether this is the ground.
    pub fn is_ground(self) -> bool {
        self.0 == usize::MAX
    }

    /// Index into the model's body list (`None` for ground and node bodies).
    pub fn index(self) -> Option<usize> {
        (self.0 < NODE_BODY_LIMIT).then_some(self.0)
    }

    /// The id of node body `j` (see [`crate::model::ModelBuilder::node_body`]).
    pub(crate) fn node_body(j: usize) -> BodyId {
        BodyId(usize::MAX - 1 - j)
    }

    /// Index `j` of a node body in [`crate::model::Model::node_bodies`] (`None` otherwise).
    pub fn node_body_index(self) -> Option<usize> {
        (self.0 >= NODE_BODY_LIMIT && !self.is_ground()).then(|| usize::MAX - 1 - self.0)
    }
}

/// Ids at or above this are node bodies (counted down from `usize::MAX - 1`) or the ground.
const NODE_BODY_LIMIT: usize = usize::MAX / 2;

/// The physical kind of a body.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyKind {
    /// A rigid body: mass [kg] and inertia tensor about the centre of mass in the body frame [kg m^2].
    /// The body frame's origin is the centre of mass.
    Rigid { mass: f64, inertia: Mat3 },
    /// A point mass [kg] with translations only (rope nodes).
    Particle { mass: f64 },
    /// A modally reduced flexible body in a floating frame (see the module doc).
    Modal { data: Arc<ModalBodyData> },
}

impl BodyKind {
    /// Number of position coordinates.
    pub fn n_q(&self) -> usize {
        match self {
            BodyKind::Rigid { .. } => 7,
            BodyKind::Particle { .. } => 3,
            BodyKind::Modal { data } => 7 + data.n_modes(),
        }
    }

    /// Number of generalized speeds (and of tangent-space position increments).
    pub fn n_v(&self) -> usize {
        match self {
            BodyKind::Rigid { .. } => 6,
            BodyKind::Particle { .. } => 3,
            BodyKind::Modal { data } => 6 + data.n_modes(),
        }
    }

    /// Whether the body has rotational coordinates.
    pub fn has_rotation(&self) -> bool {
        matches!(self, BodyKind::Rigid { .. } | BodyKind::Modal { .. })
    }

    /// Number of modal coordinates (0 for rigid bodies and particles).
    pub fn n_modes(&self) -> usize {
        match self {
            BodyKind::Modal { data } => data.n_modes(),
            _ => 0,
        }
    }

    /// The modal data of a flexible body.
    pub fn modal(&self) -> Option<&Arc<ModalBodyData>> {
        match self {
            BodyKind::Modal { data } => Some(data),
            _ => None,
        }
    }

    /// Mass [kg].
    pub fn mass(&self) -> f64 {
        match self {
            BodyKind::Rigid { mass, .. } | BodyKind::Particle { mass } => *mass,
            BodyKind::Modal { data } => data.invariants().mass,
        }
    }
}

/// A body of an assembled model with its coordinate offsets.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Name used in messages and outputs.
    pub name: String,
    pub kind: BodyKind,
    /// Offset of the body's first position coordinate in `q`.
    pub q_offset: usize,
    /// Offset of the body's first generalized speed in `v`.
    pub v_offset: usize,
    /// Characteristic length [m] of the body's translations: the relative part of the position
    /// error weights is `rtol * length_scale` (translation-invariant); `None`: `rtol * |r|`, the
    /// distance from the world origin (see [`crate::model::Model::position_scale`]).
    pub length_scale: Option<f64>,
}

/// Initial pose and velocity of a body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyInit {
    /// Position of the centre of mass [m], world frame (of the reference-frame origin for a
    /// modal body).
    pub position: Vec3,
    /// Orientation of the body frame relative to the world (ignored for particles).
    pub orientation: Quat,
    /// Velocity of the centre of mass [m/s], world frame.
    pub velocity: Vec3,
    /// Angular velocity [rad/s], body frame (ignored for particles).
    pub omega: Vec3,
}

impl BodyInit {
    /// At rest at `position` with the identity orientation.
    pub fn at(position: Vec3) -> Self {
        BodyInit {
            position,
            orientation: Quat::identity(),
            velocity: Vec3::zeros(),
            omega: Vec3::zeros(),
        }
    }

    /// Sets the orientation.
    pub fn oriented(mut self, orientation: Quat) -> Self {
        self.orientation = orientation;
        self
    }

    /// Sets the linear velocity [m/s] (world) and angular velocity [rad/s] (body frame).
    pub fn moving(mut self, velocity: Vec3, omega: Vec3) -> Self {
        self.velocity = velocity;
        self.omega = omega;
        self
    }
}
