//! PanelLock outputs against other paths to the same quantity: rates and the tip velocity
//! against finite differences of the angles and of the tip position, lock time and latched flag
//! against the angle crossing the latch's engagement angle, kinetic energy against the bodies'
//! masses and velocities, potential energy against the springs by hand, input work against the
//! motor torque times the root hinge's travel, the settled latch force against the spring torque
//! over the moment arm, the satellite's velocity and rate against the derivatives of its
//! position and attitude, and the solver counters against the integrator's statistics.

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::Vec3;
use mbcosim::model::BodyKind;
use mbcosim::scene::CoSimModel;
use mbcosim::scene::panel_lock::{ErrorControl, PanelLock, PanelLockModel, PanelLockParams};

use super::largest;

/// The default array on BDF at `rtol` per step (`atol = rtol / 100`, h_max 0.02 s).
fn tight(rtol: f64) -> PanelLockParams {
    crate::common::panel_lock::per_step(IntegratorKind::Bdf, rtol)
}

/// World position of the outer panel's tip midpoint (where `tip_normal_velocity` is taken) and
/// the rigid panel's normal there, from the bodies' positions.
fn tip(s: &mut PanelLock) -> (Vec3, Vec3) {
    s.outputs(); // brings the kinematics to the current state
    let outer = *s.layout.plates.last().unwrap();
    let len = *s.layout.plate_lengths.last().unwrap();
    let k = s.sim.system.kin(outer);
    (
        k.r + k.rot * Vec3::new(0.5 * len, 0.0, 0.0),
        k.rot * Vec3::y(),
    )
}

#[test]
fn rates_and_tip_velocity_are_the_derivatives_of_angles_and_tip_position() {
    // the deployment between 1 s and 3 s (no contact yet), sampled every millisecond: the
    // central difference of each hinge angle against the reported rate at the middle sample
    // (truncation theta''' dt^2 / 6 and the solution's error over dt: below 1e-6 rad/s here)
    let dt = 1e-3;
    let mut s = PanelLock::new(tight(1e-10)).unwrap();
    s.advance_to(1.0).unwrap();
    let mut rows = Vec::new();
    for i in 0..=2000 {
        s.advance_to(1.0 + i as f64 * dt).unwrap();
        let o = s.outputs();
        let (p, n) = tip(&mut s);
        rows.push((o, p, n));
    }
    let n_h = rows[0].0.hinges.len();
    let (mut worst_rate, mut worst_tip) = (0.0f64, 0.0f64);
    for w in rows.windows(3) {
        for k in 0..n_h {
            let fd = (w[2].0.hinges[k].angle - w[0].0.hinges[k].angle) / (2.0 * dt);
            worst_rate = worst_rate.max((fd - w[1].0.hinges[k].rate).abs());
        }
        let fd = (w[2].1 - w[0].1).dot(&w[1].2) / (2.0 * dt);
        worst_tip = worst_tip.max((fd - w[1].0.tip_normal_velocity).abs());
    }
    let rate_scale = largest(rows.iter().flat_map(|r| r.0.hinges.iter().map(|h| h.rate)));
    let tip_scale = largest(rows.iter().map(|r| r.0.tip_normal_velocity));
    println!(
        "rates: worst {worst_rate:.2e} rad/s of {rate_scale:.3} rad/s; tip normal velocity: worst {worst_tip:.2e} m/s of {tip_scale:.3} m/s"
    );
    assert!(rate_scale > 0.1 && tip_scale > 0.1, "the array moves");
    assert!(worst_rate < 1e-5 * rate_scale, "{worst_rate}");
    assert!(worst_tip < 1e-5 * tip_scale, "{worst_tip}");
}

