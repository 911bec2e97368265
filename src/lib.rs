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

pub mod flex;
pub mod math;
pub mod scene;
