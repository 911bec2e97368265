//! Hinge latches: the pin/groove wall contacts of [`crate::contact::latch`] under a contact law,
//! acting as a torque on the hinge's relative angle.
//!
//! The hinge angle is `theta = angle_offset + raw`, `raw` the relative angle of the two frames
//! (about `z` of frame i, see [`super::angle`]); `theta = lock_angle` with the pin centred. Wall
//! forces act when the latch is engaged: once the memory says so, or whenever
//! `theta >= engagement angle` (the geometry makes both wall penetrations non-positive there, so
//! engagement changes no force and needs no event location). The memory keeps it engaged, so the
//! lock holds both ways and the pin can rebound between the walls.
//!
//! Per wall: `tau = -F(delta, delta_dot) d delta / d theta` with `delta_dot = delta' theta_dot`.
//! The approach speed of the damped laws is the one recorded at the first accepted step in
//! contact; before it is recorded (the onset step) the current penetration rate stands in for it.
//!
//! Memory per latch: `[engaged, lock time, front in contact, front approach speed,
//! rear in contact, rear approach speed, peak wall force, previous theta, previous theta_dot,
//! previous time, wall force two steps back, one step back, and their times]`. The lock time is
//! located by cubic Hermite interpolation of `theta` between accepted steps (error O(h^4)); the
//! peak force by a parabola through the three accepted samples around a maximum (O(h^3)), so
//! both converge with the tolerance instead of being sampled at the step size.

use super::angle::{RelativeAngle, relative_angle};
use super::angle_force::{add_angle_force, add_angle_jacobian};
use super::{EvalCtx, ForceEffect, JacobianSink, MemoryChange};
use crate::contact::ContactLaw;
use crate::contact::latch::{LatchGeometry, WallContact};
use crate::model::Frame;

/// Number of memory values per latch.
pub const MEMORY_PER_LATCH: usize = 14;

/// One hinge latch.
#[derive(Debug, Clone)]
pub struct Latch {
    pub name: String,
    /// Frame on hinge half A (the cam), z along the hinge axis.
    pub frame_i: Frame,
    /// Frame on hinge half B (the pin).
    pub frame_j: Frame,
    /// `theta = angle_offset + raw relative angle` [rad].
    pub angle_offset: f64,
    pub geometry: LatchGeometry,
    pub law: ContactLaw,
}

/// Evaluated state of one latch.
#[derive(Debug, Clone, Copy)]
pub struct LatchEval {
    pub ra: RelativeAngle,
    /// Hinge angle [rad] and rate [rad/s].
    pub theta: f64,
    pub theta_dot: f64,
    pub engaged: bool,
    /// Wall normal forces [N] (front, rear).
    pub forces: [f64; 2],
    /// Generalized torque on theta [N m] and its partial derivatives.
    pub tau: f64,
    pub tau_theta: f64,
    pub tau_thetadot: f64,
    /// Penetrations [m] and rates [m/s] (front, rear).
    pub delta: [f64; 2],
    pub delta_dot: [f64; 2],
    /// Power dissipated by the wall damping [W] and elastic energy [J].
    pub dissipated: f64,
    pub elastic_energy: f64,
}

impl Latch {
    /// Evaluates the latch with its memory `mem` (length [`MEMORY_PER_LATCH`]).
    pub fn evaluate(&self, ctx: &EvalCtx, mem: &[f64]) -> LatchEval {
        let ra = relative_angle(ctx.kins, &self.frame_i, &self.frame_j);
        let theta = self.angle_offset + ra.theta;
        let theta_dot = ra.theta_dot;
        let engaged = mem[0] > 0.5 || self.geometry.engages(theta);
        let mut ev = LatchEval {
            ra,
            theta,
            theta_dot,
            engaged,
            forces: [0.0; 2],
            tau: 0.0,
            tau_theta: 0.0,
            tau_thetadot: 0.0,
            delta: [0.0; 2],
            delta_dot: [0.0; 2],
            dissipated: 0.0,
            elastic_energy: 0.0,
        };
        if !engaged {
            return ev;
        }
        let Ok(Some(contact)) = self.geometry.query(theta, true) else {
            return ev;
        };
        for (w, wall) in [contact.front, contact.rear].iter().enumerate() {
            self.add_wall(&mut ev, w, wall, mem[2 + 2 * w] > 0.5, mem[3 + 2 * w]);
        }
        ev
    }

