//! Tests of [`ModalBodyData`] built from a plate: exact invariants, mean-axis property of
//! free-interface modes, Craig-Bampton frame clamp, node kinematics and input checks.

use nalgebra::{DMatrix, DVector};

use super::body::{ModalBodyData, ModalBodyParts};
use super::eigen::generalized_eigenvalues;
use super::invariants_tests::{Rng, point_at};
use super::plate::{PanelSpec, PlateModel};
use super::reduce::{RigidModes, free_interface};
use crate::math::{Mat3, Vec3, exp_so3};

fn spec() -> PanelSpec {
    PanelSpec {
        a: 2.0,
        b: 1.0,
        thickness: 0.025,
        youngs_modulus: 1.2e9,
        poisson: 0.3,
        density: 60.0,
        non_structural_mass: 1.2,
    }
}

#[test]
fn consistent_invariants_are_exact_rectangle_integrals() {
    let s = spec();
    let p = PlateModel::new(&s, 6, 3).unwrap();
    let body = ModalBodyData::from_free_interface(&p, 4, 0.0, &[]).unwrap();
    let inv = body.invariants();
    let mu = s.areal_mass();
    let (a, b) = (s.a, s.b);
    let m = mu * a * b;
    assert!((inv.mass - m).abs() < 1e-12 * m);
    let sx = Vec3::new(m * a / 2.0, m * b / 2.0, 0.0);
    assert!((inv.first_moment - sx).norm() < 1e-12 * sx.norm());
    // About the corner: Jxx = m b^2/3, Jyy = m a^2/3, Jzz = Jxx + Jyy, Jxy = -m a b / 4.
    let j = Mat3::new(
        m * b * b / 3.0,
        -m * a * b / 4.0,
        0.0,
        -m * a * b / 4.0,
        m * a * a / 3.0,
        0.0,
        0.0,
        0.0,
        m * (a * a + b * b) / 3.0,
    );
    assert!((inv.inertia - j).norm() < 1e-12 * j.norm());
    // Modal mass block equals tr(P_ij) and the reduced mass (identity for free modes).
    let n = inv.n_modes();
    for i in 0..n {
        for k in 0..n {
            assert!((inv.p[i * n + k].trace() - body.mass()[(i, k)]).abs() < 1e-12);
        }
    }
    assert!((body.mass() - DMatrix::identity(n, n)).amax() < 1e-10);
}

#[test]
fn free_interface_modes_satisfy_mean_axis_conditions() {
    let p = PlateModel::new(&spec(), 8, 4).unwrap();
    let body = ModalBodyData::from_free_interface(&p, 6, 0.01, &[0]).unwrap();
    let inv = body.invariants();
    // |1^T M phi| <= sqrt(m) for mass-normalized phi: compare against that scale.
    assert!(inv.c_t.amax() < 1e-9 * inv.mass.sqrt(), "{}", inv.c_t);
    let jmax = inv.inertia.amax().sqrt();
    assert!(inv.c_r().amax() < 1e-9 * jmax, "{}", inv.c_r());
    // Out-of-plane shapes: no gyroscopic coupling between modes.
    assert!((0..6).all(|i| (0..6).all(|j| inv.phi_tilde_phi(i, j).norm() == 0.0)));
    // Frequencies of the body are the first elastic free-free ones.
    let full = generalized_eigenvalues(p.stiffness(), p.mass(), &[], 9).unwrap();
    let f = body.frequencies_hz().unwrap();
    for (fi, l) in f.iter().zip(&full[3..]) {
        let fr = l.sqrt() / (2.0 * std::f64::consts::PI);
        assert!((fi / fr - 1.0).abs() < 1e-9);
    }
}

#[test]
fn lumped_node_sums_converge_to_consistent_invariants_at_second_order() {
    let mut prev = None;
    for n in [4, 8, 16] {
        let p = PlateModel::new(&spec(), n, n / 2).unwrap();
        let body = ModalBodyData::from_free_interface(&p, 1, 0.0, &[]).unwrap();
        let lumped = body.node_sum_invariants().unwrap();
        let exact = body.invariants();
        assert!((lumped.mass - exact.mass).abs() < 1e-12 * exact.mass);
        assert!((lumped.first_moment - exact.first_moment).norm() < 1e-12 * exact.mass);
        let err = (lumped.inertia - exact.inertia).norm() / exact.inertia.norm();
        if let Some(e_prev) = prev {
            let ratio: f64 = e_prev / err;
            assert!((ratio - 4.0).abs() < 0.2, "ratio {ratio}");
        }
        prev = Some(err);
    }
}

