//! A run: consecutive contact nodes of one rope with the segments around them, evaluated together.
//!
//! The run's points are the material point before the first contact node, the contact nodes, and
//! the material point after the last. Whether the rope slides through a node is decided inside
//! every evaluation by a *return mapping* from the node's last accepted material coordinate
//! `sigma_mem` and decisions (memory): the trial state has every node as the last accepted step
//! left it (warm start; a sticking node at `sigma = sigma_mem`, a sliding one with its share
//! `mu_rope`); a sticking node slides, in the direction of the larger tension, when its tensions
//! leave the band `1/r <= T_next/T_prev <= r` of the share `s` its Coulomb cone leaves along the
//! rope ([`super::friction`]: the hold's force along the edge and the rope's pull along the rope
//! against `mu N`), and keeps that share while it slides; a sliding node whose solved `sigma` moved
//! against its direction sticks again; this repeats until nothing changes (the active set of a
//! small complementarity problem). At the accepted state the warm start is already settled, so an
//! evaluation there reproduces the step's forces. Sticking nodes split the run into chains between
//! points of fixed material coordinate; a chain of one segment follows the plain law, a longer one
//! (whose interior nodes all slide) the friction-limited sliding of [`super::slip`]. The forces are
//! thus a continuous, piecewise smooth function of the positions and the memory, and a node can
//! never slide against its friction. The Jacobian has the blocks the modes couple (see [`emit`]):
//! the sparsity pattern changes when a node starts or stops sliding (before, every pair of the
//! run's points got a block, zero where uncoupled, so a run of 256 sticking nodes had a dense
//! Newton matrix).
//!
//! Within a step's Newton iteration the integrator may freeze the modes (`ctx.frozen`, one code
//! per contact slot, see [`RopeEffect`]'s `freeze`): the run is then evaluated on that smooth
//! branch without the return mapping, so successive iterates near a slip reversal cannot cycle
//! between modes; the integrator accepts the converged iterate only if the return mapping there
//! settles on the same modes.

use super::assemble::{PointRef, add_pair, generalized};
use super::effect::{RopeEffect, plain_segment};
use super::friction::{self, ContactFrame};
use super::layout::SlipMode;
use super::segment;
use super::slip::{ChainBorder, Derivatives, MAX_MU_TAN, SlipNode, edge_ratio, eval_chain};
use crate::effect::{AuxSupport, EvalCtx, JacobianSink};
use crate::math::{Mat3, Vec3, Vector6};

/// The evaluated run.
#[derive(Debug, Clone, Default)]
pub struct RunEval {
    /// Global point indices, in rope order.
    pub points: Vec<usize>,
    /// Force on each point [N] (world).
    pub force: Vec<Vec3>,
    /// `dF_a/dp_b`, `dF_a/dv_b`, row-major over the run's points (for a bordered chain only
    /// the sparse part; the dense part is in `borders`).
    pub jac: Vec<Mat3>,
    pub damp: Vec<Mat3>,
    /// Sliding chains whose dense Jacobian part is kept as factors: first point, factors.
    pub borders: Vec<(usize, ChainBorder)>,
    /// Tension [N] and rest length [m] of each segment (one fewer than points).
    pub tension: Vec<f64>,
    pub rest: Vec<f64>,
    /// Material coordinate [m] and its rate [m/s] at each point.
    pub sigma: Vec<f64>,
    pub sigma_rate: Vec<f64>,
    /// Stick or slide at each point (material points: stick).
    pub modes: Vec<SlipMode>,
    /// Friction coefficient along the rope of each sliding node (0 at material points).
    pub share: Vec<f64>,
    /// Elastic energy [J], damping and friction power [W].
    pub energy: f64,
    pub damping_power: f64,
    pub friction_power: f64,
}

