//! Geometry of the solar-array hinge latch: a spring-loaded pin on hinge half B that drops into a
//! radial groove of a cam disc on hinge half A, whose side walls then stop the hinge both ways.
//!
//! # Frame
//! Everything is expressed in the **latch frame L**, fixed to hinge half A:
//! - origin on the hinge axis, in the plane of the cam disc (the plane perpendicular to the axis);
//! - `z` along the hinge axis, oriented so that deployment (opening) is a positive rotation of B
//!   relative to A about `+z`;
//! - `x` along the groove's centreline, pointing from the axis out through the groove;
//! - `y = z x x`.
//!
//! The relative hinge angle `theta` [rad] is the rotation of B relative to A about `+z`, with
//! `theta = lock_angle` when the seated pin is centred in the groove. The pin centre then sits at
//! polar angle `phi = theta - lock_angle` in L.
//!
//! # Geometry
//! The cam is a disc of radius `R_c`. The groove is a rectangular notch of width `w_g` (between two
//! parallel side walls at `y = -w_g/2` and `y = +w_g/2`) and depth `d_g` (floor at
//! `x = R_c - d_g`). The pin is a cylinder of radius `r_p` with its axis parallel to `z`. As the
//! hinge deploys (`theta` increasing) the pin rides on the rim and arrives from `y < 0`: the wall at
//! `y = -w_g/2` is the **rear** wall (the pin passes over it, it later stops any back-rotation),
//! the wall at `y = +w_g/2` the **front** wall (it stops the deployment: the lock impact).
//!
//! # Pin drop: a modelling decision
//! The pin's radial position is not a state. Once the pin has dropped it is **seated** at the
//! radius `r_s = R_c - d_g + r_p` (touching the floor at `theta = lock_angle`) and stays seated for
//! good: the latch is engaged. It drops at the **engagement angle**, the first angle at which a
//! seated pin fits behind the rear wall's edge: `r_s sin(phi_e) = -(w_g/2 - r_p)`. So engagement
//! creates no penetration, and the pin can then rebound between the two walls (if `w_g > 2 r_p`).
//! Reason: the paper's quantities (lock impact force, post-lock vibration) come from the wall
//! contacts alone; a radial pin coordinate would add a light, stiffly sprung degree of freedom
//! and a second contact (pin on rim and edge) that only shift the drop by a tiny angle, while the
//! real drop (pin spring much faster than the panel) ends exactly where this model places it.
//! Consequences the caller must honour: engagement is state it keeps (`engaged = engaged ||
//! latch.engages(theta)` on accepted steps, best with the event `theta = engagement_angle`
//! located); the pin is assumed to approach from `theta < engagement_angle`. Before engagement
//! the pin rides on the rim, whose normal force is radial and exerts no torque about the axis.
//!
//! # Contact query
//! Each wall is a [`Cuboid`] of cam material (from the axis to the rim, and `R_c` thick beyond the
//! wall face); the pin's cross-section is a [`Ball`] of radius `r_p` centred in the cam plane,
//! which has exactly the cylinder's in-plane penetration into a wall extruded along `z`. parry3d's
//! ball-versus-convex query projects the ball centre onto the box, which is exact. The design
//! requires `d_g >= r_p`, so the seated pin centre is below the rim and only the flat wall faces
//! can be touched: the normals are `-y` (front) and `+y` (rear), and the results hold while the
//! penetration stays below `r_p`.

use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::{Contact, contact};
use parry3d_f64::shape::{Ball, Cuboid};

use super::error::{ContactError, positive_parameter};
use crate::math::Vec3;

/// Dimensions of the latch [m] and the lock angle [rad]; see the module documentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatchParams {
    /// Cam disc radius `R_c` [m].
    pub cam_radius: f64,
    /// Groove width `w_g` [m], the distance between the two side walls.
    pub groove_width: f64,
    /// Groove depth `d_g` [m], from the rim to the floor.
    pub groove_depth: f64,
    /// Pin radius `r_p` [m].
    pub pin_radius: f64,
    /// Relative hinge angle `theta_L` [rad] at which the seated pin is centred in the groove.
    pub lock_angle: f64,
}

/// One side wall of the groove.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Wall {
    /// Wall at `y = +w_g/2`: stops the deployment (the lock impact).
    Front,
    /// Wall at `y = -w_g/2`: stops back-rotation towards the stowed position.
    Rear,
}

