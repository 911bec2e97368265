//! A running PanelLock simulation and the quantities its users read.

use super::build::{Layout, build};
use super::flex_outputs::PanelFlexOutput;
use super::interface::{
    InterfacePeaks, PeakHook, interface_motion, interface_power, interface_wrench,
};
use super::locked_frequency::{LockedFrequency, Update};
use super::params::PanelLockParams;
use crate::effect::EvalCtx;
use crate::effect::angle::relative_angle;
use crate::effect::latch::MEMORY_PER_LATCH;
use crate::integrator::SolverError;
use crate::math::Vec3;
use crate::sim::Simulation;

/// Per-hinge outputs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HingeOutput {
    /// Deployment angle [rad] and rate [rad/s].
    pub angle: f64,
    pub rate: f64,
    /// Whether the latch pin has dropped into the groove.
    pub engaged: bool,
    /// Pin/groove wall force now [N] (front + rear wall).
    pub contact_force: f64,
    /// Largest wall force so far [N].
    pub peak_force: f64,
    /// Time of lock-up [s] (latch engagement), NaN before.
    pub lock_time: f64,
}

/// Everything the scene reports at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct PanelLockOutputs {
    pub t: f64,
    pub hinges: Vec<HingeOutput>,
    /// Force [N] and torque [N m] the array applies to the satellite at the root interface,
    /// world frame, the torque about the root hinge's attachment point: the root shaft's
    /// reaction and every force element across the root hinge ([`super::interface`]).
    pub root_force: Vec3,
    pub root_torque: Vec3,
    /// Largest `|root_force|` [N] and `|root_torque|` [N m] since the start, over every
    /// accepted integrator step of [`PanelLock::advance_to`] (and the start).
    pub root_peak_force: f64,
    pub root_peak_torque: f64,
    /// Power [W] the satellite delivers into the array through the root interface,
    /// `-(root_force . v_O + root_torque . omega_satellite)` (world; 0 for a fixed satellite),
    /// and its work [J] since the start, integrated over every accepted step.
    pub root_power: f64,
    pub root_work: f64,
    /// Velocity [m/s] of the outer panel's tip midpoint along the panel normal.
    pub tip_normal_velocity: f64,
    /// Lowest undamped natural frequency [Hz] of the locked array linearized about its static
    /// equilibrium, as [`PanelLock::update_locked_frequency`] last left it (0 before every hinge
    /// has locked).
    pub locked_frequency: f64,
    /// Kinetic, potential (springs, contact, gravity) energy, energy dissipated and input work [J].
    pub kinetic: f64,
    pub potential: f64,
    pub dissipated: f64,
    pub input_work: f64,
}

/// The PanelLock scene running natively.
#[derive(Debug, Clone)]
pub struct PanelLock {
    pub params: PanelLockParams,
    pub layout: Layout,
    pub sim: Simulation,
    /// Peaks of the root interface wrench so far (kept by [`PanelLock::advance_to`]).
    pub interface_peaks: InterfacePeaks,
    /// The locked array's lowest natural frequency, brought up to date by
    /// [`PanelLock::update_locked_frequency`].
    pub locked_frequency: LockedFrequency,
}

impl PanelLock {
    /// Builds and initializes the scene at t = 0.
    pub fn new(params: PanelLockParams) -> Result<Self, String> {
        let (model, layout) = build(&params)?;
        let sim = Simulation::new(
            model,
            params.integrator_kind(),
            params.solver_settings(),
            0.0,
        )?;
        let mut scene = PanelLock {
            params,
            layout,
            sim,
            interface_peaks: InterfacePeaks::default(),
            locked_frequency: LockedFrequency::default(),
        };
        let start = scene.root_wrench().map_err(String::from)?;
        scene.interface_peaks.note(&start);
        Ok(scene)
    }

    /// The root interface wrench at the current state ([`super::interface`]), with the
    /// index-1 multipliers (accurate whatever the last step size).
    pub fn root_wrench(&mut self) -> Result<super::interface::Wrench, SolverError> {
        let lambda = self.sim.consistent_multipliers()?;
        Ok(self.root_wrench_with(&lambda))
    }

