//! The shell plate of a block as a triangle mesh, its plate edges, and the crossing of rope
//! segments with those edges.
//!
//! Everything here is in the **block frame** (body frame of the block, origin at its centre of
//! mass) [m]. A *plate edge* is a mesh edge shared by exactly two triangles that meet at a convex
//! angle larger than a threshold (so the diagonals of flat quads and the smooth interior of a
//! finely meshed plate are not edges, while a knuckle, a box corner or each facet line of a
//! faceted bilge plate is). A rope can only wrap around plate edges; edges of open boundaries
//! (one triangle) and concave edges are ignored.
//!
//! Plate edges sit in a bounding-volume hierarchy (parry3d-f64's [`Bvh`]), so a query costs about
//! the logarithm of the number of edges plus the edges actually near the segment: polygons far
//! from the rope cost nothing. parry3d-f64 0.31 works in glam types; conversions stay in this
//! module and [`detect`].

pub mod detect;
pub mod import;
pub mod mass;
pub mod parametric;

use crate::math::Vec3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector as GVec;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use std::collections::HashMap;

/// Default smallest turning angle between two triangles for their common edge to count as a plate
/// edge [rad] (0.5 deg).
pub const DEFAULT_MIN_EDGE_ANGLE: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// A convex plate edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateEdge {
    /// End points [m], block frame.
    pub a: Vec3,
    pub b: Vec3,
    /// Unit direction `(b - a) / |b - a|`.
    pub dir: Vec3,
    /// Length [m].
    pub length: f64,
    /// Outward unit normals of the two plates meeting at the edge.
    pub n1: Vec3,
    pub n2: Vec3,
    /// Angle between the two plates' normals [rad]: how much a rope wrapping tightly around the
    /// edge turns there.
    pub angle: f64,
}

impl PlateEdge {
    /// Unit outward normal bisecting the two plates.
    pub fn mean_normal(&self) -> Vec3 {
        (self.n1 + self.n2).normalize()
    }
}

/// A closed (or at least consistently oriented) triangle mesh with its plate edges.
#[derive(Debug, Clone)]
pub struct ShellMesh {
    /// Vertices [m], block frame.
    pub vertices: Vec<Vec3>,
    /// Triangles (vertex indices), counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Plate edges.
    pub edges: Vec<PlateEdge>,
    bvh: Bvh,
    /// Bounding box of all vertices [m].
    pub aabb_min: Vec3,
    pub aabb_max: Vec3,
    /// Smallest turning angle of a plate edge [rad] used to build the mesh.
    pub min_edge_angle: f64,
}

impl ShellMesh {
    /// Vertices of the convex hull of the mesh [m], block frame: the points by which the block
    /// can touch a plane (the ground).
    pub fn hull_vertices(&self) -> Vec<Vec3> {
        let pts: Vec<GVec> = self.vertices.iter().map(to_g).collect();
        let (hull, _) = parry3d_f64::transformation::convex_hull(&pts);
        hull.into_iter().map(from_g).collect()
    }
}

pub(crate) fn to_g(v: &Vec3) -> GVec {
    GVec::new(v.x, v.y, v.z)
}

pub(crate) fn from_g(v: GVec) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

