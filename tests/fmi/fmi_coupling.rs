//! Controller coupling in a second, independent importer (the Rust `fmi` crate): the packed PID
//! FMU positions the packed PanelLock FMU's root hinge through its motor input, the same loop as
//! `tests/python/test_panel_lock.py` runs in fmpy.

use crate::common;

use common::packed::{Fmi, packed};

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use mbcosim::scene;

/// Value reference of the port `name` of model `identifier`.
fn vr(identifier: &str, name: &str) -> u32 {
    let entry = scene::find_by_identifier(identifier).unwrap();
    (entry.info)()
        .ports
        .iter()
        .find(|p| p.name == name)
        .unwrap_or_else(|| panic!("{identifier} has no port {name}"))
        .vr
}

fn get(inst: &mut InstanceCS, vr: u32) -> f64 {
    let mut v = [0.0];
    inst.get_real(&[vr], &mut v).unwrap();
    v[0]
}

#[test]
fn pid_fmu_positions_the_panel_lock_fmu_in_the_fmi_crate() {
    let (pl, pid) = ("PanelLock", "PidController");
    let plant_import: Fmi2Import = fmi::import::from_path(packed(pl, Fmi::V2, "coupling")).unwrap();
    let ctrl_import: Fmi2Import = fmi::import::from_path(packed(pid, Fmi::V2, "coupling")).unwrap();
    let mut plant = plant_import.instantiate_cs("array", false, true).unwrap();
    let mut ctrl = ctrl_import.instantiate_cs("pid", false, true).unwrap();

    plant.setup_experiment(None, 0.0, None).unwrap();
    Common::enter_initialization_mode(&mut plant).unwrap();
    plant.set_integer(&[vr(pl, "n_panels")], &[1]).unwrap();
    plant.set_boolean(&[vr(pl, "latches")], &[0]).unwrap();
    let zero = [
        "root_spring_preload",
        "root_spring_stiffness",
        "panel_spring_preload",
        "panel_spring_stiffness",
    ]
    .map(|n| vr(pl, n));
    plant.set_real(&zero, &[0.0; 4]).unwrap();
    plant.set_real(&[vr(pl, "hinge_damping")], &[0.5]).unwrap();
    Common::exit_initialization_mode(&mut plant).unwrap();

    ctrl.setup_experiment(None, 0.0, None).unwrap();
    Common::enter_initialization_mode(&mut ctrl).unwrap();
    let set_point = 1.0;
    let gains = ["kp", "ki", "kd", "Tf", "setpoint", "u_min", "u_max"].map(|n| vr(pid, n));
    ctrl.set_real(&gains, &[8.0, 1.0, 12.0, 0.05, set_point, -5.0, 5.0])
        .unwrap();
    Common::exit_initialization_mode(&mut ctrl).unwrap();

    let (angle, torque, meas, u) = (
        vr(pl, "hinge0_angle"),
        vr(pl, "root_motor_torque"),
        vr(pid, "measurement"),
        vr(pid, "u"),
    );
    let (h, mut t) = (0.02, 0.0);
    let mut errors = Vec::new();
    for _ in 0..(40.0 / h) as usize {
        let a = get(&mut plant, angle);
        ctrl.set_real(&[meas], &[a]).unwrap();
        ctrl.do_step(t, h, true).unwrap();
        let cmd = get(&mut ctrl, u);
        plant.set_real(&[torque], &[cmd]).unwrap();
        plant.do_step(t, h, true).unwrap();
        t += h;
        errors.push(set_point - get(&mut plant, angle));
    }
    assert!(
        errors[0].abs() > 0.9,
        "starts away from the set point: {}",
        errors[0]
    );
    let tail = errors[errors.len() - 250..]
        .iter()
        .fold(0.0f64, |m, e| m.max(e.abs()));
    assert!(
        tail < 2e-3,
        "the loop settles on the set point: last 5 s error up to {tail:e}"
    );
}
