//! Immutable description of a multibody system: bodies, joints, force elements.
//!
//! A [`Model`] is built once by [`ModelBuilder`] (which validates every input and returns `Err`
//! with a precise message) and never changes during a simulation; everything that changes lives
//! in [`crate::state::State`].

pub mod body;
mod builder;
pub mod element;
pub mod kinematics;
pub mod profile;

pub use body::{Body, BodyId, BodyInit, BodyKind};
pub use builder::ModelBuilder;
pub use element::{AppliedLoad, Frame, Joint, JointKind, JointTorque, SpringDamper, TorsionSpring};
pub use profile::Profile;

use crate::effect::ForceEffect;
use crate::math::{Vec3, dexp_inv, exp_so3, log_so3};
use std::sync::Arc;

/// An assembled multibody model.
#[derive(Debug, Clone)]
pub struct Model {
    /// Bodies with their coordinate offsets.
    pub bodies: Vec<Body>,
    /// Holonomic joints (constraints).
    pub joints: Vec<Joint>,
    /// Gravity acceleration [m/s^2], world frame; `None` when the effect is off.
    pub gravity: Option<Vec3>,
    /// Force effects, each a group of elements of one kind (absent kinds cost nothing).
    pub forces: Vec<Arc<dyn ForceEffect>>,
    /// Names of the model inputs (read by profiles with `Profile::Input`).
    pub input_names: Vec<String>,
    /// Total number of position coordinates.
    pub n_q: usize,
    /// Total number of generalized speeds.
    pub n_v: usize,
    /// Initial positions (length `n_q`) and speeds (length `n_v`), before projection.
    pub q0: Vec<f64>,
    pub v0: Vec<f64>,
    /// Node frames of modal bodies that force effects act at: entry `j` is the *node body*
    /// returned by [`ModelBuilder::node_body`], a kinematic frame (no coordinates of its own) that rides on
    /// node `node` of `body` (see [`ModelBuilder::node_body`]).
    pub node_bodies: Vec<NodeBody>,
}

/// A node frame of a modal body seen by force effects as a rigid frame: origin
/// `r + A (rho_k + Phi_k a)`, rotation `A exp((Psi_k a)~)`, its velocity and body-frame angular
/// velocity; its forces are mapped to the modal body's speeds by the transpose of its velocity
/// map (see [`crate::dae`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeBody {
    pub body: BodyId,
    pub node: usize,
}

impl Model {
    /// Number of model inputs.
    pub fn n_inputs(&self) -> usize {
        self.input_names.len()
    }

    /// The body with the given id (`None` for ground and node bodies).
    pub fn body(&self, id: BodyId) -> Option<&Body> {
        id.index().and_then(|i| self.bodies.get(i))
    }

    /// Retraction: `out = q ⊕ dx`. Translations add in the world frame; rotations compose on the
    /// right with `exp(dtheta~)` (body-frame rotation vector); the quaternion stays normalized.
    pub fn retract(&self, q: &[f64], dx: &[f64], out: &mut [f64]) {
        for b in &self.bodies {
            let (qo, vo) = (b.q_offset, b.v_offset);
            for k in 0..3 {
                out[qo + k] = q[qo + k] + dx[vo + k];
            }
            if b.kind.has_rotation() {
                let r = kinematics::quat_at(q, qo + 3);
                let th = Vec3::new(dx[vo + 3], dx[vo + 4], dx[vo + 5]);
                let rn = r * exp_so3(&th);
                kinematics::put_quat(out, qo + 3, &rn);
            }
            for i in 0..b.kind.n_modes() {
                out[qo + 7 + i] = q[qo + 7 + i] + dx[vo + 6 + i];
            }
        }
    }

    /// Inverse of [`Model::retract`] near `q_ref`: the tangent increment `dx` with
    /// `q_ref ⊕ dx = q` (rotations of at most pi).
    pub fn local(&self, q_ref: &[f64], q: &[f64], dx: &mut [f64]) {
        for b in &self.bodies {
            let (qo, vo) = (b.q_offset, b.v_offset);
            for k in 0..3 {
                dx[vo + k] = q[qo + k] - q_ref[qo + k];
            }
            if b.kind.has_rotation() {
                let r0 = kinematics::quat_at(q_ref, qo + 3);
                let r1 = kinematics::quat_at(q, qo + 3);
                let th = log_so3(&(r0.inverse() * r1));
                dx[vo + 3..vo + 6].copy_from_slice(th.as_slice());
            }
            for i in 0..b.kind.n_modes() {
                dx[vo + 6 + i] = q[qo + 7 + i] - q_ref[qo + 7 + i];
            }
        }
    }

    /// Rate of the chart coordinates: with `q = q_ref ⊕ x`, `x_dot = T(x)^-1 v`
    /// (identity on translations, `dexp_inv` on rotation vectors).
    pub fn chart_rate(&self, x: &[f64], v: &[f64], out: &mut [f64]) {
        for b in &self.bodies {
            let vo = b.v_offset;
            out[vo..vo + 3].copy_from_slice(&v[vo..vo + 3]);
            if b.kind.has_rotation() {
                let th = Vec3::new(x[vo + 3], x[vo + 4], x[vo + 5]);
                let om = Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]);
                out[vo + 3..vo + 6].copy_from_slice(dexp_inv(&th, &om).as_slice());
            }
            let m = b.kind.n_modes();
            if m > 0 {
                out[vo + 6..vo + 6 + m].copy_from_slice(&v[vo + 6..vo + 6 + m]);
            }
        }
    }

    /// Per-coordinate magnitude used for relative error weights (`atol + rtol * scale`, for the
    /// local error test and the Newton convergence test alike): for translations [m] the body's
    /// characteristic length [`Body::length_scale`] when it has one, else |r| (its distance from
    /// the world origin); 1 rad for rotations; |a_i| for modal coordinates (the deformation
    /// relative to the body frame, in the units of the body data).
    ///
    /// A characteristic length makes the weights translation-invariant: with |r| a rope node
    /// 20 m from the origin got a tolerance a hundred times what its 0.2 m segment allows, and
    /// Newton stopped at errors comparable to the whole stretch of a loaded segment (RopeBlock
    /// sets the segment length, `scene::rope_block::build`). Models without one keep |r|:
    /// PanelLock's figures were measured with it, and the radius of its initial configuration
    /// as a default loosened its gen-alpha and DOPRI5 errors 2-10x at equal rtol.
    pub fn position_scale(&self, q: &[f64], out: &mut [f64]) {
        for b in &self.bodies {
            let (qo, vo) = (b.q_offset, b.v_offset);
            for k in 0..3 {
                out[vo + k] = b.length_scale.unwrap_or_else(|| q[qo + k].abs());
            }
            if b.kind.has_rotation() {
                out[vo + 3..vo + 6].fill(1.0);
            }
            for i in 0..b.kind.n_modes() {
                out[vo + 6 + i] = q[qo + 7 + i].abs();
            }
        }
    }
}