impl ShellMesh {
    /// Builds a mesh from vertices [m] and triangles; flips all triangles if the enclosed volume
    /// comes out negative. `Err` for non-finite or out-of-range data, degenerate triangles, or
    /// triangles whose orientation disagrees with a neighbour's.
    pub fn new(
        vertices: Vec<Vec3>,
        mut triangles: Vec<[u32; 3]>,
        min_edge_angle: f64,
    ) -> Result<Self, String> {
        if triangles.is_empty() {
            return Err("shell mesh has no triangles".into());
        }
        if !(min_edge_angle.is_finite() && (0.0..std::f64::consts::PI).contains(&min_edge_angle)) {
            return Err(format!(
                "minimum plate-edge angle must be in [0, pi) rad, got {min_edge_angle}"
            ));
        }
        if let Some(i) = vertices
            .iter()
            .position(|v| !v.iter().all(|x| x.is_finite()))
        {
            return Err(format!("shell mesh vertex {i} is not finite"));
        }
        let nv = vertices.len() as u32;
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        for v in &vertices {
            lo = lo.inf(v);
            hi = hi.sup(v);
        }
        let scale = (hi - lo).norm().max(1e-300);
        let mut volume = 0.0;
        for (t, tri) in triangles.iter().enumerate() {
            if tri.iter().any(|&i| i >= nv) {
                return Err(format!(
                    "shell mesh triangle {t} references a vertex beyond the {nv} given"
                ));
            }
            let [a, b, c] = tri.map(|i| vertices[i as usize]);
            let area2 = (b - a).cross(&(c - a)).norm();
            if area2.is_nan() || area2 <= 1e-12 * scale * scale {
                return Err(format!("shell mesh triangle {t} is degenerate (zero area)"));
            }
            volume += a.dot(&b.cross(&c)) / 6.0;
        }
        if volume < 0.0 {
            for tri in &mut triangles {
                tri.swap(1, 2);
            }
        }
        let normal = |tri: &[u32; 3]| {
            let [a, b, c] = tri.map(|i| vertices[i as usize]);
            (b - a).cross(&(c - a)).normalize()
        };
        // undirected edge -> (triangle, directed as (lo, hi)?)
        let mut map: HashMap<(u32, u32), Vec<(usize, bool)>> = HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (i, j) = (tri[k], tri[(k + 1) % 3]);
                map.entry((i.min(j), i.max(j)))
                    .or_default()
                    .push((t, i < j));
            }
        }
        let mut keys: Vec<_> = map.keys().copied().collect();
        keys.sort_unstable();
        let mut edges = Vec::new();
        for key in keys {
            let users = &map[&key];
            if users.len() != 2 {
                continue;
            }
            let ((t1, f1), (t2, f2)) = (users[0], users[1]);
            if f1 == f2 {
                return Err(format!(
                    "shell mesh triangles {t1} and {t2} are oriented inconsistently (shared edge {}-{} runs the same way in both)",
                    key.0, key.1
                ));
            }
            let (n1, n2) = (normal(&triangles[t1]), normal(&triangles[t2]));
            let (a, b) = (vertices[key.0 as usize], vertices[key.1 as usize]);
            let opposite = triangles[t2]
                .iter()
                .map(|&i| vertices[i as usize])
                .find(|v| *v != a && *v != b)
                .unwrap_or(a);
            let convex = (opposite - a).dot(&n1) < -1e-12 * scale;
            let angle = n1.dot(&n2).clamp(-1.0, 1.0).acos();
            if convex && angle > min_edge_angle {
                let length = (b - a).norm();
                edges.push(PlateEdge {
                    a,
                    b,
                    dir: (b - a) / length,
                    length,
                    n1,
                    n2,
                    angle,
                });
            }
        }
        let leaves: Vec<Aabb> = edges
            .iter()
            .map(|e| Aabb::new(to_g(&e.a.inf(&e.b)), to_g(&e.a.sup(&e.b))))
            .collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::default(), &leaves);
        Ok(ShellMesh {
            vertices,
            triangles,
            edges,
            bvh,
            aabb_min: lo,
            aabb_max: hi,
            min_edge_angle,
        })
    }

    /// Indices of the plate edges whose bounding boxes meet the box `[lo, hi]` [m].
    pub fn edges_near(&self, lo: &Vec3, hi: &Vec3, out: &mut Vec<usize>) {
        out.clear();
        if self.edges.is_empty() {
            return;
        }
        let q = Aabb::new(to_g(lo), to_g(hi));
        out.extend(self.bvh.intersect_aabb(&q).map(|i| i as usize));
    }

    /// Translates every vertex and edge by `offset` [m] (e.g. to put the centre of mass at the
    /// origin of the block frame).
    pub fn translated(&self, offset: &Vec3) -> Result<Self, String> {
        let v = self.vertices.iter().map(|p| p + offset).collect();
        ShellMesh::new(v, self.triangles.clone(), self.min_edge_angle)
    }

    /// Surface area [m^2].
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                0.5 * (b - a).cross(&(c - a)).norm()
            })
            .sum()
    }
}
