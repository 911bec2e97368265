//! # mbcosim: multibody dynamics packaged as FMI 2.0 co-simulation FMUs
//!
//! Layers, each depending only on those below it:
//!
//! ```text
//! fmi  ->  scene  ->  sim  ->  integrator / dae  ->  effect / model / state  ->  math
//! ```
//!
//! - [`math`]: nalgebra aliases, SO(3) exponential/logarithm maps.
//! - [`scene`]: FMI-agnostic model interface ([`scene::CoSimModel`]), variable tables, the port
//!   value store, state serialization helpers and the models ([`scene::pid`]).
//! - [`fmi`]: the FMI 2.0 Co-Simulation wrapper, `modelDescription.xml` writer and FMU packer;
//!   the only module with `unsafe` code.
//!
//! Units are SI throughout. Nothing outside `fmi` knows that FMI exists.
#![deny(unsafe_code)]

pub mod fmi;
pub mod math;
pub mod scene;
