//! In-place dense LU with partial pivoting on preallocated storage (no allocation after the first
//! factorization of a given size): the solver for small Newton matrices.

/// A column-major `n x n` matrix factorized in place as `P A = L U`.
#[derive(Debug, Clone, Default)]
pub struct DenseLu {
    n: usize,
    /// Column-major values; after [`DenseLu::factor`] holds `L` (unit, below) and `U`.
    pub a: Vec<f64>,
    /// Row exchanged with row `k` at step `k`.
    piv: Vec<usize>,
    /// The non-zeros of `L` below the diagonal by column (`l_ptr[c]..l_ptr[c + 1]` into
    /// `l_row`, `l_val`), and of `U` above it, gathered after [`DenseLu::factor`]: the solves
    /// skip the zeros a multibody Newton matrix keeps (its blocks fill little), doing the same
    /// operations on the non-zeros in the same order, so their results are those of the dense
    /// loops bit for bit (a skipped `b[r] -= 0 * b[c]` changes nothing).
    l_ptr: Vec<usize>,
    l_row: Vec<usize>,
    l_val: Vec<f64>,
    u_ptr: Vec<usize>,
    u_row: Vec<usize>,
    u_val: Vec<f64>,
    /// Rows of the current pivot column whose multiplier is non-zero (scratch of `factor`).
    nz: Vec<usize>,
}

impl DenseLu {
    /// Zeroes the matrix and sets its size.
    pub fn reset(&mut self, n: usize) {
        self.n = n;
        self.a.clear();
        self.a.resize(n * n, 0.0);
        self.piv.resize(n, 0);
        // capacity for a full factor, so no factorization of this size allocates again
        // (emptied first: `reserve` counts from the length; the factor is gathered again)
        for v in [&mut self.l_row, &mut self.u_row, &mut self.nz] {
            v.clear();
            v.reserve(n * n);
        }
        for v in [&mut self.l_val, &mut self.u_val] {
            v.clear();
            v.reserve(n * n);
        }
        for v in [&mut self.l_ptr, &mut self.u_ptr] {
            v.clear();
            v.reserve(n + 1);
        }
    }

    /// Adds `v` to entry `(r, c)`.
    #[inline]
    pub fn add(&mut self, r: usize, c: usize, v: f64) {
        self.a[c * self.n + r] += v;
    }

    /// Factorizes in place; `Err` names the step whose pivot vanishes or is not finite.
    pub fn factor(&mut self) -> Result<(), String> {
        let n = self.n;
        let a = &mut self.a;
        for k in 0..n {
            let (mut p, mut best) = (k, 0.0);
            for r in k..n {
                let v = a[k * n + r].abs();
                if v > best {
                    best = v;
                    p = r;
                }
            }
            if !(best > 0.0 && best.is_finite()) {
                return Err(format!(
                    "Newton matrix is singular (pivot {k} of {n} vanishes)"
                ));
            }
            self.piv[k] = p;
            if p != k {
                for c in 0..n {
                    a.swap(c * n + k, c * n + p);
                }
            }
            let inv = 1.0 / a[k * n + k];
            self.nz.clear();
            for r in k + 1..n {
                a[k * n + r] *= inv;
                if a[k * n + r] != 0.0 {
                    self.nz.push(r);
                }
            }
            // only the rows with a non-zero multiplier change (a skipped `-= 0 * akc` would
            // change at most the sign of a zero)
            for c in k + 1..n {
                let akc = a[c * n + k];
                if akc != 0.0 {
                    for &r in &self.nz {
                        a[c * n + r] -= a[k * n + r] * akc;
                    }
                }
            }
        }
        self.gather();
        Ok(())
    }

    /// Gathers the non-zeros of `L` and `U` by column for the solves (after every row exchange).
    fn gather(&mut self) {
        let (n, a) = (self.n, &self.a);
        self.l_ptr.clear();
        self.l_row.clear();
        self.l_val.clear();
        self.u_ptr.clear();
        self.u_row.clear();
        self.u_val.clear();
        for c in 0..n {
            self.l_ptr.push(self.l_row.len());
            self.u_ptr.push(self.u_row.len());
            let col = &a[c * n..(c + 1) * n];
            for (r, &x) in col.iter().enumerate() {
                if x == 0.0 || r == c {
                    continue;
                }
                if r > c {
                    self.l_row.push(r);
                    self.l_val.push(x);
                } else {
                    self.u_row.push(r);
                    self.u_val.push(x);
                }
            }
        }
        self.l_ptr.push(self.l_row.len());
        self.u_ptr.push(self.u_row.len());
    }

    /// Magnitude of pivot `k` (the diagonal of `U`) after [`DenseLu::factor`].
    pub fn pivot(&self, k: usize) -> f64 {
        self.a[k * self.n + k].abs()
    }

