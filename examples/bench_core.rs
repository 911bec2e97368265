//! Speed figures of the multibody core and PanelLock (reported, never asserted):
//! chain scaling (planar, and 3D with spherical joints), double-pendulum work-precision against a minimal-coordinate reference,
//! hard-impact rebound, and the PanelLock real-time factor at 1 % peak-force accuracy.
//!
//! Run: `cargo run --release --example bench_core` (prints markdown tables).

use mbcosim::contact::ContactLaw;
use mbcosim::effect::plane_contact::{PlaneContact, PlaneContacts};
use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::math::{Mat3, Quat, Vec3};
use mbcosim::model::*;
use mbcosim::scene::panel_lock::{PanelLock, PanelLockParams};
use mbcosim::sim::Simulation;
use std::sync::Arc;
use std::time::Instant;

#[path = "../tests/common/chain3d.rs"]
mod chain3d;

const G: f64 = 9.81;

fn rod_inertia(m: f64, l: f64) -> Mat3 {
    let r = 0.01;
    Mat3::from_diagonal(&Vec3::new(
        0.5 * m * r * r,
        m * (3.0 * r * r + l * l) / 12.0,
        m * (3.0 * r * r + l * l) / 12.0,
    ))
}

/// Best-of-`n` CPU time [s] of `f`.
fn best_of<T>(n: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..n {
        let t0 = Instant::now();
        let r = f();
        best = best.min(t0.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("n >= 1"))
}

/// A chain of `n` rods hanging from the ground by revolute joints (axes z), gravity -y, released
/// at 0.5 rad.
fn chain(n: usize) -> Model {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0))).unwrap();
    let l = 0.1;
    let a = 0.5f64;
    let dir = Vec3::new(a.sin(), -a.cos(), 0.0);
    let rot = Quat::from_axis_angle(&Vec3::z_axis(), a - std::f64::consts::FRAC_PI_2);
    let half = Vec3::new(0.5 * l, 0.0, 0.0);
    let mut prev = (BodyId::GROUND, Vec3::zeros());
    for k in 0..n {
        let c = dir * (l * k as f64 + 0.5 * l);
        let id = b
            .add_rigid_body(
                &format!("rod{k}"),
                0.1,
                rod_inertia(0.1, l),
                BodyInit::at(c).oriented(rot),
            )
            .unwrap();
        b.add_joint(
            &format!("j{k}"),
            JointKind::Revolute,
            Frame::new(prev.0, prev.1),
            Frame::new(id, -half),
        )
        .unwrap();
        prev = (id, half);
    }
    b.build().unwrap()
}

/// Time per step of a chain built by `build(n)` for each `n` of `CHAIN_SIZES` (default
/// `sizes`), generalized-alpha with a fixed step of 1 ms over `steps` steps (`CHAIN_STEPS`
/// overrides), best of 3; prints a markdown table and the cost-per-step exponent (issue #18).
/// With `CHAIN_TIP=1` it also prints `tip x y z`: the far end [m] of the last rod (0.1 m, along
/// its body x axis) after the run, for `benches/exudyn_chain3d.py`'s cross-check.
fn chain_table(title: &str, sizes: &[usize], build: fn(usize) -> Model, steps: usize) {
    let steps = std::env::var("CHAIN_STEPS")
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(steps);
    println!("## {title}: time per step (generalized-alpha, fixed step 1 ms)\n");
    println!(
        "| n bodies | unknowns | time per step [us] | Newton iterations per step | factorizations |"
    );
    println!("|---|---|---|---|---|");
    let sizes: Vec<usize> = std::env::var("CHAIN_SIZES")
        .ok()
        .and_then(|v| v.split(',').map(|x| x.trim().parse().ok()).collect())
        .unwrap_or(sizes.to_vec());
    let mut pts = Vec::new();
    for &n in &sizes {
        let s = Settings {
            fixed_step: 1e-3,
            rtol: 1e-6,
            atol: 1e-8,
            ..Settings::default()
        };
        let sim0 = Simulation::new(build(n), IntegratorKind::GenAlpha, s, 0.0).unwrap();
        let (t, (stats, tip)) = best_of(3, || {
            let mut sim = sim0.clone();
            sim.advance_to(steps as f64 * 1e-3).unwrap();
            let last = sim.system.model.bodies.last().expect("a rod");
            let (q, o) = (&sim.state.q, last.q_offset);
            let tip = Vec3::new(q[o], q[o + 1], q[o + 2])
                + mbcosim::model::kinematics::quat_at(q, o + 3) * Vec3::new(0.05, 0.0, 0.0);
            (sim.stats(), tip)
        });
        if std::env::var("CHAIN_TIP").is_ok_and(|v| v == "1") {
            println!("tip {:.15e} {:.15e} {:.15e}", tip.x, tip.y, tip.z);
        }
        let per = t / steps as f64;
        let its = stats.newton_iterations as f64 / stats.steps as f64;
        println!(
            "| {n} | {} | {:.1} | {its:.2} | {} |",
            sim0.system.n_v() + sim0.system.n_c(),
            per * 1e6,
            stats.factorizations
        );
        pts.push(((n as f64).ln(), per.ln()));
    }
    let last = pts.len() - 1;
    let ends = (pts[last].1 - pts[0].1) / (pts[last].0 - pts[0].0);
    println!(
        "\nCost-per-step exponent ({} -> {} bodies): {ends:.2} first to last, {:.2} least squares\n",
        sizes[0],
        sizes[last],
        fitted_slope(&pts)
    );
}

