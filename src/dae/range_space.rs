//! Index-1 accelerations and multipliers by the range-space method: with the block-diagonal
//! mass matrix `M` (one block per body: rigid `diag(m I, J)`, particle `m I`, modal `M(a)`),
//! `[M G^T; G 0] [v_dot; lambda] = [f; gamma]` reduces to
//!
//! `S lambda = G M^-1 f - gamma`, `S = G M^-1 G^T` (`n_c` square, symmetric positive definite
//! when `M` is and the active rows are independent), `v_dot = M^-1 (f - G^T lambda)`.
//!
//! Each body block and `S` are Cholesky-factorized; the work is `O(n_c^2)` times the row length
//! plus `O(n_c^3 / 6)`, against `O((n_v + n_c)^3)` for an LU of the full matrix (which
//! [`crate::integrator::init::accelerations`] uses). Used for outputs (reaction forces) at every
//! communication point. A body block or `S` that is not positive definite (a massless body,
//! dependent rows) is reported as `Err`; the caller falls back to the LU.

use super::System;
use crate::model::BodyKind;

/// Scratch of the range-space solve (no allocation once sized).
#[derive(Debug, Clone, Default)]
pub struct RangeSpace {
    /// Mass blocks: speed offset, size, start in `chol`.
    blocks: Vec<(usize, usize, usize)>,
    /// Cholesky factors of the blocks (symmetric, so the storage order does not matter for the
    /// input; the factor is row-major), concatenated.
    chol: Vec<f64>,
    /// Block of every speed column.
    block_of: Vec<usize>,
    /// `G` in compressed rows: row `r` has entries `row_at[r]..row_at[r + 1]` of `cols`, `vals`.
    row_at: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    /// Blocks touched by each row (at most a few), flattened like the rows.
    touched_at: Vec<usize>,
    touched: Vec<usize>,
    /// `M^-1 G^T`, `n_v x n_c` column-major (column `r` is zero outside the blocks of row `r`).
    y: Vec<f64>,
    /// `S` (lower triangle) and its Cholesky factor, `n_c x n_c` row-major.
    s: Vec<f64>,
    z: Vec<f64>,
}

/// Dot product with four accumulators (independent dependency chains).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (x, y) in ra.iter().zip(rb) {
        s += x * y;
    }
    s
}

/// In-place Cholesky `A = L L^T` of the symmetric `n x n` matrix `a`, row-major: the lower
/// triangle `a[i * n + k]` (`k <= i`) is read and overwritten by `L`. `false` if a pivot is not
/// positive. Leading zeros of each row (its envelope, which `L` keeps) are skipped, so the
/// banded `G M^-1 G^T` of a chain of joints costs far less than `n^3 / 6`.
fn cholesky(a: &mut [f64], n: usize) -> bool {
    for i in 0..n {
        let fi = (0..i).find(|&k| a[i * n + k] != 0.0).unwrap_or(i);
        // entries before fi stay zero in L
        for j in fi..=i {
            let (head, row_i) = a.split_at_mut(i * n);
            let s = if j < i {
                let row_j = &head[j * n..j * n + j];
                let k0 = fi.min(j);
                row_i[j] - dot(&row_i[k0..j], &row_j[k0..j])
            } else {
                row_i[j] - dot(&row_i[fi..j], &row_i[fi..j])
            };
            if j < i {
                row_i[j] = s / head[j * n + j];
            } else {
                if !(s > 0.0 && s.is_finite()) {
                    return false;
                }
                row_i[i] = s.sqrt();
            }
        }
    }
    true
}

/// Solves `L L^T x = b` in place with the factor of [`cholesky`].
fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let s = b[i] - dot(&l[i * n..i * n + i], &b[..i]);
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        b[i] /= l[i * n + i];
        let xi = b[i];
        for (bk, lk) in b[..i].iter_mut().zip(&l[i * n..i * n + i]) {
            *bk -= lk * xi;
        }
    }
}

/// `x <- M^-1 x` (full speed vector) with the factored blocks.
fn mass_solve(blocks: &[(usize, usize, usize)], chol: &[f64], x: &mut [f64]) {
    for &(o, n, at) in blocks {
        cholesky_solve(&chol[at..at + n * n], n, &mut x[o..o + n]);
    }
}

impl System {
    /// Factorizes the mass blocks at the last kinematics update into `ws`.
    fn factor_mass_blocks(&self, ws: &mut RangeSpace) -> Result<(), String> {
        ws.blocks.clear();
        ws.chol.clear();
        ws.block_of.clear();
        ws.block_of.resize(self.n_v(), usize::MAX);
        for (bi, b) in self.model.bodies.iter().enumerate() {
            let o = b.v_offset;
            let at = ws.chol.len();
            let n = match &b.kind {
                BodyKind::Rigid { mass, inertia } => {
                    ws.chol.resize(at + 36, 0.0);
                    let blk = &mut ws.chol[at..];
                    for i in 0..3 {
                        blk[i * 6 + i] = *mass;
                        for j in 0..3 {
                            blk[(3 + j) * 6 + 3 + i] = inertia[(i, j)];
                        }
                    }
                    6
                }
                BodyKind::Particle { mass } => {
                    ws.chol.resize(at + 9, 0.0);
                    for i in 0..3 {
                        ws.chol[at + i * 3 + i] = *mass;
                    }
                    3
                }
                BodyKind::Modal { .. } => {
                    let m = self.modal_of[bi]
                        .map(|i| &self.modal[i].mass)
                        .ok_or("modal body without floating-frame terms")?;
                    let n = m.nrows();
                    ws.chol.extend_from_slice(m.as_slice());
                    n
                }
            };
            if !cholesky(&mut ws.chol[at..at + n * n], n) {
                return Err(format!("mass block of body {bi} is not positive definite"));
            }
            ws.block_of[o..o + n].fill(ws.blocks.len());
            ws.blocks.push((o, n, at));
        }
        Ok(())
    }

