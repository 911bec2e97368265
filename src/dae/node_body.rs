//! Node bodies: rigid frames riding on nodes of modal bodies, where force effects act.
//!
//! Node `k` of a modal body (reference frame `r`, `A`, speeds `y = [v, omega, a_dot]`) carries
//! the frame
//!
//! - origin `r_n = r + A u`, `u = rho_k + Phi_k a`; rotation `R_n = A E`, `E = exp(theta~)`,
//!   `theta = Psi_k a` (the node's small rotation, applied exactly so that `R_n` is a rotation);
//! - speeds `y_n = [v_n (world); omega_n (node frame)] = N y` with
//!   `N = [[I, -A u~, A Phi_k]; [0, E^T, J_r(theta) Psi_k]]` (`J_r` the right Jacobian of
//!   `exp`); tangent increments map by the same `N`.
//!
//! Effects see it as a rigid body with speed columns past `n_v`. Its generalized forces `f_n`
//! go to the modal body as `N^T f_n` (power-consistent). Jacobian blocks: with `K_n`, `D_n` the
//! effect's blocks w.r.t. node-body increments and speeds, the body blocks are `N_a^T K N_b`,
//! `N_a^T D N_b`, plus `N_a^T D_ab W_b` in `K` (`W_b = d(N_b y)/dx`, the velocity map's
//! dependence on the configuration) and `-d(N^T f_n)/dx` at fixed `f_n` (geometric term). `W`
//! and the geometric term are central differences of the analytic `N` (rotation step 1e-6 rad,
//! modal step 1e-6 (1 + |a|)), accurate to about 1e-9 relative; the rest is exact.
//!
//! The node-body frame differs from a joint's node frame (`d + theta x d`, linearized) only at
//! second order in the node rotation, inside the linear-modes limit.

use super::modal::ModalTerms;
use crate::math::{Mat3, Matrix6, Vec3, exp_so3, skew};
use crate::model::kinematics::BodyKin;
use crate::model::{Model, NodeBody};
use nalgebra::{DMatrix, DVector};

/// Right Jacobian of `exp`: `d/dt exp(theta~) = exp(theta~) (J_r(theta) theta_dot)~`.
fn right_jacobian(theta: &Vec3) -> Mat3 {
    let t2 = theta.norm_squared();
    let (c1, c2) = if t2 < 1e-6 {
        (
            0.5 - t2 / 24.0 + t2 * t2 / 720.0,
            1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0,
        )
    } else {
        let t = t2.sqrt();
        ((1.0 - t.cos()) / t2, (t - t.sin()) / (t2 * t))
    };
    let th = skew(theta);
    Mat3::identity() - c1 * th + c2 * th * th
}

/// Rotation matrix of the rotation vector `theta`.
fn rotation(theta: &Vec3) -> Mat3 {
    exp_so3(theta).to_rotation_matrix().into_inner()
}

/// Cached kinematics and maps of one node body.
#[derive(Debug, Clone)]
pub(crate) struct NodeBodyTerms {
    /// Index into the system's modal terms.
    modal: usize,
    node: usize,
    /// Speed offset of the modal body.
    pub body_col: usize,
    /// Velocity map `N` (6 x (6 + n)).
    pub map: DMatrix<f64>,
    /// `W = d(N y)/dx` (6 x (6 + n)); filled only for Newton-matrix assembly.
    pub w: DMatrix<f64>,
    /// Kinematics of the node frame (speed columns past `n_v`).
    pub kin: BodyKin,
}

/// Velocity map `N` of node `node` at rotation `rot` and modal coordinates `a`.
fn node_map(m: &ModalTerms, node: usize, rot: &Mat3, a: &DVector<f64>) -> DMatrix<f64> {
    let n = a.len();
    let phi = &m.data.translational_shapes()[node];
    let psi = &m.data.rotational_shapes()[node];
    let u = m.data.positions()[node] + phi * a;
    let theta: Vec3 = psi * a;
    let e = rotation(&theta);
    let mut map = DMatrix::zeros(6, 6 + n);
    map.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&Mat3::identity());
    map.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(-rot * skew(&u)));
    map.view_mut((0, 6), (3, n)).copy_from(&(rot * phi));
    map.fixed_view_mut::<3, 3>(3, 3).copy_from(&e.transpose());
    map.view_mut((3, 6), (3, n))
        .copy_from(&(right_jacobian(&theta) * psi));
    map
}

/// Node bodies of `model` (`modal_of`: index into the modal terms of each body).
pub(crate) fn node_body_terms(
    model: &Model,
    modal: &[ModalTerms],
    modal_of: &[Option<usize>],
) -> Vec<NodeBodyTerms> {
    model
        .node_bodies
        .iter()
        .enumerate()
        .filter_map(|(j, nb): (usize, &NodeBody)| {
            let mi = modal_of.get(nb.body.index()?).copied().flatten()?;
            let n = modal[mi].a.len();
            Some(NodeBodyTerms {
                modal: mi,
                node: nb.node,
                body_col: modal[mi].col,
                map: DMatrix::zeros(6, 6 + n),
                w: DMatrix::zeros(6, 6 + n),
                kin: BodyKin {
                    col: model.n_v + 6 * j,
                    ..BodyKin::GROUND
                },
            })
        })
        .collect()
}

