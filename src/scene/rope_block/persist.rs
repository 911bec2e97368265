//! A running [`RopeBlockSim`] as pointer-free bytes, and an exact copy of one.
//!
//! The number of contact nodes (and so of bodies, joints and state entries) changes during a run,
//! so the bytes carry the whole [`Structure`] of the current build (every rope node with its
//! contact, the hooks), then the state, the integrator history, the contact-manager counters and
//! the event energy. Restoring rebuilds the model from that structure (the same deterministic
//! [`build`] that produced the running model), creates the simulation at the state's time and
//! restores state and integrator history into it, so the run continues bit for bit.
//!
//! What is not in the bytes comes from the parameters: the shell mesh (regenerated, or read again
//! from the mesh file), the integrator settings and the contact-manager settings.

use super::bonds::BondBooks;
use super::build::build;
use super::params::RopeBlockParams;
use super::runner::{RopeBlockSim, run_settings};
use super::scene::solver_settings;
use super::structure::{BlockSpec, EndSpec, LoadSpec, NodeContact, NodeSpec, RopeSpec, Structure};
use crate::math::{Mat3, Quat, Vec3};
use crate::rope::{HOOK_MEM, HookInit, HookMode, RopeProps, SlipMode};
use crate::scene::ModelError;
use crate::scene::bytes::{ByteReader, ByteWriter};
use crate::sim::Simulation;
use nalgebra::Quaternion;
use std::sync::Arc;

fn bad(msg: impl Into<String>) -> ModelError {
    ModelError::BadState(msg.into())
}

fn vec3(w: &mut ByteWriter, v: &Vec3) {
    w.f64s(v.as_slice());
}

