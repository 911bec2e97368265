//! Sparse LU with a few dense rows and columns split off by a Schur complement.
//!
//! faer's LU orders the columns by COLAMD and bounds the fill by the structure of `A^T A`: one
//! dense row of `A` (the speeds of a rigid body that many contact joints hold, or the auxiliary
//! row of a sliding rope's `T_0`) makes that structure full, and factors and solves then grow as
//! `n^2`. The unknowns whose row or column holds many entries (the set `D`, a few) are taken
//! out; with `S` the rest,
//!
//! ```text
//! [A_SS A_SD] [x_S]   [b_S]      X = A_SS^-1 A_SD,  C = A_DD - A_DS X  (|D| x |D|, dense LU)
//! [A_DS A_DD] [x_D] = [b_D],     x_D = C^-1 (b_D - A_DS A_SS^-1 b_S),  x_S = A_SS^-1 b_S - X x_D
//! ```
//!
//! so a factorization costs the sparse LU of `A_SS` and `|D|` solves with it, and a solve one
//! sparse solve and `O(|D| n)` products. When `A_SS` or `C` is singular the caller falls back
//! to the LU of the whole matrix.

use super::dense_lu::DenseLu;
use super::sparse_lu::SparseLu;

/// Rows or columns with more entries than this (and than `4 sqrt(n)`) are dense.
const DENSE_ENTRIES: usize = 48;
/// At most this many dense unknowns are split off (each costs a solve per factorization).
const MAX_SPLIT: usize = 32;
/// Systems below this size are left whole.
const MIN_SIZE: usize = 200;

/// Where an entry of the full pattern goes.
#[derive(Debug, Clone, Copy)]
enum Slot {
    /// Position in `A_SS`'s values.
    Ss(usize),
    /// `(row in S, column in D)`.
    Sd(usize, usize),
    /// `(row in D, column in S)`.
    Ds(usize, usize),
    /// `(row in D, column in D)`.
    Dd(usize, usize),
}

/// The split factorization of one pattern.
#[derive(Clone)]
pub struct SplitLu {
    /// Global indices of the dense unknowns `D` and of the rest `S`, ascending.
    dense: Vec<usize>,
    rest: Vec<usize>,
    slots: Vec<Slot>,
    a_ss: SparseLu,
    ss_vals: Vec<f64>,
    /// `A_SD` then `X = A_SS^-1 A_SD`, column-major `|S| x |D|`.
    x: Vec<f64>,
    /// `A_DS`, row-major `|D| x |S|`.
    a_ds: Vec<f64>,
    schur: DenseLu,
    bs: Vec<f64>,
    bd: Vec<f64>,
}

impl SplitLu {
    /// Analyses the `n x n` compressed-column pattern; `None` when it has no dense rows or
    /// columns worth splitting off (or too many).
    pub fn analyse(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Option<Result<Self, String>> {
        if n < MIN_SIZE {
            return None;
        }
        let limit = DENSE_ENTRIES.max((4.0 * (n as f64).sqrt()) as usize);
        let mut row_count = vec![0usize; n];
        for &r in row_idx {
            row_count[r] += 1;
        }
        let mut is_dense: Vec<bool> = (0..n)
            .map(|i| row_count[i] > limit || col_ptr[i + 1] - col_ptr[i] > limit)
            .collect();
        if !is_dense.iter().any(|d| *d) {
            return None;
        }
        // an unknown whose row or column is left without entries in S (the constraint rows
        // that hold only a dense body, their multipliers) goes with D, or A_SS is singular
        loop {
            let mut row_s = vec![0usize; n];
            let mut col_s = vec![0usize; n];
            for c in (0..n).filter(|&c| !is_dense[c]) {
                for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                    if !is_dense[r] {
                        row_s[r] += 1;
                        col_s[c] += 1;
                    }
                }
            }
            let mut added = false;
            for i in 0..n {
                if !is_dense[i] && (row_s[i] == 0 || col_s[i] == 0) {
                    is_dense[i] = true;
                    added = true;
                }
            }
            if !added {
                break;
            }
        }
        let dense: Vec<usize> = (0..n).filter(|&i| is_dense[i]).collect();
        if dense.len() > MAX_SPLIT {
            return None;
        }
        Some(Self::build(n, col_ptr, row_idx, dense, &is_dense))
    }

