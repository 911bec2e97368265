//! Generalized-alpha on the index-3 equations (Arnold-Bruls form, Chung-Hulbert coefficients from
//! the spectral radius `rho_inf`), with positions updated on the rotation group.
//!
//! With pseudo-accelerations `a`: `(1-am) a1 + am a0 = (1-af) w1 + af w0` (`w = v_dot`),
//! `v1 = v0 + h((1-g) a0 + g a1)`, `dx = h v0 + h^2((1/2-b) a0 + b a1)`, `q1 = q0 ⊕ dx`, and
//! Newton solves `M w1 + G^T lambda1 = f`, `Phi(q1) = 0` for `(w1, lambda1)` with the matrix
//! `[M + g h c D + b h^2 c K, G^T; G, 0]`, `c = (1-af)/(1-am)`, the constraint rows scaled by
//! `1/(b h^2 c)` so that the matrix stays well conditioned as `h -> 0`.
//!
//! Error control (adaptive mode): the local position error is estimated as
//! `(g/2 - b - 1/12) h^2 (a1 - a0)`, the leading term of the scheme's truncation error; a step
//! that gains energy beyond the tolerance is rejected as well (`GenAlpha::energy_gain`).
//! The Newton matrix is refreshed at the start of every `advance_to` call, so a run continued from
//! a restored state repeats the original bit for bit.

use super::JacobianPoint;
use super::implicit::{self, Flow, ImplicitMethod};
use super::method_core::MethodCore;
use super::newton::{MAX_ITERATIONS, NewtonTest, Progress, Verdict, factor_failure};
use super::step_control::{self, StepPolicy};
use super::{
    Cause, Collapse, Integrator, IntegratorKind, NewtonCause, NewtonFailure, Settings, SolverError,
    Stats, StepAction, StepHook, weights,
};
use crate::dae::System;
use crate::dae::linear::LinearSolver;
use crate::math::wrms;
use crate::state::State;

mod energy;
mod event_location;
mod memory;
mod method;
mod step;

/// Generalized-alpha integrator.
#[derive(Debug, Clone)]
pub struct GenAlpha {
    /// Settings, step size, counters, event location, matrix validity.
    core: MethodCore,
    am: f64,
    af: f64,
    gamma: f64,
    beta: f64,
    /// Pseudo-accelerations of the last accepted step.
    a: Vec<f64>,
    /// Dissipated and input power at the last accepted step [W].
    p_prev: (f64, f64),
    /// Kinetic and potential energy at the last accepted state [J], evaluated when the next step
    /// is tried (after the step hook has updated the system's memory); `None` until then.
    e_prev: Option<(f64, f64)>,
    /// Dissipated and input power at the end of the step just tried [W] (adaptive mode).
    p_tried: Option<(f64, f64)>,
    /// Energy gained by the step just tried, relative to its tolerance (adaptive mode).
    gain_ratio: f64,
    /// The round-off allowance of the last error test, relative to the step's share of the
    /// tolerance (adaptive mode; see [`NOISE_ALLOWANCE`]).
    err_roundoff: f64,
    /// The whole (unprojected) error estimate of the step just tried, relative to its tolerance
    /// widened by its round-off allowance, with [`ERROR_SAFETY`] (adaptive mode).
    whole_err: f64,
    /// The share of the step's tolerance that the whole estimate's round-off allowance took at
    /// the step just tried (adaptive mode).
    whole_roundoff: f64,
    /// [`Self::whole_roundoff`] of the last accepted step of the controller's size (not cut to
    /// land on an event or a call's end, not the first after a rejection); infinite before the
    /// first one (no collapse into the round-off band is judged then, see
    /// [`collapses_into_roundoff`]).
    accepted_roundoff: f64,
    /// Whether a step was rejected since the last proposal after an accepted step.
    after_rejection: bool,
    lin: LinearSolver,
    jac_h: f64,
    /// Where the current Newton matrix was formed.
    jac_point: Option<JacobianPoint>,
    /// A restored matrix point: the matrix is formed there again when it would have been reused.
    pending: Option<JacobianPoint>,
    /// Watches the constraint pivots of the Newton matrices for singular configurations.
    rank: super::rank::RankMonitor,
    // scratch
    w: Vec<f64>,
    lam: Vec<f64>,
    lam_scratch: Vec<f64>,
    a1: Vec<f64>,
    v1: Vec<f64>,
    dx: Vec<f64>,
    q1: Vec<f64>,
    f: Vec<f64>,
    rhs: Vec<f64>,
    /// Local error weights [m, rad] (adaptive mode).
    wx: Vec<f64>,
    wv: Vec<f64>,
    /// Newton weights: the position correction at which the iteration has converged [m, rad].
    wn: Vec<f64>,
    /// Weights of the error test of a step [m, rad] (adaptive mode).
    werr: Vec<f64>,
    tmp: Vec<f64>,
    /// The whole error estimate of a step before its projection onto the joints' tangent
    /// space [m, rad] (adaptive mode).
    full: Vec<f64>,
    /// The interpolated chart increment, speeds and positions at a trial instant inside a step
    /// (contact-event location).
    xd: Vec<f64>,
    vd: Vec<f64>,
    qd: Vec<f64>,
}

