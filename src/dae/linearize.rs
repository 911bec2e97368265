//! Small free vibrations about a static equilibrium: the equilibrium itself (a Newton solve of
//! the force balance with the constraints) and the undamped natural frequencies of the
//! constrained system linearized there.
//!
//! At rest (`v = 0`) the equations of motion `M a = f(q, v, t) - G^T lambda`, `Phi(q) = 0`
//! linearize to `M dx'' + (K + H(lambda)) dx + G^T dlambda = 0`, `G dx = 0`, where `dx` is the
//! increment in velocity coordinates (translations in the world frame, body-frame rotation
//! vectors, modal coordinates), `K = -df/dq` the effects' and modal bodies' tangent stiffness
//! ([`System::add_dynamics_matrix`] with `c_K = 1`) and `H(lambda)` the joints' geometric
//! stiffness ([`System::add_constraint_stiffness`]). With `N` an orthonormal basis of the null
//! space of `G`, the frequencies are the square roots of the eigenvalues of the pencil
//! `(N^T K_t N, N^T M N)` over `2 pi`. Damping (`D`) is left out: these are the undamped
//! frequencies.
//!
//! The effects are evaluated with the memory the system holds (e.g. a latch that is locked),
//! so the linearization is that of the state the caller brought the system to.

use super::System;
use super::linear::LinearSolver;
use nalgebra::{DMatrix, DVector};

/// The static equilibrium found by [`static_equilibrium`].
#[derive(Debug, Clone)]
pub struct Equilibrium {
    /// Positions [model units] and the active rows' multipliers.
    pub q: Vec<f64>,
    pub lambda: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Largest unbalanced generalized force [N or N m] and constraint residual at `q`.
    pub force_residual: f64,
    pub constraint_residual: f64,
}

/// The matrix `c_M M + c_K (K + H(lambda))` at `(t, q, v = 0)`, dense `n_v x n_v`.
fn dynamics_matrix(
    sys: &mut System,
    t: f64,
    q: &[f64],
    lambda: &[f64],
    cm: f64,
    ck: f64,
) -> DMatrix<f64> {
    let nv = sys.n_v();
    let v = vec![0.0; nv];
    let mut lin = LinearSolver::new();
    lin.begin(nv);
    sys.eval_constraints(t, q, &v);
    sys.add_dynamics_matrix(t, q, &v, cm, 0.0, ck, &mut lin, 0);
    if ck != 0.0 && !lambda.is_empty() {
        sys.add_constraint_stiffness(lambda, ck, &mut lin, 0, 0);
    }
    let mut m = DMatrix::zeros(nv, nv);
    for (r, c, x) in lin.triplets() {
        m[(r, c)] += x;
    }
    m
}

/// The active rows' Jacobian `G` (`n_c x n_v`) and residuals `Phi` at `(t, q)`.
fn constraint_rows(sys: &mut System, t: f64, q: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let nv = sys.n_v();
    sys.eval_constraints(t, q, &vec![0.0; nv]);
    let nc = sys.rows.len();
    let mut g = DMatrix::zeros(nc, nv);
    let mut e = vec![0.0; nv];
    let mut col = vec![0.0; nc];
    for j in 0..nv {
        e[j] = 1.0;
        sys.g_mul(&e, &mut col);
        e[j] = 0.0;
        for (r, &x) in col.iter().enumerate() {
            g[(r, j)] = x;
        }
    }
    let phi = DVector::from_iterator(nc, sys.rows.iter().map(|r| r.phi));
    (g, phi)
}

/// Generalized forces `f(q, 0, t)` (springs, contacts, gravity, modal stiffness).
fn rest_forces(sys: &mut System, t: f64, q: &[f64]) -> DVector<f64> {
    let nv = sys.n_v();
    let mut f = vec![0.0; nv];
    sys.forces(t, q, &vec![0.0; nv], &mut f);
    DVector::from_vec(f)
}

/// Largest absolute entry (0 for an empty vector).
fn max_abs(x: &DVector<f64>) -> f64 {
    x.iter().fold(0.0, |a, b| a.max(b.abs()))
}

