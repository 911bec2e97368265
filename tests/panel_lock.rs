//! PanelLock deployment and lock-up against independent references: lock order, energy balance,
//! static contact equilibrium, convergence with tolerance, and agreement of the integrators.

mod common;
use mbcosim::contact::ContactLaw;
use mbcosim::integrator::IntegratorKind;
use mbcosim::scene::panel_lock::{PanelLock, PanelLockParams};

/// The default scene on BDF at `rtol`, the error held per step (the tolerances of these tests
/// were chosen for that, the default before docs/panel_lock_defaults.md).
fn params(rtol: f64) -> PanelLockParams {
    common::panel_lock::per_step(IntegratorKind::Bdf, rtol)
}

/// Spring energy released between the stowed and the lock angles of every hinge [J].
fn released_spring_energy(p: &PanelLockParams) -> f64 {
    let one = |k: f64, preload: f64, stow: f64, lock: f64| {
        let free = lock + preload / k;
        0.5 * k * ((free - stow).powi(2) - (free - lock).powi(2))
    };
    one(
        p.root_spring_stiffness,
        p.root_spring_preload,
        p.root_stowed_angle,
        p.root_lock_angle,
    ) + p.n_panels as f64
        * one(
            p.panel_spring_stiffness,
            p.panel_spring_preload,
            p.panel_stowed_angle,
            p.panel_lock_angle,
        )
}

#[test]
fn hinges_lock_in_the_designed_order_and_the_energy_balance_closes() {
    // Designed order of the default array: the root hinge (strongest spring, smallest inertia while
    // the stack is folded) first, then the panel hinges from the outermost to the innermost (the
    // outer hinges carry the least inertia outboard of them).
    let mut drifts = Vec::new();
    for rtol in [1e-5, 1e-7] {
        let p = params(rtol);
        let released = released_spring_energy(&p);
        let mut s = PanelLock::new(p).unwrap();
        let o0 = s.outputs();
        let e0 = o0.kinetic + o0.potential;
        s.advance_to(40.0).unwrap();
        let o = s.outputs();
        let times: Vec<f64> = o.hinges.iter().map(|h| h.lock_time).collect();
        assert!(
            times.iter().all(|t| t.is_finite()),
            "all hinges lock within 40 s: {times:?}"
        );
        let n = times.len();
        assert!(times[0] < times[n - 1], "root first: {times:?}");
        for k in (2..n).rev() {
            assert!(
                times[k] < times[k - 1],
                "hinge {k} before hinge {}: {times:?}",
                k - 1
            );
        }
        // spring energy released = kinetic + dissipated (+ contact and stop energy stored)
        let drift = (o.kinetic + o.potential + o.dissipated - o.input_work - e0).abs() / released;
        println!(
            "rtol {rtol:e}: lock times {times:?}, balance error {drift:.2e} of {released:.3} J"
        );
        drifts.push(drift);
    }
    assert!(
        drifts[0] < 2e-3,
        "energy balance at rtol 1e-5: {:.3e}",
        drifts[0]
    );
    assert!(
        drifts[1] < 5e-5 && drifts[1] < drifts[0] / 10.0,
        "energy balance converges with the tolerance: {drifts:?}"
    );
}

