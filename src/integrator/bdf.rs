//! Variable-order (1-5), variable-step BDF (Gear) on the stabilized index-2 (GGL) form.
//!
//! Unknowns at `t1`: chart positions `x` (`q = q_n ⊕ x`), speeds `v`, multipliers `lambda`, `mu`:
//!
//! ```text
//! sum_j alpha_j x_j = dexp_inv(x) v - G^T mu      (mu = 0 at the exact solution)
//! M sum_j alpha_j v_j = f - G^T lambda
//! Phi(q, t1) = 0,   G v + Phi_t = 0
//! ```
//!
//! `alpha_j` are the derivative weights at `t1` of the polynomial through the last `k + 1`
//! points of the (variable) grid. The local error of positions and speeds (not multipliers) is
//! estimated from the predictor-corrector difference `h / (t1 - t_{n-k}) |Y1 - Y_pred|`; orders
//! `k - 1` and `k + 1` are judged from scaled divided differences of the accepted solutions.
//! In fixed-step mode (order studies) the first `k - 1` points come from a tight DOPRI5 run.
//! The history is re-expressed in the chart of the newest point at every step.

use super::ERROR_TIME_UNIT;
use super::JacobianPoint;
use super::dopri::Dopri5;
use super::implicit::{self, Flow, ImplicitMethod};
use super::method_core::MethodCore;
use super::newton::{
    DIVERGENCE_RATE, MAX_ITERATIONS, NewtonTest, Progress, Verdict, factor_failure,
};
use super::step_control::{self, StepPolicy};
use super::{
    Integrator, IntegratorKind, MemoryHook, NewtonCause, NewtonFailure, Settings, SingularPassage,
    SolverError, Stats, StepAction, StepHook, weights,
};
use crate::dae::System;
use crate::dae::linear::LinearSolver;
use crate::math::wrms;
use crate::state::State;
use std::collections::VecDeque;

mod estimate;
mod event_location;
mod history;
mod memory;
mod method;
mod newton_step;
mod polynomial;

use polynomial::{derivative_weights, interp_weights, max_abs};

/// One accepted solution point.
#[derive(Debug, Clone, PartialEq)]
struct Point {
    t: f64,
    q: Vec<f64>,
    v: Vec<f64>,
    /// Dissipated energy and input work [J].
    z: [f64; 2],
}

/// How much a first Newton correction is scaled in the convergence test (see `solve_step`).
const FIRST_CORRECTION_FACTOR: f64 = 1e4;

/// A step's error weights are at least `ROUND_OFF_EPSILONS` machine epsilons of the largest
/// position scale (positions) and of the largest speed (speeds, at least that position scale
/// per `ERROR_TIME_UNIT`): below that the estimate and Newton's stopping test would see round-off.
const ROUND_OFF_EPSILONS: f64 = 300.0;

/// A Newton iteration that stops contracting with corrections below `NEWTON_ROUND_OFF_EPSILONS`
/// machine epsilons of those scales has converged as far as the arithmetic goes.
const NEWTON_ROUND_OFF_EPSILONS: f64 = 30.0;

/// The Newton matrix is formed again when the BDF leading coefficient has moved by more than
/// this fraction since it was formed (and the serialized matrix point is reused within it).
/// BDF grows a step by at most 2x, and only by more than 20 % (a new step size costs a Newton
/// matrix; a higher order is worth more than a slightly longer step).
const STEP_POLICY: StepPolicy = StepPolicy {
    max_growth: 2.0,
    hysteresis: 1.2,
};

const MATRIX_COEFFICIENT_CHANGE: f64 = 0.15;

/// A step whose Newton iteration contracted by less than this factor per iteration after its
/// second correction leaves the next step a fresh matrix (at the new configuration).
const REFRESH_RATE: f64 = 0.2;

/// Newton stops when its estimated remaining correction is below this fraction of the step's
/// local error tolerance.
const NEWTON_FRACTION: f64 = 0.03;

