//! The RopeBlock scene as a co-simulation model would see it: built from [`RopeBlockParams`],
//! driven through hook rates, read through named outputs.
//!
//! Inputs (per hook `k`): velocity [m/s] (world) and winch pay-out rate [m/s], held constant until
//! changed, so the hook position stays continuous. Outputs (SI, see [`RopeBlockScene::output_names`]):
//!
//! | name | meaning |
//! |------|---------|
//! | `time` | simulation time [s] |
//! | `hook{k}.x/y/z` | hook position [m], world |
//! | `hook{k}.load`, `hook{k}.fz` | magnitude and vertical component of the ropes' pull on the hook [N] |
//! | `sling{r}.tension_hook`, `sling{r}.tension_lug` | tension of the sling's first and last segment [N] |
//! | `sling{r}.utilisation` | highest segment tension over the sling's breaking load [-] |
//! | `sling{r}.angle` | angle of the segment at the hook to the vertical [rad] |
//! | `contact.count` | number of contact nodes |
//! | `contact{i}.normal`, `contact{i}.friction` | force of the plate edge on the rope at contact slot `i` [N] (below) |
//! | `contact{i}.x/y/z` | node position [m] in the block's design frame |
//! | `contact{i}.sling`, `contact{i}.slip` | sling index (-1: empty slot), slip along the rope (0 stick or frictionless, +-1 sliding) |
//! | `block.x/y/z` | centre of mass [m], world |
//! | `block.qw/qx/qy/qz` | orientation quaternion (block to world) |
//! | `block.vx/vy/vz` | velocity of the centre of mass [m/s], world |
//! | `block.wx/wy/wz` | angular velocity [rad/s], block frame |
//! | `energy.kinetic/potential/dissipated/input/events` | energy bookkeeping [J] |
//! | `ground.normal/friction` | ground forces [N] (with a ground only) |
//! | `daf` | dynamic amplification factor: hooks' total vertical load / weight of everything [-] |
//! | `hook{k}.fx/fy` | world x and y of the slings' force on the crane at the hook [N] (power bond) |
//! | `hook{k}.power/work` | power the hook delivers into the model [W] and its integral [J] |
//! | `hook{k}.winch_force/winch_power/winch_work` | the winch's line force [N], power into the model [W], its integral [J] |
//!
//! The power bonds and their sign conventions: [`super::bonds`], docs/power_bonds.md.
//!
//! Contact slots are filled in rope order each time outputs are read; beyond
//! `params.contact_outputs` nodes are counted but not reported.
//!
//! The contact force ([`NodeReport::reaction`]) is the force the plate edge applies to the rope
//! in the dynamics at the communication point (the state the last accepted step and the contact
//! manager left), in the node's contact frame ([`crate::rope::friction::ContactFrame`]: `n` the
//! rope's turn bisector made perpendicular to the edge, turned to the plate's side; `e` along the
//! edge; `t = e x n` across it, along the rope). `normal` is `N`, the rope's pull
//! `-(T_prev e_prev + T_next e_next)` along `n` (positive: the plate pushes the rope; the
//! segment tensions either side, unit vectors from the node to its neighbours). `friction` is
//! `|(F_e, F_r)| >= 0`: `F_e` the edge hold's force along `e`, `F_r` the pull along `t` (the
//! tensions' difference). Coulomb: `friction <= mu N` while the node sticks, `= mu N` (to 1e-9
//! relative) while the rope slides through it; with friction off (`mu = 0`) both friction and the
//! slip flag read exactly 0. The line joint's own reaction differs by the weight and inertia of
//! the rope's lumped mass at the node (no contact force).

use super::params::RopeBlockParams;
use super::runner::RopeBlockSim;
use super::statics;
use super::structure::EndSpec;
use super::view::BlockLook;
use super::{ContactSettings, NodeReport};
use crate::integrator::Settings;
use crate::math::Vec3;
use crate::rope::SlipMode;

