//! A Craig-Bampton panel clamped to the ground at its frame node by a fixed joint (on the node's
//! frame) vibrates at the first frequency of the finite-element panel clamped at that node.
//!
//! Reference: the lowest eigenvalue of the full FE model (`flex::eigen`, all DOFs of the frame
//! node clamped). The body keeps a second attachment node (the far edge centre) as interface, so
//! its coordinates are 3 constraint-mode DOFs plus 4 fixed-interface modes: the reduced first
//! frequency is within the Craig-Bampton error of the FE one. The motion starts in the first
//! reduced mode (tip deflection about 1 cm, no damping) and the period is measured from upward
//! zero crossings of the tip deflection over three periods.

use crate::common;
use common::flex::{lowest_mode, panel, upward_crossings};
use mbcosim::flex::ModalBodyData;
use mbcosim::flex::eigen::generalized_eigenvalues;
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::Vec3;
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, ModelBuilder};
use mbcosim::sim::Simulation;
use std::f64::consts::PI;
use std::sync::Arc;

#[test]
fn clamped_panel_vibrates_at_first_fe_frequency() {
    let plate = panel(6, 2);
    let frame_node = plate.node_index(0, 1).unwrap();
    let tip = plate.node_index(6, 1).unwrap();
    let clamped = plate.node_dofs(frame_node).unwrap();
    let w2_fe = generalized_eigenvalues(plate.stiffness(), plate.mass(), &clamped, 1).unwrap()[0];
    let f_fe = w2_fe.sqrt() / (2.0 * PI);
    let data = Arc::new(
        ModalBodyData::from_craig_bampton(&plate, frame_node, &[frame_node, tip], 4, 0.0).unwrap(),
    );
    let n = data.n_modes();
    let (_, mode) = lowest_mode(data.stiffness(), data.mass());
    let phi_tip = &data.translational_shapes()[tip];
    let scale = 0.01 / (phi_tip * &mode)[2].abs();
    let a0: Vec<f64> = mode.iter().map(|x| x * scale).collect();
    let rho_f = data.positions()[frame_node];
    for kind in [
        IntegratorKind::Bdf,
        IntegratorKind::Dopri5,
        IntegratorKind::GenAlpha,
    ] {
        let mut b = ModelBuilder::new();
        let p = b
            .add_modal_body(
                "panel",
                data.clone(),
                BodyInit::at(Vec3::zeros()),
                &a0,
                &vec![0.0; n],
            )
            .unwrap();
        b.add_joint(
            "clamp",
            JointKind::Fixed,
            Frame::new(BodyId::GROUND, rho_f),
            Frame::at_node(p, frame_node),
        )
        .unwrap();
        // gen-alpha holds its error per unit step: atol 1e-10 on a 0.01 m vibration is below
        // the round-off of its index-3 form (it stops with a message), 1e-8 is not
        let (rtol, atol) = match kind {
            IntegratorKind::GenAlpha => (1e-6, 1e-8),
            _ => (1e-8, 1e-10),
        };
        let settings = Settings {
            rtol,
            atol,
            h_max: 0.01,
            ..Settings::default()
        };
        let mut sim = Simulation::new(b.build().unwrap(), kind, settings, 0.0).unwrap();
        let period_guess = 1.0 / f_fe;
        let tip_w = |s: &mbcosim::state::State| {
            (phi_tip * nalgebra::DVector::from_column_slice(&s.q[7..7 + n]))[2]
        };
        let t = upward_crossings(&mut sim, 3.3 * period_guess, period_guess / 200.0, &tip_w);
        assert!(t.len() >= 3, "{}: only {} crossings", kind.name(), t.len());
        let period = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
        let f = 1.0 / period;
        let rel = (f - f_fe).abs() / f_fe;
        println!(
            "{}: clamped panel f = {f:.6} Hz, FE {f_fe:.6} Hz, reduced {:.6} Hz, relative error {rel:.3e}",
            kind.name(),
            data.frequencies_hz().unwrap()[0]
        );
        assert!(rel < 5e-3, "{}: frequency off by {rel:.3e}", kind.name());
        assert!(sim.constraint_residual() < 1e-8);
    }
}
