//! Model reduction of an assembled FE model: free-interface normal modes and Craig-Bampton.
//!
//! Both return a [`ReducedModel`]: a basis `T` (full DOF vectors as columns) with
//! `u_full = T q`, and the reduced matrices `M_r = T^T M T`, `K_r = T^T K T`, `D_r`.
//!
//! - **Free-interface**: `q` are modal coordinates of the first `n` eigenmodes of the structure
//!   (with its fixed DOFs, often none). Rigid-body modes (`omega^2 <= 1e-12 omega^2_max`) are
//!   excluded or kept and flagged, see [`RigidModes`]. `M_r = I`, `K_r = diag(omega^2)`.
//! - **Craig-Bampton**: `q = [u_b; eta]`, the physical interface DOFs `u_b` (attachment nodes)
//!   with their constraint modes `Psi_ib = -K_ii^-1 K_ib` (static shapes for a unit interface
//!   displacement), plus `eta`, the first `n` fixed-interface modes (interface clamped,
//!   mass-normalized). `M_r` is full, `K_r = blockdiag(K_bb - K_bi K_ii^-1 K_ib, diag(omega^2))`.
//!
//! Damping ([`modal_damping`]): the reduced pair (`K_r`, `M_r`) is decomposed,
//! `K_r X = M_r X Omega^2`, `X^T M_r X = I`, and `D_r = M_r X diag(2 zeta omega_i) X^T M_r`:
//! every mode of the reduced system gets the damping ratio `zeta` exactly, rigid modes none.
//! When joints later constrain the reduced body, the damping is no longer exactly modal for
//! the constrained system, but stays close to `zeta` per mode.

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use nalgebra::DMatrix;

use super::eigen::{check_pair, free_dofs, reduced_eigen, solve_generalized};
use super::error::{FlexError, check_non_negative, invalid};

/// Relative threshold under which an eigenvalue counts as a rigid-body mode:
/// `omega^2 <= RIGID_TOL * omega^2_max`.
pub const RIGID_TOL: f64 = 1e-12;

/// What to do with rigid-body modes in a free-interface reduction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigidModes {
    /// Leave them out (a floating-frame body carries rigid motion in its reference frame).
    Exclude,
    /// Keep them as the first coordinates, flagged [`ReducedCoordinate::RigidMode`].
    Keep,
}

/// Meaning of one reduced coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ReducedCoordinate {
    /// A rigid-body mode of the unconstrained structure (free-interface, [`RigidModes::Keep`]).
    RigidMode,
    /// A normal mode (free- or fixed-interface) of circular frequency `omega` [rad/s],
    /// mass-normalized.
    Mode {
        /// Circular frequency [rad/s].
        omega: f64,
    },
    /// A physical interface DOF of the full model (Craig-Bampton boundary coordinate), in that
    /// DOF's unit ([m] or [rad]).
    Interface {
        /// Index of the DOF in the full model.
        dof: usize,
    },
}

/// A reduced model `u_full = T q`.
#[derive(Debug, Clone)]
pub struct ReducedModel {
    /// Basis `T`, `n_full x n_q`; fixed DOFs are zero rows.
    pub basis: DMatrix<f64>,
    /// Reduced mass `T^T M T`, `n_q x n_q`.
    pub mass: DMatrix<f64>,
    /// Reduced stiffness `T^T K T`, `n_q x n_q`.
    pub stiffness: DMatrix<f64>,
    /// Reduced damping (see the module doc), `n_q x n_q`.
    pub damping: DMatrix<f64>,
    /// Meaning of each coordinate, length `n_q`.
    pub coordinates: Vec<ReducedCoordinate>,
    /// Number of rigid-body modes found (excluded or kept).
    pub n_rigid: usize,
}

fn check_zeta(zeta: f64) -> Result<(), FlexError> {
    check_non_negative("modal damping ratio zeta [-]", zeta)
}

/// Free-interface normal modes: the first `n_modes` elastic modes of (`k`, `m`) with `fixed`
/// DOFs clamped, rigid-body modes handled per `rigid`, modal damping ratio `zeta`.
pub fn free_interface(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    fixed: &[usize],
    n_modes: usize,
    rigid: RigidModes,
    zeta: f64,
) -> Result<ReducedModel, FlexError> {
    check_zeta(zeta)?;
    check_pair(k, m)?;
    let free = free_dofs(k.nrows(), fixed)?;
    let nf = free.len();
    let kf = Mat::from_fn(nf, nf, |i, j| k[(free[i], free[j])]);
    let mf = Mat::from_fn(nf, nf, |i, j| m[(free[i], free[j])]);
    let (omega2, y) = reduced_eigen(&kf, &mf)?;
    let lmax = omega2.last().copied().unwrap_or(0.0).abs();
    let n_rigid = omega2
        .iter()
        .take_while(|&&l| l <= RIGID_TOL * lmax)
        .count();
    if n_rigid + n_modes > nf {
        return invalid(format!(
            "requested {n_modes} elastic modes but the model has only {} ({nf} free DOFs, \
             {n_rigid} rigid-body modes)",
            nf - n_rigid
        ));
    }
    let first = match rigid {
        RigidModes::Exclude => n_rigid,
        RigidModes::Keep => 0,
    };
    let cols: Vec<usize> = (first..n_rigid + n_modes).collect();
    let mut basis = DMatrix::zeros(k.nrows(), cols.len());
    let mut coordinates = Vec::with_capacity(cols.len());
    for (c, &e) in cols.iter().enumerate() {
        for (i, &d) in free.iter().enumerate() {
            basis[(d, c)] = y[(i, e)];
        }
        coordinates.push(if e < n_rigid {
            ReducedCoordinate::RigidMode
        } else {
            ReducedCoordinate::Mode {
                omega: omega2[e].max(0.0).sqrt(),
            }
        });
    }
    finish(k, m, basis, coordinates, n_rigid, zeta)
}

