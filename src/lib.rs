//! # mbcosim: multibody dynamics packaged as FMI 2.0 co-simulation FMUs
//!
//! Layers, each depending only on those below it:
//!
//! ```text
//! fmi  ->  scene  ->  sim  ->  integrator  ->  tree  ->  dae  ->  effect / model / state  ->  math
//! ```
//!
//! - [`math`]: nalgebra aliases, SO(3) exponential/logarithm maps.
//! - [`model`]: immutable description of bodies, joints and force elements (validating builder).
//! - [`state`]: the mutable state, a plain `Clone`.
//! - [`effect`]: force elements and joint constraints with analytic Jacobians.
//! - [`contact`]: contact force laws (Hertz, Lankarani-Nikravesh, Hunt-Crossley, Flores) and the
//!   latch pin/groove geometry.
//! - [`flex`]: plate/beam finite elements, modal reduction (Craig-Bampton, free-interface) and
//!   the inertia invariants of floating-frame flexible bodies.
//! - [`dae`]: the system as integrators see it; sparse/dense Newton solves.
//! - [`tree`]: joint coordinates of kinematic trees (detection, mapping, joint-space dynamics).
//! - [`integrator`]: generalized-alpha, BDF, DOPRI5 (maximal coordinates) and DOPRI5 in joint
//!   coordinates behind one trait.
//! - [`sim`]: a simulation (system + state + integrator) with snapshots.
//! - [`scene`]: FMI-agnostic model interface ([`scene::CoSimModel`]), variable tables, the port
//!   value store, state serialization helpers and the models ([`scene::pid`]).
//! - [`fmi`]: the FMI 2.0 Co-Simulation wrapper, `modelDescription.xml` writer and FMU packer;
//!   the only module with `unsafe` code.
//!
//! Units are SI throughout. Nothing outside `fmi` knows that FMI exists.
#![deny(unsafe_code)]

pub mod bounded_file;
pub mod contact;
pub mod dae;
pub mod effect;
pub mod flex;
pub mod fmi;
pub mod integrator;
pub mod math;
pub mod model;
pub mod report;
pub mod rope;
pub mod scene;
pub mod sim;
pub mod state;
pub mod tree;
