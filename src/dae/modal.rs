//! Floating-frame terms of modal (flexible) bodies inside the [`super::System`].
//!
//! For each modal body with speeds `y = [v (world), omega (body), a_dot]` (formulas of
//! [`crate::flex::invariants`]):
//!
//! - mass matrix `M(a)`, a full `(6 + n)` block, evaluated at the last kinematics update;
//! - generalized force `f = -h(A, a, omega, a_dot) - K a - D a_dot + f_g(A, a)` with the
//!   quadratic-velocity vector `h`, the modal stiffness `K` and damping `D`, and gravity
//!   `f_g = [m g; S(a)~ A^T g; C_t^T A^T g]` (the rigid [`crate::effect::gravity::Gravity`] effect
//!   leaves modal bodies out);
//! - potential energy `a^T K a / 2 - g . (m r + A S(a))`, dissipated power `a_dot^T D a_dot`.
//!
//! Newton-matrix blocks: `c_M M(a) + c_D D_f + c_K K_f` with `D_f = -df/dy` and `K_f = -df/dx`
//! (`x` the tangent increment: translation, body rotation vector, `da`). `D_f` is the central
//! difference of the analytic `f` in the speeds, which is exact up to rounding because `f` is
//! quadratic in them. `K_f` is the central difference in the rotation increment (step 1e-6 rad,
//! error O(1e-12) relative) and in `a` (exact up to rounding: `f` is at most quadratic in `a`);
//! `f` does not depend on the translation. The derivative of `M(q) y_dot` with respect to `q` is
//! not included (as for rigid bodies): it only slows Newton convergence by an O(h^2 |y_dot|)
//! amount and never changes the solution.

use crate::flex::ModalBodyData;
use crate::flex::invariants::axial;
#[cfg(test)]
use crate::math::exp_so3;
use crate::math::{Mat3, Vec3, skew};
use crate::model::kinematics::BodyKin;
use crate::model::{BodyKind, Model};
use nalgebra::{DMatrix, DVector, Vector3};
use std::sync::Arc;

use super::linear::LinearSolver;

/// Cached floating-frame terms of one modal body.
#[derive(Debug, Clone)]
pub(crate) struct ModalTerms {
    /// Body index in the model.
    pub body: usize,
    /// Offset of the body's position coordinates in `q`.
    q_offset: usize,
    /// Offset of the body's speeds in `v`.
    pub col: usize,
    pub data: Arc<ModalBodyData>,
    /// Modal coordinates and speeds at the last update.
    pub a: DVector<f64>,
    pub a_dot: DVector<f64>,
    /// Reference-frame pose and rates at the last update.
    pub r: Vec3,
    pub rot: Mat3,
    pub v: Vec3,
    pub omega: Vec3,
    /// `M(a)` at the last update, `(6 + n)` square.
    pub mass: DMatrix<f64>,
}

/// The modal bodies of `model`.
pub(crate) fn modal_terms(model: &Model) -> Vec<ModalTerms> {
    model
        .bodies
        .iter()
        .enumerate()
        .filter_map(|(i, b)| match &b.kind {
            BodyKind::Modal { data } => {
                let n = data.n_modes();
                Some(ModalTerms {
                    body: i,
                    q_offset: b.q_offset,
                    col: b.v_offset,
                    data: data.clone(),
                    a: DVector::zeros(n),
                    a_dot: DVector::zeros(n),
                    r: Vec3::zeros(),
                    rot: Mat3::identity(),
                    v: Vec3::zeros(),
                    omega: Vec3::zeros(),
                    mass: DMatrix::identity(6 + n, 6 + n),
                })
            }
            _ => None,
        })
        .collect()
}

