//! The scene's structure: blocks, loads, hooks and ropes with their nodes, as plain data.
//!
//! It is the single source from which the multibody model is (re)built: at start, and whenever a
//! contact node is inserted or removed, slides along its edge, or the rope is re-meshed around it.
//! Before an edit the structure is synchronized from the running state (positions, velocities,
//! contact memory), so a rebuild carries the motion over exactly.

use crate::contact::ContactLaw;
use crate::math::{Mat3, Quat, Vec3};
use crate::model::Profile;
use crate::rope::shell::ShellMesh;
use crate::rope::{HookInit, RopeProps, SlipMode};
use std::sync::Arc;

/// A rigid block with its shell plate.
#[derive(Debug, Clone)]
pub struct BlockSpec {
    /// Name used in messages and outputs.
    pub name: String,
    /// Mass [kg].
    pub mass: f64,
    /// Inertia about the centre of mass [kg m^2], block frame.
    pub inertia: Mat3,
    /// Shell plate in the block frame (origin at the centre of mass); `None`: no rope contact.
    pub mesh: Option<Arc<ShellMesh>>,
    /// Centre of mass [m] and velocity [m/s], world frame.
    pub position: Vec3,
    pub velocity: Vec3,
    /// Orientation (block frame to world).
    pub orientation: Quat,
    /// Angular velocity [rad/s], block frame.
    pub omega: Vec3,
    /// Welded to the ground (a test rig or a fixed structure).
    pub fixed: bool,
}

/// Contact of block points with the ground plane `z = height` (world frame): a normal contact law
/// per point and regularized Coulomb friction ([`crate::effect::ground_contact`]).
#[derive(Debug, Clone)]
pub struct GroundSpec {
    /// Height of the ground plane [m], world z.
    pub height: f64,
    /// Normal law of each point.
    pub law: ContactLaw,
    /// Friction coefficient [-] and regularization speed [m/s].
    pub mu: f64,
    pub slip_speed: f64,
    /// Contact points: (block, point [m] in the block frame).
    pub points: Vec<(usize, Vec3)>,
}

/// A point mass that is not part of a rope (a hook block, a test weight).
#[derive(Debug, Clone)]
pub struct LoadSpec {
    pub name: String,
    /// Mass [kg].
    pub mass: f64,
    /// Position [m] and velocity [m/s], world frame.
    pub position: Vec3,
    pub velocity: Vec3,
}

/// A body of the scene by role.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyRef {
    Block(usize),
    Load(usize),
}

/// A force `direction * magnitude(t)` [N] (world frame) acting at a body point (offset `local`
/// [m] in the body frame; 0 for loads).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceSpec {
    pub body: BodyRef,
    pub local: Vec3,
    /// Unit direction, world frame.
    pub direction: Vec3,
    /// Magnitude [N] as a function of time (or of a model input).
    pub magnitude: Profile,
}

/// Linear viscous dampers to the ground (a test rig's element: not among the FMU's parameters,
/// not in its saved state, as the applied forces). On a point of velocity `v` [m/s] a damper
/// acts with `-damping (I - a a^T) v` [N] for a unit free axis `a` (world frame): the motion
/// along `a` is free, every motion across it damped; a zero axis damps all three directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DamperSpec {
    /// On load `load`, free along `free_axis`.
    Load {
        load: usize,
        /// [N s/m], >= 0.
        damping: f64,
        free_axis: Vec3,
    },
    /// On every material node (no contact) of rope `rope`'s two strands, each with `damping`
    /// [N s/m]: free along `free_axes[0]` before the rope's first contact node, along
    /// `free_axes[1]` after its last (nodes between contact nodes are not damped). Taken at
    /// every build, so nodes merged or split on the way keep the rule.
    Strands {
        rope: usize,
        damping: f64,
        free_axes: [Vec3; 2],
    },
    /// On every contact node of rope `rope`, in all directions (its joint leaves it only the
    /// motion along its edge, so this damps its slide along the edge), with `damping` [N s/m].
    ContactNodes { rope: usize, damping: f64 },
}

/// What a rope end is attached to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EndSpec {
    /// Hook number `k` (prescribed motion).
    Hook(usize),
    /// A lug: point `local` [m] of block `block` (block frame).
    Block { block: usize, local: Vec3 },
    /// Load (point mass) number `k`.
    Load(usize),
}

