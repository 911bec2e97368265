//! All ropes of a scene as one struct-of-arrays force effect, O(N) per evaluation.
//!
//! Points are stored in flat arrays (body, offset, material coordinate, hook and contact flags),
//! ropes as ranges of them. At build time the segments are sorted into lists by what they need:
//! *plain* segments (no contact node at either end: the tension-only law, [`super::segment`]),
//! *runs* (maximal sequences of consecutive contact nodes with their adjacent segments, evaluated
//! together because slipping nodes couple their segments, [`super::slip`]), *bending* hinges and
//! *drag* nodes (lists that stay empty when the effect is off, so it costs nothing).
//!
//! Memory (see [`crate::effect::ForceEffect::n_memory`]): one record per hook, then one per
//! contact node, read and written only through the typed records of [`super::memory`] (which
//! holds the layout and what each field means).
//!
//! Decisions (frozen for a Newton iteration, see [`RopeEffect`]'s `freeze`): two values per
//! contact slot, the slip state's code and the share `mu_rope`. After an accepted step the
//! memory holds the decisions the step used, and the reports ([`RopeEffect::contact_segments`],
//! [`RopeEffect::rope_tensions`]) evaluate with exactly those: what they show is what acted.

use super::bending;
use super::drag;
use super::edge_hold;
use super::layout::{
    ContactInit, EdgeHold, HookInit, HookMode, LayoutRope, PointAt, SlipMode, hermite, ramped,
};
use super::memory::{ContactRecord, RopeMemory};
use super::props::RopeProps;
use super::run::{self, RunEval};
use super::segment::{self, Tension};
use super::slip::Derivatives;
use crate::effect::point_force::TwoPointForce;
use crate::effect::{AuxSupport, EvalCtx, ForceEffect, JacobianSink, MemoryChange};
use crate::math::{Mat3, Vec3};
use crate::model::BodyId;
use crate::model::kinematics::{BodyKin, kin_of};

pub(crate) const NONE: u32 = u32::MAX;

/// One evaluated plain segment: tension, geometry and the two-point derivatives.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Seg {
    pub law: Tension,
    pub elastic: f64,
    pub l: f64,
    pub ldot: f64,
    /// Rate the dashpot works on [m/s]: `l_dot - l L_dot / L`, the segment's strain rate times
    /// its rest length `L` (equal to `l_dot` when the rest length is constant). The damping
    /// tension `law.t - elastic` times this rate is the power the dashpot dissipates, `c L
    /// (strain rate)^2 >= 0`.
    pub dashpot_rate: f64,
    /// Force on the first point [N] (the second gets the opposite).
    pub force: Vec3,
    /// `dF/dd`, `dF/dd_dot` with `d = p_b - p_a`.
    pub kd: Mat3,
    pub cd: Mat3,
}

/// Evaluates the tension-only law between two points; `rest_rate` [m/s] is the rate at which the
/// rest length grows (winch pay-out), which enters the strain rate `l_dot/L - l L_dot/L^2`.
/// With `taut_tangent` a slack segment reports the axial stiffness `EA/L u u^T` of a taut one as
/// its `kd` (its force stays zero): the search direction of a static solve from a just-taut layout
/// (see [`RopeEffect::set_taut_tangent`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn plain_segment(
    pa: &Vec3,
    pb: &Vec3,
    va: &Vec3,
    vb: &Vec3,
    rest: f64,
    rest_rate: f64,
    props: &RopeProps,
    taut_tangent: bool,
) -> Seg {
    let d = pb - pa;
    let dd = vb - va;
    let l = d.norm().max(1e-12);
    let u = d / l;
    let ldot = u.dot(&dd);
    let law = segment::tension(props.ea, props.axial_damping, l, ldot, rest, rest_rate);
    let elastic = if l > rest {
        props.ea * (l - rest) / rest
    } else {
        0.0
    };
    let (kd, cd) = if l > rest {
        let proj = Mat3::identity() - u * u.transpose();
        let h = proj * dd / l;
        (
            u * u.transpose() * law.dt_dl + proj * (law.t / l) + u * h.transpose() * law.dt_dldot,
            u * u.transpose() * law.dt_dldot,
        )
    } else if taut_tangent {
        (u * u.transpose() * (props.ea / rest), Mat3::zeros())
    } else {
        (Mat3::zeros(), Mat3::zeros())
    };
    Seg {
        law,
        elastic,
        l,
        ldot,
        dashpot_rate: ldot - l * rest_rate / rest,
        force: u * law.t,
        kd,
        cd,
    }
}

/// Line pull [N] a winch holds on plain segment `s` of rest length `rest` [m] (axial stiffness
/// `ea` [N]) while it changes that rest length: the power conjugate of the pay-out rate, `-dV/dL`
/// of the strain energy plus the damping tension's share `T_d l / L` (the dashpot's rate
/// `l_dot - l L_dot / L` falls by `l / L` per unit pay-out rate). Zero while the segment is slack.
pub(crate) fn winch_pull(ea: f64, s: &Seg, rest: f64) -> f64 {
    -segment::strain_energy_drest(ea, s.l, rest) + (s.law.t - s.elastic) * s.l / rest
}

