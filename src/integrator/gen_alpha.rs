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
use super::events::EventLocator;
use super::implicit::{self, Flow, ImplicitMethod};
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

/// Generalized-alpha integrator.
#[derive(Debug, Clone)]
pub struct GenAlpha {
    s: Settings,
    am: f64,
    af: f64,
    gamma: f64,
    beta: f64,
    /// Pseudo-accelerations of the last accepted step.
    a: Vec<f64>,
    /// Proposed next step [s].
    h: f64,
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
    lin: LinearSolver,
    jac_h: f64,
    jac_valid: bool,
    /// Where the current Newton matrix was formed.
    jac_point: Option<JacobianPoint>,
    /// A restored matrix point: the matrix is formed there again when it would have been reused.
    pending: Option<JacobianPoint>,
    stats: Stats,
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
    /// Contact-event location (adaptive, models with contact events), and the interpolated
    /// chart increment, speeds and positions at a trial instant inside a step.
    events: EventLocator,
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

/// Share of the error tolerance that the round-off allowance may take at the step the
/// controller asks for after a rejection; beyond it the run stops with a message naming the
/// tolerance. Round-off of the index-3 form then also shows in the result: with a limit of
/// 2 (0.5), the four-bar at rtol 1e-9 returned 190 x rtol after 337 rejected steps (its share
/// was 0.14 there); at 0.1 it stops, and the chains still run at 1e-9 (6.5 and 1.4 x rtol).
const ROUNDOFF_SHARE_LIMIT: f64 = 0.1;

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
            s,
            am,
            af,
            gamma,
            beta,
            a: Vec::new(),
            h: 0.0,
            p_prev: (0.0, 0.0),
            e_prev: None,
            p_tried: None,
            gain_ratio: 0.0,
            err_roundoff: 0.0,
            lin: LinearSolver::new(),
            jac_h: 0.0,
            jac_valid: false,
            jac_point: None,
            pending: None,
            stats: Stats::default(),
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
            events: EventLocator::default(),
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

    /// Error weights (`wx`, `wv`) and Newton weights (`wn`) of an adaptive step of `h` [s]: the
    /// iteration stops at [`NEWTON_FRACTION`] of the step's share of the local error tolerance,
    /// but not below round-off. Returns the constraint violation accepted at convergence and the
    /// largest position scale [m].
    /// The first step [s] from `st`: `h_init`, or half the time in which the accelerations
    /// move the positions by their tolerance.
    fn initial_step(&mut self, sys: &System, st: &State) -> f64 {
        weights(sys, &st.q, &st.v, &self.s, &mut self.wx, &mut self.wv);
        let acc = wrms(&st.vdot, &self.wx).max(1e-12);
        if self.s.h_init > 0.0 {
            self.s.h_init
        } else {
            (0.5 * (2.0 / acc).sqrt()).min(self.s.h_max)
        }
    }

    /// How far an accepted step may grow (see [`MAX_GROWTH`]).
    fn step_policy(&self) -> StepPolicy {
        StepPolicy {
            max_growth: MAX_GROWTH,
            hysteresis: if self.s.equal_steps { 1.2 } else { 1.0 },
        }
    }

    fn adaptive_newton_weights(&mut self, sys: &System, st: &State, h: f64) -> (f64, f64) {
        weights(sys, &st.q, &st.v, &self.s, &mut self.wx, &mut self.wv);
        let floor = fixed_step_newton_weights(sys, &st.q, &mut self.wn);
        let share = self.s.error_share(h);
        let mut scale: f64 = 1e-3;
        for (n, w) in self.wn.iter_mut().zip(&self.wx) {
            // `wn` holds the round-off floor scaled like a weight (see fixed_step_newton_weights)
            *n = n.max(share * w);
        }
        scale = scale.max(floor);
        if !self.s.error_per_unit_step {
            // per step: the constraint violation of the whole tolerance, as it always was
            return (10.0 * self.s.atol, scale);
        }
        // constraints to round-off as with a fixed step: a violation left by one step is
        // corrected by the next as a velocity jump of `phi / (b h)`, which grows without bound
        // when the step shrinks (an energy rejection then shrank the step further: the step
        // collapsed to 1e-16 s on the double pendulum with a violation of `0.02 h atol`)
        (POSITION_ROUNDOFF * scale, scale)
    }

