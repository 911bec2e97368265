//! What a RopeBlock scene looks like: block, slings, rope nodes, contact nodes, hooks, loads and
//! ground as shapes ([`crate::scene::view`]), world frame, lengths in metres.
//!
//! - **block**: its shell mesh (the design mesh, triangles as built) in the block frame, whose
//!   origin is the centre of mass; posed by the block's position and orientation, the same
//!   numbers as the outputs `block_x/y/z`, `block_qw/qx/qy/qz`.
//! - **sling{r}**: a polyline through every point of rope `r`, hook end to lug end (world
//!   frame), its interior nodes drawn as beads; **contact_nodes**: every contact node of every
//!   rope (world frame), drawn larger.
//! - **hook{k}**: a sphere at hook `k` (the outputs `hook{k}_x/y/z`); **load{i}**: a sphere at a
//!   point mass; **ground**: a thin slab under the plane `z = ground_height`.
//!
//! The model has no size for hooks and nodes: they are drawn at a share of the block's bounding
//! box diagonal `d` (hooks and loads `0.015 d`, contact nodes `0.012 d`, rope nodes `0.005 d`),
//! so they stay visible whatever the block's size.

use super::RopeBlockScene;
use crate::math::{Quat, Vec3};
use crate::rope::shell::ShellMesh;
use crate::scene::view::{Geometry, Pose, Role, Shape, Snapshot};
use std::sync::Arc;

/// Sphere radii of hooks (and loads), contact nodes and rope nodes, as shares of the block's
/// bounding box diagonal [-].
pub const HOOK_SHARE: f64 = 0.015;
pub const CONTACT_NODE_SHARE: f64 = 0.012;
pub const ROPE_NODE_SHARE: f64 = 0.005;

/// The block's drawn shell: vertices [m] in the block frame (origin at the centre of mass) and
/// triangles, shared by every snapshot.
#[derive(Debug, Clone)]
pub struct BlockLook {
    vertices: Arc<[Vec3]>,
    triangles: Arc<[[u32; 3]]>,
    /// Bounding box of the vertices [m], block frame.
    min: Vec3,
    max: Vec3,
}

impl BlockLook {
    /// The shell `design` (design frame) moved so that the centre of mass `com` [m] (design
    /// frame) is the origin.
    pub fn new(design: &ShellMesh, com: &Vec3) -> Self {
        let vertices: Arc<[Vec3]> = design.vertices.iter().map(|v| v - com).collect();
        BlockLook {
            vertices,
            triangles: design.triangles.clone().into(),
            min: design.aabb_min - com,
            max: design.aabb_max - com,
        }
    }

    /// Diagonal of the bounding box [m].
    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).norm()
    }
}

fn points(name: String, role: Role, points: Vec<Vec3>, radius: f64) -> Shape {
    Shape {
        name,
        role,
        geometry: Geometry::Points { points, radius },
        pose: Pose::world(),
    }
}

fn sphere(name: String, role: Role, at: Vec3, radius: f64) -> Shape {
    Shape {
        name,
        role,
        geometry: Geometry::Sphere { radius },
        pose: Pose::at(at),
    }
}

