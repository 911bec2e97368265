//! The root interface wrench that PanelLock reports (`root_force_*`, `root_torque_*`) against
//! the momentum balance of the array, which does not go through the force bookkeeping that
//! computes it: the wrench of the satellite on the array plus the array's weight equals the
//! rate of change of the array's momentum, `sum m_i a_i` and, about the interface point `O`,
//! `sum (r_i - O) x m_i a_i + A_i (J_i omega_dot_i + omega_i x J_i omega_i)`, with the
//! accelerations of the index-1 equations. With a free satellite the same wrench also
//! accelerates the satellite (its only load). And the tracked peaks bound every sampled value
//! and do not miss the impacts between communication points.

mod common;

use mbcosim::integrator::IntegratorKind;
use mbcosim::math::Vec3;
use mbcosim::model::BodyKind;
use mbcosim::scene::panel_lock::interface::interface_point;
use mbcosim::scene::panel_lock::{PanelLock, PanelLockParams};

/// Force and torque [N, N m] of the momentum balance of the bodies `keep` selects, about `o`,
/// world frame: `sum m a - sum m g` and `sum (r - O) x (m a - m g) + A (J omega_dot + omega x
/// J omega)`; also the scale of the terms summed (for round-off).
fn momentum_rate(s: &mut PanelLock, keep: &dyn Fn(usize) -> bool, o: Vec3) -> (Vec3, Vec3, f64) {
    let (vdot, _) = s.sim.index1_solution().unwrap();
    let st = s.sim.state.clone();
    s.sim.system.update_kinematics(&st.q, &st.v);
    let g = s
        .params
        .gravity
        .map_or(Vec3::zeros(), |g| Vec3::new(0.0, 0.0, -g));
    let (mut force, mut torque, mut scale) = (Vec3::zeros(), Vec3::zeros(), 0.0);
    for (i, body) in s.sim.system.model.bodies.iter().enumerate() {
        if !keep(i) {
            continue;
        }
        let BodyKind::Rigid { mass, inertia } = &body.kind else {
            panic!("rigid bodies only");
        };
        let k = s.sim.system.kins()[i];
        let c = body.v_offset;
        let a = Vec3::new(vdot[c], vdot[c + 1], vdot[c + 2]);
        let wdot = Vec3::new(vdot[c + 3], vdot[c + 4], vdot[c + 5]);
        let net = *mass * (a - g);
        let spin = k.rot * (inertia * wdot + k.omega.cross(&(inertia * k.omega)));
        force += net;
        torque += (k.r - o).cross(&net) + spin;
        scale += net.norm() * (1.0 + (k.r - o).norm()) + spin.norm();
    }
    (force, torque, scale)
}

/// The default rigid array with gravity along the hinge axes (so the interface carries forces
/// and torques about all three axes) and a root motor torque, on `kind` at a tight tolerance.
fn loaded(kind: IntegratorKind, free_satellite: bool) -> PanelLock {
    let p = PanelLockParams {
        gravity: Some(9.81),
        free_satellite,
        cable_loop: true,
        ..common::panel_lock::per_step(kind, 1e-8)
    };
    let mut s = PanelLock::new(p).unwrap();
    s.set_motor_torque(0.3).unwrap();
    s
}

/// Largest deviation of the reported interface wrench from the array's momentum balance over a
/// deployment through every lock-up, relative to the scale of the terms; and the largest
/// interface force seen.
fn worst_balance(mut s: PanelLock, satellite_side: bool) -> (f64, f64) {
    let satellite = s.layout.satellite.index();
    let (mut worst, mut largest) = (0.0f64, 0.0f64);
    let mut t = 0.0;
    while t < 16.0 {
        let o = s.outputs();
        let point = interface_point(&s.sim.system, &s.layout);
        // the array: minus the satellite's load on it; the satellite: the array's load on it
        let (force, torque, scale) = if satellite_side {
            momentum_rate(&mut s, &|i| Some(i) == satellite, point)
        } else {
            let (f, m, sc) = momentum_rate(&mut s, &|i| Some(i) != satellite, point);
            (-f, -m, sc)
        };
        let err = (o.root_force - force)
            .norm()
            .max((o.root_torque - torque).norm());
        worst = worst.max(err / scale.max(1e-12));
        largest = largest.max(o.root_force.norm());
        t += 0.02;
        s.advance_to(t).unwrap();
    }
    assert!(
        s.lock_times().iter().all(|t| t.is_finite()),
        "every hinge locks within the run"
    );
    (worst, largest)
}

