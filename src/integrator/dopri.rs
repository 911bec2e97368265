//! Explicit Dormand-Prince 5(4) on the index-1 form, with projection onto the constraints.
//!
//! Each stage solves `[M G^T; G 0] [v_dot; lambda] = [f; gamma]`; positions are integrated in the
//! chart `q = q_n ⊕ x` with `x_dot = dexp_inv(x) v`. After every accepted step positions and
//! speeds are projected back onto `Phi = 0` and `G v + Phi_t = 0` (minimum mass-weighted change),
//! so the drift of the index-1 form never accumulates. For non-stiff scenes: its stability region
//! bounds the step by the stiffest mode (contact, rope segments).

use super::events::EventLocator;
use super::explicit::{self, ExplicitMethod};
use super::init::{
    ProjectionScratch, accelerations, project_positions_reusing, project_velocities_reusing,
};
use super::kkt::Kkt;
use super::rank::{Passage, RankMonitor};
use super::step_control::StepPolicy;
use super::{
    Cause, Collapse, Integrator, IntegratorKind, Settings, SolverError, Stats, StepAction,
    StepHook, error, time_eps, weights,
};
use crate::dae::System;
use crate::math::wrms;
use crate::state::State;

pub(super) const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
pub(super) const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
pub(super) const B: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];
pub(super) const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Smallest share of the local error tolerance a step may be held to per unit step
/// ([`Settings::error_share`]): the estimate of a shorter step, e.g. one cut to land on a contact
/// event, is round-off at about `eps / rtol` of the weights (2e-6 at rtol 1e-10). Per step,
/// every step may leave one tolerance and the four-bar, which amplifies a speed error 160-fold,
/// ended 31-730 x rtol off; per unit step the errors of many steps add up to about the
/// tolerance per second of motion.
pub(super) const MIN_ERROR_SHARE: f64 = 1e-4;

/// An explicit step costs the same at any size: grow up to 5x at every chance.
pub(super) const STEP_POLICY: StepPolicy = StepPolicy {
    max_growth: 5.0,
    hysteresis: 1.0,
};

/// Coefficients of the 4th-order continuous extension (dense output) of Dormand-Prince 5(4)
/// (Shampine 1986, as in Hairer, Norsett and Wanner, Solving ODEs I, sec. II.6): with
/// `r2 = y1 - y0`, `r3 = h k1 - r2`, `r4 = r2 - h k7 - r3`, `r5 = h sum d_i k_i`,
/// `y(t0 + theta h) = y0 + theta (r2 + (1 - theta) (r3 + theta (r4 + (1 - theta) r5)))`.
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Value at `theta` of the dense output of one component: `y0`, `y1` the step's ends, `hk1`,
/// `hk7` the step times the first and last stage derivatives, `r5 = h sum d_i k_i`.
fn dense(theta: f64, y0: f64, y1: f64, hk1: f64, hk7: f64, r5: f64) -> f64 {
    let r2 = y1 - y0;
    let r3 = hk1 - r2;
    let r4 = r2 - hk7 - r3;
    y0 + theta * (r2 + (1.0 - theta) * (r3 + theta * (r4 + (1.0 - theta) * r5)))
}