/// Sliding chains of at least this many segments keep the dense part of their Jacobian as
/// factors under [`Derivatives::Bordered`] (a bordered chain of `m` segments adds `m`
/// auxiliary unknowns and about `26 m` matrix entries where its dense blocks are `9 (m + 1)^2`).
pub const BORDER_MIN_SEGMENTS: usize = 4;

/// Evaluates the run whose contact nodes are the points `first ..= last`, settling which nodes
/// slide (see the module documentation). The derivative blocks (`RunEval::jac`, `damp`) are
/// formed as `deriv` asks (they are `(m + 1)^2` for a run of `m + 1` points; everything else
/// costs O(m) per pass of the return mapping), else left empty. With
/// [`Derivatives::Bordered`] sliding chains of [`BORDER_MIN_SEGMENTS`] or more keep their dense
/// part as factors (`RunEval::borders`).
pub fn eval(
    e: &RopeEffect,
    ctx: &EvalCtx,
    (first, last): (u32, u32),
    deriv: Derivatives,
) -> RunEval {
    let (a, b) = (first as usize - 1, last as usize + 1);
    let np = b - a + 1;
    let mut pos = Vec::with_capacity(np);
    let mut vel = Vec::with_capacity(np);
    let mut sigma_mem = Vec::with_capacity(np);
    for i in a..=b {
        let (p, v) = e.point_state(ctx, i);
        pos.push(p);
        vel.push(v);
        sigma_mem.push(e.sigma_at(ctx, i));
    }
    let mut modes = vec![SlipMode::Stick; np];
    let mut share = vec![0.0; np];
    if !ctx.frozen.is_empty() {
        // decisions frozen for a Newton iteration (see `RopeEffect::freeze`), or those of the
        // accepted step for a report
        for k in 1..np - 1 {
            let c = e.contact[a + k] as usize;
            modes[k] = SlipMode::from_code(ctx.frozen[2 * c]);
            share[k] = ctx.frozen[2 * c + 1];
        }
        return eval_modes(e, ctx, a, &pos, &vel, &sigma_mem, &modes, &share, deriv);
    }
    for k in 1..np - 1 {
        (modes[k], share[k]) = e.contact_state(ctx.memory, e.contact[a + k] as usize);
    }
    let none = Derivatives::None;
    let mut ev = eval_modes(e, ctx, a, &pos, &vel, &sigma_mem, &modes, &share, none);
    for _ in 0..4 * np {
        let mut changed = false;
        for k in 1..np - 1 {
            match modes[k] {
                SlipMode::Stick => {
                    let c = e.contact[a + k] as usize;
                    let (tp, tn) = (ev.tension[k - 1], ev.tension[k]);
                    if let Some((m, s)) = starts_sliding(e, ctx, c, &pos[k - 1..=k + 1], tp, tn) {
                        modes[k] = m;
                        share[k] = s;
                        changed = true;
                    }
                }
                m => {
                    // sliding forward brings material from the previous side: sigma decreases
                    let moved = ev.sigma[k] - sigma_mem[k];
                    if moved * m.code() > 0.0 {
                        modes[k] = SlipMode::Stick;
                        changed = true;
                    }
                }
            }
        }
        if !changed {
            break;
        }
        ev = eval_modes(e, ctx, a, &pos, &vel, &sigma_mem, &modes, &share, none);
    }
    if deriv != Derivatives::None {
        // the settled modes again, now with the derivative blocks (same forces)
        ev = eval_modes(e, ctx, a, &pos, &vel, &sigma_mem, &modes, &share, deriv);
    }
    ev
}

