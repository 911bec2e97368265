//! Laying out a rope along a route of waypoints: interior nodes by arc length, contact nodes at
//! waypoints that lie on plate edges, lumped masses, and the shortest path over an edge.

use super::structure::{EndSpec, NodeContact, NodeSpec, RopeSpec};
use crate::math::Vec3;
use crate::rope::shell::{PlateEdge, ShellMesh};
use crate::rope::{RopeProps, SlipMode};

/// A route point and, for material nodes, (leg, index, attachment) data.
type RoutePoint = (Vec3, Option<(usize, usize, Vec3)>);

/// A waypoint of a rope route.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waypoint {
    /// Position [m], world frame.
    pub position: Vec3,
    /// `Some((block, edge, anchor))` when the waypoint lies on a plate edge (anchor in the block
    /// frame [m]): it becomes a contact node.
    pub contact: Option<(usize, usize, Vec3)>,
}

/// The point of the infinite line through `edge` minimizing `|p - x| + |x - q|` [m] (the taut
/// rope's shortest path over the edge), as the edge parameter [m] from `edge.a`.
pub fn shortest_over_edge(edge: &PlateEdge, p: &Vec3, q: &Vec3) -> f64 {
    let (up, uq) = ((p - edge.a).dot(&edge.dir), (q - edge.a).dot(&edge.dir));
    let rp = (p - edge.a - edge.dir * up).norm();
    let rq = (q - edge.a - edge.dir * uq).norm();
    if rp + rq < 1e-300 {
        return 0.5 * (up + uq);
    }
    (up * rq + uq * rp) / (rp + rq)
}

/// The plate edge of `mesh` that the straight path `p q` (block frame) wraps around first: among
/// the edges the path cuts (both points outside the edge's wedge, the path's middle inside), the
/// one whose shortest path point is deepest inside the wedge; with that point (block frame).
pub fn wrap_edge(mesh: &ShellMesh, p: &Vec3, q: &Vec3) -> Option<(usize, Vec3)> {
    let mut best: Option<(usize, Vec3, f64)> = None;
    for (k, e) in mesh.edges.iter().enumerate() {
        let outside = |x: &Vec3| (x - e.a).dot(&e.n1) > 0.0 || (x - e.a).dot(&e.n2) > 0.0;
        if !outside(p) || !outside(q) {
            continue;
        }
        let u = shortest_over_edge(e, p, q);
        if !(0.0..=e.length).contains(&u) {
            continue;
        }
        let x = e.a + e.dir * u;
        // how far the straight path dips into the wedge near the edge
        let d = q - p;
        let s = ((x - p).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        let y = p + d * s;
        let depth = -((y - e.a).dot(&e.n1)).max((y - e.a).dot(&e.n2));
        if depth > 0.0 && best.is_none_or(|b| depth > b.2) {
            best = Some((k, x, depth));
        }
    }
    best.map(|b| (b.0, b.1))
}

/// A rope from `start` to `end` along `route` (the world positions of the two ends first and
/// last), with about `segments` segments of equal unstretched length, the rope unstretched
/// (`length_factor = 1`) or shorter by that factor. Node masses are lumped (each node half of its
/// two segments, the outer halves of the end segments to the nearest node), so the rope's mass is
/// its mass per length times its length.
#[allow(clippy::too_many_arguments)]
pub fn lay_rope(
    name: &str,
    props: RopeProps,
    start: EndSpec,
    end: EndSpec,
    route: &[Waypoint],
    segments: usize,
    length_factor: f64,
) -> Result<RopeSpec, String> {
    if route.len() < 2 {
        return Err(format!("rope '{name}': a route needs at least two points"));
    }
    if segments < 2 {
        return Err(format!(
            "rope '{name}': needs at least 2 segments, got {segments}"
        ));
    }
    if !(length_factor.is_finite() && length_factor > 0.0) {
        return Err(format!(
            "rope '{name}': length factor must be finite and > 0, got {length_factor}"
        ));
    }
    let legs: Vec<f64> = route
        .windows(2)
        .map(|w| (w[1].position - w[0].position).norm())
        .collect();
    let total: f64 = legs.iter().sum();
    if total.is_nan() || total <= 0.0 {
        return Err(format!("rope '{name}': route has zero length"));
    }
    // points: every waypoint, plus material nodes on each leg
    let mut pts: Vec<RoutePoint> = vec![(route[0].position, None)];
    for (k, w) in route.windows(2).enumerate() {
        let n = ((legs[k] / total * segments as f64).round() as usize).max(1);
        for i in 1..n {
            let f = i as f64 / n as f64;
            pts.push((w[0].position + (w[1].position - w[0].position) * f, None));
        }
        pts.push((w[1].position, w[1].contact));
    }
    let n = pts.len();
    let mut sigma = vec![0.0; n];
    for i in 1..n {
        sigma[i] = sigma[i - 1] + (pts[i].0 - pts[i - 1].0).norm() * length_factor;
    }
    let rho = props.mass_per_length;
    let mut nodes = Vec::with_capacity(n - 2);
    for i in 1..n - 1 {
        let mut m = 0.5 * rho * (sigma[i + 1] - sigma[i - 1]);
        if i == 1 {
            m += 0.5 * rho * sigma[1];
        }
        if i == n - 2 {
            m += 0.5 * rho * (sigma[n - 1] - sigma[n - 2]);
        }
        nodes.push(NodeSpec {
            mass: m,
            sigma: sigma[i],
            position: pts[i].0,
            velocity: Vec3::zeros(),
            contact: pts[i].1.map(|(block, edge, anchor)| NodeContact {
                block,
                edge,
                anchor,
                mode: if props.friction > 0.0 {
                    SlipMode::Stick
                } else {
                    SlipMode::SlipForward
                },
                mu_rope: props.friction,
                cap: super::structure::INITIAL_EDGE_CAPACITY,
            }),
        });
    }
    if nodes.is_empty() {
        return Err(format!(
            "rope '{name}': the route gives no interior node (use more segments)"
        ));
    }
    Ok(RopeSpec {
        name: name.into(),
        props,
        nominal_segment: total * length_factor / segments as f64,
        start,
        end,
        sigma_start: 0.0,
        sigma_end: sigma[n - 1],
        nodes,
    })
}
