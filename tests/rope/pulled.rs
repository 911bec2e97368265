//! Rigs pulled by a hook at a constant speed (issue #42): end 2 of the rope on a hook that
//! reaches `v` [m/s] along the strand's direction in 0.1 s and keeps it, end 1 a load of 100 kg
//! per 9.81 kN pulled by a constant T1 along its strand; no gravity, block welded, no detection
//! of new crossings, generalized-alpha at the quasi-static rope tests' settings (rtol 1e-6, atol
//! 1e-7 m, h_max 1 ms). Used by `examples/rope_pull_speed.rs` and the rope tests.

use super::rig::{self, Hold, Wrap};
use mbcosim::integrator::IntegratorKind;
use mbcosim::math::Vec3;
use mbcosim::model::Profile;
use mbcosim::rope::friction::FrictionLaw;
use mbcosim::rope::{HookInit, SlipMode};
use mbcosim::scene::rope_block::{ContactSettings, EndSpec, RopeBlockSim};
use std::f64::consts::PI;
use std::sync::Arc;

/// The simulation of `rig` with end 2 on a hook that reaches `v` [m/s] along `rig.e2` in 0.1 s.
pub fn hooked(rig: &Wrap, v: f64) -> RopeBlockSim {
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
    .expect("the hooked rig builds")
}

/// The 90 degree sharp edge of `tests/rope/cone.rs` (edge along z) with strand 2 tilted by
/// `tilt` [deg] along the edge, both strands 2 m at tension `t1` [N].
pub fn tilted_rig(t1: f64, tilt: f64) -> Wrap {
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

/// What a 2 s run of the tilted edge pulled by the hook gives.
#[derive(Debug, Clone, Copy)]
pub struct TiltedRun {
    /// Integrator work: accepted and rejected steps, Newton iterations and failed ones.
    pub steps: u64,
    pub rejected: u64,
    pub newton: u64,
    pub newton_failed: u64,
    /// Steps after which the contact node slid along its edge.
    pub edge_slides: u64,
    /// T2/T1 across the node (its next over its previous segment's tension), sampled every
    /// 1 ms from 1 s to 2 s: mean, least and largest [-].
    pub mean: f64,
    pub least: f64,
    pub largest: f64,
}

/// Runs the tilted edge ([`tilted_rig`] at `t1` [N], `tilt` [deg]) pulled at `v` [m/s] for 2 s.
pub fn run_tilted(t1: f64, tilt: f64, v: f64) -> TiltedRun {
    run_tilted_under(FrictionLaw::EdgeFirst, t1, tilt, v)
}

/// [`run_tilted`] with the friction law `law`.
pub fn run_tilted_under(law: FrictionLaw, t1: f64, tilt: f64, v: f64) -> TiltedRun {
    let mut rig = tilted_rig(t1, tilt);
    rig.props.friction_law = law;
    let mut sim = hooked(&rig, v);
    let (mut sum, mut n, mut least, mut largest) = (0.0, 0, f64::INFINITY, 0.0f64);
    for s in 1..=2000 {
        let t = 1e-3 * s as f64;
        sim.advance_to(t).expect("the hooked rig runs");
        if t > 1.0 {
            let rep = sim.contact_reports()[0];
            let q = rep.segments.t_next / rep.segments.t_prev;
            sum += q;
            n += 1;
            least = least.min(q);
            largest = largest.max(q);
        }
    }
    let st = sim.sim.stats();
    TiltedRun {
        steps: st.steps,
        rejected: st.rejected,
        newton: st.newton_iterations,
        newton_failed: st.newton_failures,
        edge_slides: sim.counters.edge_slides,
        mean: sum / n as f64,
        least,
        largest,
    }
}
