//! Shell meshes: plate edges of the parametric block, mesh import, crossing detection, thin-shell
//! mass properties, all against hand-computed values.

use mbcosim::math::Vec3;
use mbcosim::rope::shell::detect::segment_crossing;
use mbcosim::rope::shell::import::{parse_obj, parse_stl};
use mbcosim::rope::shell::mass::shell_mass_properties;
use mbcosim::rope::shell::parametric::BlockShape;
use std::f64::consts::PI;

fn boxy() -> BlockShape {
    BlockShape {
        length: 18.0,
        breadth: 12.0,
        height: 7.0,
        bilge_radius: 0.0,
        bilge_facets: 1,
        both_bilges: false,
    }
}

#[test]
fn box_has_twelve_right_angle_edges() {
    let m = boxy().mesh().unwrap();
    assert_eq!(m.edges.len(), 12);
    for e in &m.edges {
        assert!((e.angle - 0.5 * PI).abs() < 1e-12);
        assert!(e.n1.dot(&e.n2).abs() < 1e-12);
    }
    let total: f64 = m.edges.iter().map(|e| e.length).sum();
    assert!((total - 4.0 * (18.0 + 12.0 + 7.0)).abs() < 1e-9);
}

#[test]
fn bilge_facets_are_plate_edges_of_equal_turn() {
    let shape = BlockShape {
        bilge_facets: 8,
        bilge_radius: 2.0,
        ..boxy()
    };
    let m = shape.mesh().unwrap();
    // 9 bilge edges of 90/8 deg, 3 remaining longitudinal box corners, 2 x (4 + 8) cap edges
    let longitudinal: Vec<_> = m.edges.iter().filter(|e| e.dir.x.abs() > 0.999).collect();
    assert_eq!(longitudinal.len(), 3 + 9);
    let small = longitudinal
        .iter()
        .filter(|e| (e.angle - PI / 16.0).abs() < 1e-9)
        .count();
    assert_eq!(small, 7, "interior bilge edges turn by 90/8 deg");
    assert_eq!(m.edges.len() - longitudinal.len(), 2 * (3 + 9));
}

#[test]
fn crossing_is_the_edge_point_nearest_to_the_segment() {
    let m = boxy().mesh().unwrap();
    // a segment cutting the corner of the top edge at y = +6, z = 7, slanted along x
    let p = Vec3::new(1.0, 6.6, 6.5);
    let q = Vec3::new(2.0, 4.0, 7.3);
    let mut scratch = Vec::new();
    let c = segment_crossing(&m, &p, &q, &[], 1e-9, 1.0, &mut scratch).expect("crossing");
    let e = &m.edges[c.edge];
    assert!((e.a.y - 6.0).abs() < 1e-12 && (e.a.z - 7.0).abs() < 1e-12);
    // independent closest point between the segment and the line y = 6, z = 7
    let d = q - p;
    // minimize (p_y + s d_y - 6)^2 + (p_z + s d_z - 7)^2
    let s = -((p.y - 6.0) * d.y + (p.z - 7.0) * d.z) / (d.y * d.y + d.z * d.z);
    let x = p.x + s * d.x;
    assert!(
        (c.point - Vec3::new(x, 6.0, 7.0)).norm() < 1e-12,
        "{:?}",
        c.point
    );
    assert!((c.s - s).abs() < 1e-12);
    // a segment passing above the edge does not cross it
    let p2 = Vec3::new(1.0, 7.0, 7.5);
    let q2 = Vec3::new(2.0, 5.0, 7.1);
    assert!(segment_crossing(&m, &p2, &q2, &[], 1e-9, 1.0, &mut scratch).is_none());
    // nor one beyond the end of the edge
    let p3 = Vec3::new(9.5, 6.6, 6.5);
    let q3 = Vec3::new(9.6, 4.0, 7.3);
    assert!(segment_crossing(&m, &p3, &q3, &[], 1e-9, 1.0, &mut scratch).is_none());
}

#[test]
fn thin_shell_box_inertia_matches_plate_sums() {
    // a 2 x 4 x 6 box of 6 plates, 88 m^2, 880 kg (10 kg/m^2)
    let shape = BlockShape {
        length: 2.0,
        breadth: 4.0,
        height: 6.0,
        ..boxy()
    };
    let m = shape.mesh().unwrap();
    let (com, j) = shell_mass_properties(&m, 880.0);
    assert!((com - Vec3::new(0.0, 0.0, 3.0)).norm() < 1e-12);
    // plate about the centre: I = m (a^2 + b^2)/12 (+ parallel axis)
    let (a, b, c) = (2.0, 4.0, 6.0);
    let rho = 10.0;
    let plate = |w: f64, h: f64| rho * w * h;
    // Ixx (axis along a): plates a x b at z = +-c/2, a x c at y = +-b/2, b x c at x = +-a/2
    let ixx = 2.0 * (plate(a, b) * (b * b / 12.0 + c * c / 4.0))
        + 2.0 * (plate(a, c) * (c * c / 12.0 + b * b / 4.0))
        + 2.0 * (plate(b, c) * (b * b + c * c) / 12.0);
    assert!(
        (j[(0, 0)] - ixx).abs() < 1e-9 * ixx,
        "{} vs {ixx}",
        j[(0, 0)]
    );
    assert!(j[(0, 1)].abs() < 1e-9 * ixx);
}

#[test]
fn obj_and_stl_imports_agree_with_the_parametric_box() {
    let m = boxy().mesh().unwrap();
    let mut obj = String::new();
    for v in &m.vertices {
        obj += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    for t in &m.triangles {
        obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    let o = parse_obj(&obj, 1.0).unwrap();
    assert_eq!(o.edges.len(), 12);
    let mut stl = String::from("solid b\n");
    let mut bin = vec![0u8; 80];
    bin.extend((m.triangles.len() as u32).to_le_bytes());
    for t in &m.triangles {
        stl += "facet normal 0 0 0\nouter loop\n";
        bin.extend([0u8; 12]);
        for &i in t {
            let v = m.vertices[i as usize];
            stl += &format!("vertex {} {} {}\n", v.x, v.y, v.z);
            for c in [v.x, v.y, v.z] {
                bin.extend((c as f32).to_le_bytes());
            }
        }
        stl += "endloop\nendfacet\n";
        bin.extend([0u8; 2]);
    }
    stl += "endsolid b\n";
    assert_eq!(parse_stl(stl.as_bytes(), 1.0).unwrap().edges.len(), 12);
    assert_eq!(parse_stl(&bin, 1.0).unwrap().edges.len(), 12);
    // bad input is refused with a message
    assert!(
        parse_stl(&bin[..100], 1.0)
            .unwrap_err()
            .contains("truncated")
    );
    assert!(
        parse_obj("v 0 0 0\nf 1 2 3\n", 1.0)
            .unwrap_err()
            .contains("face index")
    );
    assert!(parse_obj("v 0 0 x\n", 1.0).unwrap_err().contains("line 1"));
    assert!(parse_obj(&obj, f64::NAN).unwrap_err().contains("scale"));
}

#[test]
fn bad_shapes_are_refused() {
    let e = BlockShape {
        bilge_radius: 8.0,
        ..BlockShape::default()
    }
    .mesh()
    .unwrap_err();
    assert!(e.contains("bilge radius"), "{e}");
    let e = BlockShape {
        length: -1.0,
        ..BlockShape::default()
    }
    .mesh()
    .unwrap_err();
    assert!(e.contains("length"), "{e}");
}
