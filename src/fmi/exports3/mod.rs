//! Every FMI 3.0 function (common, Co-Simulation, Model Exchange, Scheduled Execution), exported
//! with C linkage from the same library as the FMI 2.0 ones.
//!
//! The Co-Simulation subset drives the same [`Instance`] as FMI 2.0 through the same panic guard
//! and state machine ([`super::boundary::guard`]). Every other function exists so that importers
//! that bind the whole API when loading the library (fmpy) find it; it refuses with `fmi3Error`
//! and the reason logged (the instantiation functions of the other interface types return NULL).
//!
//! [`Instance`]: super::instance::Instance

// the argument lists are the standard's
#![allow(clippy::too_many_arguments)]

mod common;
mod cosim;
mod fmu_state;
mod unsupported;
mod values;

pub use common::*;
pub use cosim::*;
pub use fmu_state::*;
pub use unsupported::*;
pub use values::*;
