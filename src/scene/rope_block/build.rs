//! Assembles a multibody [`Model`] from a [`Structure`], and carries a running state back into
//! the structure.
//!
//! Body order: blocks, loads, then every rope's interior nodes in rope order. Joints: one
//! spherical joint per contact node (block edge point to node particle: the paper's fixed joint
//! for a point mass, three Lagrange multipliers), then one fixed joint per welded block. Force
//! effects: gravity, constant applied forces, and the one rope effect.

use super::structure::{BodyRef, EndSpec, Structure};
use crate::effect::{EvalCtx, ForceEffect};
use crate::math::Vec3;
use crate::model::kinematics::{BodyKin, evaluate, quat_at};
use crate::model::{AppliedLoad, BodyId, BodyInit, Frame, JointKind, Model, ModelBuilder, Profile};
use crate::rope::{ContactInit, LayoutPoint, LayoutRope, PointAt, RopeEffect, SlipMode};
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
            ids.push(id);
            let contact = n.contact.map(|c| {
                contacts.push((r, i));
                joints.push((blocks[c.block], c.anchor, id));
                ContactInit {
                    mode: c.mode,
                    mu_rope: c.mu_rope,
                    anchor: c.anchor,
                }
            });
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
    // contact joints read their anchor from the rope effect's memory (index patched below)
    let mut contact_map = Vec::new();
    for (k, ((blk, anchor, id), (r, i))) in joints.iter().zip(&contacts).enumerate() {
        b.add_joint(
            &format!("{}.contact{k}", s.ropes[*r].name),
            JointKind::SphericalAt { memory: 0 },
            Frame::new(*blk, *anchor),
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
    let rope = Arc::new(RopeEffect::new(&layouts, &s.hooks)?);
    b.add_force_effect(rope.clone());
    let mut model = b.build()?;
    let rope_effect = model.forces.len() - 1;
    let rope_memory: usize = model.forces[..rope_effect]
        .iter()
        .map(|e| e.n_memory())
        .sum();
    for (c, &(_, _, j)) in contact_map.iter().enumerate() {
        model.joints[j].kind = JointKind::SphericalAt {
            memory: rope_memory + rope.contact_memory_offset(c) + 3,
        };
    }
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
        let (x, v) = map.rope.hook_motion(mem, k, state.t);
        let (p, rate) = map.rope.hook_payout(mem, k, state.t);
        h.position = x;
        h.velocity = v;
        h.t0 = state.t;
        h.payout = p;
        h.payout_rate = rate;
    }
    for (r, rope) in s.ropes.iter_mut().enumerate() {
        for (n, id) in rope.nodes.iter_mut().zip(&map.nodes[r]) {
            let k = &kins[id.index().unwrap_or(0)];
            n.position = k.r;
            n.velocity = k.v;
        }
    }
    for (c, &(r, i, _)) in map.contacts.iter().enumerate() {
        let o = map.rope.contact_memory_offset(c);
        let n = &mut s.ropes[r].nodes[i];
        n.sigma = mem[o];
        if let Some(ct) = n.contact.as_mut() {
            ct.mode = SlipMode::from_code(mem[o + 1]);
            ct.mu_rope = mem[o + 2];
            ct.anchor = Vec3::new(mem[o + 3], mem[o + 4], mem[o + 5]);
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
    }
}
