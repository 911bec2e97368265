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

/// How a hook's motion is commanded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HookMode {
    /// Toward a target velocity, reached linearly over the ramp time ([`ramped`]).
    #[default]
    Velocity,
    /// Toward a target position, reached at rest after the ramp time along the cubic that keeps
    /// position and velocity continuous ([`hermite`]).
    Position,
}

impl HookMode {
    /// Code in the effect memory.
    pub fn code(self) -> f64 {
        match self {
            HookMode::Velocity => 0.0,
            HookMode::Position => 1.0,
        }
    }

    /// The mode of a memory code (anything but 1 is velocity).
    pub fn from_code(c: f64) -> Self {
        if c == 1.0 {
            HookMode::Position
        } else {
            HookMode::Velocity
        }
    }
}

/// A prescribed hook point, from position `position` [m] and velocity `velocity` [m/s] (world)
/// at `t0` [s]. In [`HookMode::Velocity`] its velocity changes linearly to `target_velocity` over
/// `ramp` [s] and stays there (a crane accelerating smoothly, so that a new command does not hit
/// the rope with a velocity jump); the position integrates it. In [`HookMode::Position`] it moves
/// to `target_position` [m] along the cubic [`hermite`], arriving at rest after `ramp` [s], and
/// stays there. The winch pay-out [m] (lengthening the segment at the hook) changes like a
/// velocity in both modes, from rate `payout_rate` to `target_payout_rate` [m/s].
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
    pub mode: HookMode,
    pub target_position: Vec3,
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
            mode: HookMode::Velocity,
            target_position: position,
        }
    }
}

/// Value and rate at `tau` [s] of a move from `x0` with rate `r0` to `x1` at rest, over `duration`
/// [s]: the cubic Hermite `x0 + (x1 - x0) (3 s^2 - 2 s^3) + r0 duration (s - 2 s^2 + s^3)`,
/// `s = tau / duration`, which keeps value and rate continuous at both ends (its acceleration
/// steps there, as a velocity ramp's does); `x1` at rest from `tau >= duration` on (and for a
/// `duration` of 0).
#[inline]
pub fn hermite(x0: f64, r0: f64, x1: f64, duration: f64, tau: f64) -> (f64, f64) {
    if tau < duration {
        let s = tau / duration;
        let d = x1 - x0;
        (
            x0 + d * s * s * (3.0 - 2.0 * s) + r0 * duration * s * (1.0 - s) * (1.0 - s),
            6.0 * d * s * (1.0 - s) / duration + r0 * (1.0 - s) * (1.0 - 3.0 * s),
        )
    } else {
        (x1, 0.0)
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
