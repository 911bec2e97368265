//! The projection onto the joints (initial state; DOPRI5 after each step) on the solver's shared
//! Newton bookkeeping: it converges from a pose far off the joints to its tolerance, checked on
//! the joints' own geometry, and a non-finite coordinate ends it with a message instead of
//! counting as satisfied.

mod common;
use common::*;
use mbcosim::dae::System;
use mbcosim::integrator::init::{initial_state, project_positions};
use mbcosim::integrator::kkt::Kkt;
use mbcosim::math::{Quat, Vec3};
use mbcosim::model::kinematics::{put_quat, quat_at};
use std::sync::Arc;

/// Distance [m] of rod 1's hinge end from the pivot and of rod 2's hinge end from rod 1's far
/// end, read off the poses (not off the solver's constraint rows).
fn hinge_gaps(q: &[f64]) -> (f64, f64) {
    let end = |i: usize, sign: f64| {
        let r = Vec3::new(q[i], q[i + 1], q[i + 2]);
        let rot = quat_at(q, i + 3);
        r + rot * Vec3::new(sign * 0.5, 0.0, 0.0)
    };
    let (a0, a1, b0) = (end(0, -1.0), end(0, 1.0), end(7, -1.0));
    (a0.norm(), (b0 - a1).norm())
}

#[test]
fn a_pose_far_off_the_joints_is_projected_onto_them() {
    let model = Arc::new(double_pendulum(0.3, 1.1));
    let mut sys = System::new(model).unwrap();
    let mut st = initial_state(&sys, 0.0);
    // rod 2 pulled 0.4 m off rod 1's end and rotated 0.5 rad about x (out of the plane)
    st.q[7] += 0.3;
    st.q[8] -= 0.25;
    st.q[9] += 0.1;
    let tilted = quat_at(&st.q, 10) * Quat::from_axis_angle(&Vec3::x_axis(), 0.5);
    put_quat(&mut st.q, 10, &tilted);
    let before = hinge_gaps(&st.q);
    assert!(before.1 > 0.35, "the pose starts off the joint: {before:?}");
    let mut lin = Kkt::new();
    project_positions(&mut sys, &mut lin, &mut st, 1e-12).unwrap();
    let after = hinge_gaps(&st.q);
    println!("hinge gaps before {before:?}, after {after:?}");
    assert!(after.0 < 1e-11 && after.1 < 1e-11, "{after:?}");
    // rod 1 stays where it was (it satisfied its joint); the correction went to rod 2
    let model = double_pendulum(0.3, 1.1);
    assert!((st.q[0] - model.q0[0]).abs() < 0.2, "{}", st.q[0]);
}

#[test]
fn a_non_finite_coordinate_ends_the_projection_with_a_message() {
    let model = Arc::new(double_pendulum(0.3, 1.1));
    let mut sys = System::new(model).unwrap();
    let mut st = initial_state(&sys, 0.0);
    // rod 2's x coordinate: its hinge rows are NaN, the first hinge's rows are satisfied (the
    // largest residual used to skip the NaN rows and report the pose as projected)
    st.q[7] = f64::NAN;
    let mut lin = Kkt::new();
    let err = project_positions(&mut sys, &mut lin, &mut st, 1e-10).unwrap_err();
    let message = err.to_string();
    assert!(
        message.contains("projection onto the joints failed at t = 0.000000000e0 s")
            && message.contains("non-finite positions or joint data"),
        "{message}"
    );
}
