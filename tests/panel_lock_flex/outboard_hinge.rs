//! The hinges on a flexible panel's outboard edge: spring, latch, stow stop, friction, cable
//! loop and the `hingeN_angle` output must all act across the same two frames as the hinge's
//! shaft joint, whose inboard frame rides on the panel's outboard node. They used to act on the
//! panel's floating frame (clamped at its inboard edge), so the latch locked, and the output
//! reported, the angle across the whole panel's rigid-body rotation instead of the hinge's.
//!
//! Independent path: the shaft joint's own frames (`model.joints`, "hingeK shaft"), with the
//! node's small rotation `theta = Psi_k a` applied to the inboard frame's axes as the joint rows
//! apply it (`e + theta x e`), the bodies' rotations read from the state vector, and the angle
//! `atan2(y_i . x_j, x_i . x_j)` formed here.

use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::Frame;
use mbcosim::scene::panel_lock::{PanelLock, PanelLockParams};
use nalgebra::Quaternion;

/// Rotation matrix (body to world) of the body of `f`, from the state `q` (identity for the
/// ground, whose frames are given in the world frame).
fn body_rotation(s: &PanelLock, f: &Frame, q: &[f64]) -> Mat3 {
    let Some(i) = f.body.index() else {
        return Mat3::identity();
    };
    let b = &s.sim.system.model.bodies[i];
    let o = b.q_offset + 3;
    Quat::new_normalize(Quaternion::new(q[o], q[o + 1], q[o + 2], q[o + 3]))
        .to_rotation_matrix()
        .into_inner()
}

/// World axes of joint frame `f` at the state `q` (the node's rotation applied linearized, as
/// the joint rows do) and the node's rotation angle [rad] (0 off nodes).
fn joint_frame_axes(s: &PanelLock, f: &Frame, q: &[f64]) -> (Mat3, f64) {
    let rot = body_rotation(s, f, q);
    let Some(node) = f.node else {
        return (rot * f.axes, 0.0);
    };
    let b = &s.sim.system.model.bodies[f.body.index().unwrap()];
    let data = b.kind.modal().expect("a node frame is on a modal body");
    let n = data.n_modes();
    let a = &q[b.q_offset + 7..b.q_offset + 7 + n];
    let psi = &data.rotational_shapes()[node];
    let theta: Vec3 = (0..n).map(|c| psi.column(c) * a[c]).sum();
    let mut axes = f.axes;
    for c in 0..3 {
        let e: Vec3 = f.axes.column(c).into();
        axes.set_column(c, &(e + theta.cross(&e)));
    }
    (rot * axes, theta.norm())
}

/// Deployment angle [rad] of hinge `k` across its shaft joint's frames, formed by hand; the
/// same with the inboard frame's node left out (what the effects used before); the node's
/// rotation [rad].
fn shaft_angle(s: &PanelLock, k: usize) -> (f64, f64, f64) {
    let q = &s.sim.state.q;
    let name = format!("hinge{k} shaft");
    let joint = s
        .sim
        .system
        .model
        .joints
        .iter()
        .find(|j| j.name == name)
        .expect("shaft joint");
    let (ai, node_rotation) = joint_frame_axes(s, &joint.frame_i, q);
    let (aj, _) = joint_frame_axes(s, &joint.frame_j, q);
    let rigid_i = body_rotation(s, &joint.frame_i, q) * joint.frame_i.axes;
    let angle = |ai: &Mat3| {
        let (xi, yi, xj) = (ai.column(0), ai.column(1), aj.column(0));
        s.layout.lock_angles[k] + yi.dot(&xj).atan2(xi.dot(&xj))
    };
    (angle(&ai), angle(&rigid_i), node_rotation)
}

#[test]
fn hinges_on_a_flexible_panels_outboard_node_act_across_the_shaft_joints_frames() {
    let p = PanelLockParams {
        flexible_panels: true,
        n_modes: 10,
        ..PanelLockParams::default()
    };
    let n = p.n_panels + 1;
    let mut s = PanelLock::new(p).expect("scene");
    let engagement: Vec<f64> = s
        .layout
        .latches
        .as_ref()
        .expect("latches")
        .elements
        .iter()
        .map(|l| l.geometry.engagement_angle())
        .collect();
    let dt = 0.005;
    let t_end = 30.0;
    // per hinge: worst |output - hand angle|, worst node effect |hand - rigid-frame angle|,
    // worst node rotation; samples (t, hand angle) to find the engagement crossing
    let mut worst = vec![0.0f64; n];
    let mut node_effect = vec![0.0f64; n];
    let mut node_rot = vec![0.0f64; n];
    let mut prev: Vec<Option<(f64, f64)>> = vec![None; n];
    let mut crossing = vec![f64::NAN; n];
    let mut t = 0.0;
    while t < t_end - 1e-9 {
        t += dt;
        s.advance_to(t).expect("run");
        for k in 0..n {
            let (out, _) = s.hinge_angle(k);
            let (hand, rigid, rot) = shaft_angle(&s, k);
            worst[k] = worst[k].max((out - hand).abs());
            node_effect[k] = node_effect[k].max((hand - rigid).abs());
            node_rot[k] = node_rot[k].max(rot);
            if let Some((t0, a0)) = prev[k]
                && crossing[k].is_nan()
                && a0 < engagement[k]
                && hand >= engagement[k]
            {
                crossing[k] = t0 + (engagement[k] - a0) / (hand - a0) * dt;
            }
            prev[k] = Some((t, hand));
        }
    }
    let locks = s.lock_times();
    for k in 0..n {
        println!(
            "hinge {k}: |output - shaft angle| {:.2e} rad, node's share {:.2e} rad, node rotation \
             {:.2e} rad; lock {:.4} s, shaft angle reaches engagement at {:.4} s",
            worst[k], node_effect[k], node_rot[k], locks[k], crossing[k]
        );
    }
    for k in 0..n {
        // the node body rotates by exp(theta), the joint's frame by (1 + theta x): they part at
        // second order in the node's rotation's components across the hinge axis (measured:
        // 1.7e-6 rad at a 1.7e-2 rad node rotation, 6e-3 of its square)
        let tol = 1e-9 + 0.1 * node_rot[k].powi(2);
        assert!(
            worst[k] <= tol,
            "hinge {k}: output {:.3e} rad off the shaft angle",
            worst[k]
        );
        // the lock-up is located where the shaft's own angle reaches the engagement angle
        // (within the sampling's linear interpolation)
        assert!(
            locks[k].is_finite() && crossing[k].is_finite(),
            "hinge {k} did not lock by {t_end} s"
        );
        assert!(
            (locks[k] - crossing[k]).abs() < 2e-3,
            "hinge {k}: lock at {} s, shaft angle at engagement at {} s",
            locks[k],
            crossing[k]
        );
    }
    // the check tells the node's frame from the panel's floating frame on the outboard hinges
    for k in 2..n {
        let tol = 1e-9 + 0.1 * node_rot[k].powi(2);
        assert!(
            node_effect[k] > 10.0 * tol,
            "hinge {k}: {:.2e}",
            node_effect[k]
        );
    }
}