/// Dormand-Prince 5(4) integrator.
#[derive(Debug, Clone)]
pub struct Dopri5 {
    s: Settings,
    h: f64,
    /// The augmented matrix of the stages and projections.
    lin: Kkt,
    stats: Stats,
    kx: Vec<Vec<f64>>,
    kv: Vec<Vec<f64>>,
    pw: [(f64, f64); 7],
    x: Vec<f64>,
    vs: Vec<f64>,
    qs: Vec<f64>,
    rhs: Vec<f64>,
    ex: Vec<f64>,
    ev: Vec<f64>,
    wx: Vec<f64>,
    wv: Vec<f64>,
    /// Stage 0 (derivative at the current state) is already in `kx[0]`, `kv[0]`, `pw[0]`.
    k1_valid: bool,
    /// Buffers of the projections.
    projection: ProjectionScratch,
    /// Contact-event location (only for models with contact events, see
    /// [`System::n_contact_events`]).
    events: EventLocator,
    /// Dense output: `h sum d_i k_i` of chart positions and speeds, and the interpolated point.
    rx: Vec<f64>,
    rv: Vec<f64>,
    xd: Vec<f64>,
    vd: Vec<f64>,
    qd: Vec<f64>,
    /// Whether [`Dopri5::try_step`] watches the stages for contact events (see `hidden`).
    watch_stages: bool,
    /// Fraction of the trial step at the first interior stage whose state has a contact event
    /// function `> 0` that is `<= 0` at the step's start (`inf`: none): a contact that closes
    /// and opens again within the step, which its ends do not show.
    hidden: f64,
    /// Watches the constraint pivots for singular configurations.
    rank: RankMonitor,
    /// Speeds where the current passage through a singular configuration began (empty outside).
    v_entry: Vec<f64>,
    /// Energy balance `T + V + dissipated - input` [J] and kinetic energy [J] where the current
    /// passage began.
    energy_entry: (f64, f64),
    /// Stiffness watch: accepted steps in a row held at the stability boundary, and the
    /// non-stiff steps since the last stiff one.
    stiff: StiffnessWatch,
}

/// `h |lambda|` above which a DOPRI5 step sits at its stability boundary (the boundary of its
/// stability region on the negative real axis is near 3.3; Hairer and Wanner's test).
const STIFF_H_LAMBDA: f64 = 3.25;

/// Accepted steps in a row at the stability boundary after which a run is stiff (Hairer and
/// Wanner's code decides after 15; 1,000 here let a stiff RopeBlock run 4-16 s CPU first).
const STIFF_STEPS: u64 = 100;

/// A stiff run stops when the call still needs more than this many steps of the current size:
/// explicit steps on a stiff time scale would take minutes where an implicit integrator takes
/// seconds (RopeBlock with `rope_damping` 1e9: 125,000 steps of 4e-7 s for one 0.05 s
/// communication step, 34 s CPU). A mildly stiff scene (the default lift's rope waves with 10
/// segments: steps of 4e-4 s, 125 per communication step) goes on.
const STIFF_CALL_STEPS: f64 = 1e4;

/// Non-stiff accepted steps that end a stiff stretch.
const NONSTIFF_STEPS: u64 = 6;

/// Counts accepted DOPRI5 steps held by stability rather than accuracy.
#[derive(Debug, Clone, Copy, Default)]
struct StiffnessWatch {
    stiff: u64,
    nonstiff: u64,
    /// Largest `h |lambda|` of the current stiff stretch.
    h_lambda: f64,
}

impl StiffnessWatch {
    /// Notes an accepted step with estimate `h_lambda`; `true` while the stiff stretch is at
    /// least [`STIFF_STEPS`] long.
    fn note(&mut self, h_lambda: f64) -> bool {
        if h_lambda > STIFF_H_LAMBDA {
            self.nonstiff = 0;
            self.stiff += 1;
            self.h_lambda = self.h_lambda.max(h_lambda);
            self.stiff >= STIFF_STEPS
        } else {
            self.nonstiff += 1;
            if self.nonstiff >= NONSTIFF_STEPS {
                self.stiff = 0;
                self.h_lambda = 0.0;
            }
            false
        }
    }
}

/// Cosine (in the kinetic-energy metric) between the speeds entering and leaving a singular
/// configuration below which the run left it on another branch. Continuing on the branch
/// keeps the direction of motion over the short passage (a passage spans a few hundredths of a
/// radian of a crank); switching branch turns it to the other branch's tangent.
const BRANCH_COS: f64 = 0.9;

