//! Assembles a multibody [`Model`] from a [`Structure`], and carries a running state back into
//! the structure.
//!
//! Body order: blocks, loads, then every rope's interior nodes in rope order. Joints: one
//! point-on-line joint per contact node (the node on its plate edge's line, two Lagrange
//! multipliers: the paper's fixed joint across the edge, while along the edge the rope effect's
//! elastic-plastic friction element holds it), then one fixed joint per welded block. Force
//! effects: gravity, constant applied forces, the test rigs' dampers, the block-ground contact when the scene has a
//! ground, and the one rope effect (last).

use super::structure::{BodyRef, EndSpec, Structure};
use crate::effect::ground_contact::GroundContact;
use crate::effect::plane_contact::PlaneContact;
use crate::effect::{EvalCtx, ForceEffect};
use crate::math::Vec3;
use crate::model::kinematics::{BodyKin, evaluate, quat_at};
use crate::model::{AppliedLoad, BodyId, BodyInit, Frame, JointKind, Model, ModelBuilder, Profile};
use crate::rope::{ContactInit, EdgeHold, LayoutPoint, LayoutRope, PointAt, RopeEffect};
use crate::state::State;
use std::sync::Arc;

/// Where the structure's items ended up in the model.
#[derive(Debug, Clone)]
pub struct BuildMap {
    pub blocks: Vec<BodyId>,
    pub loads: Vec<BodyId>,
    /// Body of each interior node, per rope.
    pub nodes: Vec<Vec<BodyId>>,
    /// For each contact slot of the rope effect: (rope, node index within the rope, joint index).
    pub contacts: Vec<(usize, usize, usize)>,
    /// Index of the rope effect in `model.forces` and the offset of its memory in the state.
    pub rope_effect: usize,
    pub rope_memory: usize,
    /// The rope effect (shared with the model).
    pub rope: Arc<RopeEffect>,
    /// The block-ground contact effect (shared with the model), when assembled.
    pub ground: Option<Arc<GroundContact>>,
}

impl BuildMap {
    /// Body of a scene body reference.
    pub fn body(&self, b: BodyRef) -> BodyId {
        match b {
            BodyRef::Block(i) => self.blocks[i],
            BodyRef::Load(i) => self.loads[i],
        }
    }
}

fn end_point(map_blocks: &[BodyId], map_loads: &[BodyId], e: &EndSpec) -> PointAt {
    match *e {
        EndSpec::Hook(k) => PointAt::Hook(k),
        EndSpec::Block { block, local } => PointAt::Body {
            body: map_blocks[block],
            local,
        },
        EndSpec::Load(k) => PointAt::Body {
            body: map_loads[k],
            local: Vec3::zeros(),
        },
    }
}

