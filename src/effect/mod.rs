//! Everything that adds forces or constraints to a model.
//!
//! A force effect is a *group* of elements of one kind (all torsion springs of a scene, say), so a
//! kind that a scene does not enable is simply absent and costs nothing. Each effect adds its
//! generalized forces and the blocks of its Jacobians `K = -df/dx` (tangent position increments)
//! and `D = -df/dv`; the integrator decides the factors by which they enter its Newton matrix.

pub mod angle;
pub mod angle_force;
pub mod angle_stop;
pub mod applied;
pub mod body_load;
pub mod cable_loop;
pub mod constraint;
pub mod constraint_stiffness;
pub mod gravity;
pub mod ground_contact;
pub mod hinge_friction;
pub mod latch;
pub mod plane_contact;
pub mod point_force;
pub mod spring_damper;
pub mod torsion;

use crate::math::{Matrix6, Vector6};
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
    /// This effect's own discrete memory (see [`ForceEffect::n_memory`]).
    pub memory: &'a [f64],
    /// Decisions frozen for the rest of a Newton iteration (see [`ForceEffect::freeze`]); empty
    /// outside a frozen iteration, and then the effect decides everything itself.
    pub frozen: &'a [f64],
}

/// How an effect's memory changed after an accepted step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum MemoryChange {
    /// Nothing changed.
    None,
    /// Changed without changing the forces at this instant (e.g. an approach speed recorded at
    /// contact onset, where the force is still zero): integration continues.
    Smooth,
    /// Changed the forces discontinuously: integrators restart their history here.
    Discontinuous,
}

/// Receives Jacobian blocks; an effect must emit the same sequence of blocks at every call for a
/// given model structure (the sparse pattern is recorded once).
pub trait JacobianSink {
    /// Adds the coupling block of speeds of `row` (equations) and `col` (unknowns): `K` (w.r.t.
    /// tangent position increments) and `D` (w.r.t. speeds), each 6x6 with translations first;
    /// only the top-left 3x3 is used for a body without rotation; ground rows/cols are skipped.
    fn add(&mut self, row: &BodyKin, col: &BodyKin, k: &Matrix6<f64>, d: &Matrix6<f64>);

    /// Whether the sink borders the system with auxiliary unknowns (see [`AuxSupport`]).
    fn aux_support(&self) -> AuxSupport {
        AuxSupport::None
    }

    /// A new auxiliary unknown `w` with its own equation row (only under
    /// [`AuxSupport::Rows`]; `None` otherwise).
    fn new_aux(&mut self) -> Option<usize> {
        None
    }

    /// Adds `k w` to the stiffness `K` (= `-df/dx`) rows of `row`'s speeds (6 entries,
    /// translations first; 3 for a body without rotation) for the auxiliary unknown `w`.
    fn add_stiffness_aux(&mut self, _row: &BodyKin, _aux: usize, _k: &Vector6<f64>) {}

    /// Adds `c . dx` to the equation of auxiliary unknown `aux`, `dx` the tangent position
    /// increment of `col` (6 entries, translations first; 3 without rotation).
    fn add_aux_position(&mut self, _aux: usize, _col: &BodyKin, _c: &Vector6<f64>) {}

    /// Adds `value w_col` to the equation of auxiliary unknown `row`.
    fn add_aux_aux(&mut self, _row: usize, _col: usize, _value: f64) {}
}

/// How a [`JacobianSink`] takes a stiffness coupling that is dense but a product of sparse
/// factors, `K = A B^-1 C` (an effect writes `A` into the stiffness rows of auxiliary unknowns
/// `w`, and the equations `C dx - B w = 0` into their rows; the Schur complement of the bordered
/// system is then `K` exactly).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AuxSupport {
    /// No auxiliary unknowns: the effect emits the dense blocks.
    None,
    /// Stiffness is not assembled (`c_K = 0`): the coupling may be left out altogether.
    Skip,
    /// Auxiliary unknowns are taken.
    Rows,
}

/// A group of force elements of one kind.
pub trait ForceEffect: Send + Sync + std::fmt::Debug {
    /// Short name used in messages.
    fn name(&self) -> &str;

