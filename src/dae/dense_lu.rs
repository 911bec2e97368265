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
}

impl DenseLu {
    /// Zeroes the matrix and sets its size.
    pub fn reset(&mut self, n: usize) {
        self.n = n;
        self.a.clear();
        self.a.resize(n * n, 0.0);
        self.piv.resize(n, 0);
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
            for r in k + 1..n {
                a[k * n + r] *= inv;
            }
            for c in k + 1..n {
                let akc = a[c * n + k];
                if akc != 0.0 {
                    for r in k + 1..n {
                        a[c * n + r] -= a[k * n + r] * akc;
                    }
                }
            }
        }
        Ok(())
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
                for r in c + 1..n {
                    b[r] -= a[c * n + r] * bc;
                }
            }
        }
        for c in (0..n).rev() {
            b[c] /= a[c * n + c];
            let bc = b[c];
            for r in 0..c {
                b[r] -= a[c * n + r] * bc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