/// Whether a Newton matrix formed for step `a` serves step `b`: equal up to the rounding of
/// step sizes computed from communication times (e.g. `0.5 * (t_end - t)`), so the matrix is
/// the same to 1e-9 relative and Newton converges as with an exact one.
fn same_step(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs()
}

/// Position correction, relative to the largest position scale, at which a fixed step's Newton
/// iteration has converged: round-off. Coarser stopping tests are not enough: on the index-3
/// form a position correction `dx` is an acceleration correction of `dx / (b h^2)`, so the
/// velocity error a step leaves grows as `1/h` (a stop at 1e-10 of the step's motion still
/// made the double pendulum less accurate from h = 1e-4 to 5e-5).
const FIXED_STEP_NEWTON_TOL: f64 = 10.0 * f64::EPSILON;

/// A fixed step forms its Newton matrix at the step's predictor, not once for the run. With a
/// matrix formed far away the multipliers' round-off (`eps / (b h^2)` from the constraint
/// residual's round-off, harmless across the constraints) leaks along the motion through the
/// stale `G`, and the iteration, judged on position increments that sit at round-off, stops
/// with an acceleration error of the same order: the four-bar ended 3.9e-7, 4.8e-5, 2.8e-4 m
/// off at h = 1e-4, 2e-5, 1e-5 (chain8 1.6e-7, 2.0e-6, 1.1e-6). With the matrix of the step:
/// 4.8e-7, 1.9e-8, 4.9e-9 (chain8 1.0e-7, 4.1e-9, 1.0e-9; Exudyn 9.8e-8 .. 6.3e-10), two
/// iterations per step instead of 3.3 .. 5.3, one factorization per step instead of one per run.
/// (Refreshing only after slow steps, more than 2 or 3 iterations, left 8e-5 .. 3e-4 m.)
fn fresh_fixed_step_matrix(fixed: bool, iterations: usize) -> bool {
    fixed && iterations == 0
}

/// A fixed step's Newton matrix carries the joints' geometric stiffness
/// ([`System::add_constraint_stiffness`]) at the multipliers the step starts from. Without it
/// the iteration converged only linearly where joints carry large forces on levers: a hanging 3D
/// chain of 1000 rods at h = 1 ms contracted by 0.25 per iteration and took 9.9 iterations per
/// step (3.0 at 10 rods); with it 2.0 at every length. Adaptive steps reuse their matrix over
/// steps, where the multipliers it was formed with go stale (impacts, singular configurations):
/// there it made a four-bar's steps collapse at rtol 1e-8 and PanelLock's energy grow by 1.1 %
/// at contact stiffness 1e9, so they form none (docs/chain_solve.md).
fn forms_constraint_stiffness(fixed: bool) -> bool {
    fixed
}

/// Round-off band of positions, relative to their largest scale: an iteration that stops
/// contracting inside it has converged as far as the arithmetic allows; also the constraint
/// violation accepted at convergence.
const POSITION_ROUNDOFF: f64 = 1e3 * f64::EPSILON;

