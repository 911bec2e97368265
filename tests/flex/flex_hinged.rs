//! A flexible panel hinged to the ground at the two corners of one edge (two revolute joints on
//! the same axis, at two nodes), as a solar-array panel on its two hinges, swinging under gravity.
//!
//! Rigid, the second hinge would repeat the first (5 redundant rows). Flexible (Craig-Bampton
//! body: frame node at one hinge, the other hinge node as interface with DOFs w, theta_x =
//! dw/dy, theta_y), the second hinge's rows act on the modal coordinates: its point rows hold the
//! node's out-of-plane deflection `w_2` (the in-plane ones repeat the first hinge, as the plate is
//! rigid in its plane) and its axis rows hold the slope along the hinge line `theta_x2` (the
//! other one involves the in-plane rotation, zero for a plate). So 7 independent rows and 3
//! redundant ones, found by the redundancy check over the modal columns.
//!
//! References: (1) the count of redundant rows; (2) the small-amplitude period equals that of
//! the linearized floating-frame pendulum with `w_2 = theta_x2 = 0` (same derivation as
//! `flex_pendulum.rs`, coordinates restricted); (3) at a larger amplitude (0.3 rad) energy is
//! conserved and the dropped rows stay satisfied.

use crate::common;
use common::flex::{hanging_linearization, lowest_mode, panel, upward_crossings};
use mbcosim::flex::ModalBodyData;
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::{Quat, Vec3};
use mbcosim::model::kinematics::quat_at;
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, ModelBuilder};
use mbcosim::sim::Simulation;
use nalgebra::DMatrix;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::Arc;

const G: f64 = 9.81;

fn hinged_sim(
    data: &Arc<ModalBodyData>,
    hinges: [usize; 2],
    theta0: f64,
    a0: &[f64],
) -> Simulation {
    let n = data.n_modes();
    let rho1 = data.positions()[hinges[0]];
    let rot0 = Quat::from_axis_angle(&Vec3::y_axis(), FRAC_PI_2 + theta0);
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, 0.0, -G))).unwrap();
    let p = b
        .add_modal_body(
            "panel",
            data.clone(),
            BodyInit::at(-(rot0 * rho1)).oriented(rot0),
            a0,
            &vec![0.0; n],
        )
        .unwrap();
    for (i, &h) in hinges.iter().enumerate() {
        let world = Vec3::new(0.0, data.positions()[h].y - rho1.y, 0.0);
        b.add_joint(
            &format!("hinge{i}"),
            JointKind::Revolute,
            Frame::with_z(BodyId::GROUND, world, Vec3::y()),
            Frame::with_z(p, Vec3::zeros(), Vec3::y()).on_node(h),
        )
        .unwrap();
    }
    let settings = Settings {
        rtol: 1e-9,
        atol: 1e-11,
        h_max: 0.01,
        ..Settings::default()
    };
    Simulation::new(b.build().unwrap(), IntegratorKind::Bdf, settings, 0.0).unwrap()
}

#[test]
fn panel_on_two_hinges_drops_the_redundant_rows_and_swings_as_predicted() {
    let plate = panel(6, 2);
    let (h1, h2) = (
        plate.node_index(0, 0).unwrap(),
        plate.node_index(0, 2).unwrap(),
    );
    let data = Arc::new(ModalBodyData::from_craig_bampton(&plate, h1, &[h1, h2], 4, 0.0).unwrap());
    let n = data.n_modes();
    // linearized pendulum with w_2 = theta_x2 = 0 (coordinates 0 and 1 of a)
    let (m_l, k_l) = hanging_linearization(&data, &data.positions()[h1], G);
    let keep: Vec<usize> = std::iter::once(0).chain(3..1 + n).collect();
    let sub =
        |x: &DMatrix<f64>| DMatrix::from_fn(keep.len(), keep.len(), |r, c| x[(keep[r], keep[c])]);
    let (w2, mode) = lowest_mode(&sub(&k_l), &sub(&m_l));
    let t_flex = 2.0 * PI / w2.sqrt();
    let t_rigid = 2.0 * PI * (2.0 * 2.0 / (3.0 * G)).sqrt();
    let theta0 = 0.01;
    let mut a0 = vec![0.0; n];
    for (i, &k) in keep.iter().enumerate().skip(1) {
        a0[k - 1] = mode[i] * theta0 / mode[0];
    }
    let mut sim = hinged_sim(&data, [h1, h2], theta0, &a0);
    assert_eq!(sim.system.n_redundant(), 3, "redundant rows");
    let theta = |s: &mbcosim::state::State| {
        let x = quat_at(&s.q, 3) * Vec3::x();
        (-x.z).atan2(x.x) - FRAC_PI_2
    };
    let t = upward_crossings(&mut sim, 3.3 * t_flex, t_flex / 400.0, &theta);
    let period = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let t_ref = t_flex * (1.0 + theta0 * theta0 / 16.0);
    let rel = (period - t_ref).abs() / t_ref;
    println!(
        "two hinges: period {period:.7} s, linearized flexible {t_ref:.7} s (rel {rel:.2e}), rigid {t_rigid:.7} s (flexible correction {:.2e})",
        t_flex / t_rigid - 1.0
    );
    // 1e-6: the single-hinge flexible pendulum (w_2, theta_x2 free) is 5e-6 away, the rigid one 8e-5
    assert!(rel < 1e-6, "period off by {rel:.3e}");

    // larger swing: energy and dropped rows
    let mut sim = hinged_sim(&data, [h1, h2], 0.3, &vec![0.0; n]);
    let e0 = sim.energy().balance();
    let mut worst: f64 = 0.0;
    for k in 1..=20 {
        sim.advance_to(0.15 * k as f64).unwrap();
        worst = worst.max((sim.energy().balance() - e0).abs());
        let s = sim.state.clone();
        sim.system
            .check_dropped_rows(s.t, &s.q, &s.v, 1e-8)
            .unwrap();
    }
    let scale = sim.energy().kinetic.max(1.0);
    println!(
        "two hinges, 0.3 rad: energy drift {:.2e} J (kinetic scale {scale:.3e} J)",
        worst
    );
    assert!(worst < 1e-6 * scale);
    assert!(sim.constraint_residual() < 1e-9);
}
