//! The augmented system `[M G^T; G -c I] [x; y] = [top; bottom]` by the range-space method:
//! with the block-diagonal mass matrix `M` (one block per body: rigid `diag(m I, J)`, particle
//! `m I`, modal `M(a)`) it reduces to
//!
//! `(S + c I) y = G M^-1 top - bottom`, `S = G M^-1 G^T` (`n_c` square, symmetric positive
//! definite when `M` is and the active rows are independent), `x = M^-1 (top - G^T y)`.
//!
//! Each body block is inverted, `S` is formed and Cholesky-factorized on its envelope (see
//! [`RangeSpace`]): `O(n)` in the bodies of a chain or tree with rows in joint order, against
//! `O((n_v + n_c)^3)` for a dense LU of the full matrix. Each solve ends with one step of
//! iterative refinement against the full matrix. Used for outputs (reaction forces) at every
//! communication point and, through [`crate::integrator::kkt::Kkt`], for DOPRI5's stages and
//! the projections. A body block or `S` that is not positive definite (a massless body,
//! dependent rows) is reported as `Err`; the caller falls back to the LU.

use super::System;
use crate::model::BodyKind;

/// Scratch and factor of the range-space solve (no allocation once sized).
///
/// `S` is stored by its envelope: row `i` holds columns `first[i]..=i`, where `first[i]` is the
/// first row sharing a body with row `i` (the Cholesky factor keeps that envelope). Rows in
/// joint order along a chain or tree couple only with their neighbours', so the envelope, the
/// factorization and the solves are `O(n)` in the number of bodies; `Y = M^-1 G^T` is kept per
/// row on the blocks the row touches.
#[derive(Debug, Clone, Default)]
pub struct RangeSpace {
    /// Mass blocks: speed offset, size, start in `chol`.
    blocks: Vec<(usize, usize, usize)>,
    /// Inverses of the blocks (symmetric, row-major), concatenated: a rigid body's is
    /// `diag(I / m, J^-1)`, a particle's `I / m`, a modal body's from its Cholesky factor.
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
    /// `Y = M^-1 G^T` by rows of `G`: row `r`'s column of `Y` on the speeds of its blocks, as
    /// segments `y_at[r]..y_at[r + 1]` of `y_seg`, each `(first speed, length, start in y_val)`;
    /// `g_val` holds row `r` of `G` on the same segments.
    y_at: Vec<usize>,
    y_seg: Vec<(usize, usize, usize)>,
    y_val: Vec<f64>,
    g_val: Vec<f64>,
    /// Rows touching each block, with the start of their segment on it: entries
    /// `block_rows_at[b]..block_rows_at[b + 1]` of `block_rows`.
    block_rows_at: Vec<usize>,
    block_rows: Vec<(usize, usize)>,
    /// Scratch of the bucket fill of `block_rows`.
    next_slot: Vec<usize>,
    /// Kind of each block's inverse (for the products with it).
    block_kind: Vec<BlockKind>,
    /// First row touching each block (`usize::MAX`: none yet).
    first_of_block: Vec<usize>,
    /// Envelope of `S` and of its factor: row `i` holds columns `first[i]..=i` at
    /// `env_at[i]..env_at[i + 1]` of `env`.
    first: Vec<usize>,
    env_at: Vec<usize>,
    env: Vec<f64>,
    /// Diagonal of `S + c I` before the factorization.
    diag: Vec<f64>,
    /// The mass blocks themselves (as `chol`), for the residual of the refinement.
    mass: Vec<f64>,
    /// The compliance `c` of the last factorization.
    compliance: f64,
    /// Scratch: a row of `G` scattered over the speeds, a block's values, `M^-1 f`, and the
    /// refinement's right-hand side and residual.
    work: Vec<f64>,
    tmp: Vec<f64>,
    orig: Vec<f64>,
    residual: Vec<f64>,
    z: Vec<f64>,
    /// The row pattern (`row_at`, `cols`, `touched*`, `first`, `y_*` segments, `block_rows*`,
    /// `env_at`) holds for the current mass-block layout; kept while the rows touch the same
    /// columns.
    pattern_valid: bool,
}

/// How a mass block's inverse is applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum BlockKind {
    /// `diag(I / m, J^-1)` (6 speeds): the translational part scales.
    Rigid,
    /// `I / m` (3 speeds).
    Particle,
    /// A full matrix.
    Dense,
}

