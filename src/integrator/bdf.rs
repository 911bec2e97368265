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
use super::events::EventLocator;
use super::implicit::{self, Flow, ImplicitMethod};
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
    s: Settings,
    hist: VecDeque<Point>,
    h: f64,
    order: usize,
    steps_at_order: usize,
    /// Accepted steps since the last (re)start (drives the start-up order ramp).
    since_start: usize,
    lin: LinearSolver,
    jac_alpha0: f64,
    jac_valid: bool,
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
    stats: Stats,
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
    /// Contact-event location (adaptive mode), and scratch for the interpolant inside a step:
    /// chart coordinates, speeds and positions at a fraction of it.
    events: EventLocator,
    xd: Vec<f64>,
    vd: Vec<f64>,
    qd: Vec<f64>,
}

/// Largest magnitude in `a` (0 when empty).
fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Weights `w` with `p(tau) = sum w_j y_j` for the polynomial through `(ts[j], y_j)`.
fn interp_weights(ts: &[f64], tau: f64, w: &mut [f64]) {
    for j in 0..ts.len() {
        let mut l = 1.0;
        for i in 0..ts.len() {
            if i != j {
                l *= (tau - ts[i]) / (ts[j] - ts[i]);
            }
        }
        w[j] = l;
    }
}

/// Weights `w` with `p'(ts[0]) = sum w_j y_j`.
fn derivative_weights(ts: &[f64], w: &mut [f64]) {
    let tau = ts[0];
    for j in 0..ts.len() {
        let mut d = 0.0;
        for m in 0..ts.len() {
            if m == j {
                continue;
            }
            let mut p = 1.0 / (ts[j] - ts[m]);
            for i in 0..ts.len() {
                if i != j && i != m {
                    p *= (tau - ts[i]) / (ts[j] - ts[i]);
                }
            }
            d += p;
        }
        w[j] = d;
    }
}

/// Assembles the GGL Newton matrix at `(t, q, v)` with leading coefficient `a0` (the constraint
/// rows must be evaluated there): unknowns `[dx, dv, dlambda, dmu]`.
fn assemble(sys: &mut System, lin: &mut LinearSolver, t: f64, q: &[f64], v: &[f64], a0: f64) {
    let (nv, nc) = (sys.n_v(), sys.n_c());
    lin.begin(2 * nv + 2 * nc);
    for i in 0..nv {
        lin.push(i, i, a0);
        lin.push(i, nv + i, -1.0);
    }
    sys.add_constraint_blocks(lin, 2 * nv, 0, a0, Some((0, 2 * nv + nc, 1.0)));
    sys.add_dynamics_matrix_at(t, q, v, [a0, 1.0, 0.0], lin, nv, nv);
    sys.add_dynamics_matrix_at(t, q, v, [0.0, 0.0, 1.0], lin, nv, 0);
    sys.add_constraint_blocks(lin, 2 * nv + nc, nv, 1.0, Some((nv, 2 * nv, 1.0)));
}

enum Outcome {
    Converged,
    Failed(NewtonFailure),
}

impl Bdf {
    /// A new integrator with the given settings.
    pub fn new(s: Settings) -> Self {
        Bdf {
            s,
            hist: VecDeque::new(),
            h: 0.0,
            order: 1,
            steps_at_order: 0,
            since_start: 0,
            lin: LinearSolver::new(),
            jac_alpha0: 0.0,
            jac_valid: false,
            per_unit_step: false,
            round_off: [0.0; 2],
            lam_last: (0.0, Vec::new()),
            lam_prev: None,
            jac_point: None,
            pending: None,
            stats: Stats::default(),
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
            events: EventLocator::default(),
            xd: Vec::new(),
            vd: Vec::new(),
            qd: Vec::new(),
        }
    }

    /// Sizes the event-location buffers for `sys` (nothing for models without contact events).
    fn resize_events(&mut self, sys: &System) {
        self.events
            .size_for(sys, &mut self.xd, &mut self.vd, &mut self.qd);
    }

    /// The event functions (into `out`) at the fraction `theta` of the converged step of order
    /// `k` and size `h` [s] that ends in `x`, `v`: on the step's own polynomial, through its end
    /// and the `k` newest history points (exact at the step's ends).
    fn events_at(&mut self, sys: &mut System, k: usize, h: f64, theta: f64, out: &mut [f64]) {
        let t0 = self.hist[0].t;
        let mut ts = [0.0; 8];
        ts[0] = t0 + h;
        for (slot, p) in ts[1..].iter_mut().zip(self.hist.iter().take(k)) {
            *slot = p.t;
        }
        let mut w = [0.0; 8];
        let tau = t0 + theta * h;
        interp_weights(&ts[..k + 1], tau, &mut w[..k + 1]);
        for i in 0..self.xd.len() {
            let (mut sx, mut sv) = (w[0] * self.x[i], w[0] * self.v[i]);
            for j in 0..k {
                sx += w[j + 1] * self.xs[j][i];
                sv += w[j + 1] * self.hist[j].v[i];
            }
            self.xd[i] = sx;
            self.vd[i] = sv;
        }
        sys.model.retract(&self.hist[0].q, &self.xd, &mut self.qd);
        sys.contact_event_functions(tau, &self.qd, &self.vd, out);
    }