/// Craig-Bampton reduction: interface DOFs `interface` (kept as physical coordinates, in the
/// given order) plus the first `n_modes` fixed-interface modes; `fixed` DOFs are clamped and
/// removed. Errors: DOFs out of range, repeated, or both fixed and interface; more modes than
/// interior DOFs; an interface that does not restrain the structure (singular `K_ii`).
pub fn craig_bampton(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    fixed: &[usize],
    interface: &[usize],
    n_modes: usize,
    zeta: f64,
) -> Result<ReducedModel, FlexError> {
    check_zeta(zeta)?;
    check_pair(k, m)?;
    let n = k.nrows();
    let mut all = fixed.to_vec();
    for &d in interface {
        if fixed.contains(&d) {
            return invalid(format!("DOF {d} is both fixed and an interface DOF"));
        }
        all.push(d);
    }
    if interface.is_empty() {
        return invalid("Craig-Bampton needs at least one interface DOF");
    }
    let interior = free_dofs(n, &all)?;
    let ni = interior.len();
    let nb = interface.len();
    if n_modes > ni {
        return invalid(format!(
            "requested {n_modes} fixed-interface modes but only {ni} interior DOFs exist"
        ));
    }
    // Constraint modes Psi_ib = -K_ii^-1 K_ib.
    let kii = Mat::from_fn(ni, ni, |i, j| k[(interior[i], interior[j])]);
    let kib = Mat::from_fn(ni, nb, |i, j| k[(interior[i], interface[j])]);
    let llt = kii.llt(Side::Lower).map_err(|_| {
        FlexError::Numerical(
            "interface and fixed DOFs do not restrain the structure's rigid-body motion \
             (interior stiffness K_ii is singular)"
                .into(),
        )
    })?;
    let psi = -llt.solve(&kib);
    let mut basis = DMatrix::zeros(n, nb + n_modes);
    let mut coordinates = Vec::with_capacity(nb + n_modes);
    for (c, &d) in interface.iter().enumerate() {
        basis[(d, c)] = 1.0;
        for (i, &di) in interior.iter().enumerate() {
            basis[(di, c)] = psi[(i, c)];
        }
        coordinates.push(ReducedCoordinate::Interface { dof: d });
    }
    if n_modes > 0 {
        let sol = solve_generalized(k, m, &all, n_modes)?;
        for c in 0..n_modes {
            basis.set_column(nb + c, &sol.modes.column(c));
            coordinates.push(ReducedCoordinate::Mode {
                omega: sol.omega2[c].max(0.0).sqrt(),
            });
        }
    }
    finish(k, m, basis, coordinates, 0, zeta)
}

/// Projects K and M on `basis` and adds modal damping.
fn finish(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    basis: DMatrix<f64>,
    coordinates: Vec<ReducedCoordinate>,
    n_rigid: usize,
    zeta: f64,
) -> Result<ReducedModel, FlexError> {
    let mass = symmetrize(basis.transpose() * (m * &basis));
    let stiffness = symmetrize(basis.transpose() * (k * &basis));
    let damping = modal_damping(&stiffness, &mass, zeta)?;
    Ok(ReducedModel {
        basis,
        mass,
        stiffness,
        damping,
        coordinates,
        n_rigid,
    })
}

/// `(a + a^T) / 2`.
pub(crate) fn symmetrize(a: DMatrix<f64>) -> DMatrix<f64> {
    0.5 * (&a + a.transpose())
}

/// Damping matrix giving every mode of the pair (`k`, `m`) the damping ratio `zeta` [-]:
/// `D = M X diag(2 zeta omega_i) X^T M` with `K X = M X Omega^2`, `X^T M X = I`.
pub fn modal_damping(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    zeta: f64,
) -> Result<DMatrix<f64>, FlexError> {
    check_zeta(zeta)?;
    check_pair(k, m)?;
    let n = k.nrows();
    if n == 0 || zeta == 0.0 {
        return Ok(DMatrix::zeros(n, n));
    }
    let (omega2, x) = reduced_eigen(&super::eigen::to_faer(k), &super::eigen::to_faer(m))?;
    let x = super::eigen::to_nalgebra(x.as_ref());
    let mx = m * &x;
    let mut scaled = mx.clone();
    let lmax = omega2.last().copied().unwrap_or(0.0).abs();
    for (c, &l) in omega2.iter().enumerate() {
        let w = if l <= RIGID_TOL * lmax { 0.0 } else { l.sqrt() };
        scaled.column_mut(c).scale_mut(2.0 * zeta * w);
    }
    Ok(symmetrize(scaled * mx.transpose()))
}

/// Natural frequencies [Hz] of the reduced pair (`k`, `m`), ascending (rigid modes give ~0).
pub fn frequencies_hz(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Result<Vec<f64>, FlexError> {
    let sol = super::eigen::generalized_eigenvalues(k, m, &[], k.nrows())?;
    Ok(sol
        .iter()
        .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect())
}
