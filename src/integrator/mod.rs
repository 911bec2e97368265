//! Time integrators behind one trait, chosen at run time.
//!
//! - [`gen_alpha::GenAlpha`]: generalized-alpha (Chung-Hulbert coefficients in the Arnold-Bruls
//!   form) on the index-3 equations, on the Lie group of rotations; fixed or adaptive steps.
//! - [`bdf::Bdf`]: variable-order (1-5), variable-step BDF on the stabilized index-2 (GGL) form.
//! - [`dopri::Dopri5`]: explicit Dormand-Prince 5(4) on the index-1 form with projection.
//! - [`tree_rk::TreeRk`]: explicit Dormand-Prince 5(4) or Verner 6(5) in joint coordinates, for
//!   models whose joints form a tree of revolute, prismatic and fixed joints ([`crate::tree`]);
//!   the DOPRI5 one is PanelLock's fourth `integrator` item, the Verner one library-only.
//!
//! All of them take `rtol`, `atol`, `h_max`, `h_init`, stop exactly at the requested time, count
//! their work in [`Stats`] and keep all memory that influences future steps in plain vectors, so
//! a clone or a serialized copy continues bit-identically.

pub mod bdf;
pub mod dopri;
pub mod error;
mod events;
mod explicit;
pub mod gen_alpha;
mod implicit;
pub mod init;
pub mod kkt;
mod method_core;
pub mod newton;
pub mod rank;
pub mod step_control;
pub mod tree_rk;
pub mod tree_tableau;
mod trial;

use crate::dae::System;
use crate::state::State;
pub use error::{
    Cause, Collapse, Failure, NewtonCause, NewtonFailure, Passage, SingularPassage, SolverError,
};

/// Which integrator; the first three ([`IntegratorKind::ALL`]) are the FMU enumeration of both
/// models (1-based there), PanelLock's has [`IntegratorKind::Dopri5Tree`] as its fourth item.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntegratorKind {
    GenAlpha,
    Bdf,
    Dopri5,
    /// Dormand-Prince 5(4) in joint coordinates ([`tree_rk::TreeRk`]): only for kinematic
    /// trees of revolute, prismatic and fixed joints; its start refuses other models, naming
    /// why. Not in [`IntegratorKind::ALL`]; PanelLock's `integrator` item 4.
    Dopri5Tree,
    /// Verner's 6(5) pair in joint coordinates, as [`IntegratorKind::Dopri5Tree`]; for tight
    /// tolerances.
    Verner65Tree,
    /// Verner's 8(7) pair in joint coordinates, as [`IntegratorKind::Dopri5Tree`]; for
    /// tolerances of about 1e-6 and tighter.
    Verner87Tree,
}

impl IntegratorKind {
    /// Kinds outside the shared enumeration [`IntegratorKind::ALL`] (the joint-coordinate ones;
    /// PanelLock offers `Dopri5Tree` as its fourth item).
    pub const LIBRARY_ONLY: [IntegratorKind; 3] = [
        IntegratorKind::Dopri5Tree,
        IntegratorKind::Verner65Tree,
        IntegratorKind::Verner87Tree,
    ];

    /// All kinds of the FMU enumeration, in enumeration order.
    pub const ALL: [IntegratorKind; 3] = [
        IntegratorKind::GenAlpha,
        IntegratorKind::Bdf,
        IntegratorKind::Dopri5,
    ];

    /// Short name.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::GenAlpha => "gen-alpha",
            IntegratorKind::Bdf => "bdf",
            IntegratorKind::Dopri5 => "dopri5",
            IntegratorKind::Dopri5Tree => "dopri5-tree",
            IntegratorKind::Verner65Tree => "verner65-tree",
            IntegratorKind::Verner87Tree => "verner87-tree",
        }
    }

    /// The spelling the FMUs' `integrator` parameter accepts for this kind (the names of
    /// PanelLock's enumeration items); `None` for the library-only Verner pairs. Solver messages
    /// name integrators by it when they advise another one.
    pub fn parameter_name(self) -> Option<&'static str> {
        match self {
            IntegratorKind::GenAlpha => Some("gen_alpha"),
            IntegratorKind::Bdf => Some("bdf"),
            IntegratorKind::Dopri5 => Some("dopri5"),
            IntegratorKind::Dopri5Tree => Some("dopri5_tree"),
            IntegratorKind::Verner65Tree | IntegratorKind::Verner87Tree => None,
        }
    }
}