    /// Accelerations `vdot` and multipliers `lambda` of the index-1 equations at `(q, v, t)` by
    /// the range-space method (module doc); `Err` when a mass block or `G M^-1 G^T` is not
    /// positive definite (the caller then uses the LU of the full matrix).
    pub fn index1_range_space(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        ws: &mut RangeSpace,
        vdot: &mut [f64],
        lambda: &mut [f64],
    ) -> Result<(), String> {
        let (nv, nc) = (self.n_v(), self.n_c());
        self.forces(t, q, v, vdot);
        self.eval_constraints(t, q, v);
        self.factor_mass_blocks(ws)?;
        // G in compressed rows, and the blocks each row touches
        ws.row_at.clear();
        ws.cols.clear();
        ws.vals.clear();
        ws.touched_at.clear();
        ws.touched.clear();
        ws.row_at.push(0);
        ws.touched_at.push(0);
        for r in 0..nc {
            let t0 = ws.touched.len();
            self.for_row(r, |c, g| {
                ws.cols.push(c);
                ws.vals.push(g);
                let b = ws.block_of[c];
                if !ws.touched[t0..].contains(&b) {
                    ws.touched.push(b);
                }
            });
            ws.row_at.push(ws.cols.len());
            ws.touched_at.push(ws.touched.len());
        }
        // Y = M^-1 G^T: column r lives on the blocks of row r (M is block diagonal)
        ws.y.clear();
        ws.y.resize(nv * nc, 0.0);
        for r in 0..nc {
            let col = &mut ws.y[r * nv..(r + 1) * nv];
            for k in ws.row_at[r]..ws.row_at[r + 1] {
                col[ws.cols[k]] += ws.vals[k];
            }
            for &b in &ws.touched[ws.touched_at[r]..ws.touched_at[r + 1]] {
                let (o, n, at) = ws.blocks[b];
                cholesky_solve(&ws.chol[at..at + n * n], n, &mut col[o..o + n]);
            }
        }
        // S = G Y (lower part suffices)
        ws.s.clear();
        ws.s.resize(nc * nc, 0.0);
        for j in 0..nc {
            let yj = &ws.y[j * nv..(j + 1) * nv];
            let tj = &ws.touched[ws.touched_at[j]..ws.touched_at[j + 1]];
            for i in j..nc {
                let ti = &ws.touched[ws.touched_at[i]..ws.touched_at[i + 1]];
                if !ti.iter().any(|b| tj.contains(b)) {
                    continue;
                }
                let mut s = 0.0;
                for k in ws.row_at[i]..ws.row_at[i + 1] {
                    s += ws.vals[k] * yj[ws.cols[k]];
                }
                ws.s[i * nc + j] = s;
            }
        }
        if !cholesky(&mut ws.s, nc) {
            return Err("G M^-1 G^T is not positive definite".into());
        }
        // z = M^-1 f; lambda = S^-1 (G z - gamma); vdot = z - Y lambda
        ws.z.clear();
        ws.z.extend_from_slice(vdot);
        mass_solve(&ws.blocks, &ws.chol, &mut ws.z);
        let z = std::mem::take(&mut ws.z);
        self.g_mul(&z, lambda);
        for (l, row) in lambda.iter_mut().zip(&self.rows) {
            *l -= row.gamma;
        }
        cholesky_solve(&ws.s, nc, lambda);
        vdot.copy_from_slice(&z);
        for (r, &l) in lambda.iter().enumerate() {
            for (a, y) in vdot.iter_mut().zip(&ws.y[r * nv..(r + 1) * nv]) {
                *a -= y * l;
            }
        }
        ws.z = z;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::dae::linear::LinearSolver;
    use crate::scene::panel_lock::{PanelLock, PanelLockParams};

    /// The range-space solution equals the LU solution of the full matrix to round-off, for the
    /// rigid and the flexible PanelLock at a state with deformation and motion.
    #[test]
    fn range_space_matches_the_full_lu() {
        for p in [PanelLockParams::default(), PanelLockParams::flexible(4)] {
            let mut s = PanelLock::new(p).unwrap();
            s.advance_to(0.3).unwrap();
            let sim = &mut s.sim;
            let mut st = sim.state.clone();
            crate::integrator::init::accelerations(
                &mut sim.system,
                &mut LinearSolver::new(),
                &mut st,
            )
            .unwrap();
            let (nv, nc) = (sim.system.n_v(), sim.system.n_c());
            let (mut vdot, mut lam) = (vec![0.0; nv], vec![0.0; nc]);
            let mut ws = super::RangeSpace::default();
            let s0 = &sim.state;
            sim.system
                .index1_range_space(s0.t, &s0.q, &s0.v, &mut ws, &mut vdot, &mut lam)
                .unwrap();
            let scale = |x: &[f64]| x.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
            let dl: Vec<f64> = lam.iter().zip(&st.lambda).map(|(a, b)| a - b).collect();
            let da: Vec<f64> = vdot.iter().zip(&st.vdot).map(|(a, b)| a - b).collect();
            assert!(
                scale(&dl) <= 1e-9 * scale(&st.lambda),
                "lambda {}",
                scale(&dl)
            );
            assert!(scale(&da) <= 1e-9 * scale(&st.vdot), "vdot {}", scale(&da));
        }
    }
}
