//! Coulomb friction of hinge shafts: a torque of magnitude `T_f` [N m] opposing the relative
//! rate `w = theta_dot` [rad/s] of the hinge's two frames (about the z axis of the first, see
//! [`super::angle`]), regularized so that it is smooth and has a Jacobian:
//!
//! `tau = -T_f tanh(w / w_s)`, `d tau / d w = -(T_f / w_s) (1 - tanh^2(w / w_s))`.
//!
//! `w_s` is the slip rate [rad/s]: below it the torque falls linearly to zero, like a viscous
//! damper of `T_f / w_s` [N m s/rad]; above `3 w_s` it is within 0.5 % of `T_f`. So a hinge "at
//! rest" under a torque below `T_f` creeps at `w_s atanh(tau / T_f)` instead of sticking: with
//! the default [`DEFAULT_SLIP_RATE`] of 1e-4 rad/s, a panel hinge held at half its friction
//! torque creeps 0.3 degrees a minute. The power `T_f tanh(w / w_s) w >= 0` is dissipated (booked
//! in the energy balance); the effect stores no energy.

use super::angle::relative_angle;
use super::angle_force::{add_angle_force, add_angle_jacobian};
use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::model::Frame;

/// Default slip rate `w_s` [rad/s] of the regularization (see the module documentation): two
/// orders of magnitude below the slowest hinge rates that matter in a deployment (the default
/// array's panels turn at 0.1-1 rad/s, a 1-DOF panel test at 0.05-0.4 rad/s).
pub const DEFAULT_SLIP_RATE: f64 = 1e-4;

/// Friction of one hinge shaft.
#[derive(Debug, Clone)]
pub struct HingeFriction {
    pub name: String,
    /// The hinge's frames (inboard side, hinge body side); the rate is that of `frame_j`
    /// relative to `frame_i` about `frame_i`'s z axis.
    pub frame_i: Frame,
    pub frame_j: Frame,
    /// Coulomb friction torque `T_f` [N m] (> 0).
    pub torque: f64,
    /// Slip rate `w_s` [rad/s] (> 0).
    pub slip_rate: f64,
}

impl HingeFriction {
    /// Torque [N m] and its derivative w.r.t. the rate [N m s/rad].
    fn torque(&self, rate: f64) -> (f64, f64) {
        let th = (rate / self.slip_rate).tanh();
        (
            -self.torque * th,
            -self.torque / self.slip_rate * (1.0 - th * th),
        )
    }
}

/// The friction of every hinge that has some (assembled only when one does).
#[derive(Debug, Clone)]
pub struct HingeFrictions {
    pub elements: Vec<HingeFriction>,
}

impl ForceEffect for HingeFrictions {
    fn name(&self) -> &str {
        "hinge-friction"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let (tau, _) = e.torque(ra.theta_dot);
            add_angle_force(ctx, &e.frame_i, &e.frame_j, &ra, tau, f);
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for e in &self.elements {
            let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
            let (tau, dtau) = e.torque(ra.theta_dot);
            add_angle_jacobian(ctx, &e.frame_i, &e.frame_j, &ra, tau, 0.0, dtau, sink);
        }
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let ra = relative_angle(ctx.kins, &e.frame_i, &e.frame_j);
                -e.torque(ra.theta_dot).0 * ra.theta_dot
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::BodyId;

    fn element() -> HingeFriction {
        let f = Frame::new(BodyId::GROUND, crate::math::Vec3::zeros());
        HingeFriction {
            name: "h".into(),
            frame_i: f,
            frame_j: f,
            torque: 0.5,
            slip_rate: 1e-3,
        }
    }

    #[test]
    fn opposes_the_rate_and_saturates() {
        let e = element();
        assert!(e.torque(0.1).0 < 0.0 && e.torque(-0.1).0 > 0.0);
        assert!((e.torque(0.1).0 + 0.5).abs() < 1e-12);
        assert_eq!(e.torque(0.0).0, 0.0);
    }

    #[test]
    fn derivative_matches_differences() {
        let e = element();
        for w in [-3e-3, -1e-4, 0.0, 5e-4, 2e-3] {
            let h = 1e-8;
            let num = (e.torque(w + h).0 - e.torque(w - h).0) / (2.0 * h);
            assert!(
                (num - e.torque(w).1).abs() < 1e-5 * (1.0 + num.abs()),
                "w {w}"
            );
        }
    }
}
