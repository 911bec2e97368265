//! Import of triangle meshes: Wavefront OBJ (text) and STL (ASCII or binary).
//!
//! OBJ: `v x y z` vertices and `f i j k ...` faces (polygons are fan-triangulated; indices may be
//! `i/t/n` and negative, relative to the end). STL stores each triangle's corners separately;
//! corners closer than `1e-9` of the model size are merged so that the plate edges can be found.
//! Lengths are taken as metres, multiplied by `scale`.

use super::{DEFAULT_MIN_EDGE_ANGLE, ShellMesh};
use crate::bounded_file::{self, FileKind};
use crate::math::Vec3;
use std::collections::HashMap;

/// Largest mesh file read: 256 MiB holds a binary STL of 5.3 million triangles, an OBJ of about
/// 4 million (docs/bounded_inputs.md).
pub const MESH_FILE_BYTES: u64 = 256 * 1024 * 1024;

/// A mesh file, for [`bounded_file`].
pub const MESH_FILE: FileKind = FileKind {
    what: "mesh file",
    max_bytes: MESH_FILE_BYTES,
    cap_name: "MESH_FILE_BYTES",
};

/// Most triangles a mesh may have (after fan triangulation of OBJ polygons): a block's shell
/// plate is a few thousand; a scanned hull some million (docs/bounded_inputs.md).
pub const MAX_MESH_TRIANGLES: usize = 4_000_000;

/// Most vertices an OBJ mesh may list.
pub const MAX_MESH_VERTICES: usize = 4_000_000;

/// `Err` naming the cap when `n` more `what` than `cap` were read.
fn over(n: usize, cap: usize, what: &str, cap_name: &str) -> Result<(), String> {
    if n > cap {
        Err(format!(
            "more than {cap} {what}, the cap on a mesh ({cap_name}; docs/bounded_inputs.md)"
        ))
    } else {
        Ok(())
    }
}

/// Parses OBJ text into a shell mesh (lengths multiplied by `scale`).
pub fn parse_obj(text: &str, scale: f64) -> Result<ShellMesh, String> {
    check_scale(scale)?;
    let mut v = Vec::new();
    let mut t = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it
                    .take(3)
                    .map(|s| s.parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|e| format!("OBJ line {}: bad vertex coordinate ({e})", ln + 1))?;
                if c.len() != 3 {
                    return Err(format!("OBJ line {}: a vertex needs 3 coordinates", ln + 1));
                }
                v.push(Vec3::new(c[0], c[1], c[2]) * scale);
                over(v.len(), MAX_MESH_VERTICES, "vertices", "MAX_MESH_VERTICES")
                    .map_err(|e| format!("OBJ line {}: {e}", ln + 1))?;
            }
            Some("f") => {
                let mut idx = Vec::new();
                for tok in it {
                    let first = tok.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| format!("OBJ line {}: bad face index '{tok}'", ln + 1))?;
                    let n = v.len() as i64;
                    let k = if i > 0 { i - 1 } else { n + i };
                    if !(0..n).contains(&k) {
                        return Err(format!(
                            "OBJ line {}: face index {i} outside the {n} vertices read so far",
                            ln + 1
                        ));
                    }
                    idx.push(k as u32);
                }
                if idx.len() < 3 {
                    return Err(format!(
                        "OBJ line {}: a face needs at least 3 vertices",
                        ln + 1
                    ));
                }
                over(
                    t.len() + idx.len() - 2,
                    MAX_MESH_TRIANGLES,
                    "triangles",
                    "MAX_MESH_TRIANGLES",
                )
                .map_err(|e| format!("OBJ line {}: {e}", ln + 1))?;
                for k in 1..idx.len() - 1 {
                    t.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    ShellMesh::new(v, t, DEFAULT_MIN_EDGE_ANGLE)
}

fn check_scale(scale: f64) -> Result<(), String> {
    if scale.is_finite() && scale > 0.0 {
        Ok(())
    } else {
        Err(format!("mesh scale must be finite and > 0, got {scale}"))
    }
}

/// Parses an STL file (ASCII if it starts with `solid` and contains `facet`, else binary).
pub fn parse_stl(bytes: &[u8], scale: f64) -> Result<ShellMesh, String> {
    check_scale(scale)?;
    let corners = if bytes.starts_with(b"solid")
        && std::str::from_utf8(bytes).is_ok_and(|s| s.contains("facet"))
    {
        stl_ascii(std::str::from_utf8(bytes).unwrap_or(""))?
    } else {
        stl_binary(bytes)?
    };
    weld(&corners, scale)
}

