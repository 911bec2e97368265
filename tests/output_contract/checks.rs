//! Which test checks each output, and against what (see `main.rs`).
//!
//! An entry names outputs by pattern: `#` stands for a decimal index (`hinge#_angle` covers
//! `hinge0_angle` ... `hinge6_angle`). Every output matches exactly one entry. A check is
//! `path::function` from the repository root: a Rust test (`tests/...rs`) or a pytest function
//! (`tests/python/...py`).

/// Which value of the continuous solution an output reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    /// The value at the communication point.
    Instant,
    /// The largest value since the start, over every internal step.
    Peak,
    /// An integral since the start (work, dissipated energy).
    Cumulative,
    /// The time of an event, fixed once it happened.
    Event,
    /// A running count since the start.
    Count,
    /// A discrete state at the communication point.
    Flag,
}

impl Sampling {
    /// The word the document uses.
    pub fn word(self) -> &'static str {
        match self {
            Sampling::Instant => "instant",
            Sampling::Peak => "peak",
            Sampling::Cumulative => "cumulative",
            Sampling::Event => "event",
            Sampling::Count => "count",
            Sampling::Flag => "flag",
        }
    }
}

/// One entry of the output contract.
#[derive(Debug, Clone, Copy)]
pub struct Check {
    /// Model identifier.
    pub model: &'static str,
    /// Output name patterns (`#`: a decimal index).
    pub outputs: &'static [&'static str],
    /// Which value the outputs report.
    pub sampling: Sampling,
    /// The tests that check them, `path::function`.
    pub tests: &'static [&'static str],
    /// What those tests compare with, and to what tolerance.
    pub against: &'static str,
}

impl Check {
    /// True when one of the entry's patterns matches `name`.
    pub fn covers(&self, name: &str) -> bool {
        self.outputs.iter().any(|p| matches(p, name))
    }
}

/// True when `name` matches `pattern`, in which each `#` stands for one or more decimal digits.
pub fn matches(pattern: &str, name: &str) -> bool {
    match pattern.split_once('#') {
        None => pattern == name,
        Some((head, tail)) => {
            let Some(rest) = name.strip_prefix(head) else {
                return false;
            };
            let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
            digits > 0 && matches(tail, &rest[digits..])
        }
    }
}

use Sampling::*;

/// The contract, model by model.
pub const CHECKS: &[Check] = &[];