#[test]
fn locked_latch_settles_at_the_contact_law_equilibrium() {
    // One panel, strong hinge and contact damping so the locked array settles; then every hinge's
    // spring torque is carried by its front wall alone: F(delta) * arm = tau_spring(theta).
    let p = PanelLockParams {
        n_panels: 1,
        hinge_damping: 0.3,
        restitution: 0.3,
        ..params(1e-9)
    };
    let law = ContactLaw::new(
        p.contact_law,
        p.contact_stiffness,
        p.contact_exponent,
        p.restitution,
    )
    .unwrap();
    let mut s = PanelLock::new(p.clone()).unwrap();
    s.advance_to(300.0).unwrap();
    for k in 0..2 {
        let (theta, rate) = s.hinge_angle(k);
        assert!(
            rate.abs() < 1e-7,
            "hinge {k} still moving at {rate:e} rad/s"
        );
        let (kk, preload, lock) = if k == 0 {
            (
                p.root_spring_stiffness,
                p.root_spring_preload,
                p.root_lock_angle,
            )
        } else {
            (
                p.panel_spring_stiffness,
                p.panel_spring_preload,
                p.panel_lock_angle,
            )
        };
        let tau_spring = kk * (lock + preload / kk - theta);
        // the latch geometry gives the penetration and arm at theta
        let geo = &s.layout.latches.as_ref().unwrap().elements[k].geometry;
        let wall = geo.query(theta, true).unwrap().unwrap().front;
        let expected = law
            .static_penetration(tau_spring / wall.moment_arm.abs())
            .unwrap();
        let rel = (wall.penetration - expected).abs() / expected;
        println!(
            "hinge {k}: delta {:.6e} m, law equilibrium {expected:.6e} m, rel {rel:.1e}",
            wall.penetration
        );
        assert!(
            rel < 1e-3,
            "hinge {k}: static penetration {} vs {expected}",
            wall.penetration
        );
    }
}

/// Root-hinge lock time [s] and peak lock force [N] (the first lock-up).
fn first_lock(kind: IntegratorKind, rtol: f64) -> (f64, f64) {
    let mut s = PanelLock::new(PanelLockParams {
        integrator: Some(kind),
        ..params(rtol)
    })
    .unwrap();
    s.advance_to(6.0).unwrap();
    let h = s.outputs().hinges[0];
    (h.lock_time, h.peak_force)
}

#[test]
fn peak_lock_force_and_lock_time_converge_with_the_tolerance() {
    let (t_ref, f_ref) = first_lock(IntegratorKind::Bdf, 1e-10);
    let mut prev = f64::INFINITY;
    for rtol in [1e-4, 1e-6, 1e-8] {
        let (t, f) = first_lock(IntegratorKind::Bdf, rtol);
        let err = ((f - f_ref) / f_ref).abs().max((t - t_ref).abs() / t_ref);
        println!(
            "rtol {rtol:e}: lock time {t:.6} s, peak force {f:.3} N, error {err:.2e} (reference {t_ref:.6} s, {f_ref:.3} N)"
        );
        assert!(err < prev, "error {err:e} did not shrink at rtol {rtol:e}");
        prev = err;
    }
    assert!(prev < 1e-4, "rtol 1e-8 error {prev:e}");
}

#[test]
fn every_integrator_gives_the_same_lock_up() {
    let (t_ref, f_ref) = first_lock(IntegratorKind::Bdf, 1e-9);
    for kind in IntegratorKind::ALL {
        let (t, f) = first_lock(kind, 1e-8);
        println!("{:10} lock {t:.6} s, peak {f:.3} N", kind.name());
        assert!(
            (t - t_ref).abs() / t_ref < 1e-4,
            "{}: lock time {t} vs {t_ref}",
            kind.name()
        );
        assert!(
            (f - f_ref).abs() / f_ref < 1e-3,
            "{}: peak force {f} vs {f_ref}",
            kind.name()
        );
    }
}