#[test]
fn lock_time_and_latched_flag_follow_the_engagement_angle_crossing() {
    // through the four lock-ups (the root near 4.9 s, the innermost panel hinge last): the lock
    // time is where the reported hinge angle, interpolated linearly between samples 2 ms apart
    // (20 ms while no unlatched hinge is within 0.1 rad of it), crosses the latch geometry's
    // engagement angle; the flag is off at every sample before and on at the first one after
    let mut s = PanelLock::new(tight(1e-9)).unwrap();
    let theta_e: Vec<f64> = s
        .layout
        .latches
        .as_ref()
        .unwrap()
        .elements
        .iter()
        .map(|l| l.geometry.engagement_angle())
        .collect();
    let mut prev = s.outputs();
    let mut crossed: Vec<Option<f64>> = vec![None; theta_e.len()];
    while crossed.iter().any(Option::is_none) && prev.t < 60.0 {
        let near = prev
            .hinges
            .iter()
            .zip(&theta_e)
            .any(|(h, e)| !h.engaged && e - h.angle < 0.1);
        let dt = if near { 2e-3 } else { 2e-2 };
        s.advance_to(prev.t + dt).unwrap();
        let o = s.outputs();
        for (k, (h, h0)) in o.hinges.iter().zip(&prev.hinges).enumerate() {
            if crossed[k].is_none() {
                assert!(!h0.engaged && h0.lock_time.is_nan(), "hinge {k} early");
                if h.angle >= theta_e[k] {
                    assert!(near, "hinge {k} crossed between coarse samples");
                    let f = (theta_e[k] - h0.angle) / (h.angle - h0.angle);
                    crossed[k] = Some(prev.t + f * (o.t - prev.t));
                    assert!(
                        h.engaged,
                        "hinge {k} past the engagement angle, not latched"
                    );
                }
            }
        }
        prev = o;
    }
    for (k, h) in prev.hinges.iter().enumerate() {
        let t = crossed[k].unwrap_or_else(|| panic!("hinge {k} never crossed"));
        println!(
            "hinge {k}: lock time {:.6} s, angle crossing {t:.6} s (difference {:.1e} s)",
            h.lock_time,
            h.lock_time - t
        );
        assert!(h.engaged);
        assert!(
            (h.lock_time - t).abs() < 5e-6,
            "hinge {k}: {} vs {t}",
            h.lock_time
        );
    }
}

/// Kinetic energy [J] from each rigid body's mass, inertia and velocities in the state.
fn kinetic_by_hand(s: &PanelLock) -> f64 {
    let v = &s.sim.state.v;
    let mut e = 0.0;
    for b in &s.sim.system.model.bodies {
        if let BodyKind::Rigid { mass, inertia } = &b.kind {
            let o = b.v_offset;
            let vel = Vec3::new(v[o], v[o + 1], v[o + 2]);
            let w = Vec3::new(v[o + 3], v[o + 4], v[o + 5]);
            e += 0.5 * mass * vel.norm_squared() + 0.5 * w.dot(&(inertia * w));
        }
    }
    e
}

/// Spring and stow-stop energy [J] of every hinge at the reported angles: the spring's
/// `k (theta_free - theta)^2 / 2`, `theta_free = lock + preload / k`, and the stop's
/// `k_stop (theta_stowed - theta)^2 / 2` while the hinge is pressed into it.
fn springs_by_hand(p: &PanelLockParams, angles: &[f64]) -> f64 {
    angles
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let (stiff, preload, lock, stow) = if k == 0 {
                let (s, l) = (p.root_spring_stiffness, p.root_lock_angle);
                (s, p.root_spring_preload, l, p.root_stowed_angle)
            } else {
                let (s, l) = (p.panel_spring_stiffness, p.panel_lock_angle);
                (s, p.panel_spring_preload, l, p.panel_stowed_angle)
            };
            let into_stop = (stow - a).max(0.0);
            0.5 * stiff * (lock + preload / stiff - a).powi(2)
                + 0.5 * p.stop_stiffness * into_stop * into_stop
        })
        .sum()
}

#[test]
fn kinetic_and_potential_energy_against_the_bodies_and_springs_by_hand() {
    // the default array deploying (no latch contact before 3.5 s, orbit; the middle panel's
    // hinge rocks on its stow stop until about 3 s): the kinetic energy is
    // sum(m v^2 + w.I w) / 2 over the bodies; the change of the potential energy is that of the
    // springs and stops at the reported angles
    let p = tight(1e-9);
    let mut s = PanelLock::new(p.clone()).unwrap();
    s.advance_to(0.5).unwrap();
    let o0 = s.outputs();
    let angles = |o: &mbcosim::scene::panel_lock::PanelLockOutputs| {
        o.hinges.iter().map(|h| h.angle).collect::<Vec<_>>()
    };
    let spring0 = springs_by_hand(&p, &angles(&o0));
    let (mut worst_k, mut worst_p, mut scale) = (0.0f64, 0.0f64, 0.0f64);
    for i in 1..=30 {
        s.advance_to(0.5 + 0.1 * i as f64).unwrap();
        let o = s.outputs();
        let k = kinetic_by_hand(&s);
        let dp = springs_by_hand(&p, &angles(&o)) - spring0;
        worst_k = worst_k.max((o.kinetic - k).abs());
        worst_p = worst_p.max((o.potential - o0.potential - dp).abs());
        scale = scale.max(k).max(dp.abs());
    }
    println!(
        "kinetic: worst {worst_k:.2e} J, potential change: worst {worst_p:.2e} J, of {scale:.4} J"
    );
    assert!(scale > 0.05, "the springs release energy: {scale}");
    assert!(worst_k < 1e-9 * scale, "kinetic {worst_k}");
    assert!(worst_p < 1e-9 * scale, "potential {worst_p}");
}

