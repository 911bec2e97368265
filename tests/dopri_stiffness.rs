//! DOPRI5's stiffness watch against a linear oscillator whose eigenvalues are known in closed
//! form: a 1 kg particle on a spring-damper to the ground, `m x'' + c x' + k x = 0`, roots
//! `r = (-c +- sqrt(c^2 - 4 m k)) / (2 m)`. Overdamped, the fast root `~ -c / m` bounds an
//! explicit step to about `3.3 m / c` (DOPRI5's stability boundary on the negative real axis)
//! long after its transient has died out.

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::Vec3;
use mbcosim::model::{BodyId, Frame, ModelBuilder, SpringDamper};
use mbcosim::sim::Simulation;

const MASS: f64 = 1.0;
const STIFFNESS: f64 = 1.0;
/// Start [m] along x from the spring's free length.
const X0: f64 = 0.1;

fn oscillator(damping: f64) -> Simulation {
    let mut b = ModelBuilder::new();
    b.set_gravity(None).unwrap();
    let p = b
        .add_particle("mass", MASS, Vec3::new(1.0 + X0, 0.0, 0.0), Vec3::zeros())
        .unwrap();
    b.add_spring_damper(SpringDamper {
        name: "spring".into(),
        a: Frame::new(BodyId::GROUND, Vec3::zeros()),
        b: Frame::new(p, Vec3::zeros()),
        stiffness: STIFFNESS,
        damping,
        free_length: 1.0,
    })
    .unwrap();
    let s = Settings {
        rtol: 1e-6,
        atol: 1e-8,
        max_steps: 10_000_000,
        ..Settings::default()
    };
    Simulation::new(b.build().unwrap(), IntegratorKind::Dopri5, s, 0.0).unwrap()
}

/// Displacement [m] at `t` [s] of the overdamped oscillator released at rest from `X0`.
fn exact(damping: f64, t: f64) -> f64 {
    let d = (damping * damping - 4.0 * MASS * STIFFNESS).sqrt();
    let (r1, r2) = ((-damping + d) / (2.0 * MASS), (-damping - d) / (2.0 * MASS));
    // x(0) = X0, x'(0) = 0
    let a = X0 * r2 / (r2 - r1);
    let b = X0 - a;
    a * (r1 * t).exp() + b * (r2 * t).exp()
}

/// `c = 1e5 N s/m`: the fast root is -1e5 1/s, the slow one -1e-5 1/s; a call to 10 s would
/// take 300,000 explicit steps of about 3.3e-5 s. The run stops as stiff within its first few
/// thousand steps, and the step it names sits at the stability boundary `3.3 m / c`.
#[test]
fn a_stiff_run_stops_naming_the_stiffness_at_the_stability_boundary() {
    let c = 1e5;
    let mut sim = oscillator(c);
    let err = sim.advance_to(10.0).unwrap_err().to_string();
    let steps = sim.stats().steps;
    println!("{err}\nsteps {steps}");
    assert!(
        err.contains("dopri5 is stiff") && err.contains("bdf or gen_alpha"),
        "{err}"
    );
    assert!(steps < 5_000, "stopped only after {steps} steps");
    let h = sim.stats().last_step;
    let boundary = 3.3 * MASS / c;
    assert!(
        (0.5 * boundary..1.5 * boundary).contains(&h),
        "last step {h:.3e} s, stability boundary {boundary:.3e} s"
    );
    // the state where it stopped is still the solution (the steps were stable)
    let x = sim.state.q[0] - 1.0;
    let want = exact(c, sim.state.t);
    assert!((x - want).abs() < 1e-6, "x {x:.9e} against {want:.9e}");
}

/// `c = 1e3 N s/m`: steps held near 3.3e-3 s, but communication steps of 0.01 s need only a
/// few of them: the run goes on to the end and follows the closed form.
#[test]
fn a_mildly_stiff_run_with_short_calls_goes_on() {
    let c = 1e3;
    let mut sim = oscillator(c);
    let mut worst: f64 = 0.0;
    for k in 1..=500 {
        let t = 0.01 * k as f64;
        sim.advance_to(t).unwrap();
        worst = worst.max((sim.state.q[0] - 1.0 - exact(c, t)).abs());
    }
    let st = sim.stats();
    println!(
        "steps {}, last step {:.3e} s, worst error {worst:.3e} m",
        st.steps, st.last_step
    );
    assert!(
        st.last_step < 3.3e-3 * 1.5,
        "not at the stability boundary: {st:?}"
    );
    assert!(worst < 1e-6, "worst error {worst:.3e} m");
}
