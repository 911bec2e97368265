//! Dense generalized symmetric eigen-solver `K phi = omega^2 M phi` with clamped DOFs.
//!
//! Method (faer, sequential), on the free DOFs:
//! 1. Diagonal scaling `D = diag(1 / sqrt(M_ii))`, `K~ = D K D`, `M~ = D M D`: balances the
//!    translational and rotational DOFs, whose masses differ by a factor h^2.
//! 2. Cholesky `M~ = L L^T` and the symmetric matrix `C = L^-1 K~ L^-T`.
//! 3. Symmetric eigen-decomposition `C = U Lambda U^T` by the implicit QR algorithm on the
//!    tridiagonal form, and back-substitution `phi = D L^-T u`.
//!
//! Why the QR algorithm and not faer's default divide-and-conquer (used from n = 128 when
//! vectors are wanted): on a 459-DOF free plate the latter returned a rigid-body eigenvalue of
//! 6e-12 of the largest one, enough to misclassify it and to put errors of a few 1e-6 on the
//! first elastic frequency; the QR algorithm keeps errors at round-off of the largest
//! eigenvalue (rigid modes at ~1e-17 of it). It costs a few times more (still well under a
//! second at 900 DOFs). The modes come out mass-normalized (`Phi^T M Phi = I`) and sorted by
//! ascending eigenvalue. Cost O(n^3): fine for a few thousand DOFs.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{
    ComputeEigenvectors, SelfAdjointEvdParams, self_adjoint_evd, self_adjoint_evd_scratch,
};
use faer::{Mat, Par, Side, Spec};
use nalgebra::DMatrix;

use super::error::{FlexError, invalid};

/// Result of [`solve_generalized`].
#[derive(Debug, Clone)]
pub struct EigenSolution {
    /// Eigenvalues `omega^2` [rad^2/s^2], ascending (tiny negative values possible for rigid
    /// modes, from round-off).
    pub omega2: Vec<f64>,
    /// Mass-normalized mode shapes as columns, full length (clamped DOFs are zero).
    pub modes: DMatrix<f64>,
}

impl EigenSolution {
    /// Natural frequencies [Hz]: `sqrt(max(omega^2, 0)) / (2 pi)`.
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.omega2
            .iter()
            .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect()
    }
}