#[test]
fn craig_bampton_body_is_clamped_at_its_frame_node() {
    let p = PlateModel::new(&spec(), 8, 4).unwrap();
    let h0 = p.node_index(0, 1).unwrap();
    let h1 = p.node_index(0, 3).unwrap();
    let tip = p.node_index(8, 2).unwrap();
    let body = ModalBodyData::from_craig_bampton(&p, h0, &[h0, h1, tip], 20, 0.02).unwrap();
    // Other attachment nodes' DOFs (2 x 3) plus 20 fixed-interface modes.
    assert_eq!(body.n_modes(), 26);
    assert_eq!(body.attachment_nodes(), &[h0, h1, tip]);
    assert_eq!(body.translational_shapes()[h0].amax(), 0.0);
    assert_eq!(body.rotational_shapes()[h0].amax(), 0.0);
    // The first CB coordinate is w of h1: unit translational shape there.
    assert_eq!(body.translational_shapes()[h1][(2, 0)], 1.0);
    assert_eq!(body.rotational_shapes()[h1][(0, 1)], 1.0);
    // Frequencies approach the full model clamped at the frame node from above.
    let full =
        generalized_eigenvalues(p.stiffness(), p.mass(), &p.node_dofs(h0).unwrap(), 4).unwrap();
    let f = body.frequencies_hz().unwrap();
    for (fi, l) in f.iter().zip(&full) {
        let fr = l.sqrt() / (2.0 * std::f64::consts::PI);
        let e = fi / fr - 1.0;
        assert!((-1e-9..1e-3).contains(&e), "{e}");
    }
    // Node kinematics.
    let a = DVector::from_fn(26, |i, _| 1e-3 * (i as f64 + 1.0).sin());
    let u = body.node_position(h1, &a).unwrap();
    assert!((u - (body.positions()[h1] + Vec3::new(0.0, 0.0, a[0]))).norm() < 1e-15);
    let th = body.node_rotation(h1, &a).unwrap();
    assert!((th - Vec3::new(a[1], a[2], 0.0)).norm() < 1e-15);
    let b = body
        .node_velocity_jacobian(tip, &Mat3::identity(), &a)
        .unwrap();
    assert_eq!(b.shape(), (3, 32));
    let g = body.node_angular_velocity_jacobian(tip).unwrap();
    assert_eq!(g[(0, 3)], 1.0);
    let f_el = body.elastic_force(&a, &DVector::zeros(26)).unwrap();
    assert!((&f_el + body.stiffness() * &a).norm() < 1e-12 * f_el.norm());
    // Floating-frame mass matrix is symmetric positive definite at a = 0.
    let m0 = body
        .invariants()
        .mass_matrix(&Mat3::identity(), &DVector::zeros(26))
        .unwrap();
    assert!((&m0 - m0.transpose()).amax() == 0.0);
    assert!(m0.clone().cholesky().is_some());
}

