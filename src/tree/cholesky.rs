//! Dense Cholesky factorization of a small symmetric positive definite matrix, in place.

/// Factorizes the `n x n` matrix `a` (row-major, lower triangle read) into `L L^T`, `L` stored in
/// the lower triangle. `Err` names the pivot that is not positive (the matrix is not positive
/// definite: a massless chain of bodies or non-finite values).
pub fn factor(a: &mut [f64], n: usize) -> Result<(), String> {
    for j in 0..n {
        let (done, rest) = a.split_at_mut(j * n);
        let row_j = &mut rest[..n];
        // row j: L_jk for k < j, then the pivot
        for k in 0..j {
            let row_k = &done[k * n..k * n + k + 1];
            let s: f64 = row_j[..k].iter().zip(&row_k[..k]).map(|(x, y)| x * y).sum();
            row_j[k] = (row_j[k] - s) / row_k[k];
        }
        let d = row_j[j] - row_j[..j].iter().map(|x| x * x).sum::<f64>();
        if !(d > 0.0 && d.is_finite()) {
            return Err(format!(
                "the joint-space mass matrix is not positive definite (pivot {j}: {d:e})"
            ));
        }
        row_j[j] = d.sqrt();
    }
    Ok(())
}

/// Solves `L L^T x = b` in place (`b` becomes `x`) with the factor of [`factor`].
pub fn solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn solves_a_small_system() {
        let mut a = vec![4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        let orig = a.clone();
        super::factor(&mut a, 3).unwrap();
        let mut b = vec![1.0, -2.0, 0.5];
        let rhs = b.clone();
        super::solve(&a, 3, &mut b);
        for i in 0..3 {
            let r: f64 = (0..3).map(|k| orig[i * 3 + k] * b[k]).sum();
            assert!((r - rhs[i]).abs() < 1e-14);
        }
        let mut bad = vec![1.0, 2.0, 2.0, 1.0];
        assert!(super::factor(&mut bad, 2).is_err());
    }
}
