//! Finite-difference checks of assembled force Jacobians (`K = -df/dx`, `D = -df/dv`).

use mbcosim::dae::System;
use mbcosim::dae::linear::LinearSolver;
use mbcosim::model::Model;
use nalgebra::DMatrix;

/// The matrix `c[0] M + c[1] D + c[2] K` as the system assembles it at time `t` [s], recovered
/// through solves (the linear solver is the only public view of the matrix): a large identity
/// keeps it invertible and is taken off again.
pub fn assembled(sys: &mut System, t: f64, q: &[f64], v: &[f64], c: [f64; 3]) -> DMatrix<f64> {
    let n = sys.n_v();
    let mut lin = LinearSolver::new();
    lin.begin(n);
    sys.add_dynamics_matrix_at(t, q, v, c, &mut lin, 0, 0);
    let big = 1e3;
    for i in 0..n {
        lin.push(i, i, big);
    }
    lin.factor().unwrap();
    let mut inv = DMatrix::zeros(n, n);
    for j in 0..n {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        lin.solve(&mut e).unwrap();
        for i in 0..n {
            inv[(i, j)] = e[i];
        }
    }
    inv.try_inverse().unwrap() - DMatrix::identity(n, n) * big
}

/// Largest difference between the assembled `K`, `D` and their central finite differences with
/// step `eps` (positions retracted on the model's configuration space), and the largest
/// finite-difference entry as the scale: `(worst, scale)`.
pub fn force_jacobian_mismatch(
    model: &Model,
    sys: &mut System,
    t: f64,
    q: &[f64],
    v: &[f64],
    eps: f64,
) -> (f64, f64) {
    let n = sys.n_v();
    let k_an = assembled(sys, t, q, v, [0.0, 0.0, 1.0]);
    let d_an = assembled(sys, t, q, v, [0.0, 1.0, 0.0]);
    let f_at = |q: &[f64], v: &[f64]| {
        let mut f = vec![0.0; n];
        sys.forces(t, q, v, &mut f);
        f
    };
    jacobian_mismatch(model, q, v, &k_an, &d_an, f_at, eps)
}

/// Largest difference between given `K`, `D` (`n_v x n_v`) and the central finite differences
/// of the generalized force `f_at(q, v)` with step `eps` (positions retracted on `model`'s
/// configuration space), and the largest finite-difference entry: `(worst, scale)`. For checking
/// one effect's share, `f_at` and the matrices are differences of two systems.
pub fn jacobian_mismatch(
    model: &Model,
    q: &[f64],
    v: &[f64],
    k_an: &DMatrix<f64>,
    d_an: &DMatrix<f64>,
    mut f_at: impl FnMut(&[f64], &[f64]) -> Vec<f64>,
    eps: f64,
) -> (f64, f64) {
    let n = k_an.nrows();
    let (mut worst, mut scale): (f64, f64) = (0.0, 0.0);
    for j in 0..n {
        let mut dx = vec![0.0; n];
        dx[j] = eps;
        let (mut qp, mut qm) = (q.to_vec(), q.to_vec());
        model.retract(q, &dx, &mut qp);
        dx[j] = -eps;
        model.retract(q, &dx, &mut qm);
        let (fp, fm) = (f_at(&qp, v), f_at(&qm, v));
        let (mut vp, mut vm) = (v.to_vec(), v.to_vec());
        vp[j] += eps;
        vm[j] -= eps;
        let (gp, gm) = (f_at(q, &vp), f_at(q, &vm));
        for i in 0..n {
            let k_fd = -(fp[i] - fm[i]) / (2.0 * eps);
            let d_fd = -(gp[i] - gm[i]) / (2.0 * eps);
            worst = worst
                .max((k_fd - k_an[(i, j)]).abs())
                .max((d_fd - d_an[(i, j)]).abs());
            scale = scale.max(k_fd.abs()).max(d_fd.abs());
        }
    }
    (worst, scale)
}
