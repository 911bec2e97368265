//! The multibody system as integrators see it: flat vectors, the retraction, residual pieces and
//! the blocks of Newton matrices.
//!
//! Equations (index 3): `M(q) v_dot + G(q)^T lambda = f(q, v, t)`, `Phi(q, t) = 0`, with
//! `q_dot = H(q) v` expressed through the retraction of [`crate::model::Model`]. Integrators ask for
//! `f`, `M a`, `Phi`, `G x`, `G^T y`, `gamma`, and for Newton matrices built from
//! `c_M M + c_D D + c_K K` and `G` blocks at offsets they choose.
//!
//! Modal (flexible) bodies add a full `(6 + n)` block `M(a)` and their floating-frame forces
//! (module `dae::modal`); force effects acting at flexible-body nodes see *node bodies*, rigid
//! frames riding on the nodes, whose forces and Jacobian blocks are mapped to the modal bodies
//! (module `dae::node_body`, private; its doc has the formulas); joint rows at node frames
//! carry modal columns (module `dae::rows`). `M(a)` in [`System::mass_mul`] is that of the last
//! kinematics update (every integrator calls it right after `forces` at the same state).

pub mod conditioning;
pub mod dense_lu;
pub mod linear;
pub mod linearize;
mod modal;
mod momentum;
mod node_body;
mod range_space;
mod redundancy;
mod rows;
mod sink;
mod sparse_lu;
mod split_lu;

use crate::effect::constraint::RowEval;
use crate::effect::{EvalCtx, ForceEffect, MemoryChange};
use crate::math::{Mat3, Vec3, skew};
use crate::model::kinematics::{self, BodyKin, kin_of};
use crate::model::{BodyId, BodyKind, Model};
use linear::LinearSolver;
use modal::{ModalTerms, modal_terms};
pub use momentum::Momentum;
use node_body::{NodeBodyTerms, node_body_terms};
pub use range_space::RangeSpace;
use sink::TripletSink;
use std::sync::Arc;

/// The assembled system with its evaluation scratch (no allocation per evaluation).
#[derive(Debug, Clone)]
pub struct System {
    pub model: Arc<Model>,
    /// Current model inputs.
    pub inputs: Vec<f64>,
    /// Bodies of each full constraint row.
    row_bodies: Vec<[BodyId; 2]>,
    /// Flexible-body nodes of the frames of each full row (`None`: not on a node).
    row_nodes: Vec<[Option<usize>; 2]>,
    /// Joint (index in `model.joints`) of each full row.
    row_joint: Vec<usize>,
    /// Modal columns of node frames: full row `r`, side `s` has `n` entries from
    /// `row_modal[row_modal_at[r][s]..]` (`usize::MAX` when the side has none).
    row_modal: Vec<f64>,
    row_modal_at: Vec<[usize; 2]>,
    /// Index into `modal` of each body (`None` for rigid bodies and particles).
    modal_of: Vec<Option<usize>>,
    /// Indices of the independent (active) rows among the full rows.
    active: Vec<usize>,
    /// For each full row, whether it lies in a component of the joint graph with a closed loop
    /// (the rows whose rank can drop; see [`System::active_row_in_loop`]).
    row_in_loop: Vec<bool>,
    /// Messages for the log that the integrators raised (e.g. a singular configuration), taken
    /// by [`System::take_solver_notes`].
    solver_notes: Vec<String>,
    kins: Vec<BodyKin>,
    rows_full: Vec<RowEval>,
    /// For each full row, its index among the active rows (`None`: left out as redundant).
    active_of_full: Vec<Option<usize>>,
    /// Active constraint rows of the last [`System::eval_constraints`].
    pub rows: Vec<RowEval>,
    /// Number of force/constraint evaluations (statistics).
    pub n_evals: u64,
    /// Memory of each force effect: `memory_offsets[i]..memory_offsets[i + 1]`.
    memory_offsets: Vec<usize>,
    /// Contact events of each force effect: `event_offsets[i]..event_offsets[i + 1]` (see
    /// [`System::contact_event_functions`]).
    event_offsets: Vec<usize>,
    /// Current effect memory (copied from the state before each evaluation).
    pub memory: Vec<f64>,
    /// Decisions of each force effect frozen within a Newton iteration (see
    /// [`System::freeze_decisions`]); seen by the effects only while `frozen_on`.
    frozen: Vec<Vec<f64>>,
    frozen_on: bool,
    /// The last step converged on the frozen decisions (see [`System::thaw_accepted`]): the
    /// memory update evaluates the effects on them.
    frozen_accepted: bool,
    /// Whether any force effect takes such decisions (else freezing is skipped).
    decides: bool,
    /// Whether any force effect or modal body can dissipate or feed power (else
    /// [`System::powers`] is zero without an evaluation).
    has_power: bool,
    /// Scratch for the next frozen decisions (the effects see the current ones when deciding).
    frozen_next: Vec<Vec<f64>>,
    /// Floating-frame terms of the modal bodies, at the last kinematics update.
    modal: Vec<ModalTerms>,
    /// Node bodies (frames on modal-body nodes where force effects act), same order as
    /// `model.node_bodies`.
    nodes: Vec<NodeBodyTerms>,
    /// Force scratch of length `n_v + 6 * nodes.len()` (node-body forces past `n_v`).
    f_ext: Vec<f64>,
    /// `(q, v)` of the last kinematics update: an update at the same point (bit for bit) is
    /// skipped, so `forces` followed by `eval_constraints` evaluates the kinematics once.
    kin_at: Option<(Vec<f64>, Vec<f64>)>,
}