#[test]
fn input_work_is_the_motor_torque_times_the_root_travel() {
    // 0.3 N m to 1.5 s, then -0.2 N m to 3 s (before any latch engages): the work is
    // sum(tau * delta theta_root)
    let mut s = PanelLock::new(tight(1e-9)).unwrap();
    let a0 = s.outputs().hinges[0].angle;
    s.set_motor_torque(0.3).unwrap();
    s.advance_to(1.5).unwrap();
    let a1 = s.outputs().hinges[0].angle;
    let w1 = s.outputs().input_work;
    s.set_motor_torque(-0.2).unwrap();
    s.advance_to(3.0).unwrap();
    let o = s.outputs();
    let a2 = o.hinges[0].angle;
    let (by_hand1, by_hand) = (0.3 * (a1 - a0), 0.3 * (a1 - a0) - 0.2 * (a2 - a1));
    println!(
        "input work {w1:.9} J at 1.5 s (by hand {by_hand1:.9} J), {:.9} J at 3 s (by hand {by_hand:.9} J)",
        o.input_work
    );
    assert!(a1 - a0 > 0.1 && a2 - a1 > 0.1, "the root hinge deploys");
    assert!((w1 - by_hand1).abs() < 1e-9 * by_hand1.abs());
    let scale = 0.3 * (a1 - a0) + 0.2 * (a2 - a1);
    assert!((o.input_work - by_hand).abs() < 1e-9 * scale);
}

#[test]
fn settled_latch_force_carries_the_spring_torque_over_its_arm() {
    // one panel, strongly damped so the locked array comes to rest: each hinge's spring torque
    // is then carried by the pin on the groove's front wall, F = tau_spring / arm (the arm from
    // the latch geometry at the reported angle; the force law is not used)
    let p = PanelLockParams {
        n_panels: 1,
        hinge_damping: 0.3,
        restitution: 0.3,
        ..tight(1e-9)
    };
    let mut s = PanelLock::new(p.clone()).unwrap();
    s.advance_to(300.0).unwrap();
    let o = s.outputs();
    for (k, h) in o.hinges.iter().enumerate() {
        assert!(h.engaged && h.rate.abs() < 1e-7, "hinge {k}: {h:?}");
        let tau = springs_torque(&p, k, h.angle);
        let geo = &s.layout.latches.as_ref().unwrap().elements[k].geometry;
        let wall = geo.query(h.angle, true).unwrap().unwrap().front;
        let by_hand = tau / wall.moment_arm.abs();
        println!(
            "hinge {k}: contact force {:.6} N, spring torque / arm {by_hand:.6} N",
            h.contact_force
        );
        assert!(
            (h.contact_force - by_hand).abs() < 1e-6 * by_hand,
            "hinge {k}: {} vs {by_hand}",
            h.contact_force
        );
    }
}