/// Static equilibrium with the rope sliding freely over every contact node and every node
/// sliding freely along its edge (equal tensions on both sides and no load along the edge, as
/// when a sling is loaded slowly), then every node sticking where it is: each node starts inside
/// its Coulomb cone (no friction at all) and at rest. `weight` [N] scales the force tolerance.
pub fn settle(sim: &mut RopeBlockSim, weight: f64) -> Result<(), String> {
    let base = sim.map.rope_memory;
    let n = sim.map.rope.n_contacts();
    let mut saved = Vec::with_capacity(n);
    for c in 0..n {
        let mut mem = sim.map.rope.memory_mut(&mut sim.sim.state.memory[base..]);
        let mut m = mem.contact_mut(c);
        saved.push((m.mode(), m.share(), m.mu(), m.cap()));
        // frictionless sliding: no share along the rope, no cone to re-stick in, and along the
        // edge a slide against no force (the hold's spring would keep the node at its rigging
        // point: the turn-over started with 1.28 mu N on its edge, and slid off at once)
        m.set_mode(SlipMode::SlipForward);
        m.set_share(0.0);
        m.set_mu(0.0);
        m.set_edge_slide(1.0);
        m.set_cap(0.0);
    }
    sim.sim.restart().map_err(String::from)?;
    statics::solve(sim, 1e-9 * weight, 300)?;
    check_breaking_loads(sim)?;
    // freeze the split of rope at each node where the free sliding left it
    sim.sim.system.update_memory(
        sim.sim.state.t,
        &sim.sim.state.q.clone(),
        &sim.sim.state.v.clone(),
        &mut sim.sim.state.memory,
    );
    // each hold sticks where its node came to rest, carrying nothing
    let anchors = sim.hold_anchors(0.0);
    for (c, (mode, share, mu, cap)) in saved.into_iter().enumerate() {
        let mut mem = sim.map.rope.memory_mut(&mut sim.sim.state.memory[base..]);
        let mut m = mem.contact_mut(c);
        m.set_mode(mode);
        m.set_share(share);
        m.set_mu(mu);
        m.set_edge_slide(0.0);
        m.set_cap(cap);
        if let Some(u0) = anchors[c] {
            m.set_anchor(u0);
        }
    }
    sim.sim.restart().map_err(String::from)
}

/// Refuses a settled scene whose slings carry more than their breaking load at rest: a load that
/// would part them has no meaningful lift to simulate (and the dynamics of slings strained far
/// beyond their breaking strain crawl). `Err` names the sling, its tension and its breaking load.
fn check_breaking_loads(sim: &mut RopeBlockSim) -> Result<(), String> {
    for r in 0..sim.map.rope.rope_ranges().len() {
        let limit = sim.map.rope.rope_props(r).breaking_load;
        let peak = sim
            .rope_tensions(r)
            .iter()
            .fold(0.0f64, |a, &(t, _)| a.max(t));
        if peak > limit {
            return Err(format!(
                "no static equilibrium within the slings' strength: sling {r} carries {peak:.4e} N at rest, above its breaking load {limit:.4e} N (the block is too heavy for this sling: lower block_mass, or use stronger slings: rope_breaking_load, or breaking_load in the scene file's [[sling]]; more slings or a better share between them also help; with ground_contact on, a ground_height above the hanging block pushes it into the slings)"
            ));
        }
    }
    Ok(())
}

/// Highest BDF order of RopeBlock scenes (see [`solver_settings`]).
pub const BDF_MAX_ORDER: usize = 2;

/// Integrator and contact-manager settings of a scene with these parameters.
pub fn solver_settings(params: &RopeBlockParams) -> (Settings, ContactSettings) {
    let (rtol, atol) = params.tolerances();
    let settings = Settings {
        rtol,
        atol,
        h_max: params.h_max,
        // BDF of order 3-5 is not A-stable: the lightly damped modes of the slings and of the
        // block bouncing on them sit in their instability region at the steps the accuracy would
        // allow, so the error control throttles them to sub-millisecond steps (or they blow up).
        // BDF2 is A-stable: the lift runs in about 5,500 steps instead of not finishing.
        max_order: BDF_MAX_ORDER,
        // equal steps per communication step, one Newton matrix for many of them (long slings)
        equal_steps: true,
        // per step (RopeBlockSim::new enforces it): per unit step gen-alpha's estimate of the
        // damped rope waves held the steps near 1e-7 s, and BDF's Newton stalled at the tighter
        // target of short steps as contact nodes slide between steps (tests/rope_ground.rs: 2e5
        // steps at t = 0.032 s)
        error_per_unit_step: false,
        rho_inf: params.rho_inf,
        ..Settings::default()
    };
    let contact = ContactSettings {
        detect: params.contact,
        ..ContactSettings::default()
    };
    (settings, contact)
}

