//! Scatters forces acting at body points, and their derivatives, into generalized forces and
//! Jacobian blocks.
//!
//! Points `a` sit at body-frame offsets `s_a` [m] on bodies (particles have `s = 0`, a hook is a
//! point of the ground). Given the world forces `F_a` [N] on the points and their derivatives
//! `J_ab = dF_a/dp_b` [N/m] and `C_ab = dF_a/dp_dot_b` [N s/m], with `P = [I, -R s~]` and
//! `Q = [0, -R (omega x s)~]` as in [`crate::effect::point_force`]:
//!
//! - generalized force on the body of `a`: `P_a^T F_a`;
//! - `K(body a, body b) = -P_a^T (J_ab P_b + C_ab Q_b)`, plus `-s_a~ (R^T F_a)~` on the rotation
//!   block of `(a, a)` (the force turning with the body);
//! - `D(body a, body b) = -P_a^T C_ab P_b`.
//!
//! For points without rotation this reduces to `K = -J`, `D = -C` in the translation block.

use crate::effect::JacobianSink;
use crate::math::{Mat3, Matrix6, Vec3, Vector6, skew};
use crate::model::kinematics::BodyKin;

/// A point of a body at one instant.
#[derive(Debug, Clone, Copy)]
pub struct PointRef<'a> {
    /// Kinematics of the body carrying the point ([`BodyKin::GROUND`] for a prescribed point).
    pub kin: &'a BodyKin,
    /// Offset of the point in the body frame [m].
    pub s: Vec3,
}

impl PointRef<'_> {
    /// `-R s~` (world displacement per body-frame rotation increment), only for rotating bodies.
    #[inline]
    fn rot_jac(&self) -> Mat3 {
        self.kin.point_rot_jacobian(&self.s)
    }

    /// `-R (omega x s)~`.
    #[inline]
    fn rate_jac(&self) -> Mat3 {
        -self.kin.rot * skew(&self.kin.omega.cross(&self.s))
    }
}

/// Adds the world force `force` [N] at point `p` to the generalized forces `f`.
#[inline]
pub fn add_force(p: &PointRef, force: &Vec3, f: &mut [f64]) {
    crate::effect::point_force::add_point_force(p.kin, &p.s, force, f);
}

/// `P^T v` for a world vector `v` at point `p`: `v` on the translations, `(-R s~)^T v` on the
/// rotations of a rotating body (their entries unused otherwise).
pub fn generalized(p: &PointRef, v: &Vec3) -> Vector6<f64> {
    let mut out = Vector6::zeros();
    out.fixed_rows_mut::<3>(0).copy_from(v);
    if p.kin.rotational {
        out.fixed_rows_mut::<3>(3)
            .copy_from(&(p.rot_jac().transpose() * v));
    }
    out
}

/// Emits the K/D block for the pair of points `(a, b)` from `J_ab`, `C_ab`; `force_a` is the
/// force on `a` when `a == b` (the geometric term), else `None`.
pub fn add_pair(
    a: &PointRef,
    b: &PointRef,
    j: &Mat3,
    c: &Mat3,
    force_a: Option<&Vec3>,
    sink: &mut dyn JacobianSink,
) {
    let mut k = Matrix6::zeros();
    let mut d = Matrix6::zeros();
    // translation rows of a, translation columns of b: -J, -C
    k.fixed_view_mut::<3, 3>(0, 0).copy_from(&(-j));
    d.fixed_view_mut::<3, 3>(0, 0).copy_from(&(-c));
    if b.kin.rotational {
        let pb = b.rot_jac();
        let qb = b.rate_jac();
        k.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-(j * pb + c * qb)));
        d.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-(c * pb)));
    }
    if a.kin.rotational {
        let pat = a.rot_jac().transpose();
        let top_k: Mat3 = k.fixed_view::<3, 3>(0, 0).into();
        let top_d: Mat3 = d.fixed_view::<3, 3>(0, 0).into();
        k.fixed_view_mut::<3, 3>(3, 0).copy_from(&(pat * top_k));
        d.fixed_view_mut::<3, 3>(3, 0).copy_from(&(pat * top_d));
        if b.kin.rotational {
            let tr_k: Mat3 = k.fixed_view::<3, 3>(0, 3).into();
            let tr_d: Mat3 = d.fixed_view::<3, 3>(0, 3).into();
            let mut rr = pat * tr_k;
            if let Some(fa) = force_a {
                rr -= skew(&a.s) * skew(&(a.kin.rot.transpose() * fa));
            }
            k.fixed_view_mut::<3, 3>(3, 3).copy_from(&rr);
            d.fixed_view_mut::<3, 3>(3, 3).copy_from(&(pat * tr_d));
        }
    }
    sink.add(a.kin, b.kin, &k, &d);
}
