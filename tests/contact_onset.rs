//! Contact onset located by DOPRI5 (docs/contact_onset.md): a particle dropped from rest onto a
//! half-space, against closed forms: the onset time `sqrt(2 d / g)`, the impact speed
//! `sqrt(2 g d)` that the damped law records as its approach speed, and (Hertz, no loss) energy
//! conservation through the rebound, whose error must fall with rtol decade by decade.

mod common;
use common::particle_on_floor;
use mbcosim::contact::{ContactLaw, LawKind};
use mbcosim::dae::System;
use mbcosim::integrator::{IntegratorKind, Settings, SolverError, StepAction, StepHook};
use mbcosim::math::Vec3;
use mbcosim::model::ModelBuilder;
use mbcosim::sim::Simulation;
use mbcosim::state::State;
use std::sync::Arc;

use common::G;
/// Drop height above the plane [m].
const DROP: f64 = 0.05;
/// End time [s]: the contact (about 5 ms from 0.101 s) is over, the particle in the air.
const T_END: f64 = 0.25;

fn drop(law: ContactLaw, kind: IntegratorKind, rtol: f64) -> Simulation {
    let s = Settings {
        rtol,
        atol: rtol,
        max_steps: 10_000_000,
        ..Settings::default()
    };
    Simulation::new(particle_on_floor(law, DROP, 0.0, true), kind, s, 0.0).unwrap()
}

/// Notes every accepted step's end time and the first approach speed the contact records.
#[derive(Default)]
struct Watch {
    times: Vec<f64>,
    approach: Option<f64>,
}

impl StepHook for Watch {
    fn after_step(&mut self, _: &mut System, st: &mut State) -> Result<StepAction, SolverError> {
        self.times.push(st.t);
        if self.approach.is_none() && st.memory[0] > 0.5 {
            self.approach = Some(st.memory[1]);
        }
        Ok(StepAction::Continue)
    }
}

fn run(law: ContactLaw, kind: IntegratorKind, rtol: f64) -> (Simulation, Watch) {
    let mut sim = drop(law, kind, rtol);
    let mut w = Watch::default();
    sim.advance_with(T_END, &mut w).unwrap();
    (sim, w)
}

#[test]
fn dopri5_lands_a_step_on_the_onset_and_records_the_impact_speed() {
    let t_on = (2.0 * DROP / G).sqrt();
    let v_on = (2.0 * G * DROP).sqrt();
    let ln = ContactLaw::new(LawKind::LankaraniNikravesh, 1e7, 1.5, 0.8).unwrap();
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let (_, w) = run(ln, IntegratorKind::Dopri5, rtol);
        // a step ends at the onset: the free fall before it is exact for DOPRI5 (a quadratic),
        // so only the location on the interpolant is in error
        let nearest = w
            .times
            .iter()
            .map(|t| (t - t_on).abs())
            .fold(f64::INFINITY, f64::min);
        let approach = w.approach.expect("the contact closes");
        println!(
            "rtol {rtol:.0e}: nearest step end {nearest:.2e} s from the onset, approach speed error {:.2e} m/s",
            approach - v_on
        );
        assert!(
            nearest < rtol * t_on,
            "rtol {rtol:e}: no step ends at the onset {t_on} s (nearest {nearest:e} s away)"
        );
        // the onset speed, not the speed at the end of the first step in contact
        assert!(
            (approach - v_on).abs() < 10.0 * rtol * v_on,
            "rtol {rtol:e}: recorded approach speed {approach} m/s, impact speed {v_on} m/s"
        );
    }
}

#[test]
fn dopri5_hertz_rebound_error_falls_decade_by_decade() {
    // no loss: after the rebound v^2 / 2 + g z = g d; error as a height [m]
    let hertz = ContactLaw::hertz(1e7, 1.5).unwrap();
    let mut errors = Vec::new();
    for k in 2..=10 {
        let rtol = 10f64.powi(-k);
        let (sim, _) = run(hertz, IntegratorKind::Dopri5, rtol);
        let (z, v) = (sim.state.q[2], sim.state.v[2]);
        assert!(
            z > 0.0,
            "rtol {rtol:e}: the particle is in the air at the end"
        );
        let err = (0.5 * v * v / G + z - DROP).abs();
        println!(
            "rtol {rtol:.0e}: energy error {err:.2e} m ({:.2} rtol)",
            err / rtol
        );
        errors.push((rtol, err));
    }
    for w in errors.windows(2) {
        let ((r0, e0), (r1, e1)) = (w[0], w[1]);
        assert!(
            e1 <= e0,
            "error grew from {e0:e} at rtol {r0:e} to {e1:e} at rtol {r1:e}: {errors:?}"
        );
    }
    for (rtol, err) in &errors {
        assert!(
            *err < 30.0 * rtol,
            "rtol {rtol:e}: error {err:e}: {errors:?}"
        );
    }
}

#[test]
fn a_model_without_contacts_has_no_contact_events() {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, 0.0, -G))).unwrap();
    b.add_particle("ball", 1.0, Vec3::zeros(), Vec3::zeros())
        .unwrap();
    let sys = System::new(Arc::new(b.build().unwrap())).unwrap();
    assert_eq!(sys.n_contact_events(), 0);
    let sim = drop(
        ContactLaw::hertz(1e7, 1.5).unwrap(),
        IntegratorKind::Dopri5,
        1e-6,
    );
    assert_eq!(sim.system.n_contact_events(), 1);
}
