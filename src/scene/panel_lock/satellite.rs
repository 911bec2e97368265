//! The satellite of a PanelLock scene: the checks of its mass properties, and the frame of the
//! loads applied to it.
//!
//! Frames (docs/panel_lock_satellite.md has a sketch): the **world frame** is inertial, its
//! origin at the root-hinge attachment point at t = 0, z along the hinge axes, the array
//! deploying along +x. The **satellite body frame** has its origin at the satellite's centre of
//! mass and its axes along the principal axes of `satellite_inertia`; it is parallel to the
//! world frame at t = 0. `satellite_cg` is the centre of mass relative to the root-hinge
//! attachment point in that frame, so the attachment point sits at `-satellite_cg` in the body
//! frame and the centre of mass starts at `satellite_cg` in the world frame.

use super::PanelLock;
use super::build::SATELLITE_INPUTS;
use super::params::PanelLockParams;
use crate::math::Vec3;
use crate::model::kinematics::quat_at;

/// Largest distance [m] of the satellite's centre of mass from the root-hinge attachment point
/// along each body axis that the validation accepts: three decades above the default 1 m.
pub const MAX_CG_OFFSET: f64 = 1000.0;

impl PanelLockParams {
    /// Checks the satellite's mass properties beyond positivity and the envelope (done with the
    /// other positive parameters): the principal moments obey the triangle inequality (a real
    /// mass distribution), the centre of mass is finite and within [`MAX_CG_OFFSET`].
    pub(super) fn validate_satellite(&self) -> Result<(), String> {
        let [a, b, c] = self.satellite_inertia;
        // the message names all three moments: any of them may be the one set wrong (a small
        // one makes another exceed the sum)
        let names = [
            "satellite_inertia_x",
            "satellite_inertia_y",
            "satellite_inertia_z",
        ];
        for (k, (v, o1, o2)) in [(a, b, c), (b, c, a), (c, a, b)].into_iter().enumerate() {
            if v > o1 + o2 {
                let (n1, n2) = (names[(k + 1) % 3], names[(k + 2) % 3]);
                return Err(format!(
                    "{} = {v} kg m^2 exceeds the sum of {n1} and {n2} ({o1} + {o2} = {} kg m^2): no mass distribution has such principal moments (triangle inequality)",
                    names[k],
                    o1 + o2
                ));
            }
        }
        for (axis, v) in ["x", "y", "z"].iter().zip(self.satellite_cg) {
            if !(v.is_finite() && v.abs() <= MAX_CG_OFFSET) {
                return Err(format!(
                    "satellite_cg_{axis} must be finite and within [-{MAX_CG_OFFSET}, {MAX_CG_OFFSET}] m, got {v}"
                ));
            }
        }
        Ok(())
    }
}

/// The satellite's motion and the system's angular momentum at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SatelliteOutput {
    /// Attitude: unit quaternion (w, x, y, z) rotating satellite body axes into world axes
    /// (identity at t = 0, and always for a fixed satellite).
    pub attitude: [f64; 4],
    /// Angular rate [rad/s] in the satellite body frame.
    pub rate: Vec3,
    /// Centre of mass [m] and its velocity [m/s], world frame (a fixed satellite's centre of
    /// mass stays at `satellite_cg`).
    pub position: Vec3,
    pub velocity: Vec3,
    /// Total angular momentum of satellite and array about the system's centre of mass
    /// [kg m^2/s], world frame (the fixed satellite, the ground, carries none).
    pub angular_momentum: Vec3,
    /// Total linear momentum of the moving bodies [kg m/s], world frame.
    pub linear_momentum: Vec3,
}

impl PanelLock {
    /// Sets satellite load component `j` (force x, y, z [N], torque x, y, z [N m], in
    /// `load_frame`, [`SATELLITE_INPUTS`] order). A fixed satellite has no loads: any value but
    /// 0 is refused with a message naming `free_satellite`. The interface peaks take the
    /// wrench with the new load.
    pub fn set_satellite_load(&mut self, j: usize, value: f64) -> Result<(), String> {
        let name = SATELLITE_INPUTS
            .get(j)
            .ok_or_else(|| format!("satellite load #{j} does not exist (0..6)"))?;
        if !value.is_finite() {
            return Err(format!("{name} must be finite, got {value}"));
        }
        match self.layout.satellite_inputs {
            Some(idx) => self.set_input_noting_peaks(idx[j], value),
            None if value == 0.0 => Ok(()),
            None => Err(format!(
                "{name} = {value} acts on the satellite, but free_satellite is off (the satellite is fixed to the inertial frame and takes no loads): switch free_satellite on, or leave the satellite loads at 0"
            )),
        }
    }

    /// The satellite's motion and the momentum of the whole system now.
    pub fn satellite_output(&mut self) -> SatelliteOutput {
        let sim = &mut self.sim;
        let m = sim.system.momentum(&sim.state.q, &sim.state.v);
        let sat = *sim.system.kin(self.layout.satellite);
        let attitude = match self.layout.satellite.index() {
            Some(i) => {
                let q = quat_at(&sim.state.q, sim.system.model.bodies[i].q_offset + 3);
                [q.w, q.i, q.j, q.k]
            }
            None => [1.0, 0.0, 0.0, 0.0],
        };
        let position = if self.params.free_satellite {
            sat.r
        } else {
            Vec3::from(self.params.satellite_cg)
        };
        SatelliteOutput {
            attitude,
            rate: sat.omega,
            position,
            velocity: sat.v,
            angular_momentum: m.angular,
            linear_momentum: m.linear,
        }
    }
}