/// Smallest relative tolerance accepted: 1e3 machine epsilons. Below it the error estimates
/// (differences of nearly equal numbers) are round-off, and error control would chase noise.
pub const MIN_RTOL: f64 = 1e3 * f64::EPSILON;

/// Smallest absolute tolerance accepted, in the state's SI units (m, rad, m/s, rad/s). Below it
/// the weight of a quantity at rest is smaller than the round-off of the quantities it is
/// computed from (unit-scale ones carry about 2e-16), so error tests and Newton tests there can
/// never pass: with atol 1e-20 every integrator failed in its first step on PanelLock's default
/// scene, blaming stiffness or singular accelerations.
pub const MIN_ATOL: f64 = 1e-15;

/// Smallest `h_max` accepted [s]: the adaptive integrators' first-step guesses are bounded below
/// by it.
pub const MIN_H_MAX: f64 = 1e-8;

/// Accuracy and step settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Relative tolerance (> 0).
    pub rtol: f64,
    /// Absolute tolerance (> 0) [m, rad, m/s, rad/s].
    pub atol: f64,
    /// Largest step [s].
    pub h_max: f64,
    /// First step [s]; 0 lets the integrator choose.
    pub h_init: f64,
    /// Fixed step [s] (gen-alpha and, for order studies, BDF/DOPRI): no error control when > 0.
    pub fixed_step: f64,
    /// Spectral radius at infinity of generalized-alpha, in [0, 1].
    pub rho_inf: f64,
    /// Highest BDF order (1..=5).
    pub max_order: usize,
    /// Bound on the number of steps in one `advance_to` call.
    pub max_steps: u64,
    /// Gen-alpha, adaptive: split each `advance_to` interval into equal steps and grow the step
    /// only by more than 20 %, so that one Newton matrix serves many steps (each new step size
    /// costs a factorization). Off by default: on contact impacts the changed step placement
    /// moved gen-alpha's energy errors past the stability suite's bounds; RopeBlock turns it on
    /// (long slings: factorizations per step 0.76 -> 0.32 at 5000 segments).
    pub equal_steps: bool,
    /// Adaptive gen-alpha, BDF and DOPRI5: hold the local error of a step of `h` to `min(h / 1 s, 1)`
    /// of the tolerance (error per unit step, on by default), so that the errors of many short
    /// steps add up to about the tolerance per second of motion rather than the tolerance per
    /// step (global error proportional to rtol; see `docs/integrator_error_control.md`). Off, each
    /// step may use the whole tolerance. RopeBlock always runs with it off (its lumped-mass rope
    /// carries axial waves of thousands of m/s^2 that gen-alpha damps on purpose, and its contact
    /// nodes slide between steps, which stalls BDF's tighter Newton target of short steps), and
    /// so do PanelLock's default parameters (damped panel modes: 3.6-10x the CPU).
    pub error_per_unit_step: bool,
    /// BDF: the local error estimate holds the speeds as well as the positions (on by default).
    /// Off, only the positions, as generalized-alpha's always does: RopeBlock turns it off (its
    /// contact nodes' edge slides between steps kick the stiff edge holds into speed
    /// oscillations of 1e-5 m/s that BDF otherwise resolved with steps of 1e-6 s: 6,876 steps
    /// and 5,004 rejections in the first 0.05 s of the two-hook lift at rtol 1e-6, 84 steps
    /// without; positions carry them at 1e-9 m).
    pub error_includes_speeds: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rtol: 1e-6,
            atol: 1e-8,
            h_max: 0.1,
            h_init: 0.0,
            fixed_step: 0.0,
            rho_inf: 0.8,
            max_order: 5,
            max_steps: 200_000,
            equal_steps: false,
            error_per_unit_step: true,
            error_includes_speeds: true,
        }
    }
}