/// BDF integrator.
#[derive(Debug, Clone)]
pub struct Bdf {
    /// Settings, step size, counters, event location, matrix validity.
    core: MethodCore,
    hist: VecDeque<Point>,
    order: usize,
    steps_at_order: usize,
    /// Accepted steps since the last (re)start (drives the start-up order ramp).
    since_start: usize,
    lin: LinearSolver,
    jac_alpha0: f64,
    /// The current step's weights are `h / ERROR_TIME_UNIT` of the tolerance (error per unit step:
    /// the estimate is of order `k` in `h`, not `k + 1`).
    per_unit_step: bool,
    /// Round-off of positions [m, rad] and speeds [m/s, rad/s]: machine epsilon times their
    /// largest scale (0 with fixed steps).
    round_off: [f64; 2],
    /// Multipliers of the last accepted point and its time [s], and those of the point before
    /// (known after two accepted points): they predict the next step's multipliers linearly.
    lam_last: (f64, Vec<f64>),
    lam_prev: Option<(f64, Vec<f64>)>,
    /// Where the current Newton matrix was formed.
    jac_point: Option<JacobianPoint>,
    /// A restored matrix point: the matrix is formed there again when it would have been reused.
    pending: Option<JacobianPoint>,
    /// Watches the constraint pivots of the Newton matrices for singular configurations.
    rank: super::rank::RankMonitor,
    /// Watches the loop rows themselves (the sparse Newton matrix hides its pivots): observed
    /// at the first start (the baseline) and when a run fails, to name a singular configuration.
    rows: super::rank::RankMonitor,
    // scratch: chart coordinates of history points (newest first), unknowns, residuals
    xs: Vec<Vec<f64>>,
    x: Vec<f64>,
    v: Vec<f64>,
    lam: Vec<f64>,
    mu: Vec<f64>,
    q1: Vec<f64>,
    f: Vec<f64>,
    rhs: Vec<f64>,
    tmp: Vec<f64>,
    wx: Vec<f64>,
    wv: Vec<f64>,
    vdot: Vec<f64>,
    /// Accelerations at the only history point (the start or a restart), from the state: the
    /// first step's predictor is `x0 + h v0`, `v0 + h vdot0` with them (empty: not known).
    start_vdot: Vec<f64>,
    /// Scratch (sized once): chart centre, G^T mu, G v, predictor, error and divided differences.
    q0: Vec<f64>,
    gtmu: Vec<f64>,
    gv: Vec<f64>,
    xp: Vec<f64>,
    vp: Vec<f64>,
    ex: Vec<f64>,
    ev: Vec<f64>,
    /// Scratch for the interpolant inside a step (contact-event location): chart coordinates,
    /// speeds and positions at a fraction of it.
    xd: Vec<f64>,
    vd: Vec<f64>,
    qd: Vec<f64>,
}

enum Outcome {
    Converged,
    Failed(NewtonFailure),
}

impl Bdf {
    /// A new integrator with the given settings.
    pub fn new(s: Settings) -> Self {
        Bdf {
            core: MethodCore::new(s),
            hist: VecDeque::new(),
            order: 1,
            steps_at_order: 0,
            since_start: 0,
            lin: LinearSolver::new(),
            jac_alpha0: 0.0,
            per_unit_step: false,
            round_off: [0.0; 2],
            lam_last: (0.0, Vec::new()),
            lam_prev: None,
            jac_point: None,
            pending: None,
            rank: super::rank::RankMonitor::default(),
            rows: super::rank::RankMonitor::default(),
            xs: Vec::new(),
            x: Vec::new(),
            v: Vec::new(),
            lam: Vec::new(),
            mu: Vec::new(),
            q1: Vec::new(),
            f: Vec::new(),
            rhs: Vec::new(),
            tmp: Vec::new(),
            wx: Vec::new(),
            wv: Vec::new(),
            vdot: Vec::new(),
            start_vdot: Vec::new(),
            q0: Vec::new(),
            gtmu: Vec::new(),
            gv: Vec::new(),
            xp: Vec::new(),
            vp: Vec::new(),
            ex: Vec::new(),
            ev: Vec::new(),
            xd: Vec::new(),
            vd: Vec::new(),
            qd: Vec::new(),
        }
    }