/// All ropes of a scene.
#[derive(Debug, Clone)]
pub struct RopeEffect {
    pub(crate) body: Vec<BodyId>,
    pub(crate) local: Vec<Vec3>,
    pub(crate) hook: Vec<u32>,
    /// -1 at a rope's first point on a hook, +1 at its last, 0 elsewhere.
    pub(crate) hook_sign: Vec<f64>,
    pub(crate) contact: Vec<u32>,
    pub(crate) sigma: Vec<f64>,
    pub(crate) rope_of: Vec<u32>,
    /// First point and one past the last point of each rope.
    pub(crate) ropes: Vec<(usize, usize)>,
    pub(crate) props: Vec<RopeProps>,
    pub(crate) nominal: Vec<f64>,
    pub(crate) plain: Vec<u32>,
    pub(crate) runs: Vec<(u32, u32)>,
    pub(crate) bend: Vec<(u32, f64)>,
    pub(crate) drag: Vec<(u32, f64)>,
    pub(crate) contact_point: Vec<u32>,
    pub(crate) contact_init: Vec<(f64, ContactInit)>,
    /// Edge friction of each contact slot with its stiffness [N/m] and damping [N s/m].
    pub(crate) holds: Vec<Option<(EdgeHold, f64, f64)>>,
    pub(crate) hooks: Vec<HookInit>,
    /// Slack segments report a taut segment's stiffness (static solves only).
    pub(crate) taut_tangent: TautTangent,
}

/// The switch behind [`RopeEffect::set_taut_tangent`]: shared by the model and the scene's handle
/// of the effect (an `Arc`), so an atomic.
#[derive(Debug, Default)]
pub(crate) struct TautTangent(std::sync::atomic::AtomicBool);

impl Clone for TautTangent {
    fn clone(&self) -> Self {
        TautTangent(std::sync::atomic::AtomicBool::new(self.get()))
    }
}

impl TautTangent {
    #[inline]
    pub(crate) fn get(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
}

impl RopeEffect {
    /// Builds the effect from rope layouts and hooks; `Err` names the rope and point at fault.
    pub fn new(ropes: &[LayoutRope], hooks: &[HookInit]) -> Result<Self, String> {
        let mut e = RopeEffect {
            body: Vec::new(),
            local: Vec::new(),
            hook: Vec::new(),
            hook_sign: Vec::new(),
            contact: Vec::new(),
            sigma: Vec::new(),
            rope_of: Vec::new(),
            ropes: Vec::new(),
            props: Vec::new(),
            nominal: Vec::new(),
            plain: Vec::new(),
            runs: Vec::new(),
            bend: Vec::new(),
            drag: Vec::new(),
            contact_point: Vec::new(),
            contact_init: Vec::new(),
            holds: Vec::new(),
            hooks: hooks.to_vec(),
            taut_tangent: TautTangent::default(),
        };
        for (k, h) in hooks.iter().enumerate() {
            let vals = [h.t0, h.payout, h.payout_rate, h.target_payout_rate, h.ramp];
            let vecs = h
                .position
                .iter()
                .chain(h.velocity.iter())
                .chain(h.target_velocity.iter())
                .chain(h.target_position.iter());
            if !(vecs.into_iter().all(|x| x.is_finite()) && vals.iter().all(|x| x.is_finite())) {
                return Err(format!(
                    "hook {k}: position, velocity or pay-out is not finite"
                ));
            }
            if h.ramp < 0.0 {
                return Err(format!(
                    "hook {k}: ramp time must be >= 0 s, got {}",
                    h.ramp
                ));
            }
        }
        for (r, rope) in ropes.iter().enumerate() {
            let owner = format!("rope {r}");
            rope.props.validate(&owner)?;
            if !(rope.nominal_segment.is_finite() && rope.nominal_segment > 0.0) {
                return Err(format!(
                    "{owner}: nominal segment length must be finite and > 0, got {}",
                    rope.nominal_segment
                ));
            }
            let n = rope.points.len();
            if n < 2 {
                return Err(format!("{owner}: needs at least 2 points, has {n}"));
            }
            let first = e.body.len();
            for (i, p) in rope.points.iter().enumerate() {
                if !p.sigma.is_finite() {
                    return Err(format!(
                        "{owner}, point {i}: material coordinate is not finite"
                    ));
                }
                if i > 0 && p.sigma <= rope.points[i - 1].sigma {
                    return Err(format!(
                        "{owner}, segment {}: rest length {} m must be > 0 (material coordinates must increase)",
                        i - 1,
                        p.sigma - rope.points[i - 1].sigma
                    ));
                }
                let (body, local, hook) = match p.at {
                    PointAt::Body { body, local } => {
                        if !local.iter().all(|x| x.is_finite()) {
                            return Err(format!("{owner}, point {i}: offset is not finite"));
                        }
                        (body, local, NONE)
                    }
                    PointAt::Hook(k) => {
                        if k >= hooks.len() {
                            return Err(format!(
                                "{owner}, point {i}: hook {k} does not exist ({} hooks)",
                                hooks.len()
                            ));
                        }
                        if i != 0 && i != n - 1 {
                            return Err(format!(
                                "{owner}, point {i}: a hook can only be a rope end"
                            ));
                        }
                        (BodyId::GROUND, Vec3::zeros(), k as u32)
                    }
                };
                let contact = match p.contact {
                    Some(ci) => {
                        if i == 0 || i == n - 1 {
                            return Err(format!(
                                "{owner}, point {i}: a contact node cannot be a rope end"
                            ));
                        }
                        if hook != NONE || body.is_ground() || local != Vec3::zeros() {
                            return Err(format!(
                                "{owner}, point {i}: a contact node must be a particle (offset 0)"
                            ));
                        }
                        let ok = |x: f64| x.is_finite() && x >= 0.0;
                        if !(ok(ci.mu_rope) && ok(ci.mu)) {
                            return Err(format!(
                                "{owner}, point {i}: friction coefficient and share must be finite and >= 0"
                            ));
                        }
                        if let Some(h) = ci.hold {
                            let ok = [h.u0, h.cap].iter().all(|x| x.is_finite())
                                && h.point.iter().chain(h.dir.iter()).all(|x| x.is_finite())
                                && (h.dir.norm() - 1.0).abs() < 1e-9
                                && h.cap >= 0.0;
                            if !ok {
                                return Err(format!(
                                    "{owner}, point {i}: edge hold needs a finite point, a unit direction and a finite capacity >= 0"
                                ));
                            }
                        }
                        e.contact_point.push(e.body.len() as u32);
                        e.contact_init.push((p.sigma, ci));
                        // stick stiffness along the edge: ten times a nominal segment's axial
                        // stiffness; damping with a 0.1 ms time constant. A frictionless edge
                        // holds nothing along it: the node slides freely (the element stays
                        // to measure the node's coordinate along the edge)
                        let k = if rope.props.friction > 0.0 {
                            10.0 * rope.props.ea / rope.nominal_segment
                        } else {
                            0.0
                        };
                        e.holds.push(ci.hold.map(|h| (h, k, 1e-4 * k)));
                        (e.contact_point.len() - 1) as u32
                    }
                    None => NONE,
                };
                e.body.push(body);
                e.local.push(local);
                e.hook.push(hook);
                e.hook_sign.push(if hook == NONE {
                    0.0
                } else if i == 0 {
                    -1.0
                } else {
                    1.0
                });
                e.contact.push(contact);
                e.sigma.push(p.sigma);
                e.rope_of.push(r as u32);
            }
            let end = e.body.len();
            e.ropes.push((first, end));
            e.props.push(rope.props);
            e.nominal.push(rope.nominal_segment);
            // classify segments
            let mut i = first;
            while i + 1 < end {
                let (ca, cb) = (e.contact[i] != NONE, e.contact[i + 1] != NONE);
                if !ca && !cb {
                    e.plain.push(i as u32);
                    i += 1;
                } else if !ca && cb {
                    let s = i + 1;
                    let mut last = s;
                    while e.contact[last + 1] != NONE {
                        last += 1;
                    }
                    e.runs.push((s as u32, last as u32));
                    i = last + 1;
                } else {
                    unreachable!("runs start at a material point");
                }
            }
            let pr = rope.props;
            for i in first + 1..end.saturating_sub(1) {
                if e.contact[i] != NONE || e.hook[i] != NONE {
                    continue;
                }
                if pr.bending_stiffness > 0.0 {
                    e.bend
                        .push((i as u32, pr.bending_stiffness / rope.nominal_segment));
                }
                if pr.drag_factor() > 0.0 && e.local[i] == Vec3::zeros() {
                    e.drag
                        .push((i as u32, pr.drag_factor() * rope.nominal_segment));
                }
            }
        }
        Ok(e)
    }

