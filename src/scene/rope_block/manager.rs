//! The contact manager: runs after every accepted step and decides, for every contact node, from
//! the joint's Lagrange multipliers and the rope's tensions, whether the rope starts or stops
//! sliding through it, slides it along its edge, or leaves the edge; finds new crossings of rope
//! segments with plate edges; and asks for re-meshing when sliding has made a segment next to a
//! contact node too short or too long.
//!
//! Changes of the slip state are written into the rope effect's memory (the integrator restarts);
//! structural changes are returned as [`Edit`]s (the integrator stops, the scene rebuilds).

use super::build::{BuildMap, rope_ctx};
use super::structure::Structure;
use crate::dae::System;
use crate::integrator::{SolverError, StepAction, StepHook};
use crate::math::Vec3;
use crate::rope::cone::{EdgeFriction, NodeCone, ShareSearch, edge_friction};
use crate::rope::friction::{self, ContactFrame, FrictionLaw, Reaction};
use crate::rope::shell::detect::{clears_edge, segment_crossing};
use crate::rope::{NodeSegments, RopeEffect, SlipMode};
use crate::state::State;

/// Settings of contact detection and node management.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSettings {
    /// Detect new crossings and insert contact nodes (existing nodes are always managed).
    pub detect: bool,
    /// A segment must cut this far into an edge's wedge to count as crossing it [m].
    pub tolerance: f64,
    /// Deepest cut still taken as a crossing (the wedge test is local) [m].
    pub max_depth: f64,
    /// A material node next to a contact node is absorbed when the segment between them falls
    /// below this fraction of the nominal segment length [-].
    pub merge_below: f64,
    /// A segment next to a contact node is split when it grows beyond this multiple of the nominal
    /// segment length [-].
    pub split_above: f64,
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            detect: true,
            tolerance: 1e-6,
            max_depth: 0.5,
            merge_below: 0.25,
            split_above: 2.5,
        }
    }
}

/// A structural change of a rope. Positions are rope point indices: 0 is the start, `i + 1` is
/// interior node `i`, `n + 1` the end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Edit {
    /// Insert a contact node where segment `seg` (points `seg`, `seg + 1`) crosses plate edge
    /// `edge` of `block` at `point` [m, block frame].
    Insert {
        rope: usize,
        seg: usize,
        block: usize,
        edge: usize,
        point: Vec3,
    },
    /// Remove contact node `node` (interior index), returning its mass to its neighbours.
    Remove { rope: usize, node: usize },
    /// Absorb material node `node` into its neighbours (it reached a contact node).
    Merge { rope: usize, node: usize },
    /// Split segment `seg` at its middle with a new material node.
    Split { rope: usize, seg: usize },
}

/// Counts of what the manager did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    pub inserted: u64,
    /// Steps in which a node moved along its edge (friction exceeded).
    pub edge_slides: u64,
    pub removed: u64,
    pub merged: u64,
    pub split: u64,
    pub rebuilds: u64,
}

/// The step hook.
pub struct Manager<'a> {
    pub structure: &'a Structure,
    pub map: &'a BuildMap,
    pub settings: &'a ContactSettings,
    pub counters: &'a mut Counters,
    /// Energy [J] removed by friction slides along the edges so far (added to).
    pub slide_dissipation: &'a mut f64,
    pub edits: Vec<Edit>,
    scratch: Vec<usize>,
    /// Kinetic plus potential energy [J] before this step's first slide.
    energy_before_slides: Option<f64>,
    /// Scratch for the energy evaluations (mass times speeds).
    energy_scratch: Vec<f64>,
    /// Ask the integrator for control back after the first accepted step.
    pub one_step: bool,
    /// An accepted step was managed.
    stepped: bool,
}

