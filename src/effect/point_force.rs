//! Generalized forces and Jacobians of a force acting between two body points.
//!
//! A force `F` (world frame) acts on point `s_a` of body A and `-F` on point `s_b` of body B. With
//! `P = [I, -R s~]` mapping body speeds to the point velocity and `Q = [0, -R (omega x s)~]` the
//! rotation derivative of that velocity, and `F = F(d, d_dot)` for `d = p_b - p_a`:
//!
//! - `f_A = P_A^T F`, `f_B = -P_B^T F`
//! - `K_AA = P_A^T (Kd P_A + Cd Q_A) - Geo_A(F)`, `K_AB = -P_A^T (Kd P_B + Cd Q_B)`, and the
//!   mirror for B with `-F`; `Geo(F)` has `s~ (R^T F)~` in its rotation block
//! - `D_AA = P_A^T Cd P_A`, `D_AB = -P_A^T Cd P_B`, ...
//!
//! where `Kd = dF/dd`, `Cd = dF/dd_dot`.

use super::JacobianSink;
use crate::math::{Mat3, Matrix6, Vec3, skew};
use crate::model::kinematics::BodyKin;
use nalgebra::SMatrix;

type Mat36 = SMatrix<f64, 3, 6>;

/// `P = [I, -R s~]` for a body point.
fn p_matrix(k: &BodyKin, s: &Vec3) -> Mat36 {
    let mut p = Mat36::zeros();
    p.fixed_view_mut::<3, 3>(0, 0).copy_from(&Mat3::identity());
    if k.rotational {
        p.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&k.point_rot_jacobian(s));
    }
    p
}

/// `Q = [0, -R (omega x s)~]`: derivative of the point velocity w.r.t. the rotation increment.
fn q_matrix(k: &BodyKin, s: &Vec3) -> Mat36 {
    let mut q = Mat36::zeros();
    if k.rotational {
        q.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-k.rot * skew(&k.omega.cross(s))));
    }
    q
}

/// Adds a world force `force` [N] acting at body point `s` [m] (body frame) to `f`.
pub fn add_point_force(k: &BodyKin, s: &Vec3, force: &Vec3, f: &mut [f64]) {
    if !k.is_free() {
        return;
    }
    let c = k.col;
    for i in 0..3 {
        f[c + i] += force[i];
    }
    if k.rotational {
        let tau = s.cross(&(k.rot.transpose() * force));
        for i in 0..3 {
            f[c + 3 + i] += tau[i];
        }
    }
}

/// A two-point force evaluated for scattering: points, force on A, and its derivatives.
pub struct TwoPointForce<'a> {
    pub a: &'a BodyKin,
    pub s_a: Vec3,
    pub b: &'a BodyKin,
    pub s_b: Vec3,
    /// Force on A [N], world frame (B receives `-force`).
    pub force: Vec3,
    /// `dF/dd` [N/m] with `d = p_b - p_a`.
    pub kd: Mat3,
    /// `dF/dd_dot` [N s/m].
    pub cd: Mat3,
}

impl TwoPointForce<'_> {
    /// Adds the generalized forces on both bodies.
    pub fn add_forces(&self, f: &mut [f64]) {
        add_point_force(self.a, &self.s_a, &self.force, f);
        add_point_force(self.b, &self.s_b, &(-self.force), f);
    }

    /// Adds the four K/D blocks (always the same sequence: AA, AB, BA, BB).
    pub fn add_jacobian(&self, sink: &mut dyn JacobianSink) {
        let pa = p_matrix(self.a, &self.s_a);
        let pb = p_matrix(self.b, &self.s_b);
        let qa = q_matrix(self.a, &self.s_a);
        let qb = q_matrix(self.b, &self.s_b);
        let ga = self.kd * pa + self.cd * qa;
        let gb = self.kd * pb + self.cd * qb;
        let geo = |k: &BodyKin, s: &Vec3, force: &Vec3| {
            let mut g = Matrix6::zeros();
            if k.rotational {
                g.fixed_view_mut::<3, 3>(3, 3)
                    .copy_from(&(skew(s) * skew(&(k.rot.transpose() * force))));
            }
            g
        };
        let k_aa = pa.transpose() * ga - geo(self.a, &self.s_a, &self.force);
        let k_ab = -pa.transpose() * gb;
        let k_ba = -pb.transpose() * ga;
        let k_bb = pb.transpose() * gb - geo(self.b, &self.s_b, &(-self.force));
        let d_aa = pa.transpose() * self.cd * pa;
        let d_ab = -pa.transpose() * self.cd * pb;
        let d_ba = -pb.transpose() * self.cd * pa;
        let d_bb = pb.transpose() * self.cd * pb;
        sink.add(self.a, self.a, &k_aa, &d_aa);
        sink.add(self.a, self.b, &k_ab, &d_ab);
        sink.add(self.b, self.a, &k_ba, &d_ba);
        sink.add(self.b, self.b, &k_bb, &d_bb);
    }
}
