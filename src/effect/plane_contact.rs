//! Contact of body points with fixed half-spaces (a floor, a wall) under a contact law.
//!
//! Penetration `delta = d - n . p` of point `p` below the plane `n . x = d` (unit normal `n`
//! pointing out of the solid); the force `F(delta, delta_dot) n` pushes the point out. Memory per
//! contact: `[in contact, approach speed, peak force]`; before the approach speed is recorded
//! (the onset step) the current penetration rate stands in for it. The contacts expose their
//! closing and opening as events ([`ForceEffect::contact_event_functions`]): an integrator that
//! locates an onset in time records the approach speed there
//! ([`ForceEffect::record_contact_event`]) instead of at the end of the first step in contact
//! (DOPRI5 does, see `docs/contact_onset.md`).

use super::point_force::TwoPointForce;
use super::{EvalCtx, ForceEffect, JacobianSink, MemoryChange};
use crate::contact::ContactLaw;
use crate::math::Vec3;
use crate::model::Frame;
use crate::model::kinematics::{BodyKin, kin_of};

/// Memory values per contact.
pub const MEMORY_PER_CONTACT: usize = 3;

/// One point-plane contact.
#[derive(Debug, Clone)]
pub struct PlaneContact {
    pub name: String,
    /// The contacting point (frame origin on its body).
    pub point: Frame,
    /// Plane normal (unit, world frame, out of the solid) and offset [m].
    pub normal: Vec3,
    pub offset: f64,
    pub law: ContactLaw,
}

/// Evaluated contact: penetration [m], rate [m/s], force [N] and its derivatives.
#[derive(Debug, Clone, Copy, Default)]
pub struct PlaneEval {
    pub delta: f64,
    pub delta_dot: f64,
    pub force: f64,
    pub d_delta: f64,
    pub d_delta_dot: f64,
    pub dissipated: f64,
    pub elastic_energy: f64,
}

impl PlaneContact {
    /// Penetration `delta` [m] of the point below the plane and its rate [m/s] (positive while
    /// approaching).
    pub fn penetration(&self, k: &BodyKin) -> (f64, f64) {
        let p = k.point(&self.point.origin);
        let delta = self.offset - self.normal.dot(&p);
        let delta_dot = -self.normal.dot(&k.point_velocity(&self.point.origin));
        (delta, delta_dot)
    }

    /// Evaluates with memory `[in contact, approach speed, ...]`.
    pub fn evaluate(&self, kins: &[BodyKin], mem: &[f64]) -> PlaneEval {
        let (delta, delta_dot) = self.penetration(kin_of(kins, self.point.body));
        let mut ev = PlaneEval {
            delta,
            delta_dot,
            ..Default::default()
        };
        if delta <= 0.0 {
            return ev;
        }
        let onset = mem[0] < 0.5;
        let approach = if onset { delta_dot.max(0.0) } else { mem[1] };
        let c = self.law.evaluate(delta, delta_dot, approach);
        ev.force = c.force;
        ev.d_delta = c.d_force_d_delta;
        ev.d_delta_dot = if onset && delta_dot > self.law.min_approach_speed() {
            0.0
        } else {
            c.d_force_d_delta_dot
        };
        ev.dissipated = c.dissipated_power;
        ev.elastic_energy = self.law.potential_energy(delta);
        ev
    }

    /// The contact as a force between the ground point under `p` (A) and the body point (B):
    /// force on A is `-F n`, so on the body it is `+F n`.
    fn two_point<'a>(&self, kins: &'a [BodyKin], ev: &PlaneEval) -> TwoPointForce<'a> {
        let k = kin_of(kins, self.point.body);
        let n = self.normal;
        // d = p_b - p_a with p_a fixed: delta = d0 - n.d, so dF/dd = -F_delta n^T, force on A = -F n
        let nn = n * n.transpose();
        TwoPointForce {
            a: &crate::model::kinematics::BodyKin::GROUND,
            s_a: Vec3::zeros(),
            b: k,
            s_b: self.point.origin,
            force: -ev.force * n,
            kd: ev.d_delta * nn,
            cd: ev.d_delta_dot * nn,
        }
    }
}

/// All point-plane contacts of a scene.
#[derive(Debug, Clone)]
pub struct PlaneContacts {
    pub elements: Vec<PlaneContact>,
}

