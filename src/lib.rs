//! # mbcosim: multibody dynamics packaged as FMI 2.0 co-simulation FMUs
//!
//! Layers, each depending only on those below it:
//!
//! ```text
//! fmi  ->  scene  ->  sim  ->  integrator / dae  ->  effect / model / state  ->  math
//! ```
//!
//! - [`math`]: nalgebra aliases, SO(3) exponential/logarithm maps.
//! - [`scene`]: FMI-agnostic model interface ([`scene::CoSimModel`]) and variable tables.
//!
//! Units are SI throughout. Nothing outside `fmi` knows that FMI exists.

pub mod dae;
pub mod effect;
pub mod integrator;
pub mod math;
pub mod model;
pub mod scene;
pub mod sim;
pub mod state;
