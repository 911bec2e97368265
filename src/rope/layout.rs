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
    /// Friction coefficient `mu` [-] of the node's Coulomb cone (along the edge and along the
    /// rope together, see [`super::friction`]).
    pub mu: f64,
    /// Friction coefficient [-] with which the rope slides through the node while it slides
    /// (the cone's share left by the load along the edge, at most `mu`).
    pub mu_rope: f64,
    /// Friction along the plate edge (the node is held on the edge line by a joint of the scene);
    /// `None`: no element along the edge.
    pub hold: Option<EdgeHold>,
}

/// The plate edge a contact node sits on and the initial state of its friction along the edge
/// (see [`super::edge_hold`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeHold {
    /// The block carrying the edge.
    pub block: BodyId,
    /// A point of the edge [m] and its unit direction, block frame.
    pub point: Vec3,
    pub dir: Vec3,
    /// Anchor coordinate along the edge [m] from `point`.
    pub u0: f64,
    /// Friction capacity along the edge [N].
    pub cap: f64,
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

/// A prescribed hook point. Its velocity changes linearly from `velocity` to `target_velocity`
/// over `ramp` [s] starting at `t0` [s] and stays there (a crane accelerating smoothly, so that a
/// new command does not hit the rope with a velocity jump); the position `position` [m] (world)
/// at `t0` integrates it. The winch pay-out [m] (lengthening the segment at the hook) changes the
/// same way from rate `payout_rate` to `target_payout_rate` [m/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HookInit {
    pub position: Vec3,
    pub velocity: Vec3,
    pub target_velocity: Vec3,
    pub t0: f64,
    pub payout: f64,
    pub payout_rate: f64,
    pub target_payout_rate: f64,
    pub ramp: f64,
}

impl HookInit {
    /// A hook at rest at `position`.
    pub fn at(position: Vec3) -> Self {
        HookInit {
            position,
            velocity: Vec3::zeros(),
            target_velocity: Vec3::zeros(),
            t0: 0.0,
            payout: 0.0,
            payout_rate: 0.0,
            target_payout_rate: 0.0,
            ramp: 0.0,
        }
    }
}

/// Value and rate at `tau` [s] of a quantity starting at `x0` with rate `r0`, its rate moving
/// linearly to `r1` over `ramp` [s].
#[inline]
pub fn ramped(x0: f64, r0: f64, r1: f64, ramp: f64, tau: f64) -> (f64, f64) {
    if tau < ramp {
        let f = tau / ramp;
        (
            x0 + r0 * tau + (r1 - r0) * tau * f * 0.5,
            r0 + (r1 - r0) * f,
        )
    } else {
        (x0 + 0.5 * (r0 + r1) * ramp + r1 * (tau - ramp), r1)
    }
}
