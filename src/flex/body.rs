//! [`ModalBodyData`]: everything a floating-frame-of-reference body needs from a reduced panel.
//!
//! Frames and units: all vectors are in the panel's body frame (origin at the panel corner, x
//! along side a, y along side b, z normal, see [`super::plate`]), SI units. The modal
//! coordinates `a` (length n) are the reduced coordinates of [`super::reduce`]:
//!
//! - [`ModalBodyData::from_free_interface`]: the first n elastic free-free modes (rigid modes
//!   excluded). Being mass-orthogonal to the rigid modes they satisfy the mean-axis conditions
//!   `C_t = 0`, `C_r = 0` at first order.
//! - [`ModalBodyData::from_craig_bampton`]: the body frame is clamped to the panel at a
//!   *frame node* (its w, theta_x, theta_y are zero in every shape, which removes the rigid
//!   bending motion); the coordinates are the DOFs of the other attachment nodes (constraint
//!   modes) plus n fixed-interface modes.
//!
//! Mass model (a deliberate choice): the FE model uses the consistent mass, and the stored
//! [`Invariants`] are computed from it, so they are exact integrals over the mid-surface of the
//! areal mass: `m = 1^T M 1`, `S`, `J0` from the rigid fields x, y, `C_t`, `Q_j` as
//! `field^T M T_j` and `P_ij = T_i^T M T_j` (z-z entry), with `T` the reduced basis. The
//! modal mass block is then exactly the reduced mass. The multibody side should use these
//! invariants (via [`Invariants::mass_matrix`] etc.) and *not* attach point masses. The
//! per-node tributary masses [`ModalBodyData::node_masses`] are kept for users who want a
//! point-mass picture (and for the text format): their node sums
//! ([`ModalBodyData::node_sum_invariants`]) converge to the consistent invariants as O(h^2).
//! Rotary inertia through the thickness (order t^2/12 against a^2/12) is neglected.
//!
//! Node motion (for joints and contacts at attachment nodes): body-frame position
//! `rho_k + Phi_k a`, small rotation `Psi_k a` relative to the body frame, world velocity
//! `B_k y` with `B_k = [I, -A u_k~, A Phi_k]`, body-frame angular velocity `omega + Psi_k a_dot`,
//! accelerations `B_k y_dot + w_k` and `A (G_k y_dot + omega~ Psi_k a_dot)` (see
//! [`ModalBodyData::node_acceleration_bias`]).
//! Elastic forces on the modal rows: `-(K a + D a_dot)`.

use faer::Side;
use nalgebra::{DMatrix, DVector, Matrix3xX};

use super::eigen::{check_pair, to_faer};
use super::error::{FlexError, invalid};
use super::invariants::Invariants;
use super::plate::PlateModel;
use super::reduce::{ReducedModel, RigidModes, craig_bampton, free_interface, frequencies_hz};
use crate::math::{Mat3, Vec3, skew};

/// Reduced flexible body in a floating frame (see the module doc for frames and formulas).
#[derive(Debug, Clone, PartialEq)]
pub struct ModalBodyData {
    positions: Vec<Vec3>,
    node_masses: Vec<f64>,
    translational_shapes: Vec<Matrix3xX<f64>>,
    rotational_shapes: Vec<Matrix3xX<f64>>,
    stiffness: DMatrix<f64>,
    damping: DMatrix<f64>,
    attachment_nodes: Vec<usize>,
    invariants: Invariants,
}

/// Node data and reduced matrices given to [`ModalBodyData::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct ModalBodyParts {
    /// Undeformed node positions `rho_k` [m], body frame.
    pub positions: Vec<Vec3>,
    /// Node masses [kg] (point-mass picture, >= 0).
    pub node_masses: Vec<f64>,
    /// Translational shapes `Phi_k`, 3 x n per node [m per unit of a].
    pub translational_shapes: Vec<Matrix3xX<f64>>,
    /// Rotational shapes `Psi_k`, 3 x n per node [rad per unit of a].
    pub rotational_shapes: Vec<Matrix3xX<f64>>,
    /// Reduced mass `M_aa`, n x n, symmetric positive definite.
    pub mass: DMatrix<f64>,
    /// Reduced stiffness `K_aa`, n x n, symmetric.
    pub stiffness: DMatrix<f64>,
    /// Reduced damping `D_aa`, n x n, symmetric.
    pub damping: DMatrix<f64>,
    /// Indices of the attachment (hinge, latch) nodes.
    pub attachment_nodes: Vec<usize>,
    /// Exact invariants if known (their modal mass must equal `mass`); `None` computes them from
    /// the node sums, and then `mass` must equal `sum m_k Phi_k^T Phi_k` (to 1e-6 relative) so
    /// that the floating-frame mass matrix is a true point-mass sum.
    pub invariants: Option<Invariants>,
}

