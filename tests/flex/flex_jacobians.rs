//! Finite-difference checks of the flexible-body terms: joint rows at flexible-body nodes (G with
//! its modal columns, Phi_t, gamma), the modal bodies' force Jacobians (K = -df/dx, D = -df/dv:
//! quadratic-velocity, elastic, damping, gravity) and the mass matrix blocks (assembled M(a) equal
//! to `mass_mul`, symmetric, and equal to the invariants' `M(a)`).

use crate::common;
use common::flex::panel;
use common::jacobian::{assembled, force_jacobian_mismatch};
use mbcosim::dae::System;
use mbcosim::flex::ModalBodyData;
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::*;
use std::sync::Arc;

/// Two Craig-Bampton panels (frame node 0, interface node `k1`, 2 fixed-interface modes) and a
/// rigid body, in general poses, deformed and moving; joints of `kind` from a node of panel 1 to
/// the rigid body, and from the rigid body to a node of panel 2 (frames with offsets and tilted
/// axes); a spring from the ground to panel 1's frame; gravity.
fn flexible_model(kind: JointKind) -> (Model, Arc<ModalBodyData>) {
    let plate = panel(4, 2);
    let (k1, k2) = (
        plate.node_index(4, 2).unwrap(),
        plate.node_index(2, 1).unwrap(),
    );
    let data = Arc::new(ModalBodyData::from_craig_bampton(&plate, 0, &[0, k1], 2, 0.02).unwrap());
    let n = data.n_modes();
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.1, -9.81, 0.3))).unwrap();
    let a0: Vec<f64> = (0..n).map(|i| 0.03 * (1.0 - 0.4 * i as f64)).collect();
    let ad0: Vec<f64> = (0..n)
        .map(|i| 0.2 * (-1.0f64).powi(i as i32) + 0.05)
        .collect();
    let p1 = b
        .add_modal_body(
            "p1",
            data.clone(),
            BodyInit::at(Vec3::new(0.2, -0.1, 0.3))
                .oriented(Quat::from_euler_angles(0.3, -0.4, 0.8))
                .moving(Vec3::new(0.3, -0.2, 0.5), Vec3::new(0.7, -1.1, 0.4)),
            &a0,
            &ad0,
        )
        .unwrap();
    let p2 = b
        .add_modal_body(
            "p2",
            data.clone(),
            BodyInit::at(Vec3::new(-1.0, 0.5, 0.2))
                .oriented(Quat::from_euler_angles(-0.2, 0.5, -0.7))
                .moving(Vec3::new(-0.1, 0.4, 0.2), Vec3::new(-0.3, 0.6, -0.9)),
            &ad0,
            &a0,
        )
        .unwrap();
    let inertia = Mat3::new(2.0, 0.1, -0.2, 0.1, 3.0, 0.15, -0.2, 0.15, 2.5);
    let r = b
        .add_rigid_body(
            "r",
            1.5,
            inertia,
            BodyInit::at(Vec3::new(1.3, 0.4, -0.2))
                .oriented(Quat::from_euler_angles(-0.6, 0.2, 1.4))
                .moving(Vec3::new(-0.4, 0.1, 0.2), Vec3::new(-0.5, 0.9, 1.3)),
        )
        .unwrap();
    let ax = Vec3::new(0.3, 0.4, 0.86);
    b.add_joint(
        "j1",
        kind,
        Frame::with_z(p1, Vec3::new(0.05, -0.02, 0.03), ax).on_node(k1),
        Frame::with_z(r, Vec3::new(-0.3, 0.2, 0.1), ax),
    )
    .unwrap();
    b.add_joint(
        "j2",
        kind,
        Frame::with_z(r, Vec3::new(0.2, 0.1, -0.1), Vec3::new(-0.2, 0.5, 0.8)),
        Frame::with_z(p2, Vec3::new(-0.04, 0.02, 0.01), Vec3::new(0.1, -0.3, 0.9)).on_node(k2),
    )
    .unwrap();
    b.add_spring_damper(SpringDamper {
        name: "s0".into(),
        a: Frame::new(BodyId::GROUND, Vec3::new(0.0, 1.0, 0.0)),
        b: Frame::new(p1, Vec3::new(0.3, -0.1, 0.2)),
        stiffness: 50.0,
        damping: 3.0,
        free_length: 0.5,
    })
    .unwrap();
    // force elements at nodes (node bodies)
    b.add_spring_damper(SpringDamper {
        name: "sn".into(),
        a: Frame::new(p1, Vec3::new(0.02, 0.01, -0.03)).on_node(k2),
        b: Frame::new(r, Vec3::new(0.1, -0.2, 0.05)),
        stiffness: 80.0,
        damping: 4.0,
        free_length: 0.3,
    })
    .unwrap();
    b.add_spring_damper(SpringDamper {
        name: "nn".into(),
        a: Frame::at_node(p1, k1),
        b: Frame::at_node(p2, k1),
        stiffness: 30.0,
        damping: 2.0,
        free_length: 0.2,
    })
    .unwrap();
    b.add_torsion_spring(TorsionSpring {
        name: "t".into(),
        frame_i: Frame::with_z(p1, Vec3::zeros(), ax).on_node(k1),
        frame_j: Frame::with_z(r, Vec3::zeros(), Vec3::new(0.2, 0.5, 0.84)),
        stiffness: 30.0,
        damping: 2.0,
        free_angle: 0.7,
        angle_offset: 0.1,
    })
    .unwrap();
    let sine = Profile::Sine {
        offset: 3.0,
        amplitude: 1.0,
        omega: 2.0,
        phase: 0.1,
    };
    b.add_applied_load(AppliedLoad {
        name: "l".into(),
        at: Frame::new(p2, Vec3::new(0.01, 0.02, 0.0)).on_node(k2),
        force_direction: Vec3::new(1.0, 2.0, -0.5),
        force: sine,
        torque_direction: Vec3::new(0.2, -0.1, 1.0),
        torque: sine,
    })
    .unwrap();
    b.add_joint_torque(JointTorque {
        name: "m".into(),
        frame_i: Frame::with_z(r, Vec3::zeros(), ax),
        frame_j: Frame::with_z(p2, Vec3::zeros(), Vec3::new(-0.1, 0.3, 0.95)).on_node(k2),
        torque: sine,
    })
    .unwrap();
    (b.build().unwrap(), data)
}

