//! Effect switches: an effect switched off is not assembled at all (no force effect, no bodies or
//! coordinates, no zero-filled blocks), the results equal those of a scene whose effect is present
//! but contributes nothing (to the last bit where the summation order is the same), and invalid
//! combinations are refused at instantiation with a clear message.

mod common;

use common::force_effect_names;
use mbcosim::scene::CoSimModel;
use mbcosim::scene::native;
use mbcosim::scene::panel_lock::{PanelLock, PanelLockModel, PanelLockParams};
use mbcosim::scene::rope_block::RopeBlockParams;

fn effect_names(s: &PanelLock) -> Vec<String> {
    force_effect_names(&s.sim.system.model)
}

/// Every hinge angle and rate, the energies and the state after `t_end` [s].
fn fingerprint(p: PanelLockParams, t_end: f64) -> (Vec<u64>, PanelLock) {
    let mut s = PanelLock::new(p).unwrap();
    s.advance_to(t_end).unwrap();
    let o = s.outputs();
    let mut bits: Vec<u64> = o
        .hinges
        .iter()
        .flat_map(|h| [h.angle.to_bits(), h.rate.to_bits()])
        .collect();
    bits.push(o.kinetic.to_bits());
    (bits, s)
}

#[test]
fn panel_lock_switches_remove_their_effects_and_nothing_else() {
    let all_on = PanelLockParams {
        latches: true,
        cable_loop: true,
        gravity: Some(9.81),
        free_satellite: true,
        ..PanelLockParams::default()
    };
    let all_off = PanelLockParams {
        latches: false,
        cable_loop: false,
        gravity: None,
        free_satellite: false,
        ..PanelLockParams::default()
    };
    let on = PanelLock::new(all_on).unwrap();
    let off = PanelLock::new(all_off).unwrap();
    let (names_on, names_off) = (effect_names(&on), effect_names(&off));
    assert!(names_on.iter().any(|n| n.contains("latch")), "{names_on:?}");
    assert!(
        !names_off.iter().any(|n| n.contains("latch")),
        "{names_off:?}"
    );
    assert!(
        !names_off.iter().any(|n| n.contains("cable")),
        "{names_off:?}"
    );
    assert!(names_off.len() < names_on.len());
    let (m_on, m_off) = (&on.sim.system.model, &off.sim.system.model);
    // the satellite body (6 speeds) exists only when it floats; no gravity vector when off
    assert_eq!(m_on.n_v, m_off.n_v + 6);
    assert_eq!(m_on.bodies.len(), m_off.bodies.len() + 1);
    assert!(m_on.gravity.is_some() && m_off.gravity.is_none());
    // the cable loops add constraint-free spring effects only: same joints without the satellite
    assert_eq!(m_on.joints.len(), m_off.joints.len());
    assert!(
        on.sim.system.memory.len() > off.sim.system.memory.len(),
        "latch memory exists only with latches"
    );
}

#[test]
fn gravity_off_equals_zero_gravity_and_latches_change_nothing_before_they_engage() {
    let base = PanelLockParams::default();
    let (off, _) = fingerprint(
        PanelLockParams {
            gravity: None,
            ..base.clone()
        },
        6.0,
    );
    let (zero, _) = fingerprint(
        PanelLockParams {
            gravity: Some(0.0),
            ..base.clone()
        },
        6.0,
    );
    assert_eq!(off, zero, "gravity off vs a zero gravity vector");
    // before the first latch engages (4.9 s) the latch effect adds exact zeros
    let (with, _) = fingerprint(base.clone(), 4.0);
    let (without, _) = fingerprint(
        PanelLockParams {
            latches: false,
            ..base
        },
        4.0,
    );
    assert_eq!(with, without, "latches on vs off before engagement");
}

#[test]
fn the_fmu_switches_equal_the_native_scene_built_without_the_effect() {
    // through the co-simulation model (what the FMU runs) with the switches off ...
    let values: Vec<(String, f64)> = [("latches", 0.0), ("cable_loop", 0.0), ("gravity_on", 0.0)]
        .iter()
        .map(|(k, v)| (k.to_string(), *v))
        .collect();
    let mut m = PanelLockModel::new();
    let table = native::simulate(&mut m, &values, 3.0, 0.5).unwrap();
    let angle = table.column("hinge0_angle").unwrap();
    // ... against the native scene assembled without those effects
    let mut s = PanelLock::new(PanelLockParams {
        latches: false,
        cable_loop: false,
        gravity: None,
        ..m.params().unwrap()
    })
    .unwrap();
    for (k, a) in angle.iter().enumerate().skip(1) {
        s.advance_to(0.5 * k as f64).unwrap();
        let native = s.hinge_angle(0).0;
        assert!(
            (native - a).abs() <= 1e-12 * native.abs().max(1.0),
            "t = {} s: FMU path {a}, native {native}",
            0.5 * k as f64
        );
    }
}

#[test]
fn invalid_effect_combinations_are_refused_with_the_parameters_named() {
    let e = PanelLock::new(PanelLockParams {
        cable_loop: true,
        cable_stiffness: 0.0,
        ..PanelLockParams::default()
    })
    .err()
    .unwrap();
    assert!(
        e.contains("cable_loop") && e.contains("cable_stiffness"),
        "{e}"
    );
    // through the FMU model: refused at initialization, naming the parameter
    let mut m = PanelLockModel::new();
    let vr = m.info().port_by_name("cable_stiffness").unwrap().vr;
    let on = m.info().port_by_name("cable_loop").unwrap().vr;
    m.set_boolean(on, true).unwrap();
    if m.set_real(vr, 0.0).is_ok() {
        let e = m.initialize(0.0).unwrap_err().to_string();
        assert!(e.contains("cable_stiffness"), "{e}");
    }
    // RopeBlock: a scene without slings or with a sling on a missing hook
    let mut p = RopeBlockParams::default();
    p.rig.slings.clear();
    let e = p.validate().unwrap_err();
    assert!(e.contains("sling"), "{e}");
}
