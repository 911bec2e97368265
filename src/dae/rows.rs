//! Constraint rows of the [`System`]: evaluation (with node frames of modal bodies) and the
//! products and blocks of `G`, whose rows have a 3- or 6-block per body plus, for a frame on a
//! flexible-body node, the body's modal columns `Phi_k^T gn_t + Psi_k^T gn_r`.

use super::System;
use super::linear::LinearSolver;
use crate::effect::constraint::{NodeKin, joint_rows};
use crate::effect::constraint_stiffness::joint_stiffness;
use crate::model::BodyId;
use crate::model::kinematics::kin_of;

impl System {
    /// Motion of node `node` of body `body` relative to its frame (`None` off nodes).
    fn node_kin(&self, body: BodyId, node: Option<usize>) -> Option<NodeKin> {
        let node = node?;
        let m = &self.modal[self.modal_of[body.index()?]?];
        let phi = m.data.translational_shapes().get(node)?;
        let psi = m.data.rotational_shapes().get(node)?;
        Some(NodeKin {
            u: m.data.positions()[node] + phi * &m.a,
            u_dot: phi * &m.a_dot,
            theta: psi * &m.a,
            theta_dot: psi * &m.a_dot,
        })
    }

    /// Evaluates the active constraint rows at `(q, v, t)` into [`System::rows`].
    pub fn eval_constraints(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.update_kinematics(q, v);
        self.rows_full.clear();
        for j in &self.model.joints {
            let nodes = [
                self.node_kin(j.frame_i.body, j.frame_i.node),
                self.node_kin(j.frame_j.body, j.frame_j.node),
            ];
            joint_rows(j, &self.kins, nodes, t, &self.inputs, &mut self.rows_full);
        }
        // modal columns of node frames: Phi_k^T gn_t + Psi_k^T gn_r
        self.row_modal.clear();
        self.row_modal_at.clear();
        for (r, row) in self.rows_full.iter().enumerate() {
            let mut at = [usize::MAX; 2];
            for (side, at_side) in at.iter_mut().enumerate() {
                let (body, node) = (self.row_bodies[r][side], self.row_nodes[r][side]);
                let Some(node) = node else { continue };
                let Some(mi) = body.index().and_then(|b| self.modal_of[b]) else {
                    continue;
                };
                let data = &self.modal[mi].data;
                let (phi, psi) = (
                    &data.translational_shapes()[node],
                    &data.rotational_shapes()[node],
                );
                let gn = &row.gn[side];
                *at_side = self.row_modal.len();
                for c in 0..phi.ncols() {
                    let mut x = 0.0;
                    for k in 0..3 {
                        x += phi[(k, c)] * gn[k] + psi[(k, c)] * gn[3 + k];
                    }
                    self.row_modal.push(x);
                }
            }
            self.row_modal_at.push(at);
        }
        if self.all_rows_active() {
            // every row active: the evaluated rows become `rows` without a copy (the previous
            // ones are overwritten by the next evaluation)
            std::mem::swap(&mut self.rows, &mut self.rows_full);
        } else {
            self.rows.clear();
            for &r in &self.active {
                self.rows.push(self.rows_full[r]);
            }
        }
    }

    /// Whether every row is active (none left out as redundant).
    pub(super) fn all_rows_active(&self) -> bool {
        self.active.len() == self.row_bodies.len()
    }

    /// Every row of the last [`System::eval_constraints`], active or not (in full-row order).
    pub(super) fn full_rows(&self) -> &[crate::effect::constraint::RowEval] {
        if self.all_rows_active() {
            &self.rows
        } else {
            &self.rows_full
        }
    }

    /// Calls `f(column, value)` for the modal columns of full row `r` (node frames only).
    pub(super) fn for_row_modal(&self, r: usize, mut f: impl FnMut(usize, f64)) {
        for side in 0..2 {
            let at = self.row_modal_at[r][side];
            if at == usize::MAX {
                continue;
            }
            let Some(bi) = self.row_bodies[r][side].index() else {
                continue;
            };
            let body = &self.model.bodies[bi];
            let n = body.kind.n_modes();
            for (c, &g) in self.row_modal[at..at + n].iter().enumerate() {
                f(body.v_offset + 6 + c, g);
            }
        }
    }

    /// Column offsets of the two bodies of active row `r` (`None` for ground) and the length of
    /// their rigid block (6 with rotations, 3 for particles).
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

    /// Calls `f(column, value)` for every structural entry of active row `r`: the 3- or 6-block
    /// of each body, then the modal columns of node frames.
    pub(super) fn for_row(&self, r: usize, mut f: impl FnMut(usize, f64)) {
        let row = &self.rows[r];
        for (side, (col, n)) in self.row_cols(r).into_iter().enumerate() {
            if let Some(c) = col {
                for k in 0..n {
                    f(c + k, row.g[side][k]);
                }
            }
        }
        self.for_row_modal(self.active[r], f);
    }

    /// `out = G x` for the last evaluated rows.
    pub fn g_mul(&self, x: &[f64], out: &mut [f64]) {
        for (r, o) in out.iter_mut().enumerate().take(self.rows.len()) {
            let mut s = 0.0;
            self.for_row(r, |c, g| s += g * x[c]);
            *o = s;
        }
    }

    /// `out += G^T y` for the last evaluated rows.
    pub fn gt_mul_add(&self, y: &[f64], out: &mut [f64]) {
        for (r, &yr) in y.iter().enumerate().take(self.rows.len()) {
            self.for_row(r, |c, g| out[c] += g * yr);
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
        for r in 0..self.rows.len() {
            self.for_row(r, |c, g| {
                lin.push(row_off + r, col_off + c, scale * g);
                if let Some((tr, tc, st)) = transpose_at {
                    lin.push(tr + c, tc + r, st * g);
                }
            });
        }
    }

    /// Adds `scale * sum_r lambda_r d(g_r)/dx`, the joints' geometric stiffness
    /// ([`crate::effect::constraint_stiffness`]), at `(row_off, col_off)` into `lin`, for the
    /// multipliers `lambda` of the active rows at the kinematics of the last update (call after
    /// [`System::add_dynamics_matrix_at`] at the same point). Which entries are pushed depends
    /// on the joints' kinds only, so the matrix's pattern does not change with `lambda`.
    pub fn add_constraint_stiffness(
        &self,
        lambda: &[f64],
        scale: f64,
        lin: &mut LinearSolver,
        row_off: usize,
        col_off: usize,
    ) {
        let mut first = 0;
        for joint in &self.model.joints {
            let n = joint.kind.n_rows();
            // the joint's multipliers by row of its kind; 0 for a row left out as redundant
            let mut rows = [0.0; 6];
            for (k, row) in rows.iter_mut().enumerate().take(n) {
                if let Some(a) = self.active_of_full[first + k] {
                    *row = lambda[a];
                }
            }
            first += n;
            let Some(h) = joint_stiffness(joint, &self.kins, &rows[..n]) else {
                continue;
            };
            let sides = [joint.frame_i.body, joint.frame_j.body].map(|b| {
                let k = kin_of(&self.kins, b);
                (k.col, if k.rotational { 6 } else { 3 }, k.is_free())
            });
            h.for_each_entry(|a, b, r, c, value| {
                let ((ca, na, free_a), (cb, nb, free_b)) = (sides[a], sides[b]);
                if free_a && free_b && r < na && c < nb {
                    lin.push(row_off + ca + r, col_off + cb + c, scale * value);
                }
            });
        }
    }
}