impl PlaneContacts {
    fn mem<'a>(ctx: &'a EvalCtx, i: usize) -> &'a [f64] {
        &ctx.memory[i * MEMORY_PER_CONTACT..(i + 1) * MEMORY_PER_CONTACT]
    }
}

impl ForceEffect for PlaneContacts {
    fn name(&self) -> &str {
        "plane-contact"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for (i, c) in self.elements.iter().enumerate() {
            let ev = c.evaluate(ctx.kins, Self::mem(ctx, i));
            if ev.force != 0.0 {
                c.two_point(ctx.kins, &ev).add_forces(f);
            }
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for (i, c) in self.elements.iter().enumerate() {
            let ev = c.evaluate(ctx.kins, Self::mem(ctx, i));
            c.two_point(ctx.kins, &ev).add_jacobian(sink);
        }
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .enumerate()
            .map(|(i, c)| c.evaluate(ctx.kins, Self::mem(ctx, i)).elastic_energy)
            .sum()
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        self.elements
            .iter()
            .enumerate()
            .map(|(i, c)| c.evaluate(ctx.kins, Self::mem(ctx, i)).dissipated)
            .sum()
    }

    fn n_memory(&self) -> usize {
        self.elements.len() * MEMORY_PER_CONTACT
    }

    fn n_contact_events(&self) -> usize {
        self.elements.len()
    }

    fn contact_event_functions(&self, ctx: &EvalCtx, out: &mut [f64]) {
        for ((i, c), g) in self.elements.iter().enumerate().zip(out.iter_mut()) {
            let delta = c.penetration(kin_of(ctx.kins, c.point.body)).0;
            *g = if Self::mem(ctx, i)[0] < 0.5 {
                delta
            } else {
                -delta
            };
        }
    }

    fn record_contact_event(&self, ctx: &EvalCtx, i: usize, memory: &mut [f64]) -> MemoryChange {
        let Some(c) = self.elements.get(i) else {
            return MemoryChange::None;
        };
        let Some(m) = memory.get_mut(i * MEMORY_PER_CONTACT..(i + 1) * MEMORY_PER_CONTACT) else {
            return MemoryChange::None;
        };
        let (delta, delta_dot) = c.penetration(kin_of(ctx.kins, c.point.body));
        let before = [m[0], m[1]];
        // the direction from the memory at the step's start: the memory update of the step
        // (already in `m`) may have closed or opened the contact on a penetration of 1e-15 m of
        // either sign (a closing recorded as an opening then dropped the onset's approach speed)
        if Self::mem(ctx, i)[0] < 0.5 {
            // closes: the approach speed of the onset (a non-finite rate records 0, unknown)
            m[0] = 1.0;
            m[1] = if delta_dot.is_finite() {
                delta_dot.max(0.0)
            } else {
                0.0
            };
        } else {
            m[0] = 0.0;
            m[1] = 0.0;
        }
        if before[0].to_bits() == m[0].to_bits() && before[1].to_bits() == m[1].to_bits() {
            MemoryChange::None
        } else if delta > 0.0 && m[0] < 0.5 {
            // opened at a penetration of the order of the integrator's accuracy: the elastic
            // force there (about k delta^n) is dropped
            MemoryChange::Discontinuous
        } else {
            // at a located onset the force is zero, or (a small penetration) evaluated with this
            // very rate standing in for the approach speed, as the recorded speed now gives
            MemoryChange::Smooth
        }
    }

    fn update_memory(&self, ctx: &EvalCtx, memory: &mut [f64]) -> MemoryChange {
        let mut change = MemoryChange::None;
        for (i, c) in self.elements.iter().enumerate() {
            let ev = c.evaluate(ctx.kins, Self::mem(ctx, i));
            let m = &mut memory[i * MEMORY_PER_CONTACT..(i + 1) * MEMORY_PER_CONTACT];
            let before = [m[0], m[1], m[2]];
            if ev.delta > 0.0 {
                if m[0] < 0.5 {
                    m[0] = 1.0;
                    m[1] = ev.delta_dot.max(0.0);
                }
            } else {
                m[0] = 0.0;
                m[1] = 0.0;
            }
            m[2] = m[2].max(ev.force);
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