/// Spring torque [N m] of hinge `k` at `angle`, deploying positive.
fn springs_torque(p: &PanelLockParams, k: usize, angle: f64) -> f64 {
    let (stiff, preload, lock) = if k == 0 {
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
    stiff * (lock + preload / stiff - angle)
}

/// Quaternion product `a b`, (w, x, y, z).
pub fn qmul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// Body-frame angular velocity from the attitude `q` and its derivative `dq`: the vector part
/// of `2 conj(q) dq`.
fn body_rate(q: [f64; 4], dq: [f64; 4]) -> Vec3 {
    let c = [q[0], -q[1], -q[2], -q[3]];
    let r = qmul(c, dq);
    Vec3::new(2.0 * r[1], 2.0 * r[2], 2.0 * r[3])
}

#[test]
fn satellite_velocity_and_rate_are_the_derivatives_of_position_and_attitude() {
    // a free satellite reacting to the deployment, 1 ms samples from 1 s to 3 s; the attitude
    // stays a unit quaternion
    let dt = 1e-3;
    let mut s = PanelLock::new(PanelLockParams {
        free_satellite: true,
        ..tight(1e-10)
    })
    .unwrap();
    let mut rows = Vec::new();
    for i in 0..=2000 {
        s.advance_to(1.0 + i as f64 * dt).unwrap();
        rows.push(s.satellite_output());
    }
    let (mut worst_v, mut worst_w, mut worst_norm) = (0.0f64, 0.0f64, 0.0f64);
    for w in rows.windows(3) {
        let fd = (w[2].position - w[0].position) / (2.0 * dt);
        worst_v = worst_v.max((fd - w[1].velocity).norm());
        let dq: Vec<f64> = (0..4)
            .map(|j| (w[2].attitude[j] - w[0].attitude[j]) / (2.0 * dt))
            .collect();
        let rate = body_rate(w[1].attitude, [dq[0], dq[1], dq[2], dq[3]]);
        worst_w = worst_w.max((rate - w[1].rate).norm());
        let n: f64 = w[1].attitude.iter().map(|x| x * x).sum();
        worst_norm = worst_norm.max((n.sqrt() - 1.0).abs());
    }
    let v_scale = largest(rows.iter().map(|r| r.velocity.norm()));
    let w_scale = largest(rows.iter().map(|r| r.rate.norm()));
    println!(
        "satellite velocity: worst {worst_v:.2e} of {v_scale:.3e} m/s; rate: worst {worst_w:.2e} of {w_scale:.3e} rad/s; |q| - 1 up to {worst_norm:.1e}"
    );
    assert!(v_scale > 1e-4 && w_scale > 1e-4, "the satellite moves");
    assert!(worst_v < 1e-5 * v_scale, "{worst_v}");
    assert!(worst_w < 1e-5 * w_scale, "{worst_w}");
    assert!(worst_norm < 1e-12, "{worst_norm}");
}

#[test]
fn solver_counters_are_the_integrator_statistics() {
    // the FMU's model stepped by 0.5 s against the native scene advanced to the same points:
    // the counters equal the integrator's statistics there, and never decrease (on
    // generalized-alpha, which counts Newton iterations and factorizations; `auto` resolves to
    // the explicit dopri5_tree on this scene, whose two are 0)
    let mut m = PanelLockModel::new();
    mbcosim::scene::native::set_by_name(&mut m, "integrator", 1.0).unwrap();
    m.initialize(0.0).unwrap();
    let mut s = PanelLock::new(PanelLockParams {
        integrator: Some(IntegratorKind::GenAlpha),
        ..PanelLockParams::default()
    })
    .unwrap();
    let names = [
        "solver_steps",
        "solver_rejected_steps",
        "solver_newton_iterations",
        "solver_factorizations",
    ];
    let read = |m: &PanelLockModel| -> Vec<i64> {
        names
            .iter()
            .map(|n| m.get_integer(m.info().port_by_name(n).unwrap().vr).unwrap() as i64)
            .collect()
    };
    let mut last = read(&m);
    for i in 0..16 {
        let t = 0.5 * i as f64;
        m.do_step(t, 0.5).unwrap();
        s.advance_to(t + 0.5).unwrap();
        let st = s.sim.stats();
        let want = [
            st.steps,
            st.rejected,
            st.newton_iterations,
            st.factorizations,
        ];
        let got = read(&m);
        assert_eq!(got, want.map(|x| x as i64), "t {}", t + 0.5);
        assert!(
            got.iter().zip(&last).all(|(a, b)| a >= b),
            "{got:?} after {last:?}"
        );
        last = got;
    }
    println!("counters at 8 s: {last:?}");
    assert!(
        last[0] > 100 && last[2] >= last[0] && last[3] > 0,
        "{last:?}"
    );
}

/// `solver_integrator` is the item number of the integrator the run is built with, read back from
/// the built simulation: `auto` gives dopri5_tree (4) for rigid panels on a fixed satellite and
/// gen_alpha (1) with flexible panels or a free satellite; an explicit choice passes through.
#[test]
fn solver_integrator_is_the_integrator_the_run_uses() {
    use mbcosim::scene::native::set_by_name;
    type Case = (&'static [(&'static str, f64)], i32, IntegratorKind);
    let cases: [Case; 5] = [
        (&[], 4, IntegratorKind::Dopri5Tree),
        (&[("flexible_panels", 1.0)], 1, IntegratorKind::GenAlpha),
        (&[("free_satellite", 1.0)], 1, IntegratorKind::GenAlpha),
        (&[("integrator", 2.0)], 2, IntegratorKind::Bdf),
        (
            &[("integrator", 3.0), ("rtol", 1e-6)],
            3,
            IntegratorKind::Dopri5,
        ),
    ];
    for (sets, code, kind) in cases {
        let mut m = PanelLockModel::new();
        for (name, v) in sets {
            set_by_name(&mut m, name, *v).unwrap();
        }
        m.initialize(0.0).unwrap();
        let vr = m.info().port_by_name("solver_integrator").unwrap().vr;
        assert_eq!(m.get_integer(vr).unwrap(), code, "{sets:?}");
        // the same through the scene the parameters build
        let p = PanelLockParams {
            flexible_panels: sets.iter().any(|(n, _)| *n == "flexible_panels"),
            free_satellite: sets.iter().any(|(n, _)| *n == "free_satellite"),
            n_modes: if sets.iter().any(|(n, _)| *n == "flexible_panels") {
                10
            } else {
                0
            },
            integrator: match code {
                _ if sets.iter().all(|(n, _)| *n != "integrator") => None,
                _ => Some(kind),
            },
            ..PanelLockParams::default()
        };
        let s = PanelLock::new(p).unwrap();
        assert_eq!(s.sim.integrator_kind(), kind, "{sets:?}");
    }
}

