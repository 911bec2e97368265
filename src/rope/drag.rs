//! Optional quadratic drag on the rope's material nodes.
//!
//! Node `i` represents a rope length `ell_i` [m] (half of each adjacent nominal segment) and feels
//! `F = -kappa |v| v` with `kappa = 1/2 rho_f C_d d ell_i` [kg/m] (fluid at rest, world frame).
//! This is the isotropic simplification of cross-flow drag (no distinction between normal and
//! tangential flow). `|v|` is regularized as `sqrt(v.v + v0^2)`, `v0 = 1e-6 m/s`, so that the
//! damping matrix stays finite at rest.

use crate::math::{Mat3, Vec3};

/// Regularization speed [m/s].
pub const V0: f64 = 1e-6;

/// Drag force [N] and `dF/dv` [N s/m] for coefficient `kappa` [kg/m] and velocity `v` [m/s].
#[inline]
pub fn drag(kappa: f64, v: &Vec3) -> (Vec3, Mat3) {
    let s = (v.norm_squared() + V0 * V0).sqrt();
    let f = -v * (kappa * s);
    let dfdv = -(Mat3::identity() * s + v * v.transpose() / s) * kappa;
    (f, dfdv)
}
