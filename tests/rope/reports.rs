//! Post-step reports while the rope slides (issue #19): a rope pulled around a 32-edge polygonal
//! drum (wrap 180 degrees, circumradius 0.52 m) at 2.2 T1 (gross slip at 1.875 T1), so that the
//! rope runs through all 32 contact nodes. At every output point the tension the scene reports for
//! each segment (`rope_tensions`, and each contact node's `contact_reports`) must equal the force
//! that acts: the axial law `EA (l - L) / L` evaluated independently here from the node positions
//! `l` and the accepted material coordinates `L` (the rope is undamped, so the law is elastic
//! only). Over 1 s the rope is re-meshed (merges and splits) on the way. On main c11afeb the
//! reports ran a fresh return mapping from the updated memory, which could settle on another set
//! of sliding nodes than the step: 1 of 200 output points here was off by 2.8 % (segments 17-32
//! reported as if the rope slid through a node the accepted state has sticking).

use crate::rig::*;
use mbcosim::math::Vec3;
use mbcosim::model::Profile;
use mbcosim::rope::{RopeProps, SlipMode};
use mbcosim::scene::rope_block::RopeBlockSim;
use std::f64::consts::PI;
use std::sync::Arc;

/// Material coordinate [m] of every point of rope 0 at the current state.
fn sigmas(sim: &RopeBlockSim) -> Vec<f64> {
    let spec = &sim.structure.ropes[0];
    let mem = &sim.sim.state.memory[sim.map.rope_memory..];
    let mut s = vec![spec.sigma_start];
    for (i, node) in spec.nodes.iter().enumerate() {
        let p = i + 1;
        s.push(match sim.map.rope.contact_of(p) {
            Some(c) => mem[sim.map.rope.contact_memory_offset(c)],
            None => node.sigma,
        });
    }
    s.push(spec.sigma_end);
    s
}

#[test]
fn reported_tensions_equal_acting_forces_while_sliding() {
    let k = 32;
    let r = 0.52;
    let t1 = 9.81e3;
    let props = RopeProps {
        mass_per_length: 6.4,
        ea: 7.5e7,
        axial_damping: 0.0,
        friction: 0.2,
        ..RopeProps::default()
    };
    let d = PI / k as f64;
    let vertices: Vec<Vec3> = (1..=k)
        .map(|j| {
            let a = 0.5 * PI + (k as f64 + 1.0 - 2.0 * j as f64) * 0.5 * d;
            Vec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect();
    let rig = Wrap {
        mesh: Arc::new(polygon(2 * k, r)),
        vertices,
        e1: Vec3::new(0.0, -1.0, 0.0),
        e2: Vec3::new(0.0, -1.0, 0.0),
        strand: 1.5,
        nodes: 2,
        props,
        t_init: vec![t1; k + 1],
        end_mass: 100.0,
        f1: Profile::constant(t1),
        f2: Profile::constant(2.2 * t1),
        hold: Hold::Fixed,
        gravity: None,
        mode: SlipMode::Stick,
        grad: [0.0; 2],
        contact_mass: 1.0,
    };
    let mut sim = rig.sim(settings(1e-3));
    let ea = props.ea;
    let (mut samples, mut bad, mut worst, mut sliding) = (0, 0, 0.0f64, 0);
    for step in 1..=200 {
        let t = 5e-3 * step as f64;
        sim.advance_to(t).unwrap();
        let pts = sim.rope_points(0);
        let sig = sigmas(&sim);
        let reported = sim.rope_tensions(0);
        let reports = sim.contact_reports();
        sliding += sim
            .slip_modes()
            .iter()
            .filter(|m| **m != SlipMode::Stick)
            .count();
        let acting: Vec<f64> = (0..pts.len() - 1)
            .map(|j| {
                let (l, rest) = ((pts[j + 1] - pts[j]).norm(), sig[j + 1] - sig[j]);
                if l > rest {
                    ea * (l - rest) / rest
                } else {
                    0.0
                }
            })
            .collect();
        let scale = acting.iter().fold(0.0f64, |a, x| a.max(*x));
        let mut off = 0.0f64;
        for (j, (tr, _)) in reported.iter().enumerate() {
            off = off.max((tr - acting[j]).abs());
        }
        for rep in &reports {
            let p = rep.node + 1;
            off = off.max((rep.segments.t_prev - acting[p - 1]).abs());
            off = off.max((rep.segments.t_next - acting[p]).abs());
        }
        samples += 1;
        let rel = off / scale;
        worst = worst.max(rel);
        if rel > 1e-6 {
            bad += 1;
            if bad <= 3 {
                println!(
                    "t = {t:.3} s: reported tension off the acting force by {off:.3e} N ({rel:.2e} of {scale:.4e} N), {:?}",
                    sim.counters
                );
            }
        }
    }
    println!(
        "32 contact nodes: {bad} of {samples} output points with reports off the acting forces (worst {worst:.2e} relative); node-samples sliding {sliding}"
    );
    assert!(sliding > 0, "the rope never slid");
    assert_eq!(bad, 0, "worst relative mismatch {worst:.3e}");
}

/// Cost per step of the sliding drum against the number of contact nodes (not a check; run with
/// `cargo test --release --test rope -- --ignored --nocapture cost_per_step`).
#[test]
#[ignore]
fn cost_per_step_against_contact_nodes() {
    for k in [8, 16, 32, 64] {
        let r = 0.52;
        let t1 = 9.81e3;
        let props = RopeProps {
            mass_per_length: 6.4,
            ea: 7.5e7,
            axial_damping: 0.0,
            friction: 0.2,
            ..RopeProps::default()
        };
        let d = PI / k as f64;
        let vertices: Vec<Vec3> = (1..=k)
            .map(|j| {
                let a = 0.5 * PI + (k as f64 + 1.0 - 2.0 * j as f64) * 0.5 * d;
                Vec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect();
        let rig = Wrap {
            mesh: Arc::new(polygon(2 * k, r)),
            vertices,
            e1: Vec3::new(0.0, -1.0, 0.0),
            e2: Vec3::new(0.0, -1.0, 0.0),
            strand: 1.5,
            nodes: 2,
            props,
            t_init: vec![t1; k + 1],
            end_mass: 100.0,
            f1: Profile::constant(t1),
            f2: Profile::constant(2.2 * t1),
            hold: Hold::Fixed,
            gravity: None,
            mode: SlipMode::Stick,
            grad: [0.0; 2],
            contact_mass: 1.0,
        };
        let mut sim = rig.sim(settings(1e-3));
        let start = std::time::Instant::now();
        sim.advance_to(0.3).unwrap();
        let wall = start.elapsed().as_secs_f64();
        let steps = sim.sim.stats().steps;
        println!(
            "k = {k:3}: {steps} steps in {wall:.3} s, {:.3} ms per step",
            1e3 * wall / steps as f64
        );
    }
}
