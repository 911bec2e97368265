//! PanelLock with flexible panels against independent references.
//!
//! Linearized reference (a **modal-level model**, built here by hand, not by the solver): one
//! flexible panel on a rigid yoke, locked straight. Coordinates `x = [theta_0, theta_1, a]`
//! (root and panel hinge angles, the panel's Craig-Bampton coordinates). Mass: the kinetic
//! energy of every body at the locked configuration, `M = sum J_b^T M_b J_b`, with planar
//! velocity maps `J_b` (hinge bodies and yoke rigid, the panel through its floating-frame mass
//! matrix `M(a = 0)` from the invariants and `y = [v_ref, omega, a_dot]`). Stiffness:
//! `diag(K_0, K_1, K_aa)`, with each hinge's `K_i = n k delta_i^(n-1) r_s^2 + k_spring`, the
//! Hertz wall stiffness at the static penetration `delta_i` solving
//! `preload - k_spring delta/r_s = k delta^n r_s` (zero-backlash latch, pin seat radius `r_s`).

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::scene::panel_lock::flex_panel::flex_panel;
use mbcosim::scene::panel_lock::study::{locked_modes, post_lock_frequency, run_case};
use mbcosim::scene::panel_lock::{ErrorControl, PanelLock, PanelLockParams};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::{FRAC_PI_2, PI};

/// One flexible panel, zero-backlash latch, strongly damped hinges (so that the post-lock
/// ringing decays into the linear range of the Hertz contact).
fn one_panel(n_modes: usize) -> PanelLockParams {
    PanelLockParams {
        n_panels: 1,
        hinge_damping: 3.0,
        restitution: 0.3,
        integrator: Some(IntegratorKind::Bdf),
        settings: Settings {
            rtol: 1e-7,
            atol: 1e-9,
            h_max: 0.02,
            ..PanelLockParams::default().settings
        },
        ..PanelLockParams::flexible(n_modes)
    }
}

/// Lowest eigenfrequency [Hz] of the linearized locked one-panel array (module doc).
fn linearized_frequency(p: &PanelLockParams) -> f64 {
    assert_eq!(p.n_panels, 1);
    let panel = flex_panel(p, true).unwrap();
    let data = &panel.data;
    let n = data.n_modes();
    let nx = 2 + n;
    let (ly, my, t) = (p.yoke_length, p.yoke_mass, p.panel_thickness);
    let (mh, ih) = (p.hinge_mass, p.hinge_mass * p.hinge_gyration_radius.powi(2));
    let mut m = DMatrix::<f64>::zeros(nx, nx);
    // root hinge body: rotation theta_0 about its own point
    m[(0, 0)] += ih;
    // yoke: rotation theta_0, centre at ly/2
    m[(0, 0)] += my * (ly * ly + t * t) / 12.0 + my * ly * ly / 4.0;
    // hinge 1 body at the yoke tip: speed ly theta_0_dot, rotation theta_0 + theta_1
    m[(0, 0)] += mh * ly * ly;
    for r in 0..2 {
        for c in 0..2 {
            m[(r, c)] += ih;
        }
    }
    // panel: y = [v_ref (world), omega (body), a_dot] = J x_dot
    let rot: Mat3 = Quat::from_axis_angle(&Vec3::x_axis(), FRAC_PI_2)
        .to_rotation_matrix()
        .into_inner();
    let mp = data
        .invariants()
        .mass_matrix(&rot, &DVector::zeros(n))
        .unwrap();
    let mut j = DMatrix::<f64>::zeros(6 + n, nx);
    j[(1, 0)] = ly; // v_ref.y = ly theta_0_dot (frame origin on the hinge axis line)
    j[(4, 0)] = 1.0; // omega about the plate's y axis = world z
    j[(4, 1)] = 1.0;
    for i in 0..n {
        j[(6 + i, 2 + i)] = 1.0;
    }
    m += j.transpose() * mp * &j;
    // stiffness
    let r_s = p.cam_radius - p.groove_depth + p.pin_radius;
    assert!(
        (p.groove_width - 2.0 * p.pin_radius).abs() < 1e-15,
        "zero backlash"
    );
    let hinge_k = |preload: f64, k_s: f64| {
        // preload - k_s d / r_s = k d^n r_s, bisection on d
        let (mut lo, mut hi) = (0.0, 1e-2);
        for _ in 0..200 {
            let d = 0.5 * (lo + hi);
            if preload - k_s * d / r_s > p.contact_stiffness * d.powf(p.contact_exponent) * r_s {
                lo = d;
            } else {
                hi = d;
            }
        }
        let d = 0.5 * (lo + hi);
        p.contact_exponent * p.contact_stiffness * d.powf(p.contact_exponent - 1.0) * r_s * r_s
            + k_s
    };
    let mut k = DMatrix::<f64>::zeros(nx, nx);
    k[(0, 0)] = hinge_k(p.root_spring_preload, p.root_spring_stiffness);
    k[(1, 1)] = hinge_k(p.panel_spring_preload, p.panel_spring_stiffness);
    k.view_mut((2, 2), (n, n)).copy_from(data.stiffness());
    // lowest eigenvalue of K x = w^2 M x
    let l = m.clone().cholesky().unwrap().l();
    let li = l.try_inverse().unwrap();
    let c = &li * k * li.transpose();
    let c = 0.5 * (&c + c.transpose());
    let w2 = c.symmetric_eigen().eigenvalues.min();
    w2.sqrt() / (2.0 * PI)
}

