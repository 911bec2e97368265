//! The description from which a [`super::RopeEffect`] is built: ropes as chains of points with
//! material coordinates, prescribed hook points, and the contact nodes' initial memory.

use super::props::RopeProps;
use crate::math::Vec3;
use crate::model::BodyId;

/// Where a rope point is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PointAt {
    /// A point fixed to a body at offset `local` [m] in the body frame (a particle node has
    /// `local = 0`; a lug is a point of the block).
    Body { body: BodyId, local: Vec3 },
    /// Prescribed hook point number `k` (see [`HookInit`]).
    Hook(usize),
}

/// Stick/slip state of a contact node along the rope, as stored in the effect's memory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SlipMode {
    /// The rope does not slide through the node: both adjacent rest lengths are frozen.
    Stick,
    /// The rope slides through the node towards the higher point index (that side is the taut one).
    SlipForward,
    /// The rope slides towards the lower point index.
    SlipBackward,
}

impl SlipMode {
    /// Memory encoding: 0, +1, -1.
    pub fn code(self) -> f64 {
        match self {
            SlipMode::Stick => 0.0,
            SlipMode::SlipForward => 1.0,
            SlipMode::SlipBackward => -1.0,
        }
    }

    /// Decodes the memory value (anything near 0 is stick).
    pub fn from_code(c: f64) -> Self {
        if c > 0.5 {
            SlipMode::SlipForward
        } else if c < -0.5 {
            SlipMode::SlipBackward
        } else {
            SlipMode::Stick
        }
    }
}

/// Initial memory of a contact node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactInit {
    /// Stick or slip.
    pub mode: SlipMode,
    /// Friction coefficient available along the rope [-] (the Coulomb cone's share left by the
    /// load along the edge).
    pub mu_rope: f64,
    /// Point of the plate edge holding the node [m], in the frame of the body it is tied to (read
    /// by a [`crate::model::JointKind::SphericalAt`] joint, so the node can slide along the edge
    /// without rebuilding the model).
    pub anchor: Vec3,
}

/// One point of a rope.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayoutPoint {
    pub at: PointAt,
    /// Material coordinate [m]: unstretched arc length from the rope's origin. Segment rest
    /// lengths are differences of consecutive coordinates.
    pub sigma: f64,
    /// `Some` for a contact node (then `at` must be a particle with `local = 0`).
    pub contact: Option<ContactInit>,
}

/// One rope: properties and its points in order.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutRope {
    pub props: RopeProps,
    /// Nominal segment length [m] (bending stiffness and drag shares use it).
    pub nominal_segment: f64,
    pub points: Vec<LayoutPoint>,
}

/// A prescribed hook point, moving linearly in time between updates by the scene:
/// `x(t) = position + velocity (t - t0)` [m, world], and a winch pay-out
/// `s(t) = payout + payout_rate (t - t0)` [m] that lengthens the segment at the hook.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HookInit {
    pub position: Vec3,
    pub velocity: Vec3,
    pub t0: f64,
    pub payout: f64,
    pub payout_rate: f64,
}

impl HookInit {
    /// A hook at rest at `position`.
    pub fn at(position: Vec3) -> Self {
        HookInit {
            position,
            velocity: Vec3::zeros(),
            t0: 0.0,
            payout: 0.0,
            payout_rate: 0.0,
        }
    }
}
