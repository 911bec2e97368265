//! A flexible panel hanging on a revolute joint (hinge axis along its edge, at the Craig-Bampton
//! frame node in the middle of that edge) swings under gravity as a pendulum.
//!
//! Reasoning for the reference. With hinge angle `theta` and modal coordinates `a`, the small
//! motions about the hanging equilibrium obey `M_l x_ddot + K_l x = 0`, `x = [theta; a]`, with
//! - `M_l = N^T M(0) N`, `N` mapping `[theta_dot; a_dot]` to the body speeds
//!   `[A (theta_dot e_y x (-rho_f)); theta_dot e_y; a_dot]` (`rho_f` the hinge point, `e_y` the
//!   hinge axis, body frame; the hinge passes through the frame origin here so the first row is 0);
//! - `K_l = [[g S_x, -g c^T]; [-g c, K_aa]]` from the potential
//!   `V = a^T K a / 2 - g (S_x cos theta + (c . a) sin theta)` (`S_x = m a_x / 2` the first moment
//!   about the hinge along the hanging direction, `c` the out-of-plane row of `C_t`).
//!
//! Freezing `a = 0` gives the rigid physical pendulum, `omega_r^2 = g S_x / J_yy`
//! (`J_yy = m L^2 / 3` about the edge). Freezing coordinates can only raise the lowest eigenvalue
//! (Rayleigh), so the flexible pendulum is slower; the elastic coordinates respond quasi-statically
//! to the self-equilibrated gravity + d'Alembert load `g theta (3 x / (2 L) - 1)` per unit mass
//! (zero net moment about the hinge), which lowers `omega^2` by a relative amount of order
//! `(omega_r / omega_1)^2` (`omega_1` the first frequency of the panel clamped at the hinge
//! node): `0 < T_flex / T_rigid - 1 < (omega_r / omega_1)^2`. The simulated small-amplitude
//! period (theta_0 = 0.01 rad, starting in the lowest linearized mode) must match
//! `T_flex (1 + theta_0^2 / 16)` (the pendulum's first amplitude correction) to 3e-5 relative,
//! which tells it apart from the rigid period (the correction is about 9e-5 here: the
//! self-equilibrated load barely projects on the low modes of this panel).

use crate::common;
use common::flex::{hanging_linearization, lowest_mode, panel, upward_crossings};
use mbcosim::flex::ModalBodyData;
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::{Quat, Vec3};
use mbcosim::model::kinematics::quat_at;
use mbcosim::model::{BodyId, BodyInit, Frame, JointKind, ModelBuilder};
use mbcosim::sim::Simulation;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::Arc;

const G: f64 = 9.81;

#[test]
fn hanging_flexible_panel_swings_with_the_flexible_pendulum_period() {
    let plate = panel(6, 2);
    let hinge_node = plate.node_index(0, 1).unwrap();
    let data = Arc::new(
        ModalBodyData::from_craig_bampton(&plate, hinge_node, &[hinge_node], 4, 0.0).unwrap(),
    );
    let n = data.n_modes();
    let inv = data.invariants();
    let rho_f = data.positions()[hinge_node];
    // hanging: body x down (world -Z), hinge axis body y = world Y, normal body z = world X;
    // A(theta) = R_Y(pi/2 + theta)
    let (m_l, k_l) = hanging_linearization(&data, &rho_f, G);
    let s_x = inv.first_moment.x - inv.mass * rho_f.x;
    let (w2_flex, mode) = lowest_mode(&k_l, &m_l);
    let t_flex = 2.0 * PI / w2_flex.sqrt();
    let w2_rigid = G * s_x / m_l[(0, 0)];
    let t_rigid = 2.0 * PI / w2_rigid.sqrt();
    // rigid reference from the panel data alone: J_yy = m L^2 / 3, S_x = m L / 2
    let l = 2.0;
    let t_book = 2.0 * PI * (2.0 * l / (3.0 * G)).sqrt();
    assert!((t_rigid - t_book).abs() < 1e-9 * t_book);
    let w1 = 2.0 * PI * data.frequencies_hz().unwrap()[0];
    let correction = t_flex / t_rigid - 1.0;
    println!(
        "T_rigid {t_rigid:.6} s, T_flex {t_flex:.6} s, correction {correction:.3e}, bound (omega_r/omega_1)^2 = {:.3e}",
        w2_rigid / (w1 * w1)
    );
    assert!(correction > 0.0 && correction < w2_rigid / (w1 * w1));

    let theta0 = 0.01;
    let x0 = &mode * (theta0 / mode[0]);
    let a0: Vec<f64> = (0..n).map(|j| x0[1 + j]).collect();
    let rot0 = Quat::from_axis_angle(&Vec3::y_axis(), FRAC_PI_2 + theta0);
    let r0 = -(rot0 * rho_f); // hinge at the world origin
    for kind in [
        IntegratorKind::Bdf,
        IntegratorKind::Dopri5,
        IntegratorKind::GenAlpha,
    ] {
        let mut b = ModelBuilder::new();
        b.set_gravity(Some(Vec3::new(0.0, 0.0, -G))).unwrap();
        let p = b
            .add_modal_body(
                "panel",
                data.clone(),
                BodyInit::at(r0).oriented(rot0),
                &a0,
                &vec![0.0; n],
            )
            .unwrap();
        b.add_joint(
            "hinge",
            JointKind::Revolute,
            Frame::with_z(BodyId::GROUND, Vec3::zeros(), Vec3::y()),
            Frame::with_z(p, Vec3::zeros(), Vec3::y()).on_node(hinge_node),
        )
        .unwrap();
        // generalized-alpha holds its error per unit step: 1e-7 (atol = rtol) suffices for the
        // period and stays above its index-3 round-off floor
        let settings = if kind == IntegratorKind::GenAlpha {
            Settings {
                rtol: 1e-7,
                atol: 1e-7,
                h_max: 0.01,
                ..Settings::default()
            }
        } else {
            Settings {
                rtol: 1e-9,
                atol: 1e-11,
                h_max: 0.01,
                ..Settings::default()
            }
        };
        let mut sim = Simulation::new(b.build().unwrap(), kind, settings, 0.0).unwrap();
        let e0 = sim.energy().balance();
        // theta from the body x axis: A e_x = (cos phi, 0, -sin phi), phi = pi/2 + theta
        let theta = |s: &mbcosim::state::State| {
            let x = quat_at(&s.q, 3) * Vec3::x();
            (-x.z).atan2(x.x) - FRAC_PI_2
        };
        let t = upward_crossings(&mut sim, 3.3 * t_flex, t_flex / 400.0, &theta);
        assert!(t.len() >= 3, "{}: only {} crossings", kind.name(), t.len());
        let period = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
        let t_ref = t_flex * (1.0 + theta0 * theta0 / 16.0);
        let rel = (period - t_ref).abs() / t_ref;
        let drift = (sim.energy().balance() - e0).abs() / sim.energy().kinetic.abs().max(1e-3);
        println!(
            "{}: period {period:.7} s vs T_flex (1 + theta0^2/16) {t_ref:.7} s (rel {rel:.2e}); vs T_rigid rel {:.2e}; energy drift {drift:.1e} (E0 {e0:.6e} J)",
            kind.name(),
            (period - t_rigid) / t_rigid
        );
        assert!(rel < 3e-5, "{}: period off by {rel:.3e}", kind.name());
    }
}