    /// Sizes the event-location buffers for `sys` (nothing for models without contact events).
    fn resize_events(&mut self, sys: &System) {
        self.events
            .size_for(sys, &mut self.xd, &mut self.vd, &mut self.qd);
    }

    /// The event functions (into `out`) at the fraction `theta` of the converged step of `h` [s]
    /// from `st`, on the step's own update formulas evaluated at `theta h` with the step's
    /// accelerations (exact at both ends, and for motion of constant acceleration before a
    /// contact).
    fn events_at(&mut self, sys: &mut System, st: &State, h: f64, theta: f64, out: &mut [f64]) {
        let (g, b) = (self.gamma, self.beta);
        let tau = theta * h;
        for k in 0..self.xd.len() {
            let (a0, a1) = (self.a[k], self.a1[k]);
            self.xd[k] = tau * st.v[k] + tau * tau * ((0.5 - b) * a0 + b * a1);
            self.vd[k] = st.v[k] + tau * ((1.0 - g) * a0 + g * a1);
        }
        sys.model.retract(&st.q, &self.xd, &mut self.qd);
        sys.contact_event_functions(st.t + tau, &self.qd, &self.vd, out);
    }

    /// After a converged step of `h` [s] from `st` (its end in `q1`, `v1`): the earliest contact
    /// closing or opening inside it as a fraction of the step, located to 1e-12 of the step;
    /// `events.landing` then holds the events at that instant. `None`: no contact closes or
    /// opens.
    fn events_in_step(&mut self, sys: &mut System, st: &State, h: f64) -> Option<f64> {
        let mut ev = std::mem::take(&mut self.events);
        sys.contact_event_functions(st.t + h, &self.q1, &self.v1, &mut ev.g1);
        let first = ev.locate(sys, st, |sys, m, out| self.events_at(sys, st, h, m, out));
        self.events = ev;
        first
    }

    /// Fills `a1`, `v1`, `dx`, `q1` from the current `w`.
    fn kinematics(&mut self, sys: &System, st: &State, h: f64) {
        let (am, af, g, b) = (self.am, self.af, self.gamma, self.beta);
        for i in 0..self.w.len() {
            self.a1[i] = (af * st.vdot[i] - am * self.a[i] + (1.0 - af) * self.w[i]) / (1.0 - am);
            self.v1[i] = st.v[i] + h * ((1.0 - g) * self.a[i] + g * self.a1[i]);
            self.dx[i] = h * st.v[i] + h * h * ((0.5 - b) * self.a[i] + b * self.a1[i]);
        }
        sys.model.retract(&st.q, &self.dx, &mut self.q1);
    }

    /// Solves step `h` (see [`GenAlpha::solve_step`]) with the discrete decisions of the force
    /// effects thawed again afterwards.
    fn try_step(&mut self, sys: &mut System, st: &State, h: f64) -> StepOutcome {
        let out = self.solve_step(sys, st, h);
        sys.thaw();
        out
    }