    /// Solves `A x = b` in place.
    pub fn solve(&self, b: &mut [f64]) {
        let (n, a) = (self.n, &self.a);
        for k in 0..n {
            b.swap(k, self.piv[k]);
        }
        for c in 0..n {
            let bc = b[c];
            if bc != 0.0 {
                let range = self.l_ptr[c]..self.l_ptr[c + 1];
                for (&r, &l) in self.l_row[range.clone()].iter().zip(&self.l_val[range]) {
                    b[r] -= l * bc;
                }
            }
        }
        for c in (0..n).rev() {
            b[c] /= a[c * n + c];
            let bc = b[c];
            let range = self.u_ptr[c]..self.u_ptr[c + 1];
            for (&r, &u) in self.u_row[range.clone()].iter().zip(&self.u_val[range]) {
                b[r] -= u * bc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Textbook Gaussian elimination with partial pivoting on a row-major copy: the independent
    /// solution the non-zero-only factor and solves are checked against.
    fn gauss(m: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
        let n = b.len();
        let mut a: Vec<Vec<f64>> = m.to_vec();
        let mut x = b.to_vec();
        for k in 0..n {
            let p = (k..n)
                .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
                .unwrap();
            a.swap(k, p);
            x.swap(k, p);
            for i in k + 1..n {
                let f = a[i][k] / a[k][k];
                let pivot_row = a[k].clone();
                for (aij, akj) in a[i][k..].iter_mut().zip(&pivot_row[k..]) {
                    *aij -= f * akj;
                }
                x[i] -= f * x[k];
            }
        }
        for k in (0..n).rev() {
            let s: f64 = (k + 1..n).map(|j| a[k][j] * x[j]).sum();
            x[k] = (x[k] - s) / a[k][k];
        }
        x
    }

    #[test]
    fn sparse_kkt_like_systems_match_gaussian_elimination() {
        // a saddle-point matrix of 4 "bodies" (3x3 mass blocks) and 5 coupling rows, with zero
        // diagonal in the constraint block (pivoting needed) and mostly zero off-diagonal blocks;
        // factorized twice with different patterns, so the gathered non-zeros are rebuilt
        let mut seed = 7u64;
        let mut rnd = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut lu = DenseLu::default();
        for variant in 0..3 {
            let (nb, nc) = (4, 5);
            let n = 3 * nb + nc;
            let mut m = vec![vec![0.0; n]; n];
            for b in 0..nb {
                for i in 0..3 {
                    m[3 * b + i][3 * b + i] = 2.0 + b as f64 + rnd().abs();
                }
                m[3 * b][3 * b + 1] = 0.1 * rnd();
                m[3 * b + 1][3 * b] = m[3 * b][3 * b + 1];
            }
            for r in 0..nc {
                // row r couples bodies r % nb and (r + 1 + variant) % nb
                for b in [r % nb, (r + 1 + variant) % nb] {
                    for i in 0..3 {
                        let g = rnd();
                        m[3 * nb + r][3 * b + i] = g;
                        m[3 * b + i][3 * nb + r] = g;
                    }
                }
            }
            let b: Vec<f64> = (0..n).map(|_| rnd()).collect();
            lu.reset(n);
            for (r, row) in m.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    if *v != 0.0 {
                        lu.add(r, c, *v);
                    }
                }
            }
            lu.factor().unwrap();
            let mut x = b.clone();
            lu.solve(&mut x);
            let reference = gauss(&m, &b);
            let scale = reference.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for (a, e) in x.iter().zip(&reference) {
                assert!((a - e).abs() <= 1e-12 * scale, "{a} vs {e}");
            }
            // and the residual of the original matrix
            for (r, row) in m.iter().enumerate() {
                let ax: f64 = row.iter().zip(&x).map(|(a, x)| a * x).sum();
                assert!((ax - b[r]).abs() < 1e-12, "residual {}", ax - b[r]);
            }
        }
    }

    #[test]
    fn solves_a_pivoting_system_exactly() {
        // needs a row exchange at the first step
        let m = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 4.0]];
        let mut lu = DenseLu::default();
        lu.reset(3);
        for (r, row) in m.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                lu.add(r, c, *v);
            }
        }
        lu.factor().unwrap();
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = m
            .iter()
            .map(|row| row.iter().zip(&x).map(|(a, b)| a * b).sum())
            .collect();
        lu.solve(&mut b);
        for (a, e) in b.iter().zip(&x) {
            assert!((a - e).abs() < 1e-14);
        }
        let mut s = DenseLu::default();
        s.reset(2);
        s.add(0, 0, 1.0);
        s.add(1, 0, 2.0);
        assert!(s.factor().unwrap_err().contains("singular"));
    }
}