#[test]
fn panel_deflections_scale_with_the_inverse_of_the_stiffness() {
    // flexible panels (4 fixed-interface modes each, damped at 50 % of critical) deploying
    // before any lock-up bend under their own inertia and the hinge loads. With the panels 100
    // and 1000 times stiffer than the default (first modes near 75 and 240 Hz against a
    // deployment of about 0.2 Hz) they follow those loads quasi-statically, so linear elasticity
    // sets every deflection and modal amplitude to the compliance 1/E times the load: the ratio
    // of the two runs is 10 (the deviation, measured 0.7 % on the outer panel and up to 5 % on
    // the inner panels' second mode, falls as 1/E: the dynamic part, (f / f_mode)^2; at the
    // default stiffness it reaches 80 %). Outputs the deployment does not excite (the inner
    // panels' modes 1 and 3, the outer panel's mode 2) stay at round-off in both.
    let run = |e: f64| {
        let mut s = PanelLock::new(PanelLockParams {
            panel_youngs_modulus: e,
            modal_damping_ratio: 0.5,
            integrator: Some(IntegratorKind::Bdf),
            error_control: ErrorControl::PerStep,
            settings: Settings {
                rtol: 1e-8,
                atol: 1e-10,
                h_max: 0.02,
                ..PanelLockParams::default().settings
            },
            ..PanelLockParams::flexible(4)
        })
        .unwrap();
        let mut rows = Vec::new();
        for i in 1..=25 {
            s.advance_to(0.5 + 0.1 * i as f64).unwrap();
            let f = s.panel_flex_outputs();
            rows.push(
                f.iter()
                    .flat_map(|p| [p.tip_deflection, p.modes[0], p.modes[1], p.modes[2]])
                    .collect::<Vec<_>>(),
            );
        }
        rows
    };
    let e = 100.0 * PanelLockParams::default().panel_youngs_modulus;
    let (soft, stiff) = (run(e), run(10.0 * e));
    let what = ["tip deflection", "mode 1", "mode 2", "mode 3"];
    let mut excited = 0;
    for j in 0..soft[0].len() {
        let name = format!("panel {} {}", j / 4 + 1, what[j % 4]);
        let (big, big_stiff) = (
            largest(soft.iter().map(|r| r[j])),
            largest(stiff.iter().map(|r| r[j])),
        );
        if big < 1e-10 {
            println!("{name}: not excited ({big:.1e} m, {big_stiff:.1e} m)");
            assert!(big_stiff < 1e-10, "{name}: {big_stiff} m");
            continue;
        }
        excited += 1;
        let ratios: Vec<f64> = soft
            .iter()
            .zip(&stiff)
            .filter(|(a, _)| a[j].abs() > 0.2 * big)
            .map(|(a, b)| a[j] / b[j])
            .collect();
        let worst = largest(ratios.iter().map(|r| r / 10.0 - 1.0));
        println!(
            "{name}: largest {big:.3e} m, {} samples, ratio within {worst:.1e} of 10",
            ratios.len()
        );
        assert!(ratios.len() >= 10 && worst < 0.08, "{name}: {ratios:?}");
    }
    // every panel's tip deflection, the outer panel's mode 1 and the inner panels' mode 2
    assert!(excited >= 7, "{excited}");
}
