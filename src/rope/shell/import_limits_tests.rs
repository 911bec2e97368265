//! The mesh importer's caps: a file that is no regular file is never read, and vertex and
//! triangle counts past their caps are refused with the cap named (docs/bounded_inputs.md).

use super::*;

#[test]
fn devices_and_fifos_are_not_meshes() {
    for dev in ["/dev/zero", "/dev/urandom"] {
        let e = load(std::path::Path::new(dev), 1.0).unwrap_err();
        assert!(
            e.contains("mesh file") && e.contains(dev) && e.contains("character device"),
            "{e}"
        );
    }
}

#[test]
fn a_binary_stl_that_claims_too_many_triangles_is_refused_by_its_header() {
    let mut b = vec![0u8; 84];
    b[80..84].copy_from_slice(&(MAX_MESH_TRIANGLES as u32 + 1).to_le_bytes());
    let e = parse_stl(&b, 1.0).unwrap_err();
    assert!(
        e.contains("MAX_MESH_TRIANGLES") && e.contains(&MAX_MESH_TRIANGLES.to_string()),
        "{e}"
    );
}

#[test]
fn an_obj_past_the_triangle_or_vertex_cap_is_refused_at_that_line() {
    // one polygon of MAX + 2 corners fans into MAX triangles: accepted count, then one more
    let corners = |n: usize| {
        let mut s = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
        for k in 0..n {
            s.push_str([" 1", " 2", " 3"][k % 3]);
        }
        s.push('\n');
        s
    };
    let e = parse_obj(&corners(MAX_MESH_TRIANGLES + 3), 1.0).unwrap_err();
    assert!(
        e.contains("OBJ line 4") && e.contains("MAX_MESH_TRIANGLES"),
        "{e}"
    );
    let mut many = String::with_capacity(8 * (MAX_MESH_VERTICES + 1));
    for _ in 0..=MAX_MESH_VERTICES {
        many.push_str("v 0 0 0\n");
    }
    let e = parse_obj(&many, 1.0).unwrap_err();
    assert!(
        e.contains(&format!("OBJ line {}", MAX_MESH_VERTICES + 1))
            && e.contains("MAX_MESH_VERTICES"),
        "{e}"
    );
}