/// A contact node's attachment to a plate edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeContact {
    /// Block and plate edge index.
    pub block: usize,
    pub edge: usize,
    /// Anchor of the node's friction along the edge [m], block frame (a point of the edge).
    pub anchor: Vec3,
    /// Sliding along the rope (state of the last accepted step).
    pub mode: SlipMode,
    /// Friction coefficient left for sliding along the rope [-].
    pub mu_rope: f64,
    /// Friction capacity along the edge [N] (updated from the normal force after every step).
    pub cap: f64,
}

/// Capacity given to a new contact node's friction along its edge until the first step has
/// measured its normal force [N] (it sticks meanwhile).
pub const INITIAL_EDGE_CAPACITY: f64 = 1e12;

/// An interior node of a rope (a material node or a contact node).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeSpec {
    /// Mass [kg].
    pub mass: f64,
    /// Material coordinate [m] (unstretched arc length from the rope's origin).
    pub sigma: f64,
    /// Position [m] and velocity [m/s], world frame.
    pub position: Vec3,
    pub velocity: Vec3,
    /// `Some` for a contact node.
    pub contact: Option<NodeContact>,
}

/// A rope between two ends, with its interior nodes in order from `start` to `end`.
#[derive(Debug, Clone)]
pub struct RopeSpec {
    pub name: String,
    pub props: RopeProps,
    /// Nominal segment length [m] (re-meshing keeps segments near it).
    pub nominal_segment: f64,
    pub start: EndSpec,
    pub end: EndSpec,
    /// Material coordinates of the two ends [m].
    pub sigma_start: f64,
    pub sigma_end: f64,
    pub nodes: Vec<NodeSpec>,
}

impl RopeSpec {
    /// Unstretched length [m] (without hook pay-out).
    pub fn length(&self) -> f64 {
        self.sigma_end - self.sigma_start
    }

    /// Total mass of the rope's nodes [kg].
    pub fn mass(&self) -> f64 {
        self.nodes.iter().map(|n| n.mass).sum()
    }
}

/// Everything a scene contains.
#[derive(Debug, Clone, Default)]
pub struct Structure {
    /// Gravity [m/s^2], world frame (`None`: off).
    pub gravity: Option<Vec3>,
    pub blocks: Vec<BlockSpec>,
    pub loads: Vec<LoadSpec>,
    pub hooks: Vec<HookInit>,
    pub ropes: Vec<RopeSpec>,
    pub forces: Vec<ForceSpec>,
    /// Viscous dampers on loads and strands (test rigs only; empty in every shipped scene).
    pub dampers: Vec<DamperSpec>,
    /// Block-ground contact (`None`: not assembled).
    pub ground: Option<GroundSpec>,
}