fn stl_ascii(text: &str) -> Result<Vec<[Vec3; 3]>, String> {
    let mut tris = Vec::new();
    let mut cur = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        if it.next() == Some("vertex") {
            let c: Vec<f64> = it
                .take(3)
                .map(|s| s.parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|e| format!("STL line {}: bad vertex ({e})", ln + 1))?;
            if c.len() != 3 {
                return Err(format!("STL line {}: a vertex needs 3 coordinates", ln + 1));
            }
            cur.push(Vec3::new(c[0], c[1], c[2]));
            if cur.len() == 3 {
                tris.push([cur[0], cur[1], cur[2]]);
                cur.clear();
                over(
                    tris.len(),
                    MAX_MESH_TRIANGLES,
                    "triangles",
                    "MAX_MESH_TRIANGLES",
                )
                .map_err(|e| format!("STL line {}: {e}", ln + 1))?;
            }
        }
    }
    if !cur.is_empty() {
        return Err("STL ends inside a facet".into());
    }
    Ok(tris)
}

fn stl_binary(b: &[u8]) -> Result<Vec<[Vec3; 3]>, String> {
    if b.len() < 84 {
        return Err(format!(
            "binary STL is truncated: {} bytes, the header alone needs 84",
            b.len()
        ));
    }
    let n = check_binary_count(b)?;
    let need = 84 + 50 * n;
    if b.len() < need {
        return Err(format!(
            "binary STL is truncated: {n} triangles need {need} bytes, got {}",
            b.len()
        ));
    }
    let f = |o: usize| f64::from(f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]));
    Ok((0..n)
        .map(|k| {
            let o = 84 + 50 * k + 12;
            std::array::from_fn(|c| {
                let p = o + 12 * c;
                Vec3::new(f(p), f(p + 4), f(p + 8))
            })
        })
        .collect())
}

/// The triangle count in the header of the binary STL `b` (at least 84 bytes), or `Err` when it
/// is over [`MAX_MESH_TRIANGLES`].
fn check_binary_count(b: &[u8]) -> Result<usize, String> {
    let n = u32::from_le_bytes([b[80], b[81], b[82], b[83]]) as usize;
    over(n, MAX_MESH_TRIANGLES, "triangles", "MAX_MESH_TRIANGLES")
        .map_err(|e| format!("binary STL header: {n} triangles: {e}"))?;
    Ok(n)
}

/// Merges coincident corners and builds the mesh.
fn weld(corners: &[[Vec3; 3]], scale: f64) -> Result<ShellMesh, String> {
    if corners.is_empty() {
        return Err("STL has no triangles".into());
    }
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    for c in corners.iter().flatten() {
        if !c.iter().all(|x| x.is_finite()) {
            return Err("STL has a non-finite vertex".into());
        }
        lo = lo.inf(c);
        hi = hi.sup(c);
    }
    let tol = 1e-9 * (hi - lo).norm().max(1e-300);
    let key = |p: &Vec3| {
        let q = (p - lo) / tol;
        (q.x.round() as i64, q.y.round() as i64, q.z.round() as i64)
    };
    let mut map: HashMap<(i64, i64, i64), u32> = HashMap::new();
    let mut v = Vec::new();
    let mut t = Vec::new();
    for tri in corners {
        let idx = tri.map(|p| {
            *map.entry(key(&p)).or_insert_with(|| {
                v.push(p * scale);
                (v.len() - 1) as u32
            })
        });
        if idx[0] != idx[1] && idx[1] != idx[2] && idx[0] != idx[2] {
            t.push(idx);
        }
    }
    ShellMesh::new(v, t, DEFAULT_MIN_EDGE_ANGLE)
}

/// Reads an OBJ or STL file (chosen by extension, case-insensitive), through
/// [`bounded_file`] (a regular file of at most [`MESH_FILE_BYTES`]).
pub fn load(path: &std::path::Path, scale: f64) -> Result<ShellMesh, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if ext == "stl" {
        // a binary STL's triangle count is refused from its header, before the file is read
        let head = bounded_file::read_head(path, &MESH_FILE, 84)?;
        if head.len() == 84 && !head.starts_with(b"solid") {
            check_binary_count(&head).map_err(|e| format!("mesh '{}': {e}", path.display()))?;
        }
    }
    let bytes = bounded_file::read_bytes(path, &MESH_FILE)?;
    match ext.as_str() {
        "obj" => parse_obj(
            std::str::from_utf8(&bytes)
                .map_err(|_| format!("mesh '{}' is not UTF-8 text", path.display()))?,
            scale,
        ),
        "stl" => parse_stl(&bytes, scale),
        _ => Err(format!(
            "mesh '{}': unknown format (expected .obj or .stl)",
            path.display()
        )),
    }
    .map_err(|e| format!("mesh '{}': {e}", path.display()))
}

#[cfg(test)]
#[path = "import_limits_tests.rs"]
mod limits_tests;