/// Bitwise equality of two slices (so `-0.0` and `0.0` differ and `NaN` equals itself).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

impl System {
    /// Prepares the system; constraint rows that are redundant at the initial configuration
    /// (e.g. in a 3D four-bar) are found by a rank-revealing QR and left out.
    pub fn new(model: Arc<Model>) -> Result<Self, String> {
        let mut row_bodies = Vec::new();
        let mut row_nodes = Vec::new();
        let mut row_joint = Vec::new();
        for (ji, j) in model.joints.iter().enumerate() {
            for _ in 0..j.kind.n_rows() {
                row_bodies.push([j.frame_i.body, j.frame_j.body]);
                row_nodes.push([j.frame_i.node, j.frame_j.node]);
                row_joint.push(ji);
            }
        }
        let modal = modal_terms(&model);
        let mut modal_of = vec![None; model.bodies.len()];
        for (i, m) in modal.iter().enumerate() {
            modal_of[m.body] = Some(i);
        }
        let n_full = row_bodies.len();
        let mut memory_offsets = vec![0];
        for e in &model.forces {
            memory_offsets.push(memory_offsets.last().copied().unwrap_or(0) + e.n_memory());
        }
        let n_mem = *memory_offsets.last().unwrap_or(&0);
        let mut event_offsets = vec![0];
        for e in &model.forces {
            event_offsets.push(event_offsets.last().copied().unwrap_or(0) + e.n_contact_events());
        }
        let nodes = node_body_terms(&model, &modal, &modal_of);
        let f_ext = vec![0.0; model.n_v + 6 * nodes.len()];
        let mut sys = System {
            memory_offsets,
            event_offsets,
            memory: vec![0.0; n_mem],
            frozen: vec![Vec::new(); model.forces.len()],
            frozen_on: false,
            frozen_accepted: false,
            decides: model.forces.iter().any(|e| e.has_decisions()),
            has_power: !modal.is_empty() || model.forces.iter().any(|e| e.has_power()),
            frozen_next: vec![Vec::new(); model.forces.len()],
            inputs: vec![0.0; model.n_inputs()],
            row_bodies,
            row_joint,
            row_nodes,
            row_modal: Vec::new(),
            row_modal_at: Vec::with_capacity(n_full),
            modal_of,
            active: (0..n_full).collect(),
            row_in_loop: Vec::new(),
            solver_notes: Vec::new(),
            kins: Vec::with_capacity(model.bodies.len()),
            rows_full: Vec::with_capacity(n_full),
            active_of_full: (0..n_full).map(Some).collect(),
            rows: Vec::with_capacity(n_full),
            n_evals: 0,
            modal,
            nodes,
            f_ext,
            kin_at: None,
            model,
        };
        let (q0, v0) = (sys.model.q0.clone(), sys.model.v0.clone());
        sys.eval_constraints(0.0, &q0, &v0);
        let modal_cols = |r: usize, dense: &mut [f64]| sys.for_row_modal(r, |c, g| dense[c] += g);
        let active = redundancy::independent_rows(
            &sys.model,
            &sys.row_bodies,
            sys.full_rows(),
            &modal_cols,
        )?;
        sys.active_of_full = vec![None; n_full];
        for (a, &r) in active.iter().enumerate() {
            sys.active_of_full[r] = Some(a);
        }
        sys.active = active;
        sys.row_in_loop = redundancy::rows_in_loops(&sys.model, &sys.row_bodies);
        Ok(sys)
    }