    /// While on, the Jacobian of a slack plain segment is that of a taut one (`EA/L` along the
    /// segment) instead of zero; forces, energies and tensions are unchanged. A static solve that
    /// starts from just-taut slings (zero tension, zero stiffness: the block would only fall)
    /// turns it on for its first Newton steps, so the first step stretches the slings to carry the
    /// load. Off for time integration.
    pub fn set_taut_tangent(&self, on: bool) {
        self.taut_tangent
            .0
            .store(on, std::sync::atomic::Ordering::Relaxed);
    }

    /// Number of rope points (all ropes).
    pub fn n_points(&self) -> usize {
        self.body.len()
    }

    /// Number of contact nodes.
    pub fn n_contacts(&self) -> usize {
        self.contact_point.len()
    }

    /// Number of hooks.
    pub fn n_hooks(&self) -> usize {
        self.hooks.len()
    }

    /// Ranges of the ropes' points: `(first, one past last)`.
    pub fn rope_ranges(&self) -> &[(usize, usize)] {
        &self.ropes
    }

    /// Properties of rope `r`.
    pub fn rope_props(&self, r: usize) -> &RopeProps {
        &self.props[r]
    }

    /// Point index of contact slot `c`.
    pub fn contact_point(&self, c: usize) -> usize {
        self.contact_point[c] as usize
    }

    /// Contact slot of point `i`, if it is a contact node.
    pub fn contact_of(&self, i: usize) -> Option<usize> {
        (self.contact[i] != NONE).then_some(self.contact[i] as usize)
    }