impl ModalBodyData {
    /// Validating constructor. Errors: no nodes, inconsistent counts or shape sizes, non-finite
    /// values, attachment node out of range or repeated, matrices not n x n or not symmetric,
    /// `M_aa` not positive definite, invariants inconsistent with `M_aa`, or a floating-frame
    /// mass matrix `M(0)` that is not positive definite (coordinates duplicating rigid motion).
    pub fn new(parts: ModalBodyParts) -> Result<Self, FlexError> {
        let nn = parts.positions.len();
        if nn == 0 {
            return invalid("a modal body needs at least one node");
        }
        if parts.rotational_shapes.len() != nn {
            return invalid(format!(
                "{} rotational shape blocks for {nn} nodes",
                parts.rotational_shapes.len()
            ));
        }
        let n = parts.mass.nrows();
        for (k, r) in parts.rotational_shapes.iter().enumerate() {
            if r.ncols() != n || !r.iter().all(|x| x.is_finite()) {
                return invalid(format!(
                    "node {k}: rotational shape must be 3 x {n} and finite"
                ));
            }
        }
        for (k, t) in parts.translational_shapes.iter().enumerate() {
            if t.ncols() != n {
                return invalid(format!(
                    "node {k}: translational shape has {} columns, expected {n}",
                    t.ncols()
                ));
            }
        }
        let mut seen = vec![false; nn];
        for &a in &parts.attachment_nodes {
            if a >= nn {
                return invalid(format!(
                    "attachment node {a} out of range (body has {nn} nodes)"
                ));
            }
            if seen[a] {
                return invalid(format!("attachment node {a} listed twice"));
            }
            seen[a] = true;
        }
        check_pair(&parts.stiffness, &parts.mass)?;
        check_pair(&parts.damping, &parts.mass)?;
        if n > 0 && to_faer(&parts.mass).llt(Side::Lower).is_err() {
            return invalid("reduced mass matrix M_aa is not positive definite");
        }
        // Node sums also validate positions, masses and translational shapes.
        let node_inv = Invariants::from_nodes(
            &parts.node_masses,
            &parts.positions,
            &parts.translational_shapes,
        )?;
        let mut inv = match parts.invariants {
            Some(inv) => {
                if inv.n_modes() != n || inv.modal_mass.shape() != (n, n) {
                    return invalid(format!(
                        "invariants have {} modes, reduced matrices {n}",
                        inv.n_modes()
                    ));
                }
                let scale = parts.mass.amax().max(f64::MIN_POSITIVE);
                if (&inv.modal_mass - &parts.mass).amax() > 1e-9 * scale {
                    return invalid("invariants' modal mass differs from the reduced mass M_aa");
                }
                inv
            }
            None => {
                // Point-mass picture: M(a) = sum m_k B_k^T B_k is positive semi-definite only
                // if the modal block is the node sum too, so M_aa must agree with it.
                let scale = parts.mass.amax().max(f64::MIN_POSITIVE);
                let diff = (&node_inv.modal_mass - &parts.mass).amax();
                if diff > 1e-6 * scale {
                    return invalid(format!(
                        "reduced mass M_aa differs from the node sums sum m_k Phi_k^T Phi_k by \
                         {diff:e} (max entry {scale:e}): give exact invariants (consistent \
                         mass) or node masses consistent with the modes"
                    ));
                }
                node_inv
            }
        };
        // The given reduced mass is the modal-mass block of the floating-frame equations.
        inv.modal_mass = parts.mass.clone();
        inv.validate()?;
        let m0 = inv.mass_matrix(&Mat3::identity(), &DVector::zeros(n))?;
        if to_faer(&m0).llt(Side::Lower).is_err() {
            return invalid(
                "floating-frame mass matrix M(0) is not positive definite: the modal \
                 coordinates duplicate a rigid-body motion of the frame (exclude rigid modes or \
                 clamp the frame at a node)",
            );
        }
        Ok(Self {
            positions: parts.positions,
            node_masses: parts.node_masses,
            translational_shapes: parts.translational_shapes,
            rotational_shapes: parts.rotational_shapes,
            stiffness: parts.stiffness,
            damping: parts.damping,
            attachment_nodes: parts.attachment_nodes,
            invariants: inv,
        })
    }