    /// [`PanelLock::root_wrench`], with the integrator's multipliers where the index-1 solve
    /// fails (outputs are always written).
    fn root_wrench_or_integrators(&mut self) -> super::interface::Wrench {
        let lambda = self
            .sim
            .consistent_multipliers()
            .unwrap_or_else(|_| self.sim.state.lambda.clone());
        self.root_wrench_with(&lambda)
    }

    /// The root interface wrench at the current state with multipliers `lambda`.
    fn root_wrench_with(&mut self, lambda: &[f64]) -> super::interface::Wrench {
        let mut scratch = Vec::new();
        interface_wrench(
            &mut self.sim.system,
            &self.layout,
            &self.sim.state,
            lambda,
            &mut scratch,
        )
    }

    /// Sets the root-hinge motor torque [N m] (positive deploys). The interface peaks take the
    /// wrench with a changed torque (the load from this instant on).
    pub fn set_motor_torque(&mut self, tau: f64) -> Result<(), String> {
        self.set_input_noting_peaks(self.layout.motor_input, tau)
    }

    /// Sets model input `index` to `value`; when that changes it, the interface peaks take the
    /// wrench with the new value (the load from this instant on).
    pub(super) fn set_input_noting_peaks(
        &mut self,
        index: usize,
        value: f64,
    ) -> Result<(), String> {
        let before = self.sim.system.inputs.get(index).copied();
        self.sim.set_input(index, value)?;
        if before.map(f64::to_bits) == Some(value.to_bits()) {
            return Ok(());
        }
        let now = self.root_wrench().map_err(String::from)?;
        self.interface_peaks.note(&now);
        Ok(())
    }

    /// Brings [`PanelLock::locked_frequency`] up to date with the locked set (computed from a
    /// copy of the system when the last hinge has locked; nothing otherwise): call it after
    /// advancing. Says what it did (computed, failed with the reason, or nothing).
    pub fn update_locked_frequency(&mut self) -> Update {
        let mut f = std::mem::take(&mut self.locked_frequency);
        let note = f.update(self);
        self.locked_frequency = f;
        note
    }

    /// Advances to `t` [s], keeping the interface peaks over every accepted step.
    pub fn advance_to(&mut self, t: f64) -> Result<(), SolverError> {
        self.advance(t, false)
    }

    /// Advances towards `t` [s]; with `one_step`, by one accepted step (exactly to `t` when
    /// that step reaches it). The interface peaks take every accepted step.
    pub fn advance(&mut self, t: f64, one_step: bool) -> Result<(), SolverError> {
        // the interface power at the start of the call (inputs may have changed since the last
        // step's end): the first step's work starts from it; a fixed satellite does not move, so
        // no power crosses and no multiplier solve is spent on it
        let p = if self.params.free_satellite {
            self.root_power()
        } else {
            0.0
        };
        self.interface_peaks.restart_power(self.sim.state.t, p);
        let mut hook = PeakHook::new(&self.layout, &mut self.interface_peaks, one_step);
        self.sim.advance_with(t, &mut hook)
    }

    /// Power [W] the satellite delivers into the array through the root interface now
    /// ([`super::interface::interface_power`]).
    pub fn root_power(&mut self) -> f64 {
        let w = self.root_wrench_or_integrators();
        self.root_power_of(&w)
    }

    fn root_power_of(&mut self, w: &super::interface::Wrench) -> f64 {
        let st = &self.sim.state;
        self.sim.system.update_kinematics(&st.q, &st.v);
        let (v, omega) = interface_motion(&self.sim.system, &self.layout);
        interface_power(w, v, omega)
    }

    /// Deployment angle [rad] and rate [rad/s] of hinge `k`.
    pub fn hinge_angle(&mut self, k: usize) -> (f64, f64) {
        let s = &self.sim.state;
        self.sim.system.update_kinematics(&s.q, &s.v);
        let (fi, fj) = self.layout.hinge_frames[k];
        let ra = relative_angle(self.sim.system.kins(), &fi, &fj);
        (self.layout.lock_angles[k] + ra.theta, ra.theta_dot)
    }

    /// Lock time of every hinge [s] (NaN before its lock-up), from the latches' memory: what
    /// [`PanelLock::outputs`] reports, without evaluating the rest.
    pub fn lock_times(&self) -> Vec<f64> {
        let n = self.layout.hinges.len();
        let mut out = vec![f64::NAN; n];
        if let (Some(latches), Some(range)) =
            (&self.layout.latches, self.sim.system.memory_range("latch"))
        {
            let mem = &self.sim.state.memory[range];
            for (k, slot) in out.iter_mut().enumerate().take(latches.elements.len()) {
                *slot = mem[k * MEMORY_PER_LATCH + 1];
            }
        }
        out
    }

