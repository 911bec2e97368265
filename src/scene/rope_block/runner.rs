//! A running rope-and-block simulation: the multibody [`Simulation`] plus the structure it was
//! built from, the contact manager after every step, and rebuilds on structural changes.

use super::bonds::{BondBooks, HookBond, hook_bonds};
use super::build::{BuildMap, build, rope_ctx, sync};
use super::edit::{apply, insert_initial_contacts};
use super::manager::{ContactSettings, Counters, Manager, NodeReport, node_reports};
use super::structure::Structure;
use crate::dae::System;
use crate::effect::ForceEffect;
use crate::integrator::{IntegratorKind, Settings, SolverError, StepAction, StepHook};
use crate::math::Vec3;
use crate::rope::{HookInit, HookMode, SlipMode};
use crate::sim::{Energy, Simulation};
use crate::state::State;
use std::sync::Arc;

/// Largest growth of the energy balance a run may show, as a share of the weight of all
/// bodies times 1 m (plus that share of the energy moved in and out), before it is stopped as
/// unstable. The lift cases of tests/stability_rope.rs stay below 1e-4 of it and the turn-over
/// (8 MJ of hook work) drifts by 0.2 kJ (tests/rope_turnover.rs); the unstable runs it exists for
/// grew by orders of magnitude more (4.8 MJ in an earlier turn-over's swing, 0.2-0.6 MJ within
/// a second for generalized-alpha at rho_inf 0.8 on 5e6 N s slings, 0.1 MJ within 0.7 s for a
/// block set down until its slings went slack, 1 MJ for BDF on that set-down).
pub const ENERGY_GROWTH_LIMIT: f64 = 5e-2;

/// A rope-and-block simulation.
#[derive(Debug, Clone)]
pub struct RopeBlockSim {
    /// The structure of the current build (positions as of the last rebuild).
    pub structure: Structure,
    pub sim: Simulation,
    pub map: BuildMap,
    pub contact: ContactSettings,
    /// What the contact manager did so far.
    pub counters: Counters,
    /// Change of kinetic + potential energy at structural events [J] (inelastic insertion
    /// impulses and node moves; negative is a loss).
    pub event_energy: f64,
    /// Energy removed by friction slides of contact nodes along their edges [J] (positive is a
    /// loss); part of the reported dissipated energy.
    pub slide_dissipation: f64,
    /// Energy balance (kinetic + potential + dissipated - input - events) [J] when the run
    /// started (`None` before the first advance); see [`RopeBlockSim::check_energy`].
    pub energy_reference: Option<f64>,
    /// Bound on rebuilds within one `advance_to` call.
    pub max_rebuilds_per_call: u64,
    /// Time over which a hook reaches a newly commanded velocity or pay-out rate [s].
    pub hook_ramp: f64,
    /// Work of the hooks' and winches' power bonds, integrated inside the steps.
    pub bonds: BondBooks,
}

/// The integrator settings a RopeBlock scene runs `settings` with (see [`RopeBlockSim::new`]
/// for why): the error held per step, on the positions only. A restored state runs with the
/// same ([`super::persist::read_sim`]).
pub fn run_settings(mut settings: Settings) -> Settings {
    settings.error_per_unit_step = false;
    settings.error_includes_speeds = false;
    settings
}

