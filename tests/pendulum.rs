//! Simple pendulum: period against the elliptic-integral closed form, for every integrator.

mod common;
use common::*;
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::sim::Simulation;

/// Time of the first downward zero crossing of the bob's x coordinate after release at +x,
/// located by bisection on re-simulations from snapshots; a quarter period.
fn quarter_period(kind: IntegratorKind, angle0: f64, rtol: f64) -> f64 {
    // generalized-alpha: atol = rtol (with atol 1e-2 rtol the small coordinates' weights put the
    // steps where its index-3 round-off fills the error estimate, and it stops on purpose)
    let atol = if kind == IntegratorKind::GenAlpha {
        rtol
    } else {
        rtol * 1e-2
    };
    let settings = Settings {
        rtol,
        atol,
        h_max: 0.01,
        ..Settings::default()
    };
    let mut sim = Simulation::new(simple_pendulum(1.0, angle0), kind, settings, 0.0).unwrap();
    let dt = 0.01;
    loop {
        let before = sim.clone();
        let t = sim.state.t + dt;
        sim.advance_to(t).unwrap();
        if sim.state.q[0] <= 0.0 {
            let (mut lo, mut hi) = (before.state.t, t);
            while hi - lo > 1e-12 {
                let mid = 0.5 * (lo + hi);
                let mut s = before.clone();
                s.advance_to(mid).unwrap();
                if s.state.q[0] <= 0.0 {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            return 0.5 * (lo + hi);
        }
    }
}

#[test]
fn ninety_degree_release_matches_elliptic_period() {
    // 4 sqrt(L/g) K(m = 1/2), L = 1 m, g = 9.81, scaled for the bob's inertia (1e-6 kg m^2):
    // the physical pendulum's period is sqrt(I_pivot / (m L^2)) times the mathematical one.
    let exact = 2.3678419475762 * (1.0f64 + 1e-6).sqrt();
    for kind in IntegratorKind::ALL {
        let rtol = match kind {
            IntegratorKind::GenAlpha => 1e-8,
            _ => 1e-10,
        };
        let period = 4.0 * quarter_period(kind, std::f64::consts::FRAC_PI_2, rtol);
        let rel = (period - exact).abs() / exact;
        println!("{:10} period {period:.12} rel err {rel:.2e}", kind.name());
        assert!(
            rel < 1e-6,
            "{}: period {period}, relative error {rel:.3e}",
            kind.name()
        );
    }
}

#[test]
fn small_angle_period_matches_linear_theory() {
    let angle0: f64 = 0.01;
    // small-angle formula of the physical pendulum (bob inertia 1e-6 kg m^2 about its centre),
    // with the first amplitude correction (theta0^2 / 16)
    let i_pivot = 1.0 + 1e-6;
    let exact = 2.0 * std::f64::consts::PI * (i_pivot / G).sqrt() * (1.0 + angle0 * angle0 / 16.0);
    for kind in IntegratorKind::ALL {
        let rtol = match kind {
            IntegratorKind::GenAlpha => 1e-8,
            _ => 1e-9,
        };
        let period = 4.0 * quarter_period(kind, angle0, rtol);
        let rel = (period - exact).abs() / exact;
        assert!(
            rel < 1e-6,
            "{}: period {period} vs {exact}, relative error {rel:.3e}",
            kind.name()
        );
    }
}