/// Least-squares slope of `(x, y)` points.
fn fitted_slope(p: &[(f64, f64)]) -> f64 {
    let n = p.len() as f64;
    let (mx, my) = (
        p.iter().map(|q| q.0).sum::<f64>() / n,
        p.iter().map(|q| q.1).sum::<f64>() / n,
    );
    let sxy: f64 = p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    let sxx: f64 = p.iter().map(|q| (q.0 - mx).powi(2)).sum();
    sxy / sxx
}

/// Minimal-coordinate reference of the double pendulum of two rods (1 m, 1 kg): the tip position
/// at time `t_end`, by RK4 with step `dt`.
fn double_pendulum_reference(a1: f64, a2: f64, t_end: f64, dt: f64) -> Vec3 {
    let (m, l) = (1.0, 1.0);
    let i = rod_inertia(m, l)[(2, 2)];
    let rhs = |y: [f64; 4]| {
        let (a1, a2, w1, w2) = (y[0], y[1], y[2], y[3]);
        let c = m * l * l / 2.0;
        let (s, co) = ((a1 - a2).sin(), (a1 - a2).cos());
        let m11 = m * l * l / 4.0 + i + m * l * l;
        let m22 = m * l * l / 4.0 + i;
        let m12 = c * co;
        let f1 = -c * s * w2 * w2 - (m * l / 2.0 + m * l) * G * a1.sin();
        let f2 = c * s * w1 * w1 - m * G * l / 2.0 * a2.sin();
        let det = m11 * m22 - m12 * m12;
        [
            w1,
            w2,
            (m22 * f1 - m12 * f2) / det,
            (m11 * f2 - m12 * f1) / det,
        ]
    };
    let mut y = [a1, a2, 0.0, 0.0];
    let n = (t_end / dt).round() as usize;
    let add = |y: [f64; 4], k: [f64; 4], h: f64| {
        [
            y[0] + h * k[0],
            y[1] + h * k[1],
            y[2] + h * k[2],
            y[3] + h * k[3],
        ]
    };
    for _ in 0..n {
        let k1 = rhs(y);
        let k2 = rhs(add(y, k1, dt / 2.0));
        let k3 = rhs(add(y, k2, dt / 2.0));
        let k4 = rhs(add(y, k3, dt));
        for j in 0..4 {
            y[j] += dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
        }
    }
    Vec3::new(
        l * y[0].sin() + l * y[1].sin(),
        -l * y[0].cos() - l * y[1].cos(),
        0.0,
    )
}

fn double_pendulum_model(a1: f64, a2: f64) -> Model {
    let mut b = ModelBuilder::new();
    b.set_gravity(Some(Vec3::new(0.0, -G, 0.0))).unwrap();
    let dir = |a: f64| Vec3::new(a.sin(), -a.cos(), 0.0);
    let rot = |a: f64| Quat::from_axis_angle(&Vec3::z_axis(), a - std::f64::consts::FRAC_PI_2);
    let r1 = b
        .add_rigid_body(
            "rod1",
            1.0,
            rod_inertia(1.0, 1.0),
            BodyInit::at(dir(a1) * 0.5).oriented(rot(a1)),
        )
        .unwrap();
    let r2 = b
        .add_rigid_body(
            "rod2",
            1.0,
            rod_inertia(1.0, 1.0),
            BodyInit::at(dir(a1) + dir(a2) * 0.5).oriented(rot(a2)),
        )
        .unwrap();
    let half = Vec3::new(0.5, 0.0, 0.0);
    b.add_joint(
        "j1",
        JointKind::Revolute,
        Frame::new(BodyId::GROUND, Vec3::zeros()),
        Frame::new(r1, -half),
    )
    .unwrap();
    b.add_joint(
        "j2",
        JointKind::Revolute,
        Frame::new(r1, half),
        Frame::new(r2, -half),
    )
    .unwrap();
    b.build().unwrap()
}

fn double_pendulum() {
    let (a1, a2, t_end) = (1.2, 1.6, 2.0);
    let reference = double_pendulum_reference(a1, a2, t_end, 2e-5);
    let check = double_pendulum_reference(a1, a2, t_end, 4e-5);
    println!("## Double pendulum (two 3D rods, revolute joints), 2 s: tip error vs CPU time\n");
    println!(
        "Reference: minimal coordinates, RK4 at 20 us (self-check against 40 us: {:.1e} m).\n",
        (reference - check).norm()
    );
    println!("| integrator | rtol | tip error [m] | CPU [ms] | steps |");
    println!("|---|---|---|---|---|");
    let model = double_pendulum_model(a1, a2);
    for kind in IntegratorKind::ALL {
        for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
            let s = Settings {
                rtol,
                atol: rtol * 1e-2,
                h_max: 0.1,
                ..Settings::default()
            };
            let (t, (tip, steps)) = best_of(5, || {
                let mut sim = Simulation::new(model.clone(), kind, s, 0.0).unwrap();
                sim.advance_to(t_end).unwrap();
                let q = &sim.state.q;
                let tip = Vec3::new(q[7], q[8], q[9])
                    + kinematics::quat_at(q, 10) * Vec3::new(0.5, 0.0, 0.0);
                (tip, sim.stats().steps)
            });
            println!(
                "| {} | {rtol:.0e} | {:.2e} | {:.3} | {steps} |",
                kind.name(),
                (tip - reference).norm(),
                t * 1e3
            );
        }
    }
    println!();
}

