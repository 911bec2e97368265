//! A simulation: system, state and integrator together, with inputs, energy bookkeeping and exact
//! snapshots.

use crate::dae::System;
use crate::integrator::{
    self, Integrator, IntegratorKind, MemoryHook, Settings, SolverError, Stats, StepAction,
    StepHook,
};
use crate::model::Model;
use crate::state::State;
use std::sync::Arc;

/// Energy bookkeeping [J].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Energy {
    pub kinetic: f64,
    pub potential: f64,
    /// Dissipated since the start.
    pub dissipated: f64,
    /// Work of inputs and drives since the start.
    pub input: f64,
}

impl Energy {
    /// `kinetic + potential + dissipated - input`: constant for an exact solution.
    pub fn balance(&self) -> f64 {
        self.kinetic + self.potential + self.dissipated - self.input
    }
}

/// A running simulation.
#[derive(Debug)]
pub struct Simulation {
    pub system: System,
    pub state: State,
    integrator: Box<dyn Integrator>,
    pub settings: Settings,
    /// Warnings raised while setting up (e.g. `rho_inf = 1`).
    pub warnings: Vec<String>,
    /// Solver of [`Simulation::consistent_multipliers`], kept so its sparse pattern analysis
    /// is done once, not at every output (scratch: no influence on results).
    kkt: crate::integrator::kkt::Kkt,
    /// Scratch of the range-space solve of [`Simulation::consistent_multipliers`].
    range_space: crate::dae::RangeSpace,
    /// The point `(t, q, v, memory, inputs)` at which the state's multipliers are the index-1
    /// ones (left by an integrator that solves them there, [`Integrator::index1_multipliers`]);
    /// [`Simulation::consistent_multipliers`] returns them while the point is unchanged, bit for
    /// bit, instead of solving again. The buffer is kept (no allocation per call); the flag says
    /// whether it holds such a point.
    multipliers_at: Vec<f64>,
    multipliers_valid: bool,
}

impl Clone for Simulation {
    fn clone(&self) -> Self {
        Simulation {
            system: self.system.clone(),
            state: self.state.clone(),
            integrator: self.integrator.clone_box(),
            settings: self.settings,
            warnings: self.warnings.clone(),
            kkt: self.kkt.clone(),
            range_space: self.range_space.clone(),
            multipliers_at: self.multipliers_at.clone(),
            multipliers_valid: self.multipliers_valid,
        }
    }
}

/// Tightest rtol at which [`IntegratorKind::Verner87Tree`] runs without a warning: measured on the
/// pendulum chains (docs/chain_solve.md), its estimate stays above round-off down to 1e-6 on 100
/// rods (at 1e-7 the run took 19,632 steps where 1e-6 took 79; 32 rods hold to 1e-7).
pub const VERNER87_RTOL_FLOOR: f64 = 1e-6;

impl Simulation {
    /// Validates settings, assembles the system and finds consistent initial conditions at `t0`.
    pub fn new(
        model: Model,
        kind: IntegratorKind,
        settings: Settings,
        t0: f64,
    ) -> Result<Self, String> {
        Self::with_inputs(model, kind, settings, t0, &[])
    }