#[test]
fn joint_rows_at_flexible_nodes_match_finite_differences() {
    let kinds = [
        JointKind::Revolute,
        JointKind::Spherical,
        JointKind::Fixed,
        JointKind::Prismatic,
        JointKind::TranslationDrive(Profile::Sine {
            offset: 0.1,
            amplitude: 0.2,
            omega: 3.0,
            phase: 0.4,
        }),
    ];
    for kind in kinds {
        let (model, _) = flexible_model(kind);
        let mut sys = System::new(Arc::new(model.clone())).unwrap();
        let (q, v) = (model.q0.clone(), model.v0.clone());
        let n = sys.n_v();
        let t = 0.3;
        sys.eval_constraints(t, &q, &v);
        let rows = sys.rows.clone();
        let nc = rows.len();
        assert_eq!(nc, 2 * kind.n_rows());
        let eps = 1e-6;
        let phi_at = |sys: &mut System, q: &[f64], t: f64| {
            sys.eval_constraints(t, q, &v);
            sys.rows.iter().map(|r| r.phi).collect::<Vec<_>>()
        };
        let mut worst: f64 = 0.0;
        let mut modal_max: f64 = 0.0;
        for j in 0..n {
            let mut dx = vec![0.0; n];
            dx[j] = eps;
            let (mut qp, mut qm) = (q.clone(), q.clone());
            model.retract(&q, &dx, &mut qp);
            dx[j] = -eps;
            model.retract(&q, &dx, &mut qm);
            let pp = phi_at(&mut sys, &qp, t);
            let pm = phi_at(&mut sys, &qm, t);
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            sys.eval_constraints(t, &q, &v);
            let mut ge = vec![0.0; nc];
            sys.g_mul(&e, &mut ge);
            // the transpose product agrees with the product
            let mut gt = vec![0.0; n];
            for r in 0..nc {
                let mut y = vec![0.0; nc];
                y[r] = 1.0;
                gt.fill(0.0);
                sys.gt_mul_add(&y, &mut gt);
                assert!((gt[j] - ge[r]).abs() < 1e-14);
            }
            let is_modal = model.bodies.iter().any(|b| {
                b.kind.n_modes() > 0 && (b.v_offset + 6..b.v_offset + b.kind.n_v()).contains(&j)
            });
            for r in 0..nc {
                let fd = (pp[r] - pm[r]) / (2.0 * eps);
                worst = worst.max((fd - ge[r]).abs());
                if is_modal {
                    modal_max = modal_max.max(ge[r].abs());
                }
            }
        }
        println!(
            "{kind:?}: worst |G - fd| {worst:.3e}, largest modal column entry {modal_max:.3e}"
        );
        assert!(worst < 1e-8, "{kind:?}: worst G mismatch {worst:.3e}");
        assert!(
            modal_max > 1e-2,
            "{kind:?}: modal columns must be exercised"
        );
        let pp = phi_at(&mut sys, &q, t + eps);
        let pm = phi_at(&mut sys, &q, t - eps);
        for r in 0..nc {
            let fd = (pp[r] - pm[r]) / (2.0 * eps);
            assert!((fd - rows[r].phi_t).abs() < 1e-7, "{kind:?}: Phi_t[{r}]");
        }
        // gamma: along q(s) = q ⊕ s v, t + s (v_dot = 0, so a_ddot = 0 and omega_dot = 0)
        let h = 1e-4;
        let path = |sys: &mut System, s: f64| {
            let dx: Vec<f64> = v.iter().map(|x| x * s).collect();
            let mut qs = q.clone();
            model.retract(&q, &dx, &mut qs);
            phi_at(sys, &qs, t + s)
        };
        let (p1, p0, m1) = (path(&mut sys, h), path(&mut sys, 0.0), path(&mut sys, -h));
        let mut gworst: f64 = 0.0;
        for r in 0..nc {
            let second = (p1[r] - 2.0 * p0[r] + m1[r]) / (h * h);
            gworst = gworst.max((second + rows[r].gamma).abs() / (1.0 + second.abs()));
            assert!(
                (second + rows[r].gamma).abs() < 1e-5 * (1.0 + second.abs()),
                "{kind:?}: gamma[{r}] {} vs -Phi'' {}",
                rows[r].gamma,
                -second
            );
        }
        println!("{kind:?}: worst gamma mismatch {gworst:.3e} (relative)");
    }
}