/// Time over which the adaptive integrators allow one local error tolerance with
/// [`Settings::error_per_unit_step`] [s]: a step of `h` may leave `min(h / ERROR_TIME_UNIT, 1)`
/// of it, so the local errors of the steps in one unit add up to about the tolerance.
pub const ERROR_TIME_UNIT: f64 = 1.0;

impl Settings {
    /// Share of the local error tolerance an adaptive step of `h` [s] may use:
    /// `min(h / ERROR_TIME_UNIT, 1)` with [`Settings::error_per_unit_step`], else 1 (the whole
    /// tolerance per step).
    pub fn error_share(&self, h: f64) -> f64 {
        if self.error_per_unit_step {
            (h / ERROR_TIME_UNIT).min(1.0)
        } else {
            1.0
        }
    }

    /// Checks the values; `Err` names the offending setting.
    pub fn validate(&self) -> Result<Vec<String>, String> {
        let mut warnings = Vec::new();
        if !(self.rtol.is_finite() && self.rtol > 0.0) {
            return Err(format!("rtol must be finite and > 0, got {}", self.rtol));
        }
        if self.rtol < MIN_RTOL {
            return Err(format!(
                "rtol {:e} is below 1e3 machine epsilons ({MIN_RTOL:.3e}): error estimates are round-off there; use rtol >= {MIN_RTOL:.3e}",
                self.rtol
            ));
        }
        if !(self.atol.is_finite() && self.atol > 0.0) {
            return Err(format!("atol must be finite and > 0, got {}", self.atol));
        }
        if self.atol < MIN_ATOL {
            return Err(format!(
                "atol {:e} is below its floor of {MIN_ATOL:e} (m, rad, m/s, rad/s): below it error and Newton tests compare round-off with the tolerance; use atol >= {MIN_ATOL:e}",
                self.atol
            ));
        }
        if !(self.h_max.is_finite() && self.h_max > 0.0) {
            return Err(format!("h_max must be finite and > 0, got {}", self.h_max));
        }
        if self.h_max < MIN_H_MAX {
            return Err(format!(
                "h_max {:e} s is below its floor of {MIN_H_MAX:e} s",
                self.h_max
            ));
        }
        if !(self.h_init.is_finite() && self.h_init >= 0.0) {
            return Err(format!(
                "h_init must be finite and >= 0, got {}",
                self.h_init
            ));
        }
        if !(self.fixed_step.is_finite() && self.fixed_step >= 0.0) {
            return Err(format!(
                "fixed_step must be finite and >= 0, got {}",
                self.fixed_step
            ));
        }
        if !(0.0..=1.0).contains(&self.rho_inf) {
            return Err(format!("rho_inf must be in [0, 1], got {}", self.rho_inf));
        }
        if !(1..=5).contains(&self.max_order) {
            return Err(format!(
                "max_order must be in 1..=5, got {}",
                self.max_order
            ));
        }
        if self.rho_inf == 1.0 {
            warnings.push("rho_inf = 1 gives no numerical damping: on the index-3 form velocities and multipliers lose accuracy; use 0.8-0.9".into());
        }
        Ok(warnings)
    }
}

