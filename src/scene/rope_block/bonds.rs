//! Power bonds at RopeBlock's hooks: the force the rope system exerts on the crane at each hook
//! beside the hook's velocity, the winch's line force beside its pay-out rate, their powers and
//! the work integrated inside the integrator's steps (docs/power_bonds.md).
//!
//! Sign conventions (world axes, `z` up):
//! - `force` [N]: force of the slings on the crane at the hook (the sum of the sling ends'
//!   reactions there; `z` negative while the hook carries weight).
//! - hook power [W] = `-force . v_hook`: power delivered by the crane INTO the model (positive
//!   while hoisting a hanging load).
//! - `winch_force` [N]: `-dV/dL` of the slings' strain energy `V` with respect to the unstretched
//!   length `L` paid out at the hook, `EA (e + e^2 / 2)` per sling end (`e` the strain of the
//!   segment at the hook), plus the axial damping tension's share `T_d l / L`
//!   ([`winch_pull`]): the line pull the winch holds, the conjugate of the pay-out rate in the
//!   model's energy (at rest it exceeds the tension `EA e` by `EA e^2 / 2`, the strain energy per
//!   unit length carried with the paid-out rope).
//! - winch power [W] = `-winch_force x payout_rate`: delivered INTO the model (negative while
//!   paying out under load).
//!
//! The decomposition mirrors the rope effect's own input power
//! ([`crate::effect::ForceEffect::input_power`] of [`RopeEffect`]) term by term, so the ports'
//! powers add up to the power the integrator books as `energy.input`.

use crate::effect::EvalCtx;
use crate::math::Vec3;
use crate::rope::effect::{NONE, RopeEffect, winch_pull};

/// One hook's bonds at one state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HookBond {
    /// Force of the slings on the crane at the hook [N], world.
    pub force: Vec3,
    /// Hook velocity [m/s], world.
    pub velocity: Vec3,
    /// Line force of the winch [N] (see the module documentation).
    pub winch_force: f64,
    /// Pay-out rate [m/s] (positive lets rope out).
    pub payout_rate: f64,
}

impl HookBond {
    /// Power the crane delivers into the model at the hook [W].
    pub fn power(&self) -> f64 {
        -self.force.dot(&self.velocity)
    }

    /// Power the winch delivers into the model [W].
    pub fn winch_power(&self) -> f64 {
        -self.winch_force * self.payout_rate
    }
}

/// The bonds of every hook of `rope` at `ctx` (the rope effect's context, with the decisions
/// of the last accepted step for sliding runs).
pub fn hook_bonds(rope: &RopeEffect, ctx: &EvalCtx) -> Vec<HookBond> {
    let decided = rope.accepted_decisions(ctx);
    let ctx = &EvalCtx {
        frozen: if ctx.frozen.is_empty() {
            &decided
        } else {
            ctx.frozen
        },
        ..*ctx
    };
    let n = rope.n_hooks();
    let mut out: Vec<HookBond> = (0..n)
        .map(|k| {
            let (_, velocity) = rope.hook_motion(ctx.memory, k, ctx.t);
            let (_, payout_rate) = rope.hook_payout(ctx.memory, k, ctx.t);
            HookBond {
                velocity,
                payout_rate,
                ..HookBond::default()
            }
        })
        .collect();
    let hook_of = |i: usize| {
        let h = rope.hook[i];
        (h != NONE).then_some(h as usize)
    };
    for &i in &rope.plain {
        let i = i as usize;
        let (ha, hb) = (hook_of(i), hook_of(i + 1));
        if ha.is_none() && hb.is_none() {
            continue;
        }
        let s = rope.eval_plain(ctx, i);
        let ea = rope.props[rope.rope_of[i] as usize].ea;
        let rest = rope.sigma_at(ctx, i + 1) - rope.sigma_at(ctx, i);
        let pull = winch_pull(ea, &s, rest);
        // `s.force` acts on the segment's first point, its opposite on the second
        if let Some(k) = ha {
            out[k].force += s.force;
            out[k].winch_force += pull;
        }
        if let Some(k) = hb {
            out[k].force -= s.force;
            out[k].winch_force += pull;
        }
    }
    for r in 0..rope.runs.len() {
        let (a, b) = rope.runs[r];
        let (a, b) = (a as usize - 1, b as usize + 1);
        let (ha, hb) = (hook_of(a), hook_of(b));
        if ha.is_none() && hb.is_none() {
            continue;
        }
        let ev = rope.eval_run(ctx, r);
        if let Some(k) = ha {
            out[k].force += ev.force[0];
        }
        if let Some(k) = hb {
            out[k].force += ev.force[ev.points.len() - 1];
        }
    }
    out
}

/// The bonds' work since the start, integrated inside the integrator's steps (trapezoidal over
/// each accepted step, from the powers at its ends).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BondBooks {
    /// Per hook: work of the hook and of the winch into the model since the start [J].
    pub work: Vec<[f64; 2]>,
    /// Time [s] and per-hook powers (hook, winch) [W] of the last sample (`None`: none yet).
    last: Option<(f64, Vec<[f64; 2]>)>,
}

impl BondBooks {
    /// Books of `n` hooks with no work done.
    pub fn new(n: usize) -> Self {
        BondBooks {
            work: vec![[0.0; 2]; n],
            last: None,
        }
    }

    /// Takes the powers at time `t` [s] as the start of the next step (after a command, a
    /// rebuild, a restored state or a state moved by an event): no work is added.
    pub fn restart(&mut self, t: f64, bonds: &[HookBond]) {
        self.last = Some((t, powers(bonds)));
    }

    /// Adds the work of the step that ended at `t` [s] with `bonds` (trapezoidal from the last
    /// sample), then takes them as the next step's start.
    pub fn step(&mut self, t: f64, bonds: &[HookBond]) {
        let p = powers(bonds);
        if let Some((t0, p0)) = &self.last {
            let h = t - t0;
            for ((w, a), b) in self.work.iter_mut().zip(p0).zip(&p) {
                w[0] += 0.5 * h * (a[0] + b[0]);
                w[1] += 0.5 * h * (a[1] + b[1]);
            }
        }
        self.last = Some((t, p));
    }

    /// Total work of all bonds into the model [J].
    pub fn total(&self) -> f64 {
        self.work.iter().map(|w| w[0] + w[1]).sum()
    }
}

fn powers(bonds: &[HookBond]) -> Vec<[f64; 2]> {
    bonds.iter().map(|b| [b.power(), b.winch_power()]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trapezoid_of_a_linear_power_is_exact() {
        // power 2 t W on hook 0, winch -3 W: work over [0, 2] s = 4 J and -6 J
        let bond = |t: f64| HookBond {
            force: Vec3::new(0.0, 0.0, -2.0 * t),
            velocity: Vec3::new(0.0, 0.0, 1.0),
            winch_force: 3.0,
            payout_rate: 1.0,
        };
        let mut b = BondBooks::new(1);
        b.restart(0.0, &[bond(0.0)]);
        for i in 1..=8 {
            let t = 0.25 * i as f64;
            b.step(t, &[bond(t)]);
        }
        assert!((b.work[0][0] - 4.0).abs() < 1e-14, "{:?}", b.work);
        assert!((b.work[0][1] + 6.0).abs() < 1e-14, "{:?}", b.work);
        assert!((b.total() + 2.0).abs() < 1e-14);
    }
}
