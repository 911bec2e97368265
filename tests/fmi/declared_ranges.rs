//! The declared min/max of every real parameter agree with the models' validation (issue #23):
//! a value at a declared bound is accepted, and where the documentation shows an open bound
//! (`(0, ...`), the bound itself is refused. Relations between parameters (latch geometry,
//! stowed below lock angle, ...) are set to values that admit the bound, as their descriptions
//! say.

use mbcosim::scene::panel_lock::ports::REAL_PARAMS;
use mbcosim::scene::panel_lock::{PanelLockModel, PanelLockParams};
use mbcosim::scene::port::{Causality, PortType};
use mbcosim::scene::rope_block::RopeBlockModel;
use mbcosim::scene::{native, panel_lock, pid, rope_block};

/// Default parameters with the other parameters set so that `name` = `v` can be valid.
fn panel_lock_params(name: &str, v: f64) -> PanelLockParams {
    let mut p = PanelLockParams::default();
    match name {
        "cam_radius" | "groove_width" | "groove_depth" | "pin_radius" => p.latches = false,
        "modal_damping_ratio"
        | "panel_youngs_modulus"
        | "panel_poisson"
        | "panel_nonstructural_mass" => {
            p.flexible_panels = true;
            p.n_modes = 1;
        }
        "gravity" => p.gravity = Some(9.81),
        // the other two moments equal and at least half this one (triangle inequality)
        "satellite_inertia_x" | "satellite_inertia_y" | "satellite_inertia_z" => {
            p.satellite_inertia = [(0.5 * v).max(1.0); 3]
        }
        "root_lock_angle" => p.root_stowed_angle = 0.01,
        "panel_lock_angle" => p.panel_stowed_angle = 0.01,
        "root_stowed_angle" => p.root_lock_angle = if v > 1.0 { std::f64::consts::PI } else { 1.0 },
        "panel_stowed_angle" => {
            p.panel_lock_angle = if v > 1.0 { std::f64::consts::PI } else { 1.0 }
        }
        _ => {}
    }
    if v < 1.0 {
        match name {
            "root_lock_angle" => p.root_stowed_angle = 0.0,
            "panel_lock_angle" => p.panel_stowed_angle = 0.0,
            _ => {}
        }
    }
    let rp = REAL_PARAMS.iter().find(|r| r.name == name).unwrap();
    (rp.set)(&mut p, v);
    p
}

#[test]
fn panel_lock_declared_ranges_match_the_validation() {
    let mut checked = 0;
    for port in panel_lock::info().ports.iter() {
        let PortType::Real { min, max, open, .. } = port.ty else {
            continue;
        };
        if port.causality != Causality::Parameter {
            continue;
        }
        let name = port.name.as_str();
        for (bound, is_open, outside) in [
            (min, open[0], min.map(f64::next_down)),
            (max, open[1], max.map(f64::next_up)),
        ] {
            let Some(b) = bound else { continue };
            let p = panel_lock_params(name, b);
            assert_eq!(p.validate(), Ok(()), "{name} = {b:e} (declared bound)");
            // through the model's port table too
            let mut m = PanelLockModel::new();
            native::set_by_name(&mut m, name, b).unwrap();
            if is_open {
                let b = outside.unwrap();
                let p = panel_lock_params(name, b);
                assert!(
                    p.validate().is_err(),
                    "{name} = {b:e} (open bound) accepted"
                );
            }
            checked += 1;
        }
        assert!(
            min.is_some() || name == "gravity",
            "{name}: no declared minimum"
        );
    }
    assert!(checked > 60, "{checked}");
}

#[test]
fn rope_block_declared_ranges_match_the_validation() {
    for port in rope_block::info().ports.iter() {
        let PortType::Real { min, max, .. } = port.ty else {
            continue;
        };
        if port.causality != Causality::Parameter {
            continue;
        }
        for b in [min.unwrap(), max.unwrap()] {
            let mut m = RopeBlockModel::new();
            native::set_by_name(&mut m, "ground_contact", 1.0).unwrap();
            native::set_by_name(&mut m, &port.name, b).unwrap();
            let p = m
                .params()
                .unwrap_or_else(|e| panic!("{} = {b:e}: {e}", port.name));
            assert_eq!(p.validate(), Ok(()), "{} = {b:e}", port.name);
        }
    }
}

#[test]
fn pid_declared_ranges_match_the_validation() {
    for port in pid::info().ports.iter() {
        let PortType::Real { min, max, .. } = port.ty else {
            continue;
        };
        if port.causality != Causality::Parameter {
            continue;
        }
        for b in [min, max].into_iter().flatten() {
            let mut m = pid::create();
            native::set_by_name(m.as_mut(), &port.name, b).unwrap();
            m.initialize(0.0)
                .unwrap_or_else(|e| panic!("{} = {b:e}: {e}", port.name));
            m.do_step(0.0, 0.1).unwrap();
        }
    }
}

/// The deployment-speed check: its estimate is the energy balance worked out by hand for the
/// default scene, and springs too strong for the panel or the yoke are refused naming them.
#[test]
fn deployment_tip_speed_estimate_and_refusal() {
    let p = PanelLockParams::default();
    // panel spring: 0.4 N m over 175 degrees plus 0.05 N m/rad linear, into a 4.5 kg, 2 m panel
    // (I = m L^2 / 3 = 6 kg m^2); root: 0.6 N m over 90 degrees plus 0.1 N m/rad into the 2 kg,
    // 1 m yoke with three stowed panels at its end
    let travel = std::f64::consts::PI - 5f64.to_radians();
    let w = 0.4 * travel + 0.5 * 0.05 * travel * travel;
    let panel = 2.0 * (2.0 * w / 6.0_f64).sqrt();
    let t_r = std::f64::consts::FRAC_PI_2;
    let w_r = 0.6 * t_r + 0.5 * 0.1 * t_r * t_r;
    let root = (2.0 * w_r / (2.0 / 3.0 + 3.0 * 4.5_f64)).sqrt();
    let [r, pa] = p.deployment_tip_speeds();
    assert!((pa - panel).abs() < 1e-12 * panel, "{pa} vs {panel}");
    assert!((r - root).abs() < 1e-12 * root, "{r} vs {root}");
    assert!(p.validate().is_ok());

    let strong = PanelLockParams {
        panel_spring_preload: 400.0,
        panel_areal_density: 1.5e-3,
        ..PanelLockParams::default()
    };
    let e = strong.validate().unwrap_err();
    assert!(
        e.contains("panel_spring_preload = 400 N m") && e.contains("m/s at its tip"),
        "{e}"
    );
    let yoke = PanelLockParams {
        root_spring_preload: 600.0,
        yoke_mass: 2e-3,
        panel_areal_density: 1.5e-3,
        ..PanelLockParams::default()
    };
    let e = yoke.validate().unwrap_err();
    assert!(e.contains("root_spring_preload = 600 N m"), "{e}");
}