/// Work counters.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Steps whose Newton iteration converged but that a check rejected (the sum of the causes
    /// below); steps whose Newton iteration failed are counted in `newton_failures`.
    pub rejected: u64,
    /// Rejected for a local error estimate above the tolerance.
    pub rejected_error: u64,
    /// Rejected for gaining energy beyond the tolerance (generalized-alpha's energy check).
    pub rejected_energy: u64,

    pub newton_iterations: u64,
    /// Newton iterations that did not converge (the step is retried with a fresh matrix or a
    /// smaller step).
    pub newton_failures: u64,
    pub jacobians: u64,
    pub factorizations: u64,
    pub rhs_evaluations: u64,
    /// Last accepted step size [s].
    pub last_step: f64,
    /// Passages through a singular configuration: the active constraint Jacobian lost rank
    /// (see [`rank::RankMonitor`]).
    pub singular_configurations: u64,
}

impl Stats {
    /// One line for the `logSolver` category: accepted steps, rejected steps by cause, Newton
    /// iterations and failures, Jacobians, factorizations, the last step size.
    pub fn summary(&self) -> String {
        format!(
            "{} accepted steps, {} rejected steps ({} for the error estimate, {} for the energy check), {} Newton iterations, {} Newton failures, {} Jacobians, {} factorizations, {} right-hand sides, last step {:e} s, {} singular configurations",
            self.steps,
            self.rejected,
            self.rejected_error,
            self.rejected_energy,
            self.newton_iterations,
            self.newton_failures,
            self.jacobians,
            self.factorizations,
            self.rhs_evaluations,
            self.last_step,
            self.singular_configurations
        )
    }

    /// Number of values in [`Stats::to_numbers`].
    pub const LEN: usize = 11;

    /// Number of values written before `singular_configurations` was added: such states are
    /// still read (the counter then starts at 0).
    pub const LEN_WITHOUT_SINGULAR: usize = 10;

    /// The counters as plain numbers (for serialized states; counts are exact below 2^53).
    pub fn to_numbers(&self) -> [f64; Self::LEN] {
        [
            self.steps as f64,
            self.rejected as f64,
            self.rejected_error as f64,
            self.rejected_energy as f64,
            self.newton_iterations as f64,
            self.newton_failures as f64,
            self.jacobians as f64,
            self.factorizations as f64,
            self.rhs_evaluations as f64,
            self.last_step,
            self.singular_configurations as f64,
        ]
    }

    /// Reads what [`Stats::to_numbers`] wrote.
    pub fn from_numbers(x: &[f64]) -> Result<Stats, String> {
        let bad = || "solver counters are truncated or corrupt".to_string();
        let count = |c: &f64| c.is_finite() && *c >= 0.0 && c.fract() == 0.0 && *c < 9.0e15;
        let old = Self::LEN_WITHOUT_SINGULAR;
        if !(x.len() == Self::LEN || x.len() == old)
            || !x[..old - 1].iter().all(count)
            || !x[old - 1].is_finite()
            || !x[old..].iter().all(count)
        {
            return Err(bad());
        }
        Ok(Stats {
            steps: x[0] as u64,
            rejected: x[1] as u64,
            rejected_error: x[2] as u64,
            rejected_energy: x[3] as u64,
            newton_iterations: x[4] as u64,
            newton_failures: x[5] as u64,
            jacobians: x[6] as u64,
            factorizations: x[7] as u64,
            rhs_evaluations: x[8] as u64,
            last_step: x[9],
            singular_configurations: x.get(10).map_or(0, |c| *c as u64),
        })
    }
}

/// What an integrator does after an accepted step, as a hook decides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepAction {
    /// Go on.
    Continue,
    /// Go on; the hook moved positions of the state by small amounts (a contact node slid
    /// along its edge) and may have changed the effects' memory. Multistep integrators translate
    /// their whole history by the same displacement, so the move is not read as a velocity;
    /// one-step integrators re-evaluate their first stage. Only additive moves of
    /// vector-space coordinates (particle positions) are meant.
    Moved,
    /// The state or the forces changed discontinuously here: restart (recompute accelerations,
    /// drop the history).
    Restart,
    /// Return now (the caller changes the system's structure and calls `start` again).
    Stop,
}