    /// The step's Newton iteration (bookkeeping in [`super::newton`]). The effects' discrete
    /// decisions (rope slip modes) are taken freely at the predictor and the first iterate, then
    /// frozen so the remaining iterations solve one smooth branch (without, iterates near a slip
    /// reversal switch modes back and forth and Newton stalls at rate ~1). A converged iterate
    /// counts only if the effects take the frozen decisions there themselves; if not, the
    /// decisions are taken again there and the iteration continues (a few times, then the step
    /// fails and is retried smaller), so the converged state is the one without freezing.
    fn solve_step(&mut self, sys: &mut System, st: &State, h: f64) -> StepOutcome {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        let t1 = st.t + h;
        let ca = (1.0 - self.af) / (1.0 - self.am);
        let cx = self.beta * h * h * ca;
        self.w.copy_from_slice(&st.vdot);
        self.lam.copy_from_slice(&st.lambda);
        let fixed = self.s.fixed_step > 0.0;
        // adaptive with the error held per unit step: constraints and Newton to round-off,
        // speeds projected, round-off allowed for in the error test (per step: none of these)
        let unit = !fixed && self.s.error_per_unit_step;
        // constraint violation accepted at convergence [m, rad]; largest position scale [m]
        let (phi_tol, scale) = if fixed {
            let scale = fixed_step_newton_weights(sys, &st.q, &mut self.wn);
            (POSITION_ROUNDOFF * scale, scale)
        } else {
            self.adaptive_newton_weights(sys, st, h)
        };
        let test = NewtonTest {
            fraction: NEWTON_FRACTION,
            first_factor: 1.0,
        };
        let mut progress = Progress::default();
        loop {
            self.kinematics(sys, st, h);
            progress.freeze_if_due(sys, t1, &self.q1, &self.v1);
            sys.forces(t1, &self.q1, &self.v1, &mut self.f);
            sys.eval_constraints(t1, &self.q1, &self.v1);
            self.stats.rhs_evaluations += 1;
            self.stats.newton_iterations += 1;
            // residual
            sys.mass_mul(&self.w, &mut self.tmp);
            for i in 0..nv {
                self.rhs[i] = self.f[i] - self.tmp[i];
            }
            let mut lam_neg = std::mem::take(&mut self.lam);
            lam_neg.iter_mut().for_each(|x| *x = -*x);
            sys.gt_mul_add(&lam_neg, &mut self.rhs[..nv]);
            lam_neg.iter_mut().for_each(|x| *x = -*x);
            self.lam = lam_neg;
            let mut phi_max: f64 = 0.0;
            for (r, row) in sys.rows.iter().enumerate() {
                self.rhs[nv + r] = -row.phi / cx;
                phi_max = phi_max.max(row.phi.abs());
            }
            if self.rhs.iter().any(|x| !x.is_finite()) {
                return StepOutcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::NonFinite("Newton residual"),
                });
            }
            let fresh = fresh_fixed_step_matrix(fixed, progress.iterations());
            if !self.jac_valid || !same_step(self.jac_h, h) || fresh {
                // a restored state's matrix is formed again at its recorded point, except where
                // the run it was saved from formed a fresh one (a fixed step's first iterate)
                let restored = if self.jac_valid {
                    None
                } else {
                    self.pending
                        .take()
                        .filter(|p| !fresh && same_step(p.coefficient, h))
                };
                // the matrix's own step: a restored point's, so the matrix is formed identically
                let hm = restored.as_ref().map_or(h, |p| p.coefficient);
                let cxm = self.beta * hm * hm * ca;
                let cvm = self.gamma * hm * ca;
                self.lin.begin(nv + nc);
                let lin = &mut self.lin;
                // the joints' geometric stiffness at the step's multipliers
                let stiff = forms_constraint_stiffness(fixed);
                let lam = &self.lam;
                match &restored {
                    Some(p) => p.with_recorded(sys, |sys| {
                        sys.eval_constraints(p.t, &p.q, &p.v);
                        // no stiffness: only adaptive steps form a matrix at a restored point
                        sys.add_dynamics_matrix(p.t, &p.q, &p.v, 1.0, cvm, cxm, lin, 0);
                        sys.add_constraint_blocks(lin, nv, 0, 1.0, Some((0, nv, 1.0)));
                        sys.eval_constraints(t1, &self.q1, &self.v1);
                    }),
                    None => {
                        sys.add_dynamics_matrix(t1, &self.q1, &self.v1, 1.0, cvm, cxm, lin, 0);
                        if stiff {
                            sys.add_constraint_stiffness(lam, cxm, lin, 0, 0);
                        }
                        sys.add_constraint_blocks(lin, nv, 0, 1.0, Some((0, nv, 1.0)));
                    }
                }
                let new = JacobianPoint::keep_or_record(
                    &mut self.jac_point,
                    restored,
                    sys,
                    t1,
                    &self.q1,
                    &self.v1,
                    h,
                );
                if new {
                    self.stats.jacobians += 1;
                    self.stats.factorizations += 1;
                }
                if let Err(e) = self.lin.factor() {
                    self.jac_valid = false;
                    return StepOutcome::Failed(factor_failure(&self.lin, e, t1));
                }
                self.jac_valid = true;
                self.jac_h = hm;
                // a restored matrix was observed when it was first formed (the restored
                // monitors hold that observation)
                if new {
                    self.rank
                        .observe(sys, &self.lin, nv, 1, t1, &mut self.stats);
                }
            }
            if let Err(e) = self.lin.solve(&mut self.rhs) {
                self.jac_valid = false;
                return StepOutcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::SingularMatrix(e),
                });
            }
            for i in 0..nv {
                self.w[i] += self.rhs[i];
                self.tmp[i] = cx * self.rhs[i];
            }
            for r in 0..nc {
                self.lam[r] += self.rhs[nv + r];
            }
            // On the index-3 form velocity increments carry round-off of order eps/h, so
            // convergence is judged on the position increments (which the velocities follow).
            let norm = wrms(&self.tmp, &self.wn);
            // largest position correction of this iterate [m, rad]: at convergence, the
            // round-off the positions actually carry
            let last_correction = self.tmp.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let rate = progress.rate(norm);
            // an iteration inside the round-off band that no longer contracts has converged:
            // its corrections are round-off. Adaptive steps take a rate of 0.2 as no longer
            // contracting (at 0.9, corrections of 10-30 epsilons that came and went at random
            // failed the steps of tight tolerances until the step collapsed); a fixed step
            // keeps iterating to 0.9 (at 0.2 the double pendulum's error at h = 1e-4 rose from
            // 5.7e-7 to 1.3e-6 m)
            let stall_rate = if fixed { 0.9 } else { 0.2 };
            // near a singular configuration the factorization amplifies round-off by the
            // inverse of its smallest pivot ratio: the round-off band widens with it
            let band = POSITION_ROUNDOFF * scale * self.rank.round_off_amplification();
            let stalled = (fixed || unit)
                && progress.iterations() >= 1
                && rate > stall_rate
                && self.tmp.iter().all(|x| x.abs() <= band);
            let verdict = progress.judge(&test, norm, stalled);
            if let Verdict::Diverged(rate) = verdict {
                return StepOutcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::Diverged(Some(rate)),
                });
            }
            let phi_tol = if unit {
                phi_tol * self.rank.round_off_amplification()
            } else {
                phi_tol
            };
            if verdict == Verdict::Converged && phi_max <= phi_tol {
                self.kinematics(sys, st, h);
                let (rtol, atol) = (self.s.rtol, self.s.atol);
                match progress.settle_decisions(sys, (t1, &self.q1, &self.v1), rtol, atol) {
                    Err(e) => return StepOutcome::Failed(e),
                    Ok(false) => continue,
                    Ok(true) => {}
                }
                let mut err = 0.0;
                if self.s.fixed_step == 0.0 {
                    let projected = if unit {
                        self.project_speeds(sys, t1)
                    } else {
                        Ok(())
                    };
                    if let Err(e) = projected {
                        self.jac_valid = false;
                        return StepOutcome::Failed(e);
                    }
                    let c = self.gamma / 2.0 - self.beta - 1.0 / 12.0;
                    for i in 0..nv {
                        self.tmp[i] = c * h * h * (self.a1[i] - self.a[i]);
                    }
                    // round-off the estimate carries: accelerations carry the round-off of
                    // positions `dx` (`eps scale`, or the last Newton correction if the
                    // iteration stalled in the round-off band) as `dx / (b h^2)`, so the
                    // estimate carries `c dx / b` whatever the step
                    let noise = if nc == 0 || !unit {
                        // no constraints: positions are not projected, accelerations carry no
                        // round-off of `1 / h^2`
                        0.0
                    } else if stalled {
                        last_correction.max(f64::EPSILON * scale)
                    } else {
                        f64::EPSILON * scale
                    } * self.rank.round_off_amplification();
                    let floor = NOISE_ALLOWANCE * c.abs() * noise / self.beta;
                    // the step's share of the tolerance, widened by the round-off: a step
                    // shortened to reach a communication point (down to 1e-12 s in event
                    // location) is not rejected for round-off it cannot remove
                    let share = self.s.error_share(h);
                    for (e, w) in self.werr.iter_mut().zip(&self.wx) {
                        *e = share * w + floor;
                    }
                    let safety = if self.s.error_per_unit_step {
                        ERROR_SAFETY
                    } else {
                        1.0
                    };
                    err = safety * wrms(&self.tmp, &self.werr);
                    for (e, w) in self.werr.iter_mut().zip(&self.wx) {
                        *e = share * w;
                    }
                    self.tmp.fill(floor);
                    self.err_roundoff = wrms(&self.tmp, &self.werr);
                    self.gain_ratio = self.energy_gain(sys, st, h);
                }
                return StepOutcome::Converged(err);
            }
            if progress.iterations() >= MAX_ITERATIONS {
                return StepOutcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::NoConvergence(MAX_ITERATIONS),
                });
            }
        }
    }

    /// Projects the step's speeds `v1` onto the velocity constraints `G v + Phi_t = 0` at `q1`
    /// (adaptive mode), with the step's Newton matrix as the metric (one more solve, no new
    /// factorization). The index-3 update leaves `G v1` off by the step's truncation error; a much
    /// smaller next step then corrects the predictor's normal motion `h G v1` through
    /// `a1 ~ G v1 / (b h)`, and the error estimate `h^2 (a1 - a0)`, taken per unit step, no longer
    /// falls with the step: after a rejection the step collapsed (double pendulum, rtol 1e-4).
    fn project_speeds(&mut self, sys: &mut System, t1: f64) -> Result<(), NewtonFailure> {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        if nc == 0 {
            return Ok(());
        }
        sys.eval_constraints(t1, &self.q1, &self.v1);
        self.rhs[..nv].fill(0.0);
        self.lam_scratch.resize(nc, 0.0);
        sys.g_mul(&self.v1, &mut self.lam_scratch);
        for (r, row) in sys.rows.iter().enumerate() {
            self.rhs[nv + r] = -(self.lam_scratch[r] + row.phi_t);
        }
        self.lin.solve(&mut self.rhs).map_err(|e| NewtonFailure {
            t: t1,
            cause: NewtonCause::SingularMatrix(e),
        })?;
        for (v, dv) in self.v1.iter_mut().zip(&self.rhs[..nv]) {
            *v += dv;
        }
        Ok(())
    }

    /// Energy gained by the step just solved, relative to its tolerance: the change of kinetic
    /// plus potential energy plus the energy dissipated minus the work put in (trapezoidal
    /// powers, as the state's balance books them). A passive step gains nothing, up to its
    /// truncation error (`O(h^3)`, like the position error, so the same step controller serves).
    ///
    /// Needed beside the position estimate: where positions are small against their scale (a
    /// contact penetration of 1e-7 m against atol 1e-9 m) the position weight admits relative
    /// errors of 1e-2 in the penetration, and an impact then returns up to several percent more
    /// energy than it took (an elastic 0.01 m/s impact with exponent 0.9 gained 6 %).
    ///
    /// The tolerance is `100 rtol` times the energy in play (kinetic and potential energy, work
    /// and dissipation of the step): the discrete energy of a second-order scheme fluctuates
    /// by more than `rtol` from step to step, and a tighter check (`10 rtol` was tried) keeps
    /// rejecting steps at tight tolerances (rtol 1e-11: 3.7 rejections per step, and a worse
    /// result from the step-size changes). With `100 rtol` the PanelLock runs take the same
    /// steps as without the check, and impacts at rtol 1e-6 gain at most 1.6e-4. The
    /// potential energy counts with its magnitude, zero level included: a scene with a large
    /// gravity potential (a lifted block) is checked loosely. Only passive steps (no work put
    /// in) that exchange potential energy are checked (see the code for why). If the steps keep
    /// gaining however small, the run stops with a message. Only growth rejects a step; the
    /// scheme's numerical damping (energy lost) never does. Speeds are not error-controlled
    /// themselves: on the index-3 form their estimate is polluted by the multipliers' transient
    /// on constrained bodies, and on free stiff structures (rope nodes) it would resolve the
    /// high frequencies the scheme is meant to damp (the RopeBlock lift took 19x the steps).
    fn energy_gain(&mut self, sys: &mut System, st: &State, h: f64) -> f64 {
        let t1 = st.t + h;
        let drive = sys.drive_power(&self.lam);
        let (pd, pi) = sys.powers(t1, &self.q1, &self.v1);
        let pi = pi + drive;
        self.p_tried = Some((pd, pi));
        let (pd0, pi0) = self.p_prev;
        if pi0 != 0.0 || pi != 0.0 {
            // work put in (a driven joint, a motor): not a passive step, and the trapezoidal
            // input work (with index-3 multipliers in it) is no reference to check against
            return 0.0;
        }
        let (k0, u0) = match self.e_prev {
            Some(e) => e,
            None => {
                let e = sys.energy_with(st.t, &st.q, &st.v, &mut self.tmp);
                self.e_prev = Some(e);
                e
            }
        };
        let (k1, u1) = sys.energy_with(t1, &self.q1, &self.v1, &mut self.tmp);
        if u1 == u0 {
            // no potential energy exchanged (a free body): nothing for the check to add to the
            // position control
            return 0.0;
        }
        let dissipated = 0.5 * h * (pd0 + pd);
        let input = 0.5 * h * (pi0 + pi);
        let gain = (k1 + u1) - (k0 + u0) + dissipated - input;
        let in_play = k0.max(k1) + u0.abs().max(u1.abs()) + dissipated.abs() + input.abs();
        // round-off of the energy sums
        let floor = 1e3 * f64::EPSILON * (k0 + k1 + u0.abs() + u1.abs());
        let mut tol = 100.0 * self.s.rtol * in_play + floor;
        if gain > tol {
            // below the energy the tolerance resolves: the kinetic energy of moving by the
            // position weights per ERROR_TIME_UNIT (a scene nearly at rest, such as slack
            // slings without gravity with 1e-20 J in play, rejected every step for gains of
            // 1e-20 J, mostly the dissipation's quadrature)
            sys.mass_mul(&self.wx, &mut self.tmp);
            let resolution = 0.5
                * self
                    .wx
                    .iter()
                    .zip(&self.tmp)
                    .map(|(w, mw)| w * mw)
                    .sum::<f64>()
                / (super::ERROR_TIME_UNIT * super::ERROR_TIME_UNIT);
            tol += resolution;
        }
        if tol > 0.0 { gain / tol } else { 0.0 }
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
        self.stats.steps += 1;
        self.stats.last_step = h;
    }
}