/// The static equilibrium nearest `q0` at time `t` with `v = 0`: Newton on
/// `f(q) - G^T lambda = 0`, `Phi(q) = 0` until the unbalanced force is below `force_tol` and
/// the constraint residual below `constraint_tol` (at most `max_iterations`). `Err` names what
/// did not converge.
pub fn static_equilibrium(
    sys: &mut System,
    t: f64,
    q0: &[f64],
    force_tol: f64,
    constraint_tol: f64,
    max_iterations: usize,
) -> Result<Equilibrium, String> {
    let nv = sys.n_v();
    let mut q = q0.to_vec();
    let (g, _) = constraint_rows(sys, t, &q);
    let nc = g.nrows();
    // the multipliers that balance the forces best at the start (least squares)
    let f = rest_forces(sys, t, &q);
    let mut lambda: Vec<f64> = if nc == 0 {
        Vec::new()
    } else {
        let ggt = &g * g.transpose();
        let rhs = &g * &f;
        ggt.lu()
            .solve(&rhs)
            .ok_or("the constraint rows are dependent at the start")?
            .as_slice()
            .to_vec()
    };
    let mut out = vec![0.0; q.len()];
    let mut iterations = 0;
    loop {
        let (g, phi) = constraint_rows(sys, t, &q);
        let f = rest_forces(sys, t, &q);
        let unbalanced = &f - g.transpose() * DVector::from_column_slice(&lambda);
        let (fr, cr) = (max_abs(&unbalanced), max_abs(&phi));
        if fr <= force_tol && cr <= constraint_tol {
            return Ok(Equilibrium {
                q,
                lambda,
                iterations,
                force_residual: fr,
                constraint_residual: cr,
            });
        }
        if iterations == max_iterations {
            return Err(format!(
                "no static equilibrium after {max_iterations} Newton iterations: unbalanced force {fr:.3e} (tolerance {force_tol:.1e}), constraint residual {cr:.3e} (tolerance {constraint_tol:.1e})"
            ));
        }
        iterations += 1;
        // [K_t G^T; G 0] [dx; dlambda] = [f - G^T lambda; -Phi]
        let kt = dynamics_matrix(sys, t, &q, &lambda, 0.0, 1.0);
        let mut a = DMatrix::zeros(nv + nc, nv + nc);
        a.view_mut((0, 0), (nv, nv)).copy_from(&kt);
        a.view_mut((0, nv), (nv, nc)).copy_from(&g.transpose());
        a.view_mut((nv, 0), (nc, nv)).copy_from(&g);
        let mut rhs = DVector::zeros(nv + nc);
        rhs.rows_mut(0, nv).copy_from(&unbalanced);
        rhs.rows_mut(nv, nc).copy_from(&(-&phi));
        let dx = a.lu().solve(&rhs).ok_or(
            "the static equilibrium's Newton matrix is singular (a free motion without stiffness)",
        )?;
        sys.model.retract(&q, &dx.as_slice()[..nv], &mut out);
        q.copy_from_slice(&out);
        for (l, d) in lambda.iter_mut().zip(&dx.as_slice()[nv..]) {
            *l += d;
        }
    }
}

/// An orthonormal basis of the null space of `g` (`n_v x (n_v - n_c)`): the eigenvectors of
/// `G^T G` of its `n_v - n_c` smallest eigenvalues (the active rows are independent, so that is
/// the null space's dimension). `Err` if those eigenvalues are not negligible (dependent rows).
fn null_space(g: &DMatrix<f64>, nv: usize) -> Result<DMatrix<f64>, String> {
    let nc = g.nrows();
    if nc == 0 {
        return Ok(DMatrix::identity(nv, nv));
    }
    let eig = (g.transpose() * g).symmetric_eigen();
    let mut order: Vec<usize> = (0..nv).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let largest = eig.eigenvalues[order[nv - 1]].max(f64::MIN_POSITIVE);
    let free = nv.saturating_sub(nc);
    if free < nv && eig.eigenvalues[order[free]] <= 1e-12 * largest {
        return Err(format!(
            "the {nc} constraint rows are dependent at the equilibrium (more than {free} free motions)"
        ));
    }
    let mut n = DMatrix::zeros(nv, free);
    for (k, &i) in order[..free].iter().enumerate() {
        n.set_column(k, &eig.eigenvectors.column(i));
    }
    Ok(n)
}

