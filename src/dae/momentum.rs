//! Total mass, centre of mass, linear and angular momentum of a system's bodies.
//!
//! Each body's generalized momentum is its block of `M v` (speeds `[v (world); omega (body);
//! a_dot]`): the first three rows are its linear momentum `L` (world frame), the next three its
//! angular momentum about its frame origin `H_O` in its body frame (for a rigid body the origin
//! is the centre of mass and `H_O = I omega`; for a modal body `H_O = S(a) x A^T v + J(a) omega
//! + C_r(a) a_dot`, [`crate::flex::invariants`]). Summed about the world origin,
//! `H_0 = sum (r_O x L + A H_O)`, and moved to the system's centre of mass `c`:
//! `H_c = H_0 - c x L_total`.

use super::System;
use crate::math::Vec3;
use crate::model::BodyKind;
use nalgebra::DVector;

/// Mass properties and momentum of all bodies at one instant (world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Momentum {
    /// Total mass [kg].
    pub mass: f64,
    /// Centre of mass [m].
    pub centre_of_mass: Vec3,
    /// Linear momentum [kg m/s].
    pub linear: Vec3,
    /// Angular momentum about the centre of mass [kg m^2/s].
    pub angular: Vec3,
}

impl System {
    /// [`Momentum`] of the bodies at `(q, v)` (the ground and the massless node bodies carry
    /// none).
    pub fn momentum(&mut self, q: &[f64], v: &[f64]) -> Momentum {
        self.update_kinematics(q, v);
        let mut mv = vec![0.0; v.len()];
        self.mass_mul(v, &mut mv);
        let (mut mass, mut first, mut linear, mut angular) =
            (0.0, Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
        for (b, k) in self.model.bodies.iter().zip(&self.kins) {
            let o = b.v_offset;
            let l = Vec3::new(mv[o], mv[o + 1], mv[o + 2]);
            let (m, centre) = match &b.kind {
                BodyKind::Rigid { mass, .. } | BodyKind::Particle { mass } => (*mass, k.r),
                BodyKind::Modal { data } => {
                    let n = data.n_modes();
                    let qa = b.q_offset + 7;
                    let a = DVector::from_column_slice(&q[qa..qa + n]);
                    let inv = data.invariants();
                    (inv.mass, k.r + k.rot * inv.first_moment_at(&a) / inv.mass)
                }
            };
            mass += m;
            first += m * centre;
            linear += l;
            angular += k.r.cross(&l);
            if b.kind.has_rotation() {
                angular += k.rot * Vec3::new(mv[o + 3], mv[o + 4], mv[o + 5]);
            }
        }
        let centre_of_mass = first / mass;
        Momentum {
            mass,
            centre_of_mass,
            linear,
            angular: angular - centre_of_mass.cross(&linear),
        }
    }
}
