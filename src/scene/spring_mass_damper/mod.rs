//! `SpringMassDamper`: the smallest model on the multibody solver, and the example of how a
//! model is added (docs/architecture.md, "Adding a model").
//!
//! A mass `m` [kg] on a linear spring `k` [N/m] and damper `c` [N s/m] to the ground, pushed by
//! the input force `F` [N] (held over each communication step):
//!
//! ```text
//! m x'' + c x' + k x = F,    x(t0) = x0,  x'(t0) = v0
//! ```
//!
//! It is built from the solver's own pieces: a particle, a spring-damper from a ground point and
//! an applied load that reads model input 0. The spring is anchored at `-FREE_LENGTH` on the x
//! axis ([`FREE_LENGTH`]) and the particle starts at `x0` on it: its x coordinate is the
//! displacement (so the integrator's error control sees `x`, not the spring's length). With no
//! gravity and no force off the axis it stays on the axis, where the spring-damper's force along
//! its line is exactly `-k x - c x'` while the spring is longer than zero
//! (`x > -FREE_LENGTH`).
//!
//! This file is the physics; [`cosim`] is the binding (ports, parameters, state bytes).

pub mod cosim;

pub use cosim::{IDENTIFIER, create, info};

use crate::scene::power_port::{PortDomain, PowerPort};

/// The mass's power port: the input force `F` beside the mass's velocity `v` (along x), so a
/// model that outputs a force and takes a velocity (a rope's winch line, a hook) can be joined
/// to it.
pub fn power_ports() -> Vec<PowerPort> {
    vec![PowerPort::new(
        "mass",
        PortDomain::LinearMechanical,
        &["F"],
        &["v"],
    )]
}

use crate::integrator::{IntegratorKind, Settings, SolverError};
use crate::math::Vec3;
use crate::model::{AppliedLoad, BodyId, Frame, ModelBuilder, Profile, SpringDamper};
use crate::sim::Simulation;

/// Free length of the spring [m]; its ground end is at `x = -FREE_LENGTH`. Long enough that no
/// displacement the parameter ranges allow compresses the spring to zero.
pub const FREE_LENGTH: f64 = 1.0e3;

/// The oscillator's parameters (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    /// Mass [kg].
    pub m: f64,
    /// Spring stiffness [N/m].
    pub k: f64,
    /// Damping coefficient [N s/m].
    pub c: f64,
    /// Initial displacement [m].
    pub x0: f64,
    /// Initial velocity [m/s].
    pub v0: f64,
    /// Relative tolerance of the integrator (0: the solver's default, 1e-6).
    pub rtol: f64,
    /// Absolute tolerance [m, m/s] (0: the solver's default, 1e-8).
    pub atol: f64,
    /// Largest internal step [s].
    pub h_max: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            m: 1.0,
            k: 100.0,
            c: 0.5,
            x0: 0.1,
            v0: 0.0,
            rtol: 1e-9,
            atol: 1e-12,
            h_max: 0.01,
        }
    }
}

/// The running oscillator: a [`Simulation`] of one particle.
#[derive(Debug, Clone)]
pub struct Oscillator {
    /// The solver's simulation (its time axis starts at 0).
    pub sim: Simulation,
    params: Params,
}

/// The outputs at the current state: `[x, v, a, spring_force]` in m, m/s, m/s^2, N.
pub type Outputs = [f64; 4];

impl Oscillator {
    /// The oscillator at `x0`, `v0` with input force `force` [N], time 0, integrated by DOPRI5.
    pub fn new(p: &Params, force: f64) -> Result<Self, String> {
        let mut b = ModelBuilder::new();
        b.set_gravity(None)?;
        let along_x = |x: f64| Vec3::new(x, 0.0, 0.0);
        let mass = b.add_particle("mass", p.m, along_x(p.x0), along_x(p.v0))?;
        b.add_spring_damper(SpringDamper {
            name: "spring".into(),
            a: Frame::new(BodyId::GROUND, along_x(-FREE_LENGTH)),
            b: Frame::new(mass, Vec3::zeros()),
            stiffness: p.k,
            damping: p.c,
            free_length: FREE_LENGTH,
        })?;
        let input = b.add_input("force");
        b.add_applied_load(AppliedLoad {
            name: "force".into(),
            at: Frame::new(mass, Vec3::zeros()),
            force_direction: Vec3::x(),
            force: Profile::Input {
                index: input,
                gain: 1.0,
            },
            torque_direction: Vec3::x(),
            torque: Profile::Polynomial {
                c0: 0.0,
                c1: 0.0,
                c2: 0.0,
            },
        })?;
        let defaults = Settings::default();
        let settings = Settings {
            rtol: if p.rtol == 0.0 { defaults.rtol } else { p.rtol },
            atol: if p.atol == 0.0 { defaults.atol } else { p.atol },
            h_max: p.h_max,
            ..defaults
        };
        let sim =
            Simulation::with_inputs(b.build()?, IntegratorKind::Dopri5, settings, 0.0, &[force])?;
        Ok(Oscillator { sim, params: *p })
    }

    /// Sets the input force [N] (acts from the current time on).
    pub fn set_force(&mut self, force: f64) -> Result<(), String> {
        self.sim.set_input(0, force)
    }

    /// Advances to `t` [s, the oscillator's own axis from 0].
    pub fn advance_to(&mut self, t: f64) -> Result<(), SolverError> {
        self.sim.advance_to(t)
    }

    /// `[x, v, a, spring_force]` now: the displacement and velocity from the particle's state,
    /// the acceleration from the equation of motion, the spring-damper's force on the mass
    /// `-k x - c v`.
    pub fn outputs(&self) -> Outputs {
        let s = &self.sim.state;
        let (x, v) = (s.q[0], s.v[0]);
        let p = &self.params;
        let spring = -p.k * x - p.c * v;
        let force = self.sim.system.inputs[0];
        [x, v, (spring + force) / p.m, spring]
    }
}

#[cfg(test)]
mod tests;
