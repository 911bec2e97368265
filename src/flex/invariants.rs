//! Inertia invariants of a floating-frame-of-reference (FFR) body and its mass matrix `M(a)`,
//! quadratic-velocity vector `h(a, omega, a_dot)` and gravity force, all from the invariants.
//!
//! # Kinematics
//! Body frame: origin `r` [m] and rotation `A` (body to world) of the reference frame. A material
//! point with undeformed body-frame position `rho` [m] and translational mode shapes `Phi`
//! (3 x n, body frame) sits at `r + A u`, `u = rho + Phi a`, with modal coordinates `a`.
//! Generalized speeds `y = [v (world frame, 3) ; omega (body frame, 3) ; a_dot (n)]`. The
//! point's world velocity is `B y` with `B = [I, -A u~, A Phi]` and its world acceleration
//! `B y_dot + w`, `w = A (omega~ omega~ u + 2 omega~ Phi a_dot)` (`x~` is the skew matrix of
//! `x`, `x~ z = x cross z`).
//!
//! # Invariants (sums over mass points `k` with mass `m_k`, or the corresponding integrals)
//! - `m = sum m_k` [kg]
//! - `S = sum m_k rho_k` [kg m] (first moment)
//! - `J0 = sum m_k (|rho_k|^2 I - rho_k rho_k^T)` [kg m^2]; `R = sum m_k rho_k rho_k^T
//!   = tr(J0)/2 I - J0`
//! - `C_t = sum m_k Phi_k` (3 x n)
//! - `Q_j = sum m_k rho_k Phi_kj^T` (3 x 3, one per mode j; `Phi_kj` = column j of `Phi_k`)
//! - `P_ij = sum m_k Phi_ki Phi_kj^T` (3 x 3, one per mode pair; `P_ji = P_ij^T`)
//! - `M_ee` (n x n): the modal mass; for point masses `M_ee[i][j] = tr(P_ij)`, for an FE model
//!   the reduced mass `T^T M T` (equal to `tr(P_ij)` when the invariants are exact integrals).
//!
//! Derived (what the literature names): `C_r = sum m_k rho_k~ Phi_k` has column j
//! `vec(Q_j)`; `sum m_k rho_k~ Phi_kj~ = Q_j^T - tr(Q_j) I`; `sum m_k Phi_ki~ Phi_kj
//! = vec(P_ij)`, where `vec(X) = (X_yz - X_zy, X_zx - X_xz, X_xy - X_yx)` (so
//! `vec(x z^T) = x cross z`).
//!
//! # Configuration-dependent terms
//! - `E_j(a) = Q_j + sum_i a_i P_ij = sum m_k u_k Phi_kj^T`
//! - `S(a) = S + C_t a`
//! - `U(a) = sum m_k u_k u_k^T = R + sum_j a_j (Q_j^T + E_j(a))`, `J(a) = tr(U) I - U`
//! - `C_r(a) = sum m_k u_k~ Phi_k`, column j `= vec(E_j(a))`
//!
//! # Mass matrix `M(a) = sum m_k B_k^T B_k` (symmetric, 6 + n)
//! ```text
//! [ m I           -A S(a)~     A C_t   ]
//! [ (sym)          J(a)        C_r(a)  ]
//! [ (sym)          (sym)       M_ee    ]
//! ```
//!
//! # Quadratic-velocity vector `h = sum m_k B_k^T w_k`
//! Equations of motion: `M(a) y_dot + h = f_ext + f_el`, with elastic forces on the modal rows
//! `f_el = -(K a + D a_dot)` and `W = sum_j a_dot_j E_j(a)^T = sum m_k (Phi_k a_dot) u_k^T`:
//! - `h_v = A (omega~ omega~ S(a) + 2 omega~ C_t a_dot)` (world frame)
//! - `h_omega = omega~ J(a) omega + 2 (tr(W) I - W) omega` (body frame)
//! - `h_a[j] = omega^T E_j(a) omega - |omega|^2 tr(E_j(a)) + 2 omega . sum_i a_dot_i vec(P_ij)`
//!
//! Gravity `g` [m/s^2] (world frame), `g_b = A^T g`: `f = [m g ; S(a)~ g_b ; C_t^T g_b]`.
//! A world force `F` at a material point: `f = B^T F`; a body-frame torque `T`:
//! `f = [0 ; T ; Psi^T T]` with the point's rotational shapes `Psi`.