/// `y = A x` for the inverse `a` (row-major `n x n`) of a block of kind `kind`.
#[inline]
fn block_mul(kind: BlockKind, a: &[f64], x: &[f64], y: &mut [f64]) {
    match kind {
        BlockKind::Rigid => {
            let inv_m = a[0];
            for i in 0..3 {
                y[i] = inv_m * x[i];
                y[3 + i] = a[(3 + i) * 6 + 3] * x[3]
                    + a[(3 + i) * 6 + 4] * x[4]
                    + a[(3 + i) * 6 + 5] * x[5];
            }
        }
        BlockKind::Particle => {
            let inv_m = a[0];
            for i in 0..3 {
                y[i] = inv_m * x[i];
            }
        }
        BlockKind::Dense => mat_vec(a, x, y),
    }
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

/// `x <- M^-1 x` (full speed vector) with the blocks' inverses; `tmp` is scratch.
fn mass_solve(
    blocks: &[(usize, usize, usize)],
    kinds: &[BlockKind],
    inv: &[f64],
    x: &mut [f64],
    tmp: &mut Vec<f64>,
) {
    for (&(o, n, at), &kind) in blocks.iter().zip(kinds) {
        tmp.clear();
        tmp.extend_from_slice(&x[o..o + n]);
        block_mul(kind, &inv[at..at + n * n], tmp, &mut x[o..o + n]);
    }
}

/// `y = A x` for the row-major square `a`.
#[inline]
fn mat_vec(a: &[f64], x: &[f64], y: &mut [f64]) {
    let n = x.len();
    for (i, yi) in y.iter_mut().enumerate() {
        *yi = dot(&a[i * n..(i + 1) * n], x);
    }
}

impl RangeSpace {
    /// Number of constraint rows of the last factorization.
    pub fn n_rows(&self) -> usize {
        self.first.len()
    }

    /// Entries of the envelope of `S` (its factor's storage): about `n_c` times the rows a row
    /// couples with, a measure of the factorization's cost.
    pub fn envelope_len(&self) -> usize {
        self.env.len()
    }

    /// Pivot of row `r` in the last factorization, as a rank watch reads it: `sqrt(p S_rr)` with
    /// `p` the Cholesky pivot (the part of `S_rr` not spanned by the rows before it), i.e. the
    /// diagonal `S_rr` times the sine of the row's angle to the rows before it (in the `M^-1`
    /// metric). It has the units of `S` and falls linearly with the distance to a singular
    /// configuration, as the LU's pivots of the full matrix do (`p` itself falls with its
    /// square).
    pub fn pivot(&self, r: usize) -> Option<f64> {
        let at = *self.env_at.get(r + 1)?;
        Some(self.env[at - 1].abs() * self.diag.get(r)?.sqrt())
    }

    /// In-place envelope Cholesky of `S + c I`; `false` if a pivot is not positive.
    fn factor_envelope(&mut self, c: f64) -> bool {
        let n = self.first.len();
        for i in 0..n {
            let (fi, ai) = (self.first[i], self.env_at[i]);
            for j in fi..=i {
                let fj = self.first[j];
                let k0 = fi.max(fj);
                let (head, row_i) = self.env.split_at_mut(ai);
                // L_ik for k in k0..j, and L_jk for the same k
                let li = &row_i[k0 - fi..j - fi];
                let s = if j < i {
                    let aj = self.env_at[j];
                    let lj = &head[aj + (k0 - fj)..aj + (j - fj)];
                    let s = row_i[j - fi] - dot(li, lj);
                    s / head[aj + (j - fj)]
                } else {
                    let s = row_i[j - fi] + c - dot(li, li);
                    if !(s > 0.0 && s.is_finite()) {
                        return false;
                    }
                    s.sqrt()
                };
                row_i[j - fi] = s;
            }
        }
        true
    }

    /// Solves `L L^T x = b` in place with the envelope factor.
    fn solve_envelope(&self, b: &mut [f64]) {
        let n = self.first.len();
        for i in 0..n {
            let (fi, ai) = (self.first[i], self.env_at[i]);
            let row = &self.env[ai..ai + (i - fi)];
            let s = b[i] - dot(row, &b[fi..i]);
            b[i] = s / self.env[ai + (i - fi)];
        }
        for i in (0..n).rev() {
            let (fi, ai) = (self.first[i], self.env_at[i]);
            b[i] /= self.env[ai + (i - fi)];
            let xi = b[i];
            for (bk, lk) in b[fi..i].iter_mut().zip(&self.env[ai..ai + (i - fi)]) {
                *bk -= lk * xi;
            }
        }
    }

    /// Solves `[M G^T; G -c I] [x; y] = [top; bottom]` in place (`rhs` of length `n_v + n_c`)
    /// with the last factorization ([`System::factor_range_space`]), with one step of iterative
    /// refinement: forming `S` squares the conditioning of `M` (rods with a small inertia about
    /// their axis: residuals of 7e-11 of the right-hand side), and one correction from the
    /// residual of the full matrix brings them to round-off (1e-15) for a second solve.
    pub fn solve(&mut self, rhs: &mut [f64]) {
        let mut b = std::mem::take(&mut self.orig);
        b.clear();
        b.extend_from_slice(rhs);
        self.solve_once(rhs);
        // r = b - A x
        let nv = self.block_of.len();
        let mut r = std::mem::take(&mut self.residual);
        r.clear();
        r.extend_from_slice(&b);
        let (x, y) = rhs.split_at(nv);
        let (r_top, r_bottom) = r.split_at_mut(nv);
        for &(o, n, at) in &self.blocks {
            for (i, ri) in r_top[o..o + n].iter_mut().enumerate() {
                *ri -= dot(&self.mass[at + i * n..at + (i + 1) * n], &x[o..o + n]);
            }
        }
        for (row, (&yr, rb)) in y.iter().zip(r_bottom.iter_mut()).enumerate() {
            let mut gx = 0.0;
            for k in self.row_at[row]..self.row_at[row + 1] {
                let col = self.cols[k];
                gx += self.vals[k] * x[col];
                r_top[col] -= self.vals[k] * yr;
            }
            *rb -= gx - self.compliance * yr;
        }
        self.solve_once(&mut r);
        for (v, d) in rhs.iter_mut().zip(&r) {
            *v += d;
        }
        self.orig = b;
        self.residual = r;
    }

    /// One solve with the factorization (no refinement).
    fn solve_once(&mut self, rhs: &mut [f64]) {
        let nv = self.block_of.len();
        let nc = self.first.len();
        let (top, bottom) = rhs.split_at_mut(nv);
        // z = M^-1 top; y = S^-1 (G z - bottom); x = z - Y y
        mass_solve(
            &self.blocks,
            &self.block_kind,
            &self.chol,
            top,
            &mut self.tmp,
        );
        for (r, b) in bottom.iter_mut().enumerate().take(nc) {
            let mut gz = 0.0;
            for k in self.row_at[r]..self.row_at[r + 1] {
                gz += self.vals[k] * top[self.cols[k]];
            }
            *b = gz - *b;
        }
        self.solve_envelope(bottom);
        for (r, &y) in bottom.iter().enumerate().take(nc) {
            for &(o, n, at) in &self.y_seg[self.y_at[r]..self.y_at[r + 1]] {
                for (x, yv) in top[o..o + n].iter_mut().zip(&self.y_val[at..at + n]) {
                    *x -= yv * y;
                }
            }
        }
    }
}

impl System {
    /// Size and kind of body `bi`'s mass block.
    fn mass_block_shape(&self, bi: usize) -> Result<(usize, BlockKind), String> {
        Ok(match &self.model.bodies[bi].kind {
            BodyKind::Rigid { .. } => (6, BlockKind::Rigid),
            BodyKind::Particle { .. } => (3, BlockKind::Particle),
            BodyKind::Modal { .. } => {
                let m = self.modal_of[bi]
                    .map(|i| &self.modal[i].mass)
                    .ok_or("modal body without floating-frame terms")?;
                (m.nrows(), BlockKind::Dense)
            }
        })
    }

    /// Writes body `bi`'s mass block and its inverse at `at` of `ws.mass` and `ws.chol` (sized
    /// by the caller). A rigid body's or particle's block equal to the one stored there (the
    /// same body as at the last factorization) is kept: their blocks are constant, only modal
    /// bodies' change with the deformation.
    fn write_mass_block(&self, bi: usize, at: usize, ws: &mut RangeSpace) -> Result<(), String> {
        let not_pd = || format!("mass block of body {bi} is not positive definite");
        let n = match &self.model.bodies[bi].kind {
            BodyKind::Rigid { mass, inertia } => {
                let m = &ws.mass[at..at + 36];
                let same = m[0] == *mass
                    && (0..3).all(|i| (0..3).all(|j| m[(3 + i) * 6 + 3 + j] == inertia[(i, j)]));
                if same && ws.chol[at] == 1.0 / mass {
                    return Ok(());
                }
                let j_inv = nalgebra::Cholesky::new(*inertia)
                    .filter(|_| *mass > 0.0)
                    .ok_or_else(not_pd)?
                    .inverse();
                let (blk, m) = (&mut ws.chol[at..at + 36], &mut ws.mass[at..at + 36]);
                blk.fill(0.0);
                m.fill(0.0);
                for i in 0..3 {
                    blk[i * 6 + i] = 1.0 / mass;
                    m[i * 6 + i] = *mass;
                    for j in 0..3 {
                        blk[(3 + i) * 6 + 3 + j] = j_inv[(i, j)];
                        m[(3 + i) * 6 + 3 + j] = inertia[(i, j)];
                    }
                }
                6
            }
            BodyKind::Particle { mass } => {
                if mass.is_nan() || *mass <= 0.0 {
                    return Err(not_pd());
                }
                if ws.mass[at] == *mass && ws.chol[at] == 1.0 / mass {
                    return Ok(());
                }
                let (blk, m) = (&mut ws.chol[at..at + 9], &mut ws.mass[at..at + 9]);
                blk.fill(0.0);
                m.fill(0.0);
                for i in 0..3 {
                    blk[i * 3 + i] = 1.0 / mass;
                    m[i * 3 + i] = *mass;
                }
                3
            }
            BodyKind::Modal { .. } => {
                let m = self.modal_of[bi]
                    .map(|i| &self.modal[i].mass)
                    .ok_or("modal body without floating-frame terms")?;
                let n = m.nrows();
                ws.mass[at..at + n * n].copy_from_slice(m.as_slice());
                ws.tmp.clear();
                ws.tmp.extend_from_slice(m.as_slice());
                if !cholesky(&mut ws.tmp, n) {
                    return Err(not_pd());
                }
                // the inverse, column by column (symmetric: rows alike)
                ws.chol[at..at + n * n].fill(0.0);
                for k in 0..n {
                    let col = &mut ws.chol[at + k * n..at + (k + 1) * n];
                    col[k] = 1.0;
                    cholesky_solve(&ws.tmp, n, col);
                }
                n
            }
        };
        if ws.chol[at..at + n * n].iter().any(|x| !x.is_finite()) {
            // not kept: the next factorization writes this block again
            ws.chol[at] = f64::NAN;
            return Err(not_pd());
        }
        Ok(())
    }

    /// Inverts the mass blocks at the last kinematics update into `ws`. The layout (one block
    /// per body) is rebuilt only when the bodies' blocks changed size or kind, which also drops
    /// the cached row pattern; rigid and particle blocks equal to the stored ones are kept.
    fn factor_mass_blocks(&self, ws: &mut RangeSpace) -> Result<(), String> {
        let bodies = &self.model.bodies;
        let same_layout = ws.blocks.len() == bodies.len()
            && ws.block_of.len() == self.n_v()
            && bodies.iter().enumerate().all(|(bi, b)| {
                let (o, n, _) = ws.blocks[bi];
                self.mass_block_shape(bi)
                    .is_ok_and(|(nb, kind)| o == b.v_offset && n == nb && ws.block_kind[bi] == kind)
            });
        if !same_layout {
            ws.pattern_valid = false;
            ws.blocks.clear();
            ws.block_kind.clear();
            ws.block_of.clear();
            ws.block_of.resize(self.n_v(), usize::MAX);
            let mut len = 0;
            for (bi, b) in bodies.iter().enumerate() {
                let (n, kind) = self.mass_block_shape(bi)?;
                ws.block_of[b.v_offset..b.v_offset + n].fill(ws.blocks.len());
                ws.blocks.push((b.v_offset, n, len));
                ws.block_kind.push(kind);
                len += n * n;
            }
            // NaN: no block stored yet, so every block is written below
            ws.chol.clear();
            ws.chol.resize(len, f64::NAN);
            ws.mass.clear();
            ws.mass.resize(len, f64::NAN);
        }
        for bi in 0..bodies.len() {
            let at = ws.blocks[bi].2;
            if let Err(e) = self.write_mass_block(bi, at, ws) {
                ws.pattern_valid = false;
                ws.blocks.clear();
                return Err(e);
            }
        }
        Ok(())
    }

    /// Reads the active rows of `G` into `ws.vals` if their columns are those of the cached
    /// pattern (`true`); `false` (and `ws.vals` partly written) otherwise.
    fn read_rows_into_pattern(&self, ws: &mut RangeSpace) -> bool {
        let nc = self.n_c();
        if !ws.pattern_valid || ws.row_at.len() != nc + 1 {
            return false;
        }
        for r in 0..nc {
            let (mut k, end) = (ws.row_at[r], ws.row_at[r + 1]);
            let mut same = true;
            self.for_row(r, |c, g| {
                if k < end && ws.cols[k] == c {
                    ws.vals[k] = g;
                } else {
                    same = false;
                }
                k += 1;
            });
            if !same || k != end {
                return false;
            }
        }
        true
    }

    /// Builds the row pattern of `G` into `ws`: its compressed rows (with the values), the
    /// blocks each row touches, the envelope of `S`, the segments of `Y = M^-1 G^T` and the rows
    /// on each block. Depends only on which columns the rows touch, so it is kept while they do.
    fn build_row_pattern(&self, ws: &mut RangeSpace) {
        let nc = self.n_c();
        ws.row_at.clear();
        ws.cols.clear();
        ws.vals.clear();
        ws.touched_at.clear();
        ws.touched.clear();
        ws.first.clear();
        ws.first_of_block.clear();
        ws.first_of_block.resize(ws.blocks.len(), usize::MAX);
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
            let mut first = r;
            for &b in &ws.touched[t0..] {
                let f = &mut ws.first_of_block[b];
                if *f == usize::MAX {
                    *f = r;
                }
                first = first.min(*f);
            }
            ws.first.push(first);
        }
        // the segments of Y (and of G on the same speeds): one per row and block it touches
        ws.y_at.clear();
        ws.y_seg.clear();
        ws.y_at.push(0);
        let mut len = 0;
        for r in 0..nc {
            for &b in &ws.touched[ws.touched_at[r]..ws.touched_at[r + 1]] {
                let (o, n, _) = ws.blocks[b];
                ws.y_seg.push((o, n, len));
                len += n;
            }
            ws.y_at.push(ws.y_seg.len());
        }
        ws.y_val.clear();
        ws.y_val.resize(len, 0.0);
        ws.g_val.clear();
        ws.g_val.resize(len, 0.0);
        // the rows on each block (in row order), with their segment's start
        ws.block_rows_at.clear();
        ws.block_rows_at.resize(ws.blocks.len() + 1, 0);
        for &b in &ws.touched {
            ws.block_rows_at[b + 1] += 1;
        }
        for b in 0..ws.blocks.len() {
            ws.block_rows_at[b + 1] += ws.block_rows_at[b];
        }
        ws.block_rows.clear();
        ws.block_rows.resize(ws.touched.len(), (0, 0));
        ws.next_slot.clear();
        ws.next_slot
            .extend_from_slice(&ws.block_rows_at[..ws.blocks.len()]);
        for r in 0..nc {
            for (t, &b) in ws.touched[ws.touched_at[r]..ws.touched_at[r + 1]]
                .iter()
                .enumerate()
            {
                let slot = ws.next_slot[b];
                ws.next_slot[b] += 1;
                ws.block_rows[slot] = (r, ws.y_seg[ws.y_at[r] + t].2);
            }
        }
        // the envelope: row i holds columns first[i]..=i
        ws.env_at.clear();
        let mut len = 0;
        for (i, &f) in ws.first.iter().enumerate() {
            ws.env_at.push(len);
            len += i - f + 1;
        }
        ws.env_at.push(len);
        ws.pattern_valid = true;
    }

    /// Factorizes `[M G^T; G -c I]` by the range-space method into `ws`: the mass blocks at
    /// `(q, v)` and the constraint rows evaluated last (`eval_constraints`). `Err` when a mass
    /// block or `S + c I` is not positive definite (a massless body, dependent rows). The row
    /// pattern and the constant mass blocks are kept from the last factorization while they
    /// stay the same (only the values are refreshed).
    pub fn factor_range_space(
        &mut self,
        q: &[f64],
        v: &[f64],
        c: f64,
        ws: &mut RangeSpace,
    ) -> Result<(), String> {
        let nc = self.n_c();
        self.update_kinematics(q, v);
        self.factor_mass_blocks(ws)?;
        if !self.read_rows_into_pattern(ws) {
            self.build_row_pattern(ws);
        }
        // G and Y = M^-1 G^T on each row's blocks (M is block diagonal), on their segments
        ws.work.clear();
        ws.work.resize(self.n_v(), 0.0);
        for r in 0..nc {
            for k in ws.row_at[r]..ws.row_at[r + 1] {
                ws.work[ws.cols[k]] += ws.vals[k];
            }
            let segs = ws.y_at[r]..ws.y_at[r + 1];
            let blocks = ws.touched_at[r]..ws.touched_at[r + 1];
            for (s, t) in segs.zip(blocks) {
                let (o, n, start) = ws.y_seg[s];
                let b = ws.touched[t];
                let at = ws.blocks[b].2;
                ws.g_val[start..start + n].copy_from_slice(&ws.work[o..o + n]);
                block_mul(
                    ws.block_kind[b],
                    &ws.chol[at..at + n * n],
                    &ws.work[o..o + n],
                    &mut ws.y_val[start..start + n],
                );
                ws.work[o..o + n].fill(0.0);
            }
        }
        // S = G Y on the envelope, block by block: rows i >= j sharing block b add G_i,b . Y_j,b
        let len = *ws.env_at.last().unwrap_or(&0);
        ws.env.clear();
        ws.env.resize(len, 0.0);
        for b in 0..ws.blocks.len() {
            let n = ws.blocks[b].1;
            let rows = &ws.block_rows[ws.block_rows_at[b]..ws.block_rows_at[b + 1]];
            for (a, &(i, gi)) in rows.iter().enumerate() {
                let g = &ws.g_val[gi..gi + n];
                let base = ws.env_at[i] - ws.first[i];
                for &(j, yj) in &rows[..=a] {
                    let y = &ws.y_val[yj..yj + n];
                    ws.env[base + j] += g.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
                }
            }
        }
        ws.compliance = c;
        ws.diag.clear();
        for i in 0..nc {
            ws.diag.push(ws.env[ws.env_at[i + 1] - 1] + c);
        }
        if !ws.factor_envelope(c) {
            return Err("G M^-1 G^T is not positive definite".into());
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
        let nv = self.n_v();
        self.forces(t, q, v, vdot);
        self.eval_constraints(t, q, v);
        self.factor_range_space(q, v, 0.0, ws)?;
        let mut rhs = std::mem::take(&mut ws.z);
        rhs.clear();
        rhs.extend_from_slice(vdot);
        rhs.extend(self.rows.iter().map(|r| r.gamma));
        ws.solve(&mut rhs);
        vdot.copy_from_slice(&rhs[..nv]);
        lambda.copy_from_slice(&rhs[nv..]);
        ws.z = rhs;
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
            let (nv, nc) = (sim.system.n_v(), sim.system.n_c());
            // the reference: the LU of the full matrix
            let sys = &mut sim.system;
            let mut rhs = vec![0.0; nv + nc];
            sys.forces(st.t, &st.q, &st.v, &mut rhs[..nv]);
            sys.eval_constraints(st.t, &st.q, &st.v);
            for (r, row) in sys.rows.iter().enumerate() {
                rhs[nv + r] = row.gamma;
            }
            let mut lu = LinearSolver::new();
            lu.begin(nv + nc);
            sys.add_dynamics_matrix(st.t, &st.q, &st.v, 1.0, 0.0, 0.0, &mut lu, 0);
            sys.add_constraint_blocks(&mut lu, nv, 0, 1.0, Some((0, nv, 1.0)));
            lu.factor().unwrap();
            lu.solve(&mut rhs).unwrap();
            st.vdot.copy_from_slice(&rhs[..nv]);
            st.lambda = rhs[nv..].to_vec();
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
