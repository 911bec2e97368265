//! PanelLock's root interface power bond (issue #46, item 1) against the energy books: with a
//! free satellite (its only load the interface wrench) the work the satellite does on the array
//! is minus the change of the satellite's own kinetic energy, computed by hand from its mass,
//! principal inertia and the reported motion; with the motor's work (`input_work`) it closes the
//! array's balance; a fixed satellite's bond carries nothing.

use crate::common::panel_lock::per_step;
use mbcosim::integrator::IntegratorKind;
use mbcosim::scene::panel_lock::{PanelLock, PanelLockParams};

/// BDF at rtol 1e-8 with steps of at most 2 ms: the work is booked by the trapezoid over each
/// step (second order), which at DOPRI5's 20 ms steps missed 1.7 % of the root work (1.3e-4 J of
/// 7.6e-3 J) and 6.5e-6 J at 2 ms; at the end of the run the whole model's balance closes to
/// 2e-7 of the energy moved here (DOPRI5 4e-6, generalized-alpha 7e-5 from its numerical
/// damping). Within the run, at the lock-up impacts, it strays to 2e-6.
fn tight(free_satellite: bool) -> PanelLockParams {
    let mut p = PanelLockParams {
        free_satellite,
        cable_loop: true,
        ..per_step(IntegratorKind::Bdf, 1e-8)
    };
    p.settings.h_max = 2e-3;
    p
}

/// Kinetic energy [J] of the satellite: `m v^2 / 2 + sum I_i w_i^2 / 2` (body axes principal).
fn satellite_kinetic(s: &mut PanelLock) -> f64 {
    let o = s.satellite_output();
    let (m, i) = (s.params.satellite_mass, s.params.satellite_inertia);
    let w = o.rate;
    0.5 * m * o.velocity.norm_squared()
        + 0.5 * (i[0] * w.x * w.x + i[1] * w.y * w.y + i[2] * w.z * w.z)
}

/// (kinetic, potential, dissipated, input work, root work) [J] now.
fn books(s: &mut PanelLock) -> [f64; 5] {
    let o = s.outputs();
    [
        o.kinetic,
        o.potential,
        o.dissipated,
        o.input_work,
        o.root_work,
    ]
}

#[test]
fn root_work_is_the_satellite_s_kinetic_energy_lost_and_closes_the_array_s_balance() {
    // the default array with cable loops, deployed by its springs and a 0.3 N m root motor on a
    // free satellite (no gravity, no satellite loads) through every lock-up ([`tight`]):
    // root work = -(change of the satellite's kinetic energy), and root work + motor work =
    // change of the array's kinetic energy (total less the satellite's) + potential + dissipated,
    // both to 1e-6 of the energy moved (the springs' energy released plus the ports' work) at
    // the end of the run, and to 1e-5 at every communication point on the way
    let mut s = PanelLock::new(tight(true)).unwrap();
    s.set_motor_torque(0.3).unwrap();
    let (e0, ks0) = (books(&mut s), satellite_kinetic(&mut s));
    let (mut worst_sat, mut worst_array, mut largest_power) = (0.0f64, 0.0f64, 0.0f64);
    let mut scale = 0.0f64;
    let mut t = 0.0;
    while t < 16.0 {
        t += 0.1;
        s.advance_to(t).unwrap();
        let e = books(&mut s);
        let ks = satellite_kinetic(&mut s);
        largest_power = largest_power.max(s.outputs().root_power.abs());
        let (root, motor) = (e[4] - e0[4], e[3] - e0[3]);
        let array = (e[0] - ks) - (e0[0] - ks0) + (e[1] - e0[1]) + (e[2] - e0[2]);
        scale = scale.max((e0[1] - e[1]).abs() + root.abs() + motor.abs());
        worst_sat = worst_sat.max((root + (ks - ks0)).abs());
        worst_array = worst_array.max((root + motor - array).abs());
    }
    assert!(s.lock_times().iter().all(|t| t.is_finite()));
    let e = books(&mut s);
    println!(
        "root work {:.6e} J, motor work {:.6e} J, satellite kinetic {:.6e} J; largest |root power| {largest_power:.3e} W; satellite off by {:.2e}, array off by {:.2e} of {scale:.4e} J",
        e[4] - e0[4],
        e[3] - e0[3],
        satellite_kinetic(&mut s) - ks0,
        worst_sat / scale,
        worst_array / scale
    );
    let ks = satellite_kinetic(&mut s);
    let (root, motor) = (e[4] - e0[4], e[3] - e0[3]);
    let array = (e[0] - ks) - (e0[0] - ks0) + (e[1] - e0[1]) + (e[2] - e0[2]);
    let (end_sat, end_array) = ((root + ks - ks0).abs(), (root + motor - array).abs());
    println!(
        "at the end: satellite off by {:.2e}, array off by {:.2e}",
        end_sat / scale,
        end_array / scale
    );
    assert!(root.abs() > 1e-4 * scale, "the satellite takes part");
    assert!(end_sat < 1e-6 * scale && end_array < 1e-6 * scale);
    assert!(worst_sat < 1e-5 * scale, "{worst_sat}");
    assert!(worst_array < 1e-5 * scale, "{worst_array}");
}

#[test]
fn a_fixed_satellite_s_bond_carries_no_power() {
    // the satellite does not move: the interface power and its work are exactly 0 while the
    // wrench is not, and the motor's work alone closes the balance (1e-6 of the energy moved at
    // the end, 1e-5 on the way)
    let mut s = PanelLock::new(tight(false)).unwrap();
    s.set_motor_torque(0.3).unwrap();
    let e0 = books(&mut s);
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    let mut t = 0.0;
    while t < 16.0 {
        t += 0.1;
        s.advance_to(t).unwrap();
        let o = s.outputs();
        assert_eq!((o.root_power, o.root_work), (0.0, 0.0));
        assert!(o.root_force.norm() + o.root_torque.norm() > 0.0);
        let e = books(&mut s);
        let stored = (e[0] - e0[0]) + (e[1] - e0[1]) + (e[2] - e0[2]);
        scale = scale.max((e0[1] - e[1]).abs() + (e[3] - e0[3]).abs());
        worst = worst.max((e[3] - e0[3] - stored).abs());
    }
    let e = books(&mut s);
    let end = (e[3] - e0[3] - ((e[0] - e0[0]) + (e[1] - e0[1]) + (e[2] - e0[2]))).abs();
    println!(
        "fixed satellite: balance off by {:.2e} at the end, {:.2e} at worst, of {scale:.4e} J",
        end / scale,
        worst / scale
    );
    assert!(end < 1e-6 * scale, "{end}");
    assert!(worst < 1e-5 * scale, "{worst}");
}