#[test]
fn modal_force_jacobians_and_mass_matrix_are_consistent() {
    let (model, data) = flexible_model(JointKind::Revolute);
    let mut sys = System::new(Arc::new(model.clone())).unwrap();
    let (q, v) = (model.q0.clone(), model.v0.clone());
    let n = sys.n_v();
    let m_an = assembled(&mut sys, 0.3, &q, &v, [1.0, 0.0, 0.0]);
    let (worst, scale) = force_jacobian_mismatch(&model, &mut sys, 0.3, &q, &v, 1e-6);
    println!("K/D: worst mismatch {worst:.3e}, scale {scale:.3e}");
    assert!(
        worst < 1e-8 * scale,
        "worst K/D mismatch {worst:.3e} (scale {scale:.3e})"
    );
    // mass matrix: assembled = mass_mul columns = invariants' M(a) on each modal block, symmetric
    sys.update_kinematics(&q, &v);
    for j in 0..n {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        let mut col = vec![0.0; n];
        sys.mass_mul(&e, &mut col);
        for i in 0..n {
            assert!((col[i] - m_an[(i, j)]).abs() < 1e-9 * (1.0 + col[i].abs()));
        }
    }
    assert!((&m_an - m_an.transpose()).amax() < 1e-9 * m_an.amax());
    let nm = data.n_modes();
    for b in model.bodies.iter().filter(|b| b.kind.n_modes() > 0) {
        let (qo, vo) = (b.q_offset, b.v_offset);
        let s = common::flex::modal_state(&q, &v, qo, vo, nm);
        let m = data.invariants().mass_matrix(&s.rot, &s.a).unwrap();
        let blk = m_an.view((vo, vo), (6 + nm, 6 + nm));
        assert!(
            (blk - &m).amax() < 1e-9 * m.amax(),
            "{}: M(a) block",
            b.name
        );
    }
}

