//! Small fixed-size math over `nalgebra`, all in double precision.
//!
//! Rotations are unit quaternions (Euler parameters) updated on the Lie group: an increment is a
//! rotation vector `theta` [rad] in the *body* frame, `R_new = R exp(theta~)`.

pub use nalgebra::{Matrix3, Matrix6, UnitQuaternion, Vector3, Vector6};

/// 3-vector [m, m/s, N, ...] depending on context.
pub type Vec3 = Vector3<f64>;
/// 3x3 matrix (rotation, inertia [kg m^2], skew).
pub type Mat3 = Matrix3<f64>;
/// Unit quaternion: orientation of a body frame relative to the world frame.
pub type Quat = UnitQuaternion<f64>;

/// Skew-symmetric matrix `a~` with `a~ b = a x b`.
#[inline]
pub fn skew(a: &Vec3) -> Mat3 {
    Mat3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Exponential map: the rotation by the rotation vector `theta` [rad].
#[inline]
pub fn exp_so3(theta: &Vec3) -> Quat {
    Quat::from_scaled_axis(*theta)
}

/// Logarithm map: the rotation vector [rad] (|theta| <= pi) of `q`.
#[inline]
pub fn log_so3(q: &Quat) -> Vec3 {
    q.scaled_axis()
}

/// Inverse of the right-trivialized tangent of `exp`: with `R(t) = R0 exp(x(t)~)` and body angular
/// velocity `omega`, the rotation vector moves as `x_dot = dexp_inv(x) omega`.
pub fn dexp_inv(x: &Vec3, omega: &Vec3) -> Vec3 {
    let th2 = x.norm_squared();
    let xo = x.cross(omega);
    let xxo = x.cross(&xo);
    // coefficient (1 - (th/2) cot(th/2)) / th^2, with its series for small angles.
    let c = if th2 < 1e-6 {
        1.0 / 12.0 + th2 / 720.0 + th2 * th2 / 30240.0
    } else {
        let th = th2.sqrt();
        (1.0 - 0.5 * th / (0.5 * th).tan()) / th2
    };
    omega + 0.5 * xo + c * xxo
}

/// Weighted root-mean-square norm `sqrt(mean((x_i / w_i)^2))`.
pub fn wrms(x: &[f64], w: &[f64]) -> f64 {
    debug_assert_eq!(x.len(), w.len());
    if x.is_empty() {
        return 0.0;
    }
    let s: f64 = x.iter().zip(w).map(|(a, b)| (a / b) * (a / b)).sum();
    (s / x.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dexp_inv_matches_finite_difference_of_log() {
        let x = Vec3::new(0.3, -0.7, 1.1);
        let omega = Vec3::new(-0.4, 0.9, 0.25);
        let h = 1e-6;
        let r0 = exp_so3(&x);
        let xp = log_so3(&(r0 * exp_so3(&(omega * h))));
        let xm = log_so3(&(r0 * exp_so3(&(-omega * h))));
        let fd = (xp - xm) / (2.0 * h);
        assert!((fd - dexp_inv(&x, &omega)).norm() < 1e-8);
    }

    #[test]
    fn skew_is_cross_product() {
        let a = Vec3::new(1.0, 2.0, 3.0);
        let b = Vec3::new(-2.0, 0.5, 4.0);
        assert!((skew(&a) * b - a.cross(&b)).norm() < 1e-15);
    }
}
