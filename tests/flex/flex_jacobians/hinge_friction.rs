//! Finite-difference check of the hinge friction's Newton blocks where it acts on a flexible
//! panel's node (the node-body path of the flexible PanelLock hinges): the friction's share of
//! `K = -df/dx` and `D = -df/dv` (the system with the friction less the system without), mapped
//! onto the modal body's rigid and modal coordinates, against central differences of its share
//! of the forces. Inside the linear zone of the law (`|w|` of order 1e-3 `w_s` here) the secant
//! slope the matrix carries equals the tangent to about 3e-7 relative, so the check sees the
//! mapping, not the choice of slope (docs/hinge_friction_cost.md; the slope is tested in the
//! effect's own tests).

use crate::common::flex::panel;
use crate::common::jacobian::{assembled, jacobian_mismatch};
use mbcosim::dae::System;
use mbcosim::effect::hinge_friction::{HingeFriction, HingeFrictions};
use mbcosim::flex::ModalBodyData;
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::*;
use nalgebra::DMatrix;
use std::sync::Arc;

/// Coulomb torque [N m] and slip rate [rad/s] of the test friction: a slope of 2 N m s/rad.
const TORQUE: f64 = 2e3;
const SLIP_RATE: f64 = 1e3;

/// A Craig-Bampton panel (2 modes, deformed and moving) and a rigid body on a revolute joint at
/// an interface node, with the friction across that joint (node frame to the rigid body) when
/// `friction`.
fn model(friction: bool) -> Model {
    let plate = panel(4, 2);
    let k1 = plate.node_index(4, 2).unwrap();
    let data = Arc::new(ModalBodyData::from_craig_bampton(&plate, 0, &[0, k1], 2, 0.02).unwrap());
    let n = data.n_modes();
    let mut b = ModelBuilder::new();
    let a0: Vec<f64> = (0..n).map(|i| 0.03 * (1.0 - 0.4 * i as f64)).collect();
    let ad0: Vec<f64> = (0..n)
        .map(|i| 0.2 * (-1.0f64).powi(i as i32) + 0.05)
        .collect();
    let p = b
        .add_modal_body(
            "p",
            data,
            BodyInit::at(Vec3::new(0.2, -0.1, 0.3))
                .oriented(Quat::from_euler_angles(0.3, -0.4, 0.8))
                .moving(Vec3::new(0.3, -0.2, 0.5), Vec3::new(0.7, -1.1, 0.4)),
            &a0,
            &ad0,
        )
        .unwrap();
    let r = b
        .add_rigid_body(
            "r",
            1.5,
            Mat3::new(2.0, 0.1, -0.2, 0.1, 3.0, 0.15, -0.2, 0.15, 2.5),
            BodyInit::at(Vec3::new(1.3, 0.4, -0.2))
                .oriented(Quat::from_euler_angles(-0.6, 0.2, 1.4))
                .moving(Vec3::new(-0.4, 0.1, 0.2), Vec3::new(-0.5, 0.9, 1.3)),
        )
        .unwrap();
    let ax = Vec3::new(0.3, 0.4, 0.86);
    let fj = Frame::with_z(r, Vec3::new(-0.3, 0.2, 0.1), ax);
    b.add_joint(
        "j",
        JointKind::Revolute,
        Frame::with_z(p, Vec3::new(0.05, -0.02, 0.03), ax).on_node(k1),
        fj,
    )
    .unwrap();
    if friction {
        let node = b.node_body(p, k1).unwrap();
        b.add_force_effect(Arc::new(HingeFrictions {
            elements: vec![HingeFriction {
                name: "f".into(),
                frame_i: Frame::with_z(node, Vec3::zeros(), ax),
                frame_j: fj,
                torque: TORQUE,
                slip_rate: SLIP_RATE,
            }],
        }));
    }
    b.build().unwrap()
}

#[test]
fn hinge_friction_at_a_panel_node_matches_finite_differences() {
    let (with, without) = (model(true), model(false));
    let mut sw = System::new(Arc::new(with.clone())).unwrap();
    let mut so = System::new(Arc::new(without)).unwrap();
    let (q, v, t) = (with.q0.clone(), with.v0.clone(), 0.3);
    let n = sw.n_v();
    // the friction's share of the assembled K and D
    let share = |c: [f64; 3], sw: &mut System, so: &mut System| -> DMatrix<f64> {
        assembled(sw, t, &q, &v, c) - assembled(so, t, &q, &v, c)
    };
    let k_an = share([0.0, 0.0, 1.0], &mut sw, &mut so);
    let d_an = share([0.0, 1.0, 0.0], &mut sw, &mut so);
    let force = |q: &[f64], v: &[f64]| -> Vec<f64> {
        let (mut fw, mut fo) = (vec![0.0; n], vec![0.0; n]);
        sw.forces(t, q, v, &mut fw);
        so.forces(t, q, v, &mut fo);
        fw.iter().zip(&fo).map(|(a, b)| a - b).collect()
    };
    let (worst, scale) = jacobian_mismatch(&with, &q, &v, &k_an, &d_an, force, 1e-6);
    println!("friction K/D share: worst mismatch {worst:.3e}, scale {scale:.3e}");
    // the friction is in the model and acts: its share is of the slope's size
    assert!(scale > 0.1 * TORQUE / SLIP_RATE, "scale {scale:.3e}");
    assert!(
        worst < 1e-5 * scale,
        "worst mismatch {worst:.3e} (scale {scale:.3e})"
    );
}