impl<'a> Manager<'a> {
    /// A manager for the current build.
    pub fn new(
        structure: &'a Structure,
        map: &'a BuildMap,
        settings: &'a ContactSettings,
        counters: &'a mut Counters,
        slide_dissipation: &'a mut f64,
    ) -> Self {
        Manager {
            structure,
            map,
            settings,
            counters,
            slide_dissipation,
            edits: Vec::new(),
            scratch: Vec::new(),
            energy_before_slides: None,
            energy_scratch: Vec::new(),
            one_step: false,
            stepped: false,
        }
    }
}

/// Geometry and forces of one contact node at the end of a step.
#[derive(Debug, Clone, Copy)]
pub struct NodeReport {
    /// Contact slot of the rope effect.
    pub slot: usize,
    /// Rope and interior node index.
    pub rope: usize,
    pub node: usize,
    pub frame: ContactFrame,
    /// The force of the plate edge on the rope at the node [N], in `frame`, as the dynamics
    /// applies it: the normal force `N` and the friction along the rope `F_r` of the rope's pull
    /// ([`NodeReport::pull`]: what the plate supplies to the tensions either side) and the
    /// friction along the edge `F_e` of the hold ([`NodeReport::hold_force`]). This is the force
    /// the node's Coulomb cone is enforced on, so `|(F_e, F_r)| <= mu N`. It is not the line
    /// joint's multipliers: those also carry the node's lumped rope mass (its weight, 30.8 N
    /// across the edge in the default rig, and its inertia) and, from an index-3 integrator, are
    /// no physical reaction at a point in time.
    pub reaction: Reaction,
    /// Coefficient `mu` of the node's Coulomb cone [-] (0: friction off) and its slip state
    /// along the rope, from the memory the report was taken with.
    pub mu: f64,
    pub mode: SlipMode,
    pub segments: NodeSegments,
    /// Turning angle of the rope at the node [rad].
    pub turn: f64,
    /// Unit vectors from the node towards its previous and next rope points (world).
    pub e_prev: Vec3,
    pub e_next: Vec3,
    pub l_prev: f64,
    pub l_next: f64,
    /// Positions of the previous and next rope points [m], world.
    pub p_prev: Vec3,
    pub p_next: Vec3,
    /// Coordinate of the node along its edge [m] from the edge's first end, and its rate [m/s]
    /// (relative to the block).
    pub u: f64,
    pub u_dot: f64,
    /// Force of the hold along the edge on the node [N].
    pub hold_force: f64,
    /// The rope's pull on the node split in the contact frame: what the plate (joint and hold)
    /// must supply for a massless node (smooth in time, unlike the index-3 multipliers). The
    /// node's Coulomb cone ([`crate::rope::friction`]) takes its normal and along-rope parts with
    /// the hold's force along the edge (`hold_force`).
    pub pull: Reaction,
}

impl NodeReport {
    /// The slip flag a user reads: 0 while the node sticks along the rope or has no friction
    /// (`mu = 0`: the rope runs freely through it and its slip direction is noise), else the
    /// slip state's code (+1 forward, -1 backward).
    pub fn slip_code(&self) -> f64 {
        if self.mu > 0.0 { self.mode.code() } else { 0.0 }
    }
}