/// Compliance of the constraint block inside a passage through a singular configuration,
/// relative to the scale of `G M^-1 G^T` (the largest constraint pivot): the accelerations solve
/// `[M G^T; G -c I]`. At the singular configuration `G M^-1 G^T` loses rank, and the exact
/// solve amplifies the constraints' inconsistency (round-off, the projection's tolerance) in the
/// lost direction by the inverse of a vanishing pivot: the error estimate stops falling with the
/// step, the step collapses (parallelogram at rtol 1e-10: below 1e-14 s) or the projection lands
/// on the crossed branch (rtol 1e-8). With the compliance the lost direction's multiplier stays
/// bounded and the steps pass through on the continuing branch; the other directions' solves are
/// perturbed by about `c` relative, and the projections after every step still enforce all
/// constraints exactly. Measured on the parallelogram (crank error at rtol 1e-8 / 1e-10): 1e-4:
/// 1.3e-5 / 4.5e-6; 1e-6: 1.1e-7 / 3.9e-8; 1e-8: 6.7e-10 / 4.1e-10; 1e-10: 3.5e-7 / 3.5e-9;
/// 1e-12: 3.1e-3 (status OK); 1e-14: crank 0.36 rad off at 1e-10 (status OK, which the energy
/// check of a passage now refuses).
const PASSAGE_COMPLIANCE: f64 = 1e-8;

/// Largest change of the energy balance over a passage through a singular configuration, in
/// units of `rtol` times the kinetic energy in play: beyond it the run stops (the projection or
/// the ill-conditioned accelerations have changed the motion; velocity continuity alone does
/// not see a change of speed along the branch).
const PASSAGE_ENERGY_RTOLS: f64 = 100.0;

impl Dopri5 {
    /// A new integrator with the given settings.
    pub fn new(s: Settings) -> Self {
        Dopri5 {
            s,
            h: 0.0,
            lin: Kkt::new(),
            stats: Stats::default(),
            kx: vec![Vec::new(); 7],
            kv: vec![Vec::new(); 7],
            pw: [(0.0, 0.0); 7],
            x: Vec::new(),
            vs: Vec::new(),
            qs: Vec::new(),
            rhs: Vec::new(),
            ex: Vec::new(),
            ev: Vec::new(),
            wx: Vec::new(),
            wv: Vec::new(),
            k1_valid: false,
            projection: ProjectionScratch::default(),
            events: EventLocator::default(),
            rx: Vec::new(),
            rv: Vec::new(),
            xd: Vec::new(),
            vd: Vec::new(),
            qd: Vec::new(),
            watch_stages: false,
            hidden: f64::INFINITY,
            rank: RankMonitor::default(),
            v_entry: Vec::new(),
            energy_entry: (0.0, 0.0),
            stiff: StiffnessWatch::default(),
        }
    }

    fn resize(&mut self, sys: &System) {
        let (nq, nv, nc) = (sys.n_q(), sys.n_v(), sys.n_c());
        for k in self.kx.iter_mut().chain(self.kv.iter_mut()) {
            k.resize(nv, 0.0);
        }
        for v in [
            &mut self.x,
            &mut self.vs,
            &mut self.ex,
            &mut self.ev,
            &mut self.wx,
            &mut self.wv,
        ] {
            v.resize(nv, 0.0);
        }
        self.qs.resize(nq, 0.0);
        self.rhs.resize(nv + nc, 0.0);
        self.events
            .size_for(sys, &mut self.xd, &mut self.vd, &mut self.qd);
        if sys.n_contact_events() > 0 {
            self.rx.resize(nv, 0.0);
            self.rv.resize(nv, 0.0);
        }
    }