    /// The typed view of this effect's memory `memory` (its first value on).
    pub fn memory<'a>(&self, memory: &'a [f64]) -> RopeMemory<&'a [f64]> {
        RopeMemory::new(memory, self.hooks.len())
    }

    /// The writable typed view of this effect's memory `memory` (its first value on).
    pub fn memory_mut<'a>(&self, memory: &'a mut [f64]) -> RopeMemory<&'a mut [f64]> {
        RopeMemory::new(memory, self.hooks.len())
    }

    /// Contact slot `c`'s record in this effect's memory `memory`.
    #[inline]
    fn contact_record<'a>(&self, memory: &'a [f64], c: usize) -> ContactRecord<&'a [f64]> {
        RopeMemory::new(memory, self.hooks.len()).contact(c)
    }

    /// Position [m] and velocity [m/s] (world) of hook `k` at time `t` given the effect memory.
    pub fn hook_motion(&self, memory: &[f64], k: usize, t: f64) -> (Vec3, Vec3) {
        let h = self.memory(memory).hook(k).get();
        let tau = t - h.t0;
        let mut x = Vec3::zeros();
        let mut v = Vec3::zeros();
        let position = h.mode == HookMode::Position;
        for i in 0..3 {
            (x[i], v[i]) = if position {
                hermite(
                    h.position[i],
                    h.velocity[i],
                    h.target_position[i],
                    h.ramp,
                    tau,
                )
            } else {
                ramped(
                    h.position[i],
                    h.velocity[i],
                    h.target_velocity[i],
                    h.ramp,
                    tau,
                )
            };
        }
        (x, v)
    }

    /// Target velocity [m/s] of hook `k` and its target pay-out rate [m/s].
    pub fn hook_targets(&self, memory: &[f64], k: usize) -> (Vec3, f64) {
        let h = self.memory(memory).hook(k);
        (h.target_velocity(), h.target_payout_rate())
    }

    /// Command mode of hook `k` and its target position [m] (world; used in
    /// [`HookMode::Position`]).
    pub fn hook_position_target(&self, memory: &[f64], k: usize) -> (HookMode, Vec3) {
        let h = self.memory(memory).hook(k);
        (h.mode(), h.target_position())
    }

    /// Pay-out [m] and its rate [m/s] of hook `k` at time `t`.
    pub fn hook_payout(&self, memory: &[f64], k: usize, t: f64) -> (f64, f64) {
        let h = self.memory(memory).hook(k);
        ramped(
            h.payout(),
            h.payout_rate(),
            h.target_payout_rate(),
            h.ramp(),
            t - h.t0(),
        )
    }

    /// Writes hook `k`'s state into the memory (see [`HookInit`]).
    pub fn write_hook(&self, memory: &mut [f64], k: usize, h: &HookInit) {
        self.memory_mut(memory).hook_mut(k).set(h);
    }

    /// Kinematics of the body carrying point `i` (ground for hooks).
    #[inline]
    pub(crate) fn kin<'a>(&self, ctx: &'a EvalCtx, i: usize) -> &'a BodyKin {
        if self.hook[i] != NONE {
            &BodyKin::GROUND
        } else {
            kin_of(ctx.kins, self.body[i])
        }
    }

    /// World position [m] and velocity [m/s] of point `i`.
    #[inline]
    pub fn point_state(&self, ctx: &EvalCtx, i: usize) -> (Vec3, Vec3) {
        if self.hook[i] != NONE {
            self.hook_motion(ctx.memory, self.hook[i] as usize, ctx.t)
        } else {
            let k = kin_of(ctx.kins, self.body[i]);
            let s = &self.local[i];
            (k.point(s), k.point_velocity(s))
        }
    }

    /// Material coordinate [m] of point `i` (hooks include the pay-out, contact nodes read their
    /// last accepted value from the memory).
    #[inline]
    pub fn sigma_at(&self, ctx: &EvalCtx, i: usize) -> f64 {
        if self.hook[i] != NONE {
            let (s, _) = self.hook_payout(ctx.memory, self.hook[i] as usize, ctx.t);
            self.sigma[i] + self.hook_sign[i] * s
        } else if self.contact[i] != NONE {
            self.contact_record(ctx.memory, self.contact[i] as usize)
                .sigma()
        } else {
            self.sigma[i]
        }
    }

    /// Evaluates the edge friction of contact slot `c` (`None` without one).
    pub fn edge_hold(&self, ctx: &EvalCtx, c: usize) -> Option<edge_hold::Hold> {
        let (h, k, damp) = self.holds[c]?;
        let node = kin_of(ctx.kins, self.body[self.contact_point[c] as usize]);
        let block = kin_of(ctx.kins, h.block);
        if let Some(force) = self.edge_slide_force(ctx.memory, c) {
            return Some(edge_hold::sliding(node, block, &h.point, &h.dir, force));
        }
        Some(edge_hold::eval(
            node,
            block,
            &h.point,
            &h.dir,
            self.contact_record(ctx.memory, c).anchor(),
            k,
            damp,
        ))
    }

    /// The friction force [N] on contact slot `c`'s coordinate along its edge while the node
    /// slides along the edge (memory: the sliding state, the force's sign, and the capacity,
    /// its magnitude); `None` while it sticks there (the hold's spring acts).
    #[inline]
    pub fn edge_slide_force(&self, memory: &[f64], c: usize) -> Option<f64> {
        let rec = self.contact_record(memory, c);
        let state = rec.edge_slide();
        (state != 0.0).then(|| state.signum() * rec.cap())
    }

    /// The edge (block, point, direction) of contact slot `c`, if it has edge friction.
    pub fn contact_edge(&self, c: usize) -> Option<EdgeHold> {
        self.holds[c].map(|h| h.0)
    }

    /// Slip state of the last accepted step and friction share along the rope of contact slot
    /// `c` from the memory.
    #[inline]
    pub fn contact_state(&self, memory: &[f64], c: usize) -> (SlipMode, f64) {
        let rec = self.contact_record(memory, c);
        (rec.mode(), rec.share())
    }

    /// The friction law of contact slot `c`'s cone (its rope's `friction_law`).
    #[inline]
    pub fn friction_law(&self, c: usize) -> super::friction::FrictionLaw {
        let p = self.contact_point[c] as usize;
        self.props[self.rope_of[p] as usize].friction_law
    }

    /// Coefficient `mu` of contact slot `c`'s Coulomb cone from the memory.
    #[inline]
    pub fn contact_mu(&self, memory: &[f64], c: usize) -> f64 {
        self.contact_record(memory, c).mu()
    }

    /// The world direction of contact slot `c`'s edge at `ctx` (`None` without an edge hold).
    pub fn edge_direction(&self, ctx: &EvalCtx, c: usize) -> Option<Vec3> {
        let (h, _, _) = self.holds[c]?;
        Some(kin_of(ctx.kins, h.block).rot * h.dir)
    }

    /// The anchor [m] that makes the hold of contact slot `c` push the node with `force` [N]
    /// along its edge at `ctx` (`None` without a hold or without stiffness along the edge).
    pub fn hold_anchor_for(&self, ctx: &EvalCtx, c: usize, force: f64) -> Option<f64> {
        let (_, k, damp) = self.holds[c]?;
        if k <= 0.0 {
            return None;
        }
        let h = self.edge_hold(ctx, c)?;
        // force = -(k (u - u0) + c u_dot)
        Some(h.u + (force + damp * h.u_dot) / k)
    }

    /// Rate [m/s] at which the rest length of a segment at a hook grows by pay-out.
    fn payout_rate_at(&self, ctx: &EvalCtx, i: usize) -> f64 {
        if self.hook[i] == NONE {
            0.0
        } else {
            self.hook_payout(ctx.memory, self.hook[i] as usize, ctx.t).1
        }
    }

    /// Rate of change [m/s] of the material coordinate of point `i` that is explicit in time
    /// (hook pay-out; zero elsewhere).
    #[inline]
    pub(crate) fn sigma_rate_at(&self, ctx: &EvalCtx, i: usize) -> f64 {
        self.hook_sign[i] * self.payout_rate_at(ctx, i)
    }

    /// Evaluates the plain segment starting at point `i`.
    #[inline]
    pub(crate) fn eval_plain(&self, ctx: &EvalCtx, i: usize) -> Seg {
        let (pa, va) = self.point_state(ctx, i);
        let (pb, vb) = self.point_state(ctx, i + 1);
        let rest = self.sigma_at(ctx, i + 1) - self.sigma_at(ctx, i);
        let rate = self.sigma_rate_at(ctx, i + 1) - self.sigma_rate_at(ctx, i);
        plain_segment(
            &pa,
            &pb,
            &va,
            &vb,
            rest,
            rate,
            &self.props[self.rope_of[i] as usize],
            self.taut_tangent.get(),
        )
    }

    /// Evaluates run `r` (its points, forces, tensions and material flow; no derivative blocks).
    pub(crate) fn eval_run(&self, ctx: &EvalCtx, r: usize) -> RunEval {
        run::eval(self, ctx, self.runs[r], Derivatives::None)
    }
}