/// Evaluates every contact node of the current build at `state`.
pub fn node_reports(
    sys: &mut System,
    map: &BuildMap,
    s: &Structure,
    st: &State,
) -> Vec<NodeReport> {
    sys.update_kinematics(&st.q, &st.v);
    let ctx = rope_ctx(map, sys.kins(), &sys.inputs, st);
    let rope = &map.rope;
    let segs = rope.contact_segments(&ctx);
    let mut out = Vec::with_capacity(segs.len());
    for (c, &(r, i, _)) in map.contacts.iter().enumerate() {
        let pi = rope.contact_point(c);
        let (x, _) = rope.point_state(&ctx, pi);
        let (pp, _) = rope.point_state(&ctx, pi - 1);
        let (pn, _) = rope.point_state(&ctx, pi + 1);
        let Some(ct) = s.ropes[r].nodes[i].contact else {
            continue;
        };
        let kin = sys.kin(map.blocks[ct.block]);
        let Some(mesh) = s.blocks[ct.block].mesh.as_ref() else {
            continue;
        };
        let edge = &mesh.edges[ct.edge];
        let (l_prev, l_next) = ((pp - x).norm().max(1e-300), (pn - x).norm().max(1e-300));
        let (e_prev, e_next) = ((pp - x) / l_prev, (pn - x) / l_next);
        let plate_normal = kin.rot * edge.mean_normal();
        let frame = ContactFrame::new(&(kin.rot * edge.dir), &plate_normal, &e_prev, &e_next)
            .facing_plate(&plate_normal);
        let hold = rope.edge_hold(&ctx, c);
        let along = hold.map(|h| h.force).unwrap_or(0.0);
        let pull = friction::rope_pull(&frame, &e_prev, &e_next, segs[c].t_prev, segs[c].t_next);
        let (mode, _) = rope.contact_state(ctx.memory, c);
        let turn = std::f64::consts::PI - e_prev.dot(&e_next).clamp(-1.0, 1.0).acos();
        out.push(NodeReport {
            slot: c,
            rope: r,
            node: i,
            frame,
            reaction: Reaction {
                along_edge: along,
                ..pull
            },
            mu: rope.contact_mu(ctx.memory, c),
            mode,
            segments: segs[c],
            turn,
            e_prev,
            e_next,
            l_prev,
            l_next,
            p_prev: pp,
            p_next: pn,
            u: hold.map(|h| h.u).unwrap_or(0.0),
            u_dot: hold.map(|h| h.u_dot).unwrap_or(0.0),
            hold_force: along,
            pull,
        });
    }
    out
}

/// The cone settlement's view ([`NodeCone`]) of a reported node, with the rope's memory `mem`.
fn node_cone<'a>(rope: &RopeEffect, rep: &'a NodeReport, mem: &[f64]) -> NodeCone<'a> {
    NodeCone {
        mu: rope.contact_mu(mem, rep.slot),
        law: rope.friction_law(rep.slot),
        mode: rope.contact_state(mem, rep.slot).0,
        pull: &rep.pull,
        hold_force: rep.hold_force,
        frame: &rep.frame,
        e_prev: &rep.e_prev,
        e_next: &rep.e_next,
        turn: rep.turn,
        t_prev: rep.segments.t_prev,
        t_next: rep.segments.t_next,
    }
}

/// Most passes of the share settlement ([`Manager::settle_shares`]) after one step.
const SHARE_PASSES: usize = 12;

/// Relative tolerance of a settled share coefficient against its target.
const SHARE_TOL: f64 = 1e-11;