    /// Body of the first `n_modes` elastic free-free modes of `plate` (rigid modes excluded),
    /// modal damping ratio `zeta` [-], recording `attachment_nodes`.
    pub fn from_free_interface(
        plate: &PlateModel,
        n_modes: usize,
        zeta: f64,
        attachment_nodes: &[usize],
    ) -> Result<Self, FlexError> {
        check_nodes(plate, attachment_nodes)?;
        let red = free_interface(
            plate.stiffness(),
            plate.mass(),
            &[],
            n_modes,
            RigidModes::Exclude,
            zeta,
        )?;
        Self::from_reduced(plate, &red, attachment_nodes)
    }

    /// Craig-Bampton body: frame clamped at `frame_node`; coordinates are the 3 DOFs (w,
    /// theta_x, theta_y) of every other node of `attachment_nodes` (in that order) followed by
    /// `n_modes` fixed-interface modes; modal damping ratio `zeta` [-].
    pub fn from_craig_bampton(
        plate: &PlateModel,
        frame_node: usize,
        attachment_nodes: &[usize],
        n_modes: usize,
        zeta: f64,
    ) -> Result<Self, FlexError> {
        check_nodes(plate, attachment_nodes)?;
        let fixed = plate.node_dofs(frame_node)?.to_vec();
        let mut interface = Vec::new();
        for &a in attachment_nodes.iter().filter(|&&a| a != frame_node) {
            interface.extend(plate.node_dofs(a)?);
        }
        let red = if interface.is_empty() {
            free_interface(
                plate.stiffness(),
                plate.mass(),
                &fixed,
                n_modes,
                RigidModes::Exclude,
                zeta,
            )?
        } else {
            craig_bampton(
                plate.stiffness(),
                plate.mass(),
                &fixed,
                &interface,
                n_modes,
                zeta,
            )?
        };
        Self::from_reduced(plate, &red, attachment_nodes)
    }

    /// Body from any reduction of `plate` (basis over the plate's DOFs), with consistent
    /// invariants (module doc).
    pub fn from_reduced(
        plate: &PlateModel,
        red: &ReducedModel,
        attachment_nodes: &[usize],
    ) -> Result<Self, FlexError> {
        check_nodes(plate, attachment_nodes)?;
        let t = &red.basis;
        if t.nrows() != plate.n_dofs() {
            return invalid(format!(
                "reduction basis has {} rows, plate has {} DOFs",
                t.nrows(),
                plate.n_dofs()
            ));
        }
        let n = t.ncols();
        let nn = plate.n_nodes();
        let translational_shapes = (0..nn)
            .map(|k| Matrix3xX::from_fn(n, |r, c| if r == 2 { t[(3 * k, c)] } else { 0.0 }))
            .collect();
        let rotational_shapes = (0..nn)
            .map(|k| Matrix3xX::from_fn(n, |r, c| if r < 2 { t[(3 * k + 1 + r, c)] } else { 0.0 }))
            .collect();
        let invariants = consistent_invariants(plate, t, &red.mass);
        Self::new(ModalBodyParts {
            positions: plate.node_positions(),
            node_masses: plate.lumped_node_masses(),
            translational_shapes,
            rotational_shapes,
            mass: red.mass.clone(),
            stiffness: red.stiffness.clone(),
            damping: red.damping.clone(),
            attachment_nodes: attachment_nodes.to_vec(),
            invariants: Some(invariants),
        })
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.positions.len()
    }

    /// Number of modal coordinates n.
    pub fn n_modes(&self) -> usize {
        self.stiffness.nrows()
    }

    /// Undeformed node positions `rho_k` [m], body frame.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Tributary (point-mass picture) node masses [kg]; see the module doc.
    pub fn node_masses(&self) -> &[f64] {
        &self.node_masses
    }