/// Copies a nalgebra matrix into a faer one.
pub(crate) fn to_faer(a: &DMatrix<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// Copies a faer matrix into a nalgebra one.
pub(crate) fn to_nalgebra(a: faer::MatRef<'_, f64>) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// Checks that `k` and `m` are square, of equal size, finite and symmetric (to round-off).
pub(crate) fn check_pair(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Result<(), FlexError> {
    let n = k.nrows();
    if k.ncols() != n || m.nrows() != n || m.ncols() != n {
        return invalid(format!(
            "stiffness ({}x{}) and mass ({}x{}) must be square and of equal size",
            k.nrows(),
            k.ncols(),
            m.nrows(),
            m.ncols()
        ));
    }
    for (name, a) in [("stiffness", k), ("mass", m)] {
        if let Some(p) = a.iter().position(|x| !x.is_finite()) {
            return invalid(format!(
                "{name} matrix entry ({}, {}) is not finite",
                p % n,
                p / n
            ));
        }
        let scale = a.amax();
        for j in 0..n {
            for i in 0..j {
                if (a[(i, j)] - a[(j, i)]).abs() > 1e-9 * scale {
                    return invalid(format!(
                        "{name} matrix is not symmetric at ({i}, {j}): {} vs {}",
                        a[(i, j)],
                        a[(j, i)]
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The DOFs not in `clamped` (ascending), after checking `clamped` for range and duplicates.
pub(crate) fn free_dofs(n: usize, clamped: &[usize]) -> Result<Vec<usize>, FlexError> {
    let mut is_clamped = vec![false; n];
    for &d in clamped {
        if d >= n {
            return invalid(format!("clamped DOF {d} out of range (model has {n} DOFs)"));
        }
        if is_clamped[d] {
            return invalid(format!("clamped DOF {d} listed twice"));
        }
        is_clamped[d] = true;
    }
    Ok((0..n).filter(|&d| !is_clamped[d]).collect())
}

/// Solves `K phi = omega^2 M phi` on the DOFs not in `clamped` and returns the lowest `n_modes`
/// eigenpairs. Errors: size mismatch, non-finite or non-symmetric matrices, clamped DOF out of
/// range or repeated, `n_modes` larger than the number of free DOFs, mass not positive definite
/// on the free DOFs, or eigen-solver failure.
pub fn solve_generalized(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    clamped: &[usize],
    n_modes: usize,
) -> Result<EigenSolution, FlexError> {
    let FreeBlocks { free, kf, mf } = free_blocks(k, m, clamped, n_modes)?;
    let (omega2, y) = reduced_eigen(&kf, &mf)?;
    let mut modes = DMatrix::zeros(k.nrows(), n_modes);
    for c in 0..n_modes {
        for (i, &d) in free.iter().enumerate() {
            modes[(d, c)] = y[(i, c)];
        }
    }
    Ok(EigenSolution {
        omega2: omega2[..n_modes].to_vec(),
        modes,
    })
}

/// Like [`solve_generalized`] but returns only the lowest `n_values` eigenvalues `omega^2`
/// [rad^2/s^2] (no eigenvectors: several times cheaper).
pub fn generalized_eigenvalues(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    clamped: &[usize],
    n_values: usize,
) -> Result<Vec<f64>, FlexError> {
    let b = free_blocks(k, m, clamped, n_values)?;
    let t = cholesky_transform(&b.kf, &b.mf)?;
    let (omega2, _) = symmetric_eigen(&t.c, false)?;
    Ok(omega2[..n_values].to_vec())
}

/// Free DOFs (ascending) and the blocks of K and M on them.
struct FreeBlocks {
    free: Vec<usize>,
    kf: Mat<f64>,
    mf: Mat<f64>,
}

/// Validates the request and extracts the free-DOF blocks of K and M.
fn free_blocks(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    clamped: &[usize],
    n_modes: usize,
) -> Result<FreeBlocks, FlexError> {
    check_pair(k, m)?;
    let free = free_dofs(k.nrows(), clamped)?;
    let nf = free.len();
    if n_modes > nf {
        return invalid(format!(
            "requested {n_modes} modes but the model has only {nf} free DOFs"
        ));
    }
    let kf = Mat::from_fn(nf, nf, |i, j| k[(free[i], free[j])]);
    let mf = Mat::from_fn(nf, nf, |i, j| m[(free[i], free[j])]);
    Ok(FreeBlocks { free, kf, mf })
}

/// The scaled standard problem of the module doc.
struct Transformed {
    /// Scaling `d_i = 1 / sqrt(M_ii)`.
    d: Vec<f64>,
    /// Cholesky factor of `D mf D`.
    l: Mat<f64>,
    /// `C = L^-1 (D kf D) L^-T`, symmetric, same eigenvalues as the pencil.
    c: Mat<f64>,
}

/// Scaling, Cholesky factor and transformed matrix of the pair (kf, mf) (module doc).
fn cholesky_transform(kf: &Mat<f64>, mf: &Mat<f64>) -> Result<Transformed, FlexError> {
    let n = mf.nrows();
    let mut d = Vec::with_capacity(n);
    for i in 0..n {
        let mii = mf[(i, i)];
        if mii.is_nan() || mii <= 0.0 {
            return Err(FlexError::Numerical(format!(
                "mass matrix is not positive definite on the free DOFs (diagonal entry {i} of \
                 the free block is {mii})"
            )));
        }
        d.push(1.0 / mii.sqrt());
    }
    let ms = Mat::from_fn(n, n, |i, j| d[i] * mf[(i, j)] * d[j]);
    let llt = ms.llt(Side::Lower).map_err(|_| {
        FlexError::Numerical(
            "mass matrix is not positive definite on the free DOFs (Cholesky failed)".into(),
        )
    })?;
    let l = llt.L().to_owned();
    // C = L^-1 K~ L^-T, built as L^-1 (L^-1 K~)^T using the symmetry of K~.
    let mut x = Mat::from_fn(n, n, |i, j| d[i] * kf[(i, j)] * d[j]);
    l.solve_lower_triangular_in_place(x.as_mut());
    let mut c = x.transpose().to_owned();
    l.solve_lower_triangular_in_place(c.as_mut());
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    Ok(Transformed { d, l, c })
}

/// Eigenvalues (ascending) and, if `vectors`, orthonormal eigenvectors of the symmetric `c`,
/// by the tridiagonal QR algorithm (see the module doc for why not divide-and-conquer).
fn symmetric_eigen(c: &Mat<f64>, vectors: bool) -> Result<(Vec<f64>, Mat<f64>), FlexError> {
    let n = c.nrows();
    let mut params: Spec<SelfAdjointEvdParams, f64> = Default::default();
    params.recursion_threshold = usize::MAX;
    let compute = if vectors {
        ComputeEigenvectors::Yes
    } else {
        ComputeEigenvectors::No
    };
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(if vectors { n } else { 0 }, if vectors { n } else { 0 });
    let mut mem = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        n,
        compute,
        Par::Seq,
        params,
    ));
    self_adjoint_evd(
        c.as_ref(),
        s.as_mut(),
        if vectors { Some(u.as_mut()) } else { None },
        Par::Seq,
        MemStack::new(&mut mem),
        params,
    )
    .map_err(|e| FlexError::Numerical(format!("symmetric eigen-solver failed: {e:?}")))?;
    let s = s.column_vector();
    Ok(((0..n).map(|i| s[i]).collect(), u))
}

/// All eigenpairs of the dense pair (kf, mf): eigenvalues `omega^2` ascending and
/// mass-normalized vectors as columns.
pub(crate) fn reduced_eigen(
    kf: &Mat<f64>,
    mf: &Mat<f64>,
) -> Result<(Vec<f64>, Mat<f64>), FlexError> {
    let t = cholesky_transform(kf, mf)?;
    let n = t.c.nrows();
    let (omega2, mut y) = symmetric_eigen(&t.c, true)?;
    t.l.transpose().solve_upper_triangular_in_place(y.as_mut());
    let y = Mat::from_fn(n, n, |i, j| t.d[i] * y[(i, j)]);
    Ok((omega2, y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_mass_chain_matches_closed_form() {
        // Masses m, m joined to ground and to each other by springs k: omega^2 = k/m, 3k/m.
        let (kk, mm) = (4.0, 2.0);
        let k = DMatrix::from_row_slice(2, 2, &[2.0 * kk, -kk, -kk, 2.0 * kk]);
        let m = DMatrix::from_row_slice(2, 2, &[mm, 0.0, 0.0, mm]);
        let s = solve_generalized(&k, &m, &[], 2).unwrap();
        assert!((s.omega2[0] - kk / mm).abs() < 1e-12);
        assert!((s.omega2[1] - 3.0 * kk / mm).abs() < 1e-12);
        let g = s.modes.transpose() * &m * &s.modes;
        assert!((g - DMatrix::identity(2, 2)).norm() < 1e-12);
        // Clamping the second mass: one spring pair left, omega^2 = 2k/m.
        let s = solve_generalized(&k, &m, &[1], 1).unwrap();
        assert!((s.omega2[0] - 2.0 * kk / mm).abs() < 1e-12);
        assert_eq!(s.modes[(1, 0)], 0.0);
    }

    #[test]
    fn rejects_bad_requests() {
        let k = DMatrix::identity(3, 3);
        let m = DMatrix::identity(3, 3);
        let e = solve_generalized(&k, &m, &[0], 3).unwrap_err();
        assert!(e.to_string().contains("only 2 free DOFs"), "{e}");
        assert!(solve_generalized(&k, &m, &[5], 1).is_err());
        assert!(solve_generalized(&k, &m, &[1, 1], 1).is_err());
        let mut bad = m.clone();
        bad[(2, 2)] = -1.0;
        let e = solve_generalized(&k, &bad, &[], 1).unwrap_err();
        assert!(e.to_string().contains("positive definite"), "{e}");
        let mut ns = k.clone();
        ns[(0, 1)] = 1.0;
        assert!(solve_generalized(&ns, &m, &[], 1).is_err());
    }
}
