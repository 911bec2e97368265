//! Flexible panels (placeholder doc, expanded below).

pub mod beam;
pub mod body;
#[cfg(test)]
mod body_tests;
pub mod eigen;
pub mod error;
pub mod invariants;
#[cfg(test)]
mod invariants_tests;
pub mod plate;
pub mod plate_element;
pub mod reduce;
#[cfg(test)]
mod reduction_tests;
#[cfg(test)]
mod validation;