#[test]
fn free_floating_satellite_keeps_the_total_momentum() {
    // no external loads: linear and angular momentum of satellite + array stay zero while the
    // springs deploy the array and the latches lock
    use mbcosim::math::Vec3;
    use mbcosim::model::BodyKind;
    use mbcosim::model::kinematics::quat_at;
    let mut s = PanelLock::new(PanelLockParams {
        free_satellite: true,
        ..params(1e-9)
    })
    .unwrap();
    let momentum = |s: &PanelLock| {
        let (mut p, mut l) = (Vec3::zeros(), Vec3::zeros());
        let (q, v) = (&s.sim.state.q, &s.sim.state.v);
        for b in &s.sim.system.model.bodies {
            let (qo, vo) = (b.q_offset, b.v_offset);
            let r = Vec3::new(q[qo], q[qo + 1], q[qo + 2]);
            let vel = Vec3::new(v[vo], v[vo + 1], v[vo + 2]);
            if let BodyKind::Rigid { mass, inertia } = &b.kind {
                let w = Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]);
                p += *mass * vel;
                l += r.cross(&(*mass * vel)) + quat_at(q, qo + 3) * (inertia * w);
            }
        }
        (p, l)
    };
    let mut worst: f64 = 0.0;
    let mut max_l: f64 = 0.0;
    for k in 1..=30 {
        s.advance_to(0.5 * k as f64).unwrap();
        let (p, l) = momentum(&s);
        worst = worst.max(p.norm()).max(l.norm());
        // the array's own angular momentum about the origin, as a scale
        max_l = max_l.max(s.outputs().kinetic.sqrt());
    }
    println!("free satellite: worst |p|, |L| = {worst:.2e} (kinetic-energy scale {max_l:.2e})");
    assert!(
        s.outputs().hinges[0].engaged,
        "the root hinge locks within 15 s"
    );
    assert!(worst < 1e-6, "total momentum {worst:e} not conserved");
}

#[test]
fn cable_loops_synchronize_the_hinges() {
    // progress of each hinge from stowed (0) to locked (1); the cable loops keep them together
    let spread = |cable: bool| {
        let mut s = PanelLock::new(PanelLockParams {
            cable_loop: cable,
            latches: false,
            ..params(1e-7)
        })
        .unwrap();
        let p = s.params.clone();
        let mut worst: f64 = 0.0;
        for k in 1..=40 {
            s.advance_to(0.1 * k as f64).unwrap();
            let prog: Vec<f64> = (0..p.n_hinges())
                .map(|h| {
                    let (stow, lock) = if h == 0 {
                        (p.root_stowed_angle, p.root_lock_angle)
                    } else {
                        (p.panel_stowed_angle, p.panel_lock_angle)
                    };
                    (s.hinge_angle(h).0 - stow) / (lock - stow)
                })
                .collect();
            let (lo, hi) = prog
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |a, x| {
                    (a.0.min(*x), a.1.max(*x))
                });
            worst = worst.max(hi - lo);
        }
        worst
    };
    let (free, synced) = (spread(false), spread(true));
    println!("largest progress spread over 4 s: {free:.3} without, {synced:.4} with cable loops");
    assert!(
        free > 0.2,
        "without loops the hinges deploy unevenly ({free})"
    );
    assert!(
        synced < 0.1 * free,
        "cable loops must synchronize: {synced} vs {free}"
    );
}

#[test]
fn gravity_along_the_hinge_axes_is_carried_by_the_root_shaft() {
    // at t = 0 the vertical interface force comes from the weight alone (the springs act
    // about z): the array hangs its whole weight on the satellite, F_z = -m_array g
    let p = PanelLockParams {
        gravity: Some(9.81),
        ..params(1e-8)
    };
    let m_array =
        p.yoke_mass + p.n_panels as f64 * p.panel_mass() + p.n_hinges() as f64 * p.hinge_mass;
    let mut s = PanelLock::new(p).unwrap();
    let o = s.outputs();
    let rel = (o.root_force.z + m_array * 9.81).abs() / (m_array * 9.81);
    println!(
        "vertical interface force {:.6} N vs weight {:.6} N",
        o.root_force.z,
        m_array * 9.81
    );
    assert!(
        rel < 1e-9,
        "vertical root force {} vs weight {}",
        o.root_force.z,
        m_array * 9.81
    );
    // gravity along the axes does no work on the deployment: same lock time as in orbit
    s.advance_to(6.0).unwrap();
    let mut orbit = PanelLock::new(params(1e-8)).unwrap();
    orbit.advance_to(6.0).unwrap();
    let (a, b) = (
        s.outputs().hinges[0].lock_time,
        orbit.outputs().hinges[0].lock_time,
    );
    assert!(
        (a - b).abs() < 1e-6,
        "lock time with gravity {a} vs orbit {b}"
    );
}
