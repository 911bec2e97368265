//! Validating builder for [`Model`]: every bad input is an `Err` with a precise message.

use super::body::{Body, BodyId, BodyInit, BodyKind};
use super::element::{
    AppliedLoad, Frame, Joint, JointKind, JointTorque, SpringDamper, TorsionSpring,
};
use super::kinematics::put_quat;
use super::{Model, NodeBody, Profile};
use crate::effect::ForceEffect;
use crate::effect::applied::AppliedLoads;
use crate::effect::gravity::Gravity;
use crate::effect::spring_damper::SpringDampers;
use crate::effect::torsion::{JointTorques, TorsionSprings};
use crate::flex::ModalBodyData;
use crate::math::{Mat3, Vec3};
use std::sync::Arc;

/// Collects bodies, joints and force elements, then checks and assembles a [`Model`].
#[derive(Debug, Default)]
pub struct ModelBuilder {
    bodies: Vec<(String, BodyKind, BodyInit)>,
    /// Initial modal coordinates and speeds of modal bodies (index = body index; empty otherwise).
    modal_init: Vec<(Vec<f64>, Vec<f64>)>,
    joints: Vec<Joint>,
    springs: Vec<SpringDamper>,
    torsions: Vec<TorsionSpring>,
    loads: Vec<AppliedLoad>,
    joint_torques: Vec<JointTorque>,
    gravity: Option<Vec3>,
    extra: Vec<Arc<dyn ForceEffect>>,
    inputs: Vec<String>,
    /// Node frames used by force effects, in order of first use (see [`ModelBuilder::node_body`]).
    node_bodies: Vec<NodeBody>,
    /// Characteristic lengths [m] set per body (index = body index; `None`: the model's).
    length_scales: Vec<Option<f64>>,
    /// The model's characteristic length [m] (`None`: distances from the origin).
    length_scale: Option<f64>,
}

fn check_length(what: &str, l: f64) -> Result<(), String> {
    if l.is_finite() && l > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "{what}: characteristic length must be finite and positive, got {l} m"
        ))
    }
}

