//! Explicit embedded Runge-Kutta pairs in joint coordinates ([`crate::tree`]): Dormand-Prince
//! 5(4) ([`IntegratorKind::Dopri5Tree`]), Verner's 6(5) ([`IntegratorKind::Verner65Tree`]) and
//! 8(7) ([`IntegratorKind::Verner87Tree`], for tight tolerances). They integrate the `n` joint coordinates and rates of a kinematic tree
//! instead of the `6 N` speeds and `5 N` multipliers of the maximal form, without projections
//! (the joints hold by construction).
//!
//! Error control as [`super::dopri::Dopri5`]: weighted RMS of the embedded estimate with weights
//! `atol + rtol * scale` (scale 1 rad for angles, `|d|` for displacements, `|rate|` for rates),
//! error per unit step, the same step policy; exact stops at the end of every call. After every
//! accepted step the joint state is mapped to the maximal `(q, v)` of [`State`], so hooks,
//! outputs and energies see the usual state. Accelerations `vdot` and multipliers `lambda` of the
//! state are computed from the maximal form (one solve of `[M G^T; G 0]`) at the end of each
//! [`Integrator::advance_to`] call, not after every internal step.
//!
//! [`Integrator::start`] refuses models that are not such trees, naming why
//! ([`JointTree::detect`]).

use super::dopri::{MIN_ERROR_SHARE, STEP_POLICY};
use super::explicit::{self, ExplicitMethod};
use super::kkt::Kkt;
use super::step_control::StepPolicy;
use super::tree_tableau::{DOPRI5, Tableau, VERNER65, VERNER87};
use super::{Integrator, IntegratorKind, Settings, SolverError, Stats, StepAction, StepHook};
use crate::dae::System;
use crate::math::wrms;
use crate::state::State;
use crate::tree::{JointTree, TreeJointKind, TreeScratch};

/// An embedded Runge-Kutta pair on the joint coordinates of a kinematic tree.
#[derive(Debug, Clone)]
pub struct TreeRk {
    kind: IntegratorKind,
    method: &'static Tableau,
    s: Settings,
    h: f64,
    stats: Stats,
    /// The tree found at the last start (`None` before).
    tree: Option<JointTree>,
    scratch: TreeScratch,
    /// Joint state `[theta, theta']` at the current state, the stage point, stage derivatives.
    y: Vec<f64>,
    ys: Vec<f64>,
    k: Vec<Vec<f64>>,
    /// Dissipated and input power [W] at each stage.
    pw: Vec<(f64, f64)>,
    ey: Vec<f64>,
    w: Vec<f64>,
    /// Stage 0 (the derivative at `y`) is already in `k[0]`, `pw[0]`.
    k1_valid: bool,
    /// Maximal-form solver for `vdot` and `lambda` at the end of each call, and its right-hand side.
    kkt: Kkt,
    rhs: Vec<f64>,
}

impl TreeRk {
    /// Dormand-Prince 5(4) with the given settings.
    pub fn dopri5(s: Settings) -> Self {
        Self::with(IntegratorKind::Dopri5Tree, &DOPRI5, s)
    }

    /// Verner's 6(5) with the given settings.
    pub fn verner65(s: Settings) -> Self {
        Self::with(IntegratorKind::Verner65Tree, &VERNER65, s)
    }

    /// Verner's 8(7) with the given settings.
    pub fn verner87(s: Settings) -> Self {
        Self::with(IntegratorKind::Verner87Tree, &VERNER87, s)
    }

    fn with(kind: IntegratorKind, method: &'static Tableau, s: Settings) -> Self {
        let stages = method.c.len();
        TreeRk {
            kind,
            method,
            s,
            h: 0.0,
            stats: Stats::default(),
            tree: None,
            scratch: TreeScratch::default(),
            y: Vec::new(),
            ys: Vec::new(),
            k: vec![Vec::new(); stages],
            pw: vec![(0.0, 0.0); stages],
            ey: Vec::new(),
            w: Vec::new(),
            k1_valid: false,
            kkt: Kkt::new(),
            rhs: Vec::new(),
        }
    }