    /// Number of generalized speeds.
    pub fn n_v(&self) -> usize {
        self.model.n_v
    }

    /// Number of position coordinates.
    pub fn n_q(&self) -> usize {
        self.model.n_q
    }

    /// Number of independent constraint rows.
    pub fn n_c(&self) -> usize {
        self.active.len()
    }

    /// Checks that every constraint row dropped as redundant is satisfied at `(q, t)` to `tol`:
    /// a dependent row with a residual is a contradiction between joints, not a redundancy.
    pub fn check_dropped_rows(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        tol: f64,
    ) -> Result<(), String> {
        self.eval_constraints(t, q, v);
        let mut r0 = 0;
        for j in &self.model.joints {
            let n = j.kind.n_rows();
            for r in r0..r0 + n {
                if !self.active.contains(&r) && self.rows_full[r].phi.abs() > tol {
                    return Err(format!(
                        "joint '{}' contradicts the other joints: its dependent constraint row {} keeps a residual of {:.3e} (the initial poses cannot satisfy all joints)",
                        j.name,
                        r - r0,
                        self.rows_full[r].phi.abs()
                    ));
                }
            }
            r0 += n;
        }
        Ok(())
    }

    /// Positions in `lambda` (active rows) of the rows of joint `joint` (index in
    /// `model.joints`); rows dropped as redundant are absent.
    pub fn joint_multiplier_rows(&self, joint: usize) -> Vec<usize> {
        self.active
            .iter()
            .enumerate()
            .filter(|(_, f)| self.row_joint[**f] == joint)
            .map(|(i, _)| i)
            .collect()
    }

    /// Whether active row `r` lies in a closed kinematic loop (only such rows can lose rank as
    /// the mechanism moves).
    pub fn active_row_in_loop(&self, r: usize) -> bool {
        self.active
            .get(r)
            .is_some_and(|&f| self.row_in_loop.get(f).copied().unwrap_or(false))
    }

    /// Whether any active row lies in a closed kinematic loop.
    pub fn has_loops(&self) -> bool {
        self.row_in_loop.iter().any(|&x| x)
    }

    /// Index in `model.joints` of the joint of active row `r`.
    pub fn joint_of_active_row(&self, r: usize) -> Option<usize> {
        self.row_joint.get(*self.active.get(r)?).copied()
    }

    /// Queues a message for the log (a model forwards it, e.g. as an FMU warning).
    pub fn push_solver_note(&mut self, note: String) {
        self.solver_notes.push(note);
    }

