//! Finite-difference checks of every analytic Jacobian: force elements (K = -df/dx, D = -df/dv)
//! and constraint rows (G against dPhi/dx, gamma against the directional second derivative).

mod common;
use common::jacobian::force_jacobian_mismatch;
use mbcosim::dae::System;
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::*;
use std::sync::Arc;

/// Two rigid bodies in general poses and motion, connected by every force element and one joint
/// of `kind` (frames with tilted axes).
fn two_body_model(kind: JointKind) -> Model {
    let mut b = ModelBuilder::new();
    let u = b.add_input("u");
    b.set_gravity(Some(Vec3::new(0.1, -9.81, 0.3))).unwrap();
    let inertia = Mat3::new(2.0, 0.1, -0.2, 0.1, 3.0, 0.15, -0.2, 0.15, 2.5);
    let i1 = BodyInit::at(Vec3::new(0.2, -0.1, 0.3))
        .oriented(Quat::from_euler_angles(0.3, -0.4, 0.8))
        .moving(Vec3::new(0.3, -0.2, 0.5), Vec3::new(0.7, -1.1, 0.4));
    let i2 = BodyInit::at(Vec3::new(1.3, 0.4, -0.2))
        .oriented(Quat::from_euler_angles(-0.6, 0.2, 1.4))
        .moving(Vec3::new(-0.4, 0.1, 0.2), Vec3::new(-0.5, 0.9, 1.3));
    let b1 = b.add_rigid_body("b1", 1.5, inertia, i1).unwrap();
    let b2 = b.add_rigid_body("b2", 2.5, inertia * 0.7, i2).unwrap();
    let ax = Vec3::new(0.3, 0.4, 0.86);
    b.add_joint(
        "j",
        kind,
        Frame::with_z(b1, Vec3::new(0.4, 0.1, -0.2), ax),
        Frame::with_z(b2, Vec3::new(-0.3, 0.2, 0.1), ax),
    )
    .unwrap();
    b.add_spring_damper(SpringDamper {
        name: "s".into(),
        a: Frame::new(b1, Vec3::new(0.1, 0.2, 0.3)),
        b: Frame::new(b2, Vec3::new(-0.2, 0.1, 0.05)),
        stiffness: 120.0,
        damping: 7.0,
        free_length: 0.4,
    })
    .unwrap();
    b.add_spring_damper(SpringDamper {
        name: "s0".into(),
        a: Frame::new(BodyId::GROUND, Vec3::new(0.0, 1.0, 0.0)),
        b: Frame::new(b1, Vec3::new(0.3, -0.1, 0.2)),
        stiffness: 50.0,
        damping: 3.0,
        free_length: 0.5,
    })
    .unwrap();
    b.add_torsion_spring(TorsionSpring {
        name: "t".into(),
        frame_i: Frame::with_z(b1, Vec3::zeros(), ax),
        frame_j: Frame::with_z(b2, Vec3::zeros(), Vec3::new(0.2, 0.5, 0.84)),
        stiffness: 30.0,
        damping: 2.0,
        free_angle: 0.7,
        angle_offset: 0.1,
    })
    .unwrap();
    b.add_applied_load(AppliedLoad {
        name: "l".into(),
        at: Frame::new(b2, Vec3::new(0.2, -0.3, 0.1)),
        force_direction: Vec3::new(1.0, 2.0, -0.5),
        force: Profile::Sine {
            offset: 3.0,
            amplitude: 1.0,
            omega: 2.0,
            phase: 0.1,
        },
        torque_direction: Vec3::new(0.2, -0.1, 1.0),
        torque: Profile::Input {
            index: u,
            gain: 4.0,
        },
    })
    .unwrap();
    b.add_joint_torque(JointTorque {
        name: "m".into(),
        frame_i: Frame::with_z(b1, Vec3::zeros(), ax),
        frame_j: Frame::with_z(b2, Vec3::zeros(), Vec3::new(-0.1, 0.3, 0.95)),
        torque: Profile::Input {
            index: u,
            gain: -2.0,
        },
    })
    .unwrap();
    b.build().unwrap()
}

#[test]
fn force_jacobians_match_finite_differences() {
    for kind in [JointKind::Revolute, JointKind::Spherical] {
        let model = two_body_model(kind);
        let mut sys = System::new(Arc::new(model.clone())).unwrap();
        sys.inputs[0] = 0.8;
        let (q, v) = (model.q0.clone(), model.v0.clone());
        let (worst, scale) = force_jacobian_mismatch(&model, &mut sys, 0.3, &q, &v, 1e-6);
        assert!(
            worst < 1e-6 * scale,
            "{kind:?}: worst K/D mismatch {worst:.3e} (scale {scale:.3e})"
        );
    }
}