/// Undamped natural frequencies [Hz] of the system linearized at `(t, q, v = 0)` with the
/// multipliers `lambda` (ascending; a mode without stiffness gives 0). `Err` if the reduced mass
/// matrix is not positive definite.
pub fn natural_frequencies(
    sys: &mut System,
    t: f64,
    q: &[f64],
    lambda: &[f64],
) -> Result<Vec<f64>, String> {
    let nv = sys.n_v();
    let (g, _) = constraint_rows(sys, t, q);
    let n = null_space(&g, nv)?;
    let m = dynamics_matrix(sys, t, q, lambda, 1.0, 0.0);
    let k = dynamics_matrix(sys, t, q, lambda, 0.0, 1.0);
    let mr = n.transpose() * &m * &n;
    let kr = n.transpose() * &k * &n;
    let mr = (&mr + mr.transpose()) * 0.5;
    let l = mr
        .cholesky()
        .ok_or("the mass matrix reduced to the free motions is not positive definite")?
        .l();
    let li = l
        .try_inverse()
        .ok_or("the reduced mass matrix's factor is singular")?;
    let a = &li * kr * li.transpose();
    // the tangent stiffness of a conservative system at rest is symmetric; the symmetric part
    // is taken (contact and geometric terms round to small asymmetries)
    let a = (&a + a.transpose()) * 0.5;
    let mut f: Vec<f64> = a
        .symmetric_eigen()
        .eigenvalues
        .iter()
        .map(|&w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Mat3, Quat, Vec3};
    use crate::model::{BodyId, BodyInit, Frame, JointKind, ModelBuilder};
    use std::sync::Arc;

    const G: f64 = 9.81;

    /// A chain of `n` uniform rods (1 kg, 1 m) on revolute joints about z, gravity along +x,
    /// built turned by `angle` [rad] about z from the hanging line (the +x axis).
    fn hanging_chain(n: usize, angle: f64) -> (System, Vec<f64>) {
        let mut b = ModelBuilder::new();
        b.set_gravity(Some(Vec3::new(G, 0.0, 0.0))).unwrap();
        let inertia = Mat3::from_diagonal(&Vec3::new(1e-4, 1.0 / 12.0, 1.0 / 12.0));
        let turn = Quat::from_axis_angle(&Vec3::z_axis(), angle);
        let half = Vec3::new(0.5, 0.0, 0.0);
        let mut prev = (BodyId::GROUND, Vec3::zeros());
        for k in 0..n {
            let at = turn * Vec3::new(k as f64 + 0.5, 0.0, 0.0);
            let id = b
                .add_rigid_body(
                    &format!("rod{k}"),
                    1.0,
                    inertia,
                    BodyInit::at(at).oriented(turn),
                )
                .unwrap();
            b.add_joint(
                &format!("hinge{k}"),
                JointKind::Revolute,
                Frame::new(prev.0, prev.1),
                Frame::new(id, -half),
            )
            .unwrap();
            prev = (id, half);
        }
        let sys = System::new(Arc::new(b.build().unwrap())).unwrap();
        let q = crate::integrator::init::initial_state(&sys, 0.0).q;
        (sys, q)
    }

    fn frequencies_at_rest(n: usize, angle: f64) -> (Equilibrium, Vec<f64>) {
        let (mut sys, q0) = hanging_chain(n, angle);
        let eq = static_equilibrium(&mut sys, 0.0, &q0, 1e-10, 1e-12, 30).unwrap();
        let f = natural_frequencies(&mut sys, 0.0, &eq.q, &eq.lambda).unwrap();
        (eq, f)
    }

    /// A compound pendulum: omega^2 = m g (L/2) / (m L^2 / 3) = 1.5 g; found from 30 degrees
    /// off the hanging line.
    #[test]
    fn compound_pendulum_frequency_by_hand() {
        let (eq, f) = frequencies_at_rest(1, std::f64::consts::FRAC_PI_6);
        let expected = (1.5 * G).sqrt() / (2.0 * std::f64::consts::PI);
        assert_eq!(f.len(), 1, "{f:?}");
        assert!(
            (f[0] / expected - 1.0).abs() < 1e-9,
            "{} against {expected}",
            f[0]
        );
        // the equilibrium hangs along +x: the rod's centre at (0.5, 0, 0)
        assert!(
            (eq.q[0] - 0.5).abs() < 1e-10 && eq.q[1].abs() < 1e-10,
            "{:?}",
            &eq.q[..3]
        );
        assert!(eq.iterations > 1);
    }

    /// Two uniform rods (absolute angles): M = [[4/3, 1/2], [1/2, 1/3]] m L^2,
    /// K = [[3/2, 0], [0, 1/2]] m g L; omega^2 are the roots of det(K - omega^2 M) = 0:
    /// (7/36) w^2 - (7/6) g w + (3/4) g^2 = 0 with w = omega^2.
    #[test]
    fn double_compound_pendulum_frequencies_by_hand() {
        let (_, f) = frequencies_at_rest(2, 0.0);
        let (a, b, c) = (7.0 / 36.0, -7.0 / 6.0 * G, 0.75 * G * G);
        let disc = (b * b - 4.0 * a * c).sqrt();
        let mut expected: Vec<f64> = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)]
            .iter()
            .map(|w: &f64| w.sqrt() / (2.0 * std::f64::consts::PI))
            .collect();
        expected.sort_by(f64::total_cmp);
        assert_eq!(f.len(), 2, "{f:?}");
        for (x, e) in f.iter().zip(&expected) {
            assert!((x / e - 1.0).abs() < 1e-9, "{f:?} against {expected:?}");
        }
    }
}