fn hard_impact() {
    println!(
        "## Hard impact: 1 kg at 1 m/s on Hertz k = 1e7 N/m^1.5, 30 ms: rebound speed error vs CPU time\n"
    );
    println!("| integrator | rtol | rebound error (rel.) | CPU [ms] | steps |");
    println!("|---|---|---|---|---|");
    for kind in IntegratorKind::ALL {
        for rtol in [1e-5, 1e-7, 1e-9] {
            let s = Settings {
                rtol,
                atol: rtol * 1e-3,
                h_max: 0.01,
                ..Settings::default()
            };
            let (t, (v, steps)) = best_of(5, || {
                let mut b = ModelBuilder::new();
                let p = b
                    .add_particle(
                        "ball",
                        1.0,
                        Vec3::new(0.0, 0.0, 0.01),
                        Vec3::new(0.0, 0.0, -1.0),
                    )
                    .unwrap();
                let law = ContactLaw::hertz(1e7, 1.5).unwrap();
                b.add_force_effect(Arc::new(PlaneContacts {
                    elements: vec![PlaneContact {
                        name: "floor".into(),
                        point: Frame::new(p, Vec3::zeros()),
                        normal: Vec3::z(),
                        offset: 0.0,
                        law,
                    }],
                }));
                let mut sim = Simulation::new(b.build().unwrap(), kind, s, 0.0).unwrap();
                sim.advance_to(0.03).unwrap();
                (sim.state.v[2], sim.stats().steps)
            });
            println!(
                "| {} | {rtol:.0e} | {:.1e} | {:.3} | {steps} |",
                kind.name(),
                (v - 1.0).abs(),
                t * 1e3
            );
        }
    }
    println!();
}

fn panel_lock_speed() {
    println!(
        "## PanelLock default scene (3 panels, rigid), 60 s: largest lock force error vs CPU time\n"
    );
    println!(
        "The design quantity is the largest pin/groove force over all hinges (it converges; the"
    );
    println!(
        "innermost hinge's late, slow lock-up after rattling is trajectory-sensitive and is not used).\n"
    );
    let run = |kind: IntegratorKind, rtol: f64| {
        let p = PanelLockParams {
            integrator: Some(kind),
            settings: Settings {
                rtol,
                atol: rtol * 1e-2,
                h_max: 0.02,
                ..Settings::default()
            },
            ..PanelLockParams::default()
        };
        best_of(2, || {
            let mut s = PanelLock::new(p.clone()).unwrap();
            s.advance_to(60.0).unwrap();
            let o = s.outputs();
            (
                o.hinges.iter().map(|h| h.peak_force).collect::<Vec<_>>(),
                s.sim.stats().steps,
            )
        })
    };
    let (_, (reference, _)) = run(IntegratorKind::Bdf, 1e-9);
    let ref_max = reference.iter().copied().fold(0.0, f64::max);
    println!(
        "Reference: BDF at rtol 1e-9, peak forces {:?} N (hinges root..outer).\n",
        reference
            .iter()
            .map(|f| (f * 10.0).round() / 10.0)
            .collect::<Vec<_>>()
    );
    println!(
        "| integrator | rtol | largest lock force error | CPU [s] | real-time factor | steps |"
    );
    println!("|---|---|---|---|---|---|");
    for kind in IntegratorKind::ALL {
        for rtol in [1e-3, 1e-4, 1e-5, 1e-6] {
            let (t, (peaks, steps)) = run(kind, rtol);
            let err = (peaks.iter().copied().fold(0.0, f64::max) - ref_max).abs() / ref_max;
            println!(
                "| {} | {rtol:.0e} | {:.1e} | {:.3} | {:.0} | {steps} |",
                kind.name(),
                err,
                t,
                60.0 / t
            );
        }
    }
    println!();
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_default();
    if which.is_empty() || which == "chain" {
        chain_table(
            "Planar chain of n rods, revolute joints",
            &[10, 100, 1000],
            chain,
            200,
        );
    }
    if which.is_empty() || which == "chain3d" {
        chain_table(
            "3D chain of n rods, spherical joints, spinning",
            &[10, 30, 100, 300, 1000],
            chain3d::spinning_chain,
            100,
        );
    }
    if which.is_empty() || which == "pendulum" {
        double_pendulum();
    }
    if which.is_empty() || which == "impact" {
        hard_impact();
    }
    if which.is_empty() || which == "panel" {
        panel_lock_speed();
    }
}