/// Whether the rope starts sliding through the sticking contact node of slot `c` (points `p`:
/// previous, node, next; tensions `tp`, `tn` [N] of its segments): the node's Coulomb cone
/// leaves the share `s` along the rope ([`friction::FrictionLaw::rope_share`] of the hold's
/// force along the edge and the rope's pull at this trial, where the node sticks); the rope slides in the direction of the larger tension, with that
/// share, when the tensions leave the share's band.
fn starts_sliding(
    e: &RopeEffect,
    ctx: &EvalCtx,
    c: usize,
    p: &[Vec3],
    tp: f64,
    tn: f64,
) -> Option<(SlipMode, f64)> {
    let mu = e.contact_mu(ctx.memory, c);
    let turn = turn_angle(&p[0], &p[1], &p[2]);
    let (la, lb) = ((p[0] - p[1]).norm(), (p[2] - p[1]).norm());
    if la <= 0.0 || lb <= 0.0 {
        return None;
    }
    let (ea, eb) = ((p[0] - p[1]) / la, (p[2] - p[1]) / lb);
    let (s_fwd, s_bwd) = match e.edge_direction(ctx, c) {
        Some(edge) => {
            let frame = ContactFrame::new(&edge, &friction::any_normal(&edge), &ea, &eb);
            let pull = friction::rope_pull(&frame, &ea, &eb, tp, tn);
            let fe = e.edge_hold(ctx, c).map(|h| h.force).unwrap_or(0.0);
            let s = e
                .friction_law(c)
                .rope_share(mu, pull.normal, fe, pull.along_rope);
            if pull.normal > 0.0 {
                // the law's coefficient in the rope's plane that gives the share in the
                // edge's frame (they differ while the rope is tilted along the edge)
                let [f, b] = friction::plane_coefficients(&frame, &ea, &eb, turn, s);
                (f.unwrap_or(s), b.unwrap_or(s))
            } else {
                (s, s)
            }
        }
        // no element along the edge: the cone in the rope's plane is the band of mu
        None => (mu, mu),
    };
    for (s, mode) in [
        (s_fwd, SlipMode::SlipForward),
        (s_bwd, SlipMode::SlipBackward),
    ] {
        if s * (0.5 * turn).tan() >= MAX_MU_TAN {
            continue;
        }
        let (r, _) = edge_ratio(s, turn);
        let leaves = match mode {
            SlipMode::SlipForward => tn > r * tp,
            _ => tp > r * tn,
        };
        if leaves {
            return Some((mode, s));
        }
    }
    None
}

/// Turning angle [rad] of the rope at `p1` between `p0` and `p2`.
fn turn_angle(p0: &Vec3, p1: &Vec3, p2: &Vec3) -> f64 {
    let (u, w) = (p1 - p0, p2 - p1);
    let d = u.norm() * w.norm();
    if d <= 0.0 {
        return 0.0;
    }
    (u.dot(&w) / d).clamp(-1.0, 1.0).acos()
}

