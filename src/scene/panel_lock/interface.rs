//! The load the array puts on the spacecraft at the root interface, and its peaks.
//!
//! The *array* is every body but the satellite (the ground when the satellite is fixed): the
//! hinge bodies, the yoke and the panels. The *interface point* `O` is the root hinge's
//! attachment point on the satellite (the origin of the root shaft's satellite-side frame,
//! world position; the world origin at t = 0). The interface wrench is everything the array
//! applies to the satellite there: the root shaft's constraint reaction and every force
//! element acting across the root hinge (deployment spring, damper, hinge friction, latch
//! contact, stow stop, cable loop, root motor), in the world frame, the torque about `O`.
//!
//! It is summed, not picked element by element: over the array's bodies, the generalized
//! forces of every force effect but gravity (forces between two array bodies cancel in the
//! sum, action against reaction) plus the root shaft's reaction on the root hinge body (the
//! only joint that crosses the interface) give the load of the satellite on the array, `W`;
//! the output is `-W`. By the array's momentum balance `W + sum m_i g = dP/dt` and, about `O`,
//! `M_O(W) + sum (r_i - O) x m_i g = sum (r_i - O) x m_i a_i + d(A_i J_i omega_i)/dt`
//! (tests/panel_lock_interface.rs checks both).
//!
//! The wrench and the satellite's motion at `O` form the root interface's power bond
//! (docs/power_bonds.md): the power the satellite delivers into the array is
//! `-(F . v_O + M_O . omega_s)` (world frame; zero for a fixed satellite), and its work is
//! integrated over every accepted step with the peaks ([`InterfacePeaks::work`]).

use super::build::Layout;
use crate::dae::{RangeSpace, System};
use crate::integrator::init::index1_motion;
use crate::integrator::kkt::Kkt;
use crate::integrator::{SolverError, StepAction, StepHook};
use crate::math::Vec3;
use crate::state::State;

/// A force [N] and a torque [N m] about the interface point, world frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Wrench {
    pub force: Vec3,
    pub torque: Vec3,
}

/// World position [m] of the interface point: the root shaft's satellite-side frame origin.
pub fn interface_point(sys: &System, layout: &Layout) -> Vec3 {
    let frame = &sys.model.joints[layout.root_joint].frame_i;
    let k = sys.kin(frame.body);
    k.r + k.rot * frame.origin
}

/// Velocity [m/s] of the interface point and angular velocity [rad/s] of the satellite, world
/// frame, at the last kinematics evaluation (zero for a fixed satellite, the ground).
pub fn interface_motion(sys: &System, layout: &Layout) -> (Vec3, Vec3) {
    let frame = &sys.model.joints[layout.root_joint].frame_i;
    let k = sys.kin(frame.body);
    (k.point_velocity(&frame.origin), k.rot * k.omega)
}

/// Power [W] the satellite delivers into the array through the wrench `w` the array applies to
/// it, with the interface point's velocity `v` and the satellite's angular velocity `omega`
/// (world): `-(F . v + M_O . omega)`.
pub fn interface_power(w: &Wrench, v: Vec3, omega: Vec3) -> f64 {
    -(w.force.dot(&v) + w.torque.dot(&omega))
}

/// The wrench the array applies to the satellite at `state` (its time, positions, speeds and
/// effect memory), with `lambda` the multipliers of the active constraint rows there (the
/// index-1 ones: [`crate::sim::Simulation::consistent_multipliers`]). `scratch` is resized to
/// `n_v` (no allocation once it has that length).
pub fn interface_wrench(
    sys: &mut System,
    layout: &Layout,
    state: &State,
    lambda: &[f64],
    scratch: &mut Vec<f64>,
) -> Wrench {
    sys.memory.copy_from_slice(&state.memory);
    scratch.resize(sys.n_v(), 0.0);
    sys.effect_forces(
        state.t,
        &state.q,
        &state.v,
        &|name| name != "gravity",
        scratch,
    );
    let o = interface_point(sys, layout);
    let mut on_array = Wrench::default();
    let mut add = |force: Vec3, point: Vec3, moment: Vec3| {
        on_array.force += force;
        on_array.torque += (point - o).cross(&force) + moment;
    };
    for (i, body) in sys.model.bodies.iter().enumerate() {
        if Some(i) == layout.satellite.index() {
            continue;
        }
        let k = sys.kins()[i];
        let c = body.v_offset;
        let force = Vec3::new(scratch[c], scratch[c + 1], scratch[c + 2]);
        let moment = if body.kind.has_rotation() {
            k.rot * Vec3::new(scratch[c + 3], scratch[c + 4], scratch[c + 5])
        } else {
            Vec3::zeros()
        };
        add(force, k.r, moment);
    }
    // the root shaft's reaction on the root hinge body: -G_j^T lambda over the shaft's rows
    sys.eval_constraints(state.t, &state.q, &state.v);
    let hinge = *sys.kin(layout.hinges[0]);
    let (mut force, mut moment_body) = (Vec3::zeros(), Vec3::zeros());
    for r in sys.joint_multiplier_rows(layout.root_joint) {
        let (g, lam) = (sys.rows[r].g[1], lambda[r]);
        force -= Vec3::new(g[0], g[1], g[2]) * lam;
        moment_body -= Vec3::new(g[3], g[4], g[5]) * lam;
    }
    add(force, hinge.r, hinge.rot * moment_body);
    Wrench {
        force: -on_array.force,
        torque: -on_array.torque,
    }
}