/// Newton weights of a fixed step (see [`FIXED_STEP_NEWTON_TOL`]), independent of the user's
/// rtol/atol, which set the local error only in adaptive mode; with a fixed step they made the
/// result less accurate as the step shrank. Returns the largest position scale [m].
fn fixed_step_newton_weights(sys: &System, q: &[f64], wx: &mut [f64]) -> f64 {
    sys.model.position_scale(q, wx);
    let scale = wx.iter().fold(1e-3f64, |m, x| m.max(*x));
    wx.fill(FIXED_STEP_NEWTON_TOL * scale / 0.02);
    scale
}

/// Factor on the local error estimate per unit step. The global error of a run is about the
/// sum of the local errors, so its ratio to rtol is the run's length [s] over this factor times
/// what the problem amplifies. Calibrated on the accuracy suite (error / rtol, rtol 1e-2 ..
/// 1e-8): at 3 the chains were 0.1 .. 6.5, the four-bar 45 .. 75 and the damped
/// (Lankarani-Nikravesh) drop 0.07 .. 0.35, above the 0.1 the issue asks of impacts, because
/// speeds, which the damping force reads, are not in the estimate; at 12 the chains are
/// 0.12 .. 1.65, the four-bar 11 .. 20, the Hertz drop 0.01 .. 0.02 and the damped drop
/// 0.02 .. 0.10 at every rtol down to 1e-10, at twice the steps per rtol (the same error per
/// CPU second).
const ERROR_SAFETY: f64 = 12.0;

/// Allowance for the round-off in the error estimate, in units of the estimate of pure round-off
/// (`|c| dx / b`): added to the error weights, so round-off alone passes the test at
/// `ERROR_SAFETY / NOISE_ALLOWANCE` = 0.5.
const NOISE_ALLOWANCE: f64 = 2.0 * ERROR_SAFETY;

/// What the projection of the error estimate onto the joints' tangent space
/// ([`GenAlpha::project_estimate`]) leaves of the estimate's round-off `c dx / b`, as a factor
/// on it, given the step's share of the tolerance (`h / 1 s` per unit step): the estimate's
/// round-off along the tangent is that of the accelerations' tangential part, `eps |a|`, and
/// of the normal part the solve's round-off, so it falls with the step as the tolerance of
/// the step does (measured: on the tangential part alone, with this allowance, the runs fell
/// 10x per decade of rtol down to 1e-10 on chain2 and the four-bar, 5-7 rejections per run).
fn projected_noise(share: f64) -> f64 {
    share
}

/// Factor on the tangential part of the error estimate where it stands in for the whole one
/// ([`whole_weight`]): the tangential part alone is smaller than the whole estimate by what the
/// normal part carried, and the runs ended 3x (chain2: 4.2 .. 6.1 x rtol) to 10x (four-bar:
/// 84 .. 131 x rtol) less accurate than with the whole estimate (1.6 and 12 x rtol).
const TANGENT_SAFETY: f64 = 4.0;

/// Weight of the whole error estimate against its tangential part (the rest), given the share
/// `s` of the tolerance that the whole estimate's round-off allowance takes: 1 up to
/// [`ROUNDOFF_SHARE_LIMIT`] / 10 (the error control of before, bit for bit), 0 from
/// [`ROUNDOFF_SHARE_LIMIT`] on (where the whole estimate's round-off stopped the run before),
/// linear in `log10 s` between. The normal part is physical at loose tolerances (it carries
/// the change of the centripetal accelerations: steering by the tangential part alone took 1.7x
/// (chain2) to 2.5x (four-bar) the steps at equal error) and round-off at tight ones (the
/// whole estimate with only the positions' round-off, or also the last Newton correction, as
/// its allowance collapsed the steps at rtol 1e-9 and 1e-10 on chain2 and the four-bar).
fn whole_weight(s: f64) -> f64 {
    let lo = 0.1 * ROUNDOFF_SHARE_LIMIT;
    if s <= lo {
        1.0
    } else if s >= ROUNDOFF_SHARE_LIMIT {
        0.0
    } else {
        (ROUNDOFF_SHARE_LIMIT / s).log10()
    }
}