/// Evaluates the run for given slip modes of its nodes and shares of the sliding ones (the
/// derivative blocks as `deriv` asks).
#[allow(clippy::too_many_arguments)]
fn eval_modes(
    e: &RopeEffect,
    ctx: &EvalCtx,
    a: usize,
    pos: &[Vec3],
    vel: &[Vec3],
    sigma_mem: &[f64],
    modes: &[SlipMode],
    share: &[f64],
    deriv: Derivatives,
) -> RunEval {
    let with_jac = deriv != Derivatives::None;
    let np = pos.len();
    let blocks = if with_jac { np * np } else { 0 };
    let props = &e.props[e.rope_of[a] as usize];
    let mut ev = RunEval {
        points: (a..a + np).collect(),
        force: vec![Vec3::zeros(); np],
        jac: vec![Mat3::zeros(); blocks],
        damp: vec![Mat3::zeros(); blocks],
        tension: vec![0.0; np - 1],
        rest: vec![0.0; np - 1],
        sigma: vec![0.0; np],
        sigma_rate: vec![0.0; np],
        modes: modes.to_vec(),
        share: share.to_vec(),
        ..Default::default()
    };
    // chain boundaries: run ends and sticking nodes
    let mut bounds = vec![0usize];
    for (k, m) in modes.iter().enumerate().take(np - 1).skip(1) {
        if *m == SlipMode::Stick {
            bounds.push(k);
        }
    }
    bounds.push(np - 1);
    for w in bounds.windows(2) {
        let (k0, k1) = (w[0], w[1]);
        let (s0, s1) = (sigma_mem[k0], sigma_mem[k1]);
        let sdot0 = if e.hook[a + k0] != super::effect::NONE {
            e.hook_sign[a + k0] * e.hook_payout(ctx.memory, e.hook[a + k0] as usize, ctx.t).1
        } else {
            0.0
        };
        ev.sigma[k0] = s0;
        ev.sigma_rate[k0] = sdot0;
        ev.sigma[k1] = s1;
        if k1 - k0 == 1 {
            let rate = e.sigma_rate_at(ctx, a + k1) - sdot0;
            let s = plain_segment(
                &pos[k0],
                &pos[k1],
                &vel[k0],
                &vel[k1],
                s1 - s0,
                rate,
                props,
                e.taut_tangent.get(),
            );
            ev.tension[k0] = s.law.t;
            ev.rest[k0] = s1 - s0;
            ev.energy += segment::strain_energy(props.ea, s.l, s1 - s0);
            ev.damping_power += (s.law.t - s.elastic) * s.ldot;
            ev.force[k0] += s.force;
            ev.force[k1] -= s.force;
            if !with_jac {
                continue;
            }
            ev.jac[k0 * np + k0] -= s.kd;
            ev.jac[k0 * np + k1] += s.kd;
            ev.jac[k1 * np + k0] += s.kd;
            ev.jac[k1 * np + k1] -= s.kd;
            ev.damp[k0 * np + k0] -= s.cd;
            ev.damp[k0 * np + k1] += s.cd;
            ev.damp[k1 * np + k0] += s.cd;
            ev.damp[k1 * np + k1] -= s.cd;
            continue;
        }
        let nodes: Vec<SlipNode> = (k0 + 1..k1)
            .map(|k| SlipNode {
                direction: modes[k].code(),
                mu: share[k],
            })
            .collect();
        let m = k1 - k0;
        let chain_deriv = match deriv {
            Derivatives::Bordered if m < BORDER_MIN_SEGMENTS => Derivatives::Dense,
            d => d,
        };
        let mut ch = eval_chain(
            &pos[k0..=k1],
            &vel[k0..=k1],
            &nodes,
            s1 - s0,
            props.ea,
            chain_deriv,
        );
        if let Some(b) = ch.border.take() {
            ev.borders.push((k0, b));
        }
        let mut sig = s0;
        let mut sdot = sdot0;
        for j in 0..m {
            ev.tension[k0 + j] = ch.tension[j];
            ev.rest[k0 + j] = ch.rest[j];
            if j > 0 {
                ev.sigma[k0 + j] = sig;
                ev.sigma_rate[k0 + j] = sdot;
            }
            sig += ch.rest[j];
            sdot += ch.rest_rate[j];
        }
        ev.energy += ch.energy;
        ev.friction_power += ch.friction_power;
        let mp = m + 1;
        for x in 0..mp {
            ev.force[k0 + x] += ch.force[x];
            if !with_jac {
                continue;
            }
            for y in 0..mp {
                ev.jac[(k0 + x) * np + k0 + y] += ch.jac[x * mp + y];
            }
        }
    }
    ev
}