/// The largest interface force and torque magnitudes [N, N m] since the start, over every
/// accepted integrator step (and the start), with the scratch their per-step evaluation uses.
#[derive(Debug, Clone, Default)]
pub struct InterfacePeaks {
    /// Largest `|force|` [N] and `|torque|` [N m] so far.
    pub force: f64,
    pub torque: f64,
    /// Work [J] the satellite has done on the array through the interface since the start,
    /// trapezoidal over every accepted step from the powers at its ends.
    pub work: f64,
    /// Time [s] and interface power [W] of the last sample (`None`: none yet).
    last_power: Option<(f64, f64)>,
    /// Solvers of the index-1 multipliers at step ends: the range-space method (`O(n)` in the
    /// bodies of the chain), the LU of the full matrix where it fails (scratch: no influence on
    /// results beyond round-off).
    range_space: RangeSpace,
    kkt: Kkt,
    rhs: Vec<f64>,
    vdot: Vec<f64>,
    lambda: Vec<f64>,
    forces: Vec<f64>,
}

impl InterfacePeaks {
    /// Takes `w` into the peaks.
    pub fn note(&mut self, w: &Wrench) {
        self.force = self.force.max(w.force.norm());
        self.torque = self.torque.max(w.torque.norm());
    }

    /// Takes the interface power `p` [W] at time `t` [s] as the start of the next step (after
    /// an input changed the load, or at the start of a call): no work is added.
    pub fn restart_power(&mut self, t: f64, p: f64) {
        self.last_power = Some((t, p));
    }

    /// Adds the work of the step that ended at `t` [s] with power `p` [W] (trapezoidal from the
    /// last sample) and takes `p` as the next step's start.
    fn step_power(&mut self, t: f64, p: f64) {
        if let Some((t0, p0)) = self.last_power {
            self.work += 0.5 * (t - t0) * (p0 + p);
        }
        self.last_power = Some((t, p));
    }

    /// Notes the wrench at the end of an accepted step, with the index-1 multipliers solved
    /// there (no integrator leaves them in the state at every step end).
    pub fn after_step(
        &mut self,
        sys: &mut System,
        layout: &Layout,
        state: &State,
    ) -> Result<(), SolverError> {
        self.vdot.resize(sys.n_v(), 0.0);
        let mut lambda = std::mem::take(&mut self.lambda);
        index1_motion(
            sys,
            &mut self.range_space,
            &mut self.kkt,
            state.t,
            &state.q,
            &state.v,
            &mut self.vdot,
            &mut lambda,
            &mut self.rhs,
        )?;
        let w = interface_wrench(sys, layout, state, &lambda, &mut self.forces);
        self.lambda = lambda;
        self.note(&w);
        sys.update_kinematics(&state.q, &state.v);
        let (v, omega) = interface_motion(sys, layout);
        self.step_power(state.t, interface_power(&w, v, omega));
        Ok(())
    }
}

/// The step hook that keeps [`InterfacePeaks`] over every accepted step; with `one_step`, it
/// asks for control back after the first.
pub struct PeakHook<'a> {
    pub layout: &'a Layout,
    pub peaks: &'a mut InterfacePeaks,
    pub one_step: bool,
    stepped: bool,
}

impl<'a> PeakHook<'a> {
    pub fn new(layout: &'a Layout, peaks: &'a mut InterfacePeaks, one_step: bool) -> Self {
        PeakHook {
            layout,
            peaks,
            one_step,
            stepped: false,
        }
    }
}

impl StepHook for PeakHook<'_> {
    fn after_step(&mut self, sys: &mut System, st: &mut State) -> Result<StepAction, SolverError> {
        self.stepped = true;
        self.peaks.after_step(sys, self.layout, st)?;
        Ok(StepAction::Continue)
    }
    fn pause(&self) -> bool {
        self.one_step && self.stepped
    }
}
