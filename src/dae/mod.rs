//! The multibody system as integrators see it: flat vectors, the retraction, residual pieces and
//! the blocks of Newton matrices.
//!
//! Equations (index 3): `M(q) v_dot + G(q)^T lambda = f(q, v, t)`, `Phi(q, t) = 0`, with
//! `q_dot = H(q) v` expressed through the retraction of [`crate::model::Model`]. Integrators ask for
//! `f`, `M a`, `Phi`, `G x`, `G^T y`, `gamma`, and for Newton matrices built from
//! `c_M M + c_D D + c_K K` and `G` blocks at offsets they choose.

pub mod linear;
mod redundancy;

use crate::effect::constraint::{RowEval, joint_rows};
use crate::effect::{EvalCtx, JacobianSink, MemoryChange};
use crate::math::{Mat3, Matrix6, Vec3, skew};
use crate::model::kinematics::{self, BodyKin, kin_of};
use crate::model::{BodyId, BodyKind, Model};
use linear::LinearSolver;
use std::sync::Arc;

/// The assembled system with its evaluation scratch (no allocation per evaluation).
#[derive(Debug, Clone)]
pub struct System {
    pub model: Arc<Model>,
    /// Current model inputs.
    pub inputs: Vec<f64>,
    /// Bodies of each full constraint row.
    row_bodies: Vec<[BodyId; 2]>,
    /// Indices of the independent (active) rows among the full rows.
    active: Vec<usize>,
    kins: Vec<BodyKin>,
    rows_full: Vec<RowEval>,
    /// Active constraint rows of the last [`System::eval_constraints`].
    pub rows: Vec<RowEval>,
    /// Number of force/constraint evaluations (statistics).
    pub n_evals: u64,
    /// Memory of each force effect: `memory_offsets[i]..memory_offsets[i + 1]`.
    memory_offsets: Vec<usize>,
    /// Current effect memory (copied from the state before each evaluation).
    pub memory: Vec<f64>,
}

/// Adds `c_K K + c_D D` blocks into a linear solver at an offset.
struct TripletSink<'a> {
    lin: &'a mut LinearSolver,
    ck: f64,
    cd: f64,
    row_off: usize,
    col_off: usize,
}

impl JacobianSink for TripletSink<'_> {
    fn add(&mut self, row: &BodyKin, col: &BodyKin, k: &Matrix6<f64>, d: &Matrix6<f64>) {
        if !row.is_free() || !col.is_free() {
            return;
        }
        let nr = if row.rotational { 6 } else { 3 };
        let nc = if col.rotational { 6 } else { 3 };
        for c in 0..nc {
            for r in 0..nr {
                let v = self.ck * k[(r, c)] + self.cd * d[(r, c)];
                self.lin
                    .push(self.row_off + row.col + r, self.col_off + col.col + c, v);
            }
        }
    }
}