    /// After a converged step of order `k` and size `h` [s] from `st` (its end in `q1`, `v`):
    /// the earliest contact closing or opening inside it as a fraction of the step, located to
    /// 1e-12 of the step; `events.landing` then holds the events at that instant. `None`: no
    /// contact closes or opens.
    fn events_in_step(&mut self, sys: &mut System, st: &State, k: usize, h: f64) -> Option<f64> {
        let mut ev = std::mem::take(&mut self.events);
        sys.contact_event_functions(st.t + h, &self.q1, &self.v, &mut ev.g1);
        let first = ev.locate(sys, st, |sys, m, out| self.events_at(sys, k, h, m, out));
        self.events = ev;
        first
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

    /// Keeps the state's accelerations for the first step's predictor while the history holds
    /// only the state's own point (after a start, a restart or a restored memory); finite and of
    /// the right length, else none.
    fn note_start_vdot(&mut self, st: &State) {
        self.start_vdot.clear();
        if self.hist.len() == 1
            && self.hist[0].t == st.t
            && st.vdot.len() == st.v.len()
            && st.vdot.iter().all(|a| a.is_finite())
        {
            self.start_vdot.extend_from_slice(&st.vdot);
        }
    }

    fn push_point(&mut self, st: &State) {
        // recycle the oldest point's storage once the history is full (no allocation per step)
        let mut p = if self.hist.len() >= 7 {
            self.hist.pop_back().unwrap_or(Point {
                t: 0.0,
                q: Vec::new(),
                v: Vec::new(),
                z: [0.0; 2],
            })
        } else {
            Point {
                t: 0.0,
                q: Vec::new(),
                v: Vec::new(),
                z: [0.0; 2],
            }
        };
        p.t = st.t;
        p.q.clone_from(&st.q);
        p.v.clone_from(&st.v);
        p.z = [st.energy_dissipated, st.work_input];
        self.hist.push_front(p);
    }

    /// Translates every history point by the displacement a step hook gave the newest one
    /// (`st.q - q_newest`, coordinate by coordinate; see [`StepAction::Moved`]): the backward
    /// differences, and with them the speeds the next steps infer, stay as they were. Without
    /// it the next step would start from the stored point, not the moved one.
    fn translate_history(&mut self, st: &State) {
        if self.hist.is_empty() {
            return;
        }
        for i in 0..st.q.len() {
            let d = st.q[i] - self.hist[0].q[i];
            if d != 0.0 {
                for p in self.hist.iter_mut() {
                    p.q[i] += d;
                }
            }
        }
    }

    /// Chart coordinates of history points `0..m` relative to the newest.
    fn chart_history(&mut self, sys: &System, m: usize) {
        let nv = sys.n_v();
        self.xs.resize(m, Vec::new());
        for j in 0..m {
            self.xs[j].resize(nv, 0.0);
            if j == 0 {
                self.xs[0].fill(0.0);
            } else {
                let mut x = std::mem::take(&mut self.xs[j]);
                sys.model.local(&self.hist[0].q, &self.hist[j].q, &mut x);
                self.xs[j] = x;
            }
        }
    }

    /// Newton iteration for one step of order `k` to `t1`; leaves the solution in `x`, `v`, ...
    fn solve_step(&mut self, sys: &mut System, k: usize, t1: f64, alpha: &[f64]) -> Outcome {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        let a0 = alpha[0];
        let n = 2 * nv + 2 * nc;
        self.q0.clone_from(&self.hist[0].q);
        let test = NewtonTest {
            fraction: NEWTON_FRACTION,
            first_factor: FIRST_CORRECTION_FACTOR,
        };
        let mut progress = Progress::default();
        let mut slow = false;
        loop {
            sys.model.retract(&self.q0, &self.x, &mut self.q1);
            progress.freeze_if_due(sys, t1, &self.q1, &self.v);
            sys.forces(t1, &self.q1, &self.v, &mut self.f);
            sys.eval_constraints(t1, &self.q1, &self.v);
            self.stats.rhs_evaluations += 1;
            self.stats.newton_iterations += 1;
            // x rows: -(sum alpha x - dexp_inv(x) v + G^T mu)
            sys.model.chart_rate(&self.x, &self.v, &mut self.tmp);
            for i in 0..nv {
                let mut s = a0 * self.x[i];
                for j in 0..k {
                    s += alpha[j + 1] * self.xs[j][i];
                }
                self.rhs[i] = -(s - self.tmp[i]);
            }
            self.gtmu.fill(0.0);
            sys.gt_mul_add(&self.mu, &mut self.gtmu);
            for (r, g) in self.rhs[..nv].iter_mut().zip(&self.gtmu) {
                *r -= g;
            }
            // v rows: -(M sum alpha v + G^T lambda - f)
            for i in 0..nv {
                let mut s = a0 * self.v[i];
                for j in 0..k {
                    s += alpha[j + 1] * self.hist[j].v[i];
                }
                self.vdot[i] = s;
            }
            sys.mass_mul(&self.vdot, &mut self.tmp);
            for i in 0..nv {
                self.rhs[nv + i] = self.f[i] - self.tmp[i];
            }
            self.lam.iter_mut().for_each(|l| *l = -*l);
            sys.gt_mul_add(&self.lam, &mut self.rhs[nv..2 * nv]);
            self.lam.iter_mut().for_each(|l| *l = -*l);
            let mut phi_max: f64 = 0.0;
            sys.g_mul(&self.v, &mut self.gv);
            let gv = &self.gv;
            for (r, row) in sys.rows.iter().enumerate() {
                self.rhs[2 * nv + r] = -a0 * row.phi;
                self.rhs[2 * nv + nc + r] = -(gv[r] + row.phi_t);
                phi_max = phi_max.max(row.phi.abs());
            }
            if self.rhs[..n].iter().any(|x| !x.is_finite()) {
                return Outcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::NonFinite("Newton residual"),
                });
            }
            let restored = if self.jac_valid {
                None
            } else {
                self.pending
                    .take()
                    .filter(|p| (a0 / p.coefficient - 1.0).abs() <= MATRIX_COEFFICIENT_CHANGE)
            };
            let refresh =
                !self.jac_valid || (a0 / self.jac_alpha0 - 1.0).abs() > MATRIX_COEFFICIENT_CHANGE;
            if refresh {
                let lin = &mut self.lin;
                match &restored {
                    Some(p) => p.with_recorded(sys, |sys| {
                        sys.eval_constraints(p.t, &p.q, &p.v);
                        assemble(sys, lin, p.t, &p.q, &p.v, p.coefficient);
                        sys.eval_constraints(t1, &self.q1, &self.v);
                    }),
                    None => assemble(sys, lin, t1, &self.q1, &self.v, a0),
                }
                let new = JacobianPoint::keep_or_record(
                    &mut self.jac_point,
                    restored,
                    sys,
                    t1,
                    &self.q1,
                    &self.v,
                    a0,
                );
                if new {
                    self.stats.jacobians += 1;
                    self.stats.factorizations += 1;
                }
                self.jac_alpha0 = self.jac_point.as_ref().map_or(a0, |p| p.coefficient);
                if let Err(e) = self.lin.factor() {
                    self.jac_valid = false;
                    return Outcome::Failed(factor_failure(&self.lin, e, t1));
                }
                self.jac_valid = true;
                // a restored matrix was observed when it was first formed: the restored monitors
                // hold that observation (observing again would read the rows evaluated last, at
                // this step's point, not the matrix's)
                if new {
                    let nv = sys.n_v();
                    self.rank.observe_factorization(
                        sys,
                        &self.lin,
                        (2 * nv, 2),
                        t1,
                        &mut self.stats,
                    );
                }
            }
            if let Err(e) = self.lin.solve(&mut self.rhs[..n]) {
                self.jac_valid = false;
                return Outcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::SingularMatrix(e),
                });
            }
            for i in 0..nv {
                self.x[i] += self.rhs[i];
                self.v[i] += self.rhs[nv + i];
            }
            for r in 0..nc {
                self.lam[r] += self.rhs[2 * nv + r];
                self.mu[r] += self.rhs[2 * nv + nc + r];
            }
            let norm = wrms(&self.rhs[..nv], &self.wx).max(wrms(&self.rhs[nv..2 * nv], &self.wv));
            let it = progress.iterations();
            let rate = progress.rate(norm);
            let (dx, dv) = (max_abs(&self.rhs[..nv]), max_abs(&self.rhs[nv..2 * nv]));
            // near a singular configuration the factorization amplifies round-off by the
            // inverse of its smallest pivot ratio: the round-off band widens with it (from the
            // approach on, not only inside a passage: at rtol 3e-10 .. 3e-9 the iteration
            // stalled in amplified round-off before the ratio reached the passage threshold)
            let amp = self.rank.conditioning_amplification();
            let round_off = dx <= NEWTON_ROUND_OFF_EPSILONS * self.round_off[0] * amp
                && dv <= NEWTON_ROUND_OFF_EPSILONS * self.round_off[1] * amp;
            // stopped contracting at round-off: converged as far as the arithmetic goes
            let stalled = it >= 1 && rate > DIVERGENCE_RATE && round_off;
            slow |= it >= 2 && rate > REFRESH_RATE;
            // a first correction shows no contraction rate yet: it is taken as converged only
            // when it is negligible (1e-4 of the tolerance, FIRST_CORRECTION_FACTOR); accepting
            // larger first corrections of a reused matrix leaves a per-step error that makes
            // fixed-step BDF first order
            let verdict = progress.judge(&test, norm, stalled);
            if let Verdict::Diverged(_) = verdict {
                return Outcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::Diverged(None),
                });
            }
            if verdict == Verdict::Converged && (stalled || phi_max <= 10.0 * self.s.atol) {
                sys.model.retract(&self.q0, &self.x, &mut self.q1);
                let (rtol, atol) = (self.s.rtol, self.s.atol);
                match progress.settle_decisions(sys, (t1, &self.q1, &self.v), rtol, atol) {
                    Err(e) => return Outcome::Failed(e),
                    Ok(false) => continue,
                    Ok(true) => {}
                }
                self.set_vdot(k, alpha);
                if slow && !stalled {
                    // the next step forms its matrix afresh
                    self.jac_valid = false;
                }
                return Outcome::Converged;
            }
            if progress.iterations() >= MAX_ITERATIONS {
                return Outcome::Failed(NewtonFailure {
                    t: t1,
                    cause: NewtonCause::NoConvergence(MAX_ITERATIONS),
                });
            }
        }
    }

    /// Starts the multipliers at `t1` [s] on the line through those of the last two accepted
    /// points (at those of the last one when only it is known). A constant start leaves a
    /// first-order residual `G^T (lambda_1 - lambda_n)` which a Newton matrix formed at an
    /// earlier configuration turns into large, mostly cancelling speed corrections.
    fn predict_multipliers(&mut self, nc: usize, t1: f64) {
        let (t0, last) = (self.lam_last.0, &self.lam_last.1);
        self.lam.clear();
        self.lam.extend_from_slice(last);
        self.lam.resize(nc, 0.0);
        if let Some((tp, lp)) = &self.lam_prev
            && lp.len() == nc
            && last.len() == nc
            && t0 > *tp
        {
            let c = (t1 - t0) / (t0 - tp);
            for (l, p) in self.lam.iter_mut().zip(lp) {
                *l += c * (*l - p);
            }
        }
    }

    /// The BDF derivative of the speeds at the new point (`sum alpha_j v_j`) into `vdot`.
    fn set_vdot(&mut self, k: usize, alpha: &[f64]) {
        for i in 0..self.v.len() {
            let mut s = alpha[0] * self.v[i];
            for j in 0..k {
                s += alpha[j + 1] * self.hist[j].v[i];
            }
            self.vdot[i] = s;
        }
    }

    /// Tries one step of size `h` at the current order. Returns the error estimates at orders
    /// (k-1, k, k+1) (NaN where unavailable) on convergence.
    fn try_step(&mut self, sys: &mut System, h: f64) -> Result<[f64; 3], NewtonFailure> {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        let k = self.order.min(self.hist.len());
        let t1 = self.hist[0].t + h;
        let navail = self.hist.len();
        self.chart_history(sys, navail);
        // predictor through k+1 points if available (k otherwise)
        let np = (k + 1).min(navail);
        let mut ts = [0.0; 8];
        for (slot, p) in ts.iter_mut().zip(self.hist.iter().take(np)) {
            *slot = p.t;
        }
        let mut wp = [0.0; 8];
        interp_weights(&ts[..np], t1, &mut wp[..np]);
        // the first step from one point: a Taylor predictor with the known derivatives, so
        // that its difference to the corrector (the error estimate) is O(h^2), as a predictor
        // through k + 1 points makes it; through the point alone it would be the whole change
        // of the speeds over the step, O(h), which a tolerance shared per unit step (also
        // O(h)) never accepts where the accelerations are large against it (the flexible
        // panels' modes at t = 0)
        let taylor = np == 1 && self.start_vdot.len() == nv;
        for i in 0..nv {
            if taylor {
                self.x[i] = self.xs[0][i] + h * self.hist[0].v[i];
                self.v[i] = self.hist[0].v[i] + h * self.start_vdot[i];
                continue;
            }
            let (mut sx, mut sv) = (0.0, 0.0);
            for (j, w) in wp[..np].iter().enumerate() {
                sx += w * self.xs[j][i];
                sv += w * self.hist[j].v[i];
            }
            self.x[i] = sx;
            self.v[i] = sv;
        }
        self.xp.copy_from_slice(&self.x);
        self.vp.copy_from_slice(&self.v);
        self.mu.iter_mut().for_each(|m| *m = 0.0);
        self.predict_multipliers(nc, t1);
        // corrector weights over t1, t_n, ..., t_{n-k+1}
        ts[0] = t1;
        for (slot, p) in ts[1..].iter_mut().zip(self.hist.iter().take(k)) {
            *slot = p.t;
        }
        let mut alpha = [0.0; 8];
        derivative_weights(&ts[..k + 1], &mut alpha[..k + 1]);
        weights(
            sys,
            &self.hist[0].q,
            &self.hist[0].v,
            &self.s,
            &mut self.wx,
            &mut self.wv,
        );
        self.scale_weights(h);
        if let Outcome::Failed(e) = self.solve_step(sys, k, t1, &alpha[..k + 1]) {
            return Err(e);
        }
        if self.s.fixed_step > 0.0 {
            return Ok([f64::NAN, 0.0, f64::NAN]);
        }
        // error at order k; the Taylor predictor of the first step stands for one through two
        // points a step apart (span 2h)
        let span = t1 - self.hist[np - 1].t;
        let c = if taylor { 0.5 } else { h / span };
        for i in 0..nv {
            self.ex[i] = c * (self.x[i] - self.xp[i]);
            self.ev[i] = c * (self.v[i] - self.vp[i]);
        }
        let err_k = self.combined(wrms(&self.ex, &self.wx), wrms(&self.ev, &self.wv));
        let err_k = if np < k + 1 { err_k.max(1e-300) } else { err_k };
        let err_lo = if k >= 2 {
            self.scaled_divided_difference(k, t1, h, navail) / k as f64
        } else {
            f64::NAN
        };
        let err_hi = if k < self.s.max_order && navail >= k + 2 {
            self.scaled_divided_difference(k + 2, t1, h, navail) / (k + 2) as f64
        } else {
            f64::NAN
        };
        Ok([err_lo, err_k, err_hi])
    }

    /// Scales the error weights `wx`, `wv` (built from rtol/atol at the step's start) to the
    /// share of the tolerance a step of `h` [s] may use: `h / ERROR_TIME_UNIT` of it (all of it from
    /// `ERROR_TIME_UNIT` on, with fixed steps and with `Settings::error_per_unit_step` off), never
    /// below the round-off floor
    /// ([`ROUND_OFF_EPSILONS`]).
    fn scale_weights(&mut self, h: f64) {
        if self.s.fixed_step > 0.0 {
            self.per_unit_step = false;
            self.round_off = [0.0; 2];
            return;
        }
        let f = self.s.error_share(h);
        self.per_unit_step = f < 1.0;
        // weights are atol + rtol * scale: recover the largest position scale [m or rad]; a
        // body at the origin still moves by its speed: lengths and speeds scale each other
        let x_scale = self
            .wx
            .iter()
            .map(|w| (w - self.s.atol) / self.s.rtol)
            .fold(0.0, f64::max);
        let v_max = max_abs(&self.hist[0].v);
        let (x_scale, v_scale) = (
            x_scale.max(v_max * ERROR_TIME_UNIT),
            v_max.max(x_scale / ERROR_TIME_UNIT),
        );
        self.round_off = [f64::EPSILON * x_scale, f64::EPSILON * v_scale];
        // near a singular configuration the solution carries round-off amplified by the
        // factorization (the inverse of its smallest pivot ratio)
        let amp = self.rank.conditioning_amplification();
        let [fx, fv] = self.round_off.map(|r| ROUND_OFF_EPSILONS * r * amp);
        // the floor never loosens a weight beyond its tolerance per step
        self.wx
            .iter_mut()
            .for_each(|w| *w = (f * *w).max(fx.min(*w)));
        self.wv
            .iter_mut()
            .for_each(|w| *w = (f * *w).max(fv.min(*w)));
    }

    /// Order in `h` of the error estimates of an order-`k` step at the current tolerance
    /// fraction: `k + 1` per step, `k` per unit step.
    fn estimate_order(&self, k: usize) -> f64 {
        if self.per_unit_step {
            k as f64
        } else {
            k as f64 + 1.0
        }
    }

    /// Weighted norm of the scaled divided difference `j! h^j y[t1, t_n, ...]` of order `j` of the
    /// new solution and the history (about `h^j y^(j)`); NaN when the history is too short.
    fn scaled_divided_difference(&mut self, j: usize, t1: f64, h: f64, navail: usize) -> f64 {
        if j > navail || j + 1 > 8 {
            return f64::NAN;
        }
        let mut ts = [0.0; 8];
        ts[0] = t1;
        for (slot, p) in ts[1..].iter_mut().zip(self.hist.iter().take(j)) {
            *slot = p.t;
        }
        let scale = (1..=j).map(|m| m as f64).product::<f64>() * h.powi(j as i32);
        for i in 0..self.x.len() {
            let (mut vx, mut vv) = ([0.0; 8], [0.0; 8]);
            vx[0] = self.x[i];
            vv[0] = self.v[i];
            for m in 0..j {
                vx[m + 1] = self.xs[m][i];
                vv[m + 1] = self.hist[m].v[i];
            }
            for lvl in 1..=j {
                for m in 0..=(j - lvl) {
                    let dt = ts[m] - ts[m + lvl];
                    vx[m] = (vx[m] - vx[m + 1]) / dt;
                    vv[m] = (vv[m] - vv[m + 1]) / dt;
                }
            }
            self.ex[i] = scale * vx[0];
            self.ev[i] = scale * vv[0];
        }
        self.combined(wrms(&self.ex, &self.wx), wrms(&self.ev, &self.wv))
    }

    /// The error norm of a step from its weighted position and speed errors: their RMS, or the
    /// position error alone without [`Settings::error_includes_speeds`].
    fn combined(&self, position: f64, speed: f64) -> f64 {
        if self.s.error_includes_speeds {
            ((position * position + speed * speed) * 0.5).sqrt()
        } else {
            position
        }
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64, alpha0_k: usize) {
        let t1 = self.hist[0].t + h;
        // quadrature of powers with the same BDF formula (explicit in z)
        let drive = sys.drive_power(&self.lam);
        let (pd, pi) = sys.powers(t1, &self.q1, &self.v);
        let pi = pi + drive;
        let k = alpha0_k;
        let mut ts = [0.0; 8];
        ts[0] = t1;
        for (slot, p) in ts[1..].iter_mut().zip(self.hist.iter().take(k)) {
            *slot = p.t;
        }
        let mut alpha = [0.0; 8];
        derivative_weights(&ts[..k + 1], &mut alpha[..k + 1]);
        let mut z = [0.0; 2];
        for (c, p) in [pd, pi].into_iter().enumerate() {
            let mut s = 0.0;
            for j in 0..k {
                s += alpha[j + 1] * self.hist[j].z[c];
            }
            z[c] = (p - s) / alpha[0];
        }
        st.t = t1;
        st.q.copy_from_slice(&self.q1);
        st.v.copy_from_slice(&self.v);
        st.vdot.copy_from_slice(&self.vdot);
        st.lambda.clear();
        st.lambda.extend_from_slice(&self.lam);
        // the last multipliers become the previous ones (their storage reused)
        let mut older = self.lam_prev.take().map(|p| p.1).unwrap_or_default();
        std::mem::swap(&mut older, &mut self.lam_last.1);
        self.lam_prev = Some((self.lam_last.0, older));
        self.lam_last.0 = t1;
        self.lam_last.1.clone_from(&self.lam);
        st.energy_dissipated = z[0];
        st.work_input = z[1];
        self.push_point(st);
        self.since_start += 1;
        self.stats.steps += 1;
        self.stats.last_step = h;
    }

    /// The first step [s] from `st`: `h_init`, or the time in which the speeds or accelerations
    /// move by 1e-3 of their tolerance, within `[MIN_H_MAX, h_max]`.
    fn initial_step(&mut self, sys: &System, st: &State) -> f64 {
        weights(sys, &st.q, &st.v, &self.s, &mut self.wx, &mut self.wv);
        let acc = wrms(&st.vdot, &self.wv)
            .max(wrms(&st.v, &self.wx))
            .max(1e-12);
        if self.s.h_init > 0.0 {
            self.s.h_init
        } else {
            (0.001 / acc).clamp(super::MIN_H_MAX.min(self.s.h_max), self.s.h_max)
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
            rtol: self.s.rtol,
        })
    }

    /// Fixed-step start: fills the history with `order - 1` points from a tight DOPRI5 run.
    fn bootstrap(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        let h = self.s.fixed_step;
        let tight = Settings {
            rtol: super::MIN_RTOL,
            atol: 1e-15,
            h_max: h,
            fixed_step: 0.0,
            ..self.s
        };
        let mut rk = Dopri5::new(tight);
        rk.start(sys, st)?;
        while self.hist.len() < self.s.max_order {
            let t = st.t + h;
            rk.advance_to(sys, st, t, &mut MemoryHook)?;
            self.push_point(st);
        }
        self.order = self.s.max_order;
        Ok(())
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
        self.h = self.initial_step(sys, st);
        self.jac_valid = false;
        self.pending = None;
        if !self.rows.observed() && sys.has_loops() {
            sys.eval_constraints(st.t, &st.q, &st.v);
            self.rows.observe_rows(sys, st.t, &mut self.stats);
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
        let h = self.h;
        self.start(sys, st)?;
        self.h = h.min(self.s.h_max);
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
        let mut m = vec![
            self.h,
            self.order as f64,
            self.steps_at_order as f64,
            self.since_start as f64,
            self.hist.len() as f64,
        ];
        for p in &self.hist {
            m.push(p.t);
            m.push(p.q.len() as f64);
            m.extend_from_slice(&p.q);
            m.push(p.v.len() as f64);
            m.extend_from_slice(&p.v);
            m.extend_from_slice(&p.z);
        }
        m.push(self.lam.len() as f64);
        m.extend_from_slice(&self.lam);
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
        // optional (states written before it have none): the previous multipliers
        if let Some((t, l)) = &self.lam_prev {
            m.push(*t);
            m.push(l.len() as f64);
            m.extend_from_slice(l);
        }
        m
    }

    fn restore_memory(&mut self, m: &[f64]) -> Result<(), String> {
        let bad = || "bdf memory is truncated or corrupt".to_string();
        let mut pos = 0usize;
        let next = |pos: &mut usize| -> Result<f64, String> {
            let v = *m.get(*pos).ok_or_else(bad)?;
            *pos += 1;
            Ok(v)
        };
        // a length of what follows: at most what is left
        let count = |x: f64| {
            if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= m.len() as f64 {
                Ok(x as usize)
            } else {
                Err(bad())
            }
        };
        // a step counter: any whole number up to 2^53 (not bounded by the memory's length)
        let counter = |x: f64| {
            if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= 9.007_199_254_740_992e15 {
                Ok(x as usize)
            } else {
                Err(bad())
            }
        };
        let h = next(&mut pos)?;
        let order = count(next(&mut pos)?)?;
        let sao = counter(next(&mut pos)?)?;
        let since = counter(next(&mut pos)?)?;
        let n = count(next(&mut pos)?)?;
        if !(1..=5).contains(&order) || n > 7 || !(h.is_finite() && h > 0.0) {
            return Err(bad());
        }
        let mut hist = VecDeque::new();
        for _ in 0..n {
            let t = next(&mut pos)?;
            let nq = count(next(&mut pos)?)?;
            let q = (0..nq)
                .map(|_| next(&mut pos))
                .collect::<Result<Vec<_>, _>>()?;
            let nv = count(next(&mut pos)?)?;
            let v = (0..nv)
                .map(|_| next(&mut pos))
                .collect::<Result<Vec<_>, _>>()?;
            let z = [next(&mut pos)?, next(&mut pos)?];
            hist.push_back(Point { t, q, v, z });
        }
        let nl = count(next(&mut pos)?)?;
        let lam = (0..nl)
            .map(|_| next(&mut pos))
            .collect::<Result<Vec<_>, _>>()?;
        let has_jac = next(&mut pos)? > 0.5;
        self.pending = if has_jac {
            let (p, used) = JacobianPoint::read(&m[pos..])?;
            pos += used;
            Some(p)
        } else {
            None
        };
        let lam_prev = if pos < m.len() {
            let t = next(&mut pos)?;
            let n = count(next(&mut pos)?)?;
            let l = (0..n)
                .map(|_| next(&mut pos))
                .collect::<Result<Vec<_>, _>>()?;
            Some((t, l))
        } else {
            None
        };
        self.h = h;
        self.order = order;
        self.steps_at_order = sao;
        self.since_start = since;
        self.lam_last = (hist.front().map_or(0.0, |p| p.t), lam.clone());
        self.lam_prev = lam_prev;
        self.hist = hist;
        self.lam = lam;
        self.jac_valid = false;
        self.jac_point = None;
        Ok(())
    }

    fn monitors(&self) -> Vec<f64> {
        let point = match (&self.jac_point, self.jac_valid) {
            (Some(p), true) => Some(p),
            _ => self.pending.as_ref(),
        };
        super::write_monitors(&[&self.rank, &self.rows], &self.lin, point)
    }

    fn restore_monitors(&mut self, m: &[f64]) -> Result<(), String> {
        super::read_monitors(
            m,
            &mut [&mut self.rank, &mut self.rows],
            &mut self.lin,
            self.pending.as_mut(),
        )
    }
}