impl RopeBlockScene {
    /// The scene's shapes at the current state; `time_offset` [s] is added to the scene time
    /// (the importer's start time).
    pub fn snapshot(&mut self, time_offset: f64) -> Snapshot {
        let look = self.look.clone();
        let d = look.diagonal().max(f64::MIN_POSITIVE);
        let sim = &mut self.sim;
        let mut shapes = Vec::new();

        // the block: the state's position and quaternion, as the outputs report them
        let st = &sim.sim.state;
        if let Some(b) = sim.map.blocks.first().and_then(|b| b.index()) {
            let qo = sim.sim.system.model.bodies[b].q_offset;
            let q = &st.q[qo..qo + 7];
            // the state's quaternion as it is (unit within rounding): the outputs' numbers
            let orientation =
                Quat::new_unchecked(nalgebra::Quaternion::new(q[3], q[4], q[5], q[6]));
            shapes.push(Shape {
                name: "block".into(),
                role: Role::Block,
                geometry: Geometry::Mesh {
                    vertices: look.vertices.clone(),
                    triangles: look.triangles.clone(),
                },
                pose: Pose {
                    position: Vec3::new(q[0], q[1], q[2]),
                    orientation,
                },
            });
        }

        let mem = &st.memory[sim.map.rope_memory..];
        for k in 0..sim.map.rope.n_hooks() {
            let (x, _) = sim.map.rope.hook_motion(mem, k, st.t);
            shapes.push(sphere(format!("hook{k}"), Role::Hook, x, HOOK_SHARE * d));
        }
        let t = st.t;
        let sys = &mut sim.sim.system;
        sys.update_kinematics(&st.q, &st.v);
        for (i, &id) in sim.map.loads.iter().enumerate() {
            let at = sys.kin(id).r;
            shapes.push(sphere(format!("load{i}"), Role::Load, at, HOOK_SHARE * d));
        }

        let mut contacts = Vec::new();
        for r in 0..sim.structure.ropes.len() {
            let pts = sim.rope_points(r);
            let nodes = &sim.structure.ropes[r].nodes;
            // points are [start end, nodes in order, end end] (build.rs)
            if pts.len() == nodes.len() + 2 {
                let interior = pts[1..pts.len() - 1].iter().zip(nodes);
                contacts.extend(
                    interior
                        .filter(|(_, n)| n.contact.is_some())
                        .map(|(p, _)| *p),
                );
            }
            shapes.push(Shape {
                name: format!("sling{r}"),
                role: Role::Rope,
                geometry: Geometry::Polyline {
                    points: pts,
                    node_radius: ROPE_NODE_SHARE * d,
                },
                pose: Pose::world(),
            });
        }
        shapes.push(points(
            "contact_nodes".into(),
            Role::ContactNode,
            contacts,
            CONTACT_NODE_SHARE * d,
        ));

        if let Some(g) = &self.params.ground {
            // a slab three block sizes wide under the block's design position, 1 % of d thick
            let span = 3.0 * d;
            let thick = 0.01 * d;
            let c = self.params.block_origin;
            shapes.push(Shape {
                name: "ground".into(),
                role: Role::Ground,
                geometry: Geometry::Box {
                    size: Vec3::new(span, span, thick),
                },
                pose: Pose::at(Vec3::new(c.x, c.y, g.height - 0.5 * thick)),
            });
        }
        Snapshot {
            time: time_offset + t,
            shapes,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::rope_block::RopeBlockParams;

    fn out(scene: &mut RopeBlockScene, name: &str) -> f64 {
        scene
            .output(name)
            .unwrap_or_else(|| panic!("no output {name}"))
    }

    /// Block pose and hooks equal the outputs; every shell vertex is where the block's pose puts
    /// the design mesh; the slings end at their hooks; contact nodes lie on the block's edges.
    fn check(scene: &mut RopeBlockScene) {
        let snap = scene.snapshot(0.0);
        let block = snap.shape("block").expect("block drawn");
        let p = block.pose.position;
        let q = block.pose.orientation;
        for (v, name) in [(p.x, "block.x"), (p.y, "block.y"), (p.z, "block.z")] {
            assert_eq!(v, out(scene, name), "{name}");
        }
        let qo = [q.w, q.i, q.j, q.k];
        for (v, name) in qo
            .iter()
            .zip(["block.qw", "block.qx", "block.qy", "block.qz"])
        {
            assert!((v - out(scene, name)).abs() < 1e-12, "{name}");
        }
        // the shell: design mesh vertex v at block_origin + R (v) in the design frame's terms,
        // i.e. com_world + R (v - com)
        let design = scene.params.design_mesh().unwrap();
        let Geometry::Mesh {
            vertices,
            triangles,
        } = &block.geometry
        else {
            panic!("the block is not a mesh")
        };
        assert_eq!(vertices.len(), design.vertices.len());
        assert_eq!(triangles.len(), design.triangles.len());
        let (com, _, _) = scene.params.mass_properties(&design);
        for (local, dv) in vertices.iter().zip(&design.vertices) {
            let w = block.pose.point(local);
            let expect = p + q * (dv - com);
            assert!((w - expect).norm() < 1e-9);
        }
        for k in 0..scene.params.rig.hooks.len() {
            let h = snap.shape(&format!("hook{k}")).expect("hook drawn");
            for (v, c) in h.pose.position.iter().zip(["x", "y", "z"]) {
                assert_eq!(*v, out(scene, &format!("hook{k}.{c}")));
            }
        }
        let n_contacts = out(scene, "contact.count") as usize;
        let Some(Geometry::Points { points, .. }) =
            snap.shape("contact_nodes").map(|s| &s.geometry)
        else {
            panic!("no contact nodes shape")
        };
        assert_eq!(points.len(), n_contacts);
        let mesh = scene.sim.structure.blocks[0].mesh.clone().expect("mesh");
        for c in points {
            // distance to the nearest plate edge line segment, block frame
            let local = q.inverse() * (c - p);
            let dist = mesh
                .edges
                .iter()
                .map(|e| {
                    let s = (local - e.a).dot(&e.dir).clamp(0.0, e.length);
                    (local - (e.a + s * e.dir)).norm()
                })
                .fold(f64::INFINITY, f64::min);
            assert!(dist < 1e-3, "contact node {c} is {dist} m off every edge");
        }
        for r in 0..scene.params.rig.slings.len() {
            let Some(Geometry::Polyline { points, .. }) =
                snap.shape(&format!("sling{r}")).map(|s| &s.geometry)
            else {
                panic!("no sling{r}")
            };
            let ends = [points[0], points[points.len() - 1]];
            let at_hook = (0..scene.params.rig.hooks.len()).any(|k| {
                let h = snap.shape(&format!("hook{k}")).unwrap().pose.position;
                ends.iter().any(|e| (e - h).norm() < 1e-12)
            });
            assert!(at_hook, "sling{r} ends at no hook");
        }
    }

    #[test]
    fn snapshot_matches_outputs_and_geometry() {
        let mut scene = RopeBlockScene::new(RopeBlockParams::default()).unwrap();
        assert!(
            out(&mut scene, "contact.count") > 0.0,
            "the lift has contacts"
        );
        check(&mut scene);
        scene.set_hook(0, Vec3::new(0.0, 0.0, 0.2), 0.0).unwrap();
        scene.step(0.2).unwrap();
        check(&mut scene);
        assert!((scene.snapshot(5.0).time - 5.2).abs() < 1e-12);
    }
}