    /// Translational shapes `Phi_k` (3 x n) of every node [m per unit of a], body frame.
    pub fn translational_shapes(&self) -> &[Matrix3xX<f64>] {
        &self.translational_shapes
    }

    /// Rotational shapes `Psi_k` (3 x n) of every node [rad per unit of a], body frame.
    pub fn rotational_shapes(&self) -> &[Matrix3xX<f64>] {
        &self.rotational_shapes
    }

    /// Reduced mass `M_aa` (n x n).
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.invariants.modal_mass
    }

    /// Reduced stiffness `K_aa` (n x n).
    pub fn stiffness(&self) -> &DMatrix<f64> {
        &self.stiffness
    }

    /// Reduced damping `D_aa` (n x n).
    pub fn damping(&self) -> &DMatrix<f64> {
        &self.damping
    }

    /// Attachment node indices.
    pub fn attachment_nodes(&self) -> &[usize] {
        &self.attachment_nodes
    }

    /// Inertia invariants for the floating-frame equations (exact when built from a plate).
    pub fn invariants(&self) -> &Invariants {
        &self.invariants
    }

    /// Invariants recomputed as point-mass sums over the nodes (`M_ee` from node sums too).
    pub fn node_sum_invariants(&self) -> Result<Invariants, FlexError> {
        Invariants::from_nodes(
            &self.node_masses,
            &self.positions,
            &self.translational_shapes,
        )
    }

    /// Natural frequencies [Hz] of the body with its frame held fixed (eigenvalues of
    /// (`K_aa`, `M_aa`)), ascending.
    pub fn frequencies_hz(&self) -> Result<Vec<f64>, FlexError> {
        frequencies_hz(&self.stiffness, self.mass())
    }

    fn check_node(&self, k: usize) -> Result<(), FlexError> {
        if k >= self.n_nodes() {
            return invalid(format!(
                "node {k} out of range (body has {} nodes)",
                self.n_nodes()
            ));
        }
        Ok(())
    }

    fn check_a(&self, a: &DVector<f64>) -> Result<(), FlexError> {
        if a.len() != self.n_modes() {
            return invalid(format!(
                "modal vector has length {}, body has {} modes",
                a.len(),
                self.n_modes()
            ));
        }
        Ok(())
    }

    /// Deformed body-frame position `rho_k + Phi_k a` [m] of node `k`.
    pub fn node_position(&self, k: usize, a: &DVector<f64>) -> Result<Vec3, FlexError> {
        self.check_node(k)?;
        self.check_a(a)?;
        Ok(self.positions[k] + &self.translational_shapes[k] * a)
    }

    /// Small rotation `Psi_k a` [rad] of node `k` relative to the body frame.
    pub fn node_rotation(&self, k: usize, a: &DVector<f64>) -> Result<Vec3, FlexError> {
        self.check_node(k)?;
        self.check_a(a)?;
        Ok(&self.rotational_shapes[k] * a)
    }

    /// `B_k = [I, -A u_k~, A Phi_k]` (3 x (6 + n)): world velocity of node `k` is `B_k y`;
    /// `rot` = A (body to world). A world force F at the node gives `f = B_k^T F`.
    pub fn node_velocity_jacobian(
        &self,
        k: usize,
        rot: &Mat3,
        a: &DVector<f64>,
    ) -> Result<DMatrix<f64>, FlexError> {
        let u = self.node_position(k, a)?;
        let n = self.n_modes();
        let mut b = DMatrix::zeros(3, 6 + n);
        b.fixed_view_mut::<3, 3>(0, 0).copy_from(&Mat3::identity());
        b.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-rot * skew(&u)));
        b.view_mut((0, 6), (3, n))
            .copy_from(&(rot * &self.translational_shapes[k]));
        Ok(b)
    }

    /// `G_k = [0, I, Psi_k]` (3 x (6 + n)): body-frame angular velocity of node `k`'s material
    /// frame is `G_k y`. A body-frame torque T at the node gives `f = G_k^T T`.
    pub fn node_angular_velocity_jacobian(&self, k: usize) -> Result<DMatrix<f64>, FlexError> {
        self.check_node(k)?;
        let n = self.n_modes();
        let mut g = DMatrix::zeros(3, 6 + n);
        g.fixed_view_mut::<3, 3>(0, 3).copy_from(&Mat3::identity());
        g.view_mut((0, 6), (3, n))
            .copy_from(&self.rotational_shapes[k]);
        Ok(g)
    }

    /// Velocity-dependent part `w_k = A (omega~ omega~ u_k + 2 omega~ Phi_k a_dot)` [m/s^2]
    /// of node `k`'s world acceleration `B_k y_dot + w_k`, with `u_k = rho_k + Phi_k a`,
    /// `omega` [rad/s] in the body frame (for the acceleration-level constraint terms).
    pub fn node_acceleration_bias(
        &self,
        k: usize,
        rot: &Mat3,
        a: &DVector<f64>,
        omega: &Vec3,
        a_dot: &DVector<f64>,
    ) -> Result<Vec3, FlexError> {
        let u = self.node_position(k, a)?;
        self.check_a(a_dot)?;
        let v_el = &self.translational_shapes[k] * a_dot;
        Ok(rot * (omega.cross(&omega.cross(&u)) + 2.0 * omega.cross(&v_el)))
    }

    /// Velocity-dependent part `A (omega~ Psi_k a_dot)` [rad/s^2] of the world angular
    /// acceleration `A G_k y_dot + A (omega~ Psi_k a_dot)` of node `k`'s material frame, whose
    /// world angular velocity is `A (omega + Psi_k a_dot)` (small elastic rotations).
    pub fn node_angular_acceleration_bias(
        &self,
        k: usize,
        rot: &Mat3,
        omega: &Vec3,
        a_dot: &DVector<f64>,
    ) -> Result<Vec3, FlexError> {
        self.check_node(k)?;
        self.check_a(a_dot)?;
        Ok(rot * omega.cross(&(&self.rotational_shapes[k] * a_dot)))
    }

    /// Elastic and damping force on the modal rows `-(K a + D a_dot)`.
    pub fn elastic_force(
        &self,
        a: &DVector<f64>,
        a_dot: &DVector<f64>,
    ) -> Result<DVector<f64>, FlexError> {
        self.check_a(a)?;
        self.check_a(a_dot)?;
        Ok(-(&self.stiffness * a + &self.damping * a_dot))
    }
}