impl Integrator for GenAlpha {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::GenAlpha
    }

    fn start(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        self.resize(sys.n_q(), sys.n_v(), sys.n_c());
        self.a.copy_from_slice(&st.vdot);
        self.h = self.initial_step(sys, st);
        sys.eval_constraints(st.t, &st.q, &st.v);
        let drive = sys.drive_power(&st.lambda);
        let (pd, pi) = sys.powers(st.t, &st.q, &st.v);
        self.p_prev = (pd, pi + drive);
        self.e_prev = None;
        self.p_tried = None;
        self.jac_valid = false;
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
        let h = self.h;
        self.start(sys, st)?;
        self.h = h;
        Ok(())
    }

    fn stats(&self) -> Stats {
        self.stats
    }

    fn set_stats(&mut self, stats: Stats) {
        self.stats = stats;
    }

    fn clone_box(&self) -> Box<dyn Integrator> {
        Box::new(self.clone())
    }

    fn memory(&self) -> Vec<f64> {
        let mut m = vec![self.h, self.p_prev.0, self.p_prev.1, self.a.len() as f64];
        m.extend_from_slice(&self.a);
        // the matrix point: the valid one, or a restored one not formed again yet
        let point = match (&self.jac_point, self.jac_valid) {
            (Some(p), true) => Some(p),
            _ => self.pending.as_ref(),
        };
        match point {
            Some(p) => {
                m.push(1.0);
                p.write(&mut m);
            }
            None => m.push(0.0),
        }
        m
    }

    fn restore_memory(&mut self, m: &[f64]) -> Result<(), String> {
        let bad = || "gen-alpha memory is truncated or corrupt".to_string();
        if m.len() < 5 || !(m[3].is_finite() && m[3] >= 0.0) {
            return Err(bad());
        }
        let na = m[3] as usize;
        if m.len() < 5 + na {
            return Err(bad());
        }
        if !(m[0].is_finite() && m[0] >= 0.0) {
            return Err(bad());
        }
        self.h = m[0];
        self.p_prev = (m[1], m[2]);
        self.e_prev = None;
        self.p_tried = None;
        self.a = m[4..4 + na].to_vec();
        self.pending = if m[4 + na] > 0.5 {
            Some(JacobianPoint::read(&m[5 + na..])?.0)
        } else {
            None
        };
        self.jac_valid = false;
        self.jac_point = None;
        Ok(())
    }

    fn monitors(&self) -> Vec<f64> {
        let point = match (&self.jac_point, self.jac_valid) {
            (Some(p), true) => Some(p),
            _ => self.pending.as_ref(),
        };
        super::write_monitors(&[&self.rank], &self.lin, point)
    }

    fn restore_monitors(&mut self, m: &[f64]) -> Result<(), String> {
        super::read_monitors(
            m,
            &mut [&mut self.rank],
            &mut self.lin,
            self.pending.as_mut(),
        )
    }
}