    /// As [`Simulation::new`] with initial input values.
    pub fn with_inputs(
        model: Model,
        kind: IntegratorKind,
        settings: Settings,
        t0: f64,
        inputs: &[f64],
    ) -> Result<Self, String> {
        let mut warnings = settings.validate()?;
        if kind == IntegratorKind::Verner87Tree && settings.rtol < VERNER87_RTOL_FLOOR {
            warnings.push(format!(
                "verner87-tree at rtol {:e}: below rtol {VERNER87_RTOL_FLOOR:e} its error estimate can sink into the round-off its large coefficients amplify (chains of 100 rods at 1e-7, of 32 at 1e-8, of 8 at 1e-11), and then its steps shrink without end; verner65-tree or dopri5-tree resolve such tolerances",
                settings.rtol
            ));
        }
        if !t0.is_finite() {
            return Err(format!("start time must be finite, got {t0}"));
        }
        let mut system = System::new(Arc::new(model))?;
        for (i, &u) in inputs.iter().enumerate() {
            if i < system.inputs.len() {
                system.inputs[i] = u;
            }
        }
        let mut state = integrator::init::initial_state(&system, t0);
        // Effects whose forces depend on their memory (e.g. rope material coordinates) need it
        // before the first force evaluation of the consistent initialization.
        state.memory = system.init_memory(state.t, &state.q, &state.v);
        let tol = (1e-3 * settings.atol).max(1e-14);
        let mut integrator = integrator::create(kind, settings);
        integrator
            .initialize(&mut system, &mut state, tol)
            .map_err(String::from)?;
        Ok(Simulation {
            system,
            state,
            integrator,
            settings,
            warnings,
            kkt: crate::integrator::kkt::Kkt::new(),
            range_space: crate::dae::RangeSpace::default(),
            multipliers_at: Vec::new(),
            multipliers_valid: false,
        })
    }

    /// Sets model input `index` (held constant until changed).
    pub fn set_input(&mut self, index: usize, value: f64) -> Result<(), String> {
        if !value.is_finite() {
            return Err(format!("input #{index} must be finite, got {value}"));
        }
        let n = self.system.inputs.len();
        let slot = self
            .system
            .inputs
            .get_mut(index)
            .ok_or_else(|| format!("input #{index} does not exist (the model has {n})"))?;
        *slot = value;
        Ok(())
    }

