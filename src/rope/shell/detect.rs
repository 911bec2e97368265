//! Where a straight rope segment cuts through the corner region of a plate edge.
//!
//! For a convex plate edge `A B` with outward plate normals `n1`, `n2`, a point `x` is inside the
//! edge's wedge when `(x - A) . n1 < 0` and `(x - A) . n2 < 0`. A rope segment `P Q` *crosses* the
//! edge when the point `x` of the segment closest to the edge line lies strictly inside the wedge
//! (deeper than `tol`), both segment ends are outside it, the closest point `y` on the edge lies
//! strictly between `A` and `B`, and `|x - y|` does not exceed `max_depth` (the wedge test is a
//! local one). The crossing point is `y`: the point of the edge nearest to the segment, where the
//! paper inserts its contact node. The closest points come from parry3d-f64's segment-segment
//! query; candidate edges from the mesh's bounding-volume hierarchy.

use super::{ShellMesh, from_g, to_g};
use crate::math::Vec3;
use parry3d_f64::query::closest_points::closest_points_segment_segment_with_locations_nD;
use parry3d_f64::shape::SegmentPointLocation;

/// A rope segment crossing a plate edge (block frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// Plate edge index.
    pub edge: usize,
    /// Position along the rope segment, 0 at `P` ... 1 at `Q` [-].
    pub s: f64,
    /// Crossing point on the edge [m].
    pub point: Vec3,
    /// Distance of the rope segment from the edge, inside the wedge [m].
    pub depth: f64,
}

fn inside(x: &Vec3, a: &Vec3, n1: &Vec3, n2: &Vec3, tol: f64) -> bool {
    (x - a).dot(n1) < -tol && (x - a).dot(n2) < -tol
}

/// The first crossing (smallest `s`) of segment `p q` [m, block frame] with a plate edge not in
/// `skip`; `scratch` is reused for the candidate list.
pub fn segment_crossing(
    mesh: &ShellMesh,
    p: &Vec3,
    q: &Vec3,
    skip: &[usize],
    tol: f64,
    max_depth: f64,
    scratch: &mut Vec<usize>,
) -> Option<Crossing> {
    let lo = p.inf(q).add_scalar(-tol);
    let hi = p.sup(q).add_scalar(tol);
    if (0..3).any(|k| hi[k] < mesh.aabb_min[k] || lo[k] > mesh.aabb_max[k]) {
        return None;
    }
    mesh.edges_near(&lo, &hi, scratch);
    let mut best: Option<Crossing> = None;
    let (gp, gq) = (to_g(p), to_g(q));
    for &ei in scratch.iter() {
        if skip.contains(&ei) {
            continue;
        }
        let e = &mesh.edges[ei];
        let (ga, gb) = (to_g(&e.a), to_g(&e.b));
        let (l1, l2) = closest_points_segment_segment_with_locations_nD((&gp, &gq), (&ga, &gb));
        let (SegmentPointLocation::OnEdge(ws), SegmentPointLocation::OnEdge(wt)) = (l1, l2) else {
            continue;
        };
        let s = ws[1];
        let x = from_g(gp * ws[0] + gq * ws[1]);
        let y = from_g(ga * wt[0] + gb * wt[1]);
        if !inside(&x, &e.a, &e.n1, &e.n2, tol)
            || inside(p, &e.a, &e.n1, &e.n2, -tol)
            || inside(q, &e.a, &e.n1, &e.n2, -tol)
        {
            continue;
        }
        let depth = (x - y).norm();
        if depth > max_depth {
            continue;
        }
        if best.is_none_or(|b| s < b.s) {
            best = Some(Crossing {
                edge: ei,
                s,
                point: y,
                depth,
            });
        }
    }
    best
}

/// Whether the straight segment `p q` [m, block frame] passes outside the wedge of `edge` near
/// the edge (its point closest to the edge line is on or outside one of the two plate planes):
/// the rope has left the edge.
pub fn clears_edge(mesh: &ShellMesh, edge: usize, p: &Vec3, q: &Vec3) -> bool {
    let e = &mesh.edges[edge];
    let (gp, gq) = (to_g(p), to_g(q));
    let (ga, gb) = (to_g(&e.a), to_g(&e.b));
    let (l1, _) = closest_points_segment_segment_with_locations_nD((&gp, &gq), (&ga, &gb));
    let x = match l1 {
        SegmentPointLocation::OnVertex(0) => *p,
        SegmentPointLocation::OnVertex(_) => *q,
        SegmentPointLocation::OnEdge(w) => from_g(gp * w[0] + gq * w[1]),
    };
    !inside(&x, &e.a, &e.n1, &e.n2, 0.0)
}