    /// After stage `i` (at `qs`, `vs`) of a trial step from `st`: notes in `hidden` the stage's
    /// fraction of the step when an event function is positive there but not at the start.
    fn watch_stage(&mut self, sys: &mut System, st: &State, i: usize) {
        let ev = &mut self.events;
        sys.contact_event_functions(st.t, &self.qs, &self.vs, &mut ev.gt);
        if !ev.gt.iter().any(|g| *g > 0.0) {
            return;
        }
        sys.contact_event_functions(st.t, &st.q, &st.v, &mut ev.g0);
        if ev
            .gt
            .iter()
            .zip(&ev.g0)
            .any(|(g, g0)| *g > 0.0 && *g0 <= 0.0)
        {
            self.hidden = C[i];
        }
    }

    /// The event functions (into `out`) at the fraction `theta` of the trial step of size `h`
    /// from `st`, on the dense output (`rx`, `rv` prepared by [`Dopri5::events_in_step`]).
    fn events_at(&mut self, sys: &mut System, st: &State, h: f64, theta: f64, out: &mut [f64]) {
        for k in 0..self.x.len() {
            let (kx1, kx7, kv1, kv7) = (self.kx[0][k], self.kx[6][k], self.kv[0][k], self.kv[6][k]);
            self.xd[k] = dense(theta, 0.0, self.x[k], h * kx1, h * kx7, self.rx[k]);
            self.vd[k] = dense(theta, st.v[k], self.vs[k], h * kv1, h * kv7, self.rv[k]);
        }
        sys.model.retract(&st.q, &self.xd, &mut self.qd);
        sys.contact_event_functions(st.t + theta * h, &self.qd, &self.vd, out);
    }

    /// After a trial step of size `h` from `st` that passed the error test (its end in `qs`,
    /// `vs`, its stages in `kx`, `kv`): the earliest contact event (closing or opening) inside
    /// the step, as a fraction of the step, located on the dense output to 1e-12 of the step;
    /// `events.landing` then holds the events at that instant. `None`: no contact closes or
    /// opens.
    fn events_in_step(&mut self, sys: &mut System, st: &State, h: f64) -> Option<f64> {
        let mut ev = std::mem::take(&mut self.events);
        sys.contact_event_functions(st.t + h, &self.qs, &self.vs, &mut ev.g1);
        if !ev.end_has_event() {
            ev.landing.clear();
            self.events = ev;
            return None;
        }
        for k in 0..self.x.len() {
            let (mut sx, mut sv) = (0.0, 0.0);
            for (i, d) in D.iter().enumerate() {
                sx += d * self.kx[i][k];
                sv += d * self.kv[i][k];
            }
            self.rx[k] = h * sx;
            self.rv[k] = h * sv;
        }
        let first = ev.locate(sys, st, |sys, m, out| self.events_at(sys, st, h, m, out));
        self.events = ev;
        first
    }

    /// Stage derivative at chart point `x`, speeds `vs`, time `t`: fills `kx[i]`, `kv[i]`, `pw[i]`.
    fn stage(&mut self, sys: &mut System, st: &State, t: f64, i: usize) -> Result<(), String> {
        let nv = sys.n_v();
        sys.model.retract(&st.q, &self.x, &mut self.qs);
        sys.forces(t, &self.qs, &self.vs, &mut self.rhs[..nv]);
        sys.eval_constraints(t, &self.qs, &self.vs);
        for (r, row) in sys.rows.iter().enumerate() {
            self.rhs[nv + r] = row.gamma;
        }
        let c = if self.rank.inside() {
            PASSAGE_COMPLIANCE * self.rank.pivot_scale()
        } else {
            0.0
        };
        self.lin.factor(sys, t, &self.qs, &self.vs, c)?;
        self.lin.solve(&mut self.rhs)?;
        self.stats.rhs_evaluations += 1;
        self.stats.factorizations += 1;
        self.kv[i].copy_from_slice(&self.rhs[..nv]);
        let drive = sys.drive_power(&self.rhs[nv..]);
        let (pd, pi) = sys.powers(t, &self.qs, &self.vs);
        self.pw[i] = (pd, pi + drive);
        let mut kx = std::mem::take(&mut self.kx[i]);
        sys.model.chart_rate(&self.x, &self.vs, &mut kx);
        self.kx[i] = kx;
        Ok(())
    }