/// Share of the error tolerance that the round-off allowance may take at the step the
/// controller asks for after a rejection; beyond it the run stops with a message naming the
/// tolerance. Round-off of the index-3 form then also shows in the result: with a limit of
/// 2 (0.5), the four-bar at rtol 1e-9 returned 190 x rtol after 337 rejected steps (its share
/// was 0.14 there); at 0.1 it stops, and the chains still run at 1e-9 (6.5 and 1.4 x rtol).
const ROUNDOFF_SHARE_LIMIT: f64 = 0.1;

/// Whether a rejection drops the steps into the whole estimate's round-off band from outside
/// it: a motion faster than the tolerance follows, refused like a tolerance below round-off.
/// `whole` is the rejected step's whole error estimate (relative, with its round-off
/// allowance), `accepted` the round-off share of the last accepted step, `next` that of the
/// step the controller asks for now.
///
/// A tolerance tight enough for the round-off band puts every step there (rtol 1e-9 and
/// 1e-10 on the suite's chains and four-bar: shares of 0.1 .. 100 at every step), and the
/// tangential estimate steers them ([`whole_weight`]). A loose tolerance reaches the band only
/// where a motion asks for steps a decade or more below the run's: the millimetre yoke under a
/// 600 N m root spring at rtol 1e-4 (it turns at about 1e4 rad/s) ran at shares of 0.006 and
/// cut its step from 2.6e-7 s to 7.7e-9 s at a latch contact (share 0.2), where the whole
/// estimate still asked for a 10x shorter step (68 times its tolerance). The tangential estimate
/// passes that contact at steps of 3e-10 s and then runs on at 3e-8 .. 3e-7 s: 85,000 steps
/// and 20 s CPU for the first 0.01 s communication step; refused here instead after 0.2 s CPU.
/// The conditions are each part of the stop before the tangential estimate (a rejection by the
/// whole estimate whose next step's share reaches [`ROUNDOFF_SHARE_LIMIT`]), so it refuses
/// nothing that was not refused before.
fn collapses_into_roundoff(whole: f64, accepted: f64, next: f64) -> bool {
    whole >= 1.0 && accepted < 0.1 * ROUNDOFF_SHARE_LIMIT && next >= ROUNDOFF_SHARE_LIMIT
}

/// Factor on the step size from the error `err` (per unit step `O(h^2)`, per step `O(h^3)`) and
/// the energy gain ratio `gain` (`O(h^3)`), both relative to their tolerances: the smaller of
/// the two proposals.
fn step_factor(err: f64, gain: f64, per_unit_step: bool) -> f64 {
    let order = if per_unit_step { 2.0 } else { 3.0 };
    step_control::proposal(err, order).min(step_control::proposal(gain, 3.0))
}

/// Gen-alpha grows a step by at most 3x; a new step size costs a Newton matrix, so with
/// `Settings::equal_steps` only a growth beyond 20 % replaces the step
/// ([`GenAlpha::step_policy`]).
const MAX_GROWTH: f64 = 3.0;

/// Fraction of the step's local error tolerance at which an adaptive step's Newton iteration
/// has converged.
const NEWTON_FRACTION: f64 = 0.02;

enum StepOutcome {
    /// Newton converged; weighted local error estimate.
    Converged(f64),
    /// Newton did not converge.
    Failed(NewtonFailure),
}