    fn resize(&mut self, nq: usize, nv: usize, nc: usize) {
        for v in [
            &mut self.x,
            &mut self.v,
            &mut self.f,
            &mut self.tmp,
            &mut self.wx,
            &mut self.wv,
            &mut self.vdot,
        ] {
            v.resize(nv, 0.0);
            for v in [
                &mut self.gtmu,
                &mut self.xp,
                &mut self.vp,
                &mut self.ex,
                &mut self.ev,
            ] {
                v.resize(nv, 0.0);
            }
            self.gv.resize(nc, 0.0);
            self.q0.resize(nq, 0.0);
            self.hist.reserve(8usize.saturating_sub(self.hist.len()));
        }
        self.lam.resize(nc, 0.0);
        self.mu.resize(nc, 0.0);
        self.q1.resize(nq, 0.0);
        self.rhs.resize(2 * nv + 2 * nc, 0.0);
    }

    /// The first step [s] from `st`: `h_init`, or the time in which the speeds or accelerations
    /// move by 1e-3 of their tolerance, within `[MIN_H_MAX, h_max]`.
    fn initial_step(&mut self, sys: &System, st: &State) -> f64 {
        weights(sys, &st.q, &st.v, &self.core.s, &mut self.wx, &mut self.wv);
        let acc = wrms(&st.vdot, &self.wv)
            .max(wrms(&st.v, &self.wx))
            .max(1e-12);
        if self.core.s.h_init > 0.0 {
            self.core.s.h_init
        } else {
            (0.001 / acc).clamp(super::MIN_H_MAX.min(self.core.s.h_max), self.core.s.h_max)
        }
    }

    /// When the run fails near a singular configuration of a closed loop (the loop rows watched
    /// directly, or the Newton matrix's pivots, inside a passage): what the monitors measured.
    fn singular_cause(&mut self, sys: &mut System, st: &State) -> Option<SingularPassage> {
        if !self.rows.observed() {
            return None;
        }
        sys.eval_constraints(st.t, &st.q, &st.v);
        // the steps' own watch (`rank`) has counted the passage already
        self.rows.observe_rows(sys, st.t, &mut Stats::default());
        let ratio = self.rows.smallest_ratio();
        if !(self.rank.inside() || self.rows.inside()) {
            return None;
        }
        let joints = self
            .rows
            .weakest_joints(sys)
            .unwrap_or_else(|| "?".to_string());
        Some(SingularPassage {
            joints,
            ratio,
            rtol: self.core.s.rtol,
        })
    }
}

impl Integrator for Bdf {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Bdf
    }

    fn start(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        self.resize(sys.n_q(), sys.n_v(), sys.n_c());
        self.hist.clear();
        self.push_point(st);
        self.lam.copy_from_slice(&st.lambda);
        self.lam_last = (st.t, st.lambda.clone());
        self.lam_prev = None;
        self.order = 1;
        self.steps_at_order = 0;
        self.since_start = 0;
        self.note_start_vdot(st);
        self.core.h = self.initial_step(sys, st);
        self.core.jac_valid = false;
        self.pending = None;
        if !self.rows.observed() && sys.has_loops() {
            sys.eval_constraints(st.t, &st.q, &st.v);
            self.rows.observe_rows(sys, st.t, &mut self.core.stats);
        }
        Ok(())
    }

    fn advance_to(
        &mut self,
        sys: &mut System,
        st: &mut State,
        t_end: f64,
        hook: &mut dyn StepHook,
    ) -> Result<(), SolverError> {
        implicit::advance(self, sys, st, t_end, hook)
    }

    fn restart(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        let mut lin = super::kkt::Kkt::new();
        super::init::accelerations(sys, &mut lin, st)?;
        let h = self.core.h;
        self.start(sys, st)?;
        self.core.h = h.min(self.core.s.h_max);
        Ok(())
    }

    fn stats(&self) -> Stats {
        self.core.stats
    }

    fn set_stats(&mut self, stats: Stats) {
        self.core.stats = stats;
    }

    fn clone_box(&self) -> Box<dyn Integrator> {
        Box::new(self.clone())
    }

    fn memory(&self) -> Vec<f64> {
        self.write_memory()
    }

    fn restore_memory(&mut self, m: &[f64]) -> Result<(), String> {
        self.read_memory(m)
    }

    fn monitors(&self) -> Vec<f64> {
        self.write_monitors()
    }

    fn restore_monitors(&mut self, m: &[f64]) -> Result<(), String> {
        self.read_monitors(m)
    }
}