    fn build(
        n: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        dense: Vec<usize>,
        is_dense: &[bool],
    ) -> Result<Self, String> {
        let rest: Vec<usize> = (0..n).filter(|&i| !is_dense[i]).collect();
        let mut local = vec![0usize; n];
        for (k, &i) in dense.iter().enumerate() {
            local[i] = k;
        }
        for (k, &i) in rest.iter().enumerate() {
            local[i] = k;
        }
        let (ns, nd) = (rest.len(), dense.len());
        let mut slots = vec![Slot::Ss(0); row_idx.len()];
        let mut ss_ptr = Vec::with_capacity(ns + 1);
        let mut ss_rows = Vec::new();
        ss_ptr.push(0);
        for c in 0..n {
            for (e, &r) in row_idx
                .iter()
                .enumerate()
                .take(col_ptr[c + 1])
                .skip(col_ptr[c])
            {
                slots[e] = match (is_dense[r], is_dense[c]) {
                    (false, false) => {
                        ss_rows.push(local[r]);
                        Slot::Ss(ss_rows.len() - 1)
                    }
                    (false, true) => Slot::Sd(local[r], local[c]),
                    (true, false) => Slot::Ds(local[r], local[c]),
                    (true, true) => Slot::Dd(local[r], local[c]),
                };
            }
            if !is_dense[c] {
                ss_ptr.push(ss_rows.len());
            }
        }
        let nnz = ss_rows.len();
        let a_ss = SparseLu::analyse(ns, ss_ptr, ss_rows)?;
        Ok(SplitLu {
            dense,
            rest,
            slots,
            a_ss,
            ss_vals: vec![0.0; nnz],
            x: vec![0.0; ns * nd],
            a_ds: vec![0.0; nd * ns],
            schur: DenseLu::default(),
            bs: vec![0.0; ns],
            bd: vec![0.0; nd],
        })
    }

    /// Number of dense unknowns split off.
    pub fn n_dense(&self) -> usize {
        self.dense.len()
    }

    /// Factorizes the values of the full pattern (`vals` in compressed-column order).
    pub fn factor(&mut self, vals: &[f64]) -> Result<(), String> {
        let (ns, nd) = (self.rest.len(), self.dense.len());
        self.x.fill(0.0);
        self.a_ds.fill(0.0);
        self.schur.reset(nd);
        for (slot, &v) in self.slots.iter().zip(vals) {
            match *slot {
                Slot::Ss(p) => self.ss_vals[p] = v,
                Slot::Sd(r, c) => self.x[c * ns + r] += v,
                Slot::Ds(r, c) => self.a_ds[r * ns + c] += v,
                Slot::Dd(r, c) => self.schur.add(r, c, v),
            }
        }
        self.a_ss.factor(&self.ss_vals)?;
        for col in self.x.chunks_exact_mut(ns) {
            self.a_ss.solve(col);
        }
        for i in 0..nd {
            let row = &self.a_ds[i * ns..(i + 1) * ns];
            for j in 0..nd {
                let xj = &self.x[j * ns..(j + 1) * ns];
                let s: f64 = row.iter().zip(xj).map(|(a, b)| a * b).sum();
                self.schur.add(i, j, -s);
            }
        }
        self.schur.factor()
    }