/// Post-lock frequency of the time response: the array deploys, locks and settles until `t0`,
/// a small root-motor torque pulse (0.07 N m for 0.1 s) excites it, and the tip velocity over
/// `[t0 + 0.1, t1]` is analysed.
fn response_frequency(p: PanelLockParams, t0: f64, t1: f64) -> (f64, f64) {
    let dt = 0.01;
    let mut s = PanelLock::new(p).unwrap();
    s.advance_to(t0).unwrap();
    let o = s.outputs();
    assert!(
        o.hinges.iter().all(|h| h.lock_time.is_finite()),
        "both hinges locked before {t0} s"
    );
    s.set_motor_torque(0.07).unwrap();
    s.advance_to(t0 + 0.1).unwrap();
    s.set_motor_torque(0.0).unwrap();
    let t0 = t0 + 0.1;
    let mut v = Vec::new();
    let steps = ((t1 - t0) / dt).round() as usize;
    for i in 0..=steps {
        s.advance_to(t0 + i as f64 * dt).unwrap();
        v.push(s.outputs().tip_normal_velocity);
    }
    let amp = v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    (post_lock_frequency(&v, dt).unwrap(), amp)
}

#[test]
fn validation_refuses_modes_without_flexible_panels_and_too_many_modes() {
    let e = PanelLockParams {
        n_modes: 4,
        ..PanelLockParams::default()
    }
    .validate()
    .unwrap_err();
    assert!(
        e.contains("n_modes") && e.contains("flexible_panels"),
        "{e}"
    );
    let e = PanelLockParams::flexible(0).validate().unwrap_err();
    assert!(
        e.contains("n_modes") && e.contains("flexible_panels"),
        "{e}"
    );
    let p = PanelLockParams::flexible(10_000);
    let e = p.validate().unwrap_err();
    assert!(e.contains("n_modes") && e.contains("exceeds"), "{e}");
    let ok = PanelLockParams::flexible(p.max_modes());
    assert!(ok.validate().is_ok());
    let e = PanelLockParams {
        panel_mesh: [8, 3],
        ..PanelLockParams::flexible(4)
    }
    .validate()
    .unwrap_err();
    assert!(e.contains("panel_mesh"), "{e}");
    // rigid: no modal coordinates at all; flexible: 3 interface + n per inner panel, n outer
    let rigid = PanelLock::new(PanelLockParams::default()).unwrap();
    assert_eq!(rigid.sim.system.n_v(), 6 * 8);
    let flex = PanelLock::new(PanelLockParams::flexible(5)).unwrap();
    assert_eq!(flex.sim.system.n_v(), 6 * 8 + 2 * (3 + 5) + 5);
}

#[test]
fn post_lock_frequency_matches_the_linearized_locked_system() {
    let p = one_panel(4);
    let f_lin = linearized_frequency(&p);
    let (f, amp) = response_frequency(p, 100.0, 140.0);
    let rel = (f - f_lin).abs() / f_lin;
    println!(
        "post-lock: response {f:.5} Hz (tip velocity amplitude {amp:.2e} m/s), linearized {f_lin:.5} Hz, rel {rel:.2e}"
    );
    assert!(rel < 0.02, "response {f} Hz vs linearized {f_lin} Hz");
}

/// The solver's linearization of the locked array ([`locked_modes`]: static equilibrium,
/// tangent stiffness, constrained eigenproblem) against the hand-built modal-level model of the
/// module doc, on the one-panel array.
#[test]
fn locked_modes_match_the_hand_built_linearization() {
    let p = one_panel(4);
    let f_hand = linearized_frequency(&p);
    let mut s = PanelLock::new(p).unwrap();
    s.advance_to(60.0).unwrap();
    let (eq, f) = locked_modes(&s).unwrap();
    let rel = (f[0] - f_hand).abs() / f_hand;
    println!(
        "locked modes: {:.6} Hz (then {:.4}, {:.4} Hz), hand model {f_hand:.6} Hz, rel {rel:.2e}; equilibrium in {} iterations, unbalanced {:.1e}",
        f[0], f[1], f[2], eq.iterations, eq.force_residual
    );
    assert!(
        rel < 2e-3,
        "linearized {} Hz vs hand model {f_hand} Hz",
        f[0]
    );
}

