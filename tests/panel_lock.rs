//! PanelLock deployment and lock-up against independent references: lock order, energy balance,
//! static contact equilibrium, convergence with tolerance, and agreement of the integrators.

use mbcosim::contact::ContactLaw;
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::{PanelLock, PanelLockParams};

fn params(rtol: f64) -> PanelLockParams {
    PanelLockParams {
        settings: Settings {
            rtol,
            atol: rtol * 1e-2,
            h_max: 0.02,
            ..Settings::default()
        },
        ..PanelLockParams::default()
    }
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
        integrator: kind,
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