impl NodeBodyTerms {
    /// Recomputes the node frame and `N` from the modal body's cached state.
    pub fn update(&mut self, modal: &[ModalTerms]) {
        let m = &modal[self.modal];
        let phi = &m.data.translational_shapes()[self.node];
        let psi = &m.data.rotational_shapes()[self.node];
        let u = m.data.positions()[self.node] + phi * &m.a;
        let theta: Vec3 = psi * &m.a;
        let e = rotation(&theta);
        self.map = node_map(m, self.node, &m.rot, &m.a);
        self.kin.r = m.r + m.rot * u;
        self.kin.rot = m.rot * e;
        self.kin.v = m.v + m.rot * (m.omega.cross(&u) + phi * &m.a_dot);
        self.kin.omega = e.transpose() * m.omega + right_jacobian(&theta) * (psi * &m.a_dot);
        self.kin.rotational = true;
    }

    /// Tangent derivative of `g(N)` over the modal body's increments (rotation, modal), by
    /// central differences of `N`; column `c` of the result is `d g / dx_c` (translation: 0).
    fn map_derivative(
        &self,
        modal: &[ModalTerms],
        rows: usize,
        g: impl Fn(&DMatrix<f64>) -> DVector<f64>,
    ) -> DMatrix<f64> {
        let m = &modal[self.modal];
        let n = m.a.len();
        let mut out = DMatrix::zeros(rows, 6 + n);
        for c in 3..6 + n {
            let (np, nm, eps) = if c < 6 {
                let eps = 1e-6;
                let e = Vec3::ith(c - 3, eps);
                let rp = m.rot * rotation(&e);
                let rm = m.rot * rotation(&-e);
                (
                    node_map(m, self.node, &rp, &m.a),
                    node_map(m, self.node, &rm, &m.a),
                    eps,
                )
            } else {
                let eps = 1e-6 * (1.0 + m.a.amax());
                let (mut ap, mut am) = (m.a.clone(), m.a.clone());
                ap[c - 6] += eps;
                am[c - 6] -= eps;
                (
                    node_map(m, self.node, &m.rot, &ap),
                    node_map(m, self.node, &m.rot, &am),
                    eps,
                )
            };
            let d = (g(&np) - g(&nm)) / (2.0 * eps);
            out.column_mut(c).copy_from(&d);
        }
        out
    }

    /// Fills `W = d(N y)/dx` for the Newton matrix.
    pub fn update_w(&mut self, modal: &[ModalTerms], v: &[f64]) {
        let nv = self.map.ncols();
        let y = DVector::from_column_slice(&v[self.body_col..self.body_col + nv]);
        self.w = self.map_derivative(modal, 6, |map| map * &y);
    }

    /// Geometric term `-d(N^T f_n)/dx` at fixed node force `f_n` ((6 + n) square).
    pub fn geometric(&self, modal: &[ModalTerms], f_n: &[f64]) -> DMatrix<f64> {
        let f = DVector::from_column_slice(f_n);
        -self.map_derivative(modal, self.map.ncols(), |map| map.transpose() * &f)
    }

    /// Adds `N^T f_n` to the modal body's rows of `f`.
    pub fn add_mapped_force(&self, f_n: &[f64], f: &mut [f64]) {
        for c in 0..self.map.ncols() {
            let s: f64 = f_n
                .iter()
                .enumerate()
                .map(|(r, x)| self.map[(r, c)] * x)
                .sum();
            f[self.body_col + c] += s;
        }
    }
}

/// One side of a Jacobian block after mapping: speed offset, size, and the node map if any.
pub(crate) struct MappedSide<'a> {
    pub col: usize,
    pub size: usize,
    pub node: Option<&'a NodeBodyTerms>,
}

/// An effect's `K`, `D` block (used `nr` x `nc` part) and the factors `ck`, `cd`.
pub(crate) struct EffectBlock<'a> {
    pub nr: usize,
    pub nc: usize,
    pub k: &'a Matrix6<f64>,
    pub d: &'a Matrix6<f64>,
    pub ck: f64,
    pub cd: f64,
}

/// The mapped block `R (ck K + cd D) C (+ ck R D W_col)` for a block between `row` and `col`
/// (see the module doc), as a dense matrix of the mapped sizes.
pub(crate) fn mapped_block(row: &MappedSide, col: &MappedSide, b: &EffectBlock) -> DMatrix<f64> {
    let (nr, nc, k, d, ck, cd) = (b.nr, b.nc, b.k, b.d, b.ck, b.cd);
    let a = DMatrix::from_fn(nr, nc, |r, c| ck * k[(r, c)] + cd * d[(r, c)]);
    let dd = DMatrix::from_fn(nr, nc, |r, c| d[(r, c)]);
    let left = |x: DMatrix<f64>| match row.node {
        Some(nb) => nb.map.transpose() * x,
        None => x,
    };
    match col.node {
        Some(nb) => left(a * &nb.map + ck * dd * &nb.w),
        None => left(a),
    }
}