/// The three-panel paper array: the lowest linearized frequency of the locked structure equals
/// the frequency of its free vibration at small amplitude, simulated from the equilibrium with
/// 1 % of the run's post-lock velocities (an independent path: the nonlinear dynamics).
#[test]
fn locked_frequency_is_the_small_amplitude_vibration_of_the_paper_array() {
    let mut s = PanelLock::new(PanelLockParams::flexible(10)).unwrap();
    s.advance_to(40.0).unwrap();
    assert!(s.lock_times().iter().all(|t| t.is_finite()));
    let (eq, f) = locked_modes(&s).unwrap();
    let t0 = s.sim.state.t;
    let v: Vec<f64> = s.sim.state.v.iter().map(|x| 0.01 * x).collect();
    s.sim.state.q.copy_from_slice(&eq.q);
    s.sim.state.v.copy_from_slice(&v);
    s.sim.restart().unwrap();
    let dt = 0.01;
    let mut tip = Vec::new();
    for i in 1..=4000 {
        s.advance_to(t0 + i as f64 * dt).unwrap();
        tip.push(s.outputs().tip_normal_velocity);
    }
    let amp = tip.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let measured = post_lock_frequency(&tip, dt).unwrap();
    let rel = (measured - f[0]).abs() / f[0];
    println!(
        "paper array: linearized {:.5} Hz, small-amplitude response {measured:.5} Hz (tip amplitude {amp:.1e} m/s), rel {rel:.2e}",
        f[0]
    );
    assert!(
        rel < 0.01,
        "linearized {} Hz vs response {measured} Hz",
        f[0]
    );
}

#[test]
fn post_lock_frequency_converges_with_the_number_of_modes() {
    // softer panels (0.3 GPa) so that the panel modes matter; linearized frequency (shown equal
    // to the time response above) for n = 1, 2, 4, 8, 16
    let f: Vec<f64> = [1, 2, 4, 8, 16]
        .iter()
        .map(|&n| {
            linearized_frequency(&PanelLockParams {
                panel_youngs_modulus: 3e8,
                ..one_panel(n)
            })
        })
        .collect();
    println!("linearized post-lock frequency vs modes 1, 2, 4, 8, 16: {f:?}");
    for w in f.windows(2) {
        assert!(
            w[1] <= w[0] * (1.0 + 1e-9),
            "more modes, lower frequency: {f:?}"
        );
    }
    let d: Vec<f64> = f.windows(2).map(|w| (w[0] - w[1]).abs()).collect();
    assert!(d[3] < 1e-4 * f[4], "converged at 8 modes: {f:?}");
    // time response with 2 and 8 modes
    let (f2, _) = response_frequency(
        PanelLockParams {
            panel_youngs_modulus: 3e8,
            ..one_panel(2)
        },
        100.0,
        140.0,
    );
    let rel = (f2 - f[1]).abs() / f[1];
    println!(
        "time response, 2 modes: {f2:.5} Hz vs linearized {:.5} Hz",
        f[1]
    );
    assert!(rel < 0.02);
}

#[test]
fn stiffer_contact_gives_higher_peak_force_and_higher_post_lock_frequency() {
    let base = PanelLockParams {
        n_panels: 1,
        ..PanelLockParams::flexible(4)
    };
    let run = |k: f64| {
        run_case(
            PanelLockParams {
                contact_stiffness: k,
                ..base.clone()
            },
            40.0,
            0.01,
        )
        .unwrap()
    };
    let (soft, stiff) = (run(1e7), run(1e8));
    let (fs, fh) = (soft.frequency.unwrap(), stiff.frequency.unwrap());
    println!(
        "k = 1e7: peak {:.1} N, {fs:.4} Hz; k = 1e8: peak {:.1} N, {fh:.4} Hz",
        soft.peak_force, stiff.peak_force
    );
    assert!(stiff.peak_force > 1.3 * soft.peak_force);
    assert!(fh > 1.3 * fs);
}

