//! Scene snapshots for visualization: what a model looks like at one instant, as plain shapes.
//!
//! A [`Snapshot`] lists [`Shape`]s, each with a stable name, a [`Role`] (what it stands for), a
//! [`Geometry`] in the shape's own frame and a [`Pose`] of that frame in the world frame. Units
//! are SI: lengths [m], time [s]; orientations are unit quaternions rotating shape-frame vectors
//! into the world frame. The world frame is the model's inertial frame (z up in both PanelLock
//! and RopeBlock).
//!
//! Snapshots are for looking at a run (the `--replay` page of the command line), not for
//! computing with: they draw the rigid reference geometry of each body (e.g. a flexible panel's
//! undeformed plate) and carry no velocities or forces. A model that has nothing to draw keeps
//! the default [`super::CoSimModel::snapshot`], which returns `None`.

use crate::math::{Mat3, Quat, Vec3};
use std::sync::Arc;

/// What a shape stands for; a viewer colours and sizes by it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The spacecraft bus carrying a solar array (PanelLock).
    Satellite,
    /// The yoke between the satellite and the first panel (PanelLock).
    Yoke,
    /// A solar-array panel (PanelLock).
    Panel,
    /// A hinge body (PanelLock).
    Hinge,
    /// A rigid ship block (RopeBlock).
    Block,
    /// A rope: the line through its points, hook to lug, with its nodes (RopeBlock).
    Rope,
    /// Rope nodes tied to a plate edge of the block (RopeBlock).
    ContactNode,
    /// A crane hook, the prescribed end of a rope (RopeBlock).
    Hook,
    /// A point mass that is not part of a rope (RopeBlock).
    Load,
    /// The ground plane (RopeBlock with ground contact).
    Ground,
}

impl Role {
    /// Lower-case name, as written in the replay page's data.
    pub fn name(self) -> &'static str {
        match self {
            Role::Satellite => "satellite",
            Role::Yoke => "yoke",
            Role::Panel => "panel",
            Role::Hinge => "hinge",
            Role::Block => "block",
            Role::Rope => "rope",
            Role::ContactNode => "contact_node",
            Role::Hook => "hook",
            Role::Load => "load",
            Role::Ground => "ground",
        }
    }
}

/// Where a shape's frame is: its origin [m] and orientation (shape frame to world), world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Origin of the shape frame [m], world frame.
    pub position: Vec3,
    /// Rotation shape frame -> world.
    pub orientation: Quat,
}

impl Pose {
    /// The world frame itself: for shapes whose points are given in world coordinates.
    pub fn world() -> Self {
        Pose {
            position: Vec3::zeros(),
            orientation: Quat::identity(),
        }
    }

    /// A frame at `position` [m] with the world's axes.
    pub fn at(position: Vec3) -> Self {
        Pose {
            position,
            orientation: Quat::identity(),
        }
    }

    /// The frame of a body point: `position` [m] and rotation matrix `rot` (body -> world).
    pub fn from_matrix(position: Vec3, rot: &Mat3) -> Self {
        Pose {
            position,
            orientation: Quat::from_matrix(rot),
        }
    }

    /// World coordinates [m] of the shape-frame point `local` [m].
    pub fn point(&self, local: &Vec3) -> Vec3 {
        self.position + self.orientation * local
    }
}

/// The form of a shape, in the shape's own frame [m].
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// A box centred on the frame origin, edges along the frame axes; `size` holds the full
    /// edge lengths along x, y, z [m].
    Box { size: Vec3 },
    /// A solid cylinder centred on the frame origin, its axis the frame's z axis: radius and full
    /// length [m].
    Cylinder { radius: f64, length: f64 },
    /// A sphere of `radius` [m] about the frame origin.
    Sphere { radius: f64 },
    /// Points [m] (shape frame), each drawn as a sphere of `radius` [m].
    Points { points: Vec<Vec3>, radius: f64 },
    /// A line through `points` [m] (shape frame), in order; its interior points drawn as spheres
    /// of `node_radius` [m] (0: the line only).
    Polyline { points: Vec<Vec3>, node_radius: f64 },
    /// A triangle mesh: vertices [m] (shape frame) and triangles as vertex indices,
    /// counter-clockwise seen from outside. Shared, so a snapshot per output point stays cheap.
    Mesh {
        vertices: Arc<[Vec3]>,
        triangles: Arc<[[u32; 3]]>,
    },
}

/// One thing to draw.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// Stable name within the model (`panel2`, `hook0`, `sling1`): a viewer matches shapes of
    /// successive snapshots by it.
    pub name: String,
    pub role: Role,
    pub geometry: Geometry,
    pub pose: Pose,
}

/// Everything a model draws at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Model time [s] (the importer's time axis, start time included).
    pub time: f64,
    pub shapes: Vec<Shape>,
}

impl Snapshot {
    /// The shape named `name`, if drawn.
    pub fn shape(&self, name: &str) -> Option<&Shape> {
        self.shapes.iter().find(|s| s.name == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pose_maps_shape_points_to_world() {
        let rot = Quat::from_axis_angle(&Vec3::z_axis(), std::f64::consts::FRAC_PI_2);
        let p = Pose::from_matrix(Vec3::new(1.0, 2.0, 3.0), rot.to_rotation_matrix().matrix());
        let w = p.point(&Vec3::new(1.0, 0.0, 0.0));
        assert!((w - Vec3::new(1.0, 3.0, 3.0)).norm() < 1e-12, "{w}");
        assert_eq!(Pose::world().point(&Vec3::x()), Vec3::x());
        assert_eq!(
            Pose::at(Vec3::z()).point(&Vec3::x()),
            Vec3::new(1.0, 0.0, 1.0)
        );
    }

    #[test]
    fn role_names_are_distinct() {
        let all = [
            Role::Satellite,
            Role::Yoke,
            Role::Panel,
            Role::Hinge,
            Role::Block,
            Role::Rope,
            Role::ContactNode,
            Role::Hook,
            Role::Load,
            Role::Ground,
        ];
        let names: std::collections::HashSet<_> = all.iter().map(|r| r.name()).collect();
        assert_eq!(names.len(), all.len());
    }
}