    /// One trial step of size `h`; returns the weighted error (0 in fixed-step mode).
    /// The step's local error estimate relative to the tolerance (weighted RMS of positions and
    /// speeds); per unit step the caller divides it by the step's share of the tolerance.
    fn try_step(&mut self, sys: &mut System, st: &State, h: f64) -> Result<f64, String> {
        let nv = sys.n_v();
        self.hidden = f64::INFINITY;
        for i in 0..7 {
            if i == 0 && self.k1_valid {
                continue;
            }
            for k in 0..nv {
                let (mut sx, mut sv) = (0.0, 0.0);
                for (j, a) in A[i][..i].iter().enumerate() {
                    sx += a * self.kx[j][k];
                    sv += a * self.kv[j][k];
                }
                self.x[k] = h * sx;
                self.vs[k] = st.v[k] + h * sv;
            }
            self.stage(sys, st, st.t + C[i] * h, i)?;
            if self.watch_stages && (1..5).contains(&i) && self.hidden.is_infinite() {
                self.watch_stage(sys, st, i);
            }
        }
        // stage 7 is at the 5th-order solution: x, vs now hold it
        if self.s.fixed_step > 0.0 {
            return Ok(0.0);
        }
        for k in 0..nv {
            let (mut sx, mut sv) = (0.0, 0.0);
            for (i, e) in E.iter().enumerate() {
                sx += e * self.kx[i][k];
                sv += e * self.kv[i][k];
            }
            self.ex[k] = h * sx;
            self.ev[k] = h * sv;
        }
        weights(sys, &st.q, &st.v, &self.s, &mut self.wx, &mut self.wv);
        let e = (wrms(&self.ex, &self.wx).powi(2) + wrms(&self.ev, &self.wv).powi(2)) * 0.5;
        Ok(e.sqrt())
    }

    /// Estimate of `h |lambda|` of the step just tried (Hairer and Wanner's test): stages 6 and 7
    /// are both at `t + h`, so the change of the derivative between their states over the change
    /// of the state is the dominant eigenvalue's magnitude the step met.
    fn h_lambda(&self, h: f64) -> f64 {
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..self.kx[0].len() {
            let dkx = self.kx[6][k] - self.kx[5][k];
            let dkv = self.kv[6][k] - self.kv[5][k];
            num += dkx * dkx + dkv * dkv;
            let (mut dx, mut dv) = (0.0, 0.0);
            for (j, (a6, a5)) in A[6].iter().zip(&A[5]).enumerate() {
                let a = a6 - a5;
                dx += a * self.kx[j][k];
                dv += a * self.kv[j][k];
            }
            den += h * h * (dx * dx + dv * dv);
        }
        if den > 0.0 {
            h * (num / den).sqrt()
        } else {
            0.0
        }
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64) -> Result<(), SolverError> {
        let (pd, pi): (f64, f64) = (0..7).fold((0.0, 0.0), |acc, i| {
            (acc.0 + B[i] * self.pw[i].0, acc.1 + B[i] * self.pw[i].1)
        });
        st.energy_dissipated += h * pd;
        st.work_input += h * pi;
        st.t += h;
        st.q.copy_from_slice(&self.qs);
        st.v.copy_from_slice(&self.vs);
        // the last stage formed [M G^T; G 0] at exactly this point: the projections reuse it
        let tol = 1e-3 * self.s.atol;
        project_positions_reusing(sys, &mut self.lin, st, tol, true, &mut self.projection)?;
        project_velocities_reusing(sys, &mut self.lin, st, true, &mut self.projection)?;
        // the derivative at the projected state: output accelerations and the next first stage
        self.x.fill(0.0);
        self.vs.copy_from_slice(&st.v);
        self.stage(sys, st, st.t, 0).map_err(SolverError::other)?;
        let nv = sys.n_v();
        self.check_branch(sys, st)?;
        st.vdot.copy_from_slice(&self.kv[0]);
        st.lambda.clear();
        st.lambda.extend_from_slice(&self.rhs[nv..]);
        self.k1_valid = true;
        self.stats.steps += 1;
        self.stats.last_step = h;
        Ok(())
    }
}

