//! The replay data: one frame per output point, encoded as JSON as the run goes.
//!
//! ```text
//! {"format":1, "model":"PanelLock", "three":"0.187.0",
//!  "units":"...", "roles":{"yoke":"yoke", "panel1":"panel", ...},
//!  "frames":[{"t":0.0, "s":{"yoke":{"p":[x,y,z,qw,qx,qy,qz], "g":{"kind":"box","size":[..]}}, ...}},
//!            {"t":0.01, "s":{"yoke":{"p":[...]}, ...}}, ...]}
//! ```
//! Per frame and shape `p` is the pose: origin [m] and unit quaternion (w, x, y, z), shape frame
//! to world. `g`, the geometry in the shape frame [m], is written only when it differs from the
//! last one written for that name (a box once, a rope polyline every frame): the geometry in
//! effect at frame `i` is the last `g` at or before `i`. A shape missing from a frame is not
//! drawn then. Geometry kinds: `box` (`size`: full edge lengths), `cylinder` (`radius`,
//! `length`, axis = shape z), `sphere` (`radius`), `points` (`radius`, `points`: flat x,y,z
//! list), `polyline` (`points`, `node_radius`: beads on the interior points, 0 none), `mesh` (`vertices`: flat x,y,z list, `triangles`: flat vertex
//! indices). Poses and times are shortest round-trip decimal forms of the model's f64 values
//! (exact); geometry numbers are rounded to f32, the precision WebGL draws with.

use std::collections::HashMap;

use mbcosim::scene::view::{Geometry, Shape, Snapshot};

use super::json;

/// Frames encoded so far.
#[derive(Default)]
pub struct Frames {
    /// The frames array's elements, comma-separated.
    body: String,
    count: usize,
    /// Name and role of every shape seen, in order of appearance.
    roles: Vec<(String, &'static str)>,
    /// Last geometry written per name.
    last: HashMap<String, Geometry>,
}

fn geometry(out: &mut String, g: &Geometry) {
    let flat =
        |pts: &[mbcosim::math::Vec3]| pts.iter().flat_map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>();
    match g {
        Geometry::Box { size } => {
            out.push_str("{\"kind\":\"box\",\"size\":");
            json::numbers32(out, [size.x, size.y, size.z]);
        }
        Geometry::Cylinder { radius, length } => {
            out.push_str("{\"kind\":\"cylinder\",\"radius\":");
            json::number32(out, *radius);
            out.push_str(",\"length\":");
            json::number32(out, *length);
        }
        Geometry::Sphere { radius } => {
            out.push_str("{\"kind\":\"sphere\",\"radius\":");
            json::number32(out, *radius);
        }
        Geometry::Points { points, radius } => {
            out.push_str("{\"kind\":\"points\",\"radius\":");
            json::number32(out, *radius);
            out.push_str(",\"points\":");
            json::numbers32(out, flat(points));
        }
        Geometry::Polyline {
            points,
            node_radius,
        } => {
            out.push_str("{\"kind\":\"polyline\",\"node_radius\":");
            json::number32(out, *node_radius);
            out.push_str(",\"points\":");
            json::numbers32(out, flat(points));
        }
        Geometry::Mesh {
            vertices,
            triangles,
        } => {
            out.push_str("{\"kind\":\"mesh\",\"vertices\":");
            json::numbers32(out, flat(vertices));
            out.push_str(",\"triangles\":");
            json::numbers(out, triangles.iter().flat_map(|t| t.map(f64::from)));
        }
    }
    out.push('}');
}

impl Frames {
    /// Appends one snapshot as a frame.
    pub fn push(&mut self, snap: &Snapshot) {
        let out = &mut self.body;
        if self.count > 0 {
            out.push(',');
        }
        out.push_str("{\"t\":");
        json::number(out, snap.time);
        out.push_str(",\"s\":{");
        for (
            i,
            Shape {
                name,
                role,
                geometry: g,
                pose,
            },
        ) in snap.shapes.iter().enumerate()
        {
            if i > 0 {
                out.push(',');
            }
            json::string(out, name);
            out.push_str(":{\"p\":");
            let (p, q) = (pose.position, pose.orientation);
            json::numbers(out, [p.x, p.y, p.z, q.w, q.i, q.j, q.k]);
            if self.last.get(name) != Some(g) {
                out.push_str(",\"g\":");
                geometry(out, g);
                self.last.insert(name.clone(), g.clone());
            }
            out.push('}');
            if !self.roles.iter().any(|(n, _)| n == name) {
                self.roles.push((name.clone(), role.name()));
            }
        }
        out.push_str("}}");
        self.count += 1;
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.count
    }

    /// The whole JSON document for `model`, drawn with three.js `three_version`.
    pub fn document(&self, model: &str, three_version: &str) -> String {
        let mut out = String::with_capacity(self.body.len() + 1024);
        out.push_str("{\"format\":1,\"model\":");
        json::string(&mut out, model);
        out.push_str(",\"three\":");
        json::string(&mut out, three_version);
        out.push_str(",\"units\":");
        json::string(
            &mut out,
            "SI: t [s]; p = position [m] and quaternion (w, x, y, z) shape frame to world; geometry [m] in the shape frame; world frame z up",
        );
        out.push_str(",\"roles\":{");
        for (i, (name, role)) in self.roles.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            json::string(&mut out, name);
            out.push(':');
            json::string(&mut out, role);
        }
        out.push_str("},\"frames\":[");
        out.push_str(&self.body);
        out.push_str("]}");
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mbcosim::math::Vec3;
    use mbcosim::scene::view::{Pose, Role};

    fn snap(t: f64, z: f64) -> Snapshot {
        Snapshot {
            time: t,
            shapes: vec![
                Shape {
                    name: "panel1".into(),
                    role: Role::Panel,
                    geometry: Geometry::Box {
                        size: Vec3::new(2.0, 0.025, 1.5),
                    },
                    pose: Pose::at(Vec3::new(1.0, 0.0, z)),
                },
                Shape {
                    name: "sling0".into(),
                    role: Role::Rope,
                    geometry: Geometry::Polyline {
                        points: vec![Vec3::zeros(), Vec3::new(0.0, 0.0, z)],
                        node_radius: 0.0,
                    },
                    pose: Pose::world(),
                },
            ],
        }
    }

    #[test]
    fn geometry_is_written_when_it_changes_only() {
        let mut f = Frames::default();
        f.push(&snap(0.0, 1.0));
        f.push(&snap(0.5, 2.0));
        assert_eq!(f.len(), 2);
        let doc = f.document("PanelLock", "0.187.0");
        assert_eq!(doc.matches("\"kind\":\"box\"").count(), 1, "{doc}");
        assert_eq!(doc.matches("\"kind\":\"polyline\"").count(), 2, "{doc}");
        assert!(
            doc.contains("\"roles\":{\"panel1\":\"panel\",\"sling0\":\"rope\"}"),
            "{doc}"
        );
        assert!(
            doc.contains(
                "{\"t\":0.5,\"s\":{\"panel1\":{\"p\":[1.0,0.0,2.0,1.0,0.0,0.0,0.0]},\"sling0\":"
            ),
            "{doc}"
        );
        assert!(doc.starts_with("{\"format\":1,\"model\":\"PanelLock\",\"three\":\"0.187.0\""));
        assert!(doc.ends_with("]}"));
    }
}