/// Generalized-alpha's step, rejection and proposal for the step loop
/// ([`implicit::advance`]): halves the last step of a call or divides the call into equal
/// steps, rejects steps that gain energy, stops when the tolerance is below round-off.
impl ImplicitMethod for GenAlpha {
    type Estimate = f64;

    fn kind(&self) -> IntegratorKind {
        IntegratorKind::GenAlpha
    }

    fn settings(&self) -> &Settings {
        &self.s
    }

    fn h_mut(&mut self) -> &mut f64 {
        &mut self.h
    }

    fn stats_mut(&mut self) -> &mut Stats {
        &mut self.stats
    }

    fn events(&mut self) -> &mut EventLocator {
        &mut self.events
    }

    fn matrix_valid(&self) -> bool {
        self.jac_valid
    }

    fn invalidate_matrix(&mut self) {
        self.jac_valid = false;
    }

    fn begin_call(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        self.resize(sys.n_q(), sys.n_v(), sys.n_c());
        self.resize_events(sys);
        // a step size that cannot advance (a forged state) is chosen afresh, as at the start
        if self.s.fixed_step == 0.0 && step_control::collapsed(self.h, st.t) {
            self.h = self.initial_step(sys, st);
        }
        Ok(())
    }

    /// At most half the rest of the call (so the call does not end on a sliver), or equal
    /// steps to its end: the same step size (and Newton matrix) for all of them, and for the
    /// next call when its length is the same.
    fn trial_step(&self, natural: f64, remaining: f64) -> f64 {
        if !self.s.equal_steps {
            if natural > 0.5 * remaining {
                0.5 * remaining
            } else {
                natural
            }
        } else {
            remaining / (remaining / natural).ceil()
        }
    }

