//! Body kinematics evaluated from the flat coordinate vectors.

use super::{BodyId, Model};
use crate::math::{Mat3, Quat, Vec3, skew};
use nalgebra::Quaternion;

/// Reads the unit quaternion stored (w, x, y, z) at `q[at..at + 4]`.
#[inline]
pub fn quat_at(q: &[f64], at: usize) -> Quat {
    Quat::new_normalize(Quaternion::new(q[at], q[at + 1], q[at + 2], q[at + 3]))
}

/// Writes a unit quaternion as (w, x, y, z) at `q[at..at + 4]`.
#[inline]
pub fn put_quat(q: &mut [f64], at: usize, r: &Quat) {
    q[at] = r.w;
    q[at + 1] = r.i;
    q[at + 2] = r.j;
    q[at + 3] = r.k;
}

/// Pose and velocity of one body at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyKin {
    /// Centre of mass [m], world frame.
    pub r: Vec3,
    /// Rotation matrix body -> world.
    pub rot: Mat3,
    /// Velocity of the centre of mass [m/s], world frame.
    pub v: Vec3,
    /// Angular velocity [rad/s], body frame.
    pub omega: Vec3,
    /// Offset of the body's speeds in `v` (`usize::MAX` for ground).
    pub col: usize,
    /// Whether the body has rotational speeds.
    pub rotational: bool,
}

impl BodyKin {
    /// The ground: at the origin, at rest, without coordinates.
    pub const GROUND: BodyKin = BodyKin {
        r: Vec3::new(0.0, 0.0, 0.0),
        rot: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        v: Vec3::new(0.0, 0.0, 0.0),
        omega: Vec3::new(0.0, 0.0, 0.0),
        col: usize::MAX,
        rotational: false,
    };

    /// Whether the body has coordinates (is not the ground).
    #[inline]
    pub fn is_free(&self) -> bool {
        self.col != usize::MAX
    }

    /// World position of the body-frame point `s` [m].
    #[inline]
    pub fn point(&self, s: &Vec3) -> Vec3 {
        self.r + self.rot * s
    }

    /// World velocity of the body-frame point `s` [m/s].
    #[inline]
    pub fn point_velocity(&self, s: &Vec3) -> Vec3 {
        self.v + self.rot * self.omega.cross(s)
    }

    /// `-R s~`: the 3x3 block mapping the body-frame rotation increment to the world displacement
    /// of point `s` (the translation block is the identity).
    #[inline]
    pub fn point_rot_jacobian(&self, s: &Vec3) -> Mat3 {
        -self.rot * skew(s)
    }

    /// Velocity-product acceleration of point `s`: `R (omega x (omega x s))` [m/s^2].
    #[inline]
    pub fn point_centripetal(&self, s: &Vec3) -> Vec3 {
        self.rot * self.omega.cross(&self.omega.cross(s))
    }
}

/// Evaluates the kinematics of every body from `q` and `v` into `out` (length = number of bodies).
pub fn evaluate(model: &Model, q: &[f64], v: &[f64], out: &mut Vec<BodyKin>) {
    out.clear();
    for b in &model.bodies {
        let (qo, vo) = (b.q_offset, b.v_offset);
        let r = Vec3::new(q[qo], q[qo + 1], q[qo + 2]);
        let vel = Vec3::new(v[vo], v[vo + 1], v[vo + 2]);
        let (rot, omega, rotational) = if b.kind.has_rotation() {
            let quat = quat_at(q, qo + 3);
            (
                quat.to_rotation_matrix().into_inner(),
                Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]),
                true,
            )
        } else {
            (Mat3::identity(), Vec3::zeros(), false)
        };
        out.push(BodyKin {
            r,
            rot,
            v: vel,
            omega,
            col: vo,
            rotational,
        });
    }
}

/// The kinematics of `id` from an evaluated list (ground for [`BodyId::GROUND`]). The list the
/// [`crate::dae::System`] keeps holds the bodies first, then the node bodies in reverse order
/// (node body `j` last but `j`), so that node bodies are found without knowing the body count.
#[inline]
pub fn kin_of(kins: &[BodyKin], id: BodyId) -> &BodyKin {
    match (id.index(), id.node_body_index()) {
        (Some(i), _) => &kins[i],
        (None, Some(j)) => kins
            .len()
            .checked_sub(1 + j)
            .map_or(&BodyKin::GROUND, |i| &kins[i]),
        _ => &BodyKin::GROUND,
    }
}