#[test]
fn interface_wrench_equals_the_arrays_momentum_balance() {
    for kind in [IntegratorKind::Dopri5, IntegratorKind::GenAlpha] {
        let (worst, largest) = worst_balance(loaded(kind, false), false);
        println!("{kind:?}: largest |W - dP/dt| / scale {worst:.2e}, largest force {largest:.1} N");
        assert!(
            worst < 1e-6,
            "{kind:?}: interface wrench off the momentum balance by {worst:.2e}"
        );
        assert!(
            largest > 100.0,
            "the lock-ups load the interface ({largest} N)"
        );
    }
}

#[test]
fn interface_wrench_accelerates_a_free_satellite() {
    let s = loaded(IntegratorKind::Dopri5, true);
    let (worst, largest) = worst_balance(s, true);
    println!("free satellite: largest |W - m_s a_s| / scale {worst:.2e}, largest {largest:.1} N");
    assert!(
        worst < 1e-6,
        "interface wrench off the satellite's momentum balance by {worst:.2e}"
    );
}

#[test]
fn interface_torque_about_the_axes_carries_the_spring_and_motor_at_rest() {
    // at t = 0 the stowed array rests against its stow stops: about the hinge axis the
    // interface carries the root spring's preload plus the motor torque (both deploy, so the
    // satellite feels their reaction), whatever the stops do inside the array
    let p = PanelLockParams {
        latches: false,
        ..common::panel_lock::per_step(IntegratorKind::Dopri5, 1e-8)
    };
    let mut s = PanelLock::new(p).unwrap();
    let rate = |s: &mut PanelLock| {
        let point = interface_point(&s.sim.system, &s.layout);
        let sat = s.layout.satellite.index();
        momentum_rate(s, &|i| Some(i) != sat, point)
    };
    let o = s.outputs();
    let (_, torque, _) = rate(&mut s);
    println!(
        "at rest: root torque {:?}, array momentum rate {:?}",
        o.root_torque, -torque
    );
    assert!(
        o.root_torque.z.abs() > 0.1,
        "the spring preload acts across the interface"
    );
    assert!((o.root_torque + torque).norm() < 1e-9 * o.root_torque.norm());
    s.set_motor_torque(0.5).unwrap();
    let with_motor = s.outputs();
    let (_, torque, _) = rate(&mut s);
    assert!((with_motor.root_torque + torque).norm() < 1e-9 * with_motor.root_torque.norm());
    assert!(
        (with_motor.root_torque.z - o.root_torque.z).abs() > 0.1,
        "the motor's torque acts on the satellite too"
    );
    // the peak takes the load from the instant the input changed it
    assert!(with_motor.root_peak_torque >= with_motor.root_torque.norm());
    assert!(with_motor.root_peak_force >= with_motor.root_force.norm());
}

#[test]
fn tracked_peaks_bound_the_samples_and_do_not_miss_the_impacts() {
    // the peaks at a coarse communication step against the largest values sampled at a fine
    // one (and at its own points): a peak taken only at communication points misses the
    // lock-up impacts by tens of percent at 0.1 s
    let run = |h: f64| {
        let mut s =
            PanelLock::new(common::panel_lock::per_step(IntegratorKind::Dopri5, 1e-8)).unwrap();
        let (mut sampled_f, mut sampled_m) = (0.0f64, 0.0f64);
        let n = (16.0 / h).round() as usize;
        for j in 1..=n {
            s.advance_to(j as f64 * h).unwrap();
            let o = s.outputs();
            sampled_f = sampled_f.max(o.root_force.norm());
            sampled_m = sampled_m.max(o.root_torque.norm());
            assert!(o.root_peak_force >= sampled_f && o.root_peak_torque >= sampled_m);
        }
        let o = s.outputs();
        (o.root_peak_force, o.root_peak_torque, sampled_f, sampled_m)
    };
    let (fine_f, fine_m, fine_sf, fine_sm) = run(0.001);
    let (coarse_f, coarse_m, coarse_sf, coarse_sm) = run(0.1);
    println!(
        "peaks at 1 ms: {fine_f:.2} N {fine_m:.3} N m (sampled {fine_sf:.2}, {fine_sm:.3}); \
         at 0.1 s: {coarse_f:.2} N {coarse_m:.3} N m (sampled {coarse_sf:.2}, {coarse_sm:.3})"
    );
    assert!(
        (coarse_f - fine_sf).abs() < 0.01 * fine_sf,
        "force peak {coarse_f} vs {fine_sf}"
    );
    assert!(
        (coarse_m - fine_sm).abs() < 0.01 * fine_sm,
        "torque peak {coarse_m} vs {fine_sm}"
    );
}
