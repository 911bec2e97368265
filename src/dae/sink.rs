//! The Jacobian sink that writes force-effect blocks into a linear solver.

use super::linear::LinearSolver;
use super::node_body::{EffectBlock, MappedSide, NodeBodyTerms, mapped_block};
use crate::effect::{AuxSupport, JacobianSink};
use crate::math::{Matrix6, Vector6};
use crate::model::kinematics::BodyKin;

/// Adds `c_K K + c_D D` blocks into a linear solver at an offset; blocks of node bodies are
/// mapped to their modal bodies (see `node_body`).
///
/// Auxiliary unknowns (bordered stiffness couplings, [`AuxSupport`]) are taken when the solver
/// allows them, stiffness is assembled (`c_K != 0`) and the model has no node bodies (their
/// speeds map onto modal bodies, which the auxiliary rows do not follow). Their rows are scaled
/// by `c_K` like the stiffness they carry, so the pivots of the bordered system stay of the
/// size of the Newton matrix's own (scaling an auxiliary row does not change the solution).
pub(super) struct TripletSink<'a> {
    pub lin: &'a mut LinearSolver,
    pub ck: f64,
    pub cd: f64,
    pub row_off: usize,
    pub col_off: usize,
    pub n_v: usize,
    pub nodes: &'a [NodeBodyTerms],
}

impl<'a> TripletSink<'a> {
    fn side(n_v: usize, nodes: &'a [NodeBodyTerms], k: &BodyKin) -> (MappedSide<'a>, usize) {
        let nk = if k.rotational { 6 } else { 3 };
        if k.col >= n_v {
            let nb = &nodes[(k.col - n_v) / 6];
            let side = MappedSide {
                col: nb.body_col,
                size: nb.map.ncols(),
                node: Some(nb),
            };
            (side, nk)
        } else {
            let side = MappedSide {
                col: k.col,
                size: nk,
                node: None,
            };
            (side, nk)
        }
    }
}

impl JacobianSink for TripletSink<'_> {
    fn add(&mut self, row: &BodyKin, col: &BodyKin, k: &Matrix6<f64>, d: &Matrix6<f64>) {
        if !row.is_free() || !col.is_free() {
            return;
        }
        if row.col >= self.n_v || col.col >= self.n_v {
            let (rs, nr) = Self::side(self.n_v, self.nodes, row);
            let (cs, nc) = Self::side(self.n_v, self.nodes, col);
            let eb = EffectBlock {
                nr,
                nc,
                k,
                d,
                ck: self.ck,
                cd: self.cd,
            };
            let blk = mapped_block(&rs, &cs, &eb);
            let (ro, co) = (self.row_off + rs.col, self.col_off + cs.col);
            for c in 0..cs.size {
                for r in 0..rs.size {
                    self.lin.push(ro + r, co + c, blk[(r, c)]);
                }
            }
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

    fn aux_support(&self) -> AuxSupport {
        if self.ck == 0.0 {
            AuxSupport::Skip
        } else if self.nodes.is_empty() && self.lin.aux_allowed() {
            AuxSupport::Rows
        } else {
            AuxSupport::None
        }
    }

    fn new_aux(&mut self) -> Option<usize> {
        if self.aux_support() == AuxSupport::Rows {
            self.lin.add_aux()
        } else {
            None
        }
    }

    fn add_stiffness_aux(&mut self, row: &BodyKin, aux: usize, k: &Vector6<f64>) {
        if !row.is_free() {
            return;
        }
        let nr = if row.rotational { 6 } else { 3 };
        for r in 0..nr {
            self.lin
                .push(self.row_off + row.col + r, aux, self.ck * k[r]);
        }
    }

    fn add_aux_position(&mut self, aux: usize, col: &BodyKin, c: &Vector6<f64>) {
        if !col.is_free() {
            return;
        }
        let nc = if col.rotational { 6 } else { 3 };
        for i in 0..nc {
            self.lin
                .push(aux, self.col_off + col.col + i, self.ck * c[i]);
        }
    }

    fn add_aux_aux(&mut self, row: usize, col: usize, value: f64) {
        self.lin.push(row, col, self.ck * value);
    }
}