use nalgebra::{DMatrix, DVector, Matrix3xX};

use super::error::{FlexError, invalid};
use crate::math::{Mat3, Vec3, skew};

/// Inertia invariants of a floating-frame body with `n` modal coordinates (see module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Invariants {
    /// Total mass `m` [kg].
    pub mass: f64,
    /// First moment `S = sum m_k rho_k` [kg m], body frame.
    pub first_moment: Vec3,
    /// Inertia about the body-frame origin `J0` [kg m^2], body frame.
    pub inertia: Mat3,
    /// `C_t = sum m_k Phi_k`, 3 x n [kg per unit of a].
    pub c_t: Matrix3xX<f64>,
    /// `Q_j = sum m_k rho_k Phi_kj^T`, n entries of 3 x 3.
    pub q: Vec<Mat3>,
    /// `P_ij = sum m_k Phi_ki Phi_kj^T`, n x n entries of 3 x 3, stored at `i * n + j`.
    pub p: Vec<Mat3>,
    /// Modal mass `M_ee`, n x n, symmetric positive definite.
    pub modal_mass: DMatrix<f64>,
}

/// `vec(X) = (X_yz - X_zy, X_zx - X_xz, X_xy - X_yx)`: `vec(x z^T) = x cross z`.
pub fn axial(x: &Mat3) -> Vec3 {
    Vec3::new(
        x[(1, 2)] - x[(2, 1)],
        x[(2, 0)] - x[(0, 2)],
        x[(0, 1)] - x[(1, 0)],
    )
}

impl Invariants {
    /// Invariants of point masses `masses[k]` [kg] at `positions[k]` [m] with translational
    /// shapes `shapes[k]` (3 x n each); `M_ee = sum m_k Phi_k^T Phi_k`.
    pub fn from_nodes(
        masses: &[f64],
        positions: &[Vec3],
        shapes: &[Matrix3xX<f64>],
    ) -> Result<Self, FlexError> {
        let nn = masses.len();
        if positions.len() != nn || shapes.len() != nn {
            return invalid(format!(
                "{} masses, {} positions and {} shape blocks: counts must agree",
                nn,
                positions.len(),
                shapes.len()
            ));
        }
        if nn == 0 {
            return invalid("a body needs at least one node");
        }
        let n = shapes[0].ncols();
        for k in 0..nn {
            if !(masses[k].is_finite() && masses[k] >= 0.0) {
                return invalid(format!(
                    "node {k}: mass must be finite and >= 0, got {}",
                    masses[k]
                ));
            }
            if !positions[k].iter().all(|x| x.is_finite()) {
                return invalid(format!("node {k}: position is not finite"));
            }
            if shapes[k].ncols() != n {
                return invalid(format!(
                    "node {k}: {} mode columns, node 0 has {n}",
                    shapes[k].ncols()
                ));
            }
            if !shapes[k].iter().all(|x| x.is_finite()) {
                return invalid(format!("node {k}: mode shape is not finite"));
            }
        }
        let mut inv = Self {
            mass: 0.0,
            first_moment: Vec3::zeros(),
            inertia: Mat3::zeros(),
            c_t: Matrix3xX::zeros(n),
            q: vec![Mat3::zeros(); n],
            p: vec![Mat3::zeros(); n * n],
            modal_mass: DMatrix::zeros(n, n),
        };
        for k in 0..nn {
            let (mk, rho, phi) = (masses[k], &positions[k], &shapes[k]);
            inv.mass += mk;
            inv.first_moment += mk * rho;
            inv.inertia += mk * (rho.norm_squared() * Mat3::identity() - rho * rho.transpose());
            inv.c_t += mk * phi;
            for j in 0..n {
                let pj: Vec3 = phi.column(j).into();
                inv.q[j] += mk * rho * pj.transpose();
                for i in 0..n {
                    let pi: Vec3 = phi.column(i).into();
                    inv.p[i * n + j] += mk * pi * pj.transpose();
                }
            }
        }
        for i in 0..n {
            for j in 0..n {
                inv.modal_mass[(i, j)] = inv.p[i * n + j].trace();
            }
        }
        Ok(inv)
    }