/// Per-hook power-bond outputs, in the order [`RopeBlockScene::outputs`] writes them (after
/// `daf`).
pub const BOND_OUTPUTS: [&str; 7] = [
    "fx",
    "fy",
    "power",
    "work",
    "winch_force",
    "winch_power",
    "winch_work",
];

/// A RopeBlock scene.
#[derive(Debug)]
pub struct RopeBlockScene {
    pub params: RopeBlockParams,
    pub sim: RopeBlockSim,
    names: Vec<String>,
    /// Centre of mass in the design frame [m] (to report positions in the design frame).
    com: Vec3,
    /// The block's shell as drawn by [`RopeBlockScene::snapshot`].
    pub(super) look: BlockLook,
}

impl RopeBlockScene {
    /// Builds the scene (and settles it in static equilibrium if `params.settle`).
    pub fn new(params: RopeBlockParams) -> Result<Self, String> {
        let structure = params.structure()?;
        let (settings, contact) = solver_settings(&params);
        let mut sim = RopeBlockSim::new(structure, params.integrator, settings, contact, 0.0)?;
        sim.hook_ramp = params.hook_ramp;
        if params.settle {
            let mass = params.mass_of(&params.design_mesh()?);
            settle(&mut sim, mass * params.gravity.max(1.0))?;
        }
        Self::from_sim(params, sim)
    }

    /// The scene around an existing simulation of `params` (e.g. one restored from bytes):
    /// nothing is built or settled.
    pub fn from_sim(params: RopeBlockParams, sim: RopeBlockSim) -> Result<Self, String> {
        let design = params.design_mesh()?;
        let (com, _, _) = params.mass_properties(&design);
        let look = BlockLook::new(&design, &com);
        let mut names: Vec<String> = vec!["time".into()];
        for k in 0..params.rig.hooks.len() {
            for c in ["x", "y", "z", "load", "fz"] {
                names.push(format!("hook{k}.{c}"));
            }
        }
        for r in 0..params.rig.slings.len() {
            for c in ["tension_hook", "tension_lug", "utilisation", "angle"] {
                names.push(format!("sling{r}.{c}"));
            }
        }
        names.push("contact.count".into());
        for i in 0..params.contact_outputs {
            for c in ["normal", "friction", "x", "y", "z", "sling", "slip"] {
                names.push(format!("contact{i}.{c}"));
            }
        }
        for c in [
            "x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz",
        ] {
            names.push(format!("block.{c}"));
        }
        for c in ["kinetic", "potential", "dissipated", "input", "events"] {
            names.push(format!("energy.{c}"));
        }
        if params.ground.is_some() {
            names.push("ground.normal".into());
            names.push("ground.friction".into());
        }
        names.push("daf".into());
        for k in 0..params.rig.hooks.len() {
            for c in BOND_OUTPUTS {
                names.push(format!("hook{k}.{c}"));
            }
        }
        Ok(RopeBlockScene {
            params,
            sim,
            names,
            com,
            look,
        })
    }

    /// The same scene (parameters, output names) around another simulation of it.
    pub fn with_sim(&self, sim: RopeBlockSim) -> Self {
        RopeBlockScene {
            params: self.params.clone(),
            sim,
            names: self.names.clone(),
            com: self.com,
            look: self.look.clone(),
        }
    }

    /// Names of the outputs, in the order of [`RopeBlockScene::outputs`].
    pub fn output_names(&self) -> &[String] {
        &self.names
    }

    /// Sets hook `k`'s velocity [m/s] (world) and pay-out rate [m/s] from now on.
    pub fn set_hook(&mut self, k: usize, velocity: Vec3, payout_rate: f64) -> Result<(), String> {
        self.sim.set_hook_rates(k, velocity, payout_rate)
    }