/// Emits the blocks of an evaluated run that its slip modes couple: the points of one chain
/// (between sticking nodes or the run's ends, which belong to both chains they bound) with each
/// other, and neighbours. A run of sticking nodes is thus block-tridiagonal, and only a sliding
/// chain fills its square; the pattern changes when a node starts or stops sliding (the linear
/// solver then analyses it anew). A bordered chain (`RunEval::borders`) couples only
/// neighbours directly and its dense part goes through auxiliary unknowns ([`emit_border`]);
/// where the sink does not assemble stiffness ([`AuxSupport::Skip`]) that part is left out.
pub fn emit(e: &RopeEffect, ctx: &EvalCtx, ev: &RunEval, sink: &mut dyn JacobianSink) {
    let np = ev.points.len();
    // sticks[i]: sticking contact nodes (interior points) among the points before i
    let mut sticks = vec![0usize; np + 1];
    for j in 0..np {
        let stick = j > 0 && j < np - 1 && ev.modes[j] == SlipMode::Stick;
        sticks[j + 1] = sticks[j] + usize::from(stick);
    }
    // interior points of bordered chains
    let mut bordered = vec![false; np];
    for (k0, b) in &ev.borders {
        bordered[k0 + 1..k0 + b.uc.len()].fill(true);
    }
    // points x < y are coupled when no sticking node lies strictly between them (and they are
    // neighbours, inside a bordered chain)
    let coupled = |x: usize, y: usize| {
        let (a, b) = (x.min(y), x.max(y));
        b <= a + 1 || (sticks[b] == sticks[a + 1] && !bordered[a + 1])
    };
    let refs: Vec<PointRef> = ev
        .points
        .iter()
        .map(|&p| PointRef {
            kin: e.kin(ctx, p),
            s: e.local[p],
        })
        .collect();
    for x in 0..np {
        for y in 0..np {
            if !coupled(x, y) {
                continue;
            }
            let fa = (x == y).then_some(&ev.force[x]);
            add_pair(
                &refs[x],
                &refs[y],
                &ev.jac[x * np + y],
                &ev.damp[x * np + y],
                fa,
                sink,
            );
        }
    }
    if sink.aux_support() == AuxSupport::Rows {
        for (k0, b) in &ev.borders {
            emit_border(&refs[*k0..=k0 + b.uc.len()], b, sink);
        }
    }
}

/// Emits the dense part of a sliding chain's stiffness through auxiliary unknowns (see
/// [`ChainBorder`]): `y` (the change of `T_0` [N]) with `y - G . dp = 0`, and `w_j = T_0 z_j`
/// [N] with `w_j - w_{j-1} - T_0 dlam_j . dp = 0` (scaled by `T_0` so that every auxiliary
/// entry is of the size of a stiffness); the force on point `a` changes by
/// `sum_j E_aj uc_j (y + w_j)`, so `K` (= `-dF/dx`) gets `-P_a^T E_aj uc_j` in the columns of
/// `y` and `w_j`. `refs` are the chain's points.
fn emit_border(refs: &[PointRef], b: &ChainBorder, sink: &mut dyn JacobianSink) {
    let m = b.uc.len();
    let Some(y) = sink.new_aux() else {
        return;
    };
    for (p, g) in refs.iter().zip(&b.g) {
        sink.add_aux_position(y, p.kin, &(-generalized(p, g)));
    }
    sink.add_aux_aux(y, y, 1.0);
    // w[j] for segments 1..m (w_0 = 0: segment 0 carries T_0 alone)
    let mut w = vec![usize::MAX; m];
    for j in 1..m {
        let Some(wj) = sink.new_aux() else {
            return;
        };
        w[j] = wj;
        for k in 0..3 {
            let p = &refs[j - 1 + k];
            sink.add_aux_position(wj, p.kin, &(-generalized(p, &(b.dlam[j][k] * b.t0))));
        }
        sink.add_aux_aux(wj, wj, 1.0);
        if j > 1 {
            sink.add_aux_aux(wj, w[j - 1], -1.0);
        }
    }
    for (j, (uc, wj)) in b.uc.iter().zip(&w).enumerate() {
        if *uc == Vec3::zeros() {
            continue;
        }
        for (a, sign) in [(j, -1.0), (j + 1, 1.0)] {
            let k: Vector6<f64> = generalized(&refs[a], &(uc * sign));
            sink.add_stiffness_aux(refs[a].kin, y, &k);
            if j > 0 {
                sink.add_stiffness_aux(refs[a].kin, *wj, &k);
            }
        }
    }
}