/// Called after every accepted step (discrete memory of effects, structural events of scenes).
pub trait StepHook {
    /// Inspects (and may change) the state after an accepted step.
    fn after_step(
        &mut self,
        sys: &mut System,
        state: &mut State,
    ) -> Result<StepAction, SolverError>;

    /// True when the caller wants control back before the next step (checked before each step
    /// of [`Integrator::advance_to`], after the previous step's action was carried out in full,
    /// step-size selection included); the call then returns with `state.t < t_end`. Default:
    /// never.
    fn pause(&self) -> bool {
        false
    }
}

/// The hook that only updates the effects' discrete memory.
#[derive(Debug, Clone, Copy, Default)]
pub struct MemoryHook;

impl StepHook for MemoryHook {
    fn after_step(&mut self, sys: &mut System, st: &mut State) -> Result<StepAction, SolverError> {
        let mut mem = std::mem::take(&mut st.memory);
        let change = sys.update_memory(st.t, &st.q, &st.v, &mut mem);
        st.memory = mem;
        Ok(if change == crate::effect::MemoryChange::Discontinuous {
            StepAction::Restart
        } else {
            StepAction::Continue
        })
    }
}

/// A time integrator for the multibody DAE.
pub trait Integrator: Send + std::fmt::Debug {
    /// Which method this is.
    fn kind(&self) -> IntegratorKind;

    /// Starts from a consistent state (positions, speeds, accelerations and multipliers set by
    /// [`init::make_consistent`]); forgets any history.
    fn start(&mut self, sys: &mut System, state: &State) -> Result<(), SolverError>;

    /// Whether [`Integrator::advance_to`] leaves in the state the index-1 multipliers of the
    /// state it ends at (the solution of `[M G^T; G 0] [v_dot; lambda] = [f; gamma]` there);
    /// `false` by default.
    fn index1_multipliers(&self) -> bool {
        false
    }

    /// Makes the initial `state` consistent (positions within `position_tol` [m] of the joints,
    /// speeds, accelerations, multipliers) and starts from it. The default projects in maximal
    /// coordinates ([`init::make_consistent`]) and calls [`Integrator::start`].
    fn initialize(
        &mut self,
        sys: &mut System,
        state: &mut State,
        position_tol: f64,
    ) -> Result<(), SolverError> {
        init::make_consistent(sys, state, position_tol)?;
        self.start(sys, state)
    }

    /// Advances `state` exactly to `t_end` [s], calling `hook` after every accepted step; returns
    /// early (with `state.t < t_end`) when the hook says [`StepAction::Stop`].
    fn advance_to(
        &mut self,
        sys: &mut System,
        state: &mut State,
        t_end: f64,
        hook: &mut dyn StepHook,
    ) -> Result<(), SolverError>;

    /// Restarts after a discontinuity at the current state (keeps the step size).
    fn restart(&mut self, sys: &mut System, state: &mut State) -> Result<(), SolverError>;

    /// Work counters since construction.
    fn stats(&self) -> Stats;

    /// Sets the work counters (a restored serialized state continues counting from them).
    fn set_stats(&mut self, stats: Stats);

    /// An exact copy (history included).
    fn clone_box(&self) -> Box<dyn Integrator>;

    /// The history that influences future steps, as plain numbers.
    fn memory(&self) -> Vec<f64>;

    /// Restores what [`Integrator::memory`] returned.
    fn restore_memory(&mut self, m: &[f64]) -> Result<(), String>;

    /// The state of the integrator's monitors that steers its numbers (the rank monitor's
    /// baseline and last observation: the round-off floors of the error and Newton tests scale
    /// with it), as plain numbers; empty for integrators without one. Serialized beside
    /// [`Integrator::memory`] so that a restored integrator continues bit for bit.
    fn monitors(&self) -> Vec<f64> {
        Vec::new()
    }

    /// Restores what [`Integrator::monitors`] returned (after [`Integrator::restore_memory`]).
    fn restore_monitors(&mut self, m: &[f64]) -> Result<(), String> {
        if m.is_empty() {
            Ok(())
        } else {
            Err("integrator monitors given to an integrator without monitors".into())
        }
    }
}