impl GenAlpha {
    /// A new integrator with the given settings.
    pub fn new(s: Settings) -> Self {
        let rho = s.rho_inf;
        let am = (2.0 * rho - 1.0) / (rho + 1.0);
        let af = rho / (rho + 1.0);
        let gamma = 0.5 + af - am;
        let beta = 0.25 * (gamma + 0.5).powi(2);
        GenAlpha {
            core: MethodCore::new(s),
            am,
            af,
            gamma,
            beta,
            a: Vec::new(),
            p_prev: (0.0, 0.0),
            e_prev: None,
            p_tried: None,
            gain_ratio: 0.0,
            err_roundoff: 0.0,
            whole_err: 0.0,
            whole_roundoff: 0.0,
            accepted_roundoff: f64::INFINITY,
            after_rejection: false,
            lin: LinearSolver::new(),
            jac_h: 0.0,
            jac_point: None,
            pending: None,
            rank: super::rank::RankMonitor::default(),
            w: Vec::new(),
            lam: Vec::new(),
            lam_scratch: Vec::new(),
            a1: Vec::new(),
            v1: Vec::new(),
            dx: Vec::new(),
            q1: Vec::new(),
            f: Vec::new(),
            rhs: Vec::new(),
            wx: Vec::new(),
            wv: Vec::new(),
            wn: Vec::new(),
            werr: Vec::new(),
            tmp: Vec::new(),
            full: Vec::new(),
            xd: Vec::new(),
            vd: Vec::new(),
            qd: Vec::new(),
        }
    }

    fn resize(&mut self, nq: usize, nv: usize, nc: usize) {
        for v in [
            &mut self.w,
            &mut self.a1,
            &mut self.v1,
            &mut self.dx,
            &mut self.f,
            &mut self.wx,
            &mut self.wv,
            &mut self.wn,
            &mut self.werr,
            &mut self.tmp,
            &mut self.full,
        ] {
            v.resize(nv, 0.0);
        }
        self.lam.resize(nc, 0.0);
        self.q1.resize(nq, 0.0);
        self.rhs.resize(nv + nc, 0.0);
        if self.a.len() != nv {
            self.a.resize(nv, 0.0);
        }
    }

    /// The first step [s] from `st`: `h_init`, or half the time in which the accelerations
    /// move the positions by their tolerance.
    fn initial_step(&mut self, sys: &System, st: &State) -> f64 {
        weights(sys, &st.q, &st.v, &self.core.s, &mut self.wx, &mut self.wv);
        let acc = wrms(&st.vdot, &self.wx).max(1e-12);
        if self.core.s.h_init > 0.0 {
            self.core.s.h_init
        } else {
            (0.5 * (2.0 / acc).sqrt()).min(self.core.s.h_max)
        }
    }

    /// How far an accepted step may grow (see [`MAX_GROWTH`]).
    fn step_policy(&self) -> StepPolicy {
        StepPolicy {
            max_growth: MAX_GROWTH,
            hysteresis: if self.core.s.equal_steps { 1.2 } else { 1.0 },
        }
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64) {
        st.t += h;
        st.q.copy_from_slice(&self.q1);
        st.v.copy_from_slice(&self.v1);
        st.vdot.copy_from_slice(&self.w);
        st.lambda.copy_from_slice(&self.lam);
        self.a.copy_from_slice(&self.a1);
        let drive = sys.drive_power(&st.lambda);
        let (pd, pi) = match self.p_tried.take() {
            Some(p) => p,
            None => {
                let (pd, pi) = sys.powers(st.t, &st.q, &st.v);
                (pd, pi + drive)
            }
        };
        self.e_prev = None;
        st.energy_dissipated += 0.5 * h * (self.p_prev.0 + pd);
        st.work_input += 0.5 * h * (self.p_prev.1 + pi);
        self.p_prev = (pd, pi);
        self.core.stats.steps += 1;
        self.core.stats.last_step = h;
    }
}

impl Integrator for GenAlpha {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::GenAlpha
    }

    fn start(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        self.resize(sys.n_q(), sys.n_v(), sys.n_c());
        self.a.copy_from_slice(&st.vdot);
        self.core.h = self.initial_step(sys, st);
        sys.eval_constraints(st.t, &st.q, &st.v);
        let drive = sys.drive_power(&st.lambda);
        let (pd, pi) = sys.powers(st.t, &st.q, &st.v);
        self.p_prev = (pd, pi + drive);
        self.e_prev = None;
        self.p_tried = None;
        self.core.jac_valid = false;
        self.pending = None;
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
        self.core.h = h;
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