impl Manager<'_> {
    /// Kinetic plus potential energy [J] of the system at the state `st`.
    fn mechanical_energy(&mut self, sys: &mut System, st: &State) -> f64 {
        self.energy_scratch.resize(st.v.len(), 0.0);
        let (kinetic, potential) = sys.energy_with(st.t, &st.q, &st.v, &mut self.energy_scratch);
        kinetic + potential
    }

    /// Decides the slip state and structural changes of every contact node; returns whether the
    /// memory changed.
    fn manage_nodes(&mut self, sys: &mut System, st: &mut State) -> bool {
        let reports = node_reports(sys, self.map, self.structure, st);
        let rope = &self.map.rope;
        let base = self.map.rope_memory;
        let mut changed = false;
        for rep in &reports {
            let c = rep.slot;
            let spec = &self.structure.ropes[rep.rope];
            let Some(ct) = spec.nodes[rep.node].contact else {
                continue;
            };
            let mu = rope.memory(&st.memory[base..]).contact(c).mu();
            // the friction law works on the rope's pull (see NodeReport::pull)
            let n = rep.pull.normal;
            let mesh = self.structure.blocks[ct.block].mesh.as_ref();
            // leaving the edge: the plate would have to pull and the straight rope clears it
            if n < 0.0 {
                let kin = sys.kin(self.map.blocks[ct.block]);
                let to_local = |p: &Vec3| kin.rot.transpose() * (p - kin.r);
                if let Some(m) = mesh
                    && clears_edge(m, ct.edge, &to_local(&rep.p_prev), &to_local(&rep.p_next))
                {
                    self.edits.push(Edit::Remove {
                        rope: rep.rope,
                        node: rep.node,
                    });
                    continue;
                }
            }
            // friction along the edge: the node's Coulomb cone gives the edge's load way last
            // (friction::return_map), so the edge slides once its hold's force exceeds mu N, and
            // then moves with the dynamics against a constant friction force on the cone
            // (`cone::edge_friction`; its force is set on the cone again by `enforce_cone`)
            let seg = rep.segments;
            let slide = rope.memory(&st.memory[base..]).contact(c).edge_slide();
            if slide == 0.0 {
                // the capacity a sticking node would slide at: not used by any force while it
                // sticks, so no memory change; the system gets it too, so that the memory a
                // Newton matrix is recorded with is the state's (a restored state's system is
                // made from the state: without this, a restored run records other bytes)
                let cap = mu * n.max(0.0);
                rope.memory_mut(&mut st.memory[base..])
                    .contact_mut(c)
                    .set_cap(cap);
                if let Some(mut rec) = sys
                    .memory
                    .get_mut(base..)
                    .and_then(|m| rope.memory_mut(m).try_into_contact(c))
                {
                    rec.set_cap(cap);
                }
            }
            let decision =
                edge_friction(mu, n, rep.pull.along_rope, rep.hold_force, slide, rep.u_dot);
            let write = match decision {
                EdgeFriction::Stick => None,
                EdgeFriction::Slide(force) => {
                    self.counters.edge_slides += 1;
                    let sign = if slide != 0.0 { slide } else { force.signum() };
                    Some([
                        sign,
                        force.abs(),
                        rope.memory(&st.memory[base..]).contact(c).anchor(),
                    ])
                }
                EdgeFriction::Restick(force) => {
                    let ctx = rope_ctx(self.map, sys.kins(), &sys.inputs, st);
                    let anchor = rope.hold_anchor_for(&ctx, c, force);
                    let rec = rope.memory(&st.memory[base..]).contact(c);
                    Some([0.0, rec.cap(), anchor.unwrap_or(rec.anchor())])
                }
            };
            let stored = {
                let rec = rope.memory(&st.memory[base..]).contact(c);
                [rec.edge_slide(), rec.cap(), rec.anchor()]
            };
            if let Some([state, cap, anchor]) = write
                && stored != [state, cap, anchor]
            {
                if self.energy_before_slides.is_none() {
                    // the system still holds the step's memory and these positions
                    self.energy_before_slides = Some(self.mechanical_energy(sys, st));
                }
                let mut mem = rope.memory_mut(&mut st.memory[base..]);
                let mut rec = mem.contact_mut(c);
                rec.set_edge_slide(state);
                rec.set_cap(cap);
                rec.set_anchor(anchor);
                changed = true;
            }
            if let Some(m) = mesh
                && (rep.u < 0.0 || rep.u > m.edges[ct.edge].length)
            {
                self.edits.push(Edit::Remove {
                    rope: rep.rope,
                    node: rep.node,
                });
                continue;
            }
            // re-meshing around the node
            let nominal = spec.nominal_segment;
            let nn = spec.nodes.len();
            let material = |k: usize| k < nn && spec.nodes[k].contact.is_none();
            if seg.rest_prev < self.settings.merge_below * nominal
                && rep.node > 0
                && material(rep.node - 1)
            {
                self.edits.push(Edit::Merge {
                    rope: rep.rope,
                    node: rep.node - 1,
                });
            } else if seg.rest_next < self.settings.merge_below * nominal && material(rep.node + 1)
            {
                self.edits.push(Edit::Merge {
                    rope: rep.rope,
                    node: rep.node + 1,
                });
            } else if seg.rest_prev > self.settings.split_above * nominal {
                self.edits.push(Edit::Split {
                    rope: rep.rope,
                    seg: rep.node,
                });
            } else if seg.rest_next > self.settings.split_above * nominal {
                self.edits.push(Edit::Split {
                    rope: rep.rope,
                    seg: rep.node + 1,
                });
            }
        }
        if changed {
            // the slides moved nodes: the rope's stick/slip decisions of the step belong to the
            // state before them, so they are taken again at the moved state (the return mapping
            // from the accepted memory), and the reports show the forces that act from there
            let State {
                t, q, v, memory, ..
            } = st;
            sys.update_memory(*t, q, v, memory);
        }
        self.enforce_cone(sys, st) || changed
    }

    /// The node's Coulomb cone at the state the step and the slides left
    /// ([`friction::return_map`]): the rope sliding through a node gets the share the edge's
    /// load leaves ([`friction::rope_share`] as the sharp-edge coefficient of
    /// [`friction::plane_coefficients`] at this geometry; a few passes, since `N` moves with the
    /// share), then every hold whose force exceeds what the cone leaves along the edge
    /// ([`friction::edge_capacity`] of the rope's pull) gets the anchor that makes its force that
    /// capacity. So `|(F_e, F_r)| <= mu N` holds at the accepted state, with equality (within
    /// the slide band) where the rope slides. Returns whether the memory changed.
    fn enforce_cone(&mut self, sys: &mut System, st: &mut State) -> bool {
        let mut changed = self.redecide_sticking(sys, st);
        // a share that changes, or a node set sliding, changes the tensions of the chains around
        // it, which can push a neighbour that sticks out of its cone (4.4e-9 relative on the
        // 64-edge drum, tests/rope/capstan.rs): decided again until no sticking node is outside
        for pass in 0..4 {
            changed |= self.settle_shares(sys, st, true);
            if pass == 3 || !self.slide_outside_sticking(sys, st) {
                break;
            }
            changed = true;
        }
        changed |= self.clip_holds(sys, st);
        if self
            .structure
            .ropes
            .iter()
            .any(|r| r.props.friction_law == FrictionLaw::PseudoCoefficient)
        {
            // the radial law cuts holds by far more than the edge-first one (every hold of a
            // node outside its cone), and a hold's force is set through its anchor, whose
            // round-off (stiffness times the coordinate's last bit: a few 1e-6 N on the lift's
            // 1e9 N/m holds, 2e-9 of its friction) leaves the node off the cone: the rope's
            // share closes that residual (as under edge first: the rope takes what the edge
            // leaves), a share being set to 1e-11
            changed |= self.settle_shares(sys, st, false);
        }
        changed
    }

    /// Gives every node the rope slides through with friction outside its cone, or below it by
    /// more than [`crate::rope::cone::SLIDE_BAND`], the share its edge load and geometry leave:
    /// `N` moves with the share, so each such node searches its fixed point ([`ShareSearch`])
    /// over a few passes, until its share is its target to [`SHARE_TOL`]. With `radial`, a node
    /// under the pseudo friction coefficient that is outside its cone gets instead the rope's
    /// part of the radially scaled force ([`NodeCone::radial_fraction`], its direction taken at
    /// the first pass; its hold is cut to the rest by [`Self::clip_holds`]). Returns whether the
    /// memory changed.
    fn settle_shares(&mut self, sys: &mut System, st: &mut State, radial: bool) -> bool {
        let mut changed = false;
        let rope = &self.map.rope;
        let base = self.map.rope_memory;
        // the fixed-point searches of the nodes being settled, by contact slot
        let mut searches: Vec<Option<ShareSearch>> = Vec::new();
        // under the pseudo friction coefficient, the rope's part of the trial's direction, taken
        // at the first pass that finds the node outside its cone and kept through the passes
        // (the radial scaling keeps the trial's direction; taken again at the settled share, the
        // direction would drift to the edge-first split)
        let mut fractions: Vec<Option<f64>> = Vec::new();
        for _ in 0..SHARE_PASSES {
            let reports = node_reports(sys, self.map, self.structure, st);
            let slots = reports.iter().map(|r| r.slot + 1).max().unwrap_or(0);
            searches.resize(searches.len().max(slots), None);
            fractions.resize(searches.len(), None);
            let mut shares = Vec::new();
            for rep in &reports {
                let share = rope.memory(&st.memory[base..]).contact(rep.slot).share();
                let node = node_cone(rope, rep, &st.memory[base..]);
                let search = &mut searches[rep.slot];
                let fraction = &mut fractions[rep.slot];
                if radial && search.is_none() && fraction.is_none() {
                    *fraction = node.radial_fraction();
                } else if fraction.is_some() && node.below() {
                    // `N` grew with the share until the trial lies inside the cone there: no
                    // scaling is left to do, the rope takes what the edge's load leaves (as
                    // for any sliding node below its cone), searched afresh
                    *fraction = None;
                    *search = None;
                }
                let target = match (*fraction, &search) {
                    (Some(f), _) => node.radial_target(f),
                    (None, Some(_)) => node.share_target(),
                    (None, None) => node.settled_share(),
                };
                let Some(g) = target else {
                    continue;
                };
                // the target's own round-off is about 2e-13 relative
                if (g - share).abs() <= SHARE_TOL * share.max(1e-3) {
                    continue;
                }
                let next = search.get_or_insert_default().next(share, g);
                shares.push((rep.slot, next));
            }
            if shares.is_empty() {
                break;
            }
            if self.energy_before_slides.is_none() {
                self.energy_before_slides = Some(self.mechanical_energy(sys, st));
            }
            let mut mem = rope.memory_mut(&mut st.memory[base..]);
            for (slot, c) in shares {
                mem.contact_mut(slot).set_share(c);
            }
            changed = true;
        }
        changed
    }

    /// Cuts every hold whose force exceeds what the cone leaves along the edge to that capacity
    /// (at sliding nodes, and wherever the edge load alone exceeds `mu N`). Returns whether the
    /// memory changed.
    fn clip_holds(&mut self, sys: &mut System, st: &mut State) -> bool {
        let rope = &self.map.rope;
        let base = self.map.rope_memory;
        let reports = node_reports(sys, self.map, self.structure, st);
        let ctx = rope_ctx(self.map, sys.kins(), &sys.inputs, st);
        let mut anchors = Vec::new();
        let mut caps = Vec::new();
        for rep in &reports {
            let c = rep.slot;
            let rec = rope.memory(ctx.memory).contact(c);
            if rec.edge_slide() != 0.0 {
                // sliding along the edge: friction on the cone, what it leaves along the edge;
                // the anchor follows (a spring carrying that force here), which a rebuild takes
                let cap = friction::edge_capacity(rep.mu, rep.pull.normal, rep.pull.along_rope);
                let force = rec.edge_slide().signum() * cap;
                if let Some(u0) = rope.hold_anchor_for(&ctx, c, force)
                    && rec.anchor() != u0
                {
                    anchors.push((c, u0));
                }
                if rec.cap() != cap {
                    caps.push((c, cap));
                }
                continue;
            }
            if let Some(force) = node_cone(rope, rep, ctx.memory).clipped_hold()
                && let Some(u0) = rope.hold_anchor_for(&ctx, c, force)
            {
                anchors.push((c, u0));
            }
        }
        if anchors.is_empty() && caps.is_empty() {
            return false;
        }
        if self.energy_before_slides.is_none() {
            self.energy_before_slides = Some(self.mechanical_energy(sys, st));
        }
        let mut mem = rope.memory_mut(&mut st.memory[base..]);
        for (c, u0) in anchors {
            mem.contact_mut(c).set_anchor(u0);
        }
        for (c, cap) in caps {
            mem.contact_mut(c).set_cap(cap);
        }
        true
    }

    /// A node the step kept sticking along the rope can sit outside its cone at the accepted
    /// state: the step was solved on frozen decisions, accepted when the return mapping's
    /// material coordinates agree with them to the position tolerance, and near the band's edge
    /// (heavy rope damping, turns under a degree) that leaves friction well above `mu N` (0.167
    /// against 0.15 in the default lift). Where a sticking node's friction leaves the cone the
    /// accepted state is decided again by the return mapping (the memory update without frozen
    /// decisions, warm-started from the step's): the rope slides through the node with its
    /// share. Returns whether the memory changed.
    fn redecide_sticking(&mut self, sys: &mut System, st: &mut State) -> bool {
        let reports = node_reports(sys, self.map, self.structure, st);
        let rope = &self.map.rope;
        let mem = &st.memory[self.map.rope_memory..];
        let outside = reports
            .iter()
            .any(|rep| node_cone(rope, rep, mem).sticks_outside());
        if !outside {
            return false;
        }
        if self.energy_before_slides.is_none() {
            self.energy_before_slides = Some(self.mechanical_energy(sys, st));
        }
        let State {
            t, q, v, memory, ..
        } = st;
        sys.update_memory(*t, q, v, memory);
        self.slide_outside_sticking(sys, st);
        true
    }

    /// Sets every node still sticking outside its cone sliding, in passes until none is left
    /// (at most eight): the tensions include the Kelvin-Voigt damping of the node's material
    /// segments, a sliding chain has none (see `rope::slip`), and on the elastic tensions alone
    /// the slide would run against its friction, so the return mapping goes back to sticking.
    /// The node is then set sliding towards the larger tension with its share and the material
    /// coordinate that branch solves: friction on the cone, the damping of those two segments
    /// dropped (booked as slide dissipation). A node set sliding changes the tensions of the
    /// chain it joins, which can push a sticking neighbour out of its cone (4.4e-9 relative on
    /// the 64-edge drum of tests/rope/capstan.rs), hence the passes. Returns whether the memory
    /// changed.
    fn slide_outside_sticking(&mut self, sys: &mut System, st: &mut State) -> bool {
        let mut changed = false;
        for _ in 0..8 {
            if !self.slide_outside_pass(sys, st) {
                break;
            }
            changed = true;
        }
        changed
    }

    /// One pass of [`Self::slide_outside_sticking`].
    fn slide_outside_pass(&mut self, sys: &mut System, st: &mut State) -> bool {
        let rope = &self.map.rope;
        let base = self.map.rope_memory;
        let mut slid = Vec::new();
        for rep in node_reports(sys, self.map, self.structure, st) {
            if let Some((mode, c)) = node_cone(rope, &rep, &st.memory[base..]).slide_out() {
                slid.push((rep.slot, mode, c));
            }
        }
        if slid.is_empty() {
            return false;
        }
        if self.energy_before_slides.is_none() {
            self.energy_before_slides = Some(self.mechanical_energy(sys, st));
        }
        let mut mem = rope.memory_mut(&mut st.memory[base..]);
        for &(slot, mode, c) in &slid {
            let mut rec = mem.contact_mut(slot);
            rec.set_mode(mode);
            rec.set_share(c);
        }
        let reports = node_reports(sys, self.map, self.structure, st);
        let mut mem = rope.memory_mut(&mut st.memory[base..]);
        for &(slot, _, _) in &slid {
            if let Some(rep) = reports.iter().find(|r| r.slot == slot) {
                mem.contact_mut(slot).set_sigma(rep.segments.sigma);
            }
        }
        sys.memory.copy_from_slice(&st.memory);
        true
    }

    /// The node cones at a state no step has managed (just rebuilt): [`Manager::enforce_cone`],
    /// with the system's memory updated and the energy it removes booked as slide dissipation.
    /// Returns whether the memory changed (the caller restarts the integrator).
    pub fn settle_cone(&mut self, sys: &mut System, st: &mut State) -> bool {
        let changed = self.enforce_cone(sys, st);
        if changed {
            sys.memory.copy_from_slice(&st.memory);
        }
        if let Some(before) = self.energy_before_slides.take() {
            *self.slide_dissipation += before - self.mechanical_energy(sys, st);
        }
        changed
    }

    /// Finds segments newly crossing plate edges.
    fn detect(&mut self, sys: &mut System, st: &State) {
        let s = self.structure;
        if !s.blocks.iter().any(|b| b.mesh.is_some()) {
            return;
        }
        sys.update_kinematics(&st.q, &st.v);
        let ctx = rope_ctx(self.map, sys.kins(), &sys.inputs, st);
        let rope = &self.map.rope;
        for (r, spec) in s.ropes.iter().enumerate() {
            let (first, end) = rope.rope_ranges()[r];
            for i in first..end - 1 {
                let (p, _) = rope.point_state(&ctx, i);
                let (q, _) = rope.point_state(&ctx, i + 1);
                for (b, blk) in s.blocks.iter().enumerate() {
                    let Some(mesh) = blk.mesh.as_ref() else {
                        continue;
                    };
                    let mut skip = [usize::MAX; 2];
                    for (k, node) in [i - first, i + 1 - first].into_iter().enumerate() {
                        if node >= 1
                            && node <= spec.nodes.len()
                            && let Some(c) = spec.nodes[node - 1].contact
                            && c.block == b
                        {
                            skip[k] = c.edge;
                        }
                    }
                    let kin = sys.kin(self.map.blocks[b]);
                    let pl = kin.rot.transpose() * (p - kin.r);
                    let ql = kin.rot.transpose() * (q - kin.r);
                    if let Some(c) = segment_crossing(
                        mesh,
                        &pl,
                        &ql,
                        &skip,
                        self.settings.tolerance,
                        self.settings.max_depth,
                        &mut self.scratch,
                    ) {
                        self.edits.push(Edit::Insert {
                            rope: r,
                            seg: i - first,
                            block: b,
                            edge: c.edge,
                            point: c.point,
                        });
                        break;
                    }
                }
            }
        }
    }
}

impl StepHook for Manager<'_> {
    fn pause(&self) -> bool {
        self.one_step && self.stepped
    }

    fn after_step(&mut self, sys: &mut System, st: &mut State) -> Result<StepAction, SolverError> {
        self.stepped = true;
        let changed = if self.map.contacts.is_empty() {
            false
        } else {
            self.manage_nodes(sys, st)
        };
        if changed {
            sys.memory.copy_from_slice(&st.memory);
        }
        if let Some(before) = self.energy_before_slides.take() {
            // a slide jumps the node (and its anchor) to the friction limit: the energy the
            // jump removes is what friction (and the skipped slip motion) dissipated
            *self.slide_dissipation += before - self.mechanical_energy(sys, st);
        }
        if self.settings.detect {
            self.detect(sys, st);
        }
        if !self.edits.is_empty() {
            return Ok(StepAction::Stop);
        }
        // Slip-state switches happen where the two laws agree (the friction limit) and a node
        // moves along its edge by micrometres to millimetres per step: the integrator goes on
        // without a restart (a restart per switch would cost a factorization each); the system
        // took the changed memory above, and a slide's move is one multistep integrators carry
        // into their history.
        Ok(if changed {
            StepAction::Moved
        } else {
            StepAction::Continue
        })
    }
}
