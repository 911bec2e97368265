//! The 34 FMI 2.0 common and co-simulation functions, exported with C linkage.
//!
//! Each export is a thin shell: it converts pointers to slices and strings (refusing NULL where
//! data is needed) inside [`super::boundary::guard`], then calls the safe [`Instance`] method
//! that implements the function. Unsupported optional functions return `fmi2Error` (or
//! `fmi2Discard` for status queries, as the standard says) with the reason logged.
//!
//! [`Instance`]: super::instance::Instance

mod common;
mod cosim;
mod fmu_state;
mod values;

pub use common::*;
pub use cosim::*;
pub use fmu_state::*;
pub use values::*;