/// How far [m], in position weights of a segment (`atol + rtol * rest length`), the material
/// coordinate of a contact node on the slip modes frozen for a Newton iteration may lie from the
/// one the return mapping settles on at the converged iterate (see
/// [`ForceEffect::frozen_consistent`]). One weight: the Newton test is a weighted RMS over all
/// coordinates, so a converged iterate's error at a single node can be of that order (0.02 of
/// the weight times the square root of the number of coordinates); near a slip reversal the
/// sticking band of a node is narrower than that, and a tighter check (0.1 was tried) keeps
/// re-deciding: the default lift at rtol 3e-5 took 3.3 s and 3104 Newton failures, against
/// 0.30 s and 75 with one weight, at the same peak tension.
const FROZEN_SLIP_TOL: f64 = 1.0;

impl ForceEffect for RopeEffect {
    fn name(&self) -> &str {
        "rope"
    }

    fn add_forces(&self, ctx: &EvalCtx, f: &mut [f64]) {
        for &i in &self.plain {
            let i = i as usize;
            let s = self.eval_plain(ctx, i);
            crate::effect::point_force::add_point_force(
                self.kin(ctx, i),
                &self.local[i],
                &s.force,
                f,
            );
            crate::effect::point_force::add_point_force(
                self.kin(ctx, i + 1),
                &self.local[i + 1],
                &(-s.force),
                f,
            );
        }
        for r in 0..self.runs.len() {
            let ev = self.eval_run(ctx, r);
            for (k, &p) in ev.points.iter().enumerate() {
                crate::effect::point_force::add_point_force(
                    self.kin(ctx, p),
                    &self.local[p],
                    &ev.force[k],
                    f,
                );
            }
        }
        for &(i, k) in &self.bend {
            let i = i as usize;
            let p: [Vec3; 3] = std::array::from_fn(|a| self.point_state(ctx, i - 1 + a).0);
            let h = bending::hinge(k, &p[0], &p[1], &p[2]);
            for a in 0..3 {
                let j = i - 1 + a;
                crate::effect::point_force::add_point_force(
                    self.kin(ctx, j),
                    &self.local[j],
                    &h.force[a],
                    f,
                );
            }
        }
        for &(i, k) in &self.drag {
            let i = i as usize;
            let (_, v) = self.point_state(ctx, i);
            let (force, _) = drag::drag(k, &v);
            crate::effect::point_force::add_point_force(
                self.kin(ctx, i),
                &self.local[i],
                &force,
                f,
            );
        }
        for c in 0..self.holds.len() {
            if let (Some(h), Some((eh, _, _))) = (self.edge_hold(ctx, c), self.holds[c]) {
                let node = kin_of(ctx.kins, self.body[self.contact_point[c] as usize]);
                edge_hold::add_forces(&h, node, kin_of(ctx.kins, eh.block), &eh.dir, f);
            }
        }
    }