/// Builds the model of `s`.
pub fn build(s: &Structure) -> Result<(Model, BuildMap), String> {
    s.validate()?;
    let mut b = ModelBuilder::new();
    b.set_gravity(s.gravity)?;
    let mut blocks = Vec::new();
    for blk in &s.blocks {
        let init = BodyInit::at(blk.position)
            .oriented(blk.orientation)
            .moving(blk.velocity, blk.omega);
        blocks.push(b.add_rigid_body(&blk.name, blk.mass, blk.inertia, init)?);
    }
    let mut loads = Vec::new();
    for l in &s.loads {
        loads.push(b.add_particle(&l.name, l.mass, l.position, l.velocity)?);
    }
    let mut nodes = Vec::new();
    let mut layouts = Vec::new();
    let mut contacts = Vec::new();
    let mut joints = Vec::new();
    for (r, rope) in s.ropes.iter().enumerate() {
        let mut ids = Vec::with_capacity(rope.nodes.len());
        let mut pts = Vec::with_capacity(rope.nodes.len() + 2);
        pts.push(LayoutPoint {
            at: end_point(&blocks, &loads, &rope.start),
            sigma: rope.sigma_start,
            contact: None,
        });
        for (i, n) in rope.nodes.iter().enumerate() {
            let id = b.add_particle(
                &format!("{}.n{i}", rope.name),
                n.mass,
                n.position,
                n.velocity,
            )?;
            // accuracy at the scale of the rope's resolution: a loaded segment's whole stretch
            // is a fraction of a percent of its length
            b.set_body_length_scale(id, rope.nominal_segment)?;
            ids.push(id);
            let contact = match n.contact {
                Some(c) => {
                    let mesh = s.blocks[c.block].mesh.as_ref().ok_or_else(|| {
                        format!("rope '{}': contact on a block without mesh", rope.name)
                    })?;
                    let edge = mesh.edges[c.edge];
                    contacts.push((r, i));
                    joints.push((blocks[c.block], edge.a, edge.dir, id));
                    Some(ContactInit {
                        mode: c.mode,
                        mu: rope.props.friction,
                        mu_rope: c.mu_rope.min(rope.props.friction),
                        hold: Some(EdgeHold {
                            block: blocks[c.block],
                            point: edge.a,
                            dir: edge.dir,
                            u0: (c.anchor - edge.a).dot(&edge.dir),
                            cap: c.cap,
                        }),
                    })
                }
                None => None,
            };
            pts.push(LayoutPoint {
                at: PointAt::Body {
                    body: id,
                    local: Vec3::zeros(),
                },
                sigma: n.sigma,
                contact,
            });
        }
        pts.push(LayoutPoint {
            at: end_point(&blocks, &loads, &rope.end),
            sigma: rope.sigma_end,
            contact: None,
        });
        nodes.push(ids);
        layouts.push(LayoutRope {
            props: rope.props,
            nominal_segment: rope.nominal_segment,
            points: pts,
        });
    }
    // contact nodes: held on their edge line by two multipliers (friction along the edge is an
    // elastic-plastic element of the rope effect)
    let mut contact_map = Vec::new();
    for (k, ((blk, a, dir, id), (r, i))) in joints.iter().zip(&contacts).enumerate() {
        b.add_joint(
            &format!("{}.contact{k}", s.ropes[*r].name),
            JointKind::PointOnLine,
            Frame::with_z(*blk, *a, *dir),
            Frame::new(*id, Vec3::zeros()),
        )?;
        contact_map.push((*r, *i, k));
    }
    for (i, blk) in s.blocks.iter().enumerate() {
        if blk.fixed {
            let rot = blk.orientation.to_rotation_matrix().into_inner();
            b.add_joint(
                &format!("{}.weld", blk.name),
                JointKind::Fixed,
                Frame::new(BodyId::GROUND, blk.position).with_axes(
                    rot.column(0).into(),
                    rot.column(1).into(),
                    rot.column(2).into(),
                ),
                Frame::new(blocks[i], Vec3::zeros()),
            )?;
        }
    }
    for (k, f) in s.forces.iter().enumerate() {
        let body = match f.body {
            BodyRef::Block(i) => blocks[i],
            BodyRef::Load(i) => loads[i],
        };
        b.add_applied_load(AppliedLoad {
            name: format!("force{k}"),
            at: Frame::new(body, f.local),
            force_direction: f.direction,
            force: f.magnitude,
            torque_direction: Vec3::zeros(),
            torque: Profile::constant(0.0),
        })?;
    }
    if !s.dampers.is_empty() {
        b.add_force_effect(Arc::new(super::rig_dampers::RigDampers::new(
            s, &loads, &nodes,
        )));
    }
    // blocks and loads: the shortest nominal segment, since their positions set the stretch of
    // the end segments
    if let Some(l) = s
        .ropes
        .iter()
        .map(|r| r.nominal_segment)
        .filter(|l| l.is_finite() && *l > 0.0)
        .reduce(f64::min)
    {
        b.set_length_scale(l)?;
    }
    let ground = s.ground.as_ref().map(|g| {
        let contacts = g
            .points
            .iter()
            .enumerate()
            .map(|(k, &(blk, p))| PlaneContact {
                name: format!("ground{k}"),
                point: Frame::new(blocks[blk], p),
                normal: Vec3::z(),
                offset: g.height,
                law: g.law,
            })
            .collect();
        let contact = Arc::new(GroundContact {
            contacts,
            mu: g.mu,
            slip_speed: g.slip_speed,
        });
        b.add_force_effect(contact.clone());
        contact
    });
    let rope = Arc::new(RopeEffect::new(&layouts, &s.hooks)?);
    b.add_force_effect(rope.clone());
    let model = b.build()?;
    let rope_effect = model.forces.len() - 1;
    let rope_memory: usize = model.forces[..rope_effect]
        .iter()
        .map(|e| e.n_memory())
        .sum();
    Ok((
        model,
        BuildMap {
            blocks,
            loads,
            nodes,
            contacts: contact_map,
            rope_effect,
            rope_memory,
            rope,
            ground,
        },
    ))
}