    /// Adds the generalized forces (length `n_v`): forces [N] in the world frame on translations,
    /// torques [N m] in the body frame on rotations.
    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]);

    /// Adds `K = -df/dx` and `D = -df/dv` blocks (they serve only as Newton iteration
    /// matrices: an effect whose tangent makes Newton cycle may give another slope and says
    /// so, as [`hinge_friction`] does).
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

    /// Whether [`ForceEffect::dissipated_power`] or [`ForceEffect::input_power`] can be other
    /// than zero (fixed for the effect's lifetime). `false` lets a model without such effects
    /// skip the power evaluation at every stage.
    fn has_power(&self) -> bool {
        true
    }

    /// Number of discrete memory values the effect keeps in the state (contact onset speeds,
    /// latch flags); they change only between steps, in [`ForceEffect::update_memory`].
    fn n_memory(&self) -> usize {
        0
    }

    /// Initial memory values.
    fn init_memory(&self, _ctx: &EvalCtx, _memory: &mut [f64]) {}

    /// Updates the memory after an accepted step (the context's `memory` holds the old values).
    fn update_memory(&self, _ctx: &EvalCtx, _memory: &mut [f64]) -> MemoryChange {
        MemoryChange::None
    }

    /// Number of contact events (closing and opening of a contact) an integrator may locate in
    /// time, one per contact whose force depends on the state at its onset (a recorded approach
    /// speed) or is not smooth where it closes and opens; see
    /// [`ForceEffect::contact_event_functions`]. 0: nothing to locate, nothing is evaluated.
    fn n_contact_events(&self) -> usize {
        0
    }

    /// Writes into `out` (length [`ForceEffect::n_contact_events`]) one event function per
    /// contact whose sign change from `<= 0` to `> 0` within a step is the contact's next event
    /// under the current memory (`ctx.memory`): the penetration [m] of a contact the memory says
    /// is separated (it closes when it turns positive), minus the penetration of a closed one
    /// (it opens when the penetration turns negative).
    fn contact_event_functions(&self, _ctx: &EvalCtx, _out: &mut [f64]) {}

    /// Records in `memory` (the effect's own, as the step's memory update left it) that the
    /// event of contact `i` happens at the state of `ctx`, where an integrator located it (event
    /// function zero to the integrator's accuracy, either sign): a contact that `ctx.memory` (the
    /// memory at the step's start, under which the event function was defined) says is
    /// separated closes here with the approach speed of this state, a closed one opens, whatever
    /// the memory update decided from the sign of a penetration that is zero to round-off.
    /// Returns how the forces at this state change from those of `memory` as it came in
    /// ([`MemoryChange::Smooth`] when they do not jump).
    fn record_contact_event(&self, _ctx: &EvalCtx, _i: usize, _memory: &mut [f64]) -> MemoryChange {
        MemoryChange::None
    }

    /// Writes into `out` (cleared by the caller) the discrete decisions the effect takes inside
    /// an evaluation at `ctx` (slip modes of rope contact nodes), for an integrator to hold
    /// within a step's Newton iteration: evaluated with them as `ctx.frozen`, the forces are the
    /// smooth branch through `ctx`, and Newton cannot cycle between branches. Nothing written:
    /// the effect has no such decisions. A non-empty `ctx.frozen` holds the decisions being
    /// replaced (they failed [`ForceEffect::frozen_consistent`] at `ctx`).
    fn freeze(&self, _ctx: &EvalCtx, _out: &mut Vec<f64>) {}

    /// Whether the effect takes decisions [`ForceEffect::freeze`] can hold (fixed for the
    /// effect's lifetime); models without any skip freezing altogether.
    fn has_decisions(&self) -> bool {
        false
    }

    /// Whether the decisions `ctx.frozen` are the ones the effect takes itself at `ctx` (checked
    /// on a converged Newton iterate: if not, the iteration continues with them re-decided), to
    /// the integrator's position tolerance `atol + rtol * scale` (the effect knows its scales).
    fn frozen_consistent(&self, _ctx: &EvalCtx, _rtol: f64, _atol: f64) -> bool {
        true
    }
}
