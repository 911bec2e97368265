//! The locked array's lowest natural frequency as a run quantity (issue #45 item 2): the array
//! linearized about its static equilibrium in the locked configuration ([`locked_modes`]),
//! computed once when the last hinge locks, from a copy of the system (the run goes on bit for
//! bit as without it).
//!
//! A latch never releases ([`crate::contact::latch`]: engagement is kept state), so the locked
//! set changes once, from "not every hinge" to "every hinge"; the tracker still keys its value
//! to the set it was computed for and computes again if that set ever differs. Before every
//! hinge has locked, without latches, and when no equilibrium is found (e.g. a free-floating
//! satellite: the linearization has rigid-body motions without stiffness, the Newton matrix of
//! the equilibrium is singular) the value is 0; the failure's reason is handed to the caller
//! once, for its log. Cost and checks: docs/panel_lock_locked_frequency.md.

use super::PanelLock;
use super::build::build_posed;
use super::params::PanelLockParams;
use crate::dae::linearize::{Equilibrium, natural_frequencies, static_equilibrium};

/// Unbalanced-force tolerance of the equilibrium [N or N m] and constraint tolerance [m].
pub const FORCE_TOL: f64 = 1e-8;
pub const CONSTRAINT_TOL: f64 = 1e-12;
/// Newton iterations allowed for the equilibrium.
pub const MAX_ITERATIONS: usize = 50;

/// Per hinge, the deployment angle [rad] of a pin seated against the front wall: turned past
/// the lock angle (groove centre) until the pin at the seat radius `r_s` penetrates the front
/// wall by `delta_0`, the penetration at which the contact law alone carries the spring preload
/// on the arm `r_s` (`k delta_0^n r_s = preload`). The Newton start of the equilibrium: close
/// to it (the spring's slope and the arm's cosine move it by a few per mille of `delta_0`) and
/// already in contact, where the Hertz stiffness `n k delta^(n-1)` is not 0.
pub fn seated_pose(p: &PanelLockParams) -> Vec<f64> {
    let r_s = p.cam_radius - p.groove_depth + p.pin_radius;
    (0..p.n_hinges())
        .map(|k| {
            let h = p.hinge(k);
            let delta = (h.spring_preload.max(0.0) / (h.contact_stiffness * r_s))
                .powf(1.0 / h.contact_exponent);
            h.lock_angle + ((0.5 * p.groove_width - p.pin_radius + delta) / r_s).asin()
        })
        .collect()
}

/// The locked array linearized about its static equilibrium ([`crate::dae::linearize`]): the
/// equilibrium found by Newton from the designed locked configuration (every hinge at its
/// [`seated_pose`], panels undeformed, the run's time and inputs) with the effects' memory of
/// the run (e.g. which latches are locked), and the undamped natural frequencies there [Hz],
/// ascending. The start does not depend on the run's state, so the result does not depend on
/// when it is computed (from the state itself, mid-rattle after a lock-up, Newton does not
/// converge on the default array). Works on a copy of the system: the run's state and system
/// are left as they are. `Err` if no equilibrium is found.
pub fn locked_modes(s: &PanelLock) -> Result<(Equilibrium, Vec<f64>), String> {
    let t = s.sim.state.t;
    let (model, _) = build_posed(&s.params, Some(&seated_pose(&s.params)))?;
    let q = &model.q0;
    if q.len() != s.sim.state.q.len() {
        return Err(format!(
            "the locked pose has {} position coordinates, the run {} (internal error)",
            q.len(),
            s.sim.state.q.len()
        ));
    }
    let mut sys = s.sim.system.clone();
    sys.memory.copy_from_slice(&s.sim.state.memory);
    let eq = static_equilibrium(&mut sys, t, q, FORCE_TOL, CONSTRAINT_TOL, MAX_ITERATIONS)
        .map_err(|e| format!("locked array: {e}"))?;
    let f = natural_frequencies(&mut sys, t, &eq.q, &eq.lambda)?;
    Ok((eq, f))
}

/// The locked frequency of a run and the locked set it belongs to.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LockedFrequency {
    /// Lowest undamped natural frequency [Hz] of the locked array; 0 until computed.
    pub hz: f64,
    /// Per hinge, locked or not, when [`Self::hz`] was last computed (empty: never).
    pub locked: Vec<bool>,
}

/// What one [`LockedFrequency::update`] did.
#[derive(Debug, Clone, PartialEq)]
pub enum Update {
    /// Nothing computed: the locked set is the one of the value held, or not every hinge is
    /// locked (the value is then 0).
    NotComputed,
    /// Computed now: the frequency [Hz] and the CPU time it took [s].
    Computed { hz: f64, cpu: f64 },
    /// The computation failed, for this reason; the value is 0.
    Failed(String),
}

impl LockedFrequency {
    /// Brings the value up to date with `scene`'s locked set: computed when every hinge is
    /// locked and the set differs from the one of the value held (at most once per run, as
    /// latches never release), back to 0 when not every hinge is locked.
    pub fn update(&mut self, scene: &PanelLock) -> Update {
        let locked: Vec<bool> = scene.lock_times().iter().map(|t| t.is_finite()).collect();
        if locked == self.locked {
            return Update::NotComputed;
        }
        let all = scene.layout.latches.is_some() && locked.iter().all(|&l| l);
        self.locked = locked;
        self.hz = 0.0;
        if !all {
            return Update::NotComputed;
        }
        let start = std::time::Instant::now();
        let result = locked_modes(scene);
        let cpu = start.elapsed().as_secs_f64();
        match result {
            Ok((_, f)) => match f.first() {
                Some(&f) if f.is_finite() => {
                    self.hz = f;
                    Update::Computed { hz: f, cpu }
                }
                _ => Update::Failed("locked_frequency: the locked array has no mode".into()),
            },
            Err(e) => Update::Failed(format!(
                "locked_frequency stays 0: no linearization of the locked array at t = {} s ({e})",
                scene.sim.state.t
            )),
        }
    }
}