/// Copies positions, velocities, hook motion and contact memory of `state` (of the model built
/// with `map`) into `s`.
pub fn sync(s: &mut Structure, model: &Model, map: &BuildMap, state: &State) {
    let mut kins: Vec<BodyKin> = Vec::new();
    evaluate(model, &state.q, &state.v, &mut kins);
    for (blk, id) in s.blocks.iter_mut().zip(&map.blocks) {
        let i = id.index().unwrap_or(0);
        let k = &kins[i];
        blk.position = k.r;
        blk.velocity = k.v;
        blk.omega = k.omega;
        blk.orientation = quat_at(&state.q, model.bodies[i].q_offset + 3);
    }
    for (l, id) in s.loads.iter_mut().zip(&map.loads) {
        let k = &kins[id.index().unwrap_or(0)];
        l.position = k.r;
        l.velocity = k.v;
    }
    let mem = &state.memory[map.rope_memory..map.rope_memory + map.rope.n_memory()];
    for (k, h) in s.hooks.iter_mut().enumerate() {
        let (t0, ramp) = {
            let rec = map.rope.memory(mem).hook(k);
            (rec.t0(), rec.ramp())
        };
        let (x, v) = map.rope.hook_motion(mem, k, state.t);
        let (p, rate) = map.rope.hook_payout(mem, k, state.t);
        let (v1, r1) = map.rope.hook_targets(mem, k);
        let (mode, x1) = map.rope.hook_position_target(mem, k);
        h.mode = mode;
        h.target_position = x1;
        h.position = x;
        h.velocity = v;
        h.target_velocity = v1;
        h.t0 = state.t;
        h.payout = p;
        h.payout_rate = rate;
        h.target_payout_rate = r1;
        // the rest of the ramp continues on the same line (a cubic move on the same cubic: it is
        // fixed by its end values and rates)
        h.ramp = (ramp - (state.t - t0)).max(0.0);
    }
    for (r, rope) in s.ropes.iter_mut().enumerate() {
        for (n, id) in rope.nodes.iter_mut().zip(&map.nodes[r]) {
            let k = &kins[id.index().unwrap_or(0)];
            n.position = k.r;
            n.velocity = k.v;
        }
    }
    for (c, &(r, i, _)) in map.contacts.iter().enumerate() {
        let rec = map.rope.memory(mem).contact(c);
        let n = &mut s.ropes[r].nodes[i];
        n.sigma = rec.sigma();
        if let (Some(ct), Some(h)) = (n.contact.as_mut(), map.rope.contact_edge(c)) {
            ct.mode = rec.mode();
            ct.mu_rope = rec.share();
            ct.anchor = h.point + h.dir * rec.anchor();
            ct.cap = rec.cap();
        }
    }
}

/// The effect context of the rope effect at `state` (kinematics must be evaluated into `kins`).
pub fn rope_ctx<'a>(
    map: &BuildMap,
    kins: &'a [BodyKin],
    inputs: &'a [f64],
    state: &'a State,
) -> EvalCtx<'a> {
    EvalCtx {
        t: state.t,
        kins,
        inputs,
        memory: &state.memory[map.rope_memory..map.rope_memory + map.rope.n_memory()],
        frozen: &[],
    }
}