/// Energy balance `T + V + dissipated - input` [J] at the accepted state `st` (constant for an
/// exact solution) and its kinetic energy [J].
fn energy_balance(sys: &mut System, st: &State) -> (f64, f64) {
    let (kinetic, potential) = sys.energy(st.t, &st.q, &st.v);
    (
        kinetic + potential + st.energy_dissipated - st.work_input,
        kinetic,
    )
}

impl Dopri5 {
    /// Joints and start time [s] of the last passage through a singular configuration (for
    /// messages; `t` when none was seen).
    fn passage(&self, sys: &System, t: f64) -> (String, f64) {
        self.rank
            .last_passage(sys)
            .unwrap_or_else(|| ("in a closed loop".into(), t))
    }

    /// Watches the factorization just made at the accepted state for a singular configuration
    /// and checks velocity continuity across each passage: the projection after every step
    /// lands on the nearest branch, which near the singular configuration may be another one.
    fn check_branch(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        let nv = sys.n_v();
        let lin = &self.lin;
        let observed = self.rank.observe_pivots_or_rows(
            sys,
            &|c| lin.pivot(c),
            (nv, 1),
            st.t,
            &mut self.stats,
        );
        match observed {
            Passage::None => Ok(()),
            Passage::Entered => {
                self.v_entry.clone_from(&st.v);
                self.energy_entry = energy_balance(sys, st);
                Ok(())
            }
            Passage::Left => {
                let v0 = std::mem::take(&mut self.v_entry);
                if v0.len() != nv {
                    return Ok(());
                }
                // kinetic-energy metric at the accepted state (its kinematics are current)
                let dot = |sys: &System, a: &[f64], b: &[f64], tmp: &mut [f64]| {
                    sys.mass_mul(b, tmp);
                    a.iter().zip(tmp.iter()).map(|(x, y)| x * y).sum::<f64>()
                };
                let mut tmp = std::mem::take(&mut self.ex);
                let c = dot(sys, &v0, &st.v, &mut tmp);
                let n0 = dot(sys, &v0, &v0, &mut tmp);
                let n1 = dot(sys, &st.v, &st.v, &mut tmp);
                self.ex = tmp;
                let cos = c / (n0 * n1).sqrt();
                if n0 > 0.0 && n1 > 0.0 && cos < BRANCH_COS {
                    let (joints, t) = self.passage(sys, st.t);
                    return Err(SolverError::at(
                        IntegratorKind::Dopri5,
                        t,
                        Cause::SingularConfiguration {
                            joints,
                            how: error::Passage::Branch {
                                degrees: cos.clamp(-1.0, 1.0).acos().to_degrees(),
                                until: st.t,
                            },
                        },
                    ));
                }
                let (e0, t0) = self.energy_entry;
                let (e1, t1) = energy_balance(sys, st);
                let allowed = PASSAGE_ENERGY_RTOLS * self.s.rtol * t0.max(t1);
                if (e1 - e0).abs() > allowed {
                    let (joints, t) = self.passage(sys, st.t);
                    return Err(SolverError::at(
                        IntegratorKind::Dopri5,
                        t,
                        Cause::SingularConfiguration {
                            joints,
                            how: error::Passage::Energy {
                                change: e1 - e0,
                                allowed,
                                until: st.t,
                            },
                        },
                    ));
                }
                Ok(())
            }
        }
    }
}