fn read_vec3(r: &mut ByteReader<'_>, what: &str) -> Result<Vec3, ModelError> {
    let v = r.f64s_exact(3, what)?;
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// A count no larger than the bytes left (each item takes at least one byte).
fn count(r: &mut ByteReader<'_>, what: &str) -> Result<usize, ModelError> {
    let n = r.u64(what)?;
    if n > r.remaining() as u64 {
        return Err(bad(format!(
            "serialized RopeBlock state: {what} {n} exceeds the bytes left"
        )));
    }
    Ok(n as usize)
}

fn write_props(w: &mut ByteWriter, p: &RopeProps) {
    w.f64s(&[
        p.mass_per_length,
        p.ea,
        p.axial_damping,
        p.bending_stiffness,
        p.diameter,
        p.drag_coefficient,
        p.fluid_density,
        p.friction,
        p.breaking_load,
    ]);
}

fn read_props(r: &mut ByteReader<'_>) -> Result<RopeProps, ModelError> {
    let v = r.f64s_exact(9, "rope properties")?;
    Ok(RopeProps {
        mass_per_length: v[0],
        ea: v[1],
        axial_damping: v[2],
        bending_stiffness: v[3],
        diameter: v[4],
        drag_coefficient: v[5],
        fluid_density: v[6],
        friction: v[7],
        breaking_load: v[8],
        // a choice of the parameters, not in the bytes (`read_sim` sets it)
        friction_law: Default::default(),
    })
}

fn write_end(w: &mut ByteWriter, e: &EndSpec) {
    match *e {
        EndSpec::Hook(k) => {
            w.u8(0);
            w.u64(k as u64);
        }
        EndSpec::Block { block, local } => {
            w.u8(1);
            w.u64(block as u64);
            vec3(w, &local);
        }
        EndSpec::Load(k) => {
            w.u8(2);
            w.u64(k as u64);
        }
    }
}

fn read_end(r: &mut ByteReader<'_>) -> Result<EndSpec, ModelError> {
    let tag = r.u8("rope end kind")?;
    let index = r.u64("rope end index")? as usize;
    Ok(match tag {
        0 => EndSpec::Hook(index),
        1 => EndSpec::Block {
            block: index,
            local: read_vec3(r, "lug point")?,
        },
        2 => EndSpec::Load(index),
        t => return Err(bad(format!("unknown rope end kind {t}"))),
    })
}

fn write_node(w: &mut ByteWriter, n: &NodeSpec) {
    w.f64(n.mass);
    w.f64(n.sigma);
    vec3(w, &n.position);
    vec3(w, &n.velocity);
    w.bool(n.contact.is_some());
    if let Some(c) = n.contact {
        w.u64(c.block as u64);
        w.u64(c.edge as u64);
        vec3(w, &c.anchor);
        w.f64(c.mode.code());
        w.f64(c.mu_rope);
        w.f64(c.cap);
    }
}

fn read_node(r: &mut ByteReader<'_>) -> Result<NodeSpec, ModelError> {
    let mass = r.f64("node mass")?;
    let sigma = r.f64("node material coordinate")?;
    let position = read_vec3(r, "node position")?;
    let velocity = read_vec3(r, "node velocity")?;
    let contact = if r.bool("node contact flag")? {
        Some(NodeContact {
            block: r.u64("contact block")? as usize,
            edge: r.u64("contact edge")? as usize,
            anchor: read_vec3(r, "contact anchor")?,
            mode: SlipMode::from_code(r.f64("contact slip mode")?),
            mu_rope: r.f64("contact friction share")?,
            cap: r.f64("contact edge capacity")?,
        })
    } else {
        None
    };
    Ok(NodeSpec {
        mass,
        sigma,
        position,
        velocity,
        contact,
    })
}

fn write_hook(w: &mut ByteWriter, h: &HookInit) {
    vec3(w, &h.position);
    vec3(w, &h.velocity);
    vec3(w, &h.target_velocity);
    w.f64s(&[h.t0, h.payout, h.payout_rate, h.target_payout_rate, h.ramp]);
    w.f64(h.mode.code());
    vec3(w, &h.target_position);
}

/// Reads a hook; state formats before 5 have no mode and target position (velocity mode).
fn read_hook(r: &mut ByteReader<'_>, version: u32) -> Result<HookInit, ModelError> {
    let position = read_vec3(r, "hook position")?;
    let velocity = read_vec3(r, "hook velocity")?;
    let target_velocity = read_vec3(r, "hook target velocity")?;
    let v = r.f64s_exact(5, "hook motion")?;
    Ok(HookInit {
        position,
        velocity,
        target_velocity,
        t0: v[0],
        payout: v[1],
        payout_rate: v[2],
        target_payout_rate: v[3],
        ramp: v[4],
        mode: if version >= 5 {
            HookMode::from_code(r.finite_f64("hook mode")?)
        } else {
            HookMode::Velocity
        },
        target_position: if version >= 5 {
            read_vec3(r, "hook target position")?
        } else {
            position
        },
    })
}

/// Writes the structure. Applied forces are not part of a RopeBlock scene built from
/// [`RopeBlockParams`] (only their count, 0, is written).
fn write_structure(w: &mut ByteWriter, s: &Structure) {
    w.bool(s.gravity.is_some());
    vec3(w, &s.gravity.unwrap_or_default());
    w.u64(s.blocks.len() as u64);
    for b in &s.blocks {
        w.str(&b.name);
        w.f64(b.mass);
        w.f64s(b.inertia.as_slice());
        w.bool(b.mesh.is_some());
        vec3(w, &b.position);
        vec3(w, &b.velocity);
        w.f64s(b.orientation.coords.as_slice());
        vec3(w, &b.omega);
        w.bool(b.fixed);
    }
    w.u64(s.loads.len() as u64);
    for l in &s.loads {
        w.str(&l.name);
        w.f64(l.mass);
        vec3(w, &l.position);
        vec3(w, &l.velocity);
    }
    w.u64(s.hooks.len() as u64);
    s.hooks.iter().for_each(|h| write_hook(w, h));
    w.u64(s.ropes.len() as u64);
    for rope in &s.ropes {
        w.str(&rope.name);
        write_props(w, &rope.props);
        w.f64(rope.nominal_segment);
        write_end(w, &rope.start);
        write_end(w, &rope.end);
        w.f64(rope.sigma_start);
        w.f64(rope.sigma_end);
        w.u64(rope.nodes.len() as u64);
        rope.nodes.iter().for_each(|n| write_node(w, n));
    }
    w.u64(s.forces.len() as u64);
}

/// Reads a structure; `mesh` is the block's shell (block frame) for blocks that had one.
fn read_structure(
    r: &mut ByteReader<'_>,
    mesh: &Arc<crate::rope::shell::ShellMesh>,
    version: u32,
) -> Result<Structure, ModelError> {
    let has_gravity = r.bool("gravity flag")?;
    let g = read_vec3(r, "gravity")?;
    let mut s = Structure {
        gravity: has_gravity.then_some(g),
        ..Structure::default()
    };
    for _ in 0..count(r, "block count")? {
        let name = r.str("block name")?.to_string();
        let mass = r.f64("block mass")?;
        let inertia = Mat3::from_column_slice(&r.f64s_exact(9, "block inertia")?);
        let has_mesh = r.bool("block mesh flag")?;
        let position = read_vec3(r, "block position")?;
        let velocity = read_vec3(r, "block velocity")?;
        let q = r.f64s_exact(4, "block orientation")?;
        let orientation = Quat::new_unchecked(Quaternion::new(q[3], q[0], q[1], q[2]));
        let omega = read_vec3(r, "block angular velocity")?;
        let fixed = r.bool("block fixed flag")?;
        s.blocks.push(BlockSpec {
            name,
            mass,
            inertia,
            mesh: has_mesh.then(|| mesh.clone()),
            position,
            velocity,
            orientation,
            omega,
            fixed,
        });
    }
    for _ in 0..count(r, "load count")? {
        s.loads.push(LoadSpec {
            name: r.str("load name")?.to_string(),
            mass: r.f64("load mass")?,
            position: read_vec3(r, "load position")?,
            velocity: read_vec3(r, "load velocity")?,
        });
    }
    for _ in 0..count(r, "hook count")? {
        s.hooks.push(read_hook(r, version)?);
    }
    for _ in 0..count(r, "rope count")? {
        let name = r.str("rope name")?.to_string();
        let props = read_props(r)?;
        let nominal_segment = r.f64("nominal segment")?;
        let start = read_end(r)?;
        let end = read_end(r)?;
        let sigma_start = r.f64("rope start coordinate")?;
        let sigma_end = r.f64("rope end coordinate")?;
        let mut nodes = Vec::new();
        for _ in 0..count(r, "node count")? {
            nodes.push(read_node(r)?);
        }
        s.ropes.push(RopeSpec {
            name,
            props,
            nominal_segment,
            start,
            end,
            sigma_start,
            sigma_end,
            nodes,
        });
    }
    for rope in &s.ropes {
        for end in [&rope.start, &rope.end] {
            check_lug_point(&s, &rope.name, end)?;
        }
    }
    if r.u64("applied force count")? != 0 {
        return Err(bad(
            "serialized RopeBlock state has applied forces (none expected)",
        ));
    }
    s.validate()
        .map_err(|e| bad(format!("serialized RopeBlock structure: {e}")))?;
    Ok(s)
}

/// A rope end fixed to a block with a mesh must lie on the block: within its bounding box
/// widened by a tenth of the box's diagonal (lugs stand a little off the plates). A forged lug
/// point far off the block restored before and left a sling whose dynamics crawled.
fn check_lug_point(s: &Structure, rope: &str, end: &EndSpec) -> Result<(), ModelError> {
    let EndSpec::Block { block, local } = end else {
        return Ok(());
    };
    let Some(spec) = s.blocks.get(*block) else {
        return Ok(()); // the structure's own validation names a missing block
    };
    let Some(mesh) = &spec.mesh else {
        return Ok(());
    };
    let margin = 0.1 * (mesh.aabb_max - mesh.aabb_min).norm();
    let inside = (0..3)
        .all(|k| local[k] >= mesh.aabb_min[k] - margin && local[k] <= mesh.aabb_max[k] + margin);
    if inside {
        Ok(())
    } else {
        Err(bad(format!(
            "serialized RopeBlock structure: lug point ({:.6e}, {:.6e}, {:.6e}) m of rope `{rope}` lies off block `{}` (bounding box ({:.3}, {:.3}, {:.3}) .. ({:.3}, {:.3}, {:.3}) m)",
            local.x,
            local.y,
            local.z,
            spec.name,
            mesh.aabb_min.x,
            mesh.aabb_min.y,
            mesh.aabb_min.z,
            mesh.aabb_max.x,
            mesh.aabb_max.y,
            mesh.aabb_max.z
        )))
    }
}

/// Writes a running simulation.
pub fn write_sim(w: &mut ByteWriter, s: &RopeBlockSim) {
    write_structure(w, &s.structure);
    crate::scene::sim_state::write_state(w, &s.sim.state);
    w.f64s(&s.sim.system.inputs);
    w.f64s(&s.sim.integrator_memory());
    let c = &s.counters;
    for n in [
        c.inserted,
        c.edge_slides,
        c.removed,
        c.merged,
        c.split,
        c.rebuilds,
    ] {
        w.u64(n);
    }
    w.f64(s.event_energy);
    w.f64(s.slide_dissipation);
    w.f64(s.energy_reference.unwrap_or(f64::NAN));
    w.u64(s.max_rebuilds_per_call);
    w.f64(s.hook_ramp);
    w.f64s(&s.sim.integrator_monitors());
    let work: Vec<f64> = s.bonds.work.iter().flatten().copied().collect();
    w.f64s(&work);
}

/// The effect memory as this version lays it out: the rope effect's memory starts at `offset`
/// with [`HOOK_MEM`] values per hook; state formats before 5 had 14 (no target position and mode),
/// the hooks get their position at `t0` as target and velocity mode.
fn widen_hook_memory(
    memory: Vec<f64>,
    offset: usize,
    hooks: usize,
    version: u32,
) -> Result<Vec<f64>, ModelError> {
    const OLD: usize = 14;
    if version >= 5 {
        return Ok(memory);
    }
    let end = offset + OLD * hooks;
    if memory.len() < end {
        return Err(bad(
            "serialized RopeBlock state: the effect memory is shorter than its hooks",
        ));
    }
    let mut out = Vec::with_capacity(memory.len() + (HOOK_MEM - OLD) * hooks);
    out.extend_from_slice(&memory[..offset]);
    for m in memory[offset..end].chunks_exact(OLD) {
        out.extend_from_slice(m);
        out.extend_from_slice(&m[..3]);
        out.push(HookMode::Velocity.code());
    }
    out.extend_from_slice(&memory[end..]);
    Ok(out)
}

/// Reads what [`write_sim`] wrote for a scene with parameters `params`, in state format
/// `version` (1 had no slide dissipation); the state's time must be the clock's `elapsed` [s].
pub fn read_sim(
    r: &mut ByteReader<'_>,
    params: &RopeBlockParams,
    version: u32,
    elapsed: f64,
) -> Result<RopeBlockSim, ModelError> {
    let design = params.design_mesh().map_err(ModelError::BadState)?;
    let (com, _, _) = params.mass_properties(&design);
    let mesh = Arc::new(design.translated(&(-com)).map_err(ModelError::BadState)?);
    let mut structure = read_structure(r, &mesh, version)?;
    // the friction law is a parameter (fixed for a run), like the mesh
    for rope in &mut structure.ropes {
        rope.props.friction_law = params.rope.friction_law;
    }
    // the ground comes from the parameters (its contact has no memory)
    structure.ground = params
        .ground
        .map(|g| g.spec(&mesh))
        .transpose()
        .map_err(ModelError::BadState)?;
    let state = crate::scene::sim_state::read_state(r, Some(elapsed))?;
    let inputs = r.f64s("inputs")?;
    let memory = r.f64s("integrator memory")?;
    let mut c = [0u64; 6];
    for (k, n) in c.iter_mut().enumerate() {
        *n = r.u64(&format!("contact counter {k}"))?;
    }
    let event_energy = r.f64("event energy")?;
    let (slide_dissipation, energy_reference) = if version >= 2 {
        let slides = r.finite_f64("slide dissipation")?;
        let reference = r.f64("energy reference")?;
        (slides, reference.is_finite().then_some(reference))
    } else {
        (0.0, None)
    };
    let max_rebuilds_per_call = r.u64("rebuild bound")?;
    let hook_ramp = r.finite_f64("hook ramp")?;
    // before version 6 the monitors were not written: a restored integrator takes its rank
    // baseline afresh (as those versions did)
    let monitors = if version >= 6 {
        r.f64s("integrator monitors")?
    } else {
        Vec::new()
    };
    // before version 7 the power bonds' work was not written: it restarts from 0
    let n_hooks = structure.hooks.len();
    let mut bonds = BondBooks::new(n_hooks);
    if version >= 7 {
        let work = r.f64s("power bond work")?;
        if work.len() != 2 * n_hooks || !work.iter().all(|w| w.is_finite()) {
            return Err(bad(
                "serialized RopeBlock state: the power bonds' work does not match its hooks",
            ));
        }
        for (b, w) in bonds.work.iter_mut().zip(work.chunks_exact(2)) {
            *b = [w[0], w[1]];
        }
    }
    let (model, map) = build(&structure).map_err(ModelError::BadState)?;
    let mut state = state;
    state.memory = widen_hook_memory(
        std::mem::take(&mut state.memory),
        map.rope_memory,
        structure.hooks.len(),
        version,
    )?;
    let (settings, contact) = solver_settings(params);
    let mut sim = Simulation::new(model, params.integrator, run_settings(settings), state.t)
        .map_err(ModelError::BadState)?;
    if inputs.len() != sim.system.inputs.len() {
        return Err(bad(
            "serialized RopeBlock state has the wrong number of model inputs",
        ));
    }
    sim.system.inputs = inputs;
    sim.restore(state, &memory).map_err(ModelError::BadState)?;
    sim.restore_integrator_monitors(&monitors)
        .map_err(ModelError::BadState)?;
    Ok(RopeBlockSim {
        structure,
        sim,
        map,
        contact,
        counters: super::Counters {
            inserted: c[0],
            edge_slides: c[1],
            removed: c[2],
            merged: c[3],
            split: c[4],
            rebuilds: c[5],
        },
        event_energy,
        slide_dissipation,
        energy_reference,
        max_rebuilds_per_call,
        hook_ramp,
        bonds,
    })
}
