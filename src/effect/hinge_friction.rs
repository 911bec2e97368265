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
//!
//! **Iteration matrix.** [`ForceEffect::add_jacobian`] gives the Newton matrices the *secant*
//! slope `tau / w = -T_f tanh(w / w_s) / w` [N m s/rad] in place of the tangent `d tau / d w`
//! (the torque is then a damper of that coefficient, frozen for one linearization; the
//! configuration terms follow it). The residual keeps the exact torque, so a converged step is
//! the same; only the path to it changes. The tangent is zero where the law saturates
//! (`|w| > 3 w_s`): an implicit step that starts slipping and whose friction impulse
//! `T_f gamma h` exceeds `I w_s` (`I` the inertia the hinge rate sees) then predicts the full
//! torque on the far side of `w = 0`, lands saturated there, and is sent back: Newton cycles
//! between the two branches with rate exactly 1. With flexible panels the hinge rate oscillates
//! through zero with the panels' vibration and the inertia behind it is small (about 5e-4
//! kg m^2, from the cycle's amplitude), so every step larger than a few microseconds cycled
//! (generalized-alpha: 5,116 steps and 8,098 Newton failures for 0.03 s at `T_f` = 1 N m).
//! With the secant, a linearization solves for the rate at which the step's momentum and other
//! forces balance a damper of the iterate's coefficient: its sign is the side they drive to,
//! whatever the iterate's, so no two-branch cycle; on one hinge the iterates approach the
//! solution monotonically (the Kacanov iteration of a saturating law, whose secant
//! `tanh(x) / x` falls with `|x|`). See docs/hinge_friction_cost.md.

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
    pub fn torque(&self, rate: f64) -> (f64, f64) {
        let th = (rate / self.slip_rate).tanh();
        (
            -self.torque * th,
            -self.torque / self.slip_rate * (1.0 - th * th),
        )
    }

    /// Secant slope `tau(w) / w` [N m s/rad] at the rate `w` [rad/s] (its limit
    /// `-T_f / w_s` at `w = 0`): the slope the iteration matrix carries (see the module
    /// documentation). Never smaller in magnitude than the tangent.
    pub fn secant_slope(&self, rate: f64) -> f64 {
        let x = rate / self.slip_rate;
        // tanh(x) / x = 1 - x^2/3 + 2 x^4/15 - ...: the series below 1e-4 (its next term is
        // below 1e-17)
        let ratio = if x.abs() < 1e-4 {
            1.0 - x * x / 3.0
        } else {
            x.tanh() / x
        };
        -self.torque / self.slip_rate * ratio
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
            let tau = e.torque(ra.theta_dot).0;
            let slope = e.secant_slope(ra.theta_dot);
            add_angle_jacobian(ctx, &e.frame_i, &e.frame_j, &ra, tau, 0.0, slope, sink);
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
    fn secant_slope_is_torque_over_rate_and_bounds_the_tangent() {
        let e = element();
        // the limit at rest is the tangent there; the series and tanh(x)/x meet at x = 1e-4
        assert_eq!(e.secant_slope(0.0), e.torque(0.0).1);
        let at = 1e-4 * e.slip_rate;
        let (below, above) = (
            e.secant_slope(at * (1.0 - 1e-12)),
            e.secant_slope(at * 1.01),
        );
        assert!(
            (below - above).abs() < 1e-8 * below.abs(),
            "{below} {above}"
        );
        for w in [-3e-1, -3e-3, -1e-4, 2e-7, 5e-4, 2e-3, 4e-2] {
            let s = e.secant_slope(w);
            let (tau, tangent) = e.torque(w);
            assert!((s * w - tau).abs() < 1e-14, "w {w}");
            // a damper (negative slope) at least as stiff as the tangent
            assert!(
                s < 0.0 && s <= tangent,
                "w {w}: secant {s}, tangent {tangent}"
            );
        }
    }

    /// The implicit step of one hinge of inertia `I` [kg m^2] that starts slipping at `w0`
    /// [rad/s] under a torque `f` [N m] below the friction torque: `k (w - w0) = tau(w) + f`,
    /// `k = I / (gamma h)`, solved by Newton from `w0` with the iteration slope `slope`. Returns
    /// the iterates.
    fn one_hinge_newton(e: &HingeFriction, slope: impl Fn(f64) -> f64, n: usize) -> Vec<f64> {
        let (k, w0, f) = (1.0, 5.0 * e.slip_rate, 0.3);
        let mut w = vec![w0];
        for _ in 0..n {
            let x = w[w.len() - 1];
            let r = k * (x - w0) - e.torque(x).0 - f;
            w.push(x - r / (k - slope(x)));
        }
        w
    }

    #[test]
    fn tangent_newton_cycles_between_the_slip_branches_and_the_secant_converges() {
        // the friction impulse over the step (T_f / k = 0.5 rad/s) is 500 slip rates: the
        // tangent (zero where the law saturates) sends the iterate from one saturated branch to
        // the other and back, a cycle of rate exactly 1
        let e = element();
        let w = one_hinge_newton(&e, |x| e.torque(x).1, 40);
        for pair in w[20..].windows(2) {
            assert!(pair[0] * pair[1] < 0.0, "{pair:?}");
            assert!(
                pair[0].abs().min(pair[1].abs()) > 100.0 * e.slip_rate,
                "{pair:?}"
            );
        }
        assert!((w[38] - w[40]).abs() < 1e-12, "{:?}", &w[36..]);
        // the secant: the solution (the hinge creeping at 0.707 w_s) to round-off
        let w = one_hinge_newton(&e, |x| e.secant_slope(x), 40);
        let x = w[40];
        let r = (x - 5.0 * e.slip_rate) - e.torque(x).0 - 0.3;
        assert!(r.abs() < 1e-14, "residual {r:e}");
        assert!((x / e.slip_rate - 0.7067).abs() < 1e-3, "{x}");
        // monotone from the first iterate on, on the side the step drives to
        for pair in w[1..].windows(2) {
            assert!(pair[1] > 0.0 && pair[1] <= pair[0] + 1e-18, "{pair:?}");
        }
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
