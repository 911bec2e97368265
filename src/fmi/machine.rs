//! The FMI 2.0 co-simulation state machine: instance states and, per function, the states in
//! which it may be called (FMI 2.0.4 section 4.2.4, the Modelica Reference-FMUs' masks).
//!
//! `StepInProgress` and `StepCanceled` never occur (no asynchronous steps), and `StepFailed`
//! only exists for completeness: a failing step returns `fmi2Error` and leads to `Error`.

/// State of one instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    /// After `fmi2Instantiate` or `fmi2Reset`: parameters and inputs may be set.
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    InitializationMode,
    /// Ready for the next `fmi2DoStep`.
    StepComplete,
    /// A step returned `fmi2Discard` (never entered by this library).
    StepFailed,
    /// After `fmi2Terminate`: outputs may still be read.
    Terminated,
    /// After any `fmi2Error`: read values, restore a state, reset or free.
    Error,
    /// After a panic (`fmi2Fatal`): only `fmi2FreeInstance`.
    Fatal,
}

impl State {
    const ALL: [State; 7] = [
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::StepFailed,
        State::Terminated,
        State::Error,
        State::Fatal,
    ];

    fn bit(self) -> u32 {
        1 << (self as u32)
    }

    /// Stable number used in serialized states.
    pub fn code(self) -> u32 {
        self as u32
    }

    /// The state with this [`State::code`].
    pub fn from_code(code: u32) -> Option<State> {
        State::ALL.get(code as usize).copied()
    }

    /// Name used in messages (as in the standard's state diagram).
    pub fn name(self) -> &'static str {
        match self {
            State::Instantiated => "instantiated",
            State::InitializationMode => "initializationMode",
            State::StepComplete => "stepComplete",
            State::StepFailed => "stepFailed",
            State::Terminated => "terminated",
            State::Error => "error",
            State::Fatal => "fatal",
        }
    }
}

/// A set of states in which a function may be called.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mask(u32);

impl Mask {
    const fn of(states: &[State]) -> Mask {
        let mut bits = 0;
        let mut i = 0;
        while i < states.len() {
            bits |= 1 << (states[i] as u32);
            i += 1;
        }
        Mask(bits)
    }

    /// True when `s` is in the set.
    pub fn contains(self, s: State) -> bool {
        self.0 & s.bit() != 0
    }

    /// The states in the set, for messages.
    pub fn names(self) -> String {
        let names: Vec<&str> = State::ALL
            .iter()
            .filter(|s| self.contains(**s))
            .map(|s| s.name())
            .collect();
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        }
    }
}

use State::*;

/// Every state but `Fatal`.
pub const ALIVE: Mask = Mask::of(&[
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
]);
/// `fmi2SetDebugLogging`, `fmi2Reset`, the FMU-state functions.
pub const ANY_BUT_FATAL: Mask = ALIVE;
/// `fmi2SetupExperiment`, `fmi2EnterInitializationMode`.
pub const INSTANTIATED: Mask = Mask::of(&[Instantiated]);
/// `fmi2ExitInitializationMode`.
pub const INIT_MODE: Mask = Mask::of(&[InitializationMode]);
/// `fmi2Terminate`.
pub const TERMINATE: Mask = Mask::of(&[StepComplete, StepFailed]);
/// `fmi2Get{Real,Integer,Boolean,String}`, `fmi2GetDirectionalDerivative`.
pub const GET_VALUES: Mask = Mask::of(&[
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
]);
/// `fmi2Set{Real,Integer,Boolean,String}` (each variable's causality restricts further).
pub const SET_VALUES: Mask = Mask::of(&[Instantiated, InitializationMode, StepComplete]);
/// `fmi2SetRealInputDerivatives`.
pub const SET_INPUT_DERIVATIVES: Mask = SET_VALUES;
/// `fmi2GetRealOutputDerivatives`.
pub const GET_OUTPUT_DERIVATIVES: Mask = Mask::of(&[StepComplete, StepFailed, Terminated, Error]);
/// `fmi2DoStep`.
pub const DO_STEP: Mask = Mask::of(&[StepComplete]);
/// `fmi2CancelStep` (needs `StepInProgress`, which never occurs).
pub const CANCEL_STEP: Mask = Mask::of(&[]);
/// `fmi2Get*Status`.
pub const GET_STATUS: Mask = Mask::of(&[StepComplete, StepFailed, Terminated]);

/// Everything the wrapper knows about one instance besides the model: saved with FMU states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Machine {
    /// Current state.
    pub state: State,
    /// Start time from `fmi2SetupExperiment` [s].
    pub start_time: f64,
    /// Stop time from `fmi2SetupExperiment`, when defined [s].
    pub stop_time: Option<f64>,
    /// Relative tolerance from `fmi2SetupExperiment`, when defined.
    pub tolerance: Option<f64>,
    /// End time of the last successful step (or the start time) [s].
    pub last_successful_time: f64,
}

impl Default for Machine {
    fn default() -> Self {
        Self {
            state: State::Instantiated,
            start_time: 0.0,
            stop_time: None,
            tolerance: None,
            last_successful_time: 0.0,
        }
    }
}

/// True when fixed parameters are frozen (after `fmi2ExitInitializationMode`).
pub fn past_initialization(s: State) -> bool {
    !matches!(s, Instantiated | InitializationMode)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_and_masks_match_the_standard() {
        for s in State::ALL {
            assert_eq!(State::from_code(s.code()), Some(s));
            assert!(!DO_STEP.contains(s) || s == StepComplete);
            assert_eq!(ALIVE.contains(s), s != Fatal);
        }
        assert_eq!(State::from_code(7), None);
        assert!(GET_VALUES.contains(Error) && !GET_VALUES.contains(Instantiated));
        assert!(SET_VALUES.contains(StepComplete) && !SET_VALUES.contains(Terminated));
        assert_eq!(CANCEL_STEP.names(), "none");
        assert_eq!(TERMINATE.names(), "stepComplete, stepFailed");
    }
}