    /// Advances exactly to `t_end` [s].
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), SolverError> {
        if !(t_end.is_finite() && t_end >= self.state.t) {
            return Err(SolverError::other(format!(
                "cannot advance from t = {} s to t = {t_end} s",
                self.state.t
            )));
        }
        self.multipliers_valid = false;
        self.integrator
            .advance_to(&mut self.system, &mut self.state, t_end, &mut MemoryHook)?;
        self.note_index1_multipliers();
        Ok(())
    }

    /// The pieces of the point of the multipliers' validity: time, positions, speeds, memory,
    /// inputs.
    fn multiplier_point(&self) -> [&[f64]; 5] {
        let s = &self.state;
        [
            std::slice::from_ref(&s.t),
            &s.q,
            &s.v,
            &s.memory,
            &self.system.inputs,
        ]
    }

    /// Records the current point when the integrator left index-1 multipliers in the state.
    fn note_index1_multipliers(&mut self) {
        self.multipliers_valid = self.integrator.index1_multipliers();
        if self.multipliers_valid {
            let mut at = std::mem::take(&mut self.multipliers_at);
            at.clear();
            for piece in self.multiplier_point() {
                at.extend_from_slice(piece);
            }
            self.multipliers_at = at;
        }
    }

    /// Whether the state's multipliers are the index-1 ones of the current point.
    fn at_multiplier_point(&self) -> bool {
        let pieces = self.multiplier_point();
        self.multipliers_valid
            && pieces.iter().map(|p| p.len()).sum::<usize>() == self.multipliers_at.len()
            && pieces
                .iter()
                .flat_map(|p| p.iter())
                .zip(&self.multipliers_at)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }

    /// Advances towards `t_end` [s] calling `hook` after each accepted step (after the effects'
    /// memory update); stops early when the hook says [`StepAction::Stop`].
    pub fn advance_with(&mut self, t_end: f64, hook: &mut dyn StepHook) -> Result<(), SolverError> {
        struct Both<'a>(&'a mut dyn StepHook);
        impl StepHook for Both<'_> {
            fn after_step(
                &mut self,
                sys: &mut System,
                st: &mut State,
            ) -> Result<StepAction, SolverError> {
                let a = MemoryHook.after_step(sys, st)?;
                let b = self.0.after_step(sys, st)?;
                Ok(match (a, b) {
                    (_, StepAction::Stop) => StepAction::Stop,
                    (StepAction::Restart, _) | (_, StepAction::Restart) => StepAction::Restart,
                    (StepAction::Moved, _) | (_, StepAction::Moved) => StepAction::Moved,
                    _ => StepAction::Continue,
                })
            }
            fn pause(&self) -> bool {
                self.0.pause()
            }
        }
        if !(t_end.is_finite() && t_end >= self.state.t) {
            return Err(SolverError::other(format!(
                "cannot advance from t = {} s to t = {t_end} s",
                self.state.t
            )));
        }
        self.multipliers_valid = false;
        self.integrator
            .advance_to(&mut self.system, &mut self.state, t_end, &mut Both(hook))?;
        self.note_index1_multipliers();
        Ok(())
    }

    /// Advances towards `t_end` [s] by one accepted step (exactly to `t_end` when that step
    /// reaches it), with the step's memory update and action carried out as in
    /// [`Simulation::advance_to`].
    pub fn advance_one_step(&mut self, t_end: f64) -> Result<(), SolverError> {
        self.advance_with(t_end, &mut OneStep::default())
    }

    /// Replaces the system (after a structural change such as an inserted contact node) with
    /// `state` mapped onto it, and restarts the integrator there.
    /// The state's effect memory is copied into the system before anything is evaluated.
    pub fn replace_system(&mut self, system: System, state: State) -> Result<(), SolverError> {
        if state.memory.len() != system.n_memory() {
            return Err(SolverError::other(format!(
                "replace_system: state has {} memory values, the system needs {}",
                state.memory.len(),
                system.n_memory()
            )));
        }
        self.system = system;
        self.state = state;
        self.system.memory.copy_from_slice(&self.state.memory);
        let mut lin = crate::integrator::kkt::Kkt::new();
        integrator::init::project_positions(
            &mut self.system,
            &mut lin,
            &mut self.state,
            (1e-3 * self.settings.atol).max(1e-14),
        )?;
        integrator::init::project_velocities(&mut self.system, &mut lin, &mut self.state)?;
        self.integrator.restart(&mut self.system, &mut self.state)
    }

    /// Copies the state's effect memory into the system after a change made from outside that
    /// keeps the solution continuous in position and velocity (e.g. a prescribed motion whose
    /// acceleration steps); the integrator keeps its history.
    pub fn sync_memory(&mut self) -> Result<(), SolverError> {
        if self.state.memory.len() != self.system.n_memory() {
            return Err(SolverError::other("state memory does not match the system"));
        }
        self.system.memory.copy_from_slice(&self.state.memory);
        Ok(())
    }

    /// Restarts the integrator at the current state after a discontinuous change made from
    /// outside (e.g. effect memory or inputs changed between steps): copies the state's memory
    /// into the system, recomputes accelerations and multipliers, and drops the history.
    pub fn restart(&mut self) -> Result<(), SolverError> {
        if self.state.memory.len() != self.system.n_memory() {
            return Err(SolverError::other("state memory does not match the system"));
        }
        self.system.memory.copy_from_slice(&self.state.memory);
        self.integrator.restart(&mut self.system, &mut self.state)
    }

    /// Energy bookkeeping at the current state.
    pub fn energy(&mut self) -> Energy {
        let s = &self.state;
        let (kinetic, potential) = self.system.energy(s.t, &s.q, &s.v);
        Energy {
            kinetic,
            potential,
            dissipated: s.energy_dissipated,
            input: s.work_input,
        }
    }

    /// Lagrange multipliers of the active constraint rows consistent with the current positions
    /// and speeds, from the index-1 system `[M G^T; G 0] [v_dot; lambda] = [f; gamma]`.
    ///
    /// Use these for reaction forces in outputs: the generalized-alpha multipliers come from the
    /// position-level (index-3) equations and carry round-off amplified by `1 / h^2`, which
    /// spoils them when communication points force steps below about 1e-4 s. The integrator's
    /// own history is not touched. Solved by the range-space method (module
    /// `dae::range_space`), by the LU of the full matrix if a mass block is singular; not solved
    /// again when the integrator left these very multipliers in the state at the unchanged
    /// point (the joint-coordinate integrators solve them at the end of every call).
    pub fn consistent_multipliers(&mut self) -> Result<Vec<f64>, SolverError> {
        if self.at_multiplier_point() {
            return Ok(self.state.lambda.clone());
        }
        let s = &self.state;
        let mut vdot = vec![0.0; self.system.n_v()];
        let mut lambda = Vec::new();
        integrator::init::index1_motion(
            &mut self.system,
            &mut self.range_space,
            &mut self.kkt,
            s.t,
            &s.q,
            &s.v,
            &mut vdot,
            &mut lambda,
            &mut Vec::new(),
        )?;
        Ok(lambda)
    }

    /// Accelerations `vdot` and multipliers `lambda` of the index-1 system
    /// `[M G^T; G 0] [v_dot; lambda] = [f; gamma]` at the current state, solved afresh (by the
    /// LU of the full matrix or the range-space method, as the structure suits); the state and
    /// the integrator's history are not touched.
    pub fn index1_solution(&mut self) -> Result<(Vec<f64>, Vec<f64>), SolverError> {
        let s = &self.state;
        let mut out = Vec::new();
        integrator::init::index1_solution(
            &mut self.system,
            &mut self.kkt,
            s.t,
            &s.q,
            &s.v,
            &mut out,
        )?;
        let lambda = out.split_off(self.system.n_v());
        Ok((out, lambda))
    }

    /// Largest absolute constraint residual at the current state.
    pub fn constraint_residual(&mut self) -> f64 {
        let s = &self.state;
        self.system.eval_constraints(s.t, &s.q, &s.v);
        self.system
            .rows
            .iter()
            .map(|r| r.phi.abs())
            .fold(0.0, f64::max)
    }

    /// Messages the solver raised since the last call (e.g. a singular configuration passed,
    /// reported once per set of joints), oldest first; models forward them to their log.
    pub fn take_solver_notes(&mut self) -> Vec<String> {
        self.system.take_solver_notes()
    }

    /// Integrator work counters.
    pub fn stats(&self) -> Stats {
        self.integrator.stats()
    }

    /// Sets the integrator's work counters (restoring a serialized state).
    pub fn set_stats(&mut self, stats: Stats) {
        self.integrator.set_stats(stats);
    }

    /// Which integrator runs.
    pub fn integrator_kind(&self) -> IntegratorKind {
        self.integrator.kind()
    }

    /// The integrator's history as plain numbers (for serialization).
    pub fn integrator_memory(&self) -> Vec<f64> {
        self.integrator.memory()
    }

    /// The integrator's monitors as plain numbers (for serialization, see
    /// [`Integrator::monitors`]).
    pub fn integrator_monitors(&self) -> Vec<f64> {
        self.integrator.monitors()
    }

    /// Restores what [`Simulation::integrator_monitors`] returned (after [`Simulation::restore`]).
    pub fn restore_integrator_monitors(&mut self, m: &[f64]) -> Result<(), String> {
        self.integrator.restore_monitors(m)
    }

    /// Restores state and integrator history saved from a simulation of the same model.
    pub fn restore(&mut self, state: State, memory: &[f64]) -> Result<(), String> {
        if state.q.len() != self.system.n_q() || state.v.len() != self.system.n_v() {
            return Err("state does not belong to this model (dimension mismatch)".into());
        }
        if state.memory.len() != self.system.memory.len() {
            return Err(
                "state does not belong to this model (effect memory length mismatch)".into(),
            );
        }
        self.system.memory.copy_from_slice(&state.memory);
        self.state = state;
        self.multipliers_valid = false;
        self.system.memory.copy_from_slice(&self.state.memory);
        self.integrator.restore_memory(memory)
    }
}

/// A hook that asks for control back after the first accepted step.
#[derive(Debug, Clone, Copy, Default)]
pub struct OneStep {
    stepped: bool,
}

impl StepHook for OneStep {
    fn after_step(
        &mut self,
        _sys: &mut System,
        _st: &mut State,
    ) -> Result<StepAction, SolverError> {
        self.stepped = true;
        Ok(StepAction::Continue)
    }
    fn pause(&self) -> bool {
        self.stepped
    }
}
