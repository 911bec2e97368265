//! Checks of a rig against its block before anything is built: a mesh that is not closed, a lug
//! off the block, a sling shorter than its straight path or too short to reach its hook over the
//! block's edge (each refused with a named error), and a sling that passes through the block with
//! no contact node to carry it round (a warning).
//!
//! Geometry in the block's design frame [m]; hooks in the world frame; the block starts at
//! [`RopeBlockParams::block_origin`] and [`RopeBlockParams::block_orientation`].

use super::params::{RopeBlockParams, route_length};
use super::rig::LUG_TOLERANCE;
use crate::math::Vec3;
use crate::rope::shell::{ShellMesh, to_g};
use parry3d_f64::query::{PointQuery, Ray, RayCast};
use parry3d_f64::shape::Triangle;
use std::collections::HashMap;

/// A rig refused at set-up. Each variant's message starts with its name (`sling_too_short`, ...).
#[derive(Debug, Clone, PartialEq)]
pub enum RigError {
    /// The block mesh has edges used by one triangle (or more than two): a rope could slip
    /// through the hole, the mass properties assume a closed shell.
    MeshNotClosed { open_edges: usize, example: Vec3 },
    /// A lug farther than [`LUG_TOLERANCE`] from the shell plate (or inside the block).
    LugOffBlock { lug: usize, distance: f64 },
    /// Reaching the hook on the straight path would stretch the sling beyond its breaking load.
    SlingTooShort {
        sling: usize,
        length: f64,
        path: f64,
        tension: f64,
        breaking_load: f64,
    },
    /// The sling reaches its hook straight, but not round the block edge its path wraps.
    SlingCannotReach {
        sling: usize,
        length: f64,
        path: f64,
        tension: f64,
        breaking_load: f64,
    },
}

impl std::fmt::Display for RigError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RigError::MeshNotClosed {
                open_edges,
                example,
            } => write!(
                f,
                "mesh_not_closed: the block mesh has {open_edges} edges not shared by exactly two triangles (one near ({:.3}, {:.3}, {:.3}) m, design frame); a block shell must be closed",
                example.x, example.y, example.z
            ),
            RigError::LugOffBlock { lug, distance } => write!(
                f,
                "lug_off_block: lug {lug} is {distance:.3} m from the block's shell plate (at most {LUG_TOLERANCE} m: a lug sits on the plate)"
            ),
            RigError::SlingTooShort {
                sling,
                length,
                path,
                tension,
                breaking_load,
            } => write!(
                f,
                "sling_too_short: sling {sling} ({length:.3} m unstretched) is shorter than its straight path from lug to hook ({path:.3} m): reaching the hook would take {tension:.4e} N, above its breaking load {breaking_load:.4e} N; lengthen the sling or move the hook"
            ),
            RigError::SlingCannotReach {
                sling,
                length,
                path,
                tension,
                breaking_load,
            } => write!(
                f,
                "sling_cannot_reach: sling {sling} ({length:.3} m unstretched) cannot reach its hook over the block edge its path wraps ({path:.3} m from lug to hook): that would take {tension:.4e} N, above its breaking load {breaking_load:.4e} N; lengthen the sling, move the hook or the lug"
            ),
        }
    }
}

/// Checks `p`'s rig against its block (loaded from the rig). `Ok` carries the warnings (a
/// sling that passes through the block without contact).
pub fn check_rig(p: &RopeBlockParams) -> Result<Vec<String>, String> {
    p.validate()?;
    let design = p.design_mesh()?;
    check_rig_with(p, &design)
}

/// [`check_rig`] with the design-frame mesh already loaded.
pub fn check_rig_with(p: &RopeBlockParams, design: &ShellMesh) -> Result<Vec<String>, String> {
    check_lugs_and_slings(p, design).map_err(|e| match e {
        Refusal::Rig(e) => e.to_string(),
        Refusal::Other(e) => e,
    })
}

enum Refusal {
    Rig(RigError),
    Other(String),
}

impl From<RigError> for Refusal {
    fn from(e: RigError) -> Self {
        Refusal::Rig(e)
    }
}