    /// Tip deflection and modal amplitudes of each panel, inboard to outboard (zeros with
    /// rigid panels; see [`super::flex_outputs`]).
    pub fn panel_flex_outputs(&self) -> Vec<PanelFlexOutput> {
        let mut out = vec![PanelFlexOutput::default(); self.params.n_panels];
        for (o, f) in out.iter_mut().zip(&self.layout.flex_panels) {
            *o = f.evaluate(&self.sim.system.model, &self.sim.state.q);
        }
        out
    }

    /// All outputs at the current state.
    pub fn outputs(&mut self) -> PanelLockOutputs {
        let n = self.layout.hinges.len();
        let mut hinges = Vec::with_capacity(n);
        for k in 0..n {
            let (angle, rate) = self.hinge_angle(k);
            hinges.push(HingeOutput {
                angle,
                rate,
                engaged: false,
                contact_force: 0.0,
                peak_force: 0.0,
                lock_time: f64::NAN,
            });
        }
        let sim = &mut self.sim;
        let st = &sim.state;
        sim.system.update_kinematics(&st.q, &st.v);
        if let (Some(latches), Some(range)) =
            (&self.layout.latches, sim.system.memory_range("latch"))
        {
            let mem = &st.memory[range];
            let ctx = EvalCtx {
                t: st.t,
                kins: sim.system.kins(),
                inputs: &sim.system.inputs,
                memory: mem,
                frozen: &[],
            };
            for (k, l) in latches.elements.iter().enumerate() {
                let m = &mem[k * MEMORY_PER_LATCH..(k + 1) * MEMORY_PER_LATCH];
                let ev = l.evaluate(&ctx, m);
                hinges[k].engaged = ev.engaged;
                hinges[k].contact_force = ev.forces[0] + ev.forces[1];
                hinges[k].lock_time = m[1];
                hinges[k].peak_force = m[6];
            }
        }
        let root = self.root_wrench_or_integrators();
        let root_power = self.root_power_of(&root);
        let sim = &mut self.sim;
        let st = &sim.state;
        let outer = *sim
            .system
            .kin(*self.layout.plates.last().expect("at least the yoke"));
        let len = *self.layout.plate_lengths.last().expect("at least the yoke");
        let (tip_v, normal) = match &self.layout.flex_tip {
            None => (
                outer.point_velocity(&Vec3::new(0.5 * len, 0.0, 0.0)),
                outer.rot * Vec3::y(),
            ),
            Some((data, node)) => {
                // node velocity v + omega x A (rho + Phi a) + A Phi a_dot (omega in body frame)
                let body = &sim.system.model.bodies[self
                    .layout
                    .plates
                    .last()
                    .and_then(|b| b.index())
                    .expect("a modal outer panel")];
                let n = data.n_modes();
                let a = nalgebra::DVector::from_column_slice(
                    &st.q[body.q_offset + 7..body.q_offset + 7 + n],
                );
                let a_dot = nalgebra::DVector::from_column_slice(
                    &st.v[body.v_offset + 6..body.v_offset + 6 + n],
                );
                let phi = &data.translational_shapes()[*node];
                let s = data.positions()[*node] + phi * &a;
                let v = outer.point_velocity(&s) + outer.rot * (phi * &a_dot);
                // the plate normal is +z; the rigid panel's normal (+y) is the plate's -z
                (v, -(outer.rot * Vec3::z()))
            }
        };
        let e = sim.energy();
        PanelLockOutputs {
            t: sim.state.t,
            hinges,
            root_force: root.force,
            root_torque: root.torque,
            root_peak_force: self.interface_peaks.force,
            root_peak_torque: self.interface_peaks.torque,
            root_power,
            root_work: self.interface_peaks.work,
            tip_normal_velocity: tip_v.dot(&normal),
            locked_frequency: self.locked_frequency.hz,
            kinetic: e.kinetic,
            potential: e.potential,
            dissipated: e.dissipated,
            input_work: e.input,
        }
    }
}