    /// Checks sizes (`c_t` 3 x n, `q` n, `p` n^2, `modal_mass` n x n), finiteness, `m > 0`,
    /// symmetry of `J0`, `M_ee` and `P_ji = P_ij^T` (to 1e-9 relative).
    pub fn validate(&self) -> Result<(), FlexError> {
        let n = self.n_modes();
        if self.q.len() != n || self.p.len() != n * n {
            return invalid(format!(
                "invariants: {} Q blocks and {} P blocks for {n} modes (expected {n} and {})",
                self.q.len(),
                self.p.len(),
                n * n
            ));
        }
        if self.modal_mass.nrows() != n || self.modal_mass.ncols() != n {
            return invalid(format!(
                "invariants: modal mass is {}x{}, expected {n}x{n}",
                self.modal_mass.nrows(),
                self.modal_mass.ncols()
            ));
        }
        if !(self.mass.is_finite() && self.mass > 0.0) {
            return invalid(format!(
                "invariants: total mass must be > 0, got {}",
                self.mass
            ));
        }
        let finite = self.first_moment.iter().all(|x| x.is_finite())
            && self.inertia.iter().all(|x| x.is_finite())
            && self.c_t.iter().all(|x| x.is_finite())
            && self.q.iter().all(|b| b.iter().all(|x| x.is_finite()))
            && self.p.iter().all(|b| b.iter().all(|x| x.is_finite()))
            && self.modal_mass.iter().all(|x| x.is_finite());
        if !finite {
            return invalid("invariants contain a non-finite value");
        }
        let tol = |s: f64| 1e-9 * s.max(f64::MIN_POSITIVE);
        if (self.inertia - self.inertia.transpose()).amax() > tol(self.inertia.amax()) {
            return invalid("invariants: inertia J0 is not symmetric");
        }
        let mm = &self.modal_mass;
        if (mm - mm.transpose()).amax() > tol(mm.amax()) {
            return invalid("invariants: modal mass is not symmetric");
        }
        let pmax = self.p.iter().map(|b| b.amax()).fold(0.0, f64::max);
        for i in 0..n {
            for j in 0..n {
                if (self.p[i * n + j] - self.p[j * n + i].transpose()).amax() > tol(pmax) {
                    return invalid(format!("invariants: P_{i}{j} != P_{j}{i}^T"));
                }
            }
        }
        Ok(())
    }

    /// Number of modal coordinates n.
    pub fn n_modes(&self) -> usize {
        self.c_t.ncols()
    }

    /// `R = sum m_k rho_k rho_k^T = tr(J0)/2 I - J0` [kg m^2].
    pub fn second_moment(&self) -> Mat3 {
        0.5 * self.inertia.trace() * Mat3::identity() - self.inertia
    }

    /// `C_r = sum m_k rho_k~ Phi_k` (3 x n), column j `= vec(Q_j)`.
    pub fn c_r(&self) -> Matrix3xX<f64> {
        Matrix3xX::from_fn(self.n_modes(), |r, j| axial(&self.q[j])[r])
    }

    /// `sum m_k rho_k~ Phi_kj~ = Q_j^T - tr(Q_j) I` (3 x 3).
    pub fn rho_tilde_phi_tilde(&self, j: usize) -> Mat3 {
        self.q[j].transpose() - self.q[j].trace() * Mat3::identity()
    }

    /// `sum m_k Phi_ki~ Phi_kj = vec(P_ij)` (3-vector).
    pub fn phi_tilde_phi(&self, i: usize, j: usize) -> Vec3 {
        axial(&self.p[i * self.n_modes() + j])
    }

    /// `E_j(a) = Q_j + sum_i a_i P_ij` for every j.
    fn e_blocks(&self, a: &DVector<f64>) -> Vec<Mat3> {
        let n = self.n_modes();
        (0..n)
            .map(|j| {
                let mut e = self.q[j];
                for i in 0..n {
                    e += a[i] * self.p[i * n + j];
                }
                e
            })
            .collect()
    }

    fn check_len(&self, what: &str, v: &DVector<f64>) -> Result<(), FlexError> {
        if v.len() != self.n_modes() {
            return invalid(format!(
                "{what} has length {}, body has {} modes",
                v.len(),
                self.n_modes()
            ));
        }
        Ok(())
    }

    /// Deformed first moment `S(a) = S + C_t a` [kg m], body frame.
    pub fn first_moment_at(&self, a: &DVector<f64>) -> Vec3 {
        self.first_moment + &self.c_t * a
    }