/// The pin against one groove wall, in the latch frame L.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallContact {
    /// Signed penetration `delta` [m] of the pin into the wall: `> 0` overlapping, `< 0` a gap
    /// (continuous through contact onset, so usable as an event function). Feed it to
    /// [`super::ContactLaw::evaluate`], which gives zero force for `delta <= 0`.
    pub penetration: f64,
    /// Unit contact normal in L: the direction of the wall's force on the pin (on half B); the force
    /// on half A is opposite.
    pub normal: Vec3,
    /// Contact point [m] in L, on the pin's surface (the deepest point of the pin in the wall).
    pub point: Vec3,
    /// Moment arm [m] about the hinge axis: the torque on half B about `+z` is
    /// `F * moment_arm` for a normal force `F >= 0`; half A receives the opposite torque.
    /// Equal to `-d_penetration_d_theta`, as virtual work requires.
    pub moment_arm: f64,
    /// `d delta / d theta` [m/rad]; the penetration rate is `delta_dot = d_penetration_d_theta *
    /// theta_dot`.
    pub d_penetration_d_theta: f64,
    /// `d^2 delta / d theta^2` [m/rad^2] (flat wall face), for the Jacobian of `delta_dot`.
    pub d2_penetration_d_theta2: f64,
}

/// Both wall contacts of an engaged latch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatchContact {
    /// The pin against the front wall (stops deployment).
    pub front: WallContact,
    /// The pin against the rear wall (stops back-rotation).
    pub rear: WallContact,
}

impl LatchContact {
    /// The contact with the given wall.
    pub fn wall(&self, wall: Wall) -> &WallContact {
        match wall {
            Wall::Front => &self.front,
            Wall::Rear => &self.rear,
        }
    }
}

/// A validated latch geometry with its parry3d shapes; queries are pure functions of `theta`.
#[derive(Debug, Clone)]
pub struct LatchGeometry {
    params: LatchParams,
    seat_radius: f64,
    engagement_offset: f64,
    pin: Ball,
    wall: Cuboid,
    front_pose: Pose,
    rear_pose: Pose,
}

