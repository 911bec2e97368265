//! A free flexible panel tumbling in space (no gravity, no damping): linear momentum, angular
//! momentum and energy are invariants of the exact motion, so their drift measures the
//! integration error of the floating-frame equations (mass matrix `M(a)`, quadratic-velocity
//! vector, elastic forces). The initial state mixes a spin about all three axes (well below the
//! first elastic frequency, ~22 Hz) with an excitation of every mode.

use crate::common;
use common::flex::{modal_state, momenta, panel};
use mbcosim::flex::ModalBodyData;
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::{Quat, Vec3};
use mbcosim::model::{BodyInit, ModelBuilder};
use mbcosim::sim::Simulation;
use std::sync::Arc;

fn tumbling(kind: IntegratorKind, rtol: f64, t_end: f64) -> (f64, f64, f64) {
    let data = Arc::new(ModalBodyData::from_free_interface(&panel(6, 3), 4, 0.0, &[]).unwrap());
    let n = data.n_modes();
    let mut b = ModelBuilder::new();
    let init = BodyInit::at(Vec3::new(0.3, -0.2, 0.1))
        .oriented(Quat::from_euler_angles(0.2, -0.3, 0.5))
        .moving(Vec3::new(0.05, 0.02, -0.03), Vec3::new(0.6, -0.9, 1.5));
    let a0: Vec<f64> = (0..n).map(|i| 2e-3 / (1.0 + i as f64)).collect();
    let a_dot0: Vec<f64> = (0..n).map(|i| 0.05 * (-1.0f64).powi(i as i32)).collect();
    let id = b
        .add_modal_body("panel", data.clone(), init, &a0, &a_dot0)
        .unwrap();
    let _ = id;
    let model = b.build().unwrap();
    let settings = Settings {
        rtol,
        atol: rtol * 1e-2,
        h_max: 0.01,
        ..Settings::default()
    };
    let mut sim = Simulation::new(model, kind, settings, 0.0).unwrap();
    let at = |sim: &Simulation| {
        let s = &sim.state;
        momenta(&data, &modal_state(&s.q, &s.v, 0, 0, n))
    };
    let (p0, l0) = at(&sim);
    let e0 = sim.energy().balance();
    let (mut dp, mut dl, mut de): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let steps = 20;
    for k in 1..=steps {
        sim.advance_to(t_end * k as f64 / steps as f64).unwrap();
        let (p, l) = at(&sim);
        dp = dp.max((p - p0).norm() / p0.norm());
        dl = dl.max((l - l0).norm() / l0.norm());
        de = de.max((sim.energy().balance() - e0).abs() / e0);
    }
    // the body really deforms and tumbles
    let a_end = modal_state(&sim.state.q, &sim.state.v, 0, 0, n).a;
    assert!(a_end.amax() > 1e-4, "modes must stay excited");
    (dp, dl, de)
}

#[test]
fn free_tumbling_panel_conserves_momenta_and_energy() {
    for (kind, rtol, tol) in [
        (IntegratorKind::Bdf, 1e-9, 1e-6),
        (IntegratorKind::Dopri5, 1e-10, 1e-7),
        (IntegratorKind::GenAlpha, 1e-7, 1e-3),
    ] {
        let (dp, dl, de) = tumbling(kind, rtol, 1.0);
        println!(
            "{}: rtol {rtol:.0e}: |dp|/|p| {dp:.3e}, |dL|/|L| {dl:.3e}, |dE|/E {de:.3e}",
            kind.name()
        );
        assert!(
            dp < tol && dl < tol && de < tol,
            "{}: drift too large",
            kind.name()
        );
    }
}

/// A panel tethered to the ground by a spring at a corner node, with a torsion spring and an
/// applied constant force at other nodes, under gravity, with modal damping (2 %): the energy
/// balance `kinetic + potential + dissipated - input` is constant. It checks that node-body forces
/// (spring, torsion spring, load at nodes) are mapped consistently with their potential and
/// power, and the modal damping's dissipated power.
#[test]
fn tethered_damped_panel_keeps_its_energy_balance() {
    use mbcosim::model::{AppliedLoad, BodyId, Frame, Profile, SpringDamper};
    let plate = panel(6, 3);
    let corner = plate.node_index(6, 3).unwrap();
    let edge = plate.node_index(3, 0).unwrap();
    let data = Arc::new(ModalBodyData::from_free_interface(&plate, 4, 0.02, &[corner]).unwrap());
    let n = data.n_modes();
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, 0.0, -9.81))).unwrap();
    let init = BodyInit::at(Vec3::new(0.0, 0.0, -1.0))
        .oriented(Quat::from_euler_angles(0.1, 0.2, -0.1))
        .moving(Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.2, -0.1, 0.3));
    let p = b
        .add_modal_body("panel", data.clone(), init, &vec![0.01; n], &vec![0.0; n])
        .unwrap();
    b.add_spring_damper(SpringDamper {
        name: "tether".into(),
        a: Frame::new(BodyId::GROUND, Vec3::new(2.0, 1.0, 0.5)),
        b: Frame::at_node(p, corner),
        stiffness: 400.0,
        damping: 0.0,
        free_length: 0.5,
    })
    .unwrap();
    b.add_applied_load(AppliedLoad {
        name: "push".into(),
        at: Frame::at_node(p, edge),
        force_direction: Vec3::new(0.0, 0.0, 1.0),
        force: Profile::Sine {
            offset: 5.0,
            amplitude: 0.0,
            omega: 0.0,
            phase: 0.0,
        },
        torque_direction: Vec3::zeros(),
        torque: Profile::Sine {
            offset: 0.0,
            amplitude: 0.0,
            omega: 0.0,
            phase: 0.0,
        },
    })
    .unwrap();
    let settings = Settings {
        rtol: 1e-9,
        atol: 1e-11,
        h_max: 0.01,
        ..Settings::default()
    };
    let mut sim = Simulation::new(b.build().unwrap(), IntegratorKind::Bdf, settings, 0.0).unwrap();
    let e0 = sim.energy().balance();
    let mut worst: f64 = 0.0;
    for k in 1..=20 {
        sim.advance_to(0.1 * k as f64).unwrap();
        worst = worst.max((sim.energy().balance() - e0).abs());
    }
    let e = sim.energy();
    println!(
        "tethered panel: kinetic {:.4} J, dissipated {:.4} J, input {:.4} J, balance drift {worst:.2e} J",
        e.kinetic, e.dissipated, e.input
    );
    assert!(e.dissipated > 1e-4, "modal damping must dissipate");
    assert!(worst < 1e-6 * e.kinetic.max(1.0));
}