impl System {
    /// Prepares the system; constraint rows that are redundant at the initial configuration
    /// (e.g. in a 3D four-bar) are found by a rank-revealing QR and left out.
    pub fn new(model: Arc<Model>) -> Result<Self, String> {
        let mut row_bodies = Vec::new();
        for j in &model.joints {
            for _ in 0..j.kind.n_rows() {
                row_bodies.push([j.frame_i.body, j.frame_j.body]);
            }
        }
        let n_full = row_bodies.len();
        let mut memory_offsets = vec![0];
        for e in &model.forces {
            memory_offsets.push(memory_offsets.last().copied().unwrap_or(0) + e.n_memory());
        }
        let n_mem = *memory_offsets.last().unwrap_or(&0);
        let mut sys = System {
            memory_offsets,
            memory: vec![0.0; n_mem],
            inputs: vec![0.0; model.n_inputs()],
            row_bodies,
            active: (0..n_full).collect(),
            kins: Vec::with_capacity(model.bodies.len()),
            rows_full: Vec::with_capacity(n_full),
            rows: Vec::with_capacity(n_full),
            n_evals: 0,
            model,
        };
        let (q0, v0) = (sys.model.q0.clone(), sys.model.v0.clone());
        sys.eval_constraints(0.0, &q0, &v0);
        sys.active = redundancy::independent_rows(&sys.model, &sys.row_bodies, &sys.rows_full)?;
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

    /// Positions in `lambda` (active rows) of the rows of joint `joint` (index in
    /// `model.joints`); rows dropped as redundant are absent.
    pub fn joint_multiplier_rows(&self, joint: usize) -> Vec<usize> {
        let start: usize = self.model.joints[..joint]
            .iter()
            .map(|j| j.kind.n_rows())
            .sum();
        let end = start + self.model.joints[joint].kind.n_rows();
        self.active
            .iter()
            .enumerate()
            .filter(|(_, r)| (start..end).contains(*r))
            .map(|(i, _)| i)
            .collect()
    }

    /// Number of constraint rows dropped as redundant.
    pub fn n_redundant(&self) -> usize {
        self.row_bodies.len() - self.active.len()
    }

    /// Body kinematics of the last evaluation.
    pub fn kins(&self) -> &[BodyKin] {
        &self.kins
    }

    /// Evaluates body kinematics at `(q, v)`.
    pub fn update_kinematics(&mut self, q: &[f64], v: &[f64]) {
        kinematics::evaluate(&self.model, q, v, &mut self.kins);
    }

    /// Evaluation context of force effect `i`.
    fn ctx(&self, t: f64, i: usize) -> EvalCtx<'_> {
        let m = &self.memory[self.memory_offsets[i]..self.memory_offsets[i + 1]];
        EvalCtx {
            t,
            kins: &self.kins,
            inputs: &self.inputs,
            memory: m,
        }
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
            let ctx = self.ctx(t, i);
            change = change.max(e.update_memory(&ctx, &mut memory[a..b]));
        }
        self.memory.copy_from_slice(memory);
        change
    }

    /// `out = M a` (block diagonal mass matrix).
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
            }
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
        for (i, e) in self.model.forces.iter().enumerate() {
            e.add_forces(&self.ctx(t, i), f);
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
            }
        }
        let mut sink = TripletSink {
            lin,
            ck,
            cd,
            row_off,
            col_off,
        };
        for (i, e) in self.model.forces.iter().enumerate() {
            e.add_jacobian(&self.ctx(t, i), &mut sink);
        }
    }

    /// Evaluates the active constraint rows at `(q, v, t)` into [`System::rows`].
    pub fn eval_constraints(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.update_kinematics(q, v);
        self.rows_full.clear();
        for j in &self.model.joints {
            joint_rows(j, &self.kins, t, &self.inputs, &mut self.rows_full);
        }
        self.rows.clear();
        for &r in &self.active {
            self.rows.push(self.rows_full[r]);
        }
    }

    /// Column offsets of the two bodies of active row `r` (`None` for ground).
    fn row_cols(&self, r: usize) -> [(Option<usize>, usize); 2] {
        let [bi, bj] = self.row_bodies[self.active[r]];
        let f = |b: BodyId| {
            let k = kin_of(&self.kins, b);
            (
                k.is_free().then_some(k.col),
                if k.rotational { 6 } else { 3 },
            )
        };
        [f(bi), f(bj)]
    }

    /// `out = G x` for the last evaluated rows.
    pub fn g_mul(&self, x: &[f64], out: &mut [f64]) {
        for (r, row) in self.rows.iter().enumerate() {
            let mut s = 0.0;
            for (side, (col, n)) in self.row_cols(r).into_iter().enumerate() {
                if let Some(c) = col {
                    for k in 0..n {
                        s += row.g[side][k] * x[c + k];
                    }
                }
            }
            out[r] = s;
        }
    }

    /// `out += G^T y` for the last evaluated rows.
    pub fn gt_mul_add(&self, y: &[f64], out: &mut [f64]) {
        for (r, row) in self.rows.iter().enumerate() {
            for (side, (col, n)) in self.row_cols(r).into_iter().enumerate() {
                if let Some(c) = col {
                    for k in 0..n {
                        out[c + k] += row.g[side][k] * y[r];
                    }
                }
            }
        }
    }

    /// Pushes `scale * G` at `(row_off, col_off)` and, if `transpose_at` is given,
    /// `scale_t * G^T` at that `(row, col)` offset.
    pub fn add_constraint_blocks(
        &self,
        lin: &mut LinearSolver,
        row_off: usize,
        col_off: usize,
        scale: f64,
        transpose_at: Option<(usize, usize, f64)>,
    ) {
        for (r, row) in self.rows.iter().enumerate() {
            for (side, (col, n)) in self.row_cols(r).into_iter().enumerate() {
                if let Some(c) = col {
                    for k in 0..n {
                        lin.push(row_off + r, col_off + c + k, scale * row.g[side][k]);
                        if let Some((tr, tc, st)) = transpose_at {
                            lin.push(tr + c + k, tc + r, st * row.g[side][k]);
                        }
                    }
                }
            }
        }
    }

    /// Kinetic and potential energy [J] at `(q, v, t)`.
    pub fn energy(&mut self, t: f64, q: &[f64], v: &[f64]) -> (f64, f64) {
        self.update_kinematics(q, v);
        let mut mv = vec![0.0; v.len()];
        self.mass_mul(v, &mut mv);
        let kinetic = 0.5 * v.iter().zip(&mv).map(|(a, b)| a * b).sum::<f64>();
        let potential = self
            .model
            .forces
            .iter()
            .enumerate()
            .map(|(i, e)| e.potential_energy(&self.ctx(t, i)))
            .sum();
        (kinetic, potential)
    }

    /// Dissipated power and input power [W] at `(q, v, t)`.
    pub fn powers(&mut self, t: f64, q: &[f64], v: &[f64]) -> (f64, f64) {
        self.update_kinematics(q, v);
        let forces = &self.model.forces;
        let diss = forces
            .iter()
            .enumerate()
            .map(|(i, e)| e.dissipated_power(&self.ctx(t, i)))
            .sum();
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
