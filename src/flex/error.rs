//! Error type of the flexible-body module: every public constructor returns
//! `Result<_, FlexError>` instead of panicking on bad input.

use std::fmt;

/// Why a flexible-body computation or import failed. The message names the offending value.
#[derive(Debug, Clone, PartialEq)]
pub enum FlexError {
    /// An input value outside what the model accepts (non-positive size, NaN, index out of range,
    /// more modes than DOFs, ...).
    InvalidInput(String),
    /// A numerical step failed (mass matrix not positive definite, eigen-solver did not converge,
    /// interface that does not restrain the structure, ...).
    Numerical(String),
    /// A malformed modal-data text file: 1-based line number and what was expected there.
    Parse {
        /// 1-based line number in the file (0 when the file ended early).
        line: usize,
        /// What was expected and what was found.
        message: String,
    },
}

impl fmt::Display for FlexError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FlexError::InvalidInput(m) => write!(f, "invalid input: {m}"),
            FlexError::Numerical(m) => write!(f, "numerical failure: {m}"),
            FlexError::Parse { line, message } => write!(f, "line {line}: {message}"),
        }
    }
}

impl std::error::Error for FlexError {}

/// Shorthand for an [`FlexError::InvalidInput`] error.
pub(crate) fn invalid<T>(msg: impl Into<String>) -> Result<T, FlexError> {
    Err(FlexError::InvalidInput(msg.into()))
}

/// Checks that `value` is finite and strictly positive; `what` names it in the message.
pub(crate) fn check_positive(what: &str, value: f64) -> Result<(), FlexError> {
    if !value.is_finite() {
        return invalid(format!("{what} must be finite, got {value}"));
    }
    if value <= 0.0 {
        return invalid(format!("{what} must be > 0, got {value}"));
    }
    Ok(())
}

/// Checks that `value` is finite and non-negative; `what` names it in the message.
pub(crate) fn check_non_negative(what: &str, value: f64) -> Result<(), FlexError> {
    if !value.is_finite() {
        return invalid(format!("{what} must be finite, got {value}"));
    }
    if value < 0.0 {
        return invalid(format!("{what} must be >= 0, got {value}"));
    }
    Ok(())
}