impl Structure {
    /// Checks cross references and values; `Err` names the item at fault.
    pub fn validate(&self) -> Result<(), String> {
        let fin = |v: &Vec3| v.iter().all(|x| x.is_finite());
        for b in &self.blocks {
            if !(b.mass.is_finite() && b.mass > 0.0) {
                return Err(format!(
                    "block '{}': mass must be finite and > 0 kg, got {}",
                    b.name, b.mass
                ));
            }
            if !(fin(&b.position) && fin(&b.velocity) && fin(&b.omega)) {
                return Err(format!("block '{}': initial state is not finite", b.name));
            }
        }
        for l in &self.loads {
            if !(l.mass.is_finite() && l.mass > 0.0) {
                return Err(format!(
                    "load '{}': mass must be finite and > 0 kg, got {}",
                    l.name, l.mass
                ));
            }
        }
        for d in &self.dampers {
            let (damping, axes) = match *d {
                DamperSpec::Load {
                    load,
                    damping,
                    free_axis,
                } => {
                    self.check_body(&BodyRef::Load(load), "damper")?;
                    (damping, vec![free_axis])
                }
                DamperSpec::Strands {
                    rope,
                    damping,
                    free_axes,
                } => {
                    if rope >= self.ropes.len() {
                        return Err(format!("damper: rope {rope} does not exist"));
                    }
                    (damping, free_axes.to_vec())
                }
                DamperSpec::ContactNodes { rope, damping } => {
                    if rope >= self.ropes.len() {
                        return Err(format!("damper: rope {rope} does not exist"));
                    }
                    (damping, vec![])
                }
            };
            let unit = |a: &Vec3| fin(a) && (a.norm() == 0.0 || (a.norm() - 1.0).abs() <= 1e-9);
            if !(damping.is_finite() && damping >= 0.0 && axes.iter().all(unit)) {
                return Err(format!(
                    "damper {d:?}: damping must be finite and >= 0 N s/m and each free axis zero or a unit vector"
                ));
            }
        }
        for f in &self.forces {
            self.check_body(&f.body, "applied force")?;
            if !(fin(&f.direction) && fin(&f.local) && f.magnitude.is_finite()) {
                return Err("applied force: direction, point or magnitude is not finite".into());
            }
            if (f.direction.norm() - 1.0).abs() > 1e-9 {
                return Err(format!(
                    "applied force: direction must be a unit vector, has length {}",
                    f.direction.norm()
                ));
            }
        }
        for r in &self.ropes {
            let owner = format!("rope '{}'", r.name);
            r.props.validate(&owner)?;
            for (which, e) in [("start", &r.start), ("end", &r.end)] {
                match *e {
                    EndSpec::Hook(k) if k >= self.hooks.len() => {
                        return Err(format!(
                            "{owner}: {which} hook {k} does not exist ({} hooks)",
                            self.hooks.len()
                        ));
                    }
                    EndSpec::Block { block, local } => {
                        self.check_body(&BodyRef::Block(block), &owner)?;
                        if !fin(&local) {
                            return Err(format!("{owner}: {which} lug point is not finite"));
                        }
                    }
                    EndSpec::Load(k) => self.check_body(&BodyRef::Load(k), &owner)?,
                    _ => {}
                }
            }
            if r.nodes.is_empty() {
                return Err(format!(
                    "{owner}: needs at least one interior node (at least 2 segments)"
                ));
            }
            let mut s = r.sigma_start;
            for (i, n) in r.nodes.iter().enumerate() {
                if !(n.mass.is_finite() && n.mass > 0.0) {
                    return Err(format!(
                        "{owner}, node {i}: mass must be finite and > 0 kg, got {}",
                        n.mass
                    ));
                }
                if !(fin(&n.position) && fin(&n.velocity)) {
                    return Err(format!(
                        "{owner}, node {i}: position or velocity not finite"
                    ));
                }
                if n.sigma.is_nan() || n.sigma <= s {
                    return Err(format!(
                        "{owner}, node {i}: material coordinate {} m does not exceed the previous {s} m (rest lengths must be > 0)",
                        n.sigma
                    ));
                }
                s = n.sigma;
                if let Some(c) = n.contact {
                    let Some(mesh) = self.blocks.get(c.block).and_then(|b| b.mesh.as_ref()) else {
                        return Err(format!(
                            "{owner}, node {i}: contact on block {} which has no shell mesh",
                            c.block
                        ));
                    };
                    if c.edge >= mesh.edges.len() {
                        return Err(format!(
                            "{owner}, node {i}: plate edge {} does not exist",
                            c.edge
                        ));
                    }
                }
            }
            if r.sigma_end.is_nan() || r.sigma_end <= s {
                return Err(format!(
                    "{owner}: end material coordinate {} m must exceed the last node's {s} m",
                    r.sigma_end
                ));
            }
        }
        Ok(())
    }

    fn check_body(&self, b: &BodyRef, owner: &str) -> Result<(), String> {
        match *b {
            BodyRef::Block(i) if i >= self.blocks.len() => Err(format!(
                "{owner}: block {i} does not exist ({} blocks)",
                self.blocks.len()
            )),
            BodyRef::Load(i) if i >= self.loads.len() => Err(format!(
                "{owner}: load {i} does not exist ({} loads)",
                self.loads.len()
            )),
            _ => Ok(()),
        }
    }

    /// Total mass of blocks, loads and rope nodes [kg].
    pub fn total_mass(&self) -> f64 {
        self.blocks.iter().map(|b| b.mass).sum::<f64>()
            + self.loads.iter().map(|l| l.mass).sum::<f64>()
            + self.ropes.iter().map(|r| r.mass()).sum::<f64>()
    }

    /// Total linear momentum of blocks, loads and rope nodes [kg m/s], world frame.
    pub fn momentum(&self) -> Vec3 {
        let mut p = Vec3::zeros();
        for b in &self.blocks {
            p += b.velocity * b.mass;
        }
        for l in &self.loads {
            p += l.velocity * l.mass;
        }
        for r in &self.ropes {
            for n in &r.nodes {
                p += n.velocity * n.mass;
            }
        }
        p
    }

    /// Number of contact nodes on all ropes.
    pub fn n_contacts(&self) -> usize {
        self.ropes
            .iter()
            .map(|r| r.nodes.iter().filter(|n| n.contact.is_some()).count())
            .sum()
    }
}
