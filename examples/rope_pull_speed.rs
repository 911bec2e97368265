//! Ropes pulled by a hook at a constant speed (issue #42, the RopeBlock items still open): end 2
//! of the rope is on a hook that reaches `v` [m/s] along the strand's direction over 0.1 s and
//! keeps it; end 1 is a load of 100 kg per 9.81 kN pulled by a constant T1 along its strand. No
//! gravity, block welded, no detection of new crossings, generalized-alpha with the quasi-static
//! rope tests' settings (rtol 1e-6, atol 1e-7 m, h_max 1 ms); steel rope of `tests/rope/rig.rs`
//! (EA 7.5e7 N, 6.4 kg/m, axial damping 7.5e3 N s, mu 0.2).
//!
//! - Capstan: the 180 degree drum of k = 32 and 64 edges (circumradius 0.52 m), T1 9.81 kN and
//!   981 kN, v = 0.2 m/s, 2 s, sampled every 1 ms: the largest segment tension over the larger
//!   of the two end segments' (`over ends`), and the largest excess of a segment over both its
//!   neighbours (`local`), both relative.
//! - Tilted sharp edge: the 90 degree edge of `tests/rope/cone.rs`, strand 2 tilted along the
//!   edge by 10 and 20 degrees, T1 981 kN (and 9.81 kN at 20 degrees), v = 0.05, 0.1, 0.2 m/s,
//!   2 s: steps, rejections, Newton work, edge slides, and T2/T1 across the node (its two
//!   segments) sampled every 1 ms, mean over 1-2 s, least and largest.
//!
//! Run: `cargo run --release --example rope_pull_speed [-- capstan | tilted]` (both by default).
//! The figures are in docs/rope_friction.md ("Pulled at a speed").

#[allow(dead_code)]
#[path = "../tests/rope/rig.rs"]
mod rig;

use mbcosim::integrator::IntegratorKind;
use mbcosim::math::Vec3;
use mbcosim::model::Profile;
use mbcosim::rope::{HookInit, SlipMode};
use mbcosim::scene::rope_block::{ContactSettings, EndSpec, RopeBlockSim};
use rig::{Hold, Wrap};
use std::f64::consts::PI;
use std::sync::Arc;

/// The simulation of `rig` with end 2 on a hook that reaches `v` [m/s] along `rig.e2` in 0.1 s.
fn hooked(rig: &Wrap, v: f64) -> RopeBlockSim {
    let mut s = rig.structure();
    let p2 = s.loads[1].position;
    s.loads.truncate(1);
    // the forces on load 1 (end 2); a welded block has no others
    s.forces.truncate(1);
    s.hooks = vec![HookInit {
        target_velocity: rig.e2 * v,
        ramp: 0.1,
        ..HookInit::at(p2)
    }];
    s.ropes[0].end = EndSpec::Hook(0);
    RopeBlockSim::new(
        s,
        IntegratorKind::GenAlpha,
        rig::settings(1e-3),
        ContactSettings {
            detect: false,
            ..ContactSettings::default()
        },
        0.0,
    )
    .unwrap()
}

fn capstan() {
    println!("capstan pulled at 0.2 m/s, 2 s, samples every 1 ms");
    for k in [32, 64] {
        for t1 in [9.81e3, 9.81e5] {
            let pull = (Profile::constant(t1), Profile::constant(t1));
            let rig = Wrap {
                end_mass: 100.0 * t1 / 9.81e3,
                ..Wrap::drum(k, 0.52, t1, rig::steel_rope(), pull, Hold::Fixed)
            };
            let mut sim = hooked(&rig, 0.2);
            let (mut over_ends, mut local) = (0.0f64, 0.0f64);
            let mut at = (0.0, 0, 0.0, 0.0);
            for s in 1..=2000 {
                let t = 1e-3 * s as f64;
                sim.advance_to(t).unwrap();
                let ten: Vec<f64> = sim.rope_tensions(0).iter().map(|x| x.0).collect();
                let ends = ten[0].max(ten[ten.len() - 1]);
                let top = ten.iter().fold(0.0f64, |a, x| a.max(*x));
                over_ends = over_ends.max(top / ends - 1.0);
                for j in 1..ten.len() - 1 {
                    let e = ten[j] / ten[j - 1].max(ten[j + 1]) - 1.0;
                    if e > local {
                        local = e;
                        at = (t, j, ten[j], ten[j - 1].max(ten[j + 1]));
                    }
                }
            }
            let st = sim.sim.stats();
            println!(
                "k {k:3}, T1 {t1:.3e} N: over ends {over_ends:.3e}, local {local:.3e} (t {:.3} s, segment {} of {}: {:.1} N, neighbours up to {:.1} N), steps {}, rejected {}, Newton {}, {:?}",
                at.0,
                at.1,
                sim.rope_tensions(0).len(),
                at.2,
                at.3,
                st.steps,
                st.rejected,
                st.newton_iterations,
                sim.counters
            );
        }
    }
}

/// The 90 degree sharp edge with strand 2 tilted by `tilt` [deg] along the edge.
fn tilted_rig(t1: f64, tilt: f64) -> Wrap {
    let g = 0.25 * PI;
    let a = tilt.to_radians();
    Wrap {
        mesh: Arc::new(rig::wedge(0.5 * PI)),
        vertices: vec![Vec3::zeros()],
        e1: Vec3::new(-g.sin(), -g.cos(), 0.0),
        e2: Vec3::new(g.sin() * a.cos(), -g.cos() * a.cos(), a.sin()),
        strand: 2.0,
        nodes: 3,
        props: rig::steel_rope(),
        t_init: vec![t1, t1],
        end_mass: 100.0 * t1 / 9.81e3,
        f1: Profile::constant(t1),
        f2: Profile::constant(t1),
        hold: Hold::Fixed,
        gravity: None,
        mode: SlipMode::Stick,
        grad: [0.0; 2],
        contact_mass: 1.0,
    }
}

fn tilted() {
    println!("tilted sharp edge pulled by the hook, 2 s; T2/T1 across the node every 1 ms");
    for (t1, tilt) in [(9.81e5, 10.0), (9.81e5, 20.0), (9.81e3, 20.0)] {
        for v in [0.05, 0.1, 0.2] {
            let mut sim = hooked(&tilted_rig(t1, tilt), v);
            let start = std::time::Instant::now();
            let (mut sum, mut n, mut lo, mut hi) = (0.0, 0, f64::INFINITY, 0.0f64);
            for s in 1..=2000 {
                let t = 1e-3 * s as f64;
                sim.advance_to(t).unwrap();
                if t > 1.0 {
                    let rep = sim.contact_reports()[0];
                    let q = rep.segments.t_next / rep.segments.t_prev;
                    sum += q;
                    n += 1;
                    lo = lo.min(q);
                    hi = hi.max(q);
                }
            }
            let st = sim.sim.stats();
            println!(
                "T1 {t1:.3e} N, tilt {tilt:4.1} deg, v {v:.2} m/s: steps {}, rejected {}, Newton {} (failed {}), edge slides {}; T2/T1 over 1-2 s mean {:.4}, least {lo:.4}, largest {hi:.4}; {:.1} s",
                st.steps,
                st.rejected,
                st.newton_iterations,
                st.newton_failures,
                sim.counters.edge_slides,
                sum / n as f64,
                start.elapsed().as_secs_f64()
            );
        }
    }
}

fn main() {
    let what: Vec<String> = std::env::args().skip(1).collect();
    let all = what.is_empty();
    if all || what.iter().any(|w| w == "capstan") {
        capstan();
    }
    if all || what.iter().any(|w| w == "tilted") {
        tilted();
    }
}