    fn add_jacobian(&self, ctx: &EvalCtx, sink: &mut dyn JacobianSink) {
        for &i in &self.plain {
            let i = i as usize;
            let s = self.eval_plain(ctx, i);
            TwoPointForce {
                a: self.kin(ctx, i),
                s_a: self.local[i],
                b: self.kin(ctx, i + 1),
                s_b: self.local[i + 1],
                force: s.force,
                kd: s.kd,
                cd: s.cd,
            }
            .add_jacobian(sink);
        }
        // sliding chains keep their dense stiffness as factors where the sink borders the
        // system (or assembles no stiffness), else emit it as blocks
        let deriv = match sink.aux_support() {
            AuxSupport::None => Derivatives::Dense,
            AuxSupport::Skip | AuxSupport::Rows => Derivatives::Bordered,
        };
        for r in 0..self.runs.len() {
            let ev = run::eval(self, ctx, self.runs[r], deriv);
            run::emit(self, ctx, &ev, sink);
        }
        for &(i, k) in &self.bend {
            let i = i as usize;
            let p: [Vec3; 3] = std::array::from_fn(|a| self.point_state(ctx, i - 1 + a).0);
            let h = bending::hinge(k, &p[0], &p[1], &p[2]);
            let refs: [super::assemble::PointRef; 3] =
                std::array::from_fn(|a| super::assemble::PointRef {
                    kin: self.kin(ctx, i - 1 + a),
                    s: self.local[i - 1 + a],
                });
            let zero = Mat3::zeros();
            for a in 0..3 {
                for b in 0..3 {
                    let fa = (a == b).then_some(&h.force[a]);
                    super::assemble::add_pair(&refs[a], &refs[b], &h.jac[a][b], &zero, fa, sink);
                }
            }
        }
        for &(i, k) in &self.drag {
            let i = i as usize;
            let (_, v) = self.point_state(ctx, i);
            let (force, dfdv) = drag::drag(k, &v);
            let pr = super::assemble::PointRef {
                kin: self.kin(ctx, i),
                s: self.local[i],
            };
            super::assemble::add_pair(&pr, &pr, &Mat3::zeros(), &dfdv, Some(&force), sink);
        }
        for c in 0..self.holds.len() {
            if let (Some(h), Some((eh, _, _))) = (self.edge_hold(ctx, c), self.holds[c]) {
                let node = kin_of(ctx.kins, self.body[self.contact_point[c] as usize]);
                edge_hold::add_jacobian(&h, node, kin_of(ctx.kins, eh.block), &eh.dir, sink);
            }
        }
    }

    fn potential_energy(&self, ctx: &EvalCtx) -> f64 {
        let mut e = 0.0;
        for &i in &self.plain {
            let i = i as usize;
            let (pa, _) = self.point_state(ctx, i);
            let (pb, _) = self.point_state(ctx, i + 1);
            let rest = self.sigma_at(ctx, i + 1) - self.sigma_at(ctx, i);
            e += segment::strain_energy(
                self.props[self.rope_of[i] as usize].ea,
                (pb - pa).norm(),
                rest,
            );
        }
        for r in 0..self.runs.len() {
            e += self.eval_run(ctx, r).energy;
        }
        for &(i, k) in &self.bend {
            let i = i as usize;
            let p: [Vec3; 3] = std::array::from_fn(|a| self.point_state(ctx, i - 1 + a).0);
            e += bending::hinge(k, &p[0], &p[1], &p[2]).energy;
        }
        for c in 0..self.holds.len() {
            if self.edge_slide_force(ctx.memory, c).is_some() {
                // sliding: no spring stores energy
                continue;
            }
            if let (Some(h), Some((_, k, _))) = (self.edge_hold(ctx, c), self.holds[c]) {
                let u0 = self.contact_record(ctx.memory, c).anchor();
                e += 0.5 * k * (h.u - u0) * (h.u - u0);
            }
        }
        e
    }

    fn dissipated_power(&self, ctx: &EvalCtx) -> f64 {
        let mut p = 0.0;
        for &i in &self.plain {
            let s = self.eval_plain(ctx, i as usize);
            // the dashpot's own rate, not `l_dot`: while a winch pays out, `l_dot` also carries
            // the rest length's growth, which is no dissipation (its share goes to the winch's
            // input power below)
            p += (s.law.t - s.elastic) * s.dashpot_rate;
        }
        for r in 0..self.runs.len() {
            let ev = self.eval_run(ctx, r);
            p += ev.damping_power + ev.friction_power;
        }
        for &(i, k) in &self.drag {
            let (_, v) = self.point_state(ctx, i as usize);
            p -= drag::drag(k, &v).0.dot(&v);
        }
        for c in 0..self.holds.len() {
            if let (Some(h), Some((_, k, _))) = (self.edge_hold(ctx, c), self.holds[c]) {
                // the force's work rate beyond the stored spring energy's rate (all of it while
                // the node slides: sliding friction)
                let stored = if self.edge_slide_force(ctx.memory, c).is_some() {
                    0.0
                } else {
                    k * (h.u - self.contact_record(ctx.memory, c).anchor())
                };
                p -= (h.force + stored) * h.u_dot;
            }
        }
        p
    }