    fn add_wall(
        &self,
        ev: &mut LatchEval,
        w: usize,
        wall: &WallContact,
        in_contact: bool,
        recorded_speed: f64,
    ) {
        let (d1, d2) = (wall.d_penetration_d_theta, wall.d2_penetration_d_theta2);
        let delta = wall.penetration;
        let delta_dot = d1 * ev.theta_dot;
        ev.delta[w] = delta;
        ev.delta_dot[w] = delta_dot;
        if delta <= 0.0 {
            return;
        }
        let onset = !in_contact;
        let approach = if onset {
            delta_dot.max(0.0)
        } else {
            recorded_speed
        };
        let c = self.law.evaluate(delta, delta_dot, approach);
        // at onset the approach speed follows the rate, so the force does not depend on it
        let f_dd = if onset && delta_dot > self.law.min_approach_speed() {
            0.0
        } else {
            c.d_force_d_delta_dot
        };
        ev.forces[w] = c.force;
        ev.tau += -c.force * d1;
        ev.tau_theta += -((c.d_force_d_delta * d1 + f_dd * d2 * ev.theta_dot) * d1 + c.force * d2);
        ev.tau_thetadot += -f_dd * d1 * d1;
        ev.dissipated += c.dissipated_power;
        ev.elastic_energy += self.law.potential_energy(delta);
    }
}

/// Time in `[t0, t1]` where the cubic Hermite interpolant of `theta` through `(t, theta,
/// theta_dot)` at both ends reaches `target` (bisection; `t1` if it never does).
fn crossing_time(a: (f64, f64, f64), b: (f64, f64, f64), target: f64) -> f64 {
    let (t0, y0, d0) = a;
    let (t1, y1, d1) = b;
    let h = t1 - t0;
    if h.is_nan() || h <= 0.0 || y0 >= target {
        return t1;
    }
    let eval = |s: f64| {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * y0
            + (s3 - 2.0 * s2 + s) * h * d0
            + (-2.0 * s3 + 3.0 * s2) * y1
            + (s3 - s2) * h * d1
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if eval(mid) >= target {
            hi = mid
        } else {
            lo = mid
        }
    }
    t0 + hi * h
}

/// The vertex value of the parabola through three samples when the middle one is a local maximum
/// (0 otherwise).
fn parabola_peak(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    parabola_vertex(a, b, c).map_or(0.0, |v| v.1)
}

/// Time and value `(t, f)` of the peak located from three samples `(t, f)` when the middle one
/// is a local maximum: the vertex of the parabola through them, or the middle sample itself when
/// the parabola does not open downwards. What the latch's peak tracker records (memory slot 6).
pub fn parabola_vertex(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> Option<(f64, f64)> {
    let ((ta, fa), (tb, fb), (tc, fc)) = (a, b, c);
    if !(fb > 0.0 && fb >= fa && fb >= fc && ta < tb && tb < tc) {
        return None;
    }
    // Newton form: f = fb + p (t - tb) + q (t - tb)^2 through the three points
    let (da, dc) = (ta - tb, tc - tb);
    let (sa, sc) = ((fa - fb) / da, (fc - fb) / dc);
    let q = (sc - sa) / (dc - da);
    let p = sa - q * da;
    if q >= 0.0 {
        return Some((tb, fb));
    }
    Some((tb - p / (2.0 * q), fb - p * p / (4.0 * q)))
}

/// All latches of a scene.
#[derive(Debug, Clone)]
pub struct Latches {
    pub elements: Vec<Latch>,
}

impl Latches {
    fn mem<'a>(ctx: &'a EvalCtx, i: usize) -> &'a [f64] {
        &ctx.memory[i * MEMORY_PER_LATCH..(i + 1) * MEMORY_PER_LATCH]
    }
}

