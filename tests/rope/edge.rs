//! A rope over one sharp plate edge: frictionless statics and the Atwood machine.

use crate::rig::*;
use mbcosim::math::Vec3;
use mbcosim::model::Profile;
use mbcosim::rope::{RopeProps, SlipMode};
use std::sync::Arc;

fn dirs(turn: f64) -> (Vec3, Vec3) {
    let g = 0.5 * (std::f64::consts::PI - turn);
    (
        Vec3::new(-g.sin(), -g.cos(), 0.0),
        Vec3::new(g.sin(), -g.cos(), 0.0),
    )
}

#[test]
fn frictionless_edge_equal_tensions_and_bisector_reaction() {
    for turn_deg in [60.0f64, 90.0, 120.0] {
        let turn = turn_deg.to_radians();
        let (e1, e2) = dirs(turn);
        let t = 2.0e4;
        let props = RopeProps {
            friction: 0.0,
            ..RopeProps::default()
        };
        let rig = Wrap {
            t_init: vec![1.3 * t, 0.8 * t],
            ..Wrap::pulled(
                wedge(0.5 * (std::f64::consts::PI - turn)),
                vec![Vec3::zeros()],
                (e1, e2),
                props,
                t,
            )
        };
        // starts out of balance (1.3 T and 0.8 T), slides and settles
        let mut sim = rig.sim(settings(0.01));
        sim.advance_to(3.0).unwrap();
        let ten = sim.rope_tensions(0);
        let (ta, tb) = (ten[3].0, ten[4].0);
        let rep = &sim.contact_reports()[0];
        let n = rep.reaction.normal;
        let n_ref = 2.0 * t * (0.5 * turn).sin();
        let dir_err = (rep.frame.normal - Vec3::new(0.0, 1.0, 0.0)).norm();
        println!(
            "turn {turn_deg} deg: T {ta:.3} / {tb:.3} N, N = {n:.3} N (ref {n_ref:.3}), friction {:.2e} N, normal direction error {dir_err:.1e}",
            rep.reaction.friction()
        );
        assert!((ta - t).abs() < 1e-6 * t && (tb - t).abs() < 1e-6 * t);
        assert!((n - n_ref).abs() < 1e-6 * n_ref);
        assert!(rep.reaction.friction() < 1e-6 * t && dir_err < 1e-9);
    }
}

/// Atwood machine over a frictionless knife edge: ends of 3 kg and 2 kg, a 0.5 kg/m rope of 2 x 1 m.
/// Reference: a = g (m1 - m2) / (m1 + m2 + m_rope) at the instant both sides are equal; the
/// displacement of the heavy end over 40 ms is fitted with x = a t^2 / 2 (the lumped rope's weight
/// on each side changes only when nodes pass the edge, so the acceleration stays a).
#[test]
fn atwood_acceleration_with_rope_mass() {
    let g = 9.81;
    let (m1, m2, rho, side) = (3.0, 2.0, 0.5, 1.0);
    let m_rope = rho * 2.0 * side;
    let a = g * (m1 - m2) / (m1 + m2 + m_rope);
    let ea = 1e7;
    let props = RopeProps {
        mass_per_length: rho,
        ea,
        axial_damping: 1e-4 * ea,
        friction: 0.0,
        ..RopeProps::default()
    };
    // quasi-rigid initial tensions: T(d) at distance d below the edge
    let t_edge = (m1 + rho * side) * (g - a);
    let rig = Wrap {
        mesh: Arc::new(wedge(5f64.to_radians())),
        vertices: vec![Vec3::zeros()],
        e1: Vec3::new(0.0, -1.0, 0.0),
        e2: Vec3::new(0.0, -1.0, 0.0),
        strand: side,
        nodes: 4,
        props,
        t_init: vec![t_edge, t_edge],
        end_mass: 0.0,
        f1: Profile::constant(0.0),
        f2: Profile::constant(0.0),
        hold: Hold::Fixed,
        gravity: Some(Vec3::new(0.0, -g, 0.0)),
        mode: SlipMode::SlipForward,
        grad: [rho * (g - a), rho * (g + a)],
        contact_mass: 1e-3,
    };
    let mut s = rig.structure();
    s.loads[0].mass = m1;
    s.loads[1].mass = m2;
    s.forces.clear();
    // the rope's mass is rho times its unstretched length (2 m less the initial stretch)
    let m_rope_model = s.ropes[0].mass();
    assert!(
        (m_rope_model - m_rope).abs() < 1e-5 * m_rope,
        "rope mass {m_rope_model}"
    );
    let a = g * (m1 - m2) / (m1 + m2 + m_rope_model);
    let mut sim = mbcosim::scene::rope_block::RopeBlockSim::new(
        s,
        mbcosim::integrator::IntegratorKind::GenAlpha,
        mbcosim::integrator::Settings {
            rtol: 1e-8,
            atol: 1e-10,
            h_max: 2e-4,
            ..Default::default()
        },
        mbcosim::scene::rope_block::ContactSettings {
            detect: false,
            ..Default::default()
        },
        0.0,
    )
    .unwrap();
    let y0 = sim.structure.loads[0].position.y;
    println!("t0 tensions {:?}", sim.rope_tensions(0));
    println!("vdot {:?}", &sim.sim.state.vdot[6..12]);
    let (mut stt, mut sty) = (0.0, 0.0);
    let n = 40;
    for k in 1..=n {
        let t = 1e-3 * k as f64;
        sim.advance_to(t).unwrap();
        sim.sync();
        let x = y0 - sim.structure.loads[0].position.y;
        let t2 = 0.5 * t * t;
        stt += t2 * t2;
        sty += t2 * x;
        if k % 10 == 0 {
            println!("t {t} x {x:e} tensions {:?}", sim.rope_tensions(0));
        }
    }
    let a_fit = sty / stt;
    let rel = (a_fit - a) / a;
    println!(
        "Atwood: a = {a_fit:.6} m/s^2, reference {a:.6}, rel err {rel:.2e}, events {:?}",
        sim.counters
    );
    assert!(rel.abs() < 1e-3, "relative error {rel:.3e}");
}