impl Integrator for Dopri5 {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Dopri5
    }

    fn start(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        self.resize(sys);
        self.k1_valid = false;
        weights(sys, &st.q, &st.v, &self.s, &mut self.wx, &mut self.wv);
        let acc = wrms(&st.vdot, &self.wv)
            .max(wrms(&st.v, &self.wx))
            .max(1e-12);
        self.h = if self.s.h_init > 0.0 {
            self.s.h_init
        } else {
            (0.01 / acc).clamp(super::MIN_H_MAX.min(self.s.h_max), self.s.h_max)
        };
        Ok(())
    }

    fn advance_to(
        &mut self,
        sys: &mut System,
        st: &mut State,
        t_end: f64,
        hook: &mut dyn StepHook,
    ) -> Result<(), SolverError> {
        explicit::advance(self, sys, st, t_end, hook)
    }

    fn restart(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        self.k1_valid = false;
        accelerations(sys, &mut self.lin, st)
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
        vec![self.h]
    }

    fn restore_memory(&mut self, m: &[f64]) -> Result<(), String> {
        let h = *m.first().ok_or("dopri5 memory is empty")?;
        if !(h.is_finite() && h >= 0.0) {
            return Err(format!("dopri5 memory is corrupt: step size {h:e} s"));
        }
        self.k1_valid = false;
        self.h = h;
        Ok(())
    }

    fn monitors(&self) -> Vec<f64> {
        super::write_monitors(&[&self.rank], self.lin.lu(), None)
    }

    fn restore_monitors(&mut self, m: &[f64]) -> Result<(), String> {
        super::read_monitors(m, &mut [&mut self.rank], self.lin.lu_mut(), None)
    }
}

/// The stages, error estimate and acceptance of [`Dopri5`] for the step loop
/// ([`explicit::advance`]), with its contact events, stiffness watch and singular
/// configurations.
impl ExplicitMethod for Dopri5 {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Dopri5
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

    fn order(&self) -> f64 {
        5.0
    }

    fn policy(&self) -> StepPolicy {
        STEP_POLICY
    }

    fn min_error_share(&self) -> f64 {
        MIN_ERROR_SHARE
    }

    fn begin_call(&mut self, sys: &mut System, _st: &State) -> Result<(), SolverError> {
        self.resize(sys);
        // inputs may have changed at this communication point: recompute the first stage
        self.k1_valid = false;
        Ok(())
    }

    fn start(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        Integrator::start(self, sys, st)
    }

    fn try_step(&mut self, sys: &mut System, st: &State, h: f64) -> f64 {
        Dopri5::try_step(self, sys, st, h).unwrap_or(f64::INFINITY)
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64) -> Result<(), SolverError> {
        Dopri5::accept(self, sys, st, h)
    }

    fn on_action(
        &mut self,
        sys: &mut System,
        st: &mut State,
        action: StepAction,
    ) -> Result<(), SolverError> {
        match action {
            StepAction::Restart => self.restart(sys, st),
            // the first stage (FSAL) was evaluated at the positions before the move
            _ => {
                self.k1_valid = false;
                Ok(())
            }
        }
    }

    fn locates_events(&mut self, sys: &System, adaptive: bool) -> bool {
        self.watch_stages = adaptive && sys.n_contact_events() > 0;
        self.watch_stages
    }

    fn landing(&mut self, cut: &mut Option<f64>) -> Option<f64> {
        self.events.begin_trial(cut)
    }

    fn rejected(&mut self) {
        self.events.landing.clear();
    }

    /// Names what was observed: inside a singular configuration the accelerations are
    /// ill-conditioned and the estimate does not fall with the step.
    fn collapse(&self, sys: &System, st: &State, h: f64) -> SolverError {
        if self.rank.inside() {
            let joints = self
                .rank
                .last_passage(sys)
                .map_or_else(|| "?".to_string(), |(j, _)| j);
            return SolverError::at(
                IntegratorKind::Dopri5,
                st.t,
                Cause::SingularConfiguration {
                    joints,
                    how: error::Passage::StepCollapse { h },
                },
            );
        }
        SolverError::at(
            IntegratorKind::Dopri5,
            st.t,
            Cause::StepCollapse {
                h,
                why: Collapse::ErrorEstimate,
            },
        )
    }

