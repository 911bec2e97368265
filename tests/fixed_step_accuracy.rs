//! Fixed-step generalized-alpha converges at second order whatever the user's rtol/atol: the
//! Newton iteration of a fixed step stops near round-off (relative to the step's motion), not at
//! a fraction of the error tolerance (which adaptive mode uses). Before, with default tolerances
//! the planar double pendulum got *less* accurate as the step shrank (1.0e-3 at h = 2e-4,
//! 8.7e-3 at h = 1e-4), because each step left a Newton residual of the tolerance's size.
//! Measured then: 9.1e-6, 2.2e-6, 5.7e-7, 1.7e-7 m at h = 4e-4 .. 5e-5 s, at any rtol; below
//! that the error rose again (the Newton matrix was formed once per run; see
//! `fresh_fixed_step_matrix` in src/integrator/gen_alpha.rs), so the halvings go on to 1.25e-5.
//!
//! Reference: the same double pendulum in minimal (joint-angle) coordinates, integrated with
//! classical RK4 at a step whose halving changes the tip by less than 1e-12 m.

mod common;
use common::*;
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::Vec3;
use mbcosim::sim::Simulation;

/// Rod inertia about its centre, z axis (as `rod_inertia(1, 1)`: radius 0.01 m) [kg m^2].
const I_ROD: f64 = (3.0 * 0.01 * 0.01 + 1.0) / 12.0;

/// Angular accelerations of the planar double pendulum of two uniform 1 kg, 1 m rods, absolute
/// angles from the downward vertical, gravity G.
fn accelerations(th: [f64; 2], om: [f64; 2]) -> [f64; 2] {
    let (m, l) = (1.0, 1.0);
    let d = th[0] - th[1];
    let m11 = m * (l / 2.0) * (l / 2.0) + I_ROD + m * l * l;
    let m12 = m * l * (l / 2.0) * d.cos();
    let m22 = m * (l / 2.0) * (l / 2.0) + I_ROD;
    let r1 = -m * l * (l / 2.0) * d.sin() * om[1] * om[1] - (m * l / 2.0 + m * l) * G * th[0].sin();
    let r2 = m * l * (l / 2.0) * d.sin() * om[0] * om[0] - m * (l / 2.0) * G * th[1].sin();
    let det = m11 * m22 - m12 * m12;
    [(m22 * r1 - m12 * r2) / det, (m11 * r2 - m12 * r1) / det]
}

/// Tip of the second rod at `t_end` from rest at `a1`, `a2`, RK4 with `n` steps.
fn reference_tip(a1: f64, a2: f64, t_end: f64, n: usize) -> Vec3 {
    let h = t_end / n as f64;
    let mut y = [a1, a2, 0.0, 0.0];
    let f = |y: [f64; 4]| {
        let a = accelerations([y[0], y[1]], [y[2], y[3]]);
        [y[2], y[3], a[0], a[1]]
    };
    let add = |y: [f64; 4], k: [f64; 4], c: f64| std::array::from_fn(|i| y[i] + c * k[i]);
    for _ in 0..n {
        let k1 = f(y);
        let k2 = f(add(y, k1, h / 2.0));
        let k3 = f(add(y, k2, h / 2.0));
        let k4 = f(add(y, k3, h));
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    Vec3::new(y[0].sin() + y[1].sin(), -y[0].cos() - y[1].cos(), 0.0)
}

fn simulated_tip(a1: f64, a2: f64, t_end: f64, s: Settings) -> Vec3 {
    let mut sim =
        Simulation::new(double_pendulum(a1, a2), IntegratorKind::GenAlpha, s, 0.0).expect("set up");
    sim.advance_to(t_end).expect("run");
    let q = &sim.state.q;
    Vec3::new(q[7], q[8], q[9])
        + mbcosim::model::kinematics::quat_at(q, 10) * Vec3::new(0.5, 0.0, 0.0)
}

#[test]
fn fixed_step_gen_alpha_converges_at_second_order_with_default_tolerances() {
    let (a1, a2, t_end) = (1.2, 1.6, 2.0);
    let reference = reference_tip(a1, a2, t_end, 400_000);
    let check = reference_tip(a1, a2, t_end, 200_000);
    assert!(
        (reference - check).norm() < 1e-12,
        "reference not converged"
    );
    let mut errors = Vec::new();
    for h in [4e-4, 2e-4, 1e-4, 5e-5, 2.5e-5, 1.25e-5] {
        let s = Settings {
            fixed_step: h,
            ..Settings::default()
        };
        let e = (simulated_tip(a1, a2, t_end, s) - reference).norm();
        println!("h = {h:.1e} s: tip error {e:.3e} m");
        errors.push(e);
    }
    for w in errors.windows(2) {
        assert!(
            w[1] < w[0] / 3.0,
            "halving h must cut the error by >= 3x: {errors:?}"
        );
    }
    assert!(errors[2] < 1e-6, "h = 1e-4: {errors:?}");
    // and the tolerance settings no longer matter in fixed-step mode
    let loose = Settings {
        fixed_step: 1e-4,
        rtol: 1e-2,
        atol: 1e-3,
        ..Settings::default()
    };
    let e = (simulated_tip(a1, a2, t_end, loose) - reference).norm();
    assert_eq!(e, errors[2], "rtol 1e-2 changed the fixed-step result");
}

/// Tip of the double pendulum after `calls` communication steps of `comm` [s] each (one
/// `advance_to` per communication point, as an FMU importer calls `fmi2DoStep`).
fn simulated_tip_on_grid(a1: f64, a2: f64, comm: f64, calls: usize, s: Settings) -> Vec3 {
    let mut sim =
        Simulation::new(double_pendulum(a1, a2), IntegratorKind::GenAlpha, s, 0.0).expect("set up");
    for k in 1..=calls {
        sim.advance_to(k as f64 * comm).expect("run");
    }
    let q = &sim.state.q;
    Vec3::new(q[7], q[8], q[9])
        + mbcosim::model::kinematics::quat_at(q, 10) * Vec3::new(0.5, 0.0, 0.0)
}

/// A communication step that is a multiple of the fixed step plus a sliver (here 3e-9 s on
/// 1e-3 s steps) must not make the run take the sliver as a step of its own: generalized-alpha's
/// Newton matrix scales with 1 / h^2, and a step of 3e-9 s after steps of 1e-3 s leaves its
/// accelerations wrong. The sliver is now split with the step before it (two steps of about
/// h / 2), so the gridded run is as accurate as one call over the same time.
#[test]
fn fixed_step_communication_points_leave_no_sliver_steps() {
    let (a1, a2) = (1.2, 1.6);
    let (comm, calls) = (0.1 + 3e-9, 20);
    let t_end = calls as f64 * comm;
    let reference = reference_tip(a1, a2, t_end, 400_000);
    let s = Settings {
        fixed_step: 1e-3,
        ..Settings::default()
    };
    let one_call = (simulated_tip(a1, a2, t_end, s) - reference).norm();
    let gridded = (simulated_tip_on_grid(a1, a2, comm, calls, s) - reference).norm();
    println!("h = 1e-3 s to {t_end} s: one call {one_call:.3e} m, {calls} calls {gridded:.3e} m");
    assert!(one_call < 1e-3, "one call: {one_call:.3e} m");
    assert!(
        gridded < 2.0 * one_call,
        "{calls} communication steps of {comm} s: {gridded:.3e} m against {one_call:.3e} m in one call"
    );
}
