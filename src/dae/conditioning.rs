//! Conditioning of the active constraint rows in closed loops, measured directly on `G`, for
//! integrators whose factorization does not show the constraint pivots (sparse LU): the pivots
//! of `G_c G_c^T` of each loop component `c` (rows in the redundancy check's order: tree rows
//! first, loop-closing rows last), cheap enough for every step.

use super::System;

impl System {
    /// The active rows in closed loops, grouped by connected component of the bodies they join
    /// (each group in increasing row order).
    pub fn loop_row_groups(&self) -> Vec<Vec<usize>> {
        let n_bodies = self.model.bodies.len();
        let mut parent: Vec<usize> = (0..n_bodies).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let rows: Vec<usize> = (0..self.n_c())
            .filter(|&r| self.active_row_in_loop(r))
            .collect();
        let body_of = |r: usize| {
            let [a, b] = self.row_bodies[self.active[r]];
            (a.index(), b.index())
        };
        for &r in &rows {
            if let (Some(a), Some(b)) = body_of(r) {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra] = rb;
            }
        }
        let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
        for &r in &rows {
            let (a, b) = body_of(r);
            let Some(body) = a.or(b) else { continue };
            let key = root(&mut parent, body);
            match groups.iter_mut().find(|g| g.0 == key) {
                Some(g) => g.1.push(r),
                None => groups.push((key, vec![r])),
            }
        }
        groups.into_iter().map(|g| g.1).collect()
    }

    /// For every active row `r` of `groups`, `out[r]` = the pivot of `r` in the Cholesky
    /// factorization (no pivoting) of its group's `G G^T`, over the row's squared norm: the
    /// squared sine of the angle between the row and the span of the rows before it (1 for a row
    /// orthogonal to them, 0 for a dependent one); rows outside the groups get 0. `out` has
    /// length `n_c`. Returns the largest squared row norm (the scale of `G G^T`).
    pub fn loop_row_pivots(&self, groups: &[Vec<usize>], out: &mut Vec<f64>) -> f64 {
        out.clear();
        out.resize(self.n_c(), 0.0);
        let nv = self.n_v();
        let mut dense = vec![0.0; nv];
        let mut scale = 0.0_f64;
        for group in groups {
            let m = group.len();
            // the rows of the group, densely over the columns they touch
            let mut cols: Vec<usize> = Vec::new();
            for &r in group {
                self.for_row(r, |c, _| cols.push(c));
            }
            cols.sort_unstable();
            cols.dedup();
            let mut g = vec![0.0; m * cols.len()];
            for (i, &r) in group.iter().enumerate() {
                self.for_row(r, |c, v| dense[c] += v);
                for (j, &c) in cols.iter().enumerate() {
                    g[i * cols.len() + j] = dense[c];
                    dense[c] = 0.0;
                }
            }
            let n = cols.len();
            let dot = |i: usize, k: usize| -> f64 {
                g[i * n..(i + 1) * n]
                    .iter()
                    .zip(&g[k * n..(k + 1) * n])
                    .map(|(a, b)| a * b)
                    .sum()
            };
            // Cholesky of G G^T, lower factor in `l`
            let mut l = vec![0.0; m * m];
            for i in 0..m {
                let norm2 = dot(i, i);
                scale = scale.max(norm2);
                for k in 0..=i {
                    let mut s = dot(i, k);
                    for j in 0..k {
                        s -= l[i * m + j] * l[k * m + j];
                    }
                    if k < i {
                        let d = l[k * m + k];
                        l[i * m + k] = if d > 0.0 { s / d } else { 0.0 };
                    } else {
                        let p = s.max(0.0);
                        l[i * m + i] = p.sqrt();
                        out[group[i]] = if norm2 > 0.0 { p / norm2 } else { 0.0 };
                    }
                }
            }
        }
        scale
    }
}