/// `f = -h - K a - D a_dot + f_g` (length `6 + n`) at the given state.
fn generalized_force(
    data: &ModalBodyData,
    rot: &Mat3,
    a: &DVector<f64>,
    omega: &Vec3,
    a_dot: &DVector<f64>,
    g: Option<&Vec3>,
) -> DVector<f64> {
    let inv = data.invariants();
    let n = data.n_modes();
    // Lengths are fixed by the model layout, so these cannot fail; zeros keep it panic-free.
    let mut f = inv
        .quadratic_velocity(rot, a, omega, a_dot)
        .map(|h| -h)
        .unwrap_or_else(|_| DVector::zeros(6 + n));
    let el = -(data.stiffness() * a + data.damping() * a_dot);
    let mut modal_rows = f.rows_mut(6, n);
    modal_rows += &el;
    if let Some(g) = g
        && let Ok(fg) = inv.gravity_force(rot, a, g)
    {
        f += fg;
    }
    f
}

impl ModalTerms {
    /// Reads `a`, `a_dot` from the flat vectors and the frame from `kin`; recomputes `M(a)`.
    pub fn update(&mut self, q: &[f64], v: &[f64], kin: &BodyKin) {
        let n = self.a.len();
        self.a
            .as_mut_slice()
            .copy_from_slice(&q[self.q_offset + 7..self.q_offset + 7 + n]);
        self.a_dot
            .as_mut_slice()
            .copy_from_slice(&v[self.col + 6..self.col + 6 + n]);
        self.r = kin.r;
        self.rot = kin.rot;
        self.v = kin.v;
        self.omega = kin.omega;
        if let Ok(m) = self.data.invariants().mass_matrix(&self.rot, &self.a) {
            self.mass = m;
        }
    }

    /// `out[body] = M(a) x[body]`.
    pub fn mass_mul(&self, x: &[f64], out: &mut [f64]) {
        let nv = self.mass.nrows();
        for r in 0..nv {
            let mut s = 0.0;
            for c in 0..nv {
                s += self.mass[(r, c)] * x[self.col + c];
            }
            out[self.col + r] = s;
        }
    }

    /// Adds the body's generalized forces (gravity `g` if on) to `f`.
    pub fn add_forces(&self, g: Option<&Vec3>, f: &mut [f64]) {
        let fb = generalized_force(&self.data, &self.rot, &self.a, &self.omega, &self.a_dot, g);
        for (i, x) in fb.iter().enumerate() {
            f[self.col + i] += x;
        }
    }

    /// Potential energy [J]: elastic `a^T K a / 2` plus gravity `-g . (m r + A S(a))`.
    pub fn potential_energy(&self, g: Option<&Vec3>) -> f64 {
        let elastic = 0.5 * self.a.dot(&(self.data.stiffness() * &self.a));
        let inv = self.data.invariants();
        let grav = g.map_or(0.0, |g| {
            -g.dot(&(inv.mass * self.r + self.rot * inv.first_moment_at(&self.a)))
        });
        elastic + grav
    }

    /// Power dissipated by modal damping `a_dot^T D a_dot` [W].
    pub fn dissipated_power(&self) -> f64 {
        self.a_dot.dot(&(self.data.damping() * &self.a_dot))
    }

