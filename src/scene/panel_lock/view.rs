//! What a PanelLock scene looks like: satellite, yoke, panels and hinge bodies as shapes
//! ([`crate::scene::view`]), world frame, lengths in metres.
//!
//! - **Yoke and panels**: boxes of `length x thickness x width` along the rigid panel frame's
//!   x (length), y (normal) and z (width = hinge axis), centred on the body. A flexible panel is
//!   drawn as its undeformed plate (the modal reference frame; the modal deflection is not
//!   drawn), in its plate frame (x length, y width, z normal) with the origin at a corner of the
//!   inboard edge.
//! - **Hinge bodies**: cylinders along the hinge axis, `panel_width` long, of the radius
//!   `sqrt(2) * hinge_gyration_radius` (a solid cylinder with that radius of gyration about its
//!   axis), centred on the hinge point.
//! - **Satellite**: the model has no satellite geometry, only its mass, inertia and centre of
//!   mass `satellite_cg` relative to the root attach point: drawn as a 2 m cube centred on the
//!   centre of mass (with the default `satellite_cg` (-1, 0, 0) m its +x face holds the root
//!   hinge). A fixed satellite is the ground: drawn at `satellite_cg`, not turning.

use super::PanelLock;
use crate::math::Vec3;
use crate::model::kinematics::BodyKin;
use crate::scene::view::{Geometry, Pose, Role, Shape, Snapshot};

/// Edge of the cube drawn for the satellite [m] (centred on its centre of mass, by default 1 m
/// behind the root hinge).
pub const SATELLITE_EDGE: f64 = 2.0;