fn check_lugs_and_slings(p: &RopeBlockParams, design: &ShellMesh) -> Result<Vec<String>, Refusal> {
    check_closed(design)?;
    for (k, l) in p.rig.lugs.iter().enumerate() {
        let d = distance_to_mesh(design, &l.position);
        if d > LUG_TOLERANCE {
            return Err(RigError::LugOffBlock {
                lug: k,
                distance: d,
            }
            .into());
        }
    }
    let (com, _, _) = p.mass_properties(design);
    let mesh = design.translated(&(-com)).map_err(Refusal::Other)?;
    let position = p.block_origin + p.block_orientation * com;
    let hooks = p.rig.hook_positions();
    let mut warnings = Vec::new();
    for (k, s) in p.rig.slings.iter().enumerate() {
        let props = s.props(&p.rope);
        let lug = p.block_origin + p.block_orientation * p.rig.lugs[s.lug].position;
        let straight = (hooks[s.hook] - lug).norm();
        let Ok(route) = p.route(k, &mesh, position, com, &hooks) else {
            continue; // a bad via point is refused, with its message, when the scene is built
        };
        let path = route_length(&route);
        let length = s.length.unwrap_or(s.length_factor * path);
        let pull = |path: f64| props.ea * (path / length - 1.0);
        if pull(straight) > props.breaking_load {
            return Err(RigError::SlingTooShort {
                sling: k,
                length,
                path: straight,
                tension: pull(straight),
                breaking_load: props.breaking_load,
            }
            .into());
        }
        if route.len() > 2 && pull(path) > props.breaking_load {
            return Err(RigError::SlingCannotReach {
                sling: k,
                length,
                path,
                tension: pull(path),
                breaking_load: props.breaking_load,
            }
            .into());
        }
        if p.contact {
            let inv = p.block_orientation.inverse();
            let to_design = |x: Vec3| inv * (x - p.block_origin);
            let crosses = route.windows(2).any(|w| {
                segment_crosses(design, &to_design(w[0].position), &to_design(w[1].position))
            });
            if crosses {
                warnings.push(format!(
                    "sling {k} passes through the block from lug {} to hook {} without a contact node (no plate edge found to wrap: is the lug outside the shell, on the hook's side?); it will run through the plates",
                    s.lug, s.hook
                ));
            }
        }
    }
    Ok(warnings)
}

/// `Err` when some mesh edge is not shared by exactly two triangles.
fn check_closed(mesh: &ShellMesh) -> Result<(), RigError> {
    let mut count: HashMap<(u32, u32), usize> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (i, j) = (t[k], t[(k + 1) % 3]);
            *count.entry((i.min(j), i.max(j))).or_default() += 1;
        }
    }
    let mut open: Vec<(u32, u32)> = count
        .into_iter()
        .filter(|(_, n)| *n != 2)
        .map(|(e, _)| e)
        .collect();
    open.sort_unstable();
    match open.first() {
        None => Ok(()),
        Some(&(i, j)) => Err(RigError::MeshNotClosed {
            open_edges: open.len(),
            example: 0.5 * (mesh.vertices[i as usize] + mesh.vertices[j as usize]),
        }),
    }
}

/// Distance [m] from `p` to the nearest point of the mesh surface.
pub fn distance_to_mesh(mesh: &ShellMesh, p: &Vec3) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| distance_to_triangle(p, t.map(|i| mesh.vertices[i as usize])))
        .fold(f64::INFINITY, f64::min)
}

/// Distance [m] from `p` to the triangle `abc` (parry3d-f64's point projection).
fn distance_to_triangle(p: &Vec3, [a, b, c]: [Vec3; 3]) -> f64 {
    Triangle::new(to_g(&a), to_g(&b), to_g(&c)).distance_to_local_point(to_g(p), true)
}

/// True when the segment `p q` (design frame) cuts a triangle of `mesh` away from its ends
/// (more than 1 cm from either: a lug or an edge point on the plate does not count); the
/// crossing is parry3d-f64's ray cast along the segment.
fn segment_crosses(mesh: &ShellMesh, p: &Vec3, q: &Vec3) -> bool {
    let d = q - p;
    let len = d.norm();
    if len < 0.02 {
        return false;
    }
    let margin = 0.01 / len;
    let ray = Ray::new(to_g(p), to_g(&d));
    mesh.triangles.iter().any(|t| {
        let [a, b, c] = t.map(|i| to_g(&mesh.vertices[i as usize]));
        Triangle::new(a, b, c)
            .cast_local_ray(&ray, 1.0 - margin, true)
            .is_some_and(|toi| toi > margin)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_a_triangle_from_each_region() {
        let abc = [
            Vec3::zeros(),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let d = |p: Vec3| distance_to_triangle(&p, abc);
        // above the face, nearest to vertex a, to vertex b, to the edge bc
        assert!((d(Vec3::new(0.2, 0.2, 3.0)) - 3.0).abs() < 1e-15);
        assert!((d(Vec3::new(-1.0, -1.0, 0.0)) - 2f64.sqrt()).abs() < 1e-15);
        assert!((d(Vec3::new(2.0, -0.1, 0.0)) - 1.01f64.sqrt()).abs() < 1e-15);
        assert!((d(Vec3::new(1.0, 1.0, 0.0)) - 0.5f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn a_segment_crosses_a_triangle_only_away_from_its_ends() {
        let mesh = ShellMesh::new(
            vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2]],
            0.1,
        )
        .unwrap();
        let z = |h: f64| Vec3::new(0.0, 0.0, h);
        assert!(segment_crosses(&mesh, &z(-1.0), &z(1.0)));
        // an end on the plate (a lug) or within 1 cm of it does not count
        assert!(!segment_crosses(&mesh, &z(0.0), &z(1.0)));
        assert!(!segment_crosses(&mesh, &z(-0.005), &z(1.0)));
        // beside the triangle, or short of it
        assert!(!segment_crosses(
            &mesh,
            &Vec3::new(3.0, 0.0, -1.0),
            &Vec3::new(3.0, 0.0, 1.0)
        ));
        assert!(!segment_crosses(&mesh, &z(-2.0), &z(-0.5)));
    }
}