fn finite3(v: &Vec3) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl ModelBuilder {
    /// An empty model without gravity.
    pub fn new() -> Self {
        Self::default()
    }

    fn check_init(name: &str, init: &BodyInit) -> Result<(), String> {
        if !finite3(&init.position) || !finite3(&init.velocity) || !finite3(&init.omega) {
            return Err(format!(
                "body '{name}': initial position or velocity is not finite"
            ));
        }
        if !init.orientation.coords.iter().all(|x| x.is_finite()) {
            return Err(format!("body '{name}': initial orientation is not finite"));
        }
        Ok(())
    }

    /// Adds a rigid body of `mass` [kg] with `inertia` [kg m^2] about its centre of mass (body frame).
    pub fn add_rigid_body(
        &mut self,
        name: &str,
        mass: f64,
        inertia: Mat3,
        init: BodyInit,
    ) -> Result<BodyId, String> {
        if !(mass.is_finite() && mass > 0.0) {
            return Err(format!(
                "body '{name}': mass must be finite and positive, got {mass}"
            ));
        }
        if !inertia.iter().all(|x| x.is_finite()) {
            return Err(format!(
                "body '{name}': inertia tensor has non-finite entries"
            ));
        }
        if (inertia - inertia.transpose()).norm() > 1e-9 * inertia.norm().max(1e-300) {
            return Err(format!("body '{name}': inertia tensor is not symmetric"));
        }
        let eig = inertia.symmetric_eigenvalues();
        let (mut p, max) = ([eig[0], eig[1], eig[2]], eig.max());
        if p.iter().any(|&x| x <= 1e-14 * max.max(1e-300)) || max <= 0.0 {
            return Err(format!(
                "body '{name}': inertia tensor is not positive definite (principal moments {:.6e}, {:.6e}, {:.6e} kg m^2)",
                p[0], p[1], p[2]
            ));
        }
        p.sort_by(|a, b| a.total_cmp(b));
        if p[0] + p[1] < p[2] * (1.0 - 1e-9) {
            return Err(format!(
                "body '{name}': principal moments {:.6e}, {:.6e}, {:.6e} kg m^2 violate the triangle inequality (no real mass distribution has them)",
                p[0], p[1], p[2]
            ));
        }
        Self::check_init(name, &init)?;
        self.bodies
            .push((name.to_string(), BodyKind::Rigid { mass, inertia }, init));
        self.modal_init.push((Vec::new(), Vec::new()));
        self.length_scales.push(None);
        Ok(BodyId(self.bodies.len() - 1))
    }

    /// Adds a point mass [kg] at `position` [m] moving with `velocity` [m/s] (world frame).
    pub fn add_particle(
        &mut self,
        name: &str,
        mass: f64,
        position: Vec3,
        velocity: Vec3,
    ) -> Result<BodyId, String> {
        if !(mass.is_finite() && mass > 0.0) {
            return Err(format!(
                "particle '{name}': mass must be finite and positive, got {mass}"
            ));
        }
        let init = BodyInit::at(position).moving(velocity, Vec3::zeros());
        Self::check_init(name, &init)?;
        self.bodies
            .push((name.to_string(), BodyKind::Particle { mass }, init));
        self.modal_init.push((Vec::new(), Vec::new()));
        self.length_scales.push(None);
        Ok(BodyId(self.bodies.len() - 1))
    }

    /// Adds a modally reduced flexible body (floating frame of reference, see
    /// [`crate::model::body`]): `init` places its reference frame (origin and orientation, speeds
    /// of the origin [m/s, world] and of the frame [rad/s, body]); `a0` and `a_dot0` are the
    /// initial modal coordinates and speeds (each of length `data.n_modes()`).
    pub fn add_modal_body(
        &mut self,
        name: &str,
        data: Arc<ModalBodyData>,
        init: BodyInit,
        a0: &[f64],
        a_dot0: &[f64],
    ) -> Result<BodyId, String> {
        let n = data.n_modes();
        if a0.len() != n || a_dot0.len() != n {
            return Err(format!(
                "modal body '{name}': initial modal coordinates have length {} and speeds {}, the body has {n} modes",
                a0.len(),
                a_dot0.len()
            ));
        }
        if !a0.iter().chain(a_dot0).all(|x| x.is_finite()) {
            return Err(format!(
                "modal body '{name}': initial modal coordinates or speeds are not finite"
            ));
        }
        Self::check_init(name, &init)?;
        self.bodies
            .push((name.to_string(), BodyKind::Modal { data }, init));
        self.modal_init.push((a0.to_vec(), a_dot0.to_vec()));
        self.length_scales.push(None);
        Ok(BodyId(self.bodies.len() - 1))
    }

    /// Sets the model's characteristic length [m]: the scale of the relative position error
    /// weights (`rtol * length`) of every body without a length of its own. Without one, a
    /// body's weights scale with its distance from the world origin (see
    /// [`Model::position_scale`]).
    pub fn set_length_scale(&mut self, length: f64) -> Result<(), String> {
        check_length("model", length)?;
        self.length_scale = Some(length);
        Ok(())
    }

    /// Sets one body's characteristic length [m] (see [`ModelBuilder::set_length_scale`]), e.g.
    /// the segment length for a rope node.
    pub fn set_body_length_scale(&mut self, body: BodyId, length: f64) -> Result<(), String> {
        let i = body
            .index()
            .filter(|&i| i < self.bodies.len())
            .ok_or_else(|| "characteristic length for an unknown body".to_string())?;
        check_length(&format!("body '{}'", self.bodies[i].0), length)?;
        self.length_scales[i] = Some(length);
        Ok(())
    }

    /// Declares a model input (a controller signal) and returns its index for [`Profile::Input`].
    pub fn add_input(&mut self, name: &str) -> usize {
        self.inputs.push(name.to_string());
        self.inputs.len() - 1
    }

    /// Switches gravity on with acceleration `g` [m/s^2] (world frame), or off with `None`.
    pub fn set_gravity(&mut self, g: Option<Vec3>) -> Result<(), String> {
        if let Some(g) = g
            && !finite3(&g)
        {
            return Err("gravity vector is not finite".into());
        }
        self.gravity = g;
        Ok(())
    }

    fn check_frame(
        &self,
        owner: &str,
        which: &str,
        f: &Frame,
        needs_rotation: bool,
    ) -> Result<(), String> {
        if let Some(i) = f.body.index() {
            let Some((bname, kind, _)) = self.bodies.get(i) else {
                return Err(format!(
                    "{owner}: frame {which} references body #{i}, but the model has {} bodies",
                    self.bodies.len()
                ));
            };
            if needs_rotation && !kind.has_rotation() {
                return Err(format!(
                    "{owner}: frame {which} is on particle '{bname}', which has no rotation"
                ));
            }
            if let Some(node) = f.node {
                let Some(data) = kind.modal() else {
                    return Err(format!(
                        "{owner}: frame {which} refers to node {node} of '{bname}', which is not a modal (flexible) body"
                    ));
                };
                if node >= data.n_nodes() {
                    return Err(format!(
                        "{owner}: frame {which} refers to node {node} of modal body '{bname}', which has {} nodes (0..{})",
                        data.n_nodes(),
                        data.n_nodes()
                    ));
                }
            }
        } else if f.node.is_some() {
            return Err(format!(
                "{owner}: frame {which} is on the ground and cannot refer to a node"
            ));
        }
        if !finite3(&f.origin) || !f.axes.iter().all(|x| x.is_finite()) {
            return Err(format!(
                "{owner}: frame {which} has a non-finite origin or axis (zero-length axis?)"
            ));
        }
        if (f.axes.transpose() * f.axes - Mat3::identity()).norm() > 1e-9
            || f.axes.determinant() < 0.0
        {
            return Err(format!(
                "{owner}: frame {which} axes are not a right-handed orthonormal set"
            ));
        }
        Ok(())
    }

    /// Checks a force element's frame; a node frame ([`Frame::on_node`]) is replaced by a frame
    /// on the node body ([`ModelBuilder::node_body`]; same offset and axes, relative to the node's
    /// frame). Built-in force elements call it themselves; a custom force effect
    /// ([`ModelBuilder::add_force_effect`]) must be given frames that went through it, or it acts
    /// on the modal body's reference frame instead of the node. `owner` and `which` name the
    /// element and the frame in errors.
    pub fn force_frame(
        &mut self,
        owner: &str,
        which: &str,
        f: &Frame,
        needs_rotation: bool,
    ) -> Result<Frame, String> {
        self.check_frame(owner, which, f, needs_rotation)?;
        match f.node {
            None => Ok(*f),
            Some(node) => Ok(Frame {
                body: self.node_body(f.body, node)?,
                node: None,
                ..*f
            }),
        }
    }

    /// The *node body* of node `node` of modal body `body`: a rigid frame riding on the node
    /// (origin at the deformed node, rotated by the node's rotation), for force effects, including
    /// custom ones ([`ModelBuilder::add_force_effect`]), that should act at the node; forces and
    /// torques on it are carried over to the modal body. Force elements given a node frame
    /// ([`Frame::on_node`]) use it automatically. A node body has no coordinates and cannot carry
    /// joints (joints take node frames directly). Errors: `body` is not a modal body or has no such
    /// node.
    pub fn node_body(&mut self, body: BodyId, node: usize) -> Result<BodyId, String> {
        let Some((bname, kind, _)) = body.index().and_then(|i| self.bodies.get(i)) else {
            return Err(format!(
                "node body: body {body:?} is not a body of the model (ground or unknown)"
            ));
        };
        let Some(data) = kind.modal() else {
            return Err(format!(
                "node body: '{bname}' is not a modal (flexible) body and has no nodes"
            ));
        };
        if node >= data.n_nodes() {
            return Err(format!(
                "node body: modal body '{bname}' has {} nodes, node {node} does not exist",
                data.n_nodes()
            ));
        }
        let nb = NodeBody { body, node };
        let i = match self.node_bodies.iter().position(|x| *x == nb) {
            Some(i) => i,
            None => {
                self.node_bodies.push(nb);
                self.node_bodies.len() - 1
            }
        };
        Ok(BodyId::node_body(i))
    }

    fn check_profile(&self, owner: &str, p: &Profile) -> Result<(), String> {
        if !p.is_finite() {
            return Err(format!("{owner}: profile has non-finite coefficients"));
        }
        if let Some(i) = p.input()
            && i >= self.inputs.len()
        {
            return Err(format!(
                "{owner}: profile reads input #{i}, but the model declares {} inputs",
                self.inputs.len()
            ));
        }
        Ok(())
    }

    /// Adds a joint between `frame_i` and `frame_j`. A frame may ride on a node of a modal body
    /// ([`Frame::on_node`], e.g. a hinge at a panel's attachment node): revolute, spherical,
    /// fixed, prismatic and translation-drive joints work there (not the angle drive). Errors
    /// name the joint and the frame: a node the body does not have, a node on a rigid body or the
    /// ground, a frame on a node body.
    pub fn add_joint(
        &mut self,
        name: &str,
        kind: JointKind,
        frame_i: Frame,
        frame_j: Frame,
    ) -> Result<(), String> {
        let owner = format!("joint '{name}'");
        self.check_frame(&owner, "i", &frame_i, kind.needs_rotation_i())?;
        self.check_frame(&owner, "j", &frame_j, kind.needs_rotation())?;
        if frame_i.body == frame_j.body {
            return Err(format!("{owner}: both frames are on the same body"));
        }
        if frame_i.body.node_body_index().is_some() || frame_j.body.node_body_index().is_some() {
            return Err(format!(
                "{owner}: a joint frame cannot be on a node body; give the modal body and the node (Frame::on_node)"
            ));
        }
        if let JointKind::AngleDrive(p) | JointKind::TranslationDrive(p) = &kind {
            self.check_profile(&owner, p)?;
        }
        if matches!(kind, JointKind::AngleDrive(_))
            && (frame_i.node.is_some() || frame_j.node.is_some())
        {
            return Err(format!(
                "{owner}: an angle drive on a flexible-body node frame is not supported (put it on the body's reference frame)"
            ));
        }
        self.joints.push(Joint {
            name: name.to_string(),
            kind,
            frame_i,
            frame_j,
        });
        Ok(())
    }

    /// Adds a translational spring-damper.
    pub fn add_spring_damper(&mut self, e: SpringDamper) -> Result<(), String> {
        let owner = format!("spring-damper '{}'", e.name);
        let mut e = e;
        e.a = self.force_frame(&owner, "a", &e.a, false)?;
        e.b = self.force_frame(&owner, "b", &e.b, false)?;
        if !(e.stiffness >= 0.0
            && e.damping >= 0.0
            && e.free_length >= 0.0
            && (e.stiffness + e.damping + e.free_length).is_finite())
        {
            return Err(format!(
                "{owner}: stiffness, damping and free length must be finite and >= 0"
            ));
        }
        self.springs.push(e);
        Ok(())
    }

    /// Adds a rotational spring-damper about the z axes of its frames.
    pub fn add_torsion_spring(&mut self, e: TorsionSpring) -> Result<(), String> {
        let owner = format!("torsion spring '{}'", e.name);
        let mut e = e;
        e.frame_i = self.force_frame(&owner, "i", &e.frame_i, true)?;
        e.frame_j = self.force_frame(&owner, "j", &e.frame_j, true)?;
        if !(e.stiffness >= 0.0
            && e.damping >= 0.0
            && (e.stiffness + e.damping + e.free_angle + e.angle_offset).is_finite())
        {
            return Err(format!(
                "{owner}: stiffness and damping must be finite and >= 0, angles finite"
            ));
        }
        self.torsions.push(e);
        Ok(())
    }

    /// Adds an applied force/torque.
    pub fn add_applied_load(&mut self, e: AppliedLoad) -> Result<(), String> {
        let owner = format!("load '{}'", e.name);
        let mut e = e;
        e.at = self.force_frame(&owner, "at", &e.at, false)?;
        self.check_profile(&owner, &e.force)?;
        self.check_profile(&owner, &e.torque)?;
        if !finite3(&e.force_direction) || !finite3(&e.torque_direction) {
            return Err(format!("{owner}: direction is not finite"));
        }
        self.loads.push(e);
        Ok(())
    }

    /// Adds a torque between two bodies about a joint axis.
    pub fn add_joint_torque(&mut self, e: JointTorque) -> Result<(), String> {
        let owner = format!("joint torque '{}'", e.name);
        let mut e = e;
        e.frame_i = self.force_frame(&owner, "i", &e.frame_i, true)?;
        e.frame_j = self.force_frame(&owner, "j", &e.frame_j, true)?;
        self.check_profile(&owner, &e.torque)?;
        self.joint_torques.push(e);
        Ok(())
    }

    /// Adds a custom force effect (contacts, ropes, ...).
    pub fn add_force_effect(&mut self, e: Arc<dyn ForceEffect>) {
        self.extra.push(e);
    }

    /// Checks cross references and assembles the model.
    pub fn build(self) -> Result<Model, String> {
        let mut bodies = Vec::with_capacity(self.bodies.len());
        let (mut n_q, mut n_v) = (0, 0);
        for ((name, kind, _), l) in self.bodies.iter().zip(&self.length_scales) {
            bodies.push(Body {
                name: name.clone(),
                kind: kind.clone(),
                q_offset: n_q,
                v_offset: n_v,
                length_scale: l.or(self.length_scale),
            });
            n_q += kind.n_q();
            n_v += kind.n_v();
        }
        let mut q0 = vec![0.0; n_q];
        let mut v0 = vec![0.0; n_v];
        for (b, (_, kind, init)) in bodies.iter().zip(&self.bodies) {
            q0[b.q_offset..b.q_offset + 3].copy_from_slice(init.position.as_slice());
            v0[b.v_offset..b.v_offset + 3].copy_from_slice(init.velocity.as_slice());
            if kind.has_rotation() {
                put_quat(&mut q0, b.q_offset + 3, &init.orientation);
                v0[b.v_offset + 3..b.v_offset + 6].copy_from_slice(init.omega.as_slice());
            }
        }
        for (b, (a0, a_dot0)) in bodies.iter().zip(&self.modal_init) {
            // only modal bodies have modal coordinates (a particle has no slots past its 3)
            if matches!(b.kind, BodyKind::Modal { .. }) {
                q0[b.q_offset + 7..b.q_offset + 7 + a0.len()].copy_from_slice(a0);
                v0[b.v_offset + 6..b.v_offset + 6 + a_dot0.len()].copy_from_slice(a_dot0);
            }
        }
        let mut forces: Vec<Arc<dyn ForceEffect>> = Vec::new();
        if let Some(g) = self.gravity {
            forces.push(Arc::new(Gravity {
                g,
                // modal bodies get their (configuration-dependent) gravity from the System
                masses: bodies
                    .iter()
                    .map(|b| match b.kind {
                        BodyKind::Modal { .. } => 0.0,
                        _ => b.kind.mass(),
                    })
                    .collect(),
            }));
        }
        if !self.springs.is_empty() {
            forces.push(Arc::new(SpringDampers {
                elements: self.springs,
            }));
        }
        if !self.torsions.is_empty() {
            forces.push(Arc::new(TorsionSprings {
                elements: self.torsions,
            }));
        }
        if !self.loads.is_empty() {
            forces.push(Arc::new(AppliedLoads {
                elements: self.loads,
            }));
        }
        if !self.joint_torques.is_empty() {
            forces.push(Arc::new(JointTorques {
                elements: self.joint_torques,
            }));
        }
        forces.extend(self.extra);
        Ok(Model {
            bodies,
            joints: self.joints,
            gravity: self.gravity,
            forces,
            input_names: self.inputs,
            n_q,
            n_v,
            q0,
            v0,
            node_bodies: self.node_bodies,
        })
    }
}