/// BDF's step, rejection and order and step selection for the step loop
/// ([`implicit::advance`]); the estimate is the order `k` the step was tried at and the errors
/// at orders `k - 1`, `k`, `k + 1`.
impl ImplicitMethod for Bdf {
    type Estimate = (usize, [f64; 3]);

    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Bdf
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

    /// Also the start-up of a fixed-step run: its first points from a tight DOPRI5 run.
    fn begin_call(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        self.resize(sys.n_q(), sys.n_v(), sys.n_c());
        if self.hist.is_empty() {
            return Err(SolverError::other("bdf: advance_to before start"));
        }
        let fixed = self.s.fixed_step > 0.0;
        self.note_start_vdot(st);
        // a step size that cannot advance (a forged state) is chosen afresh, as at the start
        if !fixed && step_control::collapsed(self.h, st.t) {
            self.h = self.initial_step(sys, st);
        }
        if fixed && self.hist.len() == 1 && self.s.max_order > 1 {
            self.bootstrap(sys, st)?;
        }
        self.resize_events(sys);
        Ok(())
    }

    fn try_step(
        &mut self,
        sys: &mut System,
        _st: &State,
        h: f64,
    ) -> Result<(usize, [f64; 3]), NewtonFailure> {
        let k = self.order.min(self.hist.len());
        Bdf::try_step(self, sys, h).map(|errors| (k, errors))
    }

