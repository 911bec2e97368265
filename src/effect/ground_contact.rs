//! Body points on a fixed plane (the ground, a support) with a normal contact law and
//! regularized Coulomb friction.
//!
//! Normal force: penetration `delta` of the point below the plane and a
//! [`crate::contact::ContactLaw`] evaluated without a recorded approach speed, so its damping uses
//! the law's floor speed ([`crate::contact::ContactLaw::with_min_approach_speed`]) as a fixed
//! reference speed: `F = k delta^n (1 + chi delta_dot / v_ref)`, memoryless and continuous where a
//! point touches down. (With the approach speed recorded at each onset, as for an isolated impact
//! in [`super::plane_contact`], a block sliding or rocking on the ground re-touches with tiny
//! approach speeds, and the huge damping they give made a block dragged along the ground
//! unstable within 0.4 s.) Friction on a point in contact, with `v_t` [m/s] its velocity within
//! the plane (world frame):
//!
//! ```text
//! F_t = -mu F_n v_t / sqrt(|v_t|^2 + v_s^2)
//! ```
//!
//! Coulomb's law (`|F_t| = mu F_n` against the sliding direction) for `|v_t| >> v_s`; below the
//! regularization speed `v_s` [m/s] it turns viscous, so there is no sticking: a tangential load
//! of a fraction `r < 1` of `mu F_n` lets the point creep at `v_s r / sqrt(1 - r^2)`. The friction
//! power `mu F_n |v_t|^2 / sqrt(|v_t|^2 + v_s^2)` is always a loss and is booked as dissipated.

use super::plane_contact::PlaneContact;
use super::point_force::TwoPointForce;
use super::{EvalCtx, ForceEffect, JacobianSink};
use crate::contact::ContactForce;
use crate::math::{Mat3, Vec3};
use crate::model::kinematics::{BodyKin, kin_of};

/// All ground contacts of a scene: normal contacts of body points with planes, plus friction.
#[derive(Debug, Clone)]
pub struct GroundContact {
    /// The points, their planes and normal laws.
    pub contacts: Vec<PlaneContact>,
    /// Coulomb friction coefficient [-] (0: frictionless).
    pub mu: f64,
    /// Regularization speed `v_s` [m/s], > 0.
    pub slip_speed: f64,
}

/// One point's contact, evaluated: normal law, kinematics, tangential velocity.
struct PointEval<'a> {
    ev: ContactForce,
    kin: &'a BodyKin,
    local: Vec3,
    /// Velocity within the plane [m/s], world frame.
    v_t: Vec3,
    /// `sqrt(|v_t|^2 + v_s^2)` [m/s].
    s: f64,
}

impl GroundContact {
    fn point<'a>(&self, ctx: &EvalCtx<'a>, c: &PlaneContact) -> PointEval<'a> {
        let kin = kin_of(ctx.kins, c.point.body);
        let local = c.point.origin;
        let (delta, delta_dot) = c.penetration(kin);
        let ev = c.law.evaluate(delta, delta_dot, 0.0);
        let v = kin.point_velocity(&local);
        let v_t = v - c.normal * c.normal.dot(&v);
        let s = (v_t.norm_squared() + self.slip_speed * self.slip_speed).sqrt();
        PointEval {
            ev,
            kin,
            local,
            v_t,
            s,
        }
    }

    /// Friction force on the body point [N], world frame (zero out of contact).
    fn friction(&self, p: &PointEval) -> Vec3 {
        if p.ev.force > 0.0 {
            -self.mu * p.ev.force / p.s * p.v_t
        } else {
            Vec3::zeros()
        }
    }

    /// Normal and friction force as one two-point force between the ground point under the body
    /// point (A) and the body point (B): force on A is `-(F_n n + F_t)`, with `d = p_b - p_a`.
    fn two_point<'a>(&self, p: &PointEval<'a>, n: &Vec3) -> TwoPointForce<'a> {
        let nn = n * n.transpose();
        let f_n = p.ev.force;
        let mut kd = p.ev.d_force_d_delta * nn;
        let mut cd = p.ev.d_force_d_delta_dot * nn;
        let mut force = -f_n * n;
        if f_n > 0.0 && self.mu > 0.0 {
            // force on A: mu F_n g, g = P_t d_dot / s; delta = d0 - n.d, so dF_n/dd = -F_delta n^T
            let g = p.v_t / p.s;
            force += self.mu * f_n * g;
            let proj = Mat3::identity() - nn;
            let w = p.v_t;
            kd -= self.mu * p.ev.d_force_d_delta * g * n.transpose();
            cd += self.mu * f_n / p.s * (proj - w * w.transpose() / (p.s * p.s))
                - self.mu * p.ev.d_force_d_delta_dot * g * n.transpose();
        }
        TwoPointForce {
            a: &BodyKin::GROUND,
            s_a: Vec3::zeros(),
            b: p.kin,
            s_b: p.local,
            force,
            kd,
            cd,
        }
    }

    /// Total normal force [N] and total friction force magnitude [N] on the ground's points
    /// (sums over the points; for outputs).
    pub fn totals(&self, ctx: &EvalCtx) -> (f64, f64) {
        let mut total = (0.0, Vec3::zeros());
        for c in &self.contacts {
            let p = self.point(ctx, c);
            total.0 += p.ev.force;
            total.1 += self.friction(&p);
        }
        (total.0, total.1.norm())
    }
}

impl ForceEffect for GroundContact {
    fn name(&self) -> &str {
        "ground-contact"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for c in &self.contacts {
            let p = self.point(ctx, c);
            if p.ev.force != 0.0 {
                self.two_point(&p, &c.normal).add_forces(f);
            }
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for c in &self.contacts {
            let p = self.point(ctx, c);
            self.two_point(&p, &c.normal).add_jacobian(sink);
        }
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        self.contacts
            .iter()
            .map(|c| {
                let (delta, _) = c.penetration(kin_of(ctx.kins, c.point.body));
                c.law.potential_energy(delta)
            })
            .sum()
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        let mut p_total = 0.0;
        for c in &self.contacts {
            let p = self.point(ctx, c);
            p_total += p.ev.dissipated_power - self.friction(&p).dot(&p.v_t);
        }
        p_total
    }
}