    /// A contact closing or opening inside the step: take the step again, ending at the event,
    /// so no step straddles the kink of the contact force and the approach speed is the one at
    /// the onset.
    fn retry_for_event(
        &mut self,
        sys: &mut System,
        st: &State,
        h: f64,
        cut: &mut Option<f64>,
    ) -> bool {
        if let Some(theta) = self.events_in_step(sys, st, h) {
            if let Some(h_on) = self.events.landing_step(theta, st.t, h) {
                *cut = Some(h_on);
                return true;
            }
        } else if self.hidden < 1.0 && self.hidden * h > time_eps(st.t) {
            // a contact closed within the step and opened again before its end: retry up to
            // that stage, until the closing shows at a step's end (not counted as a rejection:
            // `Stats` has no cause for it)
            self.h = self.hidden * h;
            return true;
        }
        false
    }

    fn check_stiffness(&mut self, st: &State, h: f64, t_end: f64) -> Result<(), SolverError> {
        if self.stiff.note(self.h_lambda(h)) && (t_end - st.t) / h > STIFF_CALL_STEPS {
            return Err(SolverError::at(
                IntegratorKind::Dopri5,
                st.t,
                Cause::Stiffness {
                    steps: self.stiff.stiff,
                    h_lambda: self.stiff.h_lambda,
                    h,
                    more: (t_end - st.t) / h,
                    t_end,
                },
            ));
        }
        Ok(())
    }

    fn before_hook(&mut self, st: &State) {
        self.events.before_hook(st);
    }

    /// The step ended on located events: the contacts close or open here.
    fn after_hook(&mut self, sys: &mut System, st: &mut State) {
        if self.events.record(sys, st) {
            self.k1_valid = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{A, B, C, D, dense};

    #[test]
    fn dense_output_is_fourth_order_and_hits_the_step_ends() {
        // y' = y cos(t) + 1 from y(0) = 1; the exact value from classical RK4 at 2e4 steps
        let f = |t: f64, y: f64| y * t.cos() + 1.0;
        let exact = |t_end: f64| {
            let n = 20_000;
            let h = t_end / n as f64;
            let mut y = 1.0;
            for s in 0..n {
                let t = s as f64 * h;
                let k1 = f(t, y);
                let k2 = f(t + 0.5 * h, y + 0.5 * h * k1);
                let k3 = f(t + 0.5 * h, y + 0.5 * h * k2);
                let k4 = f(t + h, y + h * k3);
                y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            }
            y
        };
        let mut errors = Vec::new();
        for h in [0.2, 0.1, 0.05] {
            let mut k = [0.0; 7];
            for i in 0..7 {
                let y = 1.0 + h * (0..i).map(|j| A[i][j] * k[j]).sum::<f64>();
                k[i] = f(C[i] * h, y);
            }
            let y1 = 1.0 + h * (0..7).map(|i| B[i] * k[i]).sum::<f64>();
            let r5 = h * (0..7).map(|i| D[i] * k[i]).sum::<f64>();
            let at = |theta: f64| dense(theta, 1.0, y1, h * k[0], h * k[6], r5);
            assert_eq!(at(0.0), 1.0);
            assert!((at(1.0) - y1).abs() <= 1e-15);
            errors.push((at(0.5) - exact(0.5 * h)).abs());
        }
        // local error O(h^5): halving the step divides it by about 32 (a wrong coefficient in D
        // leaves O(h^4) or worse: 16 or less)
        for w in errors.windows(2) {
            let ratio = w[0] / w[1];
            assert!(ratio > 24.0 && ratio < 45.0, "errors {errors:?}");
        }
    }
}