    fn rejects(&self, est: &(usize, [f64; 3])) -> bool {
        step_control::rejects(est.1[1])
    }

    /// Three rejections in a row drop the order to 1.
    fn rejected(
        &mut self,
        _st: &State,
        h: f64,
        &(k, [_, errk, _]): &(usize, [f64; 3]),
        in_a_row: u32,
    ) -> Result<(), SolverError> {
        self.stats.rejected += 1;
        self.stats.rejected_error += 1;
        self.h =
            step_control::after_rejection(h, step_control::proposal(errk, self.estimate_order(k)));
        if in_a_row >= 3 {
            self.order = 1;
            self.steps_at_order = 0;
        }
        Ok(())
    }

    fn event_in_step(
        &mut self,
        sys: &mut System,
        st: &State,
        h: f64,
        est: &(usize, [f64; 3]),
    ) -> Option<f64> {
        self.events_in_step(sys, st, est.0, h)
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64, est: &(usize, [f64; 3])) {
        Bdf::accept(self, sys, st, h, est.0);
    }

    /// A moved state translates the history; a restart (or forces that jump) skips the step
    /// proposal: the history's polynomial no longer describes the motion.
    fn on_action(
        &mut self,
        sys: &mut System,
        st: &mut State,
        action: StepAction,
        jump: bool,
    ) -> Result<Flow, SolverError> {
        match action {
            StepAction::Continue if !jump => {}
            StepAction::Moved if !jump => self.translate_history(st),
            StepAction::Continue | StepAction::Moved | StepAction::Restart => {
                self.restart(sys, st)?;
                return Ok(Flow::Next);
            }
            StepAction::Stop => return Ok(Flow::Stop),
        }
        Ok(Flow::Propose)
    }