#[test]
fn body_constructors_reject_bad_input() {
    let p = PlateModel::new(&spec(), 4, 2).unwrap();
    let nn = p.n_nodes();
    let e = ModalBodyData::from_free_interface(&p, 3, 0.0, &[nn]).unwrap_err();
    assert!(
        e.to_string().contains(&format!("node {nn} out of range")),
        "{e}"
    );
    let e = ModalBodyData::from_craig_bampton(&p, nn + 4, &[0], 3, 0.0).unwrap_err();
    assert!(e.to_string().contains("out of range"), "{e}");
    let e = ModalBodyData::from_free_interface(&p, 3 * nn, 0.0, &[]).unwrap_err();
    assert!(e.to_string().contains("elastic modes"), "{e}");
    let e = ModalBodyData::from_free_interface(&p, 3, f64::NAN, &[]).unwrap_err();
    assert!(e.to_string().contains("zeta"), "{e}");
    // Keeping rigid modes duplicates the frame's motion: M(0) singular.
    let red = free_interface(p.stiffness(), p.mass(), &[], 3, RigidModes::Keep, 0.0).unwrap();
    let e = ModalBodyData::from_reduced(&p, &red, &[]).unwrap_err();
    assert!(
        e.to_string().contains("duplicate a rigid-body motion"),
        "{e}"
    );
    // Raw constructor: duplicate attachment, mismatched counts, asymmetric stiffness.
    let good = ModalBodyData::from_free_interface(&p, 2, 0.0, &[0]).unwrap();
    let parts = || ModalBodyParts {
        positions: good.positions().to_vec(),
        node_masses: good.node_masses().to_vec(),
        translational_shapes: good.translational_shapes().to_vec(),
        rotational_shapes: good.rotational_shapes().to_vec(),
        mass: good.mass().clone(),
        stiffness: good.stiffness().clone(),
        damping: good.damping().clone(),
        attachment_nodes: vec![0],
        invariants: Some(good.invariants().clone()),
    };
    assert_eq!(ModalBodyData::new(parts()).unwrap(), good);
    // Node-sum invariants need a modal mass equal to the node sums (here it is consistent).
    let mut bad = parts();
    bad.invariants = None;
    let e = ModalBodyData::new(bad).unwrap_err();
    assert!(e.to_string().contains("node sums"), "{e}");
    let mut bad = parts();
    bad.attachment_nodes = vec![1, 1];
    let e = ModalBodyData::new(bad).unwrap_err();
    assert!(e.to_string().contains("listed twice"), "{e}");
    let mut bad = parts();
    bad.node_masses.pop();
    let e = ModalBodyData::new(bad).unwrap_err();
    assert!(e.to_string().contains("counts must agree"), "{e}");
    let mut bad = parts();
    bad.stiffness[(0, 1)] = 1.0;
    let e = ModalBodyData::new(bad).unwrap_err();
    assert!(e.to_string().contains("not symmetric"), "{e}");
    let mut bad = parts();
    bad.mass[(1, 1)] = -1.0;
    let e = ModalBodyData::new(bad).unwrap_err();
    assert!(e.to_string().contains("not positive definite"), "{e}");
}

/// Node kinematics of a body against finite differences along y(t) = y0 + t y1.
#[test]
fn node_accelerations_match_finite_differences() {
    let p = PlateModel::new(&spec(), 4, 2).unwrap();
    let h0 = p.node_index(0, 0).unwrap();
    let h1 = p.node_index(0, 2).unwrap();
    let tip = p.node_index(4, 1).unwrap();
    let body = ModalBodyData::from_craig_bampton(&p, h0, &[h0, h1, tip], 4, 0.0).unwrap();
    let n = body.n_modes();
    let mut rng = Rng(7);
    let rot = exp_so3(&rng.vec3()).to_rotation_matrix().into_inner();
    let a0 = 0.01 * rng.dvec(n);
    let y0 = rng.dvec(6 + n);
    let y1 = rng.dvec(6 + n);
    let omega = Vec3::new(y0[3], y0[4], y0[5]);
    let a_dot = y0.rows(6, n).into_owned();
    let h = 1e-4;
    for k in [h1, tip] {
        let phi = &body.translational_shapes()[k];
        let rho = body.positions()[k];
        let pos = |t| point_at(t, &rot, &rho, phi, &y0, &y1, &a0);
        let acc_fd = (pos(h) - 2.0 * pos(0.0) + pos(-h)) / (h * h);
        let b = body.node_velocity_jacobian(k, &rot, &a0).unwrap();
        let w = body
            .node_acceleration_bias(k, &rot, &a0, &omega, &a_dot)
            .unwrap();
        let acc = &b * &y1;
        let acc = Vec3::new(acc[0], acc[1], acc[2]) + w;
        assert!((acc - acc_fd).norm() < 1e-5 * acc.norm(), "node {k}");
        // World angular velocity A (omega + Psi a_dot) along the same path.
        let psi = &body.rotational_shapes()[k];
        let ang = |t: f64| {
            let w_t = Vec3::new(y0[3] + t * y1[3], y0[4] + t * y1[4], y0[5] + t * y1[5]);
            let ad_t = y0.rows(6, n) + t * y1.rows(6, n);
            let th = omega * t + 0.5 * Vec3::new(y1[3], y1[4], y1[5]) * t * t;
            let r_t = rot * exp_so3(&th).to_rotation_matrix().into_inner();
            r_t * (w_t + psi * ad_t)
        };
        let alpha_fd = (ang(h) - ang(-h)) / (2.0 * h);
        let g = body.node_angular_velocity_jacobian(k).unwrap();
        let gy = &g * &y1;
        let alpha = rot * Vec3::new(gy[0], gy[1], gy[2])
            + body
                .node_angular_acceleration_bias(k, &rot, &omega, &a_dot)
                .unwrap();
        assert!((alpha - alpha_fd).norm() < 1e-6 * alpha.norm(), "node {k}");
    }
}