    /// Finds the tree (when not yet found for a system of this size) and sizes the buffers.
    fn prepare(&mut self, sys: &System, st: &State) -> Result<(), SolverError> {
        let found = self
            .tree
            .as_ref()
            .is_some_and(|_| self.scratch.q.len() == sys.n_q());
        if !found {
            let tree = JointTree::detect(sys, &st.q)
                .map_err(|e| SolverError::other(format!("{}: {e}", self.method.name)))?;
            self.scratch = TreeScratch::default();
            self.tree = Some(tree);
        }
        let tree = self
            .tree
            .as_ref()
            .ok_or_else(|| SolverError::other(format!("{}: no tree", self.method.name)))?;
        let n2 = 2 * tree.n();
        self.scratch.size_for(tree, sys, &st.q);
        for v in self
            .k
            .iter_mut()
            .chain([&mut self.y, &mut self.ys, &mut self.ey, &mut self.w])
        {
            v.resize(n2, 0.0);
        }
        Ok(())
    }

    /// Starts on the found tree: the joint state read from `st`, the first stage, the initial
    /// step.
    fn begin(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        self.extract(st);
        self.ys.copy_from_slice(&self.y);
        self.stage(sys, st.t, 0)?;
        self.k1_valid = false;
        let n = self.y.len() / 2;
        self.weights();
        let acc = wrms(&self.k[0][n..], &self.w[n..])
            .max(wrms(&self.y[n..], &self.w[..n]))
            .max(1e-12);
        self.h = if self.s.h_init > 0.0 {
            self.s.h_init
        } else {
            (0.01 / acc).clamp(super::MIN_H_MAX.min(self.s.h_max), self.s.h_max)
        };
        Ok(())
    }

    /// Reads the joint state from the maximal state.
    fn extract(&mut self, st: &State) {
        if let Some(tree) = &self.tree {
            let n = tree.n();
            let (th, dth) = self.y.split_at_mut(n);
            crate::tree::extract(tree, &st.q, &st.v, th, dth);
        }
    }

    /// Derivative of the joint state `ys` at time `t` into `k[i]`, powers into `pw[i]`.
    fn stage(&mut self, sys: &mut System, t: f64, i: usize) -> Result<(), SolverError> {
        let Some(tree) = &self.tree else {
            return Err(SolverError::other(format!(
                "{}: not started",
                self.method.name
            )));
        };
        let n = tree.n();
        let (th, dth) = self.ys.split_at(n);
        let (kx, kv) = self.k[i].split_at_mut(n);
        kx.copy_from_slice(dth);
        self.scratch
            .accelerations(tree, sys, t, th, dth, kv)
            .map_err(|e| {
                SolverError::other(format!("{} at t = {t:.9e} s: {e}", self.method.name))
            })?;
        self.pw[i] = sys.powers(t, &self.scratch.q, &self.scratch.v);
        self.stats.rhs_evaluations += 1;
        self.stats.factorizations += 1;
        Ok(())
    }

    /// Error weights at the joint state `y`.
    fn weights(&mut self) {
        let Some(tree) = &self.tree else { return };
        let n = tree.n();
        for j in &tree.joints {
            let (m, scale) = match j.kind {
                TreeJointKind::Revolute(m) => (m, 1.0),
                TreeJointKind::Prismatic(m) => (m, self.y[m].abs()),
                TreeJointKind::Fixed => continue,
            };
            self.w[m] = self.s.atol + self.s.rtol * scale;
            self.w[n + m] = self.s.atol + self.s.rtol * self.y[n + m].abs();
        }
    }