    /// Order and step selection after every accepted step.
    fn propose(&mut self, h: f64, natural: f64, &(k, [lo, errk, hi]): &(usize, [f64; 3])) {
        self.steps_at_order += 1;
        // error per unit step lowers the estimates' order in h by one
        let shift = if self.per_unit_step { 0.0 } else { 1.0 };
        let ratio = |e: f64, ord: usize| step_control::proposal(e, ord as f64 + shift);
        let mut best = (ratio(errk, k), k);
        if self.steps_at_order > k {
            let rl = ratio(lo, k - 1) / 1.3;
            if k > 1 && rl > best.0 {
                best = (rl, k - 1);
            }
            let rh = ratio(hi, k + 1) / 1.4;
            if k < self.s.max_order && rh > best.0 {
                best = (rh, k + 1);
            }
        }
        // startup: raise the order as soon as enough points exist
        if self.since_start < 8 && k < self.s.max_order && self.hist.len() > k && best.1 == k {
            best.1 = k + 1;
        }
        if best.1 != self.order {
            self.order = best.1;
            self.steps_at_order = 0;
        }
        self.h = STEP_POLICY.after_acceptance(h, natural, self.h, best.0);
    }

    /// A Newton failure drops the order to 1.
    fn newton_failed(&mut self) {
        self.order = 1;
        self.steps_at_order = 0;
    }

    fn singular_cause(&mut self, sys: &mut System, st: &State) -> Option<SingularPassage> {
        Bdf::singular_cause(self, sys, st)
    }

    /// The newest history point is at the end of the call.
    fn end_call(&mut self, t_end: f64) {
        if let Some(p) = self.hist.front_mut() {
            p.t = t_end;
        }
    }
}