impl ForceEffect for Latches {
    fn name(&self) -> &str {
        "latch"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for (i, l) in self.elements.iter().enumerate() {
            let ev = l.evaluate(ctx, Self::mem(ctx, i));
            if ev.engaged {
                add_angle_force(ctx, &l.frame_i, &l.frame_j, &ev.ra, ev.tau, f);
            }
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for (i, l) in self.elements.iter().enumerate() {
            let ev = l.evaluate(ctx, Self::mem(ctx, i));
            add_angle_jacobian(
                ctx,
                &l.frame_i,
                &l.frame_j,
                &ev.ra,
                ev.tau,
                ev.tau_theta,
                ev.tau_thetadot,
                sink,
            );
        }
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .enumerate()
            .map(|(i, l)| l.evaluate(ctx, Self::mem(ctx, i)).elastic_energy)
            .sum()
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .enumerate()
            .map(|(i, l)| l.evaluate(ctx, Self::mem(ctx, i)).dissipated)
            .sum()
    }

    fn n_memory(&self) -> usize {
        self.elements.len() * MEMORY_PER_LATCH
    }

    fn init_memory(&self, ctx: &EvalCtx, memory: &mut [f64]) {
        for (i, l) in self.elements.iter().enumerate() {
            let m = &mut memory[i * MEMORY_PER_LATCH..(i + 1) * MEMORY_PER_LATCH];
            m.fill(0.0);
            m[1] = f64::NAN;
            let ra = relative_angle(ctx.kins, &l.frame_i, &l.frame_j);
            if l.geometry.engages(l.angle_offset + ra.theta) {
                m[0] = 1.0;
                m[1] = ctx.t;
            }
            m[7] = l.angle_offset + ra.theta;
            m[8] = ra.theta_dot;
            m[9] = ctx.t;
            m[12] = ctx.t;
            m[13] = ctx.t;
        }
    }

    fn update_memory(&self, ctx: &EvalCtx, memory: &mut [f64]) -> MemoryChange {
        let mut change = MemoryChange::None;
        for (i, l) in self.elements.iter().enumerate() {
            let ev = l.evaluate(ctx, Self::mem(ctx, i));
            let m = &mut memory[i * MEMORY_PER_LATCH..(i + 1) * MEMORY_PER_LATCH];
            let before = m.to_vec();
            if ev.engaged && m[0] < 0.5 {
                m[0] = 1.0;
                m[1] = crossing_time(
                    (m[9], m[7], m[8]),
                    (ctx.t, ev.theta, ev.theta_dot),
                    l.geometry.engagement_angle(),
                );
            }
            m[7] = ev.theta;
            m[8] = ev.theta_dot;
            m[9] = ctx.t;
            for w in 0..2 {
                if ev.delta[w] > 0.0 {
                    if m[2 + 2 * w] < 0.5 {
                        m[2 + 2 * w] = 1.0;
                        m[3 + 2 * w] = ev.delta_dot[w].max(0.0);
                    }
                } else {
                    m[2 + 2 * w] = 0.0;
                    m[3 + 2 * w] = 0.0;
                }
            }
            let force = ev.forces[0].max(ev.forces[1]);
            m[6] = m[6].max(force).max(parabola_peak(
                (m[12], m[10]),
                (m[13], m[11]),
                (ctx.t, force),
            ));
            m[10] = m[11];
            m[12] = m[13];
            m[11] = force;
            m[13] = ctx.t;
            if m.iter()
                .zip(&before)
                .any(|(a, b)| a.to_bits() != b.to_bits())
            {
                change = MemoryChange::Smooth;
            }
        }
        change
    }
}