#[test]
fn frames_on_missing_nodes_and_unsupported_uses_are_errors() {
    let plate = panel(4, 2);
    let data = Arc::new(ModalBodyData::from_free_interface(&plate, 3, 0.0, &[]).unwrap());
    let nodes = data.n_nodes();
    let mut b = ModelBuilder::new();
    let p = b
        .add_modal_body(
            "p",
            data.clone(),
            BodyInit::at(Vec3::zeros()),
            &[0.0; 3],
            &[0.0; 3],
        )
        .unwrap();
    let r = b
        .add_rigid_body("r", 1.0, Mat3::identity(), BodyInit::at(Vec3::x()))
        .unwrap();
    let err = b
        .add_joint(
            "j",
            JointKind::Revolute,
            Frame::at_node(p, nodes),
            Frame::new(r, Vec3::zeros()),
        )
        .unwrap_err();
    assert!(
        err.contains(&format!("node {nodes}")) && err.contains("'p'"),
        "{err}"
    );
    let err = b
        .add_joint(
            "j",
            JointKind::Spherical,
            Frame::at_node(r, 0),
            Frame::new(p, Vec3::zeros()),
        )
        .unwrap_err();
    assert!(err.contains("not a modal"), "{err}");
    let err = b
        .add_joint(
            "j",
            JointKind::Spherical,
            Frame::at_node(BodyId::GROUND, 0),
            Frame::new(p, Vec3::zeros()),
        )
        .unwrap_err();
    assert!(err.contains("ground"), "{err}");
    let err = b
        .add_joint(
            "j",
            JointKind::AngleDrive(Profile::Polynomial {
                c0: 0.0,
                c1: 0.0,
                c2: 0.0,
            }),
            Frame::new(r, Vec3::zeros()),
            Frame::at_node(p, 1),
        )
        .unwrap_err();
    assert!(err.contains("angle drive"), "{err}");
    let err = b
        .add_spring_damper(SpringDamper {
            name: "s".into(),
            a: Frame::at_node(p, nodes + 3),
            b: Frame::new(r, Vec3::zeros()),
            stiffness: 1.0,
            damping: 0.0,
            free_length: 0.0,
        })
        .unwrap_err();
    assert!(err.contains(&format!("node {}", nodes + 3)), "{err}");
    let nb = b.node_body(p, 2).unwrap();
    assert_eq!(b.node_body(p, 2).unwrap(), nb);
    assert!(b.node_body(r, 0).unwrap_err().contains("not a modal"));
    let err = b
        .add_joint(
            "j",
            JointKind::Spherical,
            Frame::new(nb, Vec3::zeros()),
            Frame::new(r, Vec3::zeros()),
        )
        .unwrap_err();
    assert!(err.contains("node body"), "{err}");
    let err = b
        .add_modal_body("q", data, BodyInit::at(Vec3::zeros()), &[0.0; 2], &[0.0; 3])
        .unwrap_err();
    assert!(err.contains("3 modes"), "{err}");
}

/// Hinge friction at a flexible panel node (issue #48 slow case).
#[path = "flex_jacobians/hinge_friction.rs"]
mod hinge_friction;
