//! Isolated impacts (1 kg at 1 m/s on a half-space, n = 1.5) integrated by the product's own
//! integrators: Hertz peak force and contact duration against the closed form, and the effective
//! restitution of each damped law against the published table.

use mbcosim::contact::{ContactLaw, LawKind};
use mbcosim::effect::plane_contact::{PlaneContact, PlaneContacts};
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::Vec3;
use mbcosim::model::{BodyId, Frame, ModelBuilder};
use mbcosim::sim::Simulation;
use std::sync::Arc;

/// A particle touching the plane z = 0 at t = 0, moving into it at 1 m/s.
fn impact(law: ContactLaw, kind: IntegratorKind) -> Simulation {
    let mut b = ModelBuilder::new();
    let p = b
        .add_particle("ball", 1.0, Vec3::zeros(), Vec3::new(0.0, 0.0, -1.0))
        .unwrap();
    let contact = PlaneContact {
        name: "floor".into(),
        point: Frame::new(p, Vec3::zeros()),
        normal: Vec3::z(),
        offset: 0.0,
        law,
    };
    b.add_force_effect(Arc::new(PlaneContacts {
        elements: vec![contact],
    }));
    let _ = BodyId::GROUND;
    // generalized-alpha holds its error per unit step: at 1e-11 / 1e-14 it would take more than
    // 200,000 steps per call; 1e-9 / 1e-12 holds it to the closed form as tightly
    let (rtol, atol) = if kind == IntegratorKind::GenAlpha {
        (1e-9, 1e-12)
    } else {
        (1e-11, 1e-14)
    };
    let s = Settings {
        rtol,
        atol,
        h_max: 2e-5,
        ..Settings::default()
    };
    Simulation::new(b.build().unwrap(), kind, s, 0.0).unwrap()
}

/// Time at which `f(sim)` changes sign from positive to non-positive after t = 0, located by
/// bisection on re-simulations from snapshots (to 1e-12 s), and the simulation there.
fn locate(mut sim: Simulation, dt: f64, f: impl Fn(&Simulation) -> f64) -> Simulation {
    loop {
        let before = sim.clone();
        let t = sim.state.t + dt;
        sim.advance_to(t).unwrap();
        if f(&sim) <= 0.0 {
            let (mut lo, mut hi) = (before.state.t, t);
            let mut best = sim;
            while hi - lo > 1e-12 {
                let mid = 0.5 * (lo + hi);
                let mut s = before.clone();
                s.advance_to(mid).unwrap();
                if f(&s) <= 0.0 {
                    hi = mid;
                    best = s;
                } else {
                    lo = mid;
                }
            }
            return best;
        }
        assert!(sim.state.t < 1.0, "no sign change");
    }
}

#[test]
fn hertz_peak_force_and_duration_match_closed_form() {
    for (k, f_ref, tc_ref) in [(1e7, 721.350, 5.10029e-3), (1e8, 1811.949, 2.03046e-3)] {
        for kind in [
            IntegratorKind::GenAlpha,
            IntegratorKind::Bdf,
            IntegratorKind::Dopri5,
        ] {
            let law = ContactLaw::hertz(k, 1.5).unwrap();
            // deepest point: the velocity changes sign
            let at_peak = locate(impact(law, kind), 1e-4, |s| -s.state.v[2]);
            let delta = -at_peak.state.q[2];
            let f_max = k * delta.powf(1.5);
            // separation: the particle leaves the plane
            let apart = locate(at_peak, 1e-4, |s| -s.state.q[2]);
            let tc = apart.state.t;
            let (ef, et) = ((f_max - f_ref).abs() / f_ref, (tc - tc_ref).abs() / tc_ref);
            println!(
                "k={k:e} {:10} F_max {f_max:.4} ({ef:.1e}) t_c {:.6} ms ({et:.1e})",
                kind.name(),
                tc * 1e3
            );
            assert!(
                ef < 1e-4 && et < 1e-4,
                "{}: F_max {f_max} vs {f_ref}, t_c {tc} vs {tc_ref}",
                kind.name()
            );
            // undamped: rebound speed equals the impact speed
            assert!(
                (apart.state.v[2] - 1.0).abs() < 1e-5,
                "rebound speed {}",
                apart.state.v[2]
            );
        }
    }
}

#[test]
fn damped_laws_reproduce_the_effective_restitution_table() {
    let nominal = [0.95, 0.9, 0.8, 0.6, 0.4, 0.2];
    let table = [
        (
            LawKind::LankaraniNikravesh,
            [0.9535, 0.9132, 0.8471, 0.7561, 0.7016, 0.6723],
        ),
        (
            LawKind::HuntCrossley,
            [0.9524, 0.909, 0.8329, 0.712, 0.6197, 0.5469],
        ),
        (
            LawKind::Flores,
            [0.9468, 0.8939, 0.7885, 0.5773, 0.3629, 0.1555],
        ),
    ];
    for kind in [IntegratorKind::Bdf, IntegratorKind::GenAlpha] {
        for (law_kind, expected) in table {
            for (e, want) in nominal.iter().zip(expected) {
                let law = ContactLaw::new(law_kind, 1e7, 1.5, *e).unwrap();
                let apart = locate(impact(law, kind), 1e-4, |s| -s.state.q[2]);
                let e_eff = apart.state.v[2];
                assert!(
                    (e_eff - want).abs() < 1e-3,
                    "{} {law_kind:?} e = {e}: effective {e_eff:.5} vs table {want}",
                    kind.name()
                );
            }
        }
    }
}