    fn try_step(&mut self, sys: &mut System, st: &State, h: f64) -> Result<f64, NewtonFailure> {
        match GenAlpha::try_step(self, sys, st, h) {
            StepOutcome::Converged(err) => Ok(err),
            StepOutcome::Failed(newton) => Err(newton),
        }
    }

    /// A step that gains energy beyond the tolerance is rejected like one with too large an
    /// error; every next step is proposed from the larger of the two estimates (both O(h^3)),
    /// so an energy rejection is not followed by a step grown from the position error alone
    /// that the energy check rejects again.
    fn rejects(&self, err: &f64) -> bool {
        step_control::rejects(err.max(self.gain_ratio))
    }

    fn rejected(&mut self, st: &State, h: f64, err: &f64, _: u32) -> Result<(), SolverError> {
        let err = *err;
        self.stats.rejected += 1;
        if self.gain_ratio > err {
            self.stats.rejected_energy += 1;
        } else {
            self.stats.rejected_error += 1;
        }
        self.h = step_control::after_rejection(
            h,
            step_factor(err, self.gain_ratio, self.s.error_per_unit_step),
        );
        // inside a singular configuration the positions' round-off grows with the conditioning
        // for a while: the allowance widens the test there instead of stopping the run
        if err >= self.gain_ratio
            && self.s.error_per_unit_step
            && !self.rank.inside()
            && (self.err_roundoff * h / self.h >= ROUNDOFF_SHARE_LIMIT
                || step_control::collapsed(self.h, st.t))
        {
            return Err(SolverError::at(
                IntegratorKind::GenAlpha,
                st.t,
                Cause::Tolerance {
                    rtol: self.s.rtol,
                    atol: self.s.atol,
                    h: self.h,
                    share: self.err_roundoff * h / self.h,
                },
            ));
        }
        if self.gain_ratio > 1.0 && step_control::collapsed(self.h, st.t) {
            return Err(SolverError::at(
                IntegratorKind::GenAlpha,
                st.t,
                Cause::StepCollapse {
                    h: self.h,
                    why: Collapse::EnergyGain {
                        gain: self.gain_ratio,
                    },
                },
            ));
        }
        Ok(())
    }

    fn event_in_step(&mut self, sys: &mut System, st: &State, h: f64, _: &f64) -> Option<f64> {
        self.events_in_step(sys, st, h)
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64, _: &f64) {
        GenAlpha::accept(self, sys, st, h);
    }

    fn on_action(
        &mut self,
        sys: &mut System,
        st: &mut State,
        action: StepAction,
        jump: bool,
    ) -> Result<Flow, SolverError> {
        match action {
            // the step starts from the state itself (positions, speeds and the algorithmic
            // accelerations), so a moved state needs nothing
            StepAction::Continue | StepAction::Moved if !jump => {}
            // forces that jump need accelerations consistent with them
            StepAction::Continue | StepAction::Moved | StepAction::Restart => {
                self.restart(sys, st)?
            }
            StepAction::Stop => return Ok(Flow::Stop),
        }
        Ok(Flow::Propose)
    }

    fn propose(&mut self, h: f64, natural: f64, err: &f64) {
        self.h = self.step_policy().after_acceptance(
            h,
            natural,
            self.h,
            step_factor(*err, self.gain_ratio, self.s.error_per_unit_step),
        );
    }
}