    fn input_power(&self, ctx: &EvalCtx) -> f64 {
        if self.hooks.is_empty() {
            return 0.0;
        }
        let mut p = 0.0;
        for &i in &self.plain {
            let i = i as usize;
            let (ha, hb) = (self.hook[i] != NONE, self.hook[i + 1] != NONE);
            if !ha && !hb {
                continue;
            }
            let s = self.eval_plain(ctx, i);
            if ha {
                p -= s.force.dot(&self.point_state(ctx, i).1);
            }
            if hb {
                p += s.force.dot(&self.point_state(ctx, i + 1).1);
            }
            let rate = self.payout_rate_at(ctx, i) + self.payout_rate_at(ctx, i + 1);
            if rate != 0.0 {
                let ea = self.props[self.rope_of[i] as usize].ea;
                let rest = self.sigma_at(ctx, i + 1) - self.sigma_at(ctx, i);
                p -= winch_pull(ea, &s, rest) * rate;
            }
        }
        for r in 0..self.runs.len() {
            let (a, b) = self.runs[r];
            let (a, b) = (a as usize - 1, b as usize + 1);
            if self.hook[a] == NONE && self.hook[b] == NONE {
                continue;
            }
            let ev = self.eval_run(ctx, r);
            let last = ev.points.len() - 1;
            if self.hook[a] != NONE {
                p -= ev.force[0].dot(&self.point_state(ctx, a).1);
            }
            if self.hook[b] != NONE {
                p -= ev.force[last].dot(&self.point_state(ctx, b).1);
            }
        }
        p
    }

    fn n_memory(&self) -> usize {
        RopeMemory::<&[f64]>::len(self.hooks.len(), self.contact_point.len())
    }

    fn init_memory(&self, _ctx: &EvalCtx, memory: &mut [f64]) {
        let mut mem = self.memory_mut(memory);
        for (k, h) in self.hooks.iter().enumerate() {
            mem.hook_mut(k).set(h);
        }
        for (c, (sigma, ci)) in self.contact_init.iter().enumerate() {
            let mut rec = mem.contact_mut(c);
            rec.set_sigma(*sigma);
            rec.set_mode(ci.mode);
            rec.set_share(ci.mu_rope);
            if let Some(h) = ci.hold {
                rec.set_anchor(h.u0);
                rec.set_cap(h.cap);
            }
            rec.set_edge_slide(0.0);
            rec.set_mu(ci.mu);
        }
    }

    fn has_decisions(&self) -> bool {
        !self.runs.is_empty()
    }

    fn freeze(&self, ctx: &EvalCtx, out: &mut Vec<f64>) {
        if self.runs.is_empty() {
            return;
        }
        let free = EvalCtx {
            frozen: &[],
            ..*ctx
        };
        out.resize(2 * self.n_contacts(), SlipMode::Stick.code());
        for r in 0..self.runs.len() {
            let ev = self.eval_run(&free, r);
            for k in 1..ev.points.len() - 1 {
                let c = self.contact[ev.points[k]] as usize;
                let code = ev.modes[k].code();
                // a slide that converged where the node slides the other way: the reversal
                // passes through sticking, which the return mapping from the step's start skips
                // (its trial stick already leaves the band on one side or the other)
                out[2 * c] = match ctx.frozen.get(2 * c) {
                    Some(&old) if old * code < 0.0 => SlipMode::Stick.code(),
                    _ => code,
                };
                out[2 * c + 1] = ev.share[k];
            }
        }
    }

    fn frozen_consistent(&self, ctx: &EvalCtx, rtol: f64, atol: f64) -> bool {
        if ctx.frozen.is_empty() {
            return true;
        }
        let free = EvalCtx {
            frozen: &[],
            ..*ctx
        };
        (0..self.runs.len()).all(|r| {
            let ev = self.eval_run(&free, r);
            let np = ev.points.len();
            if (1..np - 1)
                .all(|k| ctx.frozen[2 * self.contact[ev.points[k]] as usize] == ev.modes[k].code())
            {
                return true;
            }
            // modes differ: the two branches' material coordinates must agree to the position
            // tolerance of a segment (the Newton iterate itself is only that accurate)
            let fz = self.eval_run(ctx, r);
            (1..np - 1).all(|k| {
                let l = ev.rest[k - 1].min(ev.rest[k]).abs();
                (fz.sigma[k] - ev.sigma[k]).abs() <= FROZEN_SLIP_TOL * (atol + rtol * l)
            })
        })
    }