    /// Sends hook `k` to `target` [m] (world), arriving at rest (see
    /// [`super::RopeBlockSim::set_hook_target`]), with pay-out rate `payout_rate` [m/s].
    pub fn set_hook_target(
        &mut self,
        k: usize,
        target: Vec3,
        payout_rate: f64,
    ) -> Result<(), String> {
        self.sim.set_hook_target(k, target, payout_rate)
    }

    /// Advances by `h` [s].
    pub fn step(&mut self, h: f64) -> Result<(), String> {
        if !(h.is_finite() && h > 0.0) {
            return Err(format!("step must be finite and > 0 s, got {h}"));
        }
        let t = self.sim.time() + h;
        self.sim.advance_to(t)
    }

    /// All outputs at the current state, in the order of [`RopeBlockScene::output_names`].
    pub fn outputs(&mut self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.names.len());
        let sim = &mut self.sim;
        out.push(sim.time());
        let nh = self.params.rig.hooks.len();
        let mut pull = vec![Vec3::zeros(); nh];
        let mut ends = Vec::new();
        for r in 0..sim.structure.ropes.len() {
            let ten = sim.rope_tensions(r);
            let pts = sim.rope_points(r);
            let n = pts.len();
            let (first, last) = (ten[0].0, ten[ten.len() - 1].0);
            let peak = ten.iter().fold(0.0f64, |a, &(t, _)| a.max(t));
            let mbl = sim.map.rope.rope_props(r).breaking_load;
            let seg = pts[1] - pts[0];
            let angle = (seg.z.abs() / seg.norm()).clamp(0.0, 1.0).acos();
            ends.push((first, last, peak / mbl, angle));
            let rope = &sim.structure.ropes[r];
            if let EndSpec::Hook(k) = rope.start {
                pull[k] += (pts[1] - pts[0]).normalize() * first;
            }
            if let EndSpec::Hook(k) = rope.end {
                pull[k] += (pts[n - 2] - pts[n - 1]).normalize() * last;
            }
        }
        let mem = &sim.sim.state.memory[sim.map.rope_memory..];
        for (k, p) in pull.iter().enumerate() {
            let (x, _) = sim.map.rope.hook_motion(mem, k, sim.sim.state.t);
            out.extend([x.x, x.y, x.z, p.norm(), p.z]);
        }
        for (a, b, u, angle) in ends {
            out.extend([a, b, u, angle]);
        }
        let reports: Vec<NodeReport> = sim.contact_reports();
        out.push(reports.len() as f64);
        for i in 0..self.params.contact_outputs {
            match reports.get(i) {
                Some(r) => {
                    let c = sim.structure.ropes[r.rope].nodes[r.node]
                        .contact
                        .map(|c| c.anchor + self.com)
                        .unwrap_or_default();
                    out.extend([
                        r.reaction.normal,
                        r.reaction.friction(),
                        c.x,
                        c.y,
                        c.z,
                        r.rope as f64,
                        r.slip_code(),
                    ]);
                }
                None => out.extend([0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0]),
            }
        }
        let st = &sim.sim.state;
        let b = &sim.sim.system.model.bodies[sim.map.blocks[0].index().unwrap_or(0)];
        let (qo, vo) = (b.q_offset, b.v_offset);
        out.extend_from_slice(&st.q[qo..qo + 7]);
        out.extend_from_slice(&st.v[vo..vo + 6]);
        let e = sim.sim.energy();
        out.extend([
            e.kinetic,
            e.potential,
            e.dissipated + sim.slide_dissipation,
            e.input,
            sim.event_energy,
        ]);
        if let Some((normal, friction)) = sim.ground_forces() {
            out.extend([normal, friction]);
        }
        let weight = sim.total_mass() * self.params.gravity;
        let lift: f64 = -pull.iter().map(|p| p.z).sum::<f64>();
        out.push(if weight > 0.0 { lift / weight } else { 0.0 });
        let bonds = sim.hook_bonds();
        for (b, w) in bonds.iter().zip(&sim.bonds.work) {
            out.extend([
                b.force.x,
                b.force.y,
                b.power(),
                w[0],
                b.winch_force,
                b.winch_power(),
                w[1],
            ]);
        }
        out
    }

    /// One output by name.
    pub fn output(&mut self, name: &str) -> Option<f64> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(self.outputs()[i])
    }
}
