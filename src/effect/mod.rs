//! Everything that adds forces or constraints to a model.
//!
//! A force effect is a *group* of elements of one kind (all torsion springs of a scene, say), so a
//! kind that a scene does not enable is simply absent and costs nothing. Each effect adds its
//! generalized forces and the blocks of its Jacobians `K = -df/dx` (tangent position increments)
//! and `D = -df/dv`; the integrator decides the factors by which they enter its Newton matrix.

pub mod angle;
pub mod applied;
pub mod constraint;
pub mod gravity;
pub mod point_force;
pub mod spring_damper;
pub mod torsion;

use crate::math::Matrix6;
use crate::model::kinematics::BodyKin;

/// What an effect sees when it is evaluated.
#[derive(Debug, Clone, Copy)]
pub struct EvalCtx<'a> {
    /// Time [s].
    pub t: f64,
    /// Kinematics of every body (index = body index).
    pub kins: &'a [BodyKin],
    /// Model inputs (controller signals).
    pub inputs: &'a [f64],
}

/// Receives Jacobian blocks; an effect must emit the same sequence of blocks at every call for a
/// given model structure (the sparse pattern is recorded once).
pub trait JacobianSink {
    /// Adds the coupling block of speeds of `row` (equations) and `col` (unknowns): `K` (w.r.t.
    /// tangent position increments) and `D` (w.r.t. speeds), each 6x6 with translations first;
    /// only the top-left 3x3 is used for a body without rotation; ground rows/cols are skipped.
    fn add(&mut self, row: &BodyKin, col: &BodyKin, k: &Matrix6<f64>, d: &Matrix6<f64>);
}

/// A group of force elements of one kind.
pub trait ForceEffect: Send + Sync + std::fmt::Debug {
    /// Short name used in messages.
    fn name(&self) -> &str;

    /// Adds the generalized forces (length `n_v`): forces [N] in the world frame on translations,
    /// torques [N m] in the body frame on rotations.
    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]);

    /// Adds `K = -df/dx` and `D = -df/dv` blocks.
    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink);

    /// Potential energy stored in the elements [J].
    fn potential_energy(&self, _ctx: &EvalCtx) -> f64 {
        0.0
    }

    /// Power dissipated by the elements [W] (>= 0).
    fn dissipated_power(&self, _ctx: &EvalCtx) -> f64 {
        0.0
    }

    /// Power fed into the system by prescribed or input-driven loads [W].
    fn input_power(&self, _ctx: &EvalCtx) -> f64 {
        0.0
    }
}