    fn update_memory(&self, ctx: &EvalCtx, memory: &mut [f64]) -> MemoryChange {
        // accept the sliding of this step: every node's material coordinate, slip state and share
        // become the start of the next step's return mapping (the forces at this instant are
        // unchanged). `ctx` carries the decisions the accepted step was solved on when it was
        // frozen (see `System::update_memory`), so the memory holds what acted
        let mut changed = false;
        for r in 0..self.runs.len() {
            let ev = self.eval_run(ctx, r);
            for (k, &p) in ev.points.iter().enumerate() {
                if let Some(c) = self.contact_of(p) {
                    let mut rec = self.memory_mut(memory).into_contact(c);
                    let (sigma, mode, share) = (ev.sigma[k], ev.modes[k], ev.share[k]);
                    if rec.sigma() != sigma
                        || rec.mode_code() != mode.code()
                        || rec.share() != share
                    {
                        rec.set_sigma(sigma);
                        rec.set_mode(mode);
                        rec.set_share(share);
                        changed = true;
                    }
                }
            }
        }
        if changed {
            MemoryChange::Smooth
        } else {
            MemoryChange::None
        }
    }
}

/// The state of a contact node's two segments at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NodeSegments {
    /// Tension [N] of the segment towards the previous and the next point.
    pub t_prev: f64,
    pub t_next: f64,
    /// Rest lengths [m] of those segments.
    pub rest_prev: f64,
    pub rest_next: f64,
    /// Material coordinate [m] at the node and its rate [m/s] (negative while the rope slides
    /// towards the next point).
    pub sigma: f64,
    pub sigma_rate: f64,
}

impl RopeEffect {
    /// Segment states of every contact node (index = contact slot), evaluating each run once.
    /// Evaluated with the decisions in the memory (those of the last accepted step, see
    /// [`RopeEffect::accepted_decisions`]) unless `ctx` carries decisions.
    pub fn contact_segments(&self, ctx: &EvalCtx) -> Vec<NodeSegments> {
        let mut out = vec![NodeSegments::default(); self.contact_point.len()];
        let decided = self.accepted_decisions(ctx);
        let ctx = &with_decisions(ctx, &decided);
        for r in 0..self.runs.len() {
            let ev = self.eval_run(ctx, r);
            for k in 1..ev.points.len() - 1 {
                if let Some(c) = self.contact_of(ev.points[k]) {
                    out[c] = NodeSegments {
                        t_prev: ev.tension[k - 1],
                        t_next: ev.tension[k],
                        rest_prev: ev.rest[k - 1],
                        rest_next: ev.rest[k],
                        sigma: ev.sigma[k],
                        sigma_rate: ev.sigma_rate[k],
                    };
                }
            }
        }
        out
    }

    /// Tension [N] and rest length [m] of every segment of rope `r`, in order; runs evaluated with
    /// the decisions in the memory unless `ctx` carries decisions (as
    /// [`RopeEffect::contact_segments`]).
    pub fn rope_tensions(&self, ctx: &EvalCtx, r: usize) -> Vec<(f64, f64)> {
        let decided = self.accepted_decisions(ctx);
        let ctx = &with_decisions(ctx, &decided);
        let (first, end) = self.ropes[r];
        let mut out = vec![(0.0, 0.0); end - first - 1];
        for i in first..end - 1 {
            if self.contact[i] == NONE && self.contact[i + 1] == NONE {
                let s = self.eval_plain(ctx, i);
                out[i - first] = (s.law.t, self.sigma_at(ctx, i + 1) - self.sigma_at(ctx, i));
            }
        }
        for (k, &(a, b)) in self.runs.iter().enumerate() {
            if (a as usize) < first || (b as usize) >= end {
                continue;
            }
            let ev = self.eval_run(ctx, k);
            for j in 0..ev.tension.len() {
                out[ev.points[j] - first] = (ev.tension[j], ev.rest[j]);
            }
        }
        out
    }
}

impl RopeEffect {
    /// The decisions stored in the memory of `ctx` (slip state code and share per contact slot,
    /// the layout of the frozen decisions): those of the last accepted step. Empty when `ctx`
    /// carries decisions already (they are used instead).
    pub fn accepted_decisions(&self, ctx: &EvalCtx) -> Vec<f64> {
        if !ctx.frozen.is_empty() {
            return Vec::new();
        }
        let mut out = Vec::with_capacity(2 * self.n_contacts());
        for c in 0..self.n_contacts() {
            let (mode, share) = self.contact_state(ctx.memory, c);
            out.extend([mode.code(), share]);
        }
        out
    }

    /// Stick or slide of every contact node (index = contact slot) as the return mapping settles
    /// it at `ctx` (the memory holds the state of the last accepted step).
    pub fn contact_modes(&self, ctx: &EvalCtx) -> Vec<SlipMode> {
        let mut out = vec![SlipMode::Stick; self.contact_point.len()];
        for r in 0..self.runs.len() {
            let ev = self.eval_run(ctx, r);
            for (k, &p) in ev.points.iter().enumerate() {
                if let Some(c) = self.contact_of(p) {
                    out[c] = ev.modes[k];
                }
            }
        }
        out
    }
}

/// `ctx` evaluated on `decided` (the decisions of the last accepted step, see
/// [`RopeEffect::accepted_decisions`]) unless it carries frozen decisions of its own.
fn with_decisions<'a>(ctx: &EvalCtx<'a>, decided: &'a [f64]) -> EvalCtx<'a> {
    EvalCtx {
        frozen: if ctx.frozen.is_empty() {
            decided
        } else {
            ctx.frozen
        },
        ..*ctx
    }
}