#[test]
fn constraint_jacobian_and_gamma_match_finite_differences() {
    let kinds = [
        JointKind::Revolute,
        JointKind::Spherical,
        JointKind::Fixed,
        JointKind::Prismatic,
        JointKind::AngleDrive(Profile::Polynomial {
            c0: 0.2,
            c1: 0.5,
            c2: 0.3,
        }),
        JointKind::TranslationDrive(Profile::Sine {
            offset: 0.1,
            amplitude: 0.2,
            omega: 3.0,
            phase: 0.4,
        }),
    ];
    for kind in kinds {
        let model = two_body_model(kind);
        let mut sys = System::new(Arc::new(model.clone())).unwrap();
        let (q, v) = (model.q0.clone(), model.v0.clone());
        let n = sys.n_v();
        let t = 0.3;
        sys.eval_constraints(t, &q, &v);
        let rows = sys.rows.clone();
        let nc = rows.len();
        let mut gv = vec![0.0; nc];
        sys.g_mul(&v, &mut gv);
        let eps = 1e-6;
        let phi_at = |sys: &mut System, q: &[f64], t: f64| {
            sys.eval_constraints(t, q, &v);
            sys.rows.iter().map(|r| r.phi).collect::<Vec<_>>()
        };
        // G columns
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
            for r in 0..nc {
                let fd = (pp[r] - pm[r]) / (2.0 * eps);
                assert!(
                    (fd - ge[r]).abs() < 1e-7,
                    "{kind:?}: G[{r},{j}] = {} vs fd {fd}",
                    ge[r]
                );
            }
        }
        // Phi_t by differences in time
        let pp = phi_at(&mut sys, &q, t + eps);
        let pm = phi_at(&mut sys, &q, t - eps);
        for r in 0..nc {
            let fd = (pp[r] - pm[r]) / (2.0 * eps);
            assert!(
                (fd - rows[r].phi_t).abs() < 1e-7,
                "{kind:?}: Phi_t[{r}] {} vs fd {fd}",
                rows[r].phi_t
            );
        }
        // gamma: along the motion q(s) = q ⊕ (s v), t(s) = t + s with v_dot = 0,
        // Phi'' = G_dot v + 2 Phi_tq v + Phi_tt = -gamma (G v_dot term vanishes).
        let h = 1e-4;
        let path = |sys: &mut System, s: f64| {
            let dx: Vec<f64> = v.iter().map(|x| x * s).collect();
            let mut qs = q.clone();
            model.retract(&q, &dx, &mut qs);
            phi_at(sys, &qs, t + s)
        };
        let (p1, p0, m1) = (path(&mut sys, h), path(&mut sys, 0.0), path(&mut sys, -h));
        for r in 0..nc {
            let second = (p1[r] - 2.0 * p0[r] + m1[r]) / (h * h);
            // along q ⊕ s v the body angular velocity is constant, so this equals the exact motion's
            // second derivative with omega_dot = 0 and v_dot = 0
            assert!(
                (second + rows[r].gamma).abs() < 1e-5 * (1.0 + second.abs()),
                "{kind:?}: gamma[{r}] {} vs -Phi'' {}",
                rows[r].gamma,
                -second
            );
        }
    }
}

#[test]
fn ground_contact_jacobians_match_finite_differences() {
    use mbcosim::contact::{ContactLaw, LawKind};
    use mbcosim::effect::ground_contact::GroundContact;
    use mbcosim::effect::plane_contact::PlaneContact;
    // a tilted, spinning, sliding box whose four lower corners sink into a tilted plane: normal
    // law (Hunt-Crossley at its reference speed) and friction with a regularization speed of the
    // order of the corners' tangential speeds
    let mut b = ModelBuilder::new();
    let inertia = Mat3::new(2.0, 0.1, -0.2, 0.1, 3.0, 0.15, -0.2, 0.15, 2.5);
    let init = BodyInit::at(Vec3::new(0.1, -0.2, 0.45))
        .oriented(Quat::from_euler_angles(0.05, -0.08, 0.6))
        .moving(Vec3::new(0.3, -0.2, -0.1), Vec3::new(0.2, -0.3, 0.9));
    let body = b.add_rigid_body("box", 3.0, inertia, init).unwrap();
    let n = Vec3::new(0.05, -0.08, 1.0).normalize();
    let law = ContactLaw::new(LawKind::HuntCrossley, 2e4, 1.5, 0.6)
        .and_then(|l| l.with_min_approach_speed(0.8))
        .unwrap();
    let corners = [(-0.4, -0.3), (0.4, -0.3), (0.4, 0.3), (-0.4, 0.3)];
    let contacts: Vec<PlaneContact> = corners
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| PlaneContact {
            name: format!("c{i}"),
            point: Frame::new(body, Vec3::new(x, y, -0.5)),
            normal: n,
            offset: 0.02,
            law,
        })
        .collect();
    let effect = GroundContact {
        contacts,
        mu: 0.4,
        slip_speed: 0.3,
    };
    b.add_force_effect(Arc::new(effect));
    let model = b.build().unwrap();
    let mut sys = System::new(Arc::new(model.clone())).unwrap();
    let (q, v) = (model.q0.clone(), model.v0.clone());
    let mut f0 = vec![0.0; sys.n_v()];
    sys.forces(0.3, &q, &v, &mut f0);
    assert!(
        f0[2] > 1.0 && f0[0].abs() > 0.1,
        "the corners must press and rub: {f0:?}"
    );
    let (worst, scale) = force_jacobian_mismatch(&model, &mut sys, 0.3, &q, &v, 1e-7);
    assert!(
        worst < 1e-6 * scale,
        "ground contact: worst K/D mismatch {worst:.3e} (scale {scale:.3e})"
    );
}