    /// The queued log messages, oldest first; the queue is emptied.
    pub fn take_solver_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.solver_notes)
    }

    /// Number of constraint rows dropped as redundant.
    pub fn n_redundant(&self) -> usize {
        self.row_bodies.len() - self.active.len()
    }

    /// Body kinematics of the last evaluation.
    pub fn kins(&self) -> &[BodyKin] {
        &self.kins
    }

    /// Records `(q, v)` as the point of the kept kinematics; `false` when it already is (bit for
    /// bit).
    fn move_kinematics_point(&mut self, q: &[f64], v: &[f64]) -> bool {
        match &mut self.kin_at {
            Some((kq, kv)) if same_bits(kq, q) && same_bits(kv, v) => false,
            Some((kq, kv)) => {
                kq.clear();
                kq.extend_from_slice(q);
                kv.clear();
                kv.extend_from_slice(v);
                true
            }
            None => {
                self.kin_at = Some((q.to_vec(), v.to_vec()));
                true
            }
        }
    }

    /// Evaluates body kinematics at `(q, v)`.
    pub fn update_kinematics(&mut self, q: &[f64], v: &[f64]) {
        if !self.move_kinematics_point(q, v) {
            return;
        }
        kinematics::evaluate(&self.model, q, v, &mut self.kins);
        for m in &mut self.modal {
            m.update(q, v, &self.kins[m.body]);
        }
        for nb in &mut self.nodes {
            nb.update(&self.modal);
        }
        // node bodies after the bodies, in reverse order (see `kinematics::kin_of`)
        for nb in self.nodes.iter().rev() {
            self.kins.push(nb.kin);
        }
    }

    /// Takes the kinematics at `(q, v)` from a caller that has every body's pose and motion at
    /// hand (the joint-coordinate path's forward pass) instead of evaluating them from `q`, `v`:
    /// `fill` writes one [`BodyKin`] per body of `model.bodies`, in their order, consistent with
    /// `q` and `v`. The next force, power or constraint evaluation at the same `(q, v)` uses
    /// them. Models with modal bodies evaluate as usual (their floating-frame terms need it).
    pub fn set_kinematics(&mut self, q: &[f64], v: &[f64], fill: impl FnOnce(&mut [BodyKin])) {
        if !self.modal.is_empty() || !self.nodes.is_empty() {
            self.update_kinematics(q, v);
            return;
        }
        self.move_kinematics_point(q, v);
        self.kins.resize(self.model.bodies.len(), BodyKin::GROUND);
        fill(&mut self.kins);
    }

    /// Adds the force effects' generalized forces to `f` (length `n_v`), mapping node-body
    /// forces to their modal bodies; leaves the node-body forces in `f_ext[n_v..]`.
    fn add_effect_forces(&mut self, t: f64, f: &mut [f64]) {
        self.add_selected_effect_forces(t, f, &|_| true);
    }

    /// Generalized forces `f` (length `n_v`) at `(t, q, v)` of the force effects whose name
    /// `keep` accepts, with the current memory: a rigid body's block is the force [N] at its
    /// centre of mass (world) and the moment [N m] about it (body frame), a modal body's the
    /// force at its frame origin and the moment about that origin plus its modal forces. No
    /// gyroscopic, floating-frame inertia or modal gravity terms (see [`System::forces`]).
    pub fn effect_forces(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        keep: &dyn Fn(&str) -> bool,
        f: &mut [f64],
    ) {
        self.update_kinematics(q, v);
        f.fill(0.0);
        self.add_selected_effect_forces(t, f, &|e: &dyn ForceEffect| keep(e.name()));
    }

    /// [`System::add_effect_forces`] of the effects `keep` accepts.
    fn add_selected_effect_forces(
        &mut self,
        t: f64,
        f: &mut [f64],
        keep: &dyn Fn(&dyn ForceEffect) -> bool,
    ) {
        if self.nodes.is_empty() {
            for (i, e) in self.model.forces.iter().enumerate() {
                if keep(e.as_ref()) {
                    e.add_forces(&self.ctx(t, i), f);
                }
            }
            return;
        }
        let mut fe = std::mem::take(&mut self.f_ext);
        fe.fill(0.0);
        for (i, e) in self.model.forces.iter().enumerate() {
            if keep(e.as_ref()) {
                e.add_forces(&self.ctx(t, i), &mut fe);
            }
        }
        let nv = self.model.n_v;
        for (x, y) in f.iter_mut().zip(&fe[..nv]) {
            *x += y;
        }
        for (j, nb) in self.nodes.iter().enumerate() {
            nb.add_mapped_force(&fe[nv + 6 * j..nv + 6 * j + 6], f);
        }
        self.f_ext = fe;
    }

    /// Evaluation context of force effect `i`.
    fn ctx(&self, t: f64, i: usize) -> EvalCtx<'_> {
        let m = &self.memory[self.memory_offsets[i]..self.memory_offsets[i + 1]];
        EvalCtx {
            t,
            kins: &self.kins,
            inputs: &self.inputs,
            memory: m,
            frozen: if self.frozen_on { &self.frozen[i] } else { &[] },
        }
    }

    /// Freezes the discrete decisions the force effects take inside an evaluation at `(t, q, v)`
    /// (rope slip modes, see [`crate::effect::ForceEffect::freeze`]): later evaluations use them
    /// until [`System::thaw`]. For a step's Newton iteration, which then solves one smooth
    /// branch. Called while frozen, the effects see the decisions they replace.
    pub fn freeze_decisions(&mut self, t: f64, q: &[f64], v: &[f64]) {
        if !self.decides {
            return;
        }
        self.update_kinematics(q, v);
        for i in 0..self.model.forces.len() {
            let mut out = std::mem::take(&mut self.frozen_next[i]);
            out.clear();
            self.model.forces[i].freeze(&self.ctx(t, i), &mut out);
            self.frozen_next[i] = std::mem::replace(&mut self.frozen[i], out);
        }
        self.frozen_on = true;
        self.frozen_accepted = false;
    }

    /// The frozen decisions as plain numbers into `out` (cleared): 0 when none are frozen (the
    /// effects decide at every evaluation; what an earlier freeze left is not used), else 1
    /// and per force effect its count and values; nothing for systems whose effects take no
    /// decisions. A Newton matrix depends on them (see `JacobianPoint`).
    pub fn frozen_record(&self, out: &mut Vec<f64>) {
        out.clear();
        if !self.decides {
            return;
        }
        if !self.frozen_on {
            out.push(0.0);
            return;
        }
        out.push(1.0);
        for f in &self.frozen {
            out.push(f.len() as f64);
            out.extend_from_slice(f);
        }
    }

    /// Sets the frozen decisions [`System::frozen_record`] wrote; `false` (and nothing changed)
    /// when `record` is empty or does not fit this system's effects.
    pub fn set_frozen_record(&mut self, record: &[f64]) -> bool {
        let Some((&on, mut rest)) = record.split_first() else {
            return false;
        };
        if !self.decides || !(on == 0.0 || on == 1.0) {
            return false;
        }
        if on == 0.0 {
            if !rest.is_empty() {
                return false;
            }
            self.frozen_on = false;
            return true;
        }
        let mut parts = Vec::with_capacity(self.frozen.len());
        for _ in 0..self.frozen.len() {
            let Some((&n, tail)) = rest.split_first() else {
                return false;
            };
            if !(n >= 0.0 && n.fract() == 0.0 && n <= tail.len() as f64) {
                return false;
            }
            let (values, tail) = tail.split_at(n as usize);
            parts.push(values);
            rest = tail;
        }
        if !rest.is_empty() {
            return false;
        }
        for (f, values) in self.frozen.iter_mut().zip(parts) {
            f.clear();
            f.extend_from_slice(values);
        }
        self.frozen_on = true;
        true
    }

    /// Ends [`System::freeze_decisions`]: the effects decide at every evaluation again.
    /// Leaves the record of [`System::thaw_accepted`] alone (a step's own thaw follows it).
    pub fn thaw(&mut self) {
        self.frozen_on = false;
    }

    /// Ends [`System::freeze_decisions`] at a converged step: the next
    /// [`System::update_memory`] evaluates the effects on the decisions the step was solved on
    /// (if any were frozen), so that the memory holds what acted, not what a fresh decision at
    /// the same state would take (the two may differ within the position tolerance, see
    /// [`System::frozen_consistent`]).
    pub fn thaw_accepted(&mut self) {
        self.frozen_accepted = self.frozen_on;
        self.frozen_on = false;
    }

    /// Whether the frozen decisions are the ones the effects take themselves at `(t, q, v)`
    /// to the position tolerance `rtol`, `atol` (true when nothing is frozen).
    pub fn frozen_consistent(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        rtol: f64,
        atol: f64,
    ) -> bool {
        if !self.frozen_on {
            return true;
        }
        self.update_kinematics(q, v);
        (0..self.model.forces.len())
            .all(|i| self.model.forces[i].frozen_consistent(&self.ctx(t, i), rtol, atol))
    }

    /// Range of the memory of the first force effect called `name` in the state's memory.
    pub fn memory_range(&self, name: &str) -> Option<std::ops::Range<usize>> {
        let i = self.model.forces.iter().position(|e| e.name() == name)?;
        Some(self.memory_offsets[i]..self.memory_offsets[i + 1])
    }

    /// Number of effect memory values.
    pub fn n_memory(&self) -> usize {
        self.memory.len()
    }

    /// Initial effect memory at `(q, v, t)`.
    pub fn init_memory(&mut self, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        self.update_kinematics(q, v);
        let mut out = vec![0.0; self.memory.len()];
        for (i, e) in self.model.forces.iter().enumerate() {
            let (a, b) = (self.memory_offsets[i], self.memory_offsets[i + 1]);
            let ctx = self.ctx(t, i);
            e.init_memory(&ctx, &mut out[a..b]);
        }
        self.memory.copy_from_slice(&out);
        out
    }

    /// Updates the effect memory in `memory` after an accepted step at `(q, v, t)`; returns the
    /// strongest change.
    pub fn update_memory(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        memory: &mut [f64],
    ) -> MemoryChange {
        if memory.is_empty() {
            return MemoryChange::None;
        }
        self.memory.copy_from_slice(memory);
        self.update_kinematics(q, v);
        let mut change = MemoryChange::None;
        for (i, e) in self.model.forces.iter().enumerate() {
            let (a, b) = (self.memory_offsets[i], self.memory_offsets[i + 1]);
            if a == b {
                continue;
            }
            let ctx = EvalCtx {
                frozen: if self.frozen_accepted {
                    &self.frozen[i]
                } else {
                    &[]
                },
                ..self.ctx(t, i)
            };
            change = change.max(e.update_memory(&ctx, &mut memory[a..b]));
        }
        self.frozen_accepted = false;
        self.memory.copy_from_slice(memory);
        change
    }

    /// Number of contact events the force effects expose (0: no contact whose closing or
    /// opening matters, and integrators evaluate nothing for events).
    pub fn n_contact_events(&self) -> usize {
        self.event_offsets.last().copied().unwrap_or(0)
    }

    /// The contact event functions at `(t, q, v)` under the current memory, into `out` (length
    /// [`System::n_contact_events`]): a change from `<= 0` to `> 0` within a step is a contact
    /// closing or opening (see [`crate::effect::ForceEffect::contact_event_functions`]).
    pub fn contact_event_functions(&mut self, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.update_kinematics(q, v);
        for (i, e) in self.model.forces.iter().enumerate() {
            let (a, b) = (self.event_offsets[i], self.event_offsets[i + 1]);
            if a < b {
                e.contact_event_functions(&self.ctx(t, i), &mut out[a..b]);
            }
        }
    }

    /// Records in `memory` (the state's effect memory after the step's memory update, which the
    /// system's copy then follows) that contact event `event` (index into
    /// [`System::contact_event_functions`], as defined under `step_start`, the memory at the
    /// step's start) happens at `(t, q, v)`; returns how the forces there change.
    pub fn record_contact_event(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        step_start: &[f64],
        memory: &mut [f64],
        event: usize,
    ) -> MemoryChange {
        let Some(i) = (0..self.model.forces.len())
            .find(|&i| (self.event_offsets[i]..self.event_offsets[i + 1]).contains(&event))
        else {
            return MemoryChange::None;
        };
        if memory.len() != self.memory.len() || step_start.len() != memory.len() {
            return MemoryChange::None;
        }
        self.memory.copy_from_slice(step_start);
        self.update_kinematics(q, v);
        let (a, b) = (self.memory_offsets[i], self.memory_offsets[i + 1]);
        let ctx = self.ctx(t, i);
        let local = event - self.event_offsets[i];
        let change = self.model.forces[i].record_contact_event(&ctx, local, &mut memory[a..b]);
        self.memory.copy_from_slice(memory);
        change
    }

    /// `out = M a` (block diagonal mass matrix; the blocks of modal bodies `M(a)` are those of
    /// the last kinematics update, i.e. of the last `forces`/`eval_constraints` call).
    pub fn mass_mul(&self, a: &[f64], out: &mut [f64]) {
        for b in &self.model.bodies {
            let o = b.v_offset;
            match &b.kind {
                BodyKind::Rigid { mass, inertia } => {
                    for i in 0..3 {
                        out[o + i] = mass * a[o + i];
                    }
                    let w = inertia * Vec3::new(a[o + 3], a[o + 4], a[o + 5]);
                    out[o + 3..o + 6].copy_from_slice(w.as_slice());
                }
                BodyKind::Particle { mass } => {
                    for i in 0..3 {
                        out[o + i] = mass * a[o + i];
                    }
                }
                BodyKind::Modal { .. } => {}
            }
        }
        for m in &self.modal {
            m.mass_mul(a, out);
        }
    }

    /// Generalized forces `f(q, v, t)` including the gyroscopic term `-omega x J omega`.
    pub fn forces(&mut self, t: f64, q: &[f64], v: &[f64], f: &mut [f64]) {
        self.n_evals += 1;
        self.update_kinematics(q, v);
        f.fill(0.0);
        for (b, k) in self.model.bodies.iter().zip(&self.kins) {
            if let BodyKind::Rigid { inertia, .. } = &b.kind {
                let g = -k.omega.cross(&(inertia * k.omega));
                for i in 0..3 {
                    f[k.col + 3 + i] += g[i];
                }
            }
        }
        self.add_effect_forces(t, f);
        for m in &self.modal {
            m.add_forces(self.model.gravity.as_ref(), f);
        }
    }

    /// Adds `c_M M + c_D D + c_K K` at `(off, off)` into `lin`, evaluated at `(q, v, t)`.
    #[allow(clippy::too_many_arguments)]
    pub fn add_dynamics_matrix(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        cm: f64,
        cd: f64,
        ck: f64,
        lin: &mut LinearSolver,
        off: usize,
    ) {
        self.add_dynamics_matrix_at(t, q, v, [cm, cd, ck], lin, off, off);
    }

    /// Adds `c[0] M + c[1] D + c[2] K` at `(row_off, col_off)` into `lin`.
    #[allow(clippy::too_many_arguments)]
    pub fn add_dynamics_matrix_at(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        c: [f64; 3],
        lin: &mut LinearSolver,
        row_off: usize,
        col_off: usize,
    ) {
        let [cm, cd, ck] = c;
        self.update_kinematics(q, v);
        for (b, k) in self.model.bodies.iter().zip(&self.kins) {
            let (o, oc) = (row_off + k.col, col_off + k.col);
            match &b.kind {
                BodyKind::Rigid { mass, inertia } => {
                    for i in 0..3 {
                        lin.push(o + i, oc + i, cm * mass);
                    }
                    // gyroscopic D = omega~ J - (J omega)~
                    let dg: Mat3 = skew(&k.omega) * inertia - skew(&(inertia * k.omega));
                    let blk = cm * inertia + cd * dg;
                    for c in 0..3 {
                        for r in 0..3 {
                            lin.push(o + 3 + r, oc + 3 + c, blk[(r, c)]);
                        }
                    }
                }
                BodyKind::Particle { mass } => {
                    for i in 0..3 {
                        lin.push(o + i, oc + i, cm * mass);
                    }
                }
                BodyKind::Modal { .. } => {}
            }
        }
        for m in &self.modal {
            let g = self.model.gravity.as_ref();
            m.add_newton_block(g, cm, cd, ck, lin, row_off, col_off);
        }
        if !self.nodes.is_empty() && ck != 0.0 {
            // geometric terms of node bodies need their forces; W their velocity transport
            let mut scratch = vec![0.0; self.model.n_v];
            self.add_effect_forces(t, &mut scratch);
            let nv = self.model.n_v;
            for (j, nb) in self.nodes.iter_mut().enumerate() {
                nb.update_w(&self.modal, v);
                let geo = nb.geometric(&self.modal, &self.f_ext[nv + 6 * j..nv + 6 * j + 6]);
                let (ro, co) = (row_off + nb.body_col, col_off + nb.body_col);
                for c in 0..geo.ncols() {
                    for r in 0..geo.nrows() {
                        lin.push(ro + r, co + c, ck * geo[(r, c)]);
                    }
                }
            }
        }
        if ck == 0.0 && cd == 0.0 {
            // effects contribute only K and D blocks
            return;
        }
        let mut sink = TripletSink {
            lin,
            ck,
            cd,
            row_off,
            col_off,
            n_v: self.model.n_v,
            nodes: &self.nodes,
        };
        for (i, e) in self.model.forces.iter().enumerate() {
            e.add_jacobian(&self.ctx(t, i), &mut sink);
        }
    }

    /// Kinetic and potential energy [J] at `(q, v, t)`.
    pub fn energy(&mut self, t: f64, q: &[f64], v: &[f64]) -> (f64, f64) {
        let mut mv = vec![0.0; v.len()];
        self.energy_with(t, q, v, &mut mv)
    }

    /// [`System::energy`] with caller-provided scratch `mv` (length `n_v`): no allocation.
    pub fn energy_with(&mut self, t: f64, q: &[f64], v: &[f64], mv: &mut [f64]) -> (f64, f64) {
        self.update_kinematics(q, v);
        self.mass_mul(v, mv);
        let kinetic = 0.5 * v.iter().zip(mv.iter()).map(|(a, b)| a * b).sum::<f64>();
        let potential = self
            .model
            .forces
            .iter()
            .enumerate()
            .map(|(i, e)| e.potential_energy(&self.ctx(t, i)))
            .sum::<f64>()
            + self
                .modal
                .iter()
                .map(|m| m.potential_energy(self.model.gravity.as_ref()))
                .sum::<f64>();
        (kinetic, potential)
    }

    /// Power [W] the driven (rheonomic) constraint rows put in with the multipliers `lambda`:
    /// the sum of `lambda_i dphi_i/dt` over the active rows.
    pub fn drive_power(&self, lambda: &[f64]) -> f64 {
        self.rows.iter().zip(lambda).map(|(r, l)| l * r.phi_t).sum()
    }

    /// Dissipated power and input power [W] at `(q, v, t)`.
    pub fn powers(&mut self, t: f64, q: &[f64], v: &[f64]) -> (f64, f64) {
        if !self.has_power {
            return (0.0, 0.0);
        }
        self.update_kinematics(q, v);
        let forces = &self.model.forces;
        let diss = forces
            .iter()
            .enumerate()
            .map(|(i, e)| e.dissipated_power(&self.ctx(t, i)))
            .sum::<f64>()
            + self.modal.iter().map(|m| m.dissipated_power()).sum::<f64>();
        let input = forces
            .iter()
            .enumerate()
            .map(|(i, e)| e.input_power(&self.ctx(t, i)))
            .sum();
        (diss, input)
    }

    /// Kinematics of a body in the last evaluation.
    pub fn kin(&self, id: BodyId) -> &BodyKin {
        kin_of(&self.kins, id)
    }
}