impl RopeBlockSim {
    /// Inserts contact nodes at every initial crossing, builds the model and finds consistent
    /// initial conditions at `t0` [s]. Generalized-alpha holds its error per step here
    /// (`settings.error_per_unit_step` is set to false): the lumped-mass rope's axial waves, of
    /// thousands of m/s^2, are what the scheme damps on purpose, and held per unit step their
    /// error estimate drives the step towards the round-off of the index-3 form. BDF holds the
    /// positions' error only (`settings.error_includes_speeds` is set to false), as gen-alpha
    /// always does: the contact nodes' edge slides between steps kick the stiff edge holds into
    /// speed oscillations that it otherwise resolved with microsecond steps.
    pub fn new(
        mut structure: Structure,
        kind: IntegratorKind,
        settings: Settings,
        contact: ContactSettings,
        t0: f64,
    ) -> Result<Self, String> {
        structure.validate()?;
        for h in &mut structure.hooks {
            h.t0 = t0;
        }
        if contact.detect {
            insert_initial_contacts(&mut structure, contact.tolerance, contact.max_depth, 100);
        }
        let n_hooks = structure.hooks.len();
        let (model, map) = build(&structure)?;
        let sim = Simulation::new(model, kind, run_settings(settings), t0)?;
        Ok(RopeBlockSim {
            structure,
            sim,
            map,
            contact,
            counters: Counters::default(),
            event_energy: 0.0,
            slide_dissipation: 0.0,
            energy_reference: None,
            max_rebuilds_per_call: 100_000,
            hook_ramp: 0.5,
            bonds: BondBooks::new(n_hooks),
        })
    }

    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.sim.state.t
    }

    /// Energy balance [J]: kinetic + potential + dissipated (friction slides included) - work
    /// of the hooks - change at structural events. Constant for an exact solution; the
    /// integrators' own numerical damping only lowers it. The dissipated totals count only as
    /// losses: damping and friction cannot create energy, so a negative total (the books of an
    /// unstable run: BDF with slides on slack slings once booked -8 MJ of slide "dissipation"
    /// against its own growth) shows up as growth instead of cancelling it.
    fn balance_of(&self, e: &Energy) -> f64 {
        e.kinetic + e.potential + e.dissipated.max(0.0) + self.slide_dissipation.max(0.0)
            - e.input
            - self.event_energy
    }

    /// Mass of everything [kg]: blocks, loads, rope and contact nodes.
    pub fn total_mass(&self) -> f64 {
        self.sim
            .system
            .model
            .bodies
            .iter()
            .map(|b| b.kind.mass())
            .sum()
    }

    /// The passivity guard: the scene has no energy source but the hooks, so a balance grown by
    /// more than [`ENERGY_GROWTH_LIMIT`] of the weight of everything times 1 m (plus that share
    /// of the energy that flowed in and out) is an unstable integration; it stops the run with
    /// a message naming what to change instead of returning garbage.
    pub fn check_energy(&mut self) -> Result<(), String> {
        let e = self.sim.energy();
        let b = self.balance_of(&e);
        let Some(b0) = self.energy_reference else {
            self.energy_reference = Some(b);
            return Ok(());
        };
        let mass = self.total_mass();
        // dissipation counts only as a loss: energy "dissipated" negatively (a slide that gained
        // energy) is itself what the guard is for and must not widen its own tolerance
        let scale = mass * 9.81 * 1.0
            + e.input.abs()
            + e.dissipated.max(0.0)
            + self.slide_dissipation.max(0.0);
        let growth = b - b0;
        if growth > ENERGY_GROWTH_LIMIT * scale || !b.is_finite() {
            return Err(format!(
                "numerical instability at t = {:.4} s: the energy balance grew by {growth:.4e} J ({:.2} % of the weight of the rigging and block times 1 m) although the scene has no energy source but the hooks; {}",
                self.time(),
                100.0 * growth / (mass * 9.81),
                self.instability_remedy()
            ));
        }
        Ok(())
    }

    /// What to change after an unstable run, for the integrator it ran with.
    fn instability_remedy(&self) -> &'static str {
        if self.sim.integrator_kind() == IntegratorKind::Bdf {
            // BDF's history reads every friction slide of a contact node as a disturbance: with
            // slings slack over their edges (nodes sliding every step) it takes rejection after
            // rejection and its slide books go wrong (docs/details.md, "Slack slings")
            "use integrator = gen_alpha (the default; it handles contact nodes sliding every step, as on slack slings), a smaller rtol or h_max, or lower rope_damping / mu"
        } else {
            "use integrator = bdf, a smaller rtol or h_max, or lower rope_damping / mu"
        }
    }

    /// Advances to `t_end` [s], managing contact nodes after every step; checks the energy
    /// balance at the end ([`RopeBlockSim::check_energy`]).
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), String> {
        self.advance(t_end, false)
    }

    /// [`RopeBlockSim::advance_to`], or with `one_step` only one accepted step towards `t_end`
    /// (with the contact manager's edits and rebuild after it) and no energy check at its end:
    /// the caller of single steps checks once when it is done ([`RopeBlockSim::check_energy`]).
    pub fn advance(&mut self, t_end: f64, one_step: bool) -> Result<(), String> {
        if self.energy_reference.is_none() {
            self.check_energy()?;
        }
        self.advance_contacts(t_end, one_step)?;
        if one_step {
            return Ok(());
        }
        self.check_energy()
    }

    fn advance_contacts(&mut self, t_end: f64, one_step: bool) -> Result<(), String> {
        let mut rebuilds = 0;
        loop {
            let bonds = self.hook_bonds();
            self.bonds.restart(self.sim.state.t, &bonds);
            let mut mgr = Manager::new(
                &self.structure,
                &self.map,
                &self.contact,
                &mut self.counters,
                &mut self.slide_dissipation,
            );
            mgr.one_step = one_step;
            let mut booked = Booked {
                inner: &mut mgr,
                map: &self.map,
                books: &mut self.bonds,
            };
            self.sim
                .advance_with(t_end, &mut booked)
                .map_err(String::from)?;
            let edits = std::mem::take(&mut mgr.edits);
            if edits.is_empty() {
                return Ok(());
            }
            rebuilds += 1;
            if rebuilds > self.max_rebuilds_per_call {
                return Err(format!(
                    "more than {} contact-node rebuilds in one call at t = {:.6} s: contact keeps changing (check friction, node spacing or the tolerances)",
                    self.max_rebuilds_per_call,
                    self.time()
                ));
            }
            self.sync();
            apply(&mut self.structure, &edits, &mut self.counters);
            self.rebuild()?;
            // the rebuilt state has its nodes' cones settled like every accepted step's
            let mut mgr = Manager::new(
                &self.structure,
                &self.map,
                &self.contact,
                &mut self.counters,
                &mut self.slide_dissipation,
            );
            if mgr.settle_cone(&mut self.sim.system, &mut self.sim.state) {
                self.sim.restart().map_err(String::from)?;
            }
            if one_step {
                return Ok(());
            }
        }
    }

    /// The hooks' power bonds at the current state.
    pub fn hook_bonds(&mut self) -> Vec<HookBond> {
        let st = &self.sim.state;
        let sys = &mut self.sim.system;
        sys.update_kinematics(&st.q, &st.v);
        let ctx = rope_ctx(&self.map, sys.kins(), &sys.inputs, st);
        hook_bonds(&self.map.rope, &ctx)
    }

    /// Copies the running state into the structure.
    pub fn sync(&mut self) {
        let model = self.sim.system.model.clone();
        sync(&mut self.structure, &model, &self.map, &self.sim.state);
    }

    /// Rebuilds the model from the structure and continues from its positions and velocities.
    pub fn rebuild(&mut self) -> Result<(), String> {
        let before = self.sim.energy();
        let (model, map) = build(&self.structure)?;
        let mut sys = System::new(Arc::new(model))?;
        let old = &self.sim.state;
        let mut state = State {
            t: old.t,
            q: sys.model.q0.clone(),
            v: sys.model.v0.clone(),
            vdot: vec![0.0; sys.n_v()],
            lambda: vec![0.0; sys.n_c()],
            energy_dissipated: old.energy_dissipated,
            work_input: old.work_input,
            memory: Vec::new(),
        };
        state.memory = sys.init_memory(state.t, &state.q, &state.v);
        // the sliding nodes' material coordinates as the carried decisions give them on the new
        // build (a removed or merged node can join two runs): the memory then holds what acts,
        // as after every accepted step
        sys.update_memory(state.t, &state.q, &state.v, &mut state.memory);
        self.map = map;
        self.sim.replace_system(sys, state).map_err(String::from)?;
        self.counters.rebuilds += 1;
        let after = self.sim.energy();
        self.event_energy +=
            (after.kinetic + after.potential) - (before.kinetic + before.potential);
        Ok(())
    }

    /// The anchor [m] of every contact slot's edge hold at which its spring carries `force` [N]
    /// at the current state (`None` where the slot has no hold or no friction).
    pub fn hold_anchors(&mut self, force: f64) -> Vec<Option<f64>> {
        let st = &self.sim.state;
        let sys = &mut self.sim.system;
        sys.update_kinematics(&st.q, &st.v);
        let ctx = rope_ctx(&self.map, sys.kins(), &sys.inputs, st);
        (0..self.map.rope.n_contacts())
            .map(|c| self.map.rope.hold_anchor_for(&ctx, c, force))
            .collect()
    }

    /// Reports (geometry, tensions, reaction) of every contact node at the current state.
    pub fn contact_reports(&mut self) -> Vec<NodeReport> {
        let st = self.sim.state.clone();
        node_reports(&mut self.sim.system, &self.map, &self.structure, &st)
    }

    /// Tension [N] and rest length [m] of every segment of rope `r` at the current state.
    pub fn rope_tensions(&mut self, r: usize) -> Vec<(f64, f64)> {
        let st = &self.sim.state;
        let sys = &mut self.sim.system;
        sys.update_kinematics(&st.q, &st.v);
        let ctx = rope_ctx(&self.map, sys.kins(), &sys.inputs, st);
        self.map.rope.rope_tensions(&ctx, r)
    }

    /// Total normal force [N] and total friction force [N] of the ground on the block at the
    /// current state (`None` without a ground).
    pub fn ground_forces(&mut self) -> Option<(f64, f64)> {
        let ground = self.map.ground.as_ref()?;
        let st = &self.sim.state;
        let sys = &mut self.sim.system;
        sys.update_kinematics(&st.q, &st.v);
        let ctx = crate::effect::EvalCtx {
            t: st.t,
            kins: sys.kins(),
            inputs: &sys.inputs,
            memory: &[],
            frozen: &[],
        };
        Some(ground.totals(&ctx))
    }

    /// World positions [m] of every point of rope `r` (ends included).
    pub fn rope_points(&mut self, r: usize) -> Vec<Vec3> {
        let st = &self.sim.state;
        let sys = &mut self.sim.system;
        sys.update_kinematics(&st.q, &st.v);
        let ctx = rope_ctx(&self.map, sys.kins(), &sys.inputs, st);
        let (a, b) = self.map.rope.rope_ranges()[r];
        (a..b)
            .map(|i| self.map.rope.point_state(&ctx, i).0)
            .collect()
    }

    /// Slip mode of every contact node (index = contact slot).
    pub fn slip_modes(&self) -> Vec<SlipMode> {
        let mem = &self.sim.state.memory[self.map.rope_memory..];
        (0..self.map.rope.n_contacts())
            .map(|c| self.map.rope.contact_state(mem, c).0)
            .collect()
    }

    /// Commands hook `k`'s velocity [m/s] (world) and pay-out rate [m/s]: reached linearly over
    /// [`RopeBlockSim::hook_ramp`] seconds from the current ones. With a ramp the hook's position
    /// and velocity stay continuous (only its acceleration steps), so the integrator keeps its
    /// history (step size, BDF order and past values, generalized-alpha's accelerations) and its
    /// error control sees the kink; with a ramp of 0 the velocity jumps and the integrator
    /// restarts from consistent accelerations.
    pub fn set_hook_rates(
        &mut self,
        k: usize,
        velocity: Vec3,
        payout_rate: f64,
    ) -> Result<(), String> {
        if !velocity.iter().all(|x| x.is_finite()) {
            return Err(format!("hook {k}: velocity must be finite"));
        }
        let ramp = self.hook_ramp;
        self.command_hook(k, payout_rate, |h| {
            h.mode = HookMode::Velocity;
            h.target_velocity = velocity;
            h.target_position = h.position;
            h.ramp = ramp;
        })
    }

    /// Commands hook `k` to move to `target` [m] (world) and its pay-out rate [m/s]. The hook
    /// moves from its current position and velocity along the cubic [`crate::rope::hermite`]
    /// (position and velocity continuous, acceleration stepping at both ends, as a ramp) and
    /// arrives at rest after [`hook_move_time`] (the ramp time, or longer for a long move); the
    /// pay-out rate is reached linearly over the ramp time. The integrator keeps its history
    /// unless the move takes no time (no distance and a ramp of 0).
    pub fn set_hook_target(
        &mut self,
        k: usize,
        target: Vec3,
        payout_rate: f64,
    ) -> Result<(), String> {
        if !target.iter().all(|x| x.is_finite()) {
            return Err(format!("hook {k}: target position must be finite"));
        }
        let ramp = self.hook_ramp;
        self.command_hook(k, payout_rate, |h| {
            h.mode = HookMode::Position;
            h.target_velocity = Vec3::zeros();
            h.ramp = hook_move_time(ramp, (target - h.position).norm());
            h.target_position = target;
        })
    }

    /// Writes hook `k`'s new command: its motion from now (position, velocity and pay-out as they
    /// are), the pay-out rate to reach and what `set` writes; keeps the integrator's history when
    /// the motion stays continuous (the command's time is > 0), else restarts it.
    fn command_hook(
        &mut self,
        k: usize,
        payout_rate: f64,
        set: impl FnOnce(&mut HookInit),
    ) -> Result<(), String> {
        if k >= self.map.rope.n_hooks() {
            return Err(format!(
                "hook {k} does not exist ({} hooks)",
                self.map.rope.n_hooks()
            ));
        }
        if !payout_rate.is_finite() {
            return Err(format!("hook {k}: pay-out rate must be finite"));
        }
        let t = self.sim.state.t;
        let base = self.map.rope_memory;
        let n = self.map.rope.n_memory();
        let mem = &self.sim.state.memory[base..base + n];
        let (x, v) = self.map.rope.hook_motion(mem, k, t);
        let (p, rate) = self.map.rope.hook_payout(mem, k, t);
        let mut h = HookInit {
            position: x,
            velocity: v,
            t0: t,
            payout: p,
            payout_rate: rate,
            target_payout_rate: payout_rate,
            ramp: self.hook_ramp,
            ..HookInit::at(x)
        };
        set(&mut h);
        self.map
            .rope
            .write_hook(&mut self.sim.state.memory[base..base + n], k, &h);
        if h.ramp > 0.0 {
            // continuous command: the system follows the new memory, the history stays
            self.sim.sync_memory().map_err(String::from)
        } else {
            self.sim.restart().map_err(String::from)
        }
    }
}