#[test]
fn very_stiff_flexible_panels_reproduce_the_rigid_lock_times() {
    let rigid = PanelLockParams {
        n_panels: 2,
        ..PanelLockParams::default()
    };
    // the rigid reference at rtol 1e-8: at the default 1e-6 (BDF per step) its second lock time
    // is 17.4264 s against 17.4050 s converged (17.4055 s at 1e-8, 17.4050 s at 1e-10), an error
    // of 1.2e-3 of the 2e-3 this test allows
    let rigid_reference = PanelLockParams {
        integrator: Some(IntegratorKind::Bdf),
        error_control: ErrorControl::PerStep,
        settings: Settings {
            rtol: 1e-8,
            atol: 1e-10,
            ..rigid.settings
        },
        ..rigid.clone()
    };
    let flex = PanelLockParams {
        flexible_panels: true,
        n_modes: 12,
        // 100 times the default modulus (first panel mode near 75 Hz), heavily damped modes
        // (their transients die at once instead of forcing small steps)
        panel_youngs_modulus: 3e11,
        modal_damping_ratio: 0.5,
        // gen-alpha with the error per unit step (these modes start without trouble), rtol
        // 1e-4: lock times 4.28847, 17.45205, 7.59437 s; 3e-4 gives the same to 3e-4 s. Per
        // step at the default rtol 3e-4 the root lock is 11 ms early (docs/panel_lock_defaults.md)
        integrator: Some(IntegratorKind::GenAlpha),
        error_control: ErrorControl::PerUnitStep,
        settings: Settings {
            rtol: 1e-4,
            atol: 1e-6,
            ..rigid.settings
        },
        ..rigid.clone()
    };
    let lock_times = |p: PanelLockParams| {
        let mut s = PanelLock::new(p).unwrap();
        s.advance_to(30.0).unwrap();
        s.outputs()
            .hinges
            .iter()
            .map(|h| h.lock_time)
            .collect::<Vec<_>>()
    };
    let (tr, tf) = (lock_times(rigid_reference), lock_times(flex));
    println!("lock times rigid {tr:?}, flexible {tf:?}");
    // the second hinge (index 1) locks after 13 s of the root latch rattling in its 2 mm play,
    // which the panel modes feel: the flexible scene's own BDF runs give 17.3861 s (rtol 1e-6)
    // and 17.4299 s (1e-8), 2.5e-3 apart, so that lock is held to 5e-3; the others to 2e-3
    for (k, (a, b)) in tr.iter().zip(&tf).enumerate() {
        let allowed = if k == 1 { 5e-3 } else { 2e-3 };
        assert!(
            a.is_finite() && (a - b).abs() < allowed * a,
            "hinge {k}: {tr:?} vs {tf:?}"
        );
    }
}

/// BDF with the error held per unit step starts the flexible paper scene (ten modes per panel)
/// and follows a tight per-step BDF run (hinge angles at 0.2 s within 10 x rtol of their motion). Its first step used to be predicted from the starting
/// point alone, so the error estimate was the whole change of the speeds over the step, O(h),
/// like the per-unit-step share of the tolerance: steps fell to 6e-17 s at t = 0 at any rtol.
/// The predictor now uses the initial accelerations (O(h^2) estimate).
#[test]
fn bdf_per_unit_step_starts_the_flexible_scene() {
    let t_end = 0.2;
    let run = |rtol: f64, control: ErrorControl| {
        let mut p = PanelLockParams::flexible(10);
        p.integrator = Some(IntegratorKind::Bdf);
        p.error_control = control;
        p.settings.rtol = rtol;
        p.settings.atol = 1e-2 * rtol;
        let mut pl = PanelLock::new(p).unwrap();
        pl.advance_to(t_end)
            .unwrap_or_else(|e| panic!("rtol {rtol:e}, {control:?}: {e}"));
        let steps = pl.sim.stats().steps;
        let angles: Vec<f64> = (0..3).map(|k| pl.hinge_angle(k).0).collect();
        (angles, steps)
    };
    let (reference, _) = run(1e-9, ErrorControl::PerStep);
    // the hinges have moved by then (the test compares a motion, not the stowed angles)
    let stowed = PanelLock::new(PanelLockParams::flexible(10))
        .map(|mut pl| (0..3).map(|k| pl.hinge_angle(k).0).collect::<Vec<f64>>())
        .unwrap();
    let moved = reference
        .iter()
        .zip(&stowed)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("largest hinge motion to {t_end} s: {moved:.3e} rad");
    assert!(moved > 1e-3, "{moved:.3e} rad");
    for rtol in [1e-4, 1e-6] {
        let (angles, steps) = run(rtol, ErrorControl::PerUnitStep);
        let err = angles
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!("per unit step, rtol {rtol:e}: {steps} steps, hinge angle error {err:.2e} rad");
        assert!(err < 10.0 * rtol * moved, "rtol {rtol:e}: {err:.3e} rad");
    }
}

/// Cost and accuracy with hinge friction (issue #48 slow case).
#[path = "panel_lock_flex/hinge_friction.rs"]
mod hinge_friction;

#[path = "panel_lock_flex/outboard_hinge.rs"]
mod outboard_hinge;