/// The monitors of an integrator as [`Integrator::monitors`] lays them out: each rank monitor
/// ([`rank::RankMonitor::write`]), whether the Newton solver serves its pattern with the whole
/// LU ([`LinearSolver::whole_lu`]: 1, else 0), and the frozen decisions of the Newton matrix
/// point that [`Integrator::memory`] wrote (count, values; 0 without a point).
pub(crate) fn write_monitors(
    monitors: &[&rank::RankMonitor],
    lin: &crate::dae::linear::LinearSolver,
    point: Option<&JacobianPoint>,
) -> Vec<f64> {
    let mut m = Vec::new();
    for monitor in monitors {
        monitor.write(&mut m);
    }
    m.push(if lin.whole_lu() { 1.0 } else { 0.0 });
    let frozen = point.map_or(&[][..], |p| &p.frozen[..]);
    m.push(frozen.len() as f64);
    m.extend_from_slice(frozen);
    m
}

/// Reads what [`write_monitors`] wrote into `monitors`, `lin` and the restored matrix point
/// `point`; an empty `m` (a state written before the monitors were) leaves them as they are:
/// they start afresh.
pub(crate) fn read_monitors(
    m: &[f64],
    monitors: &mut [&mut rank::RankMonitor],
    lin: &mut crate::dae::linear::LinearSolver,
    point: Option<&mut JacobianPoint>,
) -> Result<(), String> {
    if m.is_empty() {
        return Ok(());
    }
    let bad = || "integrator monitors: truncated or corrupt".to_string();
    let mut at = 0;
    for monitor in monitors.iter_mut() {
        at += monitor.read(&m[at..])?;
    }
    let (&whole, rest) = m[at..].split_first().ok_or_else(bad)?;
    let (&n, frozen) = rest.split_first().ok_or_else(bad)?;
    if !(whole == 0.0 || whole == 1.0) || n != frozen.len() as f64 {
        return Err(bad());
    }
    lin.restore_whole_lu(whole == 1.0);
    if let Some(p) = point {
        p.frozen = frozen.to_vec();
    } else if !frozen.is_empty() {
        return Err(bad());
    }
    Ok(())
}

/// Creates an integrator of the given kind.
pub fn create(kind: IntegratorKind, settings: Settings) -> Box<dyn Integrator> {
    match kind {
        IntegratorKind::GenAlpha => Box::new(gen_alpha::GenAlpha::new(settings)),
        IntegratorKind::Bdf => Box::new(bdf::Bdf::new(settings)),
        IntegratorKind::Dopri5 => Box::new(dopri::Dopri5::new(settings)),
        IntegratorKind::Dopri5Tree => Box::new(tree_rk::TreeRk::dopri5(settings)),
        IntegratorKind::Verner65Tree => Box::new(tree_rk::TreeRk::verner65(settings)),
        IntegratorKind::Verner87Tree => Box::new(tree_rk::TreeRk::verner87(settings)),
    }
}

/// Error weights `atol + rtol * scale` for positions and speeds.
pub(crate) fn weights(
    sys: &System,
    q: &[f64],
    v: &[f64],
    s: &Settings,
    wx: &mut [f64],
    wv: &mut [f64],
) {
    sys.model.position_scale(q, wx);
    for w in wx.iter_mut() {
        *w = s.atol + s.rtol * *w;
    }
    for (w, x) in wv.iter_mut().zip(v) {
        *w = s.atol + s.rtol * x.abs();
    }
}

/// Where a Newton matrix was formed: enough to form the identical matrix again after a
/// serialized state is restored (the factorization itself is not serialized).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct JacobianPoint {
    pub t: f64,
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub inputs: Vec<f64>,
    pub memory: Vec<f64>,
    /// The integrator's coefficient the matrix depends on (step size or BDF leading coefficient).
    pub coefficient: f64,
    /// The effects' frozen decisions when the matrix was formed ([`System::frozen_record`]; a
    /// rope's slip modes enter its stiffness); empty: not known (states written before they
    /// were), the current ones serve.
    pub frozen: Vec<f64>,
}

