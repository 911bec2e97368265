//! Errors of the contact module: a rejected parameter, a query argument outside its domain, or a
//! geometry query the collision library could not answer. Every message names the offending
//! quantity, its value and what was expected, so a user can fix the input without reading code.

use std::fmt;

/// Why a contact-law or latch-geometry call was refused.
#[derive(Debug, Clone, PartialEq)]
pub enum ContactError {
    /// A construction parameter outside its admissible range (e.g. stiffness `k <= 0`).
    InvalidParameter {
        /// Name and symbol of the parameter, e.g. `"stiffness k"`.
        name: &'static str,
        /// The rejected value (in the parameter's SI unit).
        value: f64,
        /// The admissible range, in words, e.g. `"finite and > 0 N/m^n"`.
        expected: &'static str,
    },
    /// A query argument outside the query's domain (e.g. a negative static force).
    InvalidArgument {
        /// Name and symbol of the argument.
        name: &'static str,
        /// The rejected value (in the argument's SI unit).
        value: f64,
        /// The admissible range, in words.
        expected: &'static str,
    },
    /// A geometric query that parry3d-f64 did not answer (unsupported shape pair or no result).
    Geometry(String),
}

impl fmt::Display for ContactError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ContactError::InvalidParameter {
                name,
                value,
                expected,
            } => write!(
                f,
                "invalid contact parameter {name} = {value}: expected {expected}"
            ),
            ContactError::InvalidArgument {
                name,
                value,
                expected,
            } => write!(
                f,
                "invalid contact query argument {name} = {value}: expected {expected}"
            ),
            ContactError::Geometry(m) => write!(f, "contact geometry query failed: {m}"),
        }
    }
}

impl std::error::Error for ContactError {}

/// Checks `value` is finite and strictly positive; otherwise an [`ContactError::InvalidParameter`].
pub(crate) fn positive_parameter(
    name: &'static str,
    value: f64,
    expected: &'static str,
) -> Result<f64, ContactError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ContactError::InvalidParameter {
            name,
            value,
            expected,
        })
    }
}