    /// Deformed inertia `J(a)` about the body-frame origin [kg m^2], body frame.
    pub fn inertia_at(&self, a: &DVector<f64>) -> Mat3 {
        let e = self.e_blocks(a);
        Self::inertia_from(&self.second_moment(), &self.q, &e, a)
    }

    fn inertia_from(r: &Mat3, q: &[Mat3], e: &[Mat3], a: &DVector<f64>) -> Mat3 {
        let mut u = *r;
        for j in 0..q.len() {
            u += a[j] * (q[j].transpose() + e[j]);
        }
        // Symmetric in exact arithmetic; make it so in floating point too.
        let u = 0.5 * (u + u.transpose());
        u.trace() * Mat3::identity() - u
    }

    /// Mass matrix `M(a)` (6 + n square) for speeds `[v (world); omega (body); a_dot]`, with
    /// `rot` = A (body to world). Errors if `a` has the wrong length.
    pub fn mass_matrix(&self, rot: &Mat3, a: &DVector<f64>) -> Result<DMatrix<f64>, FlexError> {
        self.check_len("a", a)?;
        let n = self.n_modes();
        let e = self.e_blocks(a);
        let s_a = self.first_moment_at(a);
        let j_a = Self::inertia_from(&self.second_moment(), &self.q, &e, a);
        let mut m = DMatrix::zeros(6 + n, 6 + n);
        m.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(self.mass * Mat3::identity()));
        let mvw = -rot * skew(&s_a);
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&mvw);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&mvw.transpose());
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&j_a);
        let mva = rot * &self.c_t;
        for j in 0..n {
            let crj = axial(&e[j]);
            for r in 0..3 {
                m[(r, 6 + j)] = mva[(r, j)];
                m[(6 + j, r)] = mva[(r, j)];
                m[(3 + r, 6 + j)] = crj[r];
                m[(6 + j, 3 + r)] = crj[r];
            }
        }
        m.view_mut((6, 6), (n, n)).copy_from(&self.modal_mass);
        Ok(m)
    }

    /// Quadratic-velocity vector `h` (6 + n) of the module doc: `M y_dot + h = f`. `omega`
    /// [rad/s] in the body frame, `a_dot` modal speeds, `rot` = A (body to world).
    pub fn quadratic_velocity(
        &self,
        rot: &Mat3,
        a: &DVector<f64>,
        omega: &Vec3,
        a_dot: &DVector<f64>,
    ) -> Result<DVector<f64>, FlexError> {
        self.check_len("a", a)?;
        self.check_len("a_dot", a_dot)?;
        let n = self.n_modes();
        let e = self.e_blocks(a);
        let s_a = self.first_moment_at(a);
        let j_a = Self::inertia_from(&self.second_moment(), &self.q, &e, a);
        let mut h = DVector::zeros(6 + n);
        let ct_ad = &self.c_t * a_dot;
        let hv = rot * (omega.cross(&omega.cross(&s_a)) + 2.0 * omega.cross(&ct_ad));
        let mut w = Mat3::zeros();
        for j in 0..n {
            w += a_dot[j] * e[j].transpose();
        }
        let hw = omega.cross(&(j_a * omega)) + 2.0 * (w.trace() * omega - w * omega);
        h.fixed_rows_mut::<3>(0).copy_from(&hv);
        h.fixed_rows_mut::<3>(3).copy_from(&hw);
        let w2 = omega.norm_squared();
        for j in 0..n {
            let mut cor = Vec3::zeros();
            for i in 0..n {
                cor += a_dot[i] * axial(&self.p[i * n + j]);
            }
            h[6 + j] = omega.dot(&(e[j] * omega)) - w2 * e[j].trace() + 2.0 * omega.dot(&cor);
        }
        Ok(h)
    }

    /// Generalized gravity force (6 + n) for the world-frame field `g` [m/s^2].
    pub fn gravity_force(
        &self,
        rot: &Mat3,
        a: &DVector<f64>,
        g: &Vec3,
    ) -> Result<DVector<f64>, FlexError> {
        self.check_len("a", a)?;
        let gb = rot.transpose() * g;
        let mut f = DVector::zeros(6 + self.n_modes());
        f.fixed_rows_mut::<3>(0).copy_from(&(self.mass * g));
        f.fixed_rows_mut::<3>(3)
            .copy_from(&self.first_moment_at(a).cross(&gb));
        f.rows_mut(6, self.n_modes())
            .copy_from(&(self.c_t.transpose() * gb));
        Ok(f)
    }
}