impl LatchGeometry {
    /// Validates the dimensions and builds the shapes. Refused: any length not finite and `> 0`,
    /// a non-finite lock angle, a pin wider than the groove (`w_g < 2 r_p`), a groove shallower
    /// than the pin radius (`d_g < r_p`: the walls could cam the pin out), a groove at least as
    /// deep as the cam (`d_g >= R_c`), or a groove not narrow compared with its floor radius
    /// (`w_g >= 2 (R_c - d_g)`).
    pub fn new(p: LatchParams) -> Result<Self, ContactError> {
        let r_c = positive_parameter("cam radius R_c", p.cam_radius, "finite and > 0 m")?;
        let w_g = positive_parameter("groove width w_g", p.groove_width, "finite and > 0 m")?;
        let d_g = positive_parameter("groove depth d_g", p.groove_depth, "finite and > 0 m")?;
        let r_p = positive_parameter("pin radius r_p", p.pin_radius, "finite and > 0 m")?;
        if !p.lock_angle.is_finite() {
            return Err(ContactError::InvalidParameter {
                name: "lock angle theta_L",
                value: p.lock_angle,
                expected: "finite rad",
            });
        }
        let invalid = |name, value, expected| {
            Err(ContactError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if w_g < 2.0 * r_p {
            return invalid(
                "groove width w_g",
                w_g,
                ">= 2 r_p (the pin must fit into the groove)",
            );
        }
        if d_g < r_p {
            return invalid(
                "groove depth d_g",
                d_g,
                ">= r_p (a shallower groove lets the walls cam the pin out)",
            );
        }
        if d_g >= r_c {
            return invalid("groove depth d_g", d_g, "< cam radius R_c");
        }
        if 0.5 * w_g >= r_c - d_g {
            return invalid(
                "groove width w_g",
                w_g,
                "< 2 (R_c - d_g) (a groove narrow compared with its floor radius)",
            );
        }
        let seat_radius = r_c - d_g + r_p;
        // 0 <= w_g/2 - r_p < w_g/2 < R_c - d_g < seat_radius: the asin argument is in [0, 1).
        let engagement_offset = -((0.5 * w_g - r_p) / seat_radius).asin();
        // A wall block spans x in [0, R_c] and is R_c thick in y beyond its face; z is irrelevant
        // (the pin's section is centred at z = 0) but must contain the ball: use R_c.
        let half = Vector::new(0.5 * r_c, 0.5 * r_c, r_c);
        let y_centre = 0.5 * w_g + 0.5 * r_c;
        Ok(Self {
            params: p,
            seat_radius,
            engagement_offset,
            pin: Ball::new(r_p),
            wall: Cuboid::new(half),
            front_pose: Pose::translation(0.5 * r_c, y_centre, 0.0),
            rear_pose: Pose::translation(0.5 * r_c, -y_centre, 0.0),
        })
    }

    /// The validated dimensions.
    pub fn params(&self) -> &LatchParams {
        &self.params
    }

    /// Radius `r_s = R_c - d_g + r_p` [m] of the seated pin centre about the hinge axis.
    pub fn seat_radius(&self) -> f64 {
        self.seat_radius
    }

    /// Engagement angle `theta_e` [rad]: the pin drops into the groove when `theta >= theta_e`.
    pub fn engagement_angle(&self) -> f64 {
        self.params.lock_angle + self.engagement_offset
    }

    /// Whether the pin drops into the groove at `theta` [rad] (`theta >= theta_e`; false for NaN).
    pub fn engages(&self, theta: f64) -> bool {
        theta >= self.engagement_angle()
    }

    /// Seated pin centre [m] in the latch frame L at hinge angle `theta` [rad].
    pub fn pin_centre(&self, theta: f64) -> Vec3 {
        let phi = theta - self.params.lock_angle;
        Vec3::new(
            self.seat_radius * phi.cos(),
            self.seat_radius * phi.sin(),
            0.0,
        )
    }

    /// Wall contacts at hinge angle `theta` [rad] given the caller's latch state `engaged`.
    ///
    /// `Ok(None)` when not engaged (the pin rides on the rim: no wall contact, no torque). Refuses a
    /// non-finite `theta`.
    pub fn query(&self, theta: f64, engaged: bool) -> Result<Option<LatchContact>, ContactError> {
        if !theta.is_finite() {
            return Err(ContactError::InvalidArgument {
                name: "hinge angle theta",
                value: theta,
                expected: "finite rad",
            });
        }
        if !engaged {
            return Ok(None);
        }
        let c = self.pin_centre(theta);
        Ok(Some(LatchContact {
            front: self.wall_contact(c, Wall::Front)?,
            rear: self.wall_contact(c, Wall::Rear)?,
        }))
    }

    /// Contact of the pin (centre `c` in L) with `wall`: the closed form where the flat face is
    /// nearest, parry3d's query elsewhere.
    fn wall_contact(&self, c: Vec3, wall: Wall) -> Result<WallContact, ContactError> {
        match self.flat_face_contact(c, wall) {
            Some(w) => Ok(w),
            None => self.queried_contact(c, wall),
        }
    }

    /// The contact with a wall's flat face in closed form, where it is the answer: the pin
    /// centre `c` (in L) between the axis and the rim (`0 <= x <= R_c`) and on the groove's side
    /// of the face (`|y| < w_g/2` towards that wall), so the nearest point of the wall block is
    /// the centre's projection on the face. Then the penetration is `c.y + r_p - w_g/2` (front)
    /// or `-c.y + r_p - w_g/2` (rear), the normal into the wall `+y` or `-y`: what parry3d's
    /// ball-cuboid query computes there, without its dispatch (the latch's hot path; the unit
    /// test compares the two). `None` elsewhere (a corner or a centre inside the block: the
    /// query decides).
    fn flat_face_contact(&self, c: Vec3, wall: Wall) -> Option<WallContact> {
        let (half_width, r_p) = (0.5 * self.params.groove_width, self.params.pin_radius);
        let side = match wall {
            Wall::Front => 1.0,
            Wall::Rear => -1.0,
        };
        let towards = side * c.y;
        if !(c.x >= 0.0 && c.x <= self.params.cam_radius && towards < half_width) {
            return None;
        }
        let into_wall = Vec3::new(0.0, side, 0.0);
        // d c / d theta = z x c, so d delta / d theta = into_wall . (-c.y, c.x, 0)
        let d_delta = side * c.x;
        Some(WallContact {
            penetration: towards + r_p - half_width,
            normal: -into_wall,
            point: c + r_p * into_wall,
            moment_arm: -d_delta,
            d_penetration_d_theta: d_delta,
            d2_penetration_d_theta2: -side * c.y,
        })
    }

    /// Contact of the pin (centre `c` in L) with the block of `wall`, by parry3d's query.
    fn queried_contact(&self, c: Vec3, wall: Wall) -> Result<WallContact, ContactError> {
        let wall_pose = match wall {
            Wall::Front => &self.front_pose,
            Wall::Rear => &self.rear_pose,
        };
        let pin_pose = Pose::translation(c.x, c.y, 0.0);
        // Report gaps too: any distance inside the cam is below this prediction distance.
        let prediction = 4.0 * self.params.cam_radius;
        let found: Option<Contact> =
            contact(&pin_pose, &self.pin, wall_pose, &self.wall, prediction).map_err(|_| {
                ContactError::Geometry("parry3d-f64 does not support ball-cuboid contact".into())
            })?;
        let k = found.ok_or_else(|| {
            ContactError::Geometry(format!(
                "no pin-wall contact within {prediction} m for pin centre ({}, {}) m",
                c.x, c.y
            ))
        })?;
        // parry's normal1 points from the pin into the wall; the penetration grows along it.
        let into_wall = Vec3::new(k.normal1.x, k.normal1.y, k.normal1.z);
        // Pin-centre velocity per unit theta: z x c.
        let dc = Vec3::new(-c.y, c.x, 0.0);
        let d_delta = into_wall.dot(&dc);
        Ok(WallContact {
            penetration: -k.dist,
            normal: -into_wall,
            point: Vec3::new(k.point1.x, k.point1.y, k.point1.z),
            moment_arm: -d_delta,
            d_penetration_d_theta: d_delta,
            // d^2 c / d theta^2 = -c (in-plane), and the face normal is constant.
            d2_penetration_d_theta2: -into_wall.dot(&c),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form of the flat faces against parry3d's ball-cuboid query over the whole
    /// engaged range (the pin from behind the rear wall's edge to beyond the front wall by its
    /// radius), and it steps aside where the query must decide.
    #[test]
    fn flat_face_contact_is_parrys_answer() {
        let g = LatchGeometry::new(LatchParams {
            cam_radius: 0.03,
            groove_width: 0.012,
            groove_depth: 0.008,
            pin_radius: 0.005,
            lock_angle: 1.3,
        })
        .unwrap();
        let tol = 1e-16;
        let mut compared = 0;
        for k in 0..=2000 {
            let theta = g.engagement_angle() - 0.05 + 0.2 * k as f64 / 2000.0;
            let c = g.pin_centre(theta);
            for wall in [Wall::Front, Wall::Rear] {
                let Some(fast) = g.flat_face_contact(c, wall) else {
                    continue;
                };
                let slow = g.queried_contact(c, wall).unwrap();
                compared += 1;
                let close = |a: f64, b: f64| (a - b).abs() <= tol;
                assert!(
                    close(fast.penetration, slow.penetration),
                    "{fast:?} {slow:?}"
                );
                assert!(
                    (fast.normal - slow.normal).norm() <= 1e-15,
                    "{fast:?} {slow:?}"
                );
                assert!((fast.point - slow.point).norm() <= tol, "{fast:?} {slow:?}");
                assert!(close(fast.moment_arm, slow.moment_arm), "{fast:?} {slow:?}");
                assert!(close(
                    fast.d_penetration_d_theta,
                    slow.d_penetration_d_theta
                ));
                assert!(close(
                    fast.d2_penetration_d_theta2,
                    slow.d2_penetration_d_theta2
                ));
            }
        }
        // both walls at every angle but where the pin centre has crossed a wall's face
        assert!(compared > 3000, "{compared}");
        // a centre past the front face (penetration beyond the pin radius) is left to the query
        let past = Vec3::new(0.02, 0.0061, 0.0);
        assert!(g.flat_face_contact(past, Wall::Front).is_none());
        assert!(g.flat_face_contact(past, Wall::Rear).is_some());
    }
}
