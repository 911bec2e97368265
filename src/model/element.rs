//! Descriptions of joints and force elements (immutable data; evaluation lives in `effect`).

use super::body::BodyId;
use super::profile::Profile;
use crate::math::{Mat3, Vec3};

/// A frame attached to a body: origin [m] and axes (columns x, y, z) in the body frame.
/// For the ground the frame is given in the world frame.
///
/// On a modal (flexible) body a frame may ride on node `k` ([`Frame::on_node`]): its origin is
/// then `rho_k + Phi_k a + d + theta_k x d` and each axis `e + theta_k x e` (body frame), with
/// `d = origin` the offset from the node, `e` the given axes and `theta_k = Psi_k a` the node's
/// small rotation (see [`crate::model::body`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub body: BodyId,
    /// Origin in the body frame [m] (the offset from the node for a node frame).
    pub origin: Vec3,
    /// Orthonormal axes in the body frame (columns).
    pub axes: Mat3,
    /// Node of a modal body the frame rides on (`None`: rigidly on the body frame).
    pub node: Option<usize>,
}

impl Frame {
    /// A frame at `origin` with axes parallel to the body frame.
    pub fn new(body: BodyId, origin: Vec3) -> Self {
        Frame {
            body,
            origin,
            axes: Mat3::identity(),
            node: None,
        }
    }

    /// A frame at node `node` of modal body `body`, axes parallel to the body frame.
    pub fn at_node(body: BodyId, node: usize) -> Self {
        Frame::new(body, Vec3::zeros()).on_node(node)
    }

    /// Makes the frame ride on node `node` of its (modal) body; `origin` becomes the offset from
    /// the node [m], body frame.
    pub fn on_node(mut self, node: usize) -> Self {
        self.node = Some(node);
        self
    }

    /// A frame at `origin` whose z axis is `axis` (normalized here); x and y complete a
    /// right-handed set (x is the body-frame direction most perpendicular to `axis`).
    pub fn with_z(body: BodyId, origin: Vec3, axis: Vec3) -> Self {
        let z = axis.normalize();
        let seed = if z.x.abs() < 0.9 {
            Vec3::x()
        } else {
            Vec3::y()
        };
        let x = (seed - z * z.dot(&seed)).normalize();
        let y = z.cross(&x);
        Frame {
            body,
            origin,
            axes: Mat3::from_columns(&[x, y, z]),
            node: None,
        }
    }

    /// Sets the axes explicitly (columns x, y, z in the body frame).
    pub fn with_axes(mut self, x: Vec3, y: Vec3, z: Vec3) -> Self {
        self.axes = Mat3::from_columns(&[x, y, z]);
        self
    }
}

/// Kinds of holonomic joints between frame `i` (on body i) and frame `j` (on body j).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    /// Origins coincide, z axes aligned: 5 constraints, rotation about z free.
    Revolute,
    /// Origins coincide: 3 constraints.
    Spherical,
    /// Origin of frame j on the z axis of frame i: 2 constraints (translation along z and every
    /// rotation free; frame j may be on a particle), e.g. a rope's contact node on a plate edge.
    PointOnLine,
    /// Origins coincide, axes aligned: 6 constraints.
    Fixed,
    /// Axes aligned, origin of j on the z axis of i: 5 constraints, translation along z free.
    Prismatic,
    /// Rotation angle of frame j about the z axis of frame i prescribed [rad] (one constraint;
    /// combine with a revolute joint on the same frames).
    AngleDrive(Profile),
    /// Displacement of origin j along the z axis of frame i prescribed [m] (one constraint;
    /// combine with a prismatic joint).
    TranslationDrive(Profile),
}

impl JointKind {
    /// Number of scalar constraint equations.
    pub fn n_rows(&self) -> usize {
        match self {
            JointKind::Revolute | JointKind::Prismatic => 5,
            JointKind::Spherical => 3,
            JointKind::PointOnLine => 2,
            JointKind::Fixed => 6,
            JointKind::AngleDrive(_) | JointKind::TranslationDrive(_) => 1,
        }
    }

    /// Whether the joint needs rotational coordinates on both sides.
    pub fn needs_rotation(&self) -> bool {
        !matches!(self, JointKind::Spherical | JointKind::PointOnLine)
    }

    /// Whether frame i's body needs rotational coordinates.
    pub fn needs_rotation_i(&self) -> bool {
        self.needs_rotation() || matches!(self, JointKind::PointOnLine)
    }
}

/// A joint of the model.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    pub kind: JointKind,
    pub frame_i: Frame,
    pub frame_j: Frame,
}

/// A linear translational spring-damper between two body points (acts along the line between them).
#[derive(Debug, Clone, PartialEq)]
pub struct SpringDamper {
    pub name: String,
    /// Attachment points (frame origins; axes unused).
    pub a: Frame,
    pub b: Frame,
    /// Stiffness [N/m], damping [N s/m], free length [m].
    pub stiffness: f64,
    pub damping: f64,
    pub free_length: f64,
}

/// A rotational spring-damper about the common z axis of two frames (used on revolute joints):
/// torque on j about z_i: `T = -k (theta - theta_free) - c theta_dot`, theta the angle of x_j
/// relative to x_i about z_i.
#[derive(Debug, Clone, PartialEq)]
pub struct TorsionSpring {
    pub name: String,
    pub frame_i: Frame,
    pub frame_j: Frame,
    /// Stiffness [N m/rad], damping [N m s/rad].
    pub stiffness: f64,
    pub damping: f64,
    /// Angle at which the spring torque vanishes [rad]; a preloaded deployment spring has it beyond
    /// the deployed angle.
    pub free_angle: f64,
    /// Angle offset [rad]: the measured angle is `angle_offset + atan2(...)`, chosen so that the
    /// working range stays within (-pi, pi) of the raw measurement.
    pub angle_offset: f64,
}

/// A force [N] (world frame) applied at a body point, and a torque [N m] (world frame) applied to
/// the body, each `direction * profile(t)`.
#[derive(Debug, Clone, PartialEq)]
pub struct AppliedLoad {
    pub name: String,
    pub at: Frame,
    pub force_direction: Vec3,
    pub force: Profile,
    pub torque_direction: Vec3,
    pub torque: Profile,
}

/// A torque about the common z axis of two frames, acting on j (and its reaction on i):
/// a motor between two bodies, e.g. a hinge actuator driven by an input.
#[derive(Debug, Clone, PartialEq)]
pub struct JointTorque {
    pub name: String,
    pub frame_i: Frame,
    pub frame_j: Frame,
    pub torque: Profile,
}