impl PanelLock {
    /// The scene's shapes at the current state; `time_offset` [s] is added to the scene time
    /// (the importer's start time).
    pub fn snapshot(&mut self, time_offset: f64) -> Snapshot {
        let p = &self.params;
        let (st, sys) = (&self.sim.state, &mut self.sim.system);
        sys.update_kinematics(&st.q, &st.v);
        let kin = |id| *sys.kin(id);
        let mut shapes = Vec::with_capacity(2 * self.layout.plates.len() + 1);

        // satellite: the cube centred on its centre of mass (build.rs); ground: the attach
        // point is the world origin, the centre of mass at satellite_cg
        let sat: BodyKin = kin(self.layout.satellite);
        let centre_local = if p.free_satellite {
            Vec3::zeros()
        } else {
            Vec3::from(p.satellite_cg)
        };
        shapes.push(Shape {
            name: "satellite".into(),
            role: Role::Satellite,
            geometry: Geometry::Box {
                size: Vec3::repeat(SATELLITE_EDGE),
            },
            pose: Pose::from_matrix(sat.point(&centre_local), &sat.rot),
        });

        let hinge_radius = std::f64::consts::SQRT_2 * p.hinge_gyration_radius;
        for (k, (&plate, &len)) in self
            .layout
            .plates
            .iter()
            .zip(&self.layout.plate_lengths)
            .enumerate()
        {
            let hinge = kin(self.layout.hinges[k]);
            // the yoke is drawn as wide as the first panel
            let pv = p.panel(k.max(1));
            shapes.push(Shape {
                name: format!("hinge{k}"),
                role: Role::Hinge,
                geometry: Geometry::Cylinder {
                    radius: hinge_radius,
                    length: pv.width,
                },
                pose: Pose::from_matrix(hinge.r, &hinge.rot),
            });
            let b = kin(plate);
            let flexible = k > 0 && p.flexible_panels;
            let (size, centre) = if flexible {
                (
                    Vec3::new(len, pv.width, pv.thickness),
                    Vec3::new(0.5 * len, 0.5 * pv.width, 0.0),
                )
            } else {
                (Vec3::new(len, pv.thickness, pv.width), Vec3::zeros())
            };
            let (name, role) = if k == 0 {
                ("yoke".to_string(), Role::Yoke)
            } else {
                (format!("panel{k}"), Role::Panel)
            };
            shapes.push(Shape {
                name,
                role,
                geometry: Geometry::Box { size },
                pose: Pose::from_matrix(b.point(&centre), &b.rot),
            });
        }
        Snapshot {
            time: time_offset + st.t,
            shapes,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Mat3, Quat};
    use crate::scene::panel_lock::PanelLockParams;

    /// Rotation matrix of a yaw `phi` [rad] about the world z axis.
    fn yaw(phi: f64) -> Mat3 {
        *Quat::from_axis_angle(&Vec3::z_axis(), phi)
            .to_rotation_matrix()
            .matrix()
    }

    /// Yaw of a shape's x axis about world z [rad].
    fn yaw_of(s: &Shape) -> f64 {
        let x = s.pose.orientation * Vec3::x();
        x.y.atan2(x.x)
    }

    fn wrap(a: f64) -> f64 {
        (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    }

    /// Box corners [m], world frame.
    fn corners(s: &Shape) -> Vec<Vec3> {
        let Geometry::Box { size } = s.geometry else {
            panic!("{} is not a box", s.name)
        };
        let mut out = Vec::new();
        for sx in [-0.5, 0.5] {
            for sy in [-0.5, 0.5] {
                for sz in [-0.5, 0.5] {
                    let l = Vec3::new(sx * size.x, sy * size.y, sz * size.z);
                    out.push(s.pose.point(&l));
                }
            }
        }
        out
    }

    /// The boxes follow the chain the hinge-angle outputs describe: plate k turned by
    /// `sum_j s_j (theta_j - lock_j)` about z (s_j = +1, -1, +1, ... as in build.rs), its inboard
    /// edge at the outboard edge of plate k-1, the root at the world origin.
    fn check_chain(scene: &mut PanelLock) {
        let p = scene.params.clone();
        let out = scene.outputs();
        let snap = scene.snapshot(0.0);
        let (mut phi, mut start) = (0.0, Vec3::zeros());
        for (k, h) in out.hinges.iter().enumerate() {
            let s = if k % 2 == 1 { -1.0 } else { 1.0 };
            let lock = scene.layout.lock_angles[k];
            phi += s * (h.angle - lock);
            let name = if k == 0 {
                "yoke".to_string()
            } else {
                format!("panel{k}")
            };
            let shape = snap.shape(&name).expect("plate drawn");
            assert!(
                wrap(yaw_of(shape) - phi).abs() < 1e-7,
                "{name}: yaw {} vs {phi}",
                yaw_of(shape)
            );
            let len = scene.layout.plate_lengths[k];
            let dir = yaw(phi) * Vec3::x();
            let normal = yaw(phi) * Vec3::y();
            // the eight corners: inboard/outboard edge, +-thickness/2, +-width/2
            let mut expected = Vec::new();
            for a in [0.0, len] {
                for t in [-0.5, 0.5] {
                    for w in [-0.5, 0.5] {
                        expected.push(
                            start
                                + a * dir
                                + t * p.panel_thickness * normal
                                + w * p.panel_width * Vec3::z(),
                        );
                    }
                }
            }
            for c in corners(shape) {
                let nearest = expected
                    .iter()
                    .map(|e| (e - c).norm())
                    .fold(f64::INFINITY, f64::min);
                assert!(nearest < 1e-6, "{name}: corner {c} is {nearest} m off");
            }
            let hinge = snap.shape(&format!("hinge{k}")).expect("hinge drawn");
            assert!((hinge.pose.position - start).norm() < 1e-6, "hinge{k}");
            start += len * dir;
        }
        let sat = snap.shape("satellite").expect("satellite drawn");
        assert!((sat.pose.position - Vec3::new(-1.0, 0.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn boxes_follow_the_hinge_angles_stowed_and_deploying() {
        let mut scene = PanelLock::new(PanelLockParams::default()).unwrap();
        check_chain(&mut scene);
        scene.advance_to(2.0).unwrap();
        let out = scene.outputs();
        let (stow, lock) = (scene.params.root_stowed_angle, scene.params.root_lock_angle);
        assert!(
            out.hinges[0].angle > stow + 0.1 * (lock - stow),
            "the root hinge has opened: {} rad",
            out.hinges[0].angle
        );
        check_chain(&mut scene);
        let snap = scene.snapshot(10.0);
        assert!((snap.time - 12.0).abs() < 1e-12);
        let n = scene.layout.plates.len();
        assert_eq!(snap.shapes.len(), 1 + 2 * n);
    }

    #[test]
    fn flexible_panels_are_drawn_as_their_plates() {
        let p = PanelLockParams {
            flexible_panels: true,
            n_modes: 4,
            ..PanelLockParams::default()
        };
        let mut scene = PanelLock::new(p).unwrap();
        check_chain(&mut scene);
    }
}