impl JacobianPoint {
    /// Records the point from the system's current inputs and memory.
    pub fn record(sys: &System, t: f64, q: &[f64], v: &[f64], coefficient: f64) -> Self {
        JacobianPoint {
            t,
            q: q.to_vec(),
            v: v.to_vec(),
            inputs: sys.inputs.clone(),
            memory: sys.memory.clone(),
            coefficient,
            frozen: {
                let mut f = Vec::new();
                sys.frozen_record(&mut f);
                f
            },
        }
    }

    /// Records into `slot`, reusing its storage (no allocation once sized).
    pub fn record_into(
        slot: &mut Option<Self>,
        sys: &System,
        t: f64,
        q: &[f64],
        v: &[f64],
        coefficient: f64,
    ) {
        match slot {
            Some(p) => {
                p.t = t;
                p.coefficient = coefficient;
                p.q.clone_from_slice_or_vec(q);
                p.v.clone_from_slice_or_vec(v);
                p.inputs.clone_from_slice_or_vec(&sys.inputs);
                p.memory.clone_from_slice_or_vec(&sys.memory);
                sys.frozen_record(&mut p.frozen);
            }
            None => *slot = Some(Self::record(sys, t, q, v, coefficient)),
        }
    }

    /// The point of a Newton matrix just formed: `restored` (a restored state's point, formed
    /// again), or a new one recorded into `slot`. Returns true for a new matrix, which the
    /// caller counts; re-forming a restored matrix is part of the restore, so the work counters
    /// continue as in the run the state was taken from.
    pub fn keep_or_record(
        slot: &mut Option<Self>,
        restored: Option<Self>,
        sys: &System,
        t: f64,
        q: &[f64],
        v: &[f64],
        coefficient: f64,
    ) -> bool {
        match restored {
            Some(p) => {
                *slot = Some(p);
                false
            }
            None => {
                Self::record_into(slot, sys, t, q, v, coefficient);
                true
            }
        }
    }

    /// Appends to a flat memory vector: lengths first, then the values.
    pub fn write(&self, m: &mut Vec<f64>) {
        m.extend([
            self.q.len() as f64,
            self.v.len() as f64,
            self.inputs.len() as f64,
            self.memory.len() as f64,
            self.t,
            self.coefficient,
        ]);
        for part in [&self.q, &self.v, &self.inputs, &self.memory] {
            m.extend_from_slice(part);
        }
    }