    /// Solves `A x = rhs` in place with the last factorization.
    pub fn solve(&mut self, rhs: &mut [f64]) {
        let (ns, nd) = (self.rest.len(), self.dense.len());
        for (b, &i) in self.bs.iter_mut().zip(&self.rest) {
            *b = rhs[i];
        }
        for (b, &i) in self.bd.iter_mut().zip(&self.dense) {
            *b = rhs[i];
        }
        self.a_ss.solve(&mut self.bs);
        for i in 0..nd {
            let row = &self.a_ds[i * ns..(i + 1) * ns];
            self.bd[i] -= row.iter().zip(&self.bs).map(|(a, b)| a * b).sum::<f64>();
        }
        self.schur.solve(&mut self.bd);
        for j in 0..nd {
            let xj = &self.x[j * ns..(j + 1) * ns];
            let d = self.bd[j];
            for (b, x) in self.bs.iter_mut().zip(xj) {
                *b -= x * d;
            }
        }
        for (b, &i) in self.bs.iter().zip(&self.rest) {
            rhs[i] = *b;
        }
        for (b, &i) in self.bd.iter().zip(&self.dense) {
            rhs[i] = *b;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::dense_lu::DenseLu;
    use super::super::linear::LinearSolver;

    /// An `n x n` system: identity plus `a01` at (0, 1) and (1, 0), tridiagonal couplings of
    /// 0.1, and the last unknown coupled to every other one (a dense row and column).
    fn arrow(n: usize, a01: f64) -> Vec<(usize, usize, f64)> {
        let d = n - 1;
        let mut t = Vec::new();
        for i in 0..d {
            t.push((i, i, 1.0));
            if i + 1 < d && i > 1 {
                t.push((i, i + 1, 0.1));
                t.push((i + 1, i, -0.1));
            }
            t.push((d, i, 0.01 * (i + 1) as f64));
            t.push((i, d, 0.02 + 0.001 * i as f64));
        }
        t.push((0, 1, a01));
        t.push((1, 0, a01));
        t.push((d, d, 1.0));
        t
    }

    /// Solves with the linear solver and with a dense LU; returns the largest difference
    /// relative to the solution and the number of unknowns split off.
    fn compare(n: usize, entries: &[(usize, usize, f64)]) -> (f64, usize) {
        let mut lin = LinearSolver::new();
        lin.begin(n);
        let mut dense = DenseLu::default();
        dense.reset(n);
        for &(r, c, v) in entries {
            lin.push(r, c, v);
            dense.add(r, c, v);
        }
        lin.factor().expect("factorizes");
        dense.factor().expect("the whole matrix is regular");
        let b: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin() + 0.5).collect();
        let (mut x, mut y) = (b.clone(), b);
        lin.solve(&mut x).unwrap();
        dense.solve(&mut y);
        let scale = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let diff = x
            .iter()
            .zip(&y)
            .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
        (diff / scale, lin.split_unknowns())
    }

    #[test]
    fn a_dense_row_and_column_are_split_off_and_solve_as_the_whole() {
        let (diff, split) = compare(250, &arrow(250, 0.5));
        assert_eq!(split, 1);
        assert!(diff < 1e-13, "{diff:.2e}");
    }

    #[test]
    fn a_singular_remainder_falls_back_to_the_whole_matrix() {
        // rows 0 and 1 of the remainder are equal: A_SS is singular, A is not
        let (diff, split) = compare(250, &arrow(250, 1.0));
        assert_eq!(split, 0);
        assert!(diff < 1e-13, "{diff:.2e}");
    }

    #[test]
    fn constraint_rows_of_a_dense_body_go_with_it() {
        // row and column n-3 have their only entries on the dense unknown n-1 (a constraint
        // that holds only a dense body, and its multiplier)
        let n = 250;
        let mut t = arrow(n, 0.5);
        t.retain(|&(r, c, _)| r != n - 3 && c != n - 3);
        t.push((n - 3, n - 1, 1.0));
        t.push((n - 1, n - 3, 1.0));
        let (diff, split) = compare(n, &t);
        assert_eq!(split, 2);
        assert!(diff < 1e-13, "{diff:.2e}");
    }
}