fn check_nodes(plate: &PlateModel, nodes: &[usize]) -> Result<(), FlexError> {
    for &k in nodes {
        plate.node_dofs(k)?;
    }
    Ok(())
}

/// Exact (consistent-mass) invariants of `plate` for the basis `t` with reduced mass `m_r`.
fn consistent_invariants(plate: &PlateModel, t: &DMatrix<f64>, m_r: &DMatrix<f64>) -> Invariants {
    let m = plate.mass();
    let one = plate.linear_field(1.0, 0.0, 0.0);
    let x = plate.linear_field(0.0, 1.0, 0.0);
    let y = plate.linear_field(0.0, 0.0, 1.0);
    let m_one = m * &one;
    let m_x = m * &x;
    let m_y = m * &y;
    let mass = one.dot(&m_one);
    let first_moment = Vec3::new(x.dot(&m_one), y.dot(&m_one), 0.0);
    let rxy = 0.5 * (x.dot(&m_y) + y.dot(&m_x));
    let r = Mat3::new(x.dot(&m_x), rxy, 0.0, rxy, y.dot(&m_y), 0.0, 0.0, 0.0, 0.0);
    let inertia = r.trace() * Mat3::identity() - r;
    let n = t.ncols();
    let ct_z = t.transpose() * &m_one;
    let qx = t.transpose() * &m_x;
    let qy = t.transpose() * &m_y;
    let c_t = Matrix3xX::from_fn(n, |row, j| if row == 2 { ct_z[j] } else { 0.0 });
    let q = (0..n)
        .map(|j| {
            let mut b = Mat3::zeros();
            b[(0, 2)] = qx[j];
            b[(1, 2)] = qy[j];
            b
        })
        .collect();
    let mut p = vec![Mat3::zeros(); n * n];
    for i in 0..n {
        for j in 0..n {
            p[i * n + j][(2, 2)] = m_r[(i, j)];
        }
    }
    Invariants {
        mass,
        first_moment,
        inertia,
        c_t,
        q,
        p,
        modal_mass: m_r.clone(),
    }
}
