//! Body kinds and their coordinate layout.
//!
//! Every body owns a contiguous range of position coordinates `q` and of generalized speeds `v`:
//!
//! | kind      | q (per body)                                   | v (per body)                               |
//! |-----------|------------------------------------------------|--------------------------------------------|
//! | rigid     | `r` [m] world, unit quaternion (w, x, y, z)    | `v` [m/s] world, `omega` [rad/s] body frame |
//! | particle  | `r` [m] world                                  | `v` [m/s] world                             |
//!
//! Position increments live in the tangent space, of the same length as `v`: a translation
//! increment in the world frame and a rotation vector in the body frame (`R_new = R exp(dtheta~)`).
//! Integrators only ever see flat vectors and the retraction of [`crate::model::Model`], so further
//! kinds (a modally reduced flexible body with speeds `[v, omega, a_dot]`) slot in here without
//! touching them.

use crate::math::{Mat3, Quat, Vec3};

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

    /// Index into the model's body list (`None` for ground).
    pub fn index(self) -> Option<usize> {
        (!self.is_ground()).then_some(self.0)
    }
}

/// The physical kind of a body.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyKind {
    /// A rigid body: mass [kg] and inertia tensor about the centre of mass in the body frame [kg m^2].
    /// The body frame's origin is the centre of mass.
    Rigid { mass: f64, inertia: Mat3 },
    /// A point mass [kg] with translations only (rope nodes).
    Particle { mass: f64 },
}

impl BodyKind {
    /// Number of position coordinates.
    pub fn n_q(&self) -> usize {
        match self {
            BodyKind::Rigid { .. } => 7,
            BodyKind::Particle { .. } => 3,
        }
    }

    /// Number of generalized speeds (and of tangent-space position increments).
    pub fn n_v(&self) -> usize {
        match self {
            BodyKind::Rigid { .. } => 6,
            BodyKind::Particle { .. } => 3,
        }
    }

    /// Whether the body has rotational coordinates.
    pub fn has_rotation(&self) -> bool {
        matches!(self, BodyKind::Rigid { .. })
    }

    /// Mass [kg].
    pub fn mass(&self) -> f64 {
        match self {
            BodyKind::Rigid { mass, .. } | BodyKind::Particle { mass } => *mass,
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
}

/// Initial pose and velocity of a body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyInit {
    /// Position of the centre of mass [m], world frame.
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