    /// One trial step of size `h` from `(t, y)`: the end point in `ys` (and mapped in the
    /// scratch), the weighted error estimate returned (0 with a fixed step).
    fn try_step(&mut self, sys: &mut System, t: f64, h: f64) -> Result<f64, SolverError> {
        let n2 = self.y.len();
        let m = self.method;
        for i in 0..m.c.len() {
            if i == 0 && self.k1_valid {
                continue;
            }
            for c in 0..n2 {
                let mut s = 0.0;
                for (j, a) in m.a[i][..i].iter().enumerate() {
                    s += a * self.k[j][c];
                }
                self.ys[c] = self.y[c] + h * s;
            }
            self.stage(sys, t + m.c[i] * h, i)?;
            if i == 0 {
                self.k1_valid = true;
            }
        }
        if self.s.fixed_step > 0.0 {
            return Ok(0.0);
        }
        for c in 0..n2 {
            let mut s = 0.0;
            for (i, e) in m.e.iter().enumerate() {
                s += e * self.k[i][c];
            }
            self.ey[c] = h * s;
        }
        self.weights();
        let n = n2 / 2;
        let e = (wrms(&self.ey[..n], &self.w[..n]).powi(2)
            + wrms(&self.ey[n..], &self.w[n..]).powi(2))
            * 0.5;
        Ok(e.sqrt())
    }

    /// Takes the trial step: the joint state, the maximal state, the energy accumulators, and
    /// the derivative at the new point as the next first stage (the last stage when it is at the
    /// new point, else evaluated here; it maps the new point to `q`, `v`).
    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64) -> Result<(), SolverError> {
        let m = self.method;
        let (pd, pi) = (0..m.b.len()).fold((0.0, 0.0), |acc, i| {
            (acc.0 + m.b[i] * self.pw[i].0, acc.1 + m.b[i] * self.pw[i].1)
        });
        st.energy_dissipated += h * pd;
        st.work_input += h * pi;
        st.t += h;
        let last = m.c.len() - 1;
        if m.fsal {
            std::mem::swap(&mut self.y, &mut self.ys);
            self.k.swap(0, last);
            self.pw[0] = self.pw[last];
        } else {
            for c in 0..self.y.len() {
                let mut s = 0.0;
                for (i, b) in m.b.iter().enumerate() {
                    s += b * self.k[i][c];
                }
                self.y[c] += h * s;
            }
            self.ys.copy_from_slice(&self.y);
            self.stage(sys, st.t, 0)?;
        }
        self.k1_valid = true;
        st.q.copy_from_slice(&self.scratch.q);
        st.v.copy_from_slice(&self.scratch.v);
        self.stats.steps += 1;
        self.stats.last_step = h;
        Ok(())
    }

    /// Accelerations and multipliers of the maximal form at `st` (outputs of the state).
    fn finish(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        self.rhs.resize(nv + nc, 0.0);
        sys.forces(st.t, &st.q, &st.v, &mut self.rhs[..nv]);
        sys.eval_constraints(st.t, &st.q, &st.v);
        for (r, row) in sys.rows.iter().enumerate() {
            self.rhs[nv + r] = row.gamma;
        }
        self.kkt
            .factor(sys, st.t, &st.q, &st.v, 0.0)
            .and_then(|()| self.kkt.solve(&mut self.rhs))
            .map_err(|e| {
                SolverError::other(format!(
                    "{}: accelerations of the state: {e}",
                    self.method.name
                ))
            })?;
        st.vdot.copy_from_slice(&self.rhs[..nv]);
        st.lambda.resize(nc, 0.0);
        st.lambda.copy_from_slice(&self.rhs[nv..]);
        Ok(())
    }
}

impl Integrator for TreeRk {
    fn kind(&self) -> IntegratorKind {
        self.kind
    }

    fn start(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        self.tree = None;
        self.prepare(sys, st)?;
        self.begin(sys, st)
    }

    /// [`TreeRk`]'s `finish` solves them at the end of every call.
    fn index1_multipliers(&self) -> bool {
        true
    }