/// The contact manager's step hook with the power bonds booked at every accepted step's end
/// (before the manager's edits; sampled anew when it moved the state).
struct Booked<'a, 'b> {
    inner: &'a mut Manager<'b>,
    map: &'a BuildMap,
    books: &'a mut BondBooks,
}

impl Booked<'_, '_> {
    fn bonds(&self, sys: &mut System, st: &State) -> Vec<HookBond> {
        sys.update_kinematics(&st.q, &st.v);
        let ctx = rope_ctx(self.map, sys.kins(), &sys.inputs, st);
        hook_bonds(&self.map.rope, &ctx)
    }
}

impl StepHook for Booked<'_, '_> {
    fn after_step(&mut self, sys: &mut System, st: &mut State) -> Result<StepAction, SolverError> {
        let bonds = self.bonds(sys, st);
        self.books.step(st.t, &bonds);
        let action = self.inner.after_step(sys, st)?;
        if matches!(action, StepAction::Moved | StepAction::Restart) {
            let bonds = self.bonds(sys, st);
            self.books.restart(st.t, &bonds);
        }
        Ok(action)
    }

    fn pause(&self) -> bool {
        self.inner.pause()
    }
}

/// Largest speed of a hook's own move to a position target [m/s]: the cubic's peak speed is
/// 1.5 x distance / duration, so a move lasts at least 1.5 x distance / this.
pub const HOOK_MOVE_SPEED: f64 = 2.0;

/// Duration [s] of a hook's move over `distance` [m] with ramp time `ramp` [s]: the ramp time,
/// or longer so that the cubic's own peak speed `1.5 distance / duration` stays within
/// [`HOOK_MOVE_SPEED`].
pub fn hook_move_time(ramp: f64, distance: f64) -> f64 {
    ramp.max(1.5 * distance / HOOK_MOVE_SPEED)
}