    /// The point a restored state forms its Newton matrix at: `current` when the matrix is
    /// `valid`, else `pending` (a restored point not formed again yet).
    pub fn restore_point<'a>(
        current: &'a Option<Self>,
        valid: bool,
        pending: &'a Option<Self>,
    ) -> Option<&'a Self> {
        match (current, valid) {
            (Some(p), true) => Some(p),
            _ => pending.as_ref(),
        }
    }

    /// Appends the point a restored state forms its Newton matrix at: `current` when the matrix
    /// is `valid`, else `pending` (a restored point not formed again yet), as a flag (1: a point
    /// follows, 0: none) and [`JacobianPoint::write`]'s values.
    pub fn write_matrix_point(
        current: &Option<Self>,
        valid: bool,
        pending: &Option<Self>,
        m: &mut Vec<f64>,
    ) {
        match Self::restore_point(current, valid, pending) {
            Some(p) => {
                m.push(1.0);
                p.write(m);
            }
            None => m.push(0.0),
        }
    }

    /// Reads what [`JacobianPoint::write`] appended, starting at `m[0]`; returns it and the length used.
    pub fn read(m: &[f64]) -> Result<(Self, usize), String> {
        let bad = || "integrator memory: truncated Jacobian point".to_string();
        if m.len() < 6 {
            return Err(bad());
        }
        // lengths of what follows, each at most what is left (so their sum cannot overflow)
        let mut n = [0usize; 4];
        for (k, x) in m[..4].iter().enumerate() {
            if !(x.is_finite() && *x >= 0.0 && x.fract() == 0.0 && *x <= m.len() as f64) {
                return Err(bad());
            }
            n[k] = *x as usize;
        }
        let total = 6 + n.iter().sum::<usize>();
        if m.len() < total {
            return Err(bad());
        }
        let mut at = 6;
        let mut take = |k: usize| {
            let v = m[at..at + k].to_vec();
            at += k;
            v
        };
        let (q, v, inputs, memory) = (take(n[0]), take(n[1]), take(n[2]), take(n[3]));
        Ok((
            JacobianPoint {
                t: m[4],
                q,
                v,
                inputs,
                memory,
                coefficient: m[5],
                frozen: Vec::new(),
            },
            total,
        ))
    }

    /// Runs `f` with the system's inputs and memory set to the recorded ones, then puts the
    /// current ones back.
    pub fn with_recorded<R>(&self, sys: &mut System, f: impl FnOnce(&mut System) -> R) -> R {
        let (inputs, memory) = (sys.inputs.clone(), sys.memory.clone());
        if self.inputs.len() == inputs.len() {
            sys.inputs.copy_from_slice(&self.inputs);
        }
        if self.memory.len() == memory.len() {
            sys.memory.copy_from_slice(&self.memory);
        }
        let mut frozen = Vec::new();
        sys.frozen_record(&mut frozen);
        let set = sys.set_frozen_record(&self.frozen);
        let r = f(sys);
        if set {
            sys.set_frozen_record(&frozen);
        }
        sys.inputs = inputs;
        sys.memory = memory;
        r
    }
}

/// Copies a slice into a vector, reusing its allocation when the lengths agree.
trait CopyInto {
    fn clone_from_slice_or_vec(&mut self, src: &[f64]);
}

impl CopyInto for Vec<f64> {
    fn clone_from_slice_or_vec(&mut self, src: &[f64]) {
        self.clear();
        self.extend_from_slice(src);
    }
}

/// Relative tolerance for comparing communication times.
pub(crate) fn time_eps(t: f64) -> f64 {
    1e-12 * t.abs().max(1.0)
}

/// A remainder after a fixed step of at most this fraction of the step is the round-off of the
/// summed time, and the step absorbs it.
const FIXED_STEP_ROUND_OFF: f64 = 1e-6;

/// A remainder after a fixed step below this fraction of the step is split with it into two
/// equal steps instead of being taken alone.
const FIXED_STEP_MIN_REMAINDER: f64 = 0.01;

/// The next step [s] of a fixed-step run with step `fixed` and `remaining` [s] to the end of the
/// call. `fixed` itself, except at the end: the rest when it is at most `fixed` (plus the
/// round-off of the summed time, up to [`FIXED_STEP_ROUND_OFF`] of the step), half of it when a
/// step of `fixed` would leave a sliver below [`FIXED_STEP_MIN_REMAINDER`] of the step. A sliver
/// taken alone is a step the implicit schemes cannot take: 200,000 steps of 1e-5 s sum to 2 s
/// with an error of about 4e-11 s, beyond [`time_eps`], and generalized-alpha's step of 4e-11 s
/// (its Newton matrix scaled by 1 / h^2) left the double pendulum 6e-2 m off at the next
/// communication point and stopped the four-bar's Newton iteration.
pub(crate) fn fixed_step_size(fixed: f64, remaining: f64) -> f64 {
    let rest = remaining - fixed;
    if rest <= FIXED_STEP_ROUND_OFF * fixed {
        remaining
    } else if rest < FIXED_STEP_MIN_REMAINDER * fixed {
        0.5 * remaining
    } else {
        fixed
    }
}