    /// `D_f = -df/dy` and `K_f = -df/dx` ((6 + n) square each), analytic (module doc).
    pub fn force_jacobians(&self, g: Option<&Vec3>) -> (DMatrix<f64>, DMatrix<f64>) {
        let inv = self.data.invariants();
        let n = self.a.len();
        let nv = 6 + n;
        let (rot, om, a, ad) = (&self.rot, &self.omega, &self.a, &self.a_dot);
        let ct = &inv.c_t;
        let p = |i: usize, j: usize| &inv.p[i * n + j];
        // configuration-dependent terms
        let e: Vec<Mat3> = (0..n)
            .map(|j| {
                let mut e = inv.q[j];
                for i in 0..n {
                    e += a[i] * p(i, j);
                }
                e
            })
            .collect();
        let s_a = inv.first_moment_at(a);
        let j_a = inv.inertia_at(a);
        let c = ct * ad;
        let mut w = Mat3::zeros();
        for j in 0..n {
            w += ad[j] * e[j].transpose();
        }
        let w2 = om.norm_squared();
        let eye = Mat3::identity();
        let mut df = DMatrix::zeros(nv, nv);
        let mut kf = DMatrix::zeros(nv, nv);
        // --- speeds: omega
        let dv_dom = rot
            * (om * s_a.transpose() + om.dot(&s_a) * eye
                - 2.0 * s_a * om.transpose()
                - 2.0 * skew(&c));
        let dw_dom = skew(om) * j_a - skew(&(j_a * om)) + 2.0 * (w.trace() * eye - w);
        df.fixed_view_mut::<3, 3>(0, 3).copy_from(&dv_dom);
        df.fixed_view_mut::<3, 3>(3, 3).copy_from(&dw_dom);
        for j in 0..n {
            let mut d = Vec3::zeros();
            for i in 0..n {
                d += ad[i] * axial(p(i, j));
            }
            let row = (e[j] + e[j].transpose()) * om - 2.0 * e[j].trace() * om + 2.0 * d;
            for k in 0..3 {
                df[(6 + j, 3 + k)] = row[k];
            }
        }
        // --- speeds: a_dot
        for i in 0..n {
            let cti = Vector3::new(ct[(0, i)], ct[(1, i)], ct[(2, i)]);
            let hv = rot * (2.0 * om.cross(&cti));
            let hw = 2.0 * (e[i].trace() * om - e[i].transpose() * om);
            for k in 0..3 {
                df[(k, 6 + i)] = hv[k];
                df[(3 + k, 6 + i)] = hw[k];
            }
            for j in 0..n {
                df[(6 + j, 6 + i)] = 2.0 * om.dot(&axial(p(i, j)));
            }
        }
        let damping = self.data.damping();
        let mut dd = df.view_mut((6, 6), (n, n));
        dd += damping;
        // --- rotation increment: h_v = A u_v, gravity through A^T g
        let u_v = om.cross(&om.cross(&s_a)) + 2.0 * om.cross(&c);
        kf.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-rot * skew(&u_v)));
        let gb = g.map(|g| rot.transpose() * g);
        if let Some(gb) = &gb {
            let gbx = skew(gb);
            kf.fixed_view_mut::<3, 3>(3, 3)
                .copy_from(&(-skew(&s_a) * gbx));
            let ctg = ct.transpose() * gbx;
            let mut blk = kf.view_mut((6, 3), (n, 3));
            blk -= &ctg;
        }
        // --- modal coordinates
        for k in 0..n {
            let ctk = Vector3::new(ct[(0, k)], ct[(1, k)], ct[(2, k)]);
            let hv = rot * om.cross(&om.cross(&ctk));
            let mut fk = Mat3::zeros();
            let mut dwk = Mat3::zeros();
            for j in 0..n {
                fk += a[j] * p(k, j);
                dwk += ad[j] * p(k, j).transpose();
            }
            let du = inv.q[k] + inv.q[k].transpose() + fk + fk.transpose();
            let dj = du.trace() * eye - du;
            let mut hw = om.cross(&(dj * om)) + 2.0 * (dwk.trace() * om - dwk * om);
            if let Some(gb) = &gb {
                hw -= ctk.cross(gb);
            }
            for r in 0..3 {
                kf[(r, 6 + k)] = hv[r];
                kf[(3 + r, 6 + k)] = hw[r];
            }
            for j in 0..n {
                let pkj = p(k, j);
                kf[(6 + j, 6 + k)] = om.dot(&(pkj * om)) - w2 * pkj.trace();
            }
        }
        let stiffness = self.data.stiffness();
        let mut kk = kf.view_mut((6, 6), (n, n));
        kk += stiffness;
        (df, kf)
    }

    /// `D_f`, `K_f` by central differences of the analytic force (the reference of the tests).
    #[cfg(test)]
    pub fn force_jacobians_fd(&self, g: Option<&Vec3>) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.a.len();
        let nv = 6 + n;
        let force = |rot: &Mat3, a: &DVector<f64>, om: &Vec3, ad: &DVector<f64>| {
            generalized_force(&self.data, rot, a, om, ad, g)
        };
        let mut df = DMatrix::zeros(nv, nv);
        let mut kf = DMatrix::zeros(nv, nv);
        for c in 3..nv {
            let eps = 1e-3;
            let (mut op, mut om) = (self.omega, self.omega);
            let (mut ap, mut am) = (self.a_dot.clone(), self.a_dot.clone());
            if c < 6 {
                op[c - 3] += eps;
                om[c - 3] -= eps;
            } else {
                ap[c - 6] += eps;
                am[c - 6] -= eps;
            }
            let d = (force(&self.rot, &self.a, &op, &ap) - force(&self.rot, &self.a, &om, &am))
                / (2.0 * eps);
            df.column_mut(c).copy_from(&(-d));
            let (fp, fm, eps) = if c < 6 {
                let eps = 1e-6;
                let e = Vec3::ith(c - 3, eps);
                let rp = self.rot * exp_so3(&e).to_rotation_matrix().into_inner();
                let rm = self.rot * exp_so3(&-e).to_rotation_matrix().into_inner();
                (
                    force(&rp, &self.a, &self.omega, &self.a_dot),
                    force(&rm, &self.a, &self.omega, &self.a_dot),
                    eps,
                )
            } else {
                let eps = 1e-3 * (1.0 + self.a.amax());
                let (mut ap, mut am) = (self.a.clone(), self.a.clone());
                ap[c - 6] += eps;
                am[c - 6] -= eps;
                (
                    force(&self.rot, &ap, &self.omega, &self.a_dot),
                    force(&self.rot, &am, &self.omega, &self.a_dot),
                    eps,
                )
            };
            kf.column_mut(c).copy_from(&(-(fp - fm) / (2.0 * eps)));
        }
        (df, kf)
    }

    /// Adds `c_M M + c_D D_f + c_K K_f` of this body at `(row_off, col_off)` (module doc).
    #[allow(clippy::too_many_arguments)]
    pub fn add_newton_block(
        &self,
        g: Option<&Vec3>,
        cm: f64,
        cd: f64,
        ck: f64,
        lin: &mut LinearSolver,
        row_off: usize,
        col_off: usize,
    ) {
        let nv = 6 + self.a.len();
        let mut blk = &self.mass * cm;
        if cd != 0.0 || ck != 0.0 {
            let (df, kf) = self.force_jacobians(g);
            blk += cd * df + ck * kf;
        }
        for c in 0..nv {
            for r in 0..nv {
                lin.push(row_off + self.col + r, col_off + self.col + c, blk[(r, c)]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::dae::System;
    use crate::scene::panel_lock::{PanelLock, PanelLockParams};

    /// The analytic `D_f`, `K_f` equal central differences of the force, with gravity, at a
    /// deformed, spinning state with modal speeds.
    #[test]
    fn analytic_force_jacobians_match_differences() {
        let scene = PanelLock::new(PanelLockParams::flexible(6)).unwrap();
        let mut sys: System = scene.sim.system.clone();
        let (mut q, mut v) = (scene.sim.state.q.clone(), scene.sim.state.v.clone());
        for b in &sys.model.bodies {
            for i in 0..b.kind.n_modes() {
                q[b.q_offset + 7 + i] += 1e-3 * ((i as f64) * 0.7 + 0.2).sin();
            }
        }
        for (i, x) in v.iter_mut().enumerate() {
            *x += 0.5 * ((i as f64) * 1.3).cos();
        }
        sys.update_kinematics(&q, &v);
        let g = nalgebra::Vector3::new(0.3, -9.81, 1.1);
        for m in &sys.modal {
            for grav in [None, Some(&g)] {
                let (da, ka) = m.force_jacobians(grav);
                let (dn, kn) = m.force_jacobians_fd(grav);
                let scale = dn.amax().max(kn.amax());
                assert!(
                    (&da - &dn).amax() <= 1e-7 * scale,
                    "D_f: {}",
                    (&da - &dn).amax()
                );
                assert!(
                    (&ka - &kn).amax() <= 1e-7 * scale,
                    "K_f: {}",
                    (&ka - &kn).amax()
                );
            }
        }
    }
}
