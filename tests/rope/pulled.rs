//! Rigs pulled by a hook at a constant speed (issue #42): end 2 of the rope on a hook that
//! reaches `v` [m/s] along the strand's direction in 0.1 s and keeps it, end 1 a load of 100 kg
//! per 9.81 kN pulled by a constant T1 along its strand; no gravity, block welded, no detection
//! of new crossings, generalized-alpha at the quasi-static rope tests' settings (rtol 1e-6, atol
//! 1e-7 m, h_max 1 ms). Used by `examples/rope_pull_speed.rs` and the rope tests.
//!
//! Options ([`PullOptions`]): a viscous damper on the end load across its strand (the
//! quasi-static version of the rig: the load's swing damped, its motion along the strand free;
//! a rig element, the rope model unchanged) and the tolerances scaled (work-precision views).

use super::rig::{self, Hold, Wrap};
use mbcosim::integrator::IntegratorKind;
use mbcosim::math::Vec3;
use mbcosim::model::Profile;
use mbcosim::rope::friction::FrictionLaw;
use mbcosim::rope::{HookInit, SlipMode};
use mbcosim::scene::rope_block::{ContactSettings, DamperSpec, EndSpec, RopeBlockSim};
use std::f64::consts::PI;
use std::sync::Arc;

/// Options of a pulled run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PullOptions {
    /// Damping [N s/m] of a damper on the end load (end 1) against its velocity across the
    /// strand's direction `rig.e1` (0: none, the rig of issue #42).
    pub damping: f64,
    /// Damping [N s/m] on each material node of the two strands against its velocity across
    /// its strand's direction (0: none).
    pub strand_damping: f64,
    /// Damping [N s/m] on the contact node against its slide along its edge (0: none).
    pub contact_damping: f64,
    /// Factor on rtol and atol of [`rig::settings`] (1: rtol 1e-6, atol 1e-7 m).
    pub tol_scale: f64,
}

impl Default for PullOptions {
    fn default() -> Self {
        PullOptions {
            damping: 0.0,
            strand_damping: 0.0,
            contact_damping: 0.0,
            tol_scale: 1.0,
        }
    }
}

/// The damping [N s/m] that makes the end load's swing across its strand critically damped:
/// `2 sqrt(k m)` with the strand's lateral stiffness `k = T1 / L` (tension over strand length)
/// and the end mass `m`; 1.4e5 N s/m on the 981 kN tilted edge (swing 7 rad/s undamped).
pub fn swing_critical_damping(rig: &Wrap, t1: f64) -> f64 {
    2.0 * (t1 / rig.strand * rig.end_mass).sqrt()
}

/// The damping [N s/m] that makes a strand node's transverse vibration critically damped:
/// `2 m w` with the node's mass `m` (`rho L` of a segment `L`) and `w = sqrt(2 T1 / (m L))`;
/// about 7e3 N s/m on the 981 kN tilted edge (3.2 kg, 1.1e3 rad/s undamped).
pub fn strand_critical_damping(rig: &Wrap, t1: f64) -> f64 {
    let l = rig.strand / (rig.nodes + 1) as f64;
    let m = rig.props.mass_per_length * l;
    2.0 * m * (2.0 * t1 / (m * l)).sqrt()
}

/// The simulation of `rig` with end 2 on a hook that reaches `v` [m/s] along `rig.e2` in 0.1 s,
/// with the options `opt`.
pub fn hooked_with(rig: &Wrap, v: f64, opt: PullOptions) -> RopeBlockSim {
    let mut s = rig.structure();
    if opt.damping > 0.0 {
        s.dampers.push(DamperSpec::Load {
            load: 0,
            damping: opt.damping,
            free_axis: rig.e1,
        });
    }
    if opt.strand_damping > 0.0 {
        s.dampers.push(DamperSpec::Strands {
            rope: 0,
            damping: opt.strand_damping,
            free_axes: [rig.e1, rig.e2],
        });
    }
    if opt.contact_damping > 0.0 {
        s.dampers.push(DamperSpec::ContactNodes {
            rope: 0,
            damping: opt.contact_damping,
        });
    }
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
        mbcosim::integrator::Settings {
            rtol: 1e-6 * opt.tol_scale,
            atol: 1e-7 * opt.tol_scale,
            ..rig::settings(1e-3)
        },
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
    run_tilted_with(law, t1, tilt, v, PullOptions::default())
}

/// [`run_tilted_under`] with the options `opt`.
pub fn run_tilted_with(
    law: FrictionLaw,
    t1: f64,
    tilt: f64,
    v: f64,
    opt: PullOptions,
) -> TiltedRun {
    let mut rig = tilted_rig(t1, tilt);
    rig.props.friction_law = law;
    let mut sim = hooked_with(&rig, v, opt);
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

/// What a run of the tilted edge sampled at equal pulled lengths gives.
#[derive(Debug, Clone)]
pub struct LengthRun {
    /// Integrator work over the whole run (see [`TiltedRun`]), and the run's end [s].
    pub steps: u64,
    pub rejected: u64,
    pub newton: u64,
    pub newton_failed: u64,
    pub edge_slides: u64,
    pub t_end: f64,
    /// T2/T1 across the node at the pulled lengths `lengths` [m] (after the ramp).
    pub lengths: Vec<f64>,
    pub ratios: Vec<f64>,
}

impl LengthRun {
    /// Mean, least and largest of the ratios at pulled lengths of at least `from` [m].
    pub fn stats_from(&self, from: f64) -> (f64, f64, f64) {
        let r: Vec<f64> = self
            .lengths
            .iter()
            .zip(&self.ratios)
            .filter(|(s, _)| **s >= from - 1e-12)
            .map(|(_, q)| *q)
            .collect();
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        let least = r.iter().copied().fold(f64::INFINITY, f64::min);
        let largest = r.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (mean, least, largest)
    }
}

/// Runs the tilted edge ([`tilted_rig`] at `t1` [N], `tilt` [deg]) pulled at `v` [m/s] with
/// `opt` until the hook has pulled `s_end` [m], sampling T2/T1 every `ds` [m] of pulled length
/// from the end of the ramp on (the hook's speed ramps linearly over the first 0.1 s, so it
/// has pulled `s = v (t - 0.05)` at `t` from then on).
pub fn run_tilted_by_length(
    t1: f64,
    tilt: f64,
    v: f64,
    opt: PullOptions,
    ds: f64,
    s_end: f64,
) -> LengthRun {
    let rig = tilted_rig(t1, tilt);
    let mut sim = hooked_with(&rig, v, opt);
    let (mut lengths, mut ratios) = (Vec::new(), Vec::new());
    let n = (s_end / ds).round() as usize;
    let mut t_end = 0.0;
    for k in 1..=n {
        let s = ds * k as f64;
        let t = s / v + 0.05;
        if t < 0.1 {
            continue;
        }
        sim.advance_to(t).expect("the hooked rig runs");
        let rep = sim.contact_reports()[0];
        lengths.push(s);
        ratios.push(rep.segments.t_next / rep.segments.t_prev);
        t_end = t;
    }
    let st = sim.sim.stats();
    LengthRun {
        steps: st.steps,
        rejected: st.rejected,
        newton: st.newton_iterations,
        newton_failed: st.newton_failures,
        edge_slides: sim.counters.edge_slides,
        t_end,
        lengths,
        ratios,
    }
}