    /// The joint coordinates read from the initial state, mapped back to maximal coordinates,
    /// are consistent by construction. When they reproduce the state (positions within
    /// `position_tol`, speeds within `position_tol` per unit speed), the mapped state is taken
    /// and only the accelerations and multipliers are solved (one factorization instead of the
    /// maximal projections' two or more); otherwise the state is projected in maximal
    /// coordinates as by the other integrators. The tree is found once.
    fn initialize(
        &mut self,
        sys: &mut System,
        st: &mut State,
        position_tol: f64,
    ) -> Result<(), SolverError> {
        self.tree = None;
        self.prepare(sys, st)?;
        self.extract(st);
        if let Some(tree) = &self.tree {
            let (th, dth) = self.y.split_at(tree.n());
            self.scratch.map(tree, th, dth);
        }
        if reproduces(st, &self.scratch.q, &self.scratch.v, position_tol) {
            st.q.copy_from_slice(&self.scratch.q);
            st.v.copy_from_slice(&self.scratch.v);
            self.finish(sys, st)?;
        } else {
            super::init::make_consistent(sys, st, position_tol)?;
        }
        self.begin(sys, st)
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
        // the system may have been replaced (`Simulation::replace_system`): find its tree again
        self.tree = None;
        self.prepare(sys, st)?;
        self.extract(st);
        self.finish(sys, st)
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
        let name = self.method.name;
        let h = *m.first().ok_or_else(|| format!("{name} memory is empty"))?;
        if !(h.is_finite() && h >= 0.0) {
            return Err(format!("{name} memory is corrupt: step size {h:e} s"));
        }
        self.k1_valid = false;
        self.h = h;
        Ok(())
    }
}

/// The stages, error estimate and acceptance of [`TreeRk`] for the step loop
/// ([`explicit::advance`]); the accelerations and multipliers of the maximal form are solved
/// at every return.
impl ExplicitMethod for TreeRk {
    fn kind(&self) -> IntegratorKind {
        self.kind
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
        self.method.order
    }

    fn policy(&self) -> StepPolicy {
        STEP_POLICY
    }

    fn min_error_share(&self) -> f64 {
        MIN_ERROR_SHARE
    }

    /// The joint state is read from the state at every call (a restored or changed state), and
    /// inputs may have changed: the first stage is evaluated afresh.
    fn begin_call(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        self.prepare(sys, st)?;
        self.extract(st);
        self.k1_valid = false;
        Ok(())
    }

    fn start(&mut self, sys: &mut System, st: &State) -> Result<(), SolverError> {
        Integrator::start(self, sys, st)
    }

    fn try_step(&mut self, sys: &mut System, st: &State, h: f64) -> f64 {
        TreeRk::try_step(self, sys, st.t, h).unwrap_or(f64::INFINITY)
    }

    fn accept(&mut self, sys: &mut System, st: &mut State, h: f64) -> Result<(), SolverError> {
        TreeRk::accept(self, sys, st, h)
    }

    fn finish(&mut self, sys: &mut System, st: &mut State) -> Result<(), SolverError> {
        TreeRk::finish(self, sys, st)
    }

    fn on_action(
        &mut self,
        _sys: &mut System,
        st: &mut State,
        _action: StepAction,
    ) -> Result<(), SolverError> {
        self.extract(st);
        self.k1_valid = false;
        Ok(())
    }
}

/// Whether the maximal `(q, v)` mapped from the joint coordinates reproduces the state: centres
/// of mass within `tol` [m] (at least 64 eps of the largest coordinate), rotations within `tol`
/// [rad] (quaternions compared up to sign), speeds within `tol` per unit of the largest speed.
fn reproduces(st: &State, q: &[f64], v: &[f64], tol: f64) -> bool {
    if q.len() != st.q.len() || v.len() != st.v.len() {
        return false;
    }
    let scale = st.q.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let tol_q = tol.max(64.0 * f64::EPSILON * scale);
    // every tree body is rigid: 7 coordinates (position, unit quaternion) and 6 speeds
    let positions = st.q.chunks(7).zip(q.chunks(7)).all(|(a, b)| {
        let same_sign = a[3..].iter().zip(&b[3..]).map(|(x, y)| x * y).sum::<f64>() >= 0.0;
        let sign = if same_sign { 1.0 } else { -1.0 };
        a[..3]
            .iter()
            .zip(&b[..3])
            .all(|(x, y)| (x - y).abs() <= tol_q)
            && a[3..]
                .iter()
                .zip(&b[3..])
                .all(|(x, y)| (x - sign * y).abs() <= tol)
    });
    let v_scale = st.v.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    positions
        && st
            .v
            .iter()
            .zip(v)
            .all(|(x, y)| (x - y).abs() <= tol_q * v_scale)
}
